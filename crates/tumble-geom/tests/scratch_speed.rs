use glam::{DQuat, DVec3};
use tumble_geom::*;
#[test]
fn speed() {
    let cube = Polyhedron::cube(1.0);
    let mut poses = Vec::new();
    let mut seed = 1u64;
    let mut next = || {
        seed = seed.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
        (seed >> 11) as f64 / (1u64 << 53) as f64
    };
    for _ in 0..256 {
        let dir = DVec3::new(next() - 0.5, next() - 0.5, next() - 0.5).normalize();
        let qa = DQuat::from_axis_angle(DVec3::new(next() - 0.5, next() - 0.5, next() - 0.5).normalize(), 6.0 * next());
        let qb = DQuat::from_axis_angle(DVec3::new(next() - 0.5, next() - 0.5, next() - 0.5).normalize(), 6.0 * next());
        // Find a barely overlapping distance along dir.
        let mut lo = 0.5;
        let mut hi = 2.0;
        for _ in 0..40 {
            let mid = 0.5 * (lo + hi);
            if polyhedron_polyhedron(&cube, &Pose::new(dir * mid, qa), &cube, &Pose::new(DVec3::ZERO, qb)).is_some() { lo = mid } else { hi = mid }
        }
        poses.push((Pose::new(dir * (lo - 0.002), qa), Pose::new(DVec3::ZERO, qb)));
    }
    for round in 0..3 {
        let t = std::time::Instant::now();
        let mut n = 0;
        for _ in 0..20 {
            for (a, b) in &poses {
                n += polyhedron_polyhedron(&cube, a, &cube, b).is_some() as usize;
            }
        }
        let sat = t.elapsed().as_secs_f64() / (20.0 * 256.0);
        let t = std::time::Instant::now();
        let mut m = 0;
        for _ in 0..20 {
            for (a, b) in &poses {
                m += polyhedron_polyhedron_volume(&cube, a, &cube, b).map_or(0, |c| c.points.len());
            }
        }
        let vol = t.elapsed().as_secs_f64() / (20.0 * 256.0);
        let t = std::time::Instant::now();
        for _ in 0..20 {
            for (a, b) in &poses {
                m += overlap_volume_about(&cube, a, &cube, b, DVec3::ZERO).is_some() as usize;
            }
        }
        let ov = t.elapsed().as_secs_f64() / (20.0 * 256.0);
        println!("round {round}: sat {:.2} us ({n}), volume contact {:.2} us, overlap moments only {:.2} us ({m})", sat * 1e6, vol * 1e6, ov * 1e6);
    }
}
