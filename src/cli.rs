//! The command line (docs/cli.md, "Commands").

use crate::{RunError, RunOptions, load_scene};
use clap::{Parser, Subcommand};
use std::io::IsTerminal;
use std::path::PathBuf;
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};
use tumble_scene::schema::BackendName;

#[derive(Parser, Debug)]
#[command(name = "tumble", version, about = "Discrete element method engine for granular flow")]
pub struct Cli {
    #[command(subcommand)]
    pub command: Command,
}

#[derive(Subcommand, Debug)]
pub enum Command {
    /// Run a scene and write summary.json, observables.csv and tracks.csv.
    Run {
        /// The scene file (TOML).
        scene: PathBuf,
        /// Output folder [default: out/<scene name>/].
        #[arg(long)]
        out: Option<PathBuf>,
        /// Backend: cpu (f64, rayon) or gpu (f32, wgpu) [default: the scene's run.backend].
        #[arg(long)]
        backend: Option<String>,
        /// Worker threads [default: all cores].
        #[arg(long)]
        threads: Option<usize>,
        /// Override run.duration (seconds).
        #[arg(long, allow_hyphen_values = true)]
        duration: Option<f64>,
        /// Override run.dt (seconds).
        #[arg(long, allow_hyphen_values = true)]
        dt: Option<f64>,
        /// No progress lines.
        #[arg(long)]
        quiet: bool,
        /// Replace an earlier tumble run's outputs in the output folder.
        #[arg(long)]
        overwrite: bool,
        /// Write a checkpoint every S seconds of simulated time (overrides run.checkpoint_interval).
        #[arg(long, value_name = "S", allow_hyphen_values = true)]
        checkpoint_interval: Option<f64>,
    },
    /// Continue a run from the newest checkpoint in its output folder, appending to its files.
    Resume {
        /// The run's output folder (with checkpoints/).
        dir: PathBuf,
        /// Continue to this simulated time instead of the run's duration (seconds).
        #[arg(long, allow_hyphen_values = true)]
        duration: Option<f64>,
        /// Worker threads [default: all cores]; the CPU's results do not depend on it.
        #[arg(long)]
        threads: Option<usize>,
        /// Write a checkpoint every S seconds of simulated time from now on.
        #[arg(long, value_name = "S", allow_hyphen_values = true)]
        checkpoint_interval: Option<f64>,
        /// No progress lines.
        #[arg(long)]
        quiet: bool,
    },
    /// Run the analytic verification cases and print the table; exit status 1 on any failure.
    Verify,
    /// Print the model plan: active features and why, dt, t_col, steps per collision, memory.
    Plan {
        /// The scene file (TOML).
        scene: PathBuf,
    },
    /// Draw a run's snapshots into DIR/render/: frame_NNNNNN.png and animation.png (on the GPU).
    Render {
        /// The run's output folder (with particles.pvd).
        dir: PathBuf,
        /// front, back, side, top or iso.
        #[arg(long, default_value = "front")]
        view: String,
        /// The world axis drawn vertical: x, y or z.
        #[arg(long, default_value = "z")]
        up: String,
        /// The particle array that colours them: speed, or any point array (vectors by magnitude).
        #[arg(long, default_value = "speed")]
        color: String,
        /// The colour range as LO,HI [default: the field's range over the frames drawn].
        #[arg(long)]
        range: Option<String>,
        /// Image size, WxH.
        #[arg(long, default_value = "640x480")]
        size: String,
        /// Draw every K-th snapshot.
        #[arg(long, default_value_t = 1)]
        every: usize,
        /// Animation frames per second; 0 writes no animation.
        #[arg(long, default_value_t = 10)]
        fps: u16,
        /// No colour bar.
        #[arg(long)]
        no_legend: bool,
    },
}

/// The plan's line on the fluid on the GPU: its device memory and grid, or why it runs on the CPU
/// only; empty without a fluid.
fn fluid_gpu_line(c: &tumble_scene::CompiledScene) -> String {
    let (Some(sph), Some(fluid)) = (&c.plan.sph, &c.fluid) else { return String::new() };
    if let Some(why) = tumble_gpu::fluid_gpu_refusal(&sph.settings) {
        return format!("fluid gpu    not this scene: {why}\n");
    }
    match tumble_gpu::fluid_device_bytes(&sph.settings, fluid.len()) {
        Ok((bytes, dims)) => format!(
            "fluid gpu    {:.1} MiB in f32 ({} bytes per fluid or wall particle, 12 per cell, grid {dims:?})\n",
            bytes as f64 / (1 << 20) as f64,
            tumble_gpu::FLUID_BYTES_PER_PARTICLE
        ),
        Err(e) => format!("fluid gpu    not this scene: {e}\n"),
    }
}

/// Writes `text` to stdout; a reader that has gone (`tumble plan SCENE | head`) is not an error.
fn print_out(text: &str) {
    use std::io::Write;
    let _ = std::io::stdout().lock().write_all(text.as_bytes());
}

/// Runs the command line; returns the process exit code.
pub fn main_with(cli: Cli) -> i32 {
    match cli.command {
        Command::Verify => {
            let (table, pass) = crate::verify::report();
            print_out(&format!("{table}{}\n", if pass { "all verification checks passed" } else { "verification FAILED" }));
            if pass { 0 } else { 1 }
        }
        Command::Plan { scene } => match load_scene(&scene, None, None) {
            Ok(c) if c.plan.sph.is_some() && c.particles.is_empty() && c.plan.model.sources.is_empty() => {
                // Fluid alone: no DEM particle.
                print_out(&format!("{}{}", c.plan.describe(0), fluid_gpu_line(&c)));
                0
            }
            Ok(c) => {
                // The device's cell grid is sized for the capacity; its arrays grow to it in chunks.
                let (start, n) = (c.particles.len() as u64, c.particles.len() as u64 + c.plan.inserted_at_most());
                let grid = tumble_gpu::Grid::planned(&c.plan, start);
                let mib = |slots: u64| tumble_gpu::device_bytes(&c.plan, slots, &grid) as f64 / (1 << 20) as f64;
                let growth = if c.plan.model.sources.is_empty() { String::new() } else { format!(" at the start, {:.1} MiB at capacity", mib(n)) };
                print_out(&format!(
                    "{}{}gpu memory   {:.1} MiB{growth} ({} bytes per particle, {} per cell, grid {:?})\n",
                    c.plan.describe(c.particles.len()),
                    fluid_gpu_line(&c),
                    mib(start + c.plan.tuning.capacity_chunk),
                    tumble_gpu::bytes_per_particle(&c.plan),
                    tumble_gpu::BYTES_PER_CELL,
                    grid.dims
                ));
                if let Some(every) = c.plan.run.checkpoint_every {
                    let bytes = crate::checkpoint::estimated_bytes(&c);
                    print_out(&format!(
                        "checkpoints  every {every} steps ({:.4e} s), newest {} kept; about {:.3} MiB each ({} bytes per particle) + {} bytes per contact spring\n",
                        every as f64 * c.plan.model.dt,
                        c.plan.run.checkpoint_keep,
                        bytes as f64 / (1 << 20) as f64,
                        bytes / n.max(1),
                        crate::checkpoint::BYTES_PER_SPRING
                    ));
                }
                0
            }
            Err(e) => {
                eprintln!("error: {e}");
                2
            }
        },
        Command::Render { dir, view, up, color, range, size, every, fps, no_legend } => {
            match crate::render::options_from_args(&view, &up, color, range.as_deref(), &size, every, fps, !no_legend)
                .and_then(|options| crate::render::render_run(&dir, &options))
            {
                Ok(r) => {
                    print_out(&r.describe(&dir.join("render")));
                    0
                }
                Err(e) => {
                    eprintln!("error: {e}");
                    2
                }
            }
        }
        Command::Resume { dir, duration, threads, checkpoint_interval, quiet } => {
            if let Err(e) = check_threads(threads).and(check_interval(checkpoint_interval)).and(check_duration(duration)) {
                eprintln!("error: {e}");
                return 2;
            }
            let mut options = RunOptions { duration, checkpoint_interval, ..interactive_options(quiet) };
            if let Some(t) = threads {
                options.threads = t;
            }
            finish_run(crate::resume_run(&dir, &options))
        }
        Command::Run { scene, out, backend, threads, duration, dt, quiet, overwrite, checkpoint_interval } => {
            let backend = match backend.as_deref().map(|b| (b, BackendName::from_name(b))) {
                None => None,
                Some((_, Some(b))) => Some(b),
                Some((b, None)) => {
                    eprintln!("error: --backend {b}: unknown backend (valid: cpu, gpu)");
                    return 2;
                }
            };
            if let Err(e) = check_threads(threads).and(check_interval(checkpoint_interval)).and(check_duration(duration)) {
                eprintln!("error: {e}");
                return 2;
            }
            let (compiled, record) = match crate::load_recorded(&scene, &RunOptions { duration, dt, checkpoint_interval, ..Default::default() }) {
                Ok(loaded) => loaded,
                Err(e) => {
                    eprintln!("error: {e}");
                    return 2;
                }
            };
            // The plan's warnings before the first step: a likely mistake is told before the run
            // spends its time, not only by `tumble plan`.
            for w in &compiled.plan.report.warnings {
                eprintln!("warning: {w}");
            }
            let mut options = RunOptions { out_dir: out, duration, dt, backend, overwrite, checkpoint_interval, ..interactive_options(quiet) };
            if let Some(t) = threads {
                options.threads = t;
            }
            finish_run(crate::run_recorded(compiled, Some(record), &options))
        }
    }
}

/// Options of a run from the command line: progress unless `quiet`, and Ctrl-C, SIGTERM
/// (timeout, SLURM) and SIGHUP stop the run after the current chunk with every output flushed.
fn interactive_options(quiet: bool) -> RunOptions {
    let interrupt = Arc::new(AtomicBool::new(false));
    let flag = interrupt.clone();
    let _ = ctrlc::set_handler(move || flag.store(true, Ordering::Relaxed));
    RunOptions { progress: !quiet, terminal: std::io::stderr().is_terminal(), interrupt: Some(interrupt), ..Default::default() }
}

fn check_threads(threads: Option<usize>) -> Result<(), String> {
    if threads == Some(0) {
        return Err("--threads must be at least 1".into());
    }
    // Far more threads than cores only adds scheduling (thousands of them stall the run).
    let cores = std::thread::available_parallelism().map_or(1, |n| n.get());
    match threads {
        Some(t) if t > 4 * cores => Err(format!("--threads {t}: this machine has {cores} cores; use at most {}", 4 * cores)),
        _ => Ok(()),
    }
}

fn check_interval(interval: Option<f64>) -> Result<(), String> {
    match interval {
        Some(s) if !(s.is_finite() && s > 0.0) => Err(format!("--checkpoint-interval {s}: must be a positive number of seconds")),
        _ => Ok(()),
    }
}

fn check_duration(duration: Option<f64>) -> Result<(), String> {
    match duration {
        Some(s) if !(s.is_finite() && s > 0.0) => Err(format!("--duration {s}: must be a positive number of seconds")),
        _ => Ok(()),
    }
}

/// Prints how a run ended and returns the exit code: 0 done, 3 stopped by the physics or a
/// capacity, 130 interrupted, 2 anything else (nothing run).
fn finish_run(result: Result<crate::RunSummary, RunError>) -> i32 {
    match result {
        Ok(s) => {
            for w in &s.warnings {
                eprintln!("warning: {w}");
            }
            let phases: String = s.phase_particles.iter().map(|(name, n)| format!(" and {n} {name} particles")).collect();
            print_out(&format!(
                "{} steps of {} particles{phases} in {:.3} s: {:.3e} particle-steps/s; outputs in {}\n",
                s.steps,
                s.particles,
                s.wall_seconds,
                s.particle_steps_per_second,
                s.out_dir.display()
            ));
            if let Some(t) = &s.step_seconds {
                let all = (t.fluid + t.coupling + t.particles).max(1e-12);
                print_out(&format!(
                    "time in the step: fluid {:.3} s ({:.0} %), coupling {:.3} s ({:.0} %), particles {:.3} s ({:.0} %)\n",
                    t.fluid,
                    100.0 * t.fluid / all,
                    t.coupling,
                    100.0 * t.coupling / all,
                    t.particles,
                    100.0 * t.particles / all
                ));
            }
            0
        }
        Err(e @ (RunError::Unstable(_) | RunError::Capacity(_) | RunError::Lost(_) | RunError::Phase(_) | RunError::Idle(_))) => {
            eprintln!("error: {e}");
            3
        }
        Err(e @ RunError::Interrupted { .. }) => {
            eprintln!("{e}");
            130
        }
        Err(e) => {
            eprintln!("error: {e}");
            2
        }
    }
}
