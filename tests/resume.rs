//! `tumble resume` from the command line: a run killed (SIGKILL) at random moments and resumed
//! each time ends with the files of a run that went straight through; SIGTERM writes a
//! checkpoint to resume from; damaged, foreign and mismatched checkpoints are refused with a
//! message that names them and change nothing.

use std::path::{Path, PathBuf};
use std::process::{Command, Output, Stdio};
use std::time::Duration;
use tumble_testkit::run_files::assert_same_files;

fn root() -> &'static Path {
    Path::new(env!("CARGO_MANIFEST_DIR"))
}

fn tmp(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("tumble-resume-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

fn tumble(args: &[&str]) -> Command {
    let mut c = Command::new(env!("CARGO_BIN_EXE_tumble"));
    c.args(args).current_dir(root()).stdin(Stdio::null());
    c
}

fn run(args: &[&str]) -> Output {
    tumble(args).output().unwrap()
}

/// The small mill with snapshots, written into `dir`: `duration` s, about 14,000 steps a second.
fn mill_scene(dir: &Path, duration: f64) -> PathBuf {
    let text = std::fs::read_to_string(root().join("scenes/conformance/small_mill.toml")).unwrap();
    let text = text.replace("output_interval = 0.02", "output_interval = 0.01\nsnapshot_interval = 0.05");
    let text = text.replace("duration = 0.6", &format!("duration = {duration}"));
    let path = dir.join("mill.toml");
    std::fs::write(&path, text).unwrap();
    path
}

fn summary(dir: &Path) -> serde_json::Value {
    serde_json::from_str(&std::fs::read_to_string(dir.join("summary.json")).unwrap()).unwrap()
}

/// A small deterministic generator for the moments of the kills (printed, so a failure can be replayed).
fn moments(seed: u64, n: usize) -> Vec<u64> {
    let mut x = seed;
    (0..n)
        .map(|_| {
            x = x.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
            50 + (x >> 33) % 500
        })
        .collect()
}

#[test]
fn a_run_killed_at_random_moments_and_resumed_ends_as_the_uninterrupted_run() {
    let dir = tmp("kill");
    // Long enough (about 40,000 steps) that the kills land before the end.
    let scene = mill_scene(&dir, 3.0);
    let scene = scene.to_str().unwrap();
    let straight = dir.join("straight");
    let out = run(&["run", scene, "--quiet", "--threads", "2", "--out", straight.to_str().unwrap()]);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));

    let killed = dir.join("killed");
    let killed_arg = killed.to_str().unwrap();
    let seed = std::process::id() as u64;
    let waits = moments(seed, 4);
    println!("kill -9 after {waits:?} ms (seed {seed})");
    let mut resumes = 0;
    let finished = || std::fs::read_to_string(killed.join("summary.json")).is_ok_and(|t| t.contains("\"completed\""));
    for (k, &ms) in waits.iter().enumerate() {
        if finished() {
            break;
        }
        // The first part starts the run; each later one resumes it (or starts again if the run
        // was killed before its first checkpoint).
        let started = killed.join("checkpoints").is_dir();
        let mut child = match started {
            false => tumble(&["run", scene, "--quiet", "--threads", "1", "--overwrite", "--checkpoint-interval", "0.02", "--out", killed_arg]),
            true => {
                resumes += 1;
                tumble(&["resume", killed_arg, "--quiet", "--threads", if k % 2 == 0 { "1" } else { "2" }])
            }
        }
        .stdout(Stdio::null())
        .stderr(Stdio::null())
        .spawn()
        .unwrap();
        std::thread::sleep(Duration::from_millis(ms));
        let _ = child.kill();
        child.wait().unwrap();
    }
    // Then resumed to the end.
    if !finished() {
        let out = match killed.join("checkpoints").is_dir() {
            true => run(&["resume", killed_arg, "--quiet"]),
            false => run(&["run", scene, "--quiet", "--overwrite", "--checkpoint-interval", "0.02", "--out", killed_arg]),
        };
        assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
        resumes += 1;
    }
    assert!(resumes >= 2, "the kills landed too late to test a resume ({resumes} resumes)");
    println!("resumed {resumes} times; the last part started at step {}", summary(&killed)["resumed_from_step"]);
    assert_same_files(&straight, &killed);
    assert_eq!(summary(&killed)["status"], "completed");
    assert_eq!(summary(&killed)["steps"], summary(&straight)["steps"]);
    let left: Vec<String> = std::fs::read_dir(killed.join("checkpoints")).unwrap().map(|e| e.unwrap().file_name().into_string().unwrap()).collect();
    assert!(left.len() <= 3 && left.iter().all(|n| n.ends_with(".ckpt")), "the newest three checkpoints only: {left:?}");
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn sigterm_writes_a_checkpoint_that_resumes_to_the_uninterrupted_run() {
    let dir = tmp("term");
    let scene = mill_scene(&dir, 0.6);
    let scene = scene.to_str().unwrap();
    let straight = dir.join("straight");
    assert!(run(&["run", scene, "--quiet", "--threads", "1", "--out", straight.to_str().unwrap()]).status.success());
    let stopped = dir.join("stopped");
    // An interval longer than the run: the only checkpoints are at step 0 and at the signal.
    let mut child = tumble(&["run", scene, "--quiet", "--threads", "1", "--checkpoint-interval", "10", "--out", stopped.to_str().unwrap()])
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let start = std::time::Instant::now();
    while std::fs::read_to_string(stopped.join("observables.csv")).map_or(0, |t| t.lines().count()) < 5 {
        assert!(start.elapsed() < Duration::from_secs(120), "no output rows appeared");
        std::thread::sleep(Duration::from_millis(20));
    }
    Command::new("kill").args(["-TERM", &child.id().to_string()]).status().unwrap();
    let status = child.wait().unwrap();
    assert_eq!(status.code(), Some(130));
    let s = summary(&stopped);
    let step = s["steps"].as_u64().unwrap();
    assert!(s["stopped"].as_str().unwrap().contains("tumble resume"), "{}", s["stopped"]);
    assert_eq!(s["checkpoints"]["last"].as_str().unwrap(), stopped.join(format!("checkpoints/step_{step:012}.ckpt")).to_str().unwrap());
    let out = run(&["resume", stopped.to_str().unwrap(), "--quiet", "--threads", "2"]);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    assert_eq!(summary(&stopped)["resumed_from_step"], step);
    assert_same_files(&straight, &stopped);
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn a_run_with_a_source_and_an_outlet_stopped_midway_resumes_to_the_uninterrupted_files() {
    // The pouring hopper with its outlet raised into the stream, so particles are inserted and
    // deleted within 0.1 s: the sources' generators and counts and the outlets' tallies must
    // travel in the checkpoint.
    let dir = tmp("pour");
    let text = std::fs::read_to_string(root().join("scenes/protocols/hopper_pour.toml")).unwrap();
    let text = text.replace("plane = { point = [0.0, 0.0, -0.06]", "plane = { point = [0.0, 0.0, 0.12]");
    let scene = dir.join("pour.toml");
    std::fs::write(&scene, text).unwrap();
    let scene = scene.to_str().unwrap();
    let straight = dir.join("straight");
    let args = |out: &Path, duration: &'static str| {
        vec![
            "run".to_string(),
            scene.to_string(),
            "--quiet".into(),
            "--duration".into(),
            duration.into(),
            "--checkpoint-interval".into(),
            "0.01".into(),
            "--out".into(),
            out.to_str().unwrap().to_string(),
        ]
    };
    let run_args = |a: Vec<String>| run(&a.iter().map(String::as_str).collect::<Vec<_>>());
    assert!(run_args(args(&straight, "0.1")).status.success());
    let halves = dir.join("halves");
    assert!(run_args(args(&halves, "0.05")).status.success());
    let out = run(&["resume", halves.to_str().unwrap(), "--quiet", "--duration", "0.1", "--threads", "1"]);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let last = |dir: &Path, column: &str| {
        let text = std::fs::read_to_string(dir.join("observables.csv")).unwrap();
        let header: Vec<&str> = text.lines().next().unwrap().split(',').collect();
        let k = header.iter().position(|h| *h == column).unwrap();
        text.lines().last().unwrap().split(',').nth(k).unwrap().parse::<f64>().unwrap()
    };
    let (inserted, deleted) = (last(&straight, "inserted_feed"), last(&straight, "deleted_bin"));
    println!("uninterrupted: {inserted} inserted, {deleted} deleted by t = 0.1 s");
    assert!(inserted > 500.0 && deleted > 20.0, "the test must insert and delete particles on both sides of the stop");
    assert_same_files(&straight, &halves);
    let _ = std::fs::remove_dir_all(&dir);
}

/// Every file in `dir` with its bytes, checkpoints and summary included.
fn everything(dir: &Path) -> Vec<(PathBuf, Vec<u8>)> {
    let mut all = Vec::new();
    let mut stack = vec![dir.to_path_buf()];
    while let Some(d) = stack.pop() {
        for e in std::fs::read_dir(&d).unwrap() {
            let p = e.unwrap().path();
            if p.is_dir() {
                stack.push(p);
            } else {
                all.push((p.clone(), std::fs::read(&p).unwrap()));
            }
        }
    }
    all.sort();
    all
}

/// `tumble resume` refuses with exit status 2 and one line containing every one of `expect`,
/// and the folder is left as it was.
fn refused(dir: &Path, extra: &[&str], expect: &[&str]) {
    let before = everything(dir);
    let mut args = vec!["resume", dir.to_str().unwrap(), "--quiet"];
    args.extend_from_slice(extra);
    let out = run(&args);
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(2), "{err}");
    assert_eq!(err.trim().lines().count(), 1, "one line: {err}");
    for e in expect {
        assert!(err.contains(e), "{err:?} does not say {e:?}");
    }
    assert!(everything(dir) == before, "a refused resume changed the folder");
}

/// A run's mesh wall is part of what it continues: a mesh file changed or removed since the
/// run started is refused, naming the file; restored, the run continues.
#[test]
fn a_mesh_file_changed_since_the_run_started_is_refused() {
    let dir = tmp("mesh");
    let sheet = "v -2 -1 0\nv 2 -1 0\nv 2 1 0\nv -2 1 0\nf 1 2 3\nf 1 3 4\n";
    std::fs::write(dir.join("belt.obj"), sheet).unwrap();
    let text = std::fs::read_to_string(root().join("scenes/test/belt.toml")).unwrap().replace(
        "plane = { point = [0.0, 0.0, 0.0], normal = [0.0, 0.0, 1.0] }\nmotion = { translate = { velocity = [0.5, 0.0, 0.0] } }",
        "mesh = { file = \"belt.obj\" }\nsurface_velocity = [0.5, 0.0, 0.0]",
    );
    assert!(text.contains("belt.obj"));
    let scene = dir.join("belt.toml");
    std::fs::write(&scene, text).unwrap();
    let run_dir = dir.join("run");
    let r = run_dir.to_str().unwrap();
    let out = run(&["run", scene.to_str().unwrap(), "--quiet", "--duration", "0.05", "--checkpoint-interval", "0.01", "--out", r]);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    // Lowered by 1 mm: the same scene text, another geometry.
    std::fs::write(dir.join("belt.obj"), sheet.replace(" 0\n", " -0.001\n")).unwrap();
    refused(&run_dir, &["--duration", "0.1"], &["belt.obj", "changed", "geometry"]);
    std::fs::remove_file(dir.join("belt.obj")).unwrap();
    refused(&run_dir, &["--duration", "0.1"], &["belt.obj", "geometry"]);
    std::fs::write(dir.join("belt.obj"), sheet).unwrap();
    let out = run(&["resume", r, "--quiet", "--duration", "0.1"]);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn damaged_foreign_and_mismatched_checkpoints_are_refused_and_change_nothing() {
    let dir = tmp("refuse");
    let scene = mill_scene(&dir, 0.6);
    let run_dir = dir.join("run");
    let r = run_dir.to_str().unwrap();
    let out = run(&["run", scene.to_str().unwrap(), "--quiet", "--duration", "0.05", "--checkpoint-interval", "0.01", "--out", r]);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let list = |d: &Path| {
        let mut v: Vec<PathBuf> = std::fs::read_dir(d.join("checkpoints")).unwrap().map(|e| e.unwrap().path()).collect();
        v.sort();
        v
    };
    let checkpoints = list(&run_dir);
    let (newest, before) = (checkpoints[checkpoints.len() - 1].clone(), checkpoints[checkpoints.len() - 2].clone());
    let name = |p: &Path| p.file_name().unwrap().to_str().unwrap().to_string();

    // A finished run continues only to a longer duration.
    refused(&run_dir, &[], &["already reached its end", "--duration"]);
    // One flipped bit in the newest checkpoint: named, with the one before.
    let good = std::fs::read(&newest).unwrap();
    let mut bad = good.clone();
    let n = bad.len();
    bad[n / 2] ^= 0x04;
    std::fs::write(&newest, &bad).unwrap();
    refused(&run_dir, &["--duration", "0.1"], &[&name(&newest), "damaged", &name(&before)]);
    // Cut short (a disk that filled up).
    std::fs::write(&newest, &good[..n - 100]).unwrap();
    refused(&run_dir, &["--duration", "0.1"], &[&name(&newest), "cut"]);
    // Another layout version.
    let mut other = good.clone();
    other[8] = 99;
    std::fs::write(&newest, &other).unwrap();
    refused(&run_dir, &["--duration", "0.1"], &[&name(&newest), "version 99"]);
    std::fs::write(&newest, &good).unwrap();
    // The scene file edited since the run started.
    let text = std::fs::read_to_string(&scene).unwrap();
    std::fs::write(&scene, text.replace("restitution = 0.5", "restitution = 0.6")).unwrap();
    refused(&run_dir, &["--duration", "0.1"], &["mill.toml", "scene file changed"]);
    std::fs::write(&scene, &text).unwrap();
    // A checkpoint of another scene's run dropped into this folder.
    let other_dir = dir.join("other");
    let out = run(&[
        "run",
        "scenes/box_settle.toml",
        "--quiet",
        "--duration",
        "0.01",
        "--checkpoint-interval",
        "0.005",
        "--out",
        other_dir.to_str().unwrap(),
    ]);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let foreign = list(&other_dir).pop().unwrap();
    let planted = run_dir.join("checkpoints/step_999999999999.ckpt");
    std::fs::copy(&foreign, &planted).unwrap();
    refused(&run_dir, &["--duration", "0.1"], &["step_999999999999.ckpt", "box-settle", "conformance-small-mill"]);
    std::fs::remove_file(&planted).unwrap();
    // A folder without checkpoints, and one no tumble run wrote.
    let plain = dir.join("plain");
    assert!(run(&["run", scene.to_str().unwrap(), "--quiet", "--duration", "0.01", "--out", plain.to_str().unwrap()]).status.success());
    refused(&plain, &[], &["no checkpoint"]);
    refused(&dir, &[], &["not the output folder of a tumble run"]);
    // Bad flags.
    refused(&run_dir, &["--checkpoint-interval=-1"], &["--checkpoint-interval"]);
    refused(&run_dir, &["--threads", "0"], &["--threads"]);

    // Intact, it continues: the rows before the checkpoint are kept, none repeated.
    let out = run(&["resume", r, "--quiet", "--duration", "0.1"]);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let csv = std::fs::read_to_string(run_dir.join("observables.csv")).unwrap();
    let times: Vec<f64> = csv.lines().skip(1).map(|l| l.split(',').next().unwrap().parse().unwrap()).collect();
    assert!(times.windows(2).all(|w| w[1] > w[0]), "rows repeated or out of order: {times:?}");
    assert!((times.last().unwrap() - 0.1).abs() < 1e-3, "{times:?}");
    let _ = std::fs::remove_dir_all(&dir);
}

/// A value of the CSV row `row` (0 = t = 0) in column `name`.
fn csv_value(dir: &Path, row: usize, name: &str) -> f64 {
    let text = std::fs::read_to_string(dir.join("observables.csv")).unwrap();
    let mut lines = text.lines();
    let header: Vec<&str> = lines.next().unwrap().split(',').collect();
    let col = header.iter().position(|h| *h == name).unwrap_or_else(|| panic!("no column {name}"));
    lines.nth(row).unwrap().split(',').nth(col).unwrap().parse().unwrap()
}

#[test]
fn a_charge_settled_once_seeds_a_run_at_speed_with_its_contacts() {
    use tumble::{RunOptions, run_scene_file};
    let dir = tmp("seed");
    let text = std::fs::read_to_string(root().join("scenes/conformance/small_mill.toml")).unwrap();
    // Settled in the mill standing still (so its lifters are where the turning run starts them).
    let still: String = text.lines().filter(|l| !l.starts_with("motion")).map(|l| format!("{l}\n")).collect();
    let still = still.replace("duration = 0.6", "duration = 0.3\ncheckpoint_interval = 0.3");
    std::fs::write(dir.join("settle.toml"), &still).unwrap();
    let settle = dir.join("settle");
    let settled = run_scene_file(&dir.join("settle.toml"), &RunOptions { out_dir: Some(settle.clone()), threads: 2, ..Default::default() }).unwrap();
    let last = settled.steps as usize / 275 + 1;
    let seed_line = format!("start = {{ from = {:?} }}", settle.to_str().unwrap());
    // The same charge in the same mill, still: at t = 0 it is the settled charge.
    let again = still.replace("duration = 0.3\ncheckpoint_interval = 0.3", &format!("duration = 0.05\n{seed_line}"));
    std::fs::write(dir.join("again.toml"), &again).unwrap();
    let seeded = dir.join("seeded");
    run_scene_file(&dir.join("again.toml"), &RunOptions { out_dir: Some(seeded.clone()), threads: 1, ..Default::default() }).unwrap();
    for name in ["kinetic_energy", "rotational_energy", "potential_energy", "contacts"] {
        let (a, b) = (csv_value(&settle, last, name), csv_value(&seeded, 0, name));
        assert!((a - b).abs() <= 1e-12 * a.abs().max(1e-12), "{name}: settled {a:e}, seeded {b:e}");
    }
    assert_eq!(csv_value(&seeded, 0, "dissipated_energy"), 0.0);
    // The springs come along: the stored energy agrees to the one step of slip that the first
    // force pass adds (as every pass does), far closer than without the springs.
    let (_, cp) = tumble::checkpoint::newest(&settle).unwrap();
    let held: f64 =
        (0..cp.snapshot.state.len()).flat_map(|i| cp.snapshot.state.history.of(i).map(|(_, s)| s.stored_energy()).collect::<Vec<_>>()).sum();
    let (a, b) = (csv_value(&settle, last, "elastic_energy"), csv_value(&seeded, 0, "elastic_energy"));
    println!("elastic energy: settled {a:e}, seeded {b:e}; springs hold {held:e} J (pairs counted from both sides)");
    assert!((a - b).abs() < 1e-3 * a && (a - b).abs() < 0.02 * held, "settled {a:e}, seeded {b:e}, springs {held:e}");
    // And the mill turning at 60 rpm from the same charge.
    let turning = text.replace("duration = 0.6", &format!("duration = 0.05\n{seed_line}"));
    std::fs::write(dir.join("turning.toml"), &turning).unwrap();
    let spun = dir.join("turning");
    run_scene_file(&dir.join("turning.toml"), &RunOptions { out_dir: Some(spun.clone()), threads: 1, ..Default::default() }).unwrap();
    assert_eq!(csv_value(&spun, 0, "potential_energy"), csv_value(&seeded, 0, "potential_energy"));
    assert!(csv_value(&spun, 3, "wall_work") > 0.0, "the turning mill works on the charge");

    // A scene that declares other particles is refused, naming the field and the particle.
    let other = turning.replace("diameter = 0.01 ", "diameter = 0.0099 ");
    std::fs::write(dir.join("other.toml"), other).unwrap();
    let e = run_scene_file(&dir.join("other.toml"), &RunOptions { out_dir: Some(dir.join("other")), threads: 1, ..Default::default() })
        .unwrap_err()
        .to_string();
    assert!(e.contains("run.start.from") && e.contains("particle 0") && !e.contains('\n'), "{e}");
    assert!(!dir.join("other").exists(), "a refused seed wrote nothing");
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn the_plan_states_the_size_of_a_checkpoint() {
    let dir = tmp("size");
    let scene = mill_scene(&dir, 0.002);
    let text = std::fs::read_to_string(&scene).unwrap().replace("integrator = \"verlet\"", "integrator = \"verlet\"\ncheckpoint_interval = 1.0");
    std::fs::write(&scene, text).unwrap();
    let plan = String::from_utf8(run(&["plan", scene.to_str().unwrap()]).stdout).unwrap();
    let line = plan.lines().find(|l| l.starts_with("checkpoints")).unwrap_or_else(|| panic!("{plan}"));
    let mib: f64 = line.split("about ").nth(1).unwrap().split(' ').next().unwrap().parse().unwrap();
    let out = dir.join("run");
    assert!(run(&["run", scene.to_str().unwrap(), "--quiet", "--out", out.to_str().unwrap()]).status.success());
    // The checkpoint at t = 0 holds no springs yet.
    let first = std::fs::metadata(out.join("checkpoints/step_000000000000.ckpt")).unwrap().len() as f64 / (1u64 << 20) as f64;
    println!("{line}; the t = 0 checkpoint is {first:.4} MiB");
    assert!((mib - first).abs() < 0.05 * first, "the plan says {mib} MiB, the file is {first} MiB");
    let _ = std::fs::remove_dir_all(&dir);
}
