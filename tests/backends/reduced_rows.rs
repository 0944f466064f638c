//! The GPU's small output rows: observables, wall-group power and work and drum profiles
//! reduced on the device and tracked particles gathered there, against the host's f64 sums,
//! `tumble_state::drum_profiles` and `tumble_state::tracks` of the full read-back; one
//! read-back per row whose size does not grow with the particles; run to run bit-identical.

use crate::support::scene;
use tumble::Observables;
use tumble_gpu::GpuSimulation;
use tumble_scene::CompiledScene;
use tumble_testkit::scenes::file;

const SMALL_MILL: &str = include_str!("../../scenes/conformance/small_mill.toml");
const SMALL_CUBE_DRUM: &str = include_str!("../../scenes/conformance/cube_drum.toml");

/// The energy-balance box (spheres, rotation, walls, friction) for `steps` steps, with its
/// lattice up to `top` (m), moving in random directions (so they meet within a few steps),
/// and three tracked spheres above it.
fn energy_box(top: f64, steps: u64) -> CompiledScene {
    let text = file("scenes/verify/09_energy_balance.toml");
    let lattice = "max = [0.15, 0.15, 0.196], spacing = 0.0125, jitter = 0.04 }";
    assert!(text.contains(lattice));
    let mut text = text.replace(
        lattice,
        &format!("max = [0.15, 0.15, {top}], spacing = 0.0125, jitter = 0.04 }}\nvelocity = {{ random = {{ mean_speed = 1.0, std = 0.2 }} }}"),
    );
    text.push_str(
        r#"
[[particles]]
material = "glass"
shape = { sphere = { diameter = 0.01 } }
positions = [[0.03, 0.03, 0.3], [0.07, 0.08, 0.31], [0.11, 0.12, 0.32]]
track = true
"#,
    );
    let mut sc = scene(&text);
    let mut s = tumble_scene::parse_scene(&text).unwrap();
    s.run.duration = steps as f64 * sc.plan.model.dt;
    s.run.dt = Some(tumble_scene::schema::DtSpec::Seconds(sc.plan.model.dt));
    sc = tumble_scene::compile(&s).unwrap();
    sc
}

/// Every seventh particle of `sc` tracked too.
fn tracking_every_seventh(mut sc: CompiledScene) -> CompiledScene {
    for (i, t) in sc.particles.track.iter_mut().enumerate() {
        *t |= i % 7 == 3;
    }
    sc
}

/// Σ|term| of each energy of the host's sums over the full read-back state, the scale the
/// device's sums are judged against: kinetic, rotational, potential, elastic, dissipated,
/// fluid work.
fn term_scales(gpu: &GpuSimulation) -> [f64; 6] {
    let s = gpu.state();
    let a = gpu.device_arrays();
    let g = gpu.plan().model.gravity;
    let alive = a.alive_by_id();
    let movable = |i: usize| s.inv_mass[i] != 0.0;
    let ke: f64 = (0..s.len()).filter(|&i| movable(i)).map(|i| 0.5 * s.mass[i] * s.vel[i].length_squared()).sum();
    let re: f64 = if s.omega.is_empty() { 0.0 } else { (0..s.len()).filter(|&i| movable(i)).map(|i| s.rotational_energy(i)).sum() };
    let pe: f64 = (0..s.len()).filter(|&i| movable(i)).map(|i| (s.mass[i] * g.dot(s.pos[i])).abs()).sum();
    let sum = |f: &dyn Fn(usize) -> f32| alive.iter().map(|&i| (f(i) as f64).abs()).sum::<f64>();
    [ke, re, pe, sum(&|i| a.force[i][3]), sum(&|i| a.energy[i][0]), sum(&|i| a.energy[i][1])]
}

/// The device's row against the host's f64 sums of the same arrays: energies within 1e-6 of
/// their Σ|term| (f32 terms are good to a few 1e-8 each; the two-float sums and, where the
/// adapter's fma is fused, the products add far less), everything else exact.
fn assert_reduced_matches_full(name: &str, gpu: &GpuSimulation) {
    let reduced = gpu.frame(false);
    let full = gpu.full_frame(false);
    let (d, h) = (&reduced.observables, &full.observables);
    let scales = term_scales(gpu);
    let energies = |o: &Observables| [o.kinetic_energy, o.rotational_energy, o.potential_energy, o.elastic_energy, o.dissipated_energy, o.fluid_work];
    let names = ["kinetic", "rotational", "potential", "elastic", "dissipated", "fluid work"];
    let errors: Vec<(&str, f64, f64, f64)> = names
        .iter()
        .zip(energies(d).into_iter().zip(energies(h)))
        .zip(scales)
        .map(|((n, (dv, hv)), scale)| (*n, dv, hv, (dv - hv).abs() / scale.max(1e-300)))
        .collect();
    println!("{name}: differences of Σ|term|: {}", errors.iter().map(|(n, _, _, e)| format!("{n} {e:.1e}")).collect::<Vec<_>>().join(", "));
    for (name_k, dv, hv, error) in &errors {
        assert!(*error <= 1e-6, "{name}: {name_k} device {dv:e} host {hv:e} ({error:.2e} of Σ|term|)");
    }
    assert!(d.elastic_energy != 0.0 && d.dissipated_energy != 0.0 || name == "stokes drag", "{name}: the row has contacts");
    assert_eq!((d.time, d.contacts, d.particles, d.finite), (h.time, h.contacts, h.particles, h.finite), "{name}");
    assert_wall_groups_and_drums_match(name, &reduced, &full);
    assert_eq!(d.max_overlap_ratio.to_bits(), h.max_overlap_ratio.to_bits(), "{name}: max overlap ratio");
    assert!(!full.tracks.is_empty(), "{name}: tracked particles");
    assert_eq!(reduced.tracks, full.tracks, "{name}: tracked rows");
    assert_eq!(reduced.tracks, tumble_state::tracks(&gpu.state()), "{name}: tracked rows against tumble_state::tracks");
    println!("{name}: {} particles, {} tracked", d.particles, reduced.tracks.len());
}

/// Per wall group, power, work, force and torque within 1e-5 of the largest group's (f32 entries summed
/// pairwise, against f64 in id order); per drum, the charge's mass and centre of mass as the
/// host sums them, toe and shoulder within one histogram bin (0.1°).
fn assert_wall_groups_and_drums_match(name: &str, d: &tumble_state::Frame, h: &tumble_state::Frame) {
    for (what, dv, hv) in [("power", &d.wall_power, &h.wall_power), ("work", &d.wall_work, &h.wall_work)] {
        assert_eq!(dv.len(), hv.len());
        let scale = hv.iter().fold(0.0f64, |m, v| m.max(v.abs()));
        let worst = dv.iter().zip(hv).map(|(a, b)| (a - b).abs()).fold(0.0, f64::max);
        println!("{name}: wall {what} per group {dv:.6?}, largest difference {:.1e} of the largest group", worst / scale.max(1e-300));
        assert!(worst <= 1e-5 * scale, "{name}: wall {what} device {dv:?} host {hv:?}");
    }
    // Force and torque (about the reference point) per axis, against the largest group's magnitude.
    for (what, dv, hv) in [("force", &d.wall_force, &h.wall_force), ("torque", &d.wall_torque, &h.wall_torque)] {
        assert_eq!(dv.len(), hv.len());
        let scale = hv.iter().fold(0.0f64, |m, v| m.max(v.length()));
        let worst = dv.iter().zip(hv).map(|(a, b)| (*a - *b).length()).fold(0.0, f64::max);
        println!("{name}: wall {what} per group {dv:.6?}, largest difference {:.1e} of the largest group", worst / scale.max(1e-300));
        assert!((hv.is_empty() || scale > 0.0) && worst <= 1e-5 * scale, "{name}: wall {what} device {dv:?} host {hv:?}");
    }
    let total = |w: &[f64]| w.iter().sum::<f64>();
    assert!(
        (d.observables.wall_work - total(&d.wall_work)).abs() <= 1e-12 * total(&h.wall_work).abs().max(1e-300),
        "{name}: the row's wall work is the groups' sum"
    );
    assert_eq!(d.drums.len(), h.drums.len(), "{name}: drums");
    for (k, (a, b)) in d.drums.iter().zip(&h.drums).enumerate() {
        println!("{name}: drum {k}: device {a:?}\n{name}: drum {k}: host   {b:?}");
        let rel = |x: f64, y: f64| (x - y).abs() / y.abs().max(1e-300);
        assert!(b.charge_mass > 0.0, "{name}: drum {k} holds a charge");
        assert!(rel(a.charge_mass, b.charge_mass) <= 1e-6, "{name}: drum {k} charge mass");
        assert!(rel(a.com_radius, b.com_radius) <= 1e-5 && (a.com_angle - b.com_angle).abs() <= 1e-3, "{name}: drum {k} centre of mass");
        // The torque-arm power follows from these by the one function both sides call.
        assert!(b.toe.is_finite() && b.shoulder.is_finite(), "{name}: drum {k} has a shell layer");
        assert!((a.toe - b.toe).abs() <= 0.1 && (a.shoulder - b.shoulder).abs() <= 0.1, "{name}: drum {k} toe and shoulder");
    }
}

pub fn drums_and_wall_groups_reduced_on_the_device_match_the_host_sums() {
    for (name, text, steps) in [("small mill", SMALL_MILL, 1500), ("cube drum", SMALL_CUBE_DRUM, 1200)] {
        let sc = tracking_every_seventh(scene(text));
        let (groups, drums) = (sc.plan.model.wall_groups.len() as u64, sc.plan.model.drums.len() as u64);
        let tracked = sc.particles.track.iter().filter(|&&t| t).count() as u64;
        let mut gpu = GpuSimulation::new(sc).unwrap();
        gpu.advance(steps);
        let before = (gpu.readbacks(), gpu.readback_bytes());
        gpu.frame(false);
        // One partial per lane (observables, wall groups, drums), the track rows, 3600 bins per drum.
        let row = (1 + groups + drums) * 80 + tracked * 64 + drums * 3600 * 4;
        assert_eq!((gpu.readbacks() - before.0, gpu.readback_bytes() - before.1), (1, row), "{name}: one read-back of {row} bytes");
        assert!(groups >= 2 && drums >= 1, "{name}: {groups} wall groups, {drums} drums");
        assert_reduced_matches_full(name, &gpu);
    }
}

pub fn device_reduced_rows_match_the_host_sums_of_the_full_arrays() {
    // Spheres with rotation, friction and walls, most of them in contact.
    let mut gpu = GpuSimulation::new(tracking_every_seventh(energy_box(0.196, 300))).unwrap();
    gpu.advance(300);
    assert_reduced_matches_full("energy box", &gpu);
    // Cubes and spheres (body-frame inertia), history springs.
    let mut gpu = GpuSimulation::new(tracking_every_seventh(crate::polyhedra_step::bed(true, 0.36))).unwrap();
    gpu.advance(800);
    assert_reduced_matches_full("cube and sphere bed", &gpu);
    // Fluid work.
    let mut sc = scene(&file("scenes/verify/01_stokes_drag.toml"));
    sc.particles.track.iter_mut().for_each(|t| *t = true);
    let steps = sc.plan.run.steps / 4;
    let mut gpu = GpuSimulation::new(sc).unwrap();
    gpu.advance(steps);
    assert!(gpu.frame(false).observables.fluid_work != 0.0);
    assert_reduced_matches_full("stokes drag", &gpu);
}

pub fn an_output_row_reads_back_the_same_few_bytes_whatever_the_particle_count() {
    let mut bytes = Vec::new();
    for top in [0.07, 0.196] {
        let mut gpu = GpuSimulation::new(energy_box(top, 40)).unwrap();
        gpu.advance(40);
        let (before, before_bytes) = (gpu.readbacks(), gpu.readback_bytes());
        let frame = gpu.frame(false);
        assert_eq!(gpu.readbacks() - before, 1, "one read-back per output row");
        let row = gpu.readback_bytes() - before_bytes;
        assert_eq!(frame.tracks.len(), 3);
        // One 80-byte partial per lane (the observables, the box's wall group) and one 64-byte row per tracked particle.
        assert_eq!(row, 2 * 80 + 3 * 64, "{} particles", frame.observables.particles);
        let before_bytes = gpu.readback_bytes();
        gpu.frame(true);
        let full = gpu.readback_bytes() - before_bytes;
        println!("{} particles: an output row reads {row} bytes, a snapshot row {full}", frame.observables.particles);
        assert!(full > 100 * row);
        bytes.push((frame.observables.particles, row));
    }
    assert!(bytes[1].0 > 2 * bytes[0].0 && bytes[0].1 == bytes[1].1, "{bytes:?}");
}

pub fn device_reduced_rows_are_bit_identical_run_to_run() {
    for sc in [tracking_every_seventh(energy_box(0.196, 300)), tracking_every_seventh(scene(SMALL_MILL))] {
        rows_repeat(sc);
    }
}

fn rows_repeat(sc: CompiledScene) {
    let run = || {
        let mut gpu = GpuSimulation::new(sc.clone()).unwrap();
        let mut rows = Vec::new();
        for _ in 0..3 {
            gpu.advance(100);
            rows.push(gpu.frame(false));
        }
        rows
    };
    let (a, b) = (run(), run());
    let bits = |o: &Observables| {
        [o.kinetic_energy, o.rotational_energy, o.potential_energy, o.elastic_energy, o.dissipated_energy, o.fluid_work, o.max_overlap_ratio]
            .map(f64::to_bits)
    };
    for (x, y) in a.iter().zip(&b) {
        assert_eq!(bits(&x.observables), bits(&y.observables));
        assert_eq!(x.observables, y.observables);
        assert_eq!(x.tracks, y.tracks);
        let walls = |f: &tumble_state::Frame| {
            let loads = f.wall_force.iter().chain(&f.wall_torque).flat_map(|v| v.to_array());
            f.wall_power.iter().chain(&f.wall_work).copied().chain(loads).map(f64::to_bits).collect::<Vec<_>>()
        };
        assert_eq!(walls(x), walls(y));
        assert_eq!(format!("{:?}", x.drums), format!("{:?}", y.drums));
    }
    println!("three rows of two runs bit-identical ({} particles)", a[0].observables.particles);
}
