//! `cargo xtask mesh-hopper`: the conical hopper of scenes/mesh_hopper.toml with its cone read
//! from a binary STL file and with the same cone built from 48 analytic quads, over several
//! seeds of the lattice jitter: the discharge rate of each, their means and the spread, written
//! to docs/charts/mesh_hopper.csv (docs/meshes.md).

use crate::mill::{arg, root, run_all, threads};
use crate::seed_stats::{compare, write_csv};
use std::fmt::Write as _;
use std::time::Instant;
use tumble::{FlowCounter, Simulation, compile, parse_scene};
use tumble_geom::DVec3;

/// The cone of scenes/meshes/hopper_cone.obj in the scene's frame (metres, z up): 48 facets from
/// radius 20 mm at z = 0 to 60 mm at z = 100 mm.
const FACETS: usize = 48;
const OUTLET_RADIUS: f64 = 0.02;
const TOP_RADIUS: f64 = 0.06;
const HEIGHT: f64 = 0.1;

/// The cone's facets as quads (bottom k, bottom k + 1, top k + 1, top k), corners in f64.
fn facets() -> Vec<[DVec3; 4]> {
    let ring = |r: f64, z: f64, k: usize| {
        let phi = std::f64::consts::TAU * (k % FACETS) as f64 / FACETS as f64;
        DVec3::new(r * phi.cos(), r * phi.sin(), z)
    };
    (0..FACETS)
        .map(|k| [ring(OUTLET_RADIUS, 0.0, k), ring(OUTLET_RADIUS, 0.0, k + 1), ring(TOP_RADIUS, HEIGHT, k + 1), ring(TOP_RADIUS, HEIGHT, k)])
        .collect()
}

/// The cone as a binary STL file (two triangles per facet, coordinates in f32 as the format has them).
fn write_stl(path: &std::path::Path) -> std::io::Result<()> {
    let mut bytes = vec![0u8; 80];
    bytes.extend_from_slice(&(2 * FACETS as u32).to_le_bytes());
    for [a, b, c, d] in facets() {
        for tri in [[a, b, c], [a, c, d]] {
            let n = (tri[1] - tri[0]).cross(tri[2] - tri[0]).normalize();
            for v in std::iter::once(n).chain(tri) {
                for x in v.to_array() {
                    bytes.extend_from_slice(&(x as f32).to_le_bytes());
                }
            }
            bytes.extend_from_slice(&[0, 0]);
        }
    }
    std::fs::write(path, bytes)
}

/// One discharge run.
struct Row {
    cone: &'static str,
    seed: u64,
    rate: f64,
    particles: usize,
    seconds: f64,
}

/// The scene with the cone as `cone` ("stl" or "quads") and the lattice jitter drawn from `seed`.
fn run(cone: &'static str, seed: u64, stl: &std::path::Path, duration: f64, from: f64) -> Row {
    let text = std::fs::read_to_string(root().join("scenes/mesh_hopper.toml")).unwrap();
    let mesh_line = text.lines().find(|l| l.starts_with("mesh = ")).expect("scenes/mesh_hopper.toml's cone is a mesh").to_string();
    let replacement = match cone {
        "stl" => format!("mesh = {{ file = \"{}\" }}", stl.display()),
        _ => {
            let v = |p: DVec3| format!("[{:?}, {:?}, {:?}]", p.x, p.y, p.z);
            let quads: Vec<String> =
                facets().iter().map(|q| format!("quad = {{ corners = [{}, {}, {}, {}] }}", v(q[0]), v(q[1]), v(q[2]), v(q[3]))).collect();
            quads.join("\n\n[[walls]]\nname = \"cone\"\nmaterial = \"steel\"\n")
        }
    };
    let mut scene = parse_scene(&text.replace(&mesh_line, &replacement)).unwrap_or_else(|e| panic!("{e}"));
    scene.run.seed = seed;
    scene.run.duration = duration;
    scene.run.snapshot_interval = None;
    let compiled = compile(&scene).unwrap_or_else(|e| panic!("{e}"));
    let particles = compiled.particles.len();
    let mut sim = Simulation::new(compiled, threads());
    let every = (0.02 / sim.plan().model.dt).round() as u64;
    let mut flow = FlowCounter::new(&sim);
    let start = Instant::now();
    let mut first = None;
    let mut last = (0.0, 0.0);
    while sim.steps() < sim.plan().run.steps {
        sim.advance(every.min(sim.plan().run.steps - sim.steps()));
        let (_, mass) = flow.update(&sim)[0];
        last = (sim.time(), mass);
        if first.is_none() && sim.time() >= from - 1e-9 {
            first = Some(last);
        }
        assert!(sim.observables().finite, "{cone}, seed {seed}: non-finite state at t = {}", sim.time());
    }
    let (t0, m0) = first.expect("the run reaches the start of the window");
    let rate = (last.1 - m0) / (last.0 - t0);
    let seconds = start.elapsed().as_secs_f64();
    eprintln!("{cone} seed {seed}: {rate:.5} kg/s, {particles} particles, {seconds:.1} s");
    Row { cone, seed, rate, particles, seconds }
}

/// `cargo xtask mesh-hopper [--seeds N (6)] [--duration T (0.6)] [--from T0 (0.25)] [--jobs J (1)]`.
pub fn run_study(args: &[String]) -> i32 {
    let start = Instant::now();
    let seeds: u64 = arg(args, "--seeds").unwrap_or(6);
    let duration: f64 = arg(args, "--duration").unwrap_or(0.6);
    let from: f64 = arg(args, "--from").unwrap_or(0.25);
    let jobs: usize = arg(args, "--jobs").unwrap_or(1);
    let stl = std::env::temp_dir().join(format!("tumble-hopper-cone-{}.stl", std::process::id()));
    if let Err(e) = write_stl(&stl) {
        eprintln!("cannot write {}: {e}", stl.display());
        return 1;
    }
    let runs: Vec<(&'static str, u64)> = (1..=seeds).flat_map(|s| [("stl", s), ("quads", s)]).collect();
    let rows = run_all(&runs, jobs, |&(cone, seed)| run(cone, seed, &stl, duration, from));
    let _ = std::fs::remove_file(&stl);
    let mut csv = format!(
        "# scenes/mesh_hopper.toml ({} beads of 8 mm): the cone from a binary STL of {} triangles and from {FACETS} analytic quads; \
         rate through the outlet plane between t = {from} s and {duration} s; {} threads per run\n",
        rows[0].particles,
        2 * FACETS,
        threads()
    );
    csv.push_str("cone,seed,rate_kg_s,wall_seconds\n");
    for r in &rows {
        let _ = writeln!(csv, "{},{},{:.5},{:.1}", r.cone, r.seed, r.rate, r.seconds);
    }
    let rates = |cone: &str| rows.iter().filter(|r| r.cone == cone).map(|r| r.rate).collect::<Vec<_>>();
    compare(&mut csv, ("stl", &rates("stl")), ("quads", &rates("quads")), "kg/s", 5);
    eprintln!("total: {:.1} s", start.elapsed().as_secs_f64());
    write_csv("mesh_hopper", &csv)
}
