//! Invariants of the contact pass on either backend.

use crate::scenes::{compiled, file};
use tumble::Simulation;
use tumble_scene::schema::BackendName;

/// Two spheres in Hertz contact: one computation, negated for the higher id, so the two
/// contact forces are exactly opposite at every step.
pub fn pair_forces_are_exactly_equal_and_opposite(backend: BackendName) {
    let mut sim = Simulation::on(backend, compiled(&file("scenes/verify/07_hertz_impact.toml")), 1).unwrap();
    let mut touching = 0;
    for _ in 0..200 {
        sim.advance(1);
        let (a, b) = (sim.contact_force(0).unwrap(), sim.contact_force(1).unwrap());
        assert_eq!(a, -b);
        touching += usize::from(a != glam::DVec3::ZERO);
    }
    assert!(touching > 10, "the spheres should touch: {touching} steps in contact");
}
