//! Determinism: two runs of one scene on one backend are bit-identical, and on the CPU so are
//! runs on one and on two threads.

use crate::scenes::{compiled, file, shortened};
use tumble::Simulation;
use tumble_scene::CompiledScene;
use tumble_scene::schema::BackendName;

/// Every particle's position, velocity, acceleration, spin and orientation as bits, by id,
/// with the walls' work and power and the contact count.
#[derive(PartialEq)]
struct Fingerprint {
    particles: Vec<(u32, Vec<u64>)>,
    walls: Vec<u64>,
    contacts: u64,
}

fn fingerprint(sim: &Simulation) -> Fingerprint {
    let s = sim.state();
    let mut rows: Vec<(u32, Vec<u64>)> = (0..s.len())
        .map(|i| {
            let q = s.orient.get(i).map_or([0.0; 4], |q| q.to_array());
            let values = [s.pos[i], s.vel[i], s.acc[i], s.omega[i], s.alpha[i]].into_iter().flat_map(|v| v.to_array()).chain(q);
            (s.id[i], values.map(f64::to_bits).collect())
        })
        .collect();
    rows.sort_unstable_by_key(|r| r.0);
    let walls = sim.wall_work().into_iter().chain(sim.wall_power()).map(f64::to_bits).collect();
    Fingerprint { particles: rows, walls, contacts: sim.observables().contacts }
}

/// Runs `scene` for `steps` on `backend` with `threads` (CPU) and fingerprints the end.
fn run(backend: BackendName, scene: &CompiledScene, steps: u64, threads: usize) -> Fingerprint {
    let mut sim = Simulation::on(backend, scene.clone(), threads).unwrap();
    sim.advance(steps);
    fingerprint(&sim)
}

/// A cohesive drum of 2,000 spheres thrown about at random (cohesion, friction, a cylinder, a
/// thousand contacts) for 200 steps, and the small drum of 30 cubes with lifters, turning end
/// plates and tangential springs for 1,200 (41 contacts by then): any dependence on scheduling
/// or summation order would show.
pub fn two_runs_of_a_scene_are_bit_identical(backend: BackendName) {
    let cases = [
        ("cohesive drum", shortened(&file("scenes/drum_cohesive.toml"), 200), 200),
        ("cube drum", compiled(&file("scenes/conformance/cube_drum.toml")), 1200),
    ];
    for (name, scene, steps) in cases {
        let first = run(backend, &scene, steps, 1);
        assert!(first.contacts > 0, "{name}: the particles should touch");
        assert!(first == run(backend, &scene, steps, 1), "{name}: two runs on {backend:?} differ");
        if backend == BackendName::Cpu {
            assert!(first == run(backend, &scene, steps, 2), "{name}: one and two threads differ");
        }
        println!("{backend:?} {name}: {} particles, {steps} steps, {} contacts: bit-identical", first.particles.len(), first.contacts);
    }
}
