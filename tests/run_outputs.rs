//! Outputs that cannot mislead: lost particles are reported and stop a run, an output folder is
//! never mixed with another run's files, summary.json says whether the run finished, and the
//! memory estimate is the memory the grid takes.

use std::path::{Path, PathBuf};
use std::process::Command;
use tumble::{RunError, RunOptions, compile, parse_scene, run_compiled};

fn tmp(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("tumble-outputs-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    d
}

/// Ten beads at rest on a floor and one flying out through the open +x side at 5 m/s.
fn escaping_scene(extra_run: &str) -> String {
    format!(
        r#"name = "escape"
[run]
duration = 0.2
output_interval = 0.01
{extra_run}
[domain]
min = [-0.5, -0.5, 0.0]
max = [0.5, 0.5, 0.5]
[gravity]
acceleration = [0.0, 0.0, -9.81]
[[materials]]
name = "glass"
density = 2500.0
[contact]
normal = {{ model = "linear", stiffness = 1.0e4 }}
restitution = 0.5
[[particles]]
name = "bed"
material = "glass"
shape = {{ sphere = {{ diameter = 0.02 }} }}
lattice = {{ min = [-0.05, -0.01, 0.0], max = [0.05, 0.01, 0.02], spacing = 0.02 }}
[[particles]]
name = "bullet"
material = "glass"
shape = {{ sphere = {{ diameter = 0.02 }} }}
positions = [[0.3, 0.0, 0.25]]
velocity = [5.0, 0.0, 0.0]
[[walls]]
name = "floor"
material = "glass"
plane = {{ point = [0.0, 0.0, 0.0], normal = [0.0, 0.0, 1.0] }}
"#
    )
}

fn options(out: &Path) -> RunOptions {
    RunOptions { out_dir: Some(out.to_path_buf()), threads: 1, ..Default::default() }
}

fn column(csv: &str, name: &str) -> Vec<String> {
    let header: Vec<&str> = csv.lines().next().unwrap().split(',').collect();
    let k = header.iter().position(|h| *h == name).unwrap_or_else(|| panic!("no column {name} in {header:?}"));
    csv.lines().skip(1).map(|l| l.split(',').nth(k).unwrap().to_string()).collect()
}

#[test]
fn a_particle_lost_beyond_the_allowed_fraction_stops_the_run() {
    let out = tmp("lost");
    let compiled = compile(&parse_scene(&escaping_scene("")).unwrap()).unwrap();
    let n = compiled.particles.len();
    let err = run_compiled(compiled, &options(&out)).unwrap_err();
    let RunError::Lost(text) = &err else { panic!("expected a loss, got {err}") };
    println!("{text}");
    assert!(text.contains(&format!("1 of {n} particles")) && text.contains("run.max_lost_fraction = 0.01"), "{text}");
    let summary: serde_json::Value = serde_json::from_str(&std::fs::read_to_string(out.join("summary.json")).unwrap()).unwrap();
    assert_eq!(summary["status"], "stopped");
    assert_eq!(summary["removed_particles"], 1);
    assert!(summary["stopped"].as_str().unwrap().contains("left the domain"));
    let removed = column(&std::fs::read_to_string(out.join("observables.csv")).unwrap(), "removed");
    assert_eq!(removed.first().map(String::as_str), Some("0"));
    assert_eq!(removed.last().map(String::as_str), Some("1"), "the row where it left is written before the stop");
    // The bullet needs 0.2 / 5 = 0.04 s to leave: the run stops at the first row after that, not at the end.
    let t = column(&std::fs::read_to_string(out.join("observables.csv")).unwrap(), "t");
    let t_stop: f64 = t.last().unwrap().parse().unwrap();
    assert!((0.04..0.06).contains(&t_stop), "stopped at t = {t_stop}");
}

#[test]
fn an_allowed_loss_finishes_with_a_warning_on_the_terminal_and_in_the_summary() {
    let out = tmp("allowed");
    let scene = out.with_extension("toml");
    std::fs::write(&scene, escaping_scene("max_lost_fraction = 1.0")).unwrap();
    let result = Command::new(env!("CARGO_BIN_EXE_tumble")).args(["run", "--quiet", "--out"]).arg(&out).arg(&scene).output().unwrap();
    let stderr = String::from_utf8_lossy(&result.stderr);
    assert!(result.status.success(), "{stderr}");
    assert!(stderr.contains("warning: 1 of 6 particles") && stderr.contains("left the domain"), "{stderr}");
    let summary: serde_json::Value = serde_json::from_str(&std::fs::read_to_string(out.join("summary.json")).unwrap()).unwrap();
    assert_eq!(summary["status"], "completed");
    assert!(summary["warnings"][0].as_str().unwrap().contains("left the domain"), "{summary}");
    // The default fraction refuses it: exit status 3, like an instability.
    std::fs::write(&scene, escaping_scene("")).unwrap();
    let result = Command::new(env!("CARGO_BIN_EXE_tumble")).args(["run", "--quiet", "--overwrite", "--out"]).arg(&out).arg(&scene).output().unwrap();
    assert_eq!(result.status.code(), Some(3), "{}", String::from_utf8_lossy(&result.stderr));
    let _ = std::fs::remove_file(&scene);
}

#[test]
fn a_second_run_into_the_same_folder_needs_overwrite_and_leaves_nothing_stale() {
    let out = tmp("again");
    let scene = escaping_scene("max_lost_fraction = 1.0\nsnapshot_interval = 0.1");
    run_compiled(compile(&parse_scene(&scene).unwrap()).unwrap(), &options(&out)).unwrap();
    // A stale file from some earlier, longer run.
    let stale = out.join("snapshots").join("particles_000099.vtp");
    std::fs::write(&stale, "stale").unwrap();
    let before = std::fs::read_to_string(out.join("observables.csv")).unwrap();
    let err = run_compiled(compile(&parse_scene(&scene).unwrap()).unwrap(), &options(&out)).unwrap_err();
    assert!(matches!(err, RunError::OutputFolder(_)) && err.to_string().contains("--overwrite"), "{err}");
    assert!(stale.exists() && std::fs::read_to_string(out.join("observables.csv")).unwrap() == before, "a refusal changes nothing");
    let again = RunOptions { overwrite: true, ..options(&out) };
    run_compiled(compile(&parse_scene(&scene).unwrap()).unwrap(), &again).unwrap();
    assert!(!stale.exists(), "the earlier run's files are gone");
    assert!(out.join("snapshots").join("particles_000002.vtp").exists());
}

#[test]
fn overwrite_never_clears_a_folder_tumble_did_not_make() {
    let out = tmp("foreign");
    std::fs::create_dir_all(&out).unwrap();
    std::fs::write(out.join("notes.txt"), "mine").unwrap();
    let result = Command::new(env!("CARGO_BIN_EXE_tumble"))
        .args(["run", "--quiet", "--overwrite", "--out"])
        .arg(&out)
        .arg(Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/test/elastic_pair.toml"))
        .output()
        .unwrap();
    let stderr = String::from_utf8_lossy(&result.stderr);
    assert_eq!(result.status.code(), Some(2), "{stderr}");
    assert!(stderr.contains("no tumble run wrote") && stderr.trim_end().lines().count() == 1, "{stderr}");
    let left: Vec<_> = std::fs::read_dir(&out).unwrap().map(|e| e.unwrap().file_name()).collect();
    assert_eq!(left, vec![std::ffi::OsString::from("notes.txt")]);
}

#[test]
fn drum_columns_are_empty_cells_not_nan_where_a_profile_is_undefined() {
    // A ball released at the drum's centre: no shell layer for a toe or a shoulder until it lands.
    let text = std::fs::read_to_string(Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/test/drum_one_ball.toml"))
        .unwrap()
        .replace("positions = [[0.0, -0.28, 0.1]]", "positions = [[0.0, 0.0, 0.1]]")
        .replace("duration = 3.0", "duration = 0.05\noutput_interval = 0.01");
    let out = tmp("drum");
    run_compiled(compile(&parse_scene(&text).unwrap()).unwrap(), &options(&out)).unwrap();
    let csv = std::fs::read_to_string(out.join("observables.csv")).unwrap();
    assert!(!csv.to_lowercase().contains("nan"), "{csv}");
    let toe = column(&csv, "toe_shell");
    assert!(toe.iter().any(String::is_empty), "the toe is undefined while the ball is in the air: {toe:?}");
    // Every other cell is a number.
    for line in csv.lines().skip(1) {
        for cell in line.split(',').filter(|c| !c.is_empty()) {
            assert!(cell.parse::<f64>().is_ok_and(f64::is_finite), "{cell:?} in {line}");
        }
    }
}

#[test]
fn the_memory_estimate_of_one_sphere_in_a_large_box_is_the_grid_the_cpu_can_build() {
    let text = escaping_scene("").replace("min = [-0.5, -0.5, 0.0]\nmax = [0.5, 0.5, 0.5]", "min = [-1.0, -1.0, -1.0]\nmax = [1.0, 1.0, 1.0]");
    let mut scene = parse_scene(&text).unwrap();
    scene.particles.truncate(1);
    scene.particles[0].lattice = None;
    scene.particles[0].positions = Some(vec![[0.0, 0.0, 0.5].into()]);
    scene.particles[0].shape = parse_scene(&text.replace("diameter = 0.02", "diameter = 0.0016")).unwrap().particles[0].shape.clone();
    let compiled = compile(&scene).unwrap();
    let bytes = compiled.plan.memory_bytes(1);
    let grid = tumble_broad::CellGrid::new(&compiled.plan.model.domain, compiled.plan.tuning.cell_size + compiled.plan.tuning.skin);
    // The estimate is the grid's cell table (the largest the grid can be) and one particle's arrays.
    assert_eq!(bytes, 4 * (grid.cell_count() + 1) + compiled.plan.tuning.bytes_per_particle);
    assert!(bytes < 300 << 20, "{} MiB for one sphere", bytes >> 20);
}
