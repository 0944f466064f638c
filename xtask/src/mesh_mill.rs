//! `cargo xtask mesh-mill`: the laboratory mill of scenes/lab_mill/ at its calibration point
//! (20 % filling, 50 % of critical, μ_w = 0.9, μ_r = 0.4) with its eight lifter bars given as one
//! closed mesh turning with the shell, against the analytic lifter prisms, over several seeds:
//! the power each draws, written to docs/charts/mill_mesh_liner.csv (docs/meshes.md).

use crate::mill::{arg, charge_means, run_all, threads};
use crate::mill_calibration::calibration_scene;
use crate::seed_stats::{compare, write_csv};
use std::fmt::Write as _;
use std::time::Instant;
use tumble::{Simulation, compile};
use tumble_geom::SurfaceShape;
use tumble_scene::schema::{MeshSection, Scene};

/// Writes the scene's lifter prisms (two triangles per face) to an OBJ file; returns the count.
fn write_lifters(scene: &Scene, path: &std::path::Path) -> usize {
    let plan = compile(scene).unwrap_or_else(|e| panic!("{e}")).plan;
    let mut text = String::new();
    let mut faces = 0;
    for w in &plan.model.walls {
        if let SurfaceShape::Prism(p) = &w.shape {
            for face in p.corners() {
                for v in face {
                    let _ = writeln!(text, "v {:?} {:?} {:?}", v.x, v.y, v.z);
                }
                let k = 4 * faces + 1;
                let _ = writeln!(text, "f {} {} {}\nf {} {} {}", k, k + 1, k + 2, k, k + 2, k + 3);
                faces += 1;
            }
        }
    }
    std::fs::write(path, text).unwrap_or_else(|e| panic!("cannot write {}: {e}", path.display()));
    2 * faces
}

/// The scene with its lifters replaced by the mesh in `file`, turning as the cylinder they sat on.
fn meshed(mut scene: Scene, file: &std::path::Path) -> Scene {
    let k = scene.walls.iter().position(|w| w.lifters.is_some()).expect("the lab mill has lifters");
    let on = scene.walls[k].lifters.take().unwrap().on;
    let motion = scene.walls.iter().find(|w| w.name.as_deref() == Some(on.as_str())).and_then(|w| w.motion.clone()).expect("the shell turns");
    let curvature = tumble_geom::DEFAULT_CURVATURE.to_degrees();
    scene.walls[k].mesh =
        Some(MeshSection { file: file.display().to_string(), scale: 1.0, rotate: None, translate: Default::default(), curvature, closed: true });
    scene.walls[k].motion = Some(motion);
    scene
}

struct Row {
    liner: &'static str,
    seed: u64,
    power: f64,
    lifters: f64,
    seconds: f64,
}

/// `cargo xtask mesh-mill [--seeds N (5)] [--jobs J (1)]`.
pub fn run_study(args: &[String]) -> i32 {
    let start = Instant::now();
    let seeds: u64 = arg(args, "--seeds").unwrap_or(5);
    let jobs: usize = arg(args, "--jobs").unwrap_or(1);
    let file = std::env::temp_dir().join(format!("tumble-lab-mill-lifters-{}.obj", std::process::id()));
    let triangles = write_lifters(&calibration_scene(1).0, &file);
    let runs: Vec<(&'static str, u64)> = (1..=seeds).flat_map(|s| [("prisms", s), ("mesh", s)]).collect();
    let rows = run_all(&runs, jobs, |&(liner, seed)| {
        let (scene, spin_up) = calibration_scene(seed);
        let scene = if liner == "mesh" { meshed(scene, &file) } else { scene };
        let mut sim = Simulation::new(compile(&scene).unwrap_or_else(|e| panic!("{e}")), threads());
        let begun = Instant::now();
        let means = charge_means(&mut sim, spin_up, |_| {});
        let row = Row { liner, seed, power: means.total_power(), lifters: means.power[1], seconds: begun.elapsed().as_secs_f64() };
        eprintln!("{liner} seed {seed}: {:.1} W (lifters {:.1} W), {:.1} s", row.power, row.lifters, row.seconds);
        row
    });
    let _ = std::fs::remove_file(&file);
    let mut csv = format!(
        "# scenes/lab_mill/lab_mill_20.toml at 50 % of critical, mu_w = 0.9, mu_r = 0.4: the eight lifters as analytic prisms and as one closed mesh of {triangles} triangles turning with the shell; power averaged over one revolution after 2 s; {} threads per run\n",
        threads()
    );
    csv.push_str("lifters,seed,power_w,lifter_power_w,wall_seconds\n");
    for r in &rows {
        let _ = writeln!(csv, "{},{},{:.2},{:.2},{:.1}", r.liner, r.seed, r.power, r.lifters, r.seconds);
    }
    let powers = |liner: &str| rows.iter().filter(|r| r.liner == liner).map(|r| r.power).collect::<Vec<_>>();
    compare(&mut csv, ("mesh", &powers("mesh")), ("prisms", &powers("prisms")), "W", 1);
    eprintln!("total: {:.1} s", start.elapsed().as_secs_f64());
    write_csv("mill_mesh_liner", &csv)
}
