use glam::DQuat;
use tumble::{Simulation, compile, parse_scene};
use tumble_testkit::scenes::{replaced, test_scene};

fn random_rotation(seed: &mut u64) -> DQuat {
    let mut next = || {
        *seed = seed.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
        (*seed >> 11) as f64 / (1u64 << 53) as f64
    };
    let (u1, u2, u3) = (next(), next(), next());
    let t = std::f64::consts::TAU;
    DQuat::from_xyzw((1.0 - u1).sqrt() * (t * u2).sin(), (1.0 - u1).sqrt() * (t * u2).cos(), u1.sqrt() * (t * u3).sin(), u1.sqrt() * (t * u3).cos())
}
fn elastic_pair(a: (&str, [f64; 3], DQuat, f64), b: (&str, [f64; 3], DQuat, f64)) -> String {
    let body = |(shape, x, q, v): (&str, [f64; 3], DQuat, f64)| {
        format!(
            "[[particles]]\nmaterial = \"steel\"\nshape = {shape}\npositions = [[{}, {}, {}]]\norientation = [{}, {}, {}, {}]\nvelocity = [{v}, 0.0, 0.0]\n",
            x[0], x[1], x[2], q.w, q.x, q.y, q.z
        )
    };
    let text = test_scene("elastic_pair");
    let bodies = text.find("[[particles]]").unwrap();
    format!("{}{}{}", &text[..bodies], body(a), body(b))
}

#[test]
fn scratch() {
    for frac in [50, 100, 200, 400] {
        let mut seed = 7u64;
        let mut ratios = Vec::new();
        for shape in ["{ cube = { edge = 0.03 } }", "{ platonic = { kind = \"dodecahedron\", radius = 0.02 } }"] {
            for k in 0..8 {
                let (qa, qb) = (random_rotation(&mut seed), random_rotation(&mut seed));
                let offset = 0.004 * (k % 4) as f64;
                let text = elastic_pair((shape, [-0.04, offset, 0.0], qa, 0.5), (shape, [0.04, 0.0, 0.0], qb, -0.5))
                    .replace("duration = 1.0", &format!("duration = 0.09\ndt = {{ collision_fraction = {frac} }}"));
                let text = replaced(&text, "restitution = 1.0", "restitution = 1.0");
                let mut s = Simulation::new(compile(&parse_scene(&text).unwrap()).unwrap(), 1);
                let e0 = s.observables().mechanical_energy();
                s.advance(s.plan().run.steps);
                let o = s.observables();
                ratios.push((o.mechanical_energy() + o.dissipated_energy) / e0 - 1.0);
            }
        }
        let worst = ratios.iter().map(|r| r.abs()).fold(0.0, f64::max);
        println!("frac {frac}: worst {worst:.3e} {:?}", ratios.iter().map(|r| format!("{r:.1e}")).collect::<Vec<_>>());
    }
}
