//! Particles and a 3D SPH fluid acting on each other in a run (docs/sph.md, "Coupling the
//! particles"): a sphere settles through the shipped scene's liquid moving through it at its drag
//! law's terminal velocity and a light one rises, fluid and particles together conserve their
//! momentum in a periodic box, coupled runs do not depend on the thread count and continue
//! bit-identically through a checkpoint, and the plan says when the phases couple.

use glam::DVec3;
use std::path::{Path, PathBuf};
use std::process::{Command, Output, Stdio};
use tumble::Simulation;
use tumble_testkit::run_files::{assert_thread_independent_and_resumable, csv_column, scratch_dir};

fn root() -> &'static Path {
    Path::new(env!("CARGO_MANIFEST_DIR"))
}

fn tmp_dir(name: &str) -> PathBuf {
    scratch_dir("coupling", name)
}

fn tumble(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_tumble")).args(args).current_dir(root()).stdin(Stdio::null()).output().unwrap()
}

/// The glass of the scenes written here and their contact laws.
const GLASS: &str = r#"[[materials]]
name = "glass"
density = 2500.0
youngs_modulus = 1.0e8
poisson_ratio = 0.25
[contact]
normal = { model = "hertz" }
restitution = 0.5
tangential = { model = "history", friction = 0.3 }
"#;

/// The terminal velocity of a sphere of `diameter` and `density` in the liquid of the shipped
/// settling scene (1000 kg/m³, 1 Pa s) under Gidaspow's law at ε = 1 (Wen & Yu, Schiller &
/// Naumann's C_D), solved by fixed-point iteration.
fn terminal_velocity(diameter: f64, density: f64) -> f64 {
    let (rho, mu, g) = (1000.0, 1.0, 9.81);
    let mut v: f64 = 1e-3;
    for _ in 0..200 {
        let re = rho * diameter * v / mu;
        let cd = 24.0 / re * (1.0 + 0.15 * re.powf(0.687));
        v = (4.0 * (density - rho).abs() * g * diameter / (3.0 * cd * rho)).sqrt();
    }
    v
}

/// Runs the shipped settling sphere (its density replaced by `density`, its start at height
/// `z`) for `duration`; answers its vertical velocity and the slip the coupling read, per row.
fn settle(dir: &Path, density: f64, z: f64, duration: &str) -> (Vec<f64>, Vec<f64>, Vec<f64>) {
    let text = std::fs::read_to_string(root().join("scenes/settling_sphere.toml")).unwrap();
    let text = text.replace("density = 2500.0", &format!("density = {density:.1}")).replace("0.024, 0.024, 0.07]]", &format!("0.024, 0.024, {z}]]"));
    let scene = dir.join("scene.toml");
    std::fs::write(&scene, text).unwrap();
    let out = dir.join("out");
    let o = tumble(&["run", scene.to_str().unwrap(), "--quiet", "--duration", duration, "--out", out.to_str().unwrap()]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    (csv_column(&out.join("tracks.csv"), "t"), csv_column(&out.join("tracks.csv"), "vz"), csv_column(&out.join("coupling.csv"), "largest_slip"))
}

/// The glass sphere of the shipped scene (3 mm, 2500 kg/m³; h/d = 3; Re = 0.02) sinks. From 5
/// relaxation times on the coupling reads its slip through the liquid about it within 3 % of
/// the law's terminal velocity (measured −1.8 to +0.5 %). Its own speed follows the liquid
/// about it, which the column's settling and the sphere's own drag set moving at a few mm/s
/// (docs/sph.md): its mean over the rows is held within 15 % (measured −3.9 %), which still
/// catches a missing buoyancy (+67 %) or a halved drag (+100 %).
#[test]
fn a_sphere_sinks_through_the_liquid_at_its_drag_laws_terminal_velocity() {
    let dir = tmp_dir("sink");
    let (t, vz, slip) = settle(&dir, 2500.0, 0.07, "0.02");
    let vt = terminal_velocity(0.003, 2500.0);
    let relaxation = 2500.0 * 0.003f64.powi(2) / 18.0;
    let rows: Vec<usize> = (0..t.len()).filter(|&k| t[k] > 5.0 * relaxation).collect();
    for &k in &rows {
        println!(
            "t = {:.4} s: speed {:.4e} m/s ({:+.2} %), slip {:.4e} m/s ({:+.2} %)",
            t[k],
            -vz[k],
            100.0 * (-vz[k] / vt - 1.0),
            slip[k],
            100.0 * (slip[k] / vt - 1.0)
        );
        assert!((slip[k] / vt - 1.0).abs() < 0.03, "slip {} against {vt}", slip[k]);
    }
    let mean = -rows.iter().map(|&k| vz[k]).sum::<f64>() / rows.len() as f64;
    println!("mean speed {mean:.4e} m/s against the law's {vt:.4e} m/s ({:+.2} %)", 100.0 * (mean / vt - 1.0));
    assert!(rows.len() >= 10 && (mean / vt - 1.0).abs() < 0.15);
    let _ = std::fs::remove_dir_all(&dir);
}

/// A sphere of 500 kg/m³ rises through the same liquid: buoyancy comes from the fluid's pressure
/// gradient, and the drag opposes the motion whichever way it goes. Its slip is held within 3 %
/// of the law's terminal velocity; its own slower speed (measured −10 % on average) follows
/// the liquid about it, held within 35 %.
#[test]
fn a_light_sphere_rises_through_the_liquid() {
    let dir = tmp_dir("rise");
    let (t, vz, slip) = settle(&dir, 500.0, 0.03, "0.02");
    let vt = terminal_velocity(0.003, 500.0);
    let rows: Vec<usize> = (0..t.len()).filter(|&k| t[k] > 0.005).collect();
    for &k in &rows {
        assert!((slip[k] / vt - 1.0).abs() < 0.03, "slip {} against {vt}", slip[k]);
    }
    let mean = rows.iter().map(|&k| vz[k]).sum::<f64>() / rows.len() as f64;
    println!("rising at {mean:.4e} m/s on average; the law's terminal velocity {vt:.4e} m/s ({:+.2} %)", 100.0 * (mean / vt - 1.0));
    assert!(mean > 0.0 && (mean / vt - 1.0).abs() < 0.35);
    let _ = std::fs::remove_dir_all(&dir);
}

/// Five glass spheres thrown through water filling a fully periodic 10 cm box, no gravity: the
/// drag slows them and the water takes up what they lose, so the momentum of both together
/// stays what it was to round-off at every row.
#[test]
fn fluid_and_particles_conserve_their_momentum_in_a_periodic_box() {
    let scene = r#"
name = "periodic-coupling"
[run]
duration = 0.05
output_interval = 0.01
[domain]
min = [0.0, 0.0, 0.0]
max = [0.1, 0.1, 0.1]
periodic = [true, true, true]
GLASS
[[particles]]
material = "glass"
shape = { sphere = { diameter = 0.008 } }
positions = [[0.02, 0.03, 0.05], [0.05, 0.05, 0.05], [0.08, 0.07, 0.02], [0.03, 0.08, 0.08], [0.07, 0.02, 0.07]]
velocity = [0.3, -0.1, 0.2]
[sph]
spacing = 0.01
density = 1000.0
viscosity = 1.0e-3
expected_speed = 0.5
density_diffusion = { model = "fourtakas", delta = 0.1 }
[[sph.regions]]
box = { min = [0.0, 0.0, 0.0], max = [0.1, 0.1, 0.1] }
"#
    .replace("GLASS\n", GLASS);
    let compiled = tumble_scene::compile(&tumble_scene::parse_scene(&scene).unwrap()).unwrap();
    assert!(compiled.plan.coupling().is_some_and(|c| c.substeps > 1), "the plan couples the phases with sub-steps");
    let mut sim = Simulation::new(compiled, 2);
    let momentum = |sim: &Simulation| {
        let s = sim.state();
        let solids: DVec3 = (0..s.len()).map(|i| s.mass[i] * s.vel[i]).sum();
        (solids, sim.fluid_phase().unwrap().fluid().observables().momentum)
    };
    let (solids0, fluid0) = momentum(&sim);
    let scale = solids0.length();
    let every = sim.plan().run.output_every;
    for _ in 0..5 {
        sim.advance(every);
        assert!(sim.stop().is_none(), "{:?}", sim.stop());
        let (solids, fluid) = momentum(&sim);
        let drift = (solids + fluid - solids0 - fluid0).length() / scale;
        println!(
            "t = {:.3} s: the spheres keep {:.1} % of their momentum; fluid and spheres drift by {drift:.2e}",
            sim.time(),
            100.0 * solids.dot(solids0) / scale.powi(2)
        );
        assert!(drift < 1e-12, "drift {drift:e}");
    }
    let (solids, _) = momentum(&sim);
    assert!(solids.dot(solids0) < 0.95 * scale * scale, "the water slowed the spheres");
}

/// A coupled run writes the same files on 1 and 2 threads, and a run checkpointed halfway
/// and resumed writes them too.
#[test]
fn coupled_runs_are_thread_independent_and_resume_bit_identically() {
    let dir = tmp_dir("resume");
    let text = std::fs::read_to_string(root().join("scenes/settling_sphere.toml")).unwrap();
    let scene = dir.join("scene.toml");
    std::fs::write(&scene, text.replace("output_interval = 0.001", "output_interval = 0.001\nsnapshot_interval = 0.002")).unwrap();
    let one = assert_thread_independent_and_resumable(Path::new(env!("CARGO_BIN_EXE_tumble")), root(), &scene, &dir, ["0.002", "0.004", "0.002"]);
    let has = |file: &str, name: &str| {
        let bytes = std::fs::read(one.join("snapshots").join(file)).unwrap();
        let name = format!("Name=\"{name}\"");
        bytes.windows(name.len()).any(|w| w == name.as_bytes())
    };
    assert!(has("fluid_000002.vtp", "fluid_fraction") && has("particles_000002.vtp", "fluid_force"));
    let _ = std::fs::remove_dir_all(&dir);
}

/// `tumble plan` says the phases couple and why; a plane fluid beside particles does not couple
/// and says so; a prescribed [fluid] beside a coupled one is refused; the GPU refuses coupling.
#[test]
fn the_plan_says_when_the_particles_and_the_fluid_couple() {
    let o = tumble(&["plan", "scenes/settling_sphere.toml"]);
    let text = String::from_utf8_lossy(&o.stdout);
    assert!(o.status.success() && text.contains("coupling     on, as the scene has particles and a 3D fluid"), "{text}");
    let dir = tmp_dir("plan");
    let base = std::fs::read_to_string(root().join("scenes/settling_sphere.toml")).unwrap();
    let plane = base.replace("dimension = 3", "dimension = 2");
    let write = |name: &str, text: &str| {
        let p = dir.join(name);
        std::fs::write(&p, text).unwrap();
        p.to_str().unwrap().to_string()
    };
    let o = tumble(&["plan", &write("plane.toml", &plane)]);
    let text = String::from_utf8_lossy(&o.stdout);
    assert!(!text.contains("coupling     on") && text.contains("do not act on each other"), "{text}{}", String::from_utf8_lossy(&o.stderr));
    let doubled = format!("{base}\n[fluid]\nviscosity = 1.0\n");
    let o = tumble(&["plan", &write("doubled.toml", &doubled)]);
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(!o.status.success() && err.contains("would drag them twice"), "{err}");
    let o = tumble(&["run", "scenes/settling_sphere.toml", "--backend", "gpu", "--quiet", "--out", dir.join("gpu").to_str().unwrap()]);
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(!o.status.success() && err.contains("CPU backend only"), "{err}");
    let _ = std::fs::remove_dir_all(&dir);
}

/// A bed of fixed glass spheres (3 mm on a 3.6 mm lattice: solid fraction 0.30) fills the lower
/// 25 mm of a 60 mm water column. In the locally averaged equations the water fills only the
/// pores and its pressure is that of its own density: between the probes 6 and 36 mm above the
/// floor it rises by ρ g Δz, as without the bed (measured +1.5 %; the bed's weight (1 − ε) ρ g
/// per volume carried by the water instead would add 19 %), and the spheres together feel the
/// buoyancy ρ g V of their volume (measured +5.9 %, the bed's edges, where the water's density
/// changes, read high). Its front upwards is its top layer.
#[test]
fn water_in_a_fixed_bed_rests_at_its_hydrostatic_pressure_and_buoys_the_spheres() {
    let scene = r#"
name = "bed-at-rest"
[run]
duration = 0.15
output_interval = 0.025
[domain]
min = [0.0, 0.0, 0.0]
max = [0.0396, 0.0396, 0.08]
[gravity]
acceleration = [0.0, 0.0, -9.81]
GLASS
[[particles]]
material = "glass"
fixed = true
shape = { sphere = { diameter = 0.003 } }
lattice = { min = [0.0, 0.0, 0.0], max = [0.0396, 0.0396, 0.0252], spacing = 0.0036 }
[sph]
spacing = 0.0036
density = 1000.0
viscosity = 1.0e-3
expected_speed = 1.1
viscosity_model = { model = "artificial", alpha = 0.1 }
density_diffusion = { model = "fourtakas", delta = 0.1 }
coupling = { front = [0.0, 0.0, 2.0] }
[[sph.regions]]
box = { min = [0.0, 0.0, 0.0], max = [0.0396, 0.0396, 0.06] }
[[sph.probes]]
name = "bottom"
pressure = [0.0198, 0.0198, 0.006]
[[sph.probes]]
name = "above"
pressure = [0.0198, 0.0198, 0.036]
[[walls]]
material = "glass"
box = { min = [0.0, 0.0, 0.0], max = [0.0396, 0.0396, 0.08] }
"#
    .replace("GLASS\n", GLASS);
    let dir = tmp_dir("bed");
    let path = dir.join("bed.toml");
    std::fs::write(&path, scene).unwrap();
    let out = dir.join("out");
    let o = tumble(&["run", path.to_str().unwrap(), "--quiet", "--out", out.to_str().unwrap()]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let (rho, g) = (1000.0, 9.81);
    let last = |file: &str, column_name: &str| *csv_column(&out.join(file), column_name).last().unwrap();
    let spheres = 11.0 * 11.0 * 7.0;
    let buoyancy = spheres * rho * g * std::f64::consts::PI / 6.0 * 0.003f64.powi(3);
    let (bottom, above) = (last("probe_bottom.csv", "pressure"), last("probe_above.csv", "pressure"));
    let (lift, fraction) = (last("coupling.csv", "fluid_force_z"), last("coupling.csv", "mean_fluid_fraction"));
    let speed = last("fluid.csv", "largest_speed");
    println!(
        "bottom {bottom:.1} Pa, above the bed {above:.1} Pa: {:.1} Pa apart against ρ g Δz = {:.1}; the spheres' lift {lift:.4e} N against ρ g V = {buoyancy:.4e} N; fluid fraction at them {fraction:.4}; largest speed {speed:.2e} m/s",
        bottom - above,
        rho * g * 0.030
    );
    assert_eq!(last("coupling.csv", "wetted_particles"), spheres);
    // The bed's front upwards: its top layer of centres, 0.0018 + 6 × 0.0036 m.
    assert!((last("coupling.csv", "solid_front") - 0.0234).abs() < 1e-12);
    assert!(((bottom - above) / (rho * g * 0.030) - 1.0).abs() < 0.03, "bottom {bottom}, above {above}");
    assert!((lift / buoyancy - 1.0).abs() < 0.08, "lift {lift}");
    assert!(fraction > 0.65 && fraction < 0.8 && speed < 0.05, "{fraction} {speed}");
    let _ = std::fs::remove_dir_all(&dir);
}

/// Water driven by a body force g through a fixed cubic lattice of 2 mm glass spheres 2.2 mm
/// apart (fluid fraction 1 − π/6 (2/2.2)³ = 0.6066) filling a fully periodic box; h/d = 2.5.
/// In steady flow the water's weight ε ρ g per volume is all handed to the bed, as a pressure
/// gradient G would hand over ε G: the body force stands for G = ρ g. The superficial velocity
/// U = Σ m u / (ρ V) the water reaches then meets Ergun's (1952) pressure drop,
/// G = 150 μ (1 − ε)² U / (ε³ d²) + 1.75 ρ (1 − ε) U² / (ε³ d), at the fraction the spheres
/// read, within 1 %, with the viscous term ahead (Re = 5.5) and the inertial one (Re = 141)
/// (measured −0.011 and −0.015 %); the fraction they read is the lattice's within 0.1 %
/// (measured equal to 5 digits). Ergun's G moves 10 % for 0.01 of fraction.
#[test]
fn water_driven_through_a_fixed_bed_meets_erguns_pressure_drop() {
    let (rho, mu, d, spacing): (f64, f64, f64, f64) = (1000.0, 1.0e-3, 0.002, 0.0022);
    let lattice_fraction = 1.0 - std::f64::consts::PI / 6.0 * (d / spacing).powi(3);
    let dir = tmp_dir("ergun");
    // (g, the fluid's expected speed, duration): seven drag relaxation times ε ρ / β each.
    for (g, expected_speed, duration) in [(0.083, 0.02, 0.45), (9.56, 0.12, 0.1)] {
        let scene = format!(
            r#"
name = "packed-bed-flow"
[run]
duration = {duration}
output_interval = {duration}
[domain]
min = [0.0, 0.0, 0.0]
max = [0.0264, 0.0264, 0.0264]
periodic = [true, true, true]
[gravity]
acceleration = [{g}, 0.0, 0.0]
{GLASS}
[[particles]]
material = "glass"
fixed = true
shape = {{ sphere = {{ diameter = {d} }} }}
lattice = {{ min = [0.0, 0.0, 0.0], max = [0.0264, 0.0264, 0.0264], spacing = {spacing} }}
[sph]
spacing = 0.0033
density = {rho}
viscosity = {mu}
expected_speed = {expected_speed}
viscosity_model = {{ model = "laminar" }}
density_diffusion = {{ model = "fourtakas", delta = 0.1 }}
[[sph.regions]]
box = {{ min = [0.0, 0.0, 0.0], max = [0.0264, 0.0264, 0.0264] }}
"#
        );
        let path = dir.join(format!("bed-{g}.toml"));
        std::fs::write(&path, scene).unwrap();
        let out = dir.join(format!("out-{g}"));
        let o = tumble(&["run", path.to_str().unwrap(), "--quiet", "--out", out.to_str().unwrap()]);
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        let last = |file: &str, name: &str| *csv_column(&out.join(file), name).last().unwrap();
        let u = last("fluid.csv", "momentum_x") / (rho * 0.0264f64.powi(3));
        let e = last("coupling.csv", "mean_fluid_fraction");
        let viscous = 150.0 * mu * (1.0 - e).powi(2) * u / (e.powi(3) * d * d);
        let inertial = 1.75 * rho * (1.0 - e) * u * u / (e.powi(3) * d);
        let ergun = viscous + inertial;
        println!(
            "g = {g} m/s²: U = {u:.5e} m/s (Re = {:.1}), fraction read {e:.5} against the lattice's {lattice_fraction:.5}; Ergun's G {ergun:.5e} Pa/m ({:.0} % viscous) against ρ g = {:.5e} ({:+.3} %)",
            rho * u * d / mu,
            100.0 * viscous / ergun,
            rho * g,
            100.0 * (ergun / (rho * g) - 1.0)
        );
        assert!((e / lattice_fraction - 1.0).abs() < 1e-3, "fraction {e}");
        assert!((ergun / (rho * g) - 1.0).abs() < 0.01, "Ergun's {ergun} against {}", rho * g);
        // The two regimes are both reached.
        assert!(if g < 1.0 { viscous > 0.8 * ergun } else { inertial > 0.7 * ergun });
        // The run says where its time went.
        let summary: serde_json::Value = serde_json::from_str(&std::fs::read_to_string(out.join("summary.json")).unwrap()).unwrap();
        for part in ["fluid", "coupling", "particles"] {
            assert!(summary["step_seconds"][part].as_f64().is_some_and(|s| s > 0.0), "{part}: {}", summary["step_seconds"]);
        }
        assert!(String::from_utf8_lossy(&o.stdout).contains("time in the step: fluid"));
    }
    let _ = std::fs::remove_dir_all(&dir);
}
