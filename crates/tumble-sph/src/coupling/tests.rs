use super::*;
use crate::particles::FluidParticles;

const RHO: f64 = 1000.0;
const WATER: DragFluid = DragFluid { density: RHO, viscosity: 1.0e-3 };

/// A periodic cube of side `side`.
fn cube(side: f64) -> PeriodicBox {
    PeriodicBox { min: DVec3::ZERO, max: DVec3::splat(side), periodic: [true; 3] }
}

/// Water at rest on a cubic lattice of spacing `dp` filling `domain`, moving at `velocity`.
fn water(domain: &PeriodicBox, dp: f64, velocity: DVec3) -> FluidParticles {
    let n = (domain.extent() / dp).round().as_uvec3();
    let mut p = FluidParticles::default();
    for k in 0..n.z {
        for j in 0..n.y {
            for i in 0..n.x {
                p.id.push(p.position.len() as u32);
                p.kind.push(ParticleKind::Fluid);
                p.position.push(domain.min + (DVec3::new(i as f64, j as f64, k as f64) + 0.5) * dp);
                p.velocity.push(velocity);
                p.density.push(RHO);
                p.mass.push(RHO * dp * dp * dp);
                p.wall.push(0);
            }
        }
    }
    p
}

/// Solids of radius `r` on a cubic lattice of spacing `s` filling `domain`, shifted by `shift`.
fn bed(domain: &PeriodicBox, s: f64, r: f64, shift: DVec3) -> (Vec<DVec3>, Vec<f64>) {
    let n = (domain.extent() / s).round().as_uvec3();
    let mut x = Vec::new();
    for k in 0..n.z {
        for j in 0..n.y {
            for i in 0..n.x {
                x.push(domain.min + (DVec3::new(i as f64, j as f64, k as f64) + 0.5) * s + shift);
            }
        }
    }
    let radii = vec![r; x.len()];
    (x, radii)
}

/// A bed of solid fraction φ = 0.3 (spheres 1 mm apart on a lattice, h = 1.5 mm, the fluid 0.5 mm
/// apart): the fluid fraction at every fluid particle is 1 − φ within 1 %, and on average
/// within 1e-4 (the kernel's sum over the solids' lattice integrates it).
#[test]
fn a_uniform_bed_leaves_the_fluid_its_share_of_the_volume() {
    let (s, dp, h) = (1.0e-3, 0.5e-3, 1.5e-3);
    let domain = cube(8.0 * s);
    let phi: f64 = 0.3;
    let r = (phi * s * s * s * 3.0 / (4.0 * std::f64::consts::PI)).cbrt();
    let fluid = water(&domain, dp, DVec3::ZERO);
    let (x, radius) = bed(&domain, s, r, DVec3::new(0.13, 0.29, 0.41) * s);
    let v = vec![DVec3::ZERO; x.len()];
    let coupling = Coupling::new(h, Dimension::Three, domain, DragLaw::Gidaspow, WATER).unwrap();
    let out = coupling.evaluate(&fluid, &vec![DVec3::ZERO; fluid.len()], Solids { position: &x, velocity: &v, radius: &radius });
    let mean = out.fraction.iter().sum::<f64>() / out.fraction.len() as f64;
    let worst = out.fraction.iter().map(|e| (e - (1.0 - phi)).abs()).fold(0.0, f64::max);
    println!("φ = {phi}: mean fluid fraction {mean:.6}, worst deviation {worst:.2e}; at the solids {:.6}", out.solid_fraction[0]);
    assert!((mean - (1.0 - phi)).abs() < 1e-4, "mean {mean}");
    assert!(worst < 0.01 * (1.0 - phi), "worst {worst}");
    assert!(out.solid_fraction.iter().all(|e| (e - (1.0 - phi)).abs() < 0.01), "the fraction interpolated at the solids");
}

/// In water at rest whose pressure holds it against gravity (θ = +g ẑ at every fluid particle),
/// a solid anywhere feels its displaced water's weight upward, V ρ g, to round-off, and no drag:
/// buoyancy comes from the pressure gradient.
#[test]
fn a_solid_in_water_at_rest_feels_archimedes_buoyancy() {
    let (dp, h) = (1.0e-3, 1.3e-3);
    let domain = cube(12.0 * dp);
    let fluid = water(&domain, dp, DVec3::ZERO);
    let up = DVec3::new(0.0, 0.0, 9.81);
    let x = vec![DVec3::new(3.3, 7.1, 5.6) * dp, DVec3::new(0.2, 11.9, 0.1) * dp];
    let (radius, v) = (vec![0.4 * dp, 0.2 * dp], vec![DVec3::ZERO; 2]);
    let coupling = Coupling::new(h, Dimension::Three, domain, DragLaw::DiFelice, WATER).unwrap();
    let out = coupling.evaluate(&fluid, &vec![up; fluid.len()], Solids { position: &x, velocity: &v, radius: &radius });
    for (i, r) in radius.iter().enumerate() {
        let weight = 4.0 / 3.0 * std::f64::consts::PI * r.powi(3) * RHO * up;
        assert!((out.force[i] - weight).length() <= 1e-12 * weight.length(), "solid {i}: {} against {weight}", out.force[i]);
        assert_eq!(out.drag[i], DVec3::ZERO);
    }
}

/// A solid at rest in a uniform stream U feels the drag its law gives at the interpolated
/// fraction, with the stream's velocity interpolated exactly; the reactions on the fluid add up
/// to minus the solids' forces to round-off (momentum is conserved), with the fluid and solids
/// moving at random.
#[test]
fn drag_follows_the_law_and_the_reaction_conserves_momentum() {
    let (dp, h) = (1.0e-3, 1.3e-3);
    let domain = cube(10.0 * dp);
    let stream = DVec3::new(0.02, -0.01, 0.005);
    let mut fluid = water(&domain, dp, stream);
    let x = vec![DVec3::new(2.3, 4.1, 5.6) * dp, DVec3::new(2.9, 4.4, 6.0) * dp, DVec3::new(8.7, 0.3, 9.9) * dp];
    let radius = vec![0.45 * dp, 0.3 * dp, 0.5 * dp];
    let coupling = Coupling::new(h, Dimension::Three, domain, DragLaw::Gidaspow, WATER).unwrap();
    let rest = vec![DVec3::ZERO; 3];
    let out = coupling.evaluate(&fluid, &vec![DVec3::ZERO; fluid.len()], Solids { position: &x, velocity: &rest, radius: &radius });
    for (i, r) in radius.iter().enumerate() {
        assert!((out.fluid_velocity[i] - stream).length() < 1e-15, "{}", out.fluid_velocity[i]);
        let k = DragLaw::Gidaspow.coefficient(&WATER, 2.0 * r, out.solid_fraction[i], stream.length());
        let expected = k * 4.0 / 3.0 * std::f64::consts::PI * r.powi(3) * stream;
        assert!((out.drag[i] - expected).length() < 1e-12 * expected.length());
        assert!(out.solid_fraction[i] < 1.0 && out.solid_fraction[i] > 0.5);
    }
    // Random motion and accelerations: Σ F_i + Σ S_a = 0.
    let mut state = 12345u64;
    let mut rand = || {
        state = state.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
        (state >> 11) as f64 / (1u64 << 53) as f64 - 0.5
    };
    for a in 0..fluid.len() {
        fluid.velocity[a] = DVec3::new(rand(), rand(), rand()) * 0.1;
        fluid.density[a] = RHO * (1.0 + 0.01 * rand());
    }
    let theta: Vec<DVec3> = (0..fluid.len()).map(|_| DVec3::new(rand(), rand(), rand()) * 20.0).collect();
    let v: Vec<DVec3> = (0..3).map(|_| DVec3::new(rand(), rand(), rand()) * 0.1).collect();
    let out = coupling.evaluate(&fluid, &theta, Solids { position: &x, velocity: &v, radius: &radius });
    let on_solids: DVec3 = out.force.iter().sum();
    let on_fluid: DVec3 = out.reaction.iter().sum();
    println!("Σ F on the solids {on_solids}, Σ S on the fluid {on_fluid}");
    assert!(on_solids.length() > 1e-8);
    assert!((on_solids + on_fluid).length() < 1e-12 * on_solids.length());
}

/// The passes gather: the same bits on one thread and on four.
#[test]
fn the_coupling_is_the_same_for_any_thread_count() {
    let (s, dp, h) = (1.0e-3, 0.5e-3, 1.5e-3);
    let domain = cube(6.0 * s);
    let mut fluid = water(&domain, dp, DVec3::ZERO);
    for (a, v) in fluid.velocity.iter_mut().enumerate() {
        *v = DVec3::new((a as f64 * 0.37).sin(), (a as f64 * 0.11).cos(), (a as f64 * 0.73).sin()) * 0.01;
    }
    let (x, radius) = bed(&domain, s, 0.35 * s, DVec3::splat(0.2 * s));
    let v: Vec<DVec3> = (0..x.len()).map(|i| DVec3::new(0.0, 0.0, -0.001 * i as f64)).collect();
    let theta = vec![DVec3::new(0.1, 0.0, 9.81); fluid.len()];
    let coupling = Coupling::new(h, Dimension::Three, domain, DragLaw::DiFelice, WATER).unwrap();
    let run = |threads: usize| {
        let pool = rayon::ThreadPoolBuilder::new().num_threads(threads).build().unwrap();
        pool.install(|| coupling.evaluate(&fluid, &theta, Solids { position: &x, velocity: &v, radius: &radius }))
    };
    assert_eq!(run(1), run(4));
}

/// A plane fluid is refused, as is a periodic axis shorter than two cells.
#[test]
fn a_plane_fluid_or_a_short_periodic_axis_is_refused() {
    assert!(Coupling::new(1e-3, Dimension::Two, cube(0.1), DragLaw::Gidaspow, WATER).is_err());
    assert!(Coupling::new(1e-3, Dimension::Three, cube(3e-3), DragLaw::Gidaspow, WATER).is_err());
}
