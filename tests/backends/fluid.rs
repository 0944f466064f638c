//! The SPH fluid on the GPU (f32) against tumble-sph's f64 phase on the CPU: one step term for
//! term with every switch of the method, a dam break's front, a column at rest, momentum in a
//! periodic box; the same bits run to run and from a snapshot.

use std::collections::HashMap;
use tumble_geom::{DVec3, PeriodicBox};
use tumble_gpu::GpuFluid;
use tumble_sph::cases::ColumnInTank;
use tumble_sph::*;
use tumble_testkit::run_files::{csv_column, scratch_dir};

/// The fluid particles' (position, velocity, density) by id.
fn by_id(p: &FluidParticles) -> HashMap<u32, (DVec3, DVec3, f64)> {
    (0..p.len()).filter(|&i| p.kind[i] == ParticleKind::Fluid).map(|i| (p.id[i], (p.position[i], p.velocity[i], p.density[i]))).collect()
}

fn front(p: &FluidParticles) -> f64 {
    (0..p.len()).filter(|&i| p.kind[i] == ParticleKind::Fluid).map(|i| p.position[i].x).fold(f64::NEG_INFINITY, f64::max)
}

/// A collapsing column after `steps` CPU steps, as the CPU phase and the same state on the GPU.
fn collapsing(case: ColumnInTank, steps: usize) -> (FluidPhase, GpuFluid, f64) {
    let mut cpu = case.build();
    let dt = TimeStepLimits::planned(cpu.settings()).dt();
    for _ in 0..steps {
        cpu.step(dt).unwrap();
    }
    let mut gpu = GpuFluid::new(cpu.settings(), cpu.particles()).unwrap();
    gpu.restore(&cpu.snapshot()).unwrap();
    (cpu, gpu, dt)
}

/// One step from the same moving state on both backends, with each switch of the method: the
/// velocities differ by f32 round-off of the largest acceleration times Δt, the densities by
/// f32 round-off of ρ₀ (a wrong sign, factor or missing term shows as a difference of the
/// term's own size, orders above these).
pub fn one_step_matches_the_cpu_with_every_switch() {
    let variants = [
        (Viscosity::Artificial { alpha: 0.02 }, DensityDiffusion::Fourtakas { delta: 0.1 }, false, 0.0),
        (Viscosity::Laminar, DensityDiffusion::MolteniColagrossi { delta: 0.1 }, true, 0.5),
        (Viscosity::Artificial { alpha: 0.1 }, DensityDiffusion::None, true, 0.0),
    ];
    for three_d in [false, true] {
        for (viscosity, diffusion, tensile, xsph) in variants {
            let mut case = ColumnInTank::plane(0.3, 0.1, 0.2, if three_d { 10 } else { 20 });
            if three_d {
                case.dimension = Dimension::Three;
                case.depth = 0.05;
            }
            (case.viscosity, case.diffusion, case.tensile_correction) = (viscosity, diffusion, tensile);
            let column = case.build();
            let settings = FluidSettings { xsph, ..column.settings().clone() };
            let mut cpu = FluidPhase::new(settings, column.particles().clone()).unwrap();
            let dt = TimeStepLimits::planned(cpu.settings()).dt();
            for _ in 0..150 {
                cpu.step(dt).unwrap();
            }
            let mut gpu = GpuFluid::new(cpu.settings(), cpu.particles()).unwrap();
            gpu.restore(&cpu.snapshot()).unwrap();
            let before = by_id(cpu.particles());
            cpu.step(dt).unwrap();
            gpu.advance(1, dt);
            let (c, g) = (by_id(cpu.particles()), by_id(&gpu.particles()));
            assert_eq!(c.len(), g.len());
            let (mut dv, mut largest_change, mut drho, mut dx) = (0.0f64, 0.0f64, 0.0f64, 0.0f64);
            for (id, (x, v, rho)) in &c {
                let (gx, gv, grho) = g[id];
                dv = dv.max((gv - *v).length());
                largest_change = largest_change.max((*v - before[id].1).length());
                drho = drho.max((grho - rho).abs());
                dx = dx.max((gx - *x).length());
            }
            let label = format!("3D {three_d}, {viscosity:?}, {diffusion:?}, tensile {tensile}, xsph {xsph}");
            println!("{label}: |Δv| {dv:.2e} of a step's change {largest_change:.2e}; |Δρ| {drho:.2e}; |Δx| {dx:.2e}");
            assert!(largest_change > 1e-4, "{label}: the step changed nothing");
            assert!(dv < 1e-3 * largest_change.max(1e-2), "{label}: velocities differ by {dv:.3e}");
            assert!(drho < 2e-3, "{label}: densities differ by {drho:.3e} kg/m³");
            assert!(dx < 1e-6, "{label}: positions differ by {dx:.3e} m");
        }
    }
}

/// The dam break (a = 5 cm, 30 particles over the column's height) on both backends: the
/// fronts agree within a tenth of the spacing up to T = t √(2g/a) = 2.5, where the front has
/// run 1.5 a.
pub fn a_dam_break_on_the_gpu_follows_the_cpu() {
    let a = 0.05;
    let case = ColumnInTank::plane(7.0 * a, a, 2.0 * a, 30);
    let (mut cpu, mut gpu, dt) = collapsing(case, 0);
    let scale = (2.0 * tumble_sph::cases::G / a).sqrt();
    let mut worst: f64 = 0.0;
    for t_star in [1.0, 2.0, 2.5] {
        let steps = ((t_star / scale - cpu.time()) / dt).round() as u64;
        for _ in 0..steps {
            cpu.step(dt).unwrap();
        }
        gpu.advance(steps, dt);
        let (fc, fg) = (front(cpu.particles()), front(&gpu.particles()));
        println!("T {t_star}: front {:.4} a on the CPU, {:.4} a on the GPU", fc / a, fg / a);
        worst = worst.max((fc - fg).abs());
    }
    let dp = case.spacing();
    assert!(worst < 0.1 * dp, "the fronts differ by {worst:.3e} m ({:.2} Δp)", worst / dp);
}

/// A column at rest (2D, H = 0.2 m, 20 particles over its height) after 0.3 s on the GPU: the
/// pressure below 2h matches ρ g z within 2 % of ρ g H, as on the CPU (tumble-sph's
/// hydrostatic tests), and no particle has crossed a wall.
pub fn a_column_at_rest_on_the_gpu_keeps_its_hydrostatic_pressure() {
    let (height, per_height) = (0.2, 20);
    let case = ColumnInTank::plane(0.1, 0.1, height, per_height);
    let cpu = case.build();
    let dt = TimeStepLimits::planned(cpu.settings()).dt();
    let mut gpu = GpuFluid::new(cpu.settings(), cpu.particles()).unwrap();
    let steps = (0.3 / dt).round() as u64;
    gpu.advance(steps, dt);
    let p = gpu.particles();
    let pressures = gpu.pressures();
    let (rho0, g, h) = (cpu.settings().rho0, tumble_sph::cases::G, cpu.settings().h);
    let bottom = rho0 * g * height;
    let mut worst: f64 = 0.0;
    let mut checked = 0;
    for i in 0..p.len() {
        let x = p.position[i];
        if p.kind[i] != ParticleKind::Fluid {
            continue;
        }
        assert!(x.x > 0.0 && x.x < 0.1 && x.z > 0.0, "particle {} crossed a wall: {x}", p.id[i]);
        let depth = height - x.z;
        if depth > 2.0 * h {
            worst = worst.max((pressures[i] - rho0 * g * depth).abs());
            checked += 1;
        }
    }
    println!("{checked} particles below 2h: largest error {:.3} % of ρgH after {steps} steps", 100.0 * worst / bottom);
    assert!(checked > 100);
    assert!(worst < 0.02 * bottom, "pressure off ρgz by {:.2} % of ρgH", 100.0 * worst / bottom);
}

/// A periodic box (3D, every axis periodic, no gravity) of fluid stirred at random: its momentum
/// stays at its start within f32 round-off of the momenta exchanged, and the particles come back
/// through the sides.
pub fn a_periodic_box_on_the_gpu_keeps_its_momentum() {
    let dp = 0.01;
    let side = 0.08;
    let settings = FluidSettings {
        dimension: Dimension::Three,
        spacing: dp,
        h: 1.3 * dp,
        rho0: 1000.0,
        mu: 1e-3,
        sound_speed: 10.0,
        viscosity: Viscosity::Artificial { alpha: 0.05 },
        density_diffusion: DensityDiffusion::Fourtakas { delta: 0.1 },
        tensile_correction: true,
        xsph: 0.0,
        gravity: DVec3::ZERO,
        body_force: DVec3::ZERO,
        domain: PeriodicBox { min: DVec3::ZERO, max: DVec3::splat(side), periodic: [true; 3] },
        moving_walls: Vec::new(),
        floating: Vec::new(),
        inflows: Vec::new(),
        outflows: Vec::new(),
    };
    let mut particles = FluidParticles::default();
    let n = (side / dp).round() as usize;
    let mut seed = 12345u64;
    let mut random = || {
        seed = seed.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
        (seed >> 11) as f64 / (1u64 << 53) as f64 - 0.5
    };
    for k in 0..n * n * n {
        let x = DVec3::new((k % n) as f64, ((k / n) % n) as f64, (k / (n * n)) as f64) * dp + DVec3::splat(0.5 * dp);
        let v = DVec3::new(random(), random(), random()) + DVec3::new(0.3, 0.0, 0.0);
        particles.push(ParticleKind::Fluid, x, v, 1000.0, 1000.0 * dp * dp * dp);
    }
    let momentum = |p: &FluidParticles| (0..p.len()).map(|i| p.mass[i] * p.velocity[i]).sum::<DVec3>();
    let exchanged = |p: &FluidParticles| (0..p.len()).map(|i| p.mass[i] * p.velocity[i].length()).sum::<f64>();
    let mut gpu = GpuFluid::new(&settings, &particles).unwrap();
    let start = momentum(&particles);
    let dt = TimeStepLimits::planned(&settings).dt();
    gpu.advance(200, dt);
    let p = gpu.particles();
    let drift = (momentum(&p) - start).length();
    let scale = exchanged(&particles);
    println!("momentum {start} → {}: moved by {:.2e} of Σ m|v| = {scale:.3e}", momentum(&p), drift / scale);
    assert!(p.position.iter().all(|x| x.cmpge(DVec3::ZERO).all() && x.cmplt(DVec3::splat(side)).all()), "a particle left the periodic box");
    assert!(drift < 1e-5 * scale, "the momentum moved by {drift:.3e} kg m/s");
    let wrapped = (0..p.len()).filter(|&i| (p.position[i].x - particles.position[p.id[i] as usize].x).abs() > 0.5 * side).count();
    assert!(wrapped > 0, "no particle came back through a side");
}

/// Two GPU runs of a dam break give the same bits, and one continued from a snapshot taken
/// halfway gives them too.
pub fn gpu_fluid_runs_are_bit_identical_and_restart_exactly() {
    let a = 0.05;
    let case = ColumnInTank::plane(4.0 * a, a, 2.0 * a, 20);
    let (_, mut first, dt) = collapsing(case, 0);
    let (_, mut second, _) = collapsing(case, 0);
    first.advance(150, dt);
    let halfway = first.snapshot();
    first.advance(150, dt);
    second.advance(300, dt);
    assert!(first.particles() == second.particles(), "two runs differ");
    let (_, mut resumed, _) = collapsing(case, 0);
    resumed.restore(&halfway).unwrap();
    resumed.advance(150, dt);
    assert!(resumed.particles() == first.particles(), "the resumed run differs");
    assert_eq!(resumed.steps(), 300);
    assert!(front(&first.particles()) > 1.1 * a, "the column has not moved: front {}", front(&first.particles()));
}

/// Runs the `tumble` command in the repository's root; it must succeed.
fn tumble(args: &[&str]) {
    let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR"));
    let o =
        std::process::Command::new(env!("CARGO_BIN_EXE_tumble")).args(args).current_dir(root).stdin(std::process::Stdio::null()).output().unwrap();
    assert!(o.status.success(), "{args:?}: {}", String::from_utf8_lossy(&o.stderr));
}

/// A shipped scene with `from` replaced by `to` (a coarser spacing), written into `dir`.
fn shipped_scene(dir: &std::path::Path, scene: &str, from: &str, to: &str) -> String {
    let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR"));
    let text = std::fs::read_to_string(root.join("scenes").join(scene)).unwrap();
    assert!(text.contains(from), "{scene} has no {from}");
    let path = dir.join(scene);
    std::fs::write(&path, text.replace(from, to)).unwrap();
    path.to_str().unwrap().to_string()
}

/// `tumble run SCENE --backend BACKEND` into `dir/out` for `duration`, with checkpoints.
fn run_scene(dir: &std::path::Path, scene: &str, out: &str, duration: &str, backend: &str) {
    let out = dir.join(out);
    tumble(&["run", scene, "--quiet", "--backend", backend, "--duration", duration, "--checkpoint-interval", "0.02", "--out", out.to_str().unwrap()]);
}

/// `scene` on the GPU for `duration` into `dir/gpu`, checkpointed every quarter of it; then a
/// copy of that folder cut back to its checkpoint at three quarters (the newer one removed)
/// and resumed to `duration` in `dir/resumed`: `files` of the two runs are byte-identical. (A
/// second run to a checkpoint halfway would cost half as much again on lavapipe.)
fn gpu_run_resumes_identically(dir: &std::path::Path, scene: &str, duration: f64, files: &[&str]) {
    let (full, resumed) = (dir.join("gpu"), dir.join("resumed"));
    let (d, every) = (duration.to_string(), (duration / 4.0).to_string());
    tumble(&["run", scene, "--quiet", "--backend", "gpu", "--duration", &d, "--checkpoint-interval", &every, "--out", full.to_str().unwrap()]);
    copy_folder(&full, &resumed);
    let dt = summary_dt(&full);
    let resume_step = (0.75 * duration / dt).round() as u64 + 1;
    let mut kept = Vec::new();
    for entry in std::fs::read_dir(resumed.join("checkpoints")).unwrap() {
        let path = entry.unwrap().path();
        let step: u64 = path.file_stem().unwrap().to_str().unwrap().trim_start_matches("step_").parse().unwrap();
        if step > resume_step { std::fs::remove_file(&path).unwrap() } else { kept.push(step) }
    }
    assert!(kept.iter().any(|&s| s as f64 * dt > 0.5 * duration), "no checkpoint between half and three quarters: {kept:?}");
    tumble(&["resume", resumed.to_str().unwrap(), "--quiet", "--duration", &d]);
    for file in files {
        let (a, b) = (std::fs::read(full.join(file)).unwrap(), std::fs::read(resumed.join(file)).unwrap());
        assert!(a == b, "{file} differs after the resume");
    }
}

/// The step Δt of the run in `out`, from its summary.json.
fn summary_dt(out: &std::path::Path) -> f64 {
    let summary: serde_json::Value = serde_json::from_str(&std::fs::read_to_string(out.join("summary.json")).unwrap()).unwrap();
    summary["dt"].as_f64().unwrap()
}

/// Copies the folder `from` (and its subfolders) to `to`.
fn copy_folder(from: &std::path::Path, to: &std::path::Path) {
    std::fs::create_dir_all(to).unwrap();
    for entry in std::fs::read_dir(from).unwrap() {
        let entry = entry.unwrap();
        let target = to.join(entry.file_name());
        if entry.file_type().unwrap().is_dir() {
            copy_folder(&entry.path(), &target);
        } else {
            std::fs::copy(entry.path(), target).unwrap();
        }
    }
}

/// The shipped dam break (at twice its spacing) run by `tumble run --backend gpu` for 0.06 s: a
/// run checkpointed at 0.045 s and resumed writes the same fluid.csv, probes and fluid snapshots as one
/// that went straight through, and its front is the CPU's within a tenth of the spacing.
pub fn a_gpu_fluid_scene_resumes_bit_identically() {
    let dir = scratch_dir("gpu-fluid", "resume");
    let scene = shipped_scene(&dir, "dam_break.toml", "spacing = 0.0025", "spacing = 0.005");
    let files = ["fluid.csv", "probe_front.csv", "probe_column.csv", "probe_floor.csv", "snapshots/fluid_000003.vtp"];
    gpu_run_resumes_identically(&dir, &scene, 0.06, &files);
    run_scene(&dir, &scene, "cpu", "0.06", "cpu");
    let (gpu, cpu) = (
        *csv_column(&dir.join("gpu/probe_front.csv"), "front").last().unwrap(),
        *csv_column(&dir.join("cpu/probe_front.csv"), "front").last().unwrap(),
    );
    println!("front at 0.06 s: GPU {gpu:.6} m, CPU {cpu:.6} m");
    assert!((gpu - cpu).abs() < 0.1 * 0.005, "fronts {gpu} and {cpu} differ");
    let _ = std::fs::remove_dir_all(&dir);
}

/// The shipped turning drum (at twice its spacing, its turning ramped up over 0.5 s) on both
/// backends for 0.2 s: the water beside the wall is dragged as on the CPU (the bottom probe's
/// velocity within 2 % of the wall's speed), the deep probe reads the CPU's pressure within 1 %,
/// and a run resumed from a checkpoint writes the same files.
pub fn a_turning_drum_on_the_gpu_drags_the_water_as_on_the_cpu() {
    let dir = scratch_dir("gpu-fluid", "drum");
    let scene = shipped_scene(&dir, "drum_water.toml", "spacing = 0.0025", "spacing = 0.005");
    gpu_run_resumes_identically(&dir, &scene, 0.2, &["fluid.csv", "probe_bottom.csv", "probe_deep.csv"]);
    run_scene(&dir, &scene, "cpu", "0.2", "cpu");
    let read = |out: &str, file: &str, column: &str| *csv_column(&dir.join(out).join(file), column).last().unwrap();
    let (vg, vc) = (read("gpu", "probe_bottom.csv", "velocity_x"), read("cpu", "probe_bottom.csv", "velocity_x"));
    let (pg, pc) = (read("gpu", "probe_deep.csv", "pressure"), read("cpu", "probe_deep.csv", "pressure"));
    let wall_speed = 10.0 * 2.0 * std::f64::consts::PI / 60.0 * 0.1 * 0.2 / 0.5;
    println!("at 0.2 s: bottom velocity GPU {vg:.5} m/s, CPU {vc:.5} m/s (wall {wall_speed:.4} m/s); deep pressure GPU {pg:.2} Pa, CPU {pc:.2} Pa");
    assert!(vc < -0.15 * wall_speed, "the CPU's water is not dragged: {vc}");
    assert!((vg - vc).abs() < 0.02 * wall_speed, "bottom velocity {vg} against the CPU's {vc}");
    assert!((pg - pc).abs() < 0.01 * pc, "deep pressure {pg} against the CPU's {pc}");
    let _ = std::fs::remove_dir_all(&dir);
}

/// The shipped floating box (at twice its spacing, 1 cm) dropped into its tank on both backends
/// for 0.4 s: it strikes the water at 0.1 s at 1 m/s and sinks in. The GPU's body follows the
/// CPU's at every row (its height within a tenth of the spacing, its vertical velocity within
/// 5 % of the fastest), and a GPU run resumed from a checkpoint writes the same files. A force
/// summed wrong on the device (a sign, a missing term, a body's particles missed) stops or
/// throws the box at once.
pub fn a_floating_box_on_the_gpu_moves_as_on_the_cpu() {
    let dir = scratch_dir("gpu-fluid", "floating");
    let scene = shipped_scene(&dir, "floating_box.toml", "spacing = 0.005", "spacing = 0.01");
    gpu_run_resumes_identically(&dir, &scene, 0.4, &["fluid.csv", "floating_box.csv", "probe_left.csv"]);
    run_scene(&dir, &scene, "cpu", "0.4", "cpu");
    let read = |out: &str, name: &str| csv_column(&dir.join(out).join("floating_box.csv"), name);
    let (zg, zc, vg, vc) = (read("gpu", "z"), read("cpu", "z"), read("gpu", "velocity_z"), read("cpu", "velocity_z"));
    assert_eq!(zg.len(), zc.len());
    let fastest = vc.iter().fold(0.0f64, |m, v| m.max(v.abs()));
    let dz = zg.iter().zip(&zc).map(|(a, b)| (a - b).abs()).fold(0.0, f64::max);
    let dv = vg.iter().zip(&vc).map(|(a, b)| (a - b).abs()).fold(0.0, f64::max);
    println!(
        "floating box, {} rows to 0.4 s: centre from {:.4} to {:.4} m (CPU {:.4} m), largest difference {dz:.2e} m; vertical velocity within {dv:.2e} of the fastest {fastest:.3} m/s",
        zc.len(),
        zc[0],
        zg[zg.len() - 1],
        zc[zc.len() - 1]
    );
    assert!(zc[0] - zc[zc.len() - 1] > 0.06, "the CPU's box did not fall into the water: {zc:?}");
    assert!(dz < 0.1 * 0.01, "the GPU's box is {dz} m from the CPU's");
    assert!(dv < 0.05 * fastest, "the GPU's box moves at up to {dv} m/s from the CPU's");
    let _ = std::fs::remove_dir_all(&dir);
}

/// A GPU run from a shell without XDG_RUNTIME_DIR (batch jobs, containers) prints only its own
/// lines: Mesa's "XDG_RUNTIME_DIR is invalid or not set" error, which used to come with every
/// GPU command, is not among them.
pub fn a_gpu_run_without_a_runtime_dir_prints_no_loader_error() {
    let dir = scratch_dir("gpu-fluid", "xdg");
    let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR"));
    let scene = root.join("scenes/conformance/fluid_dam_break.toml");
    let out = dir.join("out");
    let o = std::process::Command::new(env!("CARGO_BIN_EXE_tumble"))
        .args(["run", scene.to_str().unwrap(), "--backend", "gpu", "--duration", "0.005", "--quiet", "--out", out.to_str().unwrap()])
        .env_remove("XDG_RUNTIME_DIR")
        .stdin(std::process::Stdio::null())
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(o.status.success(), "{err}");
    assert!(!err.contains("XDG_RUNTIME_DIR"), "{err}");
    let _ = std::fs::remove_dir_all(&dir);
}
