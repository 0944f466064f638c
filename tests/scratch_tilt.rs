use glam::{DQuat, DVec3};
use tumble::{Simulation, compile, parse_scene};
use tumble_testkit::scenes::cube_drop;

#[test]
fn scratch() {
    for (name, model) in [("volume", ""), ("depth", "polyhedron_model = \"depth\"\n")] {
        let axis = DVec3::new(1.0, 2.0, 0.0).normalize();
        let q = DQuat::from_axis_angle(axis, 8f64.to_radians());
        let text = cube_drop([0.0, 0.0, 0.03], [q.w, q.x, q.y, q.z], 0.3, 1.5).replace("restitution = 0.3", &format!("restitution = 0.3\n{model}"));
        let mut s = Simulation::new(compile(&parse_scene(&text).unwrap()).unwrap(), 1);
        let e0 = s.observables().mechanical_energy();
        println!("{name}: dt {:e}", s.plan().model.dt);
        for k in 0..30 {
            s.advance((0.05 / s.plan().model.dt) as u64);
            let o = s.observables();
            let st = s.cpu().state();
            let up = [DVec3::X, DVec3::Y, DVec3::Z].iter().map(|&a| (st.orient[0] * a).dot(DVec3::Z).abs()).fold(0.0, f64::max);
            println!("t {:.2} z {:.5} up {:.5} w {:.3e} v {:.3e} E+D-E0 {:.3e} diss {:.3e} ratio {:.3e}", 0.05 * (k + 1) as f64, st.pos[0].z, up, st.omega[0].length(), st.vel[0].length(), o.mechanical_energy() + o.dissipated_energy - e0, o.dissipated_energy, o.max_overlap_ratio);
        }
    }
}
