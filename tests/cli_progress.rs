//! What a user sees while `tumble run` works: a redrawn bar on a terminal, plain lines
//! in a pipe; Ctrl-C leaves complete outputs; ParaView snapshots read back.

use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

fn root() -> &'static Path {
    Path::new(env!("CARGO_MANIFEST_DIR"))
}

fn tmp(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("tumble-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    d
}

#[test]
fn progress_is_a_bar_on_a_terminal_and_lines_in_a_pipe() {
    let bin = env!("CARGO_BIN_EXE_tumble");
    let out = tmp("progress");
    // A pipe: plain lines, no carriage returns.
    let piped = Command::new(bin)
        .args(["run", "scenes/verify/09_energy_balance.toml", "--duration", "0.02", "--out"])
        .arg(&out)
        .current_dir(root())
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&piped.stderr);
    assert!(piped.status.success(), "{err}");
    assert!(err.lines().any(|l| l.starts_with("progress") && l.contains("particle-steps/s") && l.contains("left")), "{err}");
    assert!(!err.contains('\r'), "no redraws in a pipe: {err:?}");
    // A pseudo-terminal (util-linux `script`): the bar is redrawn in place.
    if Command::new("script").arg("--version").output().is_err() {
        println!("skipping the terminal half: util-linux `script` is not installed");
        return;
    }
    let cmd = format!("{bin} run scenes/verify/09_energy_balance.toml --duration 0.02 --overwrite --out {}", out.display());
    let tty = Command::new("script").args(["-qec", &cmd, "/dev/null"]).current_dir(root()).stdin(Stdio::null()).output().unwrap();
    let screen = String::from_utf8_lossy(&tty.stdout);
    assert!(tty.status.success(), "{screen}");
    assert!(screen.contains("\r[") && screen.contains("] ") && screen.contains("particle-steps/s"), "{screen:?}");
    assert!(!screen.contains("progress "), "no plain lines on a terminal: {screen:?}");
    let _ = std::fs::remove_dir_all(&out);
}

#[test]
fn ctrl_c_stops_cleanly_with_complete_outputs() {
    stops_cleanly_on("INT");
}

/// SIGTERM is what `timeout` and SLURM send at a wall-time limit: it must leave what Ctrl-C leaves.
#[test]
fn sigterm_stops_cleanly_with_complete_outputs() {
    stops_cleanly_on("TERM");
}

fn stops_cleanly_on(signal: &str) {
    let out = tmp(&format!("interrupt-{signal}"));
    let mut child = Command::new(env!("CARGO_BIN_EXE_tumble"))
        .args(["run", "scenes/box_settle.toml", "--quiet", "--threads", "1", "--out"])
        .arg(&out)
        .current_dir(root())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    // Wait until the run has written a few rows, then send the signal (SIGINT is a terminal's Ctrl-C).
    let start = Instant::now();
    while std::fs::read_to_string(out.join("observables.csv")).map_or(0, |t| t.lines().count()) < 3 {
        assert!(start.elapsed() < Duration::from_secs(120), "no output rows appeared");
        std::thread::sleep(Duration::from_millis(50));
    }
    Command::new("kill").args([&format!("-{signal}"), &child.id().to_string()]).status().unwrap();
    let status = child.wait().unwrap();
    let mut stderr = String::new();
    std::io::Read::read_to_string(child.stderr.as_mut().unwrap(), &mut stderr).unwrap();
    assert_eq!(status.code(), Some(130), "{stderr}");
    assert!(stderr.contains("interrupted at step"), "{stderr}");
    let summary: serde_json::Value = serde_json::from_str(&std::fs::read_to_string(out.join("summary.json")).unwrap()).unwrap();
    assert!(summary["stopped"].as_str().unwrap().starts_with("interrupted"));
    let steps = summary["steps"].as_u64().unwrap();
    let total = tumble::load_scene(&root().join("scenes/box_settle.toml"), None, None).unwrap().plan.run.steps;
    assert!(steps > 0 && steps < total, "stopped early: {steps} of {total} steps");
    for file in ["observables.csv", "tracks.csv"] {
        let text = std::fs::read_to_string(out.join(file)).unwrap();
        let width = text.lines().next().unwrap().split(',').count();
        for line in text.lines().skip(1) {
            assert_eq!(line.split(',').count(), width, "{file}: a partial row {line:?}");
            assert!(line.split(',').all(|f| f.parse::<f64>().is_ok_and(f64::is_finite)), "{file}: {line}");
        }
    }
    let _ = std::fs::remove_dir_all(&out);
}

/// The numbers of a named DataArray in a VTK XML file.
fn data_array(vtp: &str, name: &str) -> Vec<f64> {
    let tag = vtp.find(&format!("Name=\"{name}\"")).unwrap_or_else(|| panic!("no array {name}"));
    let body = &vtp[tag..];
    let open = body.find('>').unwrap() + 1;
    let close = body.find("</DataArray>").unwrap();
    body[open..close].split_whitespace().map(|v| v.parse().unwrap()).collect()
}

#[test]
fn snapshots_read_back_with_the_particles_state() {
    let out = tmp("snapshots");
    let path = root().join("scenes/verify/09_energy_balance.toml");
    let mut scene = tumble::read_scene(&path).unwrap();
    scene.run.duration = 0.02;
    scene.run.snapshot_interval = Some(0.01);
    scene.run.output_interval = Some(0.01);
    scene.particles[0].track = true;
    // Read as text below.
    scene.output.snapshot_format = tumble_scene::schema::SnapshotFormat::Ascii;
    let compiled = tumble::compile(&scene).unwrap();
    let n = compiled.particles.len();
    tumble::run_compiled(compiled, &tumble::RunOptions { out_dir: Some(out.clone()), threads: 2, ..Default::default() }).unwrap();
    // The box's six faces as polygons.
    let walls = std::fs::read_to_string(out.join("walls.vtp")).unwrap();
    assert!(walls.contains("NumberOfPolys=\"6\""), "{walls}");
    assert_eq!(data_array(&walls, "offsets"), vec![4.0, 8.0, 12.0, 16.0, 20.0, 24.0]);
    let corners = data_array(&walls, "position");
    assert!(corners.iter().all(|&c| c == 0.0 || c == 0.15 || c == 0.35), "box corners: {corners:?}");
    let pvd = std::fs::read_to_string(out.join("particles.pvd")).unwrap();
    let files: Vec<&str> = pvd.lines().filter_map(|l| l.split("file=\"").nth(1)).map(|f| f.trim_end_matches("\"/>")).collect();
    // The interval's three, and the state at the run's end (its last step falls just past 0.02 s).
    assert_eq!(files.len(), 4, "t = 0, 0.01, 0.02 and the end: {pvd}");
    let last = std::fs::read_to_string(out.join(files[3])).unwrap();
    assert!(last.contains(&format!("NumberOfPoints=\"{n}\"")));
    let (radius, velocity, points, ids) =
        (data_array(&last, "radius"), data_array(&last, "velocity"), data_array(&last, "position"), data_array(&last, "id"));
    assert_eq!((radius.len(), velocity.len(), points.len(), ids.len()), (n, 3 * n, 3 * n, n));
    assert!(radius.iter().all(|&r| (0.0045..=0.0055).contains(&r)), "diameters 9–11 mm");
    assert_eq!(data_array(&last, "connectivity").len(), n);
    // The last snapshot holds the state tracks.csv has at the same time.
    let t_snap: f64 = pvd.lines().filter_map(|l| l.split("timestep=\"").nth(1)).next_back().unwrap().split('"').next().unwrap().parse().unwrap();
    let tracks = std::fs::read_to_string(out.join("tracks.csv")).unwrap();
    let rows: Vec<Vec<f64>> = tracks.lines().skip(1).map(|l| l.split(',').map(|f| f.parse().unwrap()).collect()).collect();
    let same_time: Vec<&Vec<f64>> = rows.iter().filter(|r| r[0] == t_snap).collect();
    assert_eq!(same_time.len(), n, "every particle is tracked at t = {t_snap}");
    for r in same_time {
        let k = ids.iter().position(|&id| id == r[1]).unwrap();
        for c in 0..3 {
            assert_eq!(points[3 * k + c], r[2 + c]);
            assert_eq!(velocity[3 * k + c], r[5 + c]);
        }
    }
    let _ = std::fs::remove_dir_all(&out);
}
