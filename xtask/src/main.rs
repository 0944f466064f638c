//! `cargo xtask verify` prints the verification table and writes it as CSV;
//! `cargo xtask conformance` runs the conformance suite on every backend present.

mod charts;
mod chung_ooi;
mod chute;
mod conformance;
mod coupling;
mod friction_charts;
mod mesh_hopper;
mod mesh_mill;
mod mill;
mod mill_calibration;
mod mill_spectra;
mod perf_guard;
mod seed_stats;
mod sph;
mod svg;
mod sweep;
mod tidy;
mod verify;

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let code = match args.first().map(String::as_str) {
        Some("verify") => verify::run(&args[1..]),
        Some("conformance") => conformance::run(&args[1..]),
        Some("charts") => charts::run(&args[1..]),
        Some("gpu-profile") => gpu_profile(&args[1..]),
        Some("sweep") => sweep::run(&args[1..]),
        Some("mill") => mill::mill(&args[1..]),
        Some("mill-calibrate") => mill_calibration::run(&args[1..]),
        Some("hopper") => mill::hopper(&args[1..]),
        Some("drum") => mill::drum(&args[1..]),
        Some("mesh-hopper") => mesh_hopper::run_study(&args[1..]),
        Some("mesh-mill") => mesh_mill::run_study(&args[1..]),
        Some("chute") => chute::chute(&args[1..]),
        Some("chung-ooi") => chung_ooi::run(&args[1..]),
        Some("tidy") => tidy::run(&args[1..]),
        Some("perf-guard") => perf_guard::run(&args[1..]),
        Some("sph") => sph::run(&args[1..]),
        Some("coupling") => coupling::run(&args[1..]),
        _ => {
            eprintln!(
                "usage: cargo xtask <verify|conformance|charts|gpu-profile|sweep|mill|mill-calibrate|hopper|mesh-hopper|mesh-mill|drum|chute|chung-ooi|tidy|perf-guard|sph|coupling>\n  verify       the analytic verification table (case x integrator x dt x error x order), CSV in docs/verification.csv\n  conformance  the cross-backend conformance table; exits 1 on any failure (--only WORD: just the families named with WORD, e.g. polyhedra; --mill-only: only the small-mill rows, docs untouched)\n  charts       speed-vs-accuracy, stability-map, convergence and friction charts (SVG + CSV) in docs/charts/ (charts friction: only the friction ones)\n  gpu-profile  SCENE [STEPS]: GPU particle-steps/s and per-kernel device times (timestamp queries)\n  sweep        agglomeration in a Taylor-Green vortex over Stk x Sy (cargo xtask sweep --help): CSV and heat maps in docs/agglomeration/\n  mill         ball-mill power draw and charge profile against speed and filling (docs/charts/mill_power.*)\n  mill-calibrate  the laboratory mill (scenes/lab_mill/) calibrated on its measured power at one point, predictions at the others, sensitivity (docs/charts/mill_calibration.*; --seeds, --jobs, --backend)\n  hopper       hopper discharge rate against orifice width, spheres and dodecahedra (docs/charts/hopper_discharge.*)\n  mesh-hopper  the conical hopper with its cone from an STL file against the same cone of analytic quads, over seeds (docs/charts/mesh_hopper.csv; --seeds, --duration, --from, --jobs)\n  mesh-mill    the laboratory mill at its calibration point with its lifters as a turning mesh against the analytic prisms, over seeds (docs/charts/mill_mesh_liner.csv; --seeds, --jobs)\n  drum         drum of cubes against spheres of equal volume: charge profile and power (docs/charts/drum_cubes.csv)\n  chute        periodic inclined chute under the monitor: v_x(z) against Bagnold's profile, flux (docs/charts/chute_profile.*; --duration, --from)\n  chung-ooi    Chung & Ooi (2011) impact benchmarks 1–8: docs/charts/chung_ooi_*.svg and .csv, tables in docs/chung-ooi.md\n  tidy         every file the code and docs cite exists; files under crates/ over 600 lines state why\n  perf-guard   [REV] the CPU step's speed on the speed beds against REV (default: the last commit in benches/perf_guard.csv), alternating pairs of release builds (--pairs N, --threads 1,2, --beds dense,sheared,cubes, --steps-scale F, --record)\n  sph          the fluid: 2D dam break against Martin & Moyce at three resolutions, stability against c0/v_max (docs/charts/sph_*; --resolutions 20,40,80, --no-stability)\n  coupling     particles in a fluid: a settling sphere at Re 0.02 and 100, two spacings each, and Ergun's packed bed (docs/charts/coupling.csv; --quick: the short cases; --only stokes|water|hindered|bed)"
            );
            2
        }
    };
    std::process::exit(code);
}

/// `cargo xtask gpu-profile SCENE [STEPS]`: throughput and the per-kernel split of a scene on the GPU.
fn gpu_profile(args: &[String]) -> i32 {
    let Some(path) = args.first() else {
        eprintln!("usage: cargo xtask gpu-profile SCENE [STEPS]");
        return 2;
    };
    let steps: u64 = args.get(1).and_then(|s| s.parse().ok()).unwrap_or(50);
    let compiled = match tumble::load_scene(path.as_ref(), None, None) {
        Ok(c) => c,
        Err(e) => {
            eprintln!("error: {e}");
            return 2;
        }
    };
    let n = compiled.particles.len();
    let mut sim = match tumble_gpu::GpuSimulation::new(compiled) {
        Ok(s) => s,
        Err(e) => {
            eprintln!("error: {e}");
            return 2;
        }
    };
    println!("{n} particles on {}, grid {:?}", sim.adapter(), sim.grid().dims);
    sim.advance(5);
    let start = std::time::Instant::now();
    sim.advance(steps);
    let wall = start.elapsed().as_secs_f64();
    println!("{steps} steps in {wall:.3} s: {:.3e} particle-steps/s", n as f64 * steps as f64 / wall);
    match sim.profile(steps) {
        Some(times) => {
            let total: f64 = times.iter().map(|t| t.seconds).sum();
            for t in times {
                println!("{:<12} {:>10.3} ms per step {:>6.1} %", t.kernel, 1e3 * t.seconds / steps as f64, 100.0 * t.seconds / total);
            }
        }
        None => println!("the adapter has no TIMESTAMP_QUERY: no per-kernel split"),
    }
    0
}
