//! `cargo xtask sweep`: agglomeration in a Taylor–Green vortex over a grid of Stokes and
//! stickiness numbers (issue 7). Every grid point is the example scene
//! (scenes/agglomeration_tg.toml) with the particle count, box, duration and the two target
//! numbers replaced; the scenes run in parallel, one thread each, and their agglomerates.csv
//! rows are averaged over a time window into sweep.csv and two heat maps.

use crate::svg::heat_map;
use std::path::{Path, PathBuf};
use std::sync::Mutex;
use std::sync::atomic::{AtomicUsize, Ordering};
use std::time::Instant;
use tumble::{RunOptions, compile, read_scene, run_compiled};
use tumble_scene::schema::{BackendName, CohesionSection, StokesTarget, ViscositySpec};

const USAGE: &str = "usage: cargo xtask sweep [--stk 0.1,1,5,10] [--sy 0.1,0.6,1.0,1.5] [--particles 2000] [--box L] [--duration 2.0]
                          [--window T0,T1] [--output-interval S] [--threads N] [--backend cpu|gpu] [--scene scenes/agglomeration_tg.toml]
                          [--out docs/agglomeration] [--runs out/sweep]
  Runs every Stk x Sy scene (the example scene with those targets), averages agglomerates.csv over the window
  [default: the second half of the run] and writes OUT/sweep.csv, OUT/mean_size.svg/.png, OUT/void_fraction.svg/.png.
  --box is the periodic box edge in m [default: one Taylor-Green period 2*pi/a]; --particles keep d_b, d_e, density.";

#[derive(Clone, Debug)]
struct Options {
    stk: Vec<f64>,
    sy: Vec<f64>,
    particles: usize,
    box_edge: Option<f64>,
    duration: f64,
    window: Option<(f64, f64)>,
    output_interval: Option<f64>,
    threads: usize,
    /// cpu: scenes in parallel, one thread each; gpu: one scene at a time on the adapter.
    backend: BackendName,
    scene: PathBuf,
    out: PathBuf,
    runs: PathBuf,
}

fn root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("..")
}

fn parse(args: &[String]) -> Result<Options, String> {
    let mut o = Options {
        stk: vec![0.1, 1.0, 5.0, 10.0],
        sy: vec![0.1, 0.6, 1.0, 1.5],
        particles: 2000,
        box_edge: None,
        duration: 2.0,
        window: None,
        output_interval: None,
        threads: std::thread::available_parallelism().map_or(1, |n| n.get()),
        backend: BackendName::Cpu,
        scene: root().join("scenes/agglomeration_tg.toml"),
        out: root().join("docs/agglomeration"),
        runs: root().join("out/sweep"),
    };
    let list = |v: &str| -> Result<Vec<f64>, String> {
        v.split(',').map(|x| x.trim().parse::<f64>().map_err(|e| format!("{x:?}: {e}"))).collect::<Result<Vec<_>, _>>()
    };
    let mut it = args.iter();
    while let Some(flag) = it.next() {
        let mut value = || it.next().cloned().ok_or_else(|| format!("{flag} needs a value"));
        match flag.as_str() {
            "--stk" => o.stk = list(&value()?)?,
            "--sy" => o.sy = list(&value()?)?,
            "--particles" => o.particles = value()?.parse().map_err(|e| format!("--particles: {e}"))?,
            "--box" => o.box_edge = Some(value()?.parse().map_err(|e| format!("--box: {e}"))?),
            "--duration" => o.duration = value()?.parse().map_err(|e| format!("--duration: {e}"))?,
            "--output-interval" => o.output_interval = Some(value()?.parse().map_err(|e| format!("--output-interval: {e}"))?),
            "--window" => {
                let w = list(&value()?)?;
                if w.len() != 2 || w[1].partial_cmp(&w[0]) != Some(std::cmp::Ordering::Greater) {
                    return Err("--window needs T0,T1 with T1 > T0".into());
                }
                o.window = Some((w[0], w[1]));
            }
            "--threads" => o.threads = value()?.parse().map_err(|e| format!("--threads: {e}"))?,
            "--backend" => {
                let b = value()?;
                o.backend = BackendName::from_name(&b).ok_or_else(|| format!("--backend {b}: valid backends are cpu and gpu"))?;
            }
            "--scene" => o.scene = PathBuf::from(value()?),
            "--out" => o.out = PathBuf::from(value()?),
            "--runs" => o.runs = PathBuf::from(value()?),
            "-h" | "--help" => return Err(String::new()),
            other => return Err(format!("unknown option {other}")),
        }
    }
    if o.stk.is_empty() || o.sy.is_empty() || o.particles == 0 || o.threads == 0 || o.duration.is_nan() || o.duration <= 0.0 {
        return Err("need at least one Stk and one Sy, particles > 0, threads > 0 and duration > 0".into());
    }
    if o.backend == BackendName::Gpu {
        o.threads = 1; // one adapter: the scenes queue up on it
    }
    Ok(o)
}

/// One grid point's time-averaged result.
#[derive(Clone, Debug, Default)]
struct Point {
    stk: f64,
    sy: f64,
    viscosity: f64,
    cohesion_stiffness: f64,
    particles: usize,
    steps: u64,
    dt: f64,
    wall_seconds: f64,
    particle_steps_per_second: f64,
    rows: usize,
    agglomerates: f64,
    mean_size: f64,
    weighted_mean_size: f64,
    max_size: f64,
    mean_void_fraction: f64,
    mean_void_fraction_multi: f64,
    /// Mean number of agglomerates wrapping around the box (box-spanning networks).
    wrapping: f64,
    error: Option<String>,
}

pub fn run(args: &[String]) -> i32 {
    let o = match parse(args) {
        Ok(o) => o,
        Err(e) => {
            if !e.is_empty() {
                eprintln!("error: {e}");
            }
            eprintln!("{USAGE}");
            return 2;
        }
    };
    let base = match read_scene(&o.scene) {
        Ok(s) => s,
        Err(e) => {
            eprintln!("error: {e}");
            return 2;
        }
    };
    let window = o.window.unwrap_or((0.5 * o.duration, o.duration));
    let grid: Vec<(usize, usize)> = (0..o.sy.len()).flat_map(|j| (0..o.stk.len()).map(move |i| (i, j))).collect();
    let results: Mutex<Vec<Option<Point>>> = Mutex::new(vec![None; grid.len()]);
    let next = AtomicUsize::new(0);
    let start = Instant::now();
    eprintln!(
        "sweep: {} scenes ({} Stk x {} Sy), {} particles, {} s each, window [{}, {}] s, {} threads",
        grid.len(),
        o.stk.len(),
        o.sy.len(),
        o.particles,
        o.duration,
        window.0,
        window.1,
        o.threads
    );
    std::thread::scope(|s| {
        for _ in 0..o.threads.min(grid.len()) {
            s.spawn(|| {
                loop {
                    let k = next.fetch_add(1, Ordering::Relaxed);
                    if k >= grid.len() {
                        break;
                    }
                    let (i, j) = grid[k];
                    let p = run_point(&base, &o, o.stk[i], o.sy[j], window);
                    eprintln!(
                        "  Stk {:>5} Sy {:>4}: {} ({:.0} s, {:.3e} particle-steps/s)",
                        o.stk[i],
                        o.sy[j],
                        match &p.error {
                            Some(e) => format!("FAILED: {e}"),
                            None => format!("mean size {:.4}, max {:.1}, void fraction {:.4}", p.mean_size, p.max_size, p.mean_void_fraction),
                        },
                        p.wall_seconds,
                        p.particle_steps_per_second
                    );
                    results.lock().unwrap()[k] = Some(p);
                }
            });
        }
    });
    let wall = start.elapsed().as_secs_f64();
    let points: Vec<Point> = results.into_inner().unwrap().into_iter().map(Option::unwrap).collect();
    let particle_steps: f64 = points.iter().map(|p| p.particles as f64 * p.steps as f64).sum();
    let failed = points.iter().filter(|p| p.error.is_some()).count();
    if let Err(e) = write_outputs(&o, &points, window, wall, particle_steps) {
        eprintln!("error: {e}");
        return 1;
    }
    println!(
        "sweep done: {} scenes in {wall:.1} s wall, {particle_steps:.3e} particle-steps, {:.3e} particle-steps/s over the sweep",
        points.len(),
        particle_steps / wall
    );
    if failed > 0 {
        eprintln!("{failed} scenes failed");
        return 1;
    }
    0
}

fn run_point(base: &tumble::Scene, o: &Options, stk: f64, sy: f64, window: (f64, f64)) -> Point {
    let mut p = Point { stk, sy, ..Default::default() };
    let mut scene = base.clone();
    scene.name = format!("sweep-stk{stk}-sy{sy}");
    scene.run.duration = o.duration;
    scene.run.output_interval = Some(o.output_interval.unwrap_or(o.duration / 60.0));
    scene.run.snapshot_interval = None;
    scene.run.agglomerates = Some(true);
    scene.run.backend = o.backend;
    let a = match scene.fluid.as_ref().map(|f| &f.flow) {
        Some(tumble_scene::schema::FlowSection::TaylorGreen(tg)) => tg.frequency,
        _ => {
            p.error = Some("the base scene needs a Taylor–Green flow".into());
            return p;
        }
    };
    let edge = o.box_edge.unwrap_or(2.0 * std::f64::consts::PI / a);
    scene.domain.min = [0.0; 3].into();
    scene.domain.max = [edge; 3].into();
    scene.domain.periodic = [true; 3];
    if let Some(f) = scene.fluid.as_mut() {
        f.viscosity = Some(ViscositySpec::Target(StokesTarget { stokes_number: stk }));
    }
    scene.contact.as_mut().expect("the bed has a [contact] table").cohesion =
        Some(CohesionSection { stiffness: None, stickiness_number: Some(sy), collision_speed: None });
    for g in &mut scene.particles {
        if let Some(r) = g.random.as_mut() {
            r.count = o.particles;
            r.region.min = [0.0; 3].into();
            r.region.max = [edge; 3].into();
        }
    }
    let compiled = match compile(&scene) {
        Ok(c) => c,
        Err(e) => {
            p.error = Some(e.to_string());
            return p;
        }
    };
    p.viscosity = compiled.plan.report.targets.taylor_green.and_then(|t| t.viscosity).unwrap_or(f64::NAN);
    p.cohesion_stiffness = compiled.plan.report.targets.stickiness.map_or(f64::NAN, |s| s.stiffness);
    p.dt = compiled.plan.model.dt;
    let dir = o.runs.join(format!("stk{stk}_sy{sy}"));
    let summary = match run_compiled(compiled, &RunOptions { out_dir: Some(dir.clone()), threads: 1, overwrite: true, ..Default::default() }) {
        Ok(s) => s,
        Err(e) => {
            p.error = Some(e.to_string());
            return p;
        }
    };
    p.particles = summary.particles;
    p.steps = summary.steps;
    p.wall_seconds = summary.wall_seconds;
    p.particle_steps_per_second = summary.particle_steps_per_second;
    match average(&dir.join("agglomerates.csv"), window) {
        Ok(avg) => {
            p.rows = avg.0;
            [p.agglomerates, p.mean_size, p.weighted_mean_size, p.max_size, p.mean_void_fraction, p.mean_void_fraction_multi, p.wrapping] = avg.1;
        }
        Err(e) => p.error = Some(e),
    }
    p
}

/// Averages of (agglomerates, mean_size, weighted_mean_size, max_size, mean_void_fraction,
/// mean_void_fraction_multi, wrapping) over the rows with t in the window.
fn average(path: &Path, (t0, t1): (f64, f64)) -> Result<(usize, [f64; 7]), String> {
    let text = std::fs::read_to_string(path).map_err(|e| format!("{}: {e}", path.display()))?;
    let mut lines = text.lines();
    let header: Vec<&str> = lines.next().ok_or("empty agglomerates.csv")?.split(',').collect();
    let names = ["agglomerates", "mean_size", "weighted_mean_size", "max_size", "mean_void_fraction", "mean_void_fraction_multi", "wrapping"];
    let cols: Vec<usize> = names.iter().map(|n| header.iter().position(|h| h == n).ok_or(format!("no column {n}"))).collect::<Result<_, _>>()?;
    let (mut sum, mut rows) = ([0.0; 7], 0usize);
    for line in lines {
        let v: Vec<f64> = line.split(',').map(|x| x.parse::<f64>().unwrap_or(f64::NAN)).collect();
        // A small tolerance so rows at the window's ends count despite rounding in t.
        if v[0] >= t0 - 1e-9 && v[0] <= t1 + 1e-9 {
            for (k, &c) in cols.iter().enumerate() {
                sum[k] += v[c];
            }
            rows += 1;
        }
    }
    if rows == 0 {
        return Err(format!("no rows of {} in the window [{t0}, {t1}]", path.display()));
    }
    Ok((rows, sum.map(|s| s / rows as f64)))
}

fn write_outputs(o: &Options, points: &[Point], window: (f64, f64), wall: f64, particle_steps: f64) -> Result<(), String> {
    std::fs::create_dir_all(&o.out).map_err(|e| format!("{}: {e}", o.out.display()))?;
    let write = |name: &str, text: String| std::fs::write(o.out.join(name), text).map_err(|e| format!("{name}: {e}"));
    let mut csv = String::from(
        "stk,sy,viscosity,cohesion_stiffness,particles,steps,dt,wall_seconds,particle_steps_per_second,rows_averaged,agglomerates,mean_size,weighted_mean_size,max_size,mean_void_fraction,mean_void_fraction_multi,wrapping\n",
    );
    for p in points {
        csv += &format!(
            "{},{},{:.6e},{:.6e},{},{},{:.6e},{:.2},{:.4e},{},{:.3},{:.5},{:.5},{:.3},{:.5},{:.5},{:.3}\n",
            p.stk,
            p.sy,
            p.viscosity,
            p.cohesion_stiffness,
            p.particles,
            p.steps,
            p.dt,
            p.wall_seconds,
            p.particle_steps_per_second,
            p.rows,
            p.agglomerates,
            p.mean_size,
            p.weighted_mean_size,
            p.max_size,
            p.mean_void_fraction,
            p.mean_void_fraction_multi,
            p.wrapping
        );
    }
    write("sweep.csv", csv)?;
    let n = points.first().map_or(0, |p| p.particles);
    let steps = points.first().map_or(0, |p| p.steps);
    write(
        "sweep.txt",
        format!(
            "cargo xtask sweep: {} scenes, {} particles, duration {} s ({} steps), window [{}, {}] s, {} threads\nwall {:.1} s, {:.4e} particle-steps, {:.4e} particle-steps/s over the sweep (mean per scene {:.4e})\n",
            points.len(),
            n,
            o.duration,
            steps,
            window.0,
            window.1,
            o.threads,
            wall,
            particle_steps,
            particle_steps / wall,
            points.iter().map(|p| p.particle_steps_per_second).sum::<f64>() / points.len() as f64
        ),
    )?;
    let at = |i: usize, j: usize| &points[j * o.stk.len() + i];
    let x_ticks: Vec<String> = o.stk.iter().map(|v| format!("{v}")).collect();
    let y_ticks: Vec<String> = o.sy.iter().map(|v| format!("{v}")).collect();
    let grid = |f: &dyn Fn(&Point) -> f64| -> Vec<Vec<f64>> { (0..o.sy.len()).map(|j| (0..o.stk.len()).map(|i| f(at(i, j))).collect()).collect() };
    let subtitle = format!("{n} spheres, Taylor–Green A = 5, a = 3; mean over t in [{}, {}] s of a {} s run", window.0, window.1, o.duration);
    let size = heat_map(
        "Mean agglomerate size",
        &subtitle,
        "Stokes number Stk",
        &x_ticks,
        "Stickiness number Sy",
        &y_ticks,
        &grid(&|p| p.mean_size),
        |j, i| vec![format!("{:.3}", at(i, j).mean_size), format!("weighted {:.2}, max {:.0}", at(i, j).weighted_mean_size, at(i, j).max_size)],
        "particles per agglomerate",
    );
    let void = heat_map(
        "Mean void fraction of agglomerates",
        &subtitle,
        "Stokes number Stk",
        &x_ticks,
        "Stickiness number Sy",
        &y_ticks,
        &grid(&|p| p.mean_void_fraction),
        |j, i| vec![format!("{:.4}", at(i, j).mean_void_fraction), format!("clusters only {:.3}", at(i, j).mean_void_fraction_multi)],
        "1 - sum V_p / V_bs (singles count 0)",
    );
    for (name, svg) in [("mean_size", size), ("void_fraction", void)] {
        write(&format!("{name}.svg"), svg)?;
        let (svg_path, png_path) = (o.out.join(format!("{name}.svg")), o.out.join(format!("{name}.png")));
        match std::process::Command::new("rsvg-convert").args(["-w", "900", "-o"]).arg(&png_path).arg(&svg_path).status() {
            Ok(s) if s.success() => println!("wrote {}", png_path.display()),
            _ => eprintln!("skipping {name}.png: rsvg-convert (apt-get install librsvg2-bin) is not available"),
        }
    }
    println!("wrote {}/sweep.csv, sweep.txt, mean_size.svg, void_fraction.svg", o.out.display());
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn defaults_and_options() {
        let o = parse(&[]).unwrap();
        assert_eq!((o.stk.len(), o.sy.len(), o.particles, o.duration), (4, 4, 2000, 2.0));
        let args: Vec<String> = ["--stk", "1,2", "--sy", "0.5", "--window", "0.1,0.2", "--particles", "10"].iter().map(|s| s.to_string()).collect();
        let o = parse(&args).unwrap();
        assert_eq!((o.stk, o.sy, o.window, o.particles), (vec![1.0, 2.0], vec![0.5], Some((0.1, 0.2)), 10));
        assert!(parse(&["--window".into(), "0.2,0.1".into()]).is_err());
        assert!(parse(&["--backend".into(), "tpu".into()]).is_err());
        let gpu = parse(&["--backend".into(), "gpu".into(), "--threads".into(), "4".into()]).unwrap();
        assert_eq!((gpu.backend, gpu.threads), (BackendName::Gpu, 1));
    }

    #[test]
    fn averages_rows_in_the_window() {
        let dir = std::env::temp_dir().join(format!("tumble-sweep-avg-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let path = dir.join("agglomerates.csv");
        let mut text = tumble::agglomerates::csv_header(4) + "\n";
        text += "0,4,4,1,1,1,0,0,0,0,4,0,0\n0.5,4,2,2,2,2,0.375,1,0.75,0,1,0,0\n1,4,1,4,4,4,0.8,1,0.8,0,0,0,1\n";
        std::fs::write(&path, text).unwrap();
        let (rows, avg) = average(&path, (0.5, 1.0)).unwrap();
        assert_eq!(rows, 2);
        assert_eq!(avg, [1.5, 3.0, 3.0, 3.0, 0.5875, 0.775, 0.0]);
        let _ = std::fs::remove_dir_all(&dir);
    }
}
