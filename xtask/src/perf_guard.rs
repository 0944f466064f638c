//! `cargo xtask perf-guard [REV]`: the CPU step's speed against a recorded commit.
//!
//! Builds REV (default: the newest commit in benches/perf_guard.csv) and the working tree in
//! release, then runs the speed beds with each binary in alternating pairs (base first in even
//! pairs, the working tree first in odd ones, so a drift of the machine falls on both alike)
//! and prints, per bed and thread count, each binary's median particle-steps/s and the ratio
//! working tree / REV with its spread over the pairs. `--record` appends the working tree's
//! figures to benches/perf_guard.csv under HEAD (only from a clean tree, so the row names the
//! code that was measured).
//!
//! Options: `--pairs N` (default 3), `--threads 1,2` (default 1,2), `--beds dense,sheared,cubes`
//! (default all), `--steps-scale F` (multiplies each bed's guard duration; default 1), `--new REV2`
//! (a second revision in place of the working tree: one step of a bisection).

use crate::mill::{arg, root};
use std::path::{Path, PathBuf};
use std::process::Command;
use std::time::Instant;

/// One speed bed as the guard runs it: the scene and the simulated time of one run.
struct Bed {
    name: &'static str,
    scene: &'static str,
    /// Simulated seconds per run: long enough that set-up is a few per cent of the run.
    duration: f64,
}

const BEDS: [Bed; 3] = [
    // 120,000 spheres, linear + viscous-Coulomb, 1,200 steps of 5 µs.
    Bed { name: "dense", scene: "scenes/bench/dense_bed.toml", duration: 0.006 },
    // 44,800 spheres, Hertz–Mindlin with history and rolling resistance, 1,500 steps of 2 µs.
    Bed { name: "sheared", scene: "scenes/bench/sheared_bed.toml", duration: 0.003 },
    // 3,072 cubes stacked face to face (overlap-volume law), 1,495 steps of 7.0 µs.
    Bed { name: "cubes", scene: "scenes/bench/cube_bed.toml", duration: 0.0105 },
];

/// The file of accepted figures: commit, date, bed, threads, steps, particle-steps/s.
const RECORD: &str = "benches/perf_guard.csv";

pub fn run(args: &[String]) -> i32 {
    match guard(args) {
        Ok(()) => 0,
        Err(e) => {
            eprintln!("perf-guard: {e}");
            1
        }
    }
}

fn guard(args: &[String]) -> Result<(), String> {
    let root = root().canonicalize().map_err(|e| format!("the repository: {e}"))?;
    let pairs: usize = arg(args, "--pairs").unwrap_or(3).max(1);
    let scale: f64 = arg(args, "--steps-scale").unwrap_or(1.0);
    let threads: Vec<usize> = list(args, "--threads", "1,2")?;
    let beds: Vec<String> = list(args, "--beds", "dense,sheared,cubes")?;
    let beds: Vec<&Bed> = beds
        .iter()
        .map(|b| BEDS.iter().find(|bed| bed.name == b).ok_or_else(|| format!("--beds: no bed {b:?} (dense, sheared, cubes)")))
        .collect::<Result<_, _>>()?;
    let record = args.iter().any(|a| a == "--record");
    let new: Option<String> = arg(args, "--new");
    // The revision: the one argument that is neither an option nor an option's value.
    const VALUED: [&str; 5] = ["--pairs", "--steps-scale", "--threads", "--beds", "--new"];
    let positional = args.iter().enumerate().find(|(k, a)| !a.starts_with("--") && (*k == 0 || !VALUED.contains(&args[k - 1].as_str())));
    let rev = match positional {
        Some((_, r)) => r.clone(),
        None => last_recorded(&root)?,
    };
    let commit = git(&root, &["rev-parse", "--verify", &format!("{rev}^{{commit}}")])?;
    let head = git(&root, &["rev-parse", "HEAD"])?;
    let clean = git(&root, &["status", "--porcelain", "--untracked-files=no"])?.is_empty();
    if record && (!clean || new.is_some()) {
        return Err("--record needs a clean working tree: commit first, so the row names the code measured".into());
    }
    let dir = root.join("target/perf-guard");
    std::fs::create_dir_all(&dir).map_err(|e| format!("{}: {e}", dir.display()))?;
    let base = build_revision(&root, &dir, &commit)?;
    let (work, against) = match &new {
        Some(rev) => {
            let c = git(&root, &["rev-parse", "--verify", &format!("{rev}^{{commit}}")])?;
            (build_revision(&root, &dir, &c)?, c[..10].to_owned())
        }
        None => (build_work_tree(&root, &dir)?, format!("the working tree ({})", if clean { &head[..10] } else { "uncommitted changes" })),
    };
    let short = &commit[..10];
    println!("base {short} against {against}, {pairs} pairs");
    println!(
        "{:<8} {:>7} {:>6} {:>14} {:>14} {:>22} {:>22}",
        "bed", "threads", "steps", "base p-s/s", "new p-s/s", "ratio median (range)", "process-time ratio"
    );
    let mut rows = String::new();
    for bed in &beds {
        let scene = root.join(bed.scene);
        let duration = bed.duration * scale;
        for &t in &threads {
            let mut speed = [Vec::new(), Vec::new()];
            let mut wall = [Vec::new(), Vec::new()];
            let mut steps = 0;
            for k in 0..pairs {
                let order = if k % 2 == 0 { [0, 1] } else { [1, 0] };
                for which in order {
                    let bin = if which == 0 { &base } else { &work };
                    let r = run_once(bin, &scene, duration, t, &dir)?;
                    speed[which].push(r.speed);
                    wall[which].push(r.seconds);
                    steps = r.steps;
                }
            }
            let ratios: Vec<f64> = speed[1].iter().zip(&speed[0]).map(|(n, b)| n / b).collect();
            let process: Vec<f64> = wall[0].iter().zip(&wall[1]).map(|(b, n)| b / n).collect();
            let (lo, mid, hi) = spread(&ratios);
            let (plo, pmid, phi) = spread(&process);
            println!(
                "{:<8} {:>7} {:>6} {:>14.4e} {:>14.4e} {:>8.3} ({:.3}-{:.3}) {:>8.3} ({:.3}-{:.3})",
                bed.name,
                t,
                steps,
                median(&speed[0]),
                median(&speed[1]),
                mid,
                lo,
                hi,
                pmid,
                plo,
                phi
            );
            rows.push_str(&format!("{},{},{},{},{},{:.6e}\n", &head[..10], today(), bed.name, t, steps, median(&speed[1])));
        }
    }
    println!(
        "ratios are new / base throughput (above 1: the new build is faster); the process-time ratio is base / new wall time of the whole command, set-up included"
    );
    if record {
        let path = root.join(RECORD);
        let mut text = std::fs::read_to_string(&path).unwrap_or_else(|_| "commit,date,bed,threads,steps,particle_steps_per_s\n".into());
        text.push_str(&rows);
        std::fs::write(&path, text).map_err(|e| format!("{}: {e}", path.display()))?;
        println!("recorded under {} in {RECORD}", &head[..10]);
    }
    Ok(())
}

/// A comma-separated option, or its default.
fn list<T: std::str::FromStr>(args: &[String], name: &str, default: &str) -> Result<Vec<T>, String> {
    let text = args.iter().position(|a| a == name).and_then(|k| args.get(k + 1)).map_or(default, String::as_str);
    text.split(',').map(|s| s.trim().parse().map_err(|_| format!("{name}: cannot read {s:?} in {text:?}"))).collect()
}

/// The newest commit in the record.
fn last_recorded(root: &Path) -> Result<String, String> {
    let text = std::fs::read_to_string(root.join(RECORD)).map_err(|e| format!("{RECORD}: {e} (name a revision to compare with)"))?;
    text.lines()
        .skip(1)
        .filter_map(|l| l.split(',').next())
        .filter(|c| !c.is_empty())
        .last()
        .map(str::to_owned)
        .ok_or_else(|| format!("{RECORD} records no commit yet: name a revision"))
}

fn git(root: &Path, args: &[&str]) -> Result<String, String> {
    let out = Command::new("git").current_dir(root).args(args).output().map_err(|e| format!("git: {e}"))?;
    if !out.status.success() {
        return Err(format!("git {}: {}", args.join(" "), String::from_utf8_lossy(&out.stderr).trim()));
    }
    Ok(String::from_utf8_lossy(&out.stdout).trim().to_owned())
}

/// The release binary of `commit`, built once from its exported tree and kept by its hash.
fn build_revision(root: &Path, dir: &Path, commit: &str) -> Result<PathBuf, String> {
    let bin = dir.join(format!("tumble-{commit}"));
    if bin.exists() {
        return Ok(bin);
    }
    let src = dir.join("src");
    if src.exists() {
        std::fs::remove_dir_all(&src).map_err(|e| format!("{}: {e}", src.display()))?;
    }
    std::fs::create_dir_all(&src).map_err(|e| format!("{}: {e}", src.display()))?;
    // `git archive | tar -x`: the commit's tracked files, without touching the working tree. `-m`
    // stamps them with the present time: with the commit's times, cargo would take an older
    // revision's sources as older than the last build in the shared target folder and link
    // stale crates.
    let status = Command::new("sh")
        .arg("-c")
        .arg(format!("git -C '{}' archive {commit} | tar -x -m -C '{}'", root.display(), src.display()))
        .status()
        .map_err(|e| format!("git archive: {e}"))?;
    if !status.success() {
        return Err(format!("could not export {commit}"));
    }
    eprintln!("building {} in release ...", &commit[..10]);
    // One target folder for every base revision, so dependencies build once.
    cargo_release(&src, &dir.join("build"))?;
    std::fs::copy(dir.join("build/release/tumble"), &bin).map_err(|e| format!("{}: {e}", bin.display()))?;
    Ok(bin)
}

/// The working tree's release binary, copied so that a later build cannot replace it mid-run.
fn build_work_tree(root: &Path, dir: &Path) -> Result<PathBuf, String> {
    eprintln!("building the working tree in release ...");
    cargo_release(root, &root.join("target"))?;
    let bin = dir.join("tumble-work");
    std::fs::copy(root.join("target/release/tumble"), &bin).map_err(|e| format!("{}: {e}", bin.display()))?;
    Ok(bin)
}

fn cargo_release(tree: &Path, target: &Path) -> Result<(), String> {
    let status = Command::new(std::env::var("CARGO").unwrap_or_else(|_| "cargo".into()))
        .current_dir(tree)
        .env("CARGO_TARGET_DIR", target)
        .args(["build", "--release", "--quiet", "--bin", "tumble"])
        .status()
        .map_err(|e| format!("cargo: {e}"))?;
    if status.success() { Ok(()) } else { Err(format!("the release build in {} failed", tree.display())) }
}

struct Timed {
    speed: f64,
    seconds: f64,
    steps: u64,
}

/// One `tumble run` of `scene` for `duration` on `threads` threads: its own particle-steps/s
/// (from summary.json) and the whole command's wall time.
fn run_once(bin: &Path, scene: &Path, duration: f64, threads: usize, dir: &Path) -> Result<Timed, String> {
    let out = dir.join("run");
    let _ = std::fs::remove_dir_all(&out);
    let start = Instant::now();
    let result = Command::new(bin)
        .args([
            "run",
            &scene.to_string_lossy(),
            "--quiet",
            "--threads",
            &threads.to_string(),
            "--duration",
            &duration.to_string(),
            "--out",
            &out.to_string_lossy(),
        ])
        .output()
        .map_err(|e| format!("{}: {e}", bin.display()))?;
    let seconds = start.elapsed().as_secs_f64();
    if !result.status.success() {
        return Err(format!("{} run {} failed: {}", bin.display(), scene.display(), String::from_utf8_lossy(&result.stderr).trim()));
    }
    let summary = std::fs::read_to_string(out.join("summary.json")).map_err(|e| format!("summary.json: {e}"))?;
    let speed = json_number(&summary, "particle_steps_per_second").ok_or("summary.json has no particle_steps_per_second")?;
    let steps = json_number(&summary, "steps").unwrap_or(0.0) as u64;
    Ok(Timed { speed, seconds, steps })
}

/// The number after `"key":` in a JSON text (the summaries are flat enough for this).
fn json_number(text: &str, key: &str) -> Option<f64> {
    let at = text.find(&format!("\"{key}\""))? + key.len() + 2;
    let rest = text[at..].trim_start().strip_prefix(':')?.trim_start();
    let end = rest.find(|c: char| !(c.is_ascii_digit() || "+-.eE".contains(c))).unwrap_or(rest.len());
    rest[..end].parse().ok()
}

fn median(v: &[f64]) -> f64 {
    spread(v).1
}

/// (smallest, median, largest).
fn spread(v: &[f64]) -> (f64, f64, f64) {
    let mut s = v.to_vec();
    s.sort_by(f64::total_cmp);
    let n = s.len();
    let mid = if n % 2 == 1 { s[n / 2] } else { 0.5 * (s[n / 2 - 1] + s[n / 2]) };
    (s[0], mid, s[n - 1])
}

/// Today's date (UTC) as YYYY-MM-DD.
fn today() -> String {
    Command::new("date").args(["-u", "+%Y-%m-%d"]).output().ok().map(|o| String::from_utf8_lossy(&o.stdout).trim().to_owned()).unwrap_or_default()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn reads_numbers_from_a_summary() {
        let text = "{\n  \"steps\": 1200,\n  \"particle_steps_per_second\": 1.25e7,\n  \"x\": null\n}";
        assert_eq!(json_number(text, "steps"), Some(1200.0));
        assert_eq!(json_number(text, "particle_steps_per_second"), Some(1.25e7));
        assert_eq!(json_number(text, "x"), None);
        assert_eq!(spread(&[3.0, 1.0, 2.0, 10.0]), (1.0, 2.5, 10.0));
    }
}
