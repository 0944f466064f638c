//! The plan's time-step guard, the instability monitor, and `tumble run` / `tumble plan` outputs.

use std::path::Path;
use std::process::Command;
use tumble::{RunError, RunOptions, compile, parse_scene, run_compiled};
use tumble_scene::schema::DtSpec;

fn scene_file(name: &str) -> String {
    std::fs::read_to_string(Path::new(env!("CARGO_MANIFEST_DIR")).join(name)).unwrap()
}

fn tmp(name: &str) -> std::path::PathBuf {
    let d = std::env::temp_dir().join(format!("tumble-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    d
}

/// 2/ω of the verification sphere (d = 0.1 m, ρ = 10 kg/m³) on a fixed partner with k_n = 1e5 N/m.
fn collision_limit() -> f64 {
    let m = 10.0 * std::f64::consts::PI / 6.0 * 1e-3;
    2.0 / (1.0e5f64 / m).sqrt()
}

#[test]
fn dt_above_two_over_omega_is_refused_by_the_plan() {
    let mut scene = parse_scene(&scene_file("scenes/verify/02_elastic_collision.toml")).unwrap();
    let limit = collision_limit();
    scene.run.dt = Some(DtSpec::Seconds(1.01 * limit));
    let err = compile(&scene).unwrap_err().to_string();
    assert!(err.contains("run.dt") && err.contains("stability limit"), "{err}");
    assert!(err.contains(&format!("{limit:.4e}")), "names the limit: {err}");
    scene.run.dt = Some(DtSpec::Seconds(0.99 * limit));
    assert!(compile(&scene).is_ok());
}

#[test]
fn a_forced_unstable_step_stops_with_a_message_and_valid_outputs() {
    // A sphere resting on the floor, integrated at 1.5 × 2/ω: the contact oscillation grows every step.
    let mut scene = parse_scene(&scene_file("scenes/verify/03_sliding.toml")).unwrap();
    let limit = collision_limit();
    scene.run.dt = Some(DtSpec::Seconds(1.5 * limit));
    scene.run.integrator = tumble_scene::schema::IntegratorName::SymplecticEuler;
    scene.run.output_interval = Some(1.5 * limit);
    scene.run.allow_unstable_dt = true;
    let compiled = compile(&scene).unwrap();
    let out = tmp("unstable");
    let err = run_compiled(compiled, &RunOptions { out_dir: Some(out.clone()), threads: 1, ..Default::default() }).unwrap_err();
    let RunError::Unstable(e) = &err else { panic!("expected an instability, got {err}") };
    let msg = err.to_string();
    println!("{msg}");
    assert!(msg.contains("unstable at step") && msg.contains("use dt <="), "{msg}");
    assert!(e.suggested_dt < limit);
    let csv = std::fs::read_to_string(out.join("observables.csv")).unwrap();
    let mut rows = 0;
    for line in csv.lines().skip(1) {
        rows += 1;
        for field in line.split(',') {
            let v: f64 = field.parse().unwrap_or_else(|_| panic!("unparseable {field:?} in {line}"));
            assert!(v.is_finite(), "non-finite value in {line}");
        }
    }
    assert!(rows >= 1);
    let summary: serde_json::Value = serde_json::from_str(&std::fs::read_to_string(out.join("summary.json")).unwrap()).unwrap();
    assert!(summary["stopped"].as_str().unwrap().contains("unstable"));
    let _ = std::fs::remove_dir_all(&out);
}

#[test]
fn tumble_run_writes_summary_observables_and_tracks() {
    let out = tmp("run");
    let result = Command::new(env!("CARGO_BIN_EXE_tumble"))
        .args(["run", "scenes/verify/02_normal_collision.toml", "--threads", "2", "--quiet", "--out"])
        .arg(&out)
        .current_dir(env!("CARGO_MANIFEST_DIR"))
        .output()
        .unwrap();
    assert!(result.status.success(), "{}", String::from_utf8_lossy(&result.stderr));
    let summary: serde_json::Value = serde_json::from_str(&std::fs::read_to_string(out.join("summary.json")).unwrap()).unwrap();
    for key in [
        "scene",
        "backend",
        "device",
        "precision",
        "particles",
        "steps",
        "dt",
        "simulated_time",
        "wall_seconds",
        "particle_steps_per_second",
        "plan",
        "final",
        "removed_particles",
    ] {
        assert!(!summary[key].is_null(), "summary.json lacks {key}");
    }
    assert_eq!(summary["particles"], 2);
    assert_eq!(summary["backend"], "cpu");
    let obs = std::fs::read_to_string(out.join("observables.csv")).unwrap();
    assert!(
        obs.starts_with("t,kinetic_energy,rotational_energy,potential_energy,elastic_energy,dissipated_energy,contacts,max_overlap_ratio,removed\n")
    );
    let steps = summary["steps"].as_u64().unwrap();
    let every = (1e-5 / summary["dt"].as_f64().unwrap()).round().max(1.0) as u64;
    assert_eq!(obs.lines().count() as u64, 1 + 1 + steps.div_ceil(every), "a header, a row at t = 0 and one per output interval");
    let tracks = std::fs::read_to_string(out.join("tracks.csv")).unwrap();
    assert!(tracks.starts_with("t,id,x,y,z,vx,vy,vz,wx,wy,wz\n"));
    // The projectile (id 1) rebounds at e |u0| = 1.6 m/s.
    let last: Vec<f64> = tracks.lines().last().unwrap().split(',').map(|f| f.parse().unwrap()).collect();
    assert_eq!(last[1], 1.0);
    assert!((last[5] - 1.6).abs() < 0.01, "{last:?}");
    let _ = std::fs::remove_dir_all(&out);
}

#[test]
fn tumble_plan_explains_each_feature() {
    let result = Command::new(env!("CARGO_BIN_EXE_tumble"))
        .args(["plan", "scenes/verify/04_cohesive_collision.toml"])
        .current_dir(env!("CARGO_MANIFEST_DIR"))
        .output()
        .unwrap();
    let text = String::from_utf8_lossy(&result.stdout);
    assert!(result.status.success());
    for needle in ["t_col", "steps per collision", "memory", "rotation     off", "cohesion     on", "drag         off"] {
        assert!(text.contains(needle), "plan lacks {needle:?}:\n{text}");
    }
}

#[test]
fn the_plan_carries_only_what_the_scene_needs() {
    let plan = |path: &str| tumble::load_scene(&Path::new(env!("CARGO_MANIFEST_DIR")).join(path), None, None).unwrap().plan;
    let collision = plan("scenes/verify/02_normal_collision.toml");
    assert!(!collision.model.rotation && !collision.model.cohesion && collision.model.fluid.is_none());
    assert_eq!(collision.tuning.cell_size, 0.1, "no cohesion: the search reaches body contact only");
    let cohesive = plan("scenes/verify/04_cohesive_collision.toml");
    assert!(cohesive.model.cohesion && (cohesive.tuning.cell_size - 0.15).abs() < 1e-12);
    assert!(plan("scenes/verify/08_slide_to_roll.toml").model.rotation);
    assert!(!plan("scenes/verify/03_sliding.toml").model.rotation, "rotation = \"off\" wins");
    assert!(plan("scenes/verify/01_stokes_drag.toml").model.fluid.is_some());
    // Less state per particle when the scene needs less.
    assert!(collision.tuning.bytes_per_particle < plan("scenes/verify/08_slide_to_roll.toml").tuning.bytes_per_particle);
    // Default Δt = t_col / 50.
    let t = collision.report.timescales.collision_time.unwrap();
    assert!((collision.model.dt - t / 50.0).abs() < 1e-15);
}

#[test]
fn a_scene_asking_for_the_gpu_backend_runs_there_or_is_refused_cleanly() {
    let dir = tmp("gpu");
    std::fs::create_dir_all(&dir).unwrap();
    let scene = dir.join("gpu.toml");
    std::fs::write(
        &scene,
        scene_file("scenes/verify/02_normal_collision.toml").replace("integrator = \"verlet\"", "integrator = \"verlet\"\nbackend = \"gpu\""),
    )
    .unwrap();
    let out = dir.join("out");
    let result = Command::new(env!("CARGO_BIN_EXE_tumble")).arg("run").arg(&scene).arg("--out").arg(&out).arg("--quiet").output().unwrap();
    let stderr = String::from_utf8_lossy(&result.stderr);
    if tumble_gpu::available() {
        assert_eq!(result.status.code(), Some(0), "{stderr}");
        let summary: serde_json::Value = serde_json::from_str(&std::fs::read_to_string(out.join("summary.json")).unwrap()).unwrap();
        assert_eq!(summary["backend"], "gpu");
        assert_eq!(summary["precision"], "f32");
        assert!(summary["adapter"]["name"].as_str().is_some_and(|n| !n.is_empty()), "{summary}");
        assert!(summary["adapter"]["backend"].is_string() && summary["adapter"]["driver"].is_string(), "{summary}");
        assert!(summary["bytes_per_particle"].as_u64().unwrap() > 0);
    } else {
        println!("skipped the GPU run: no GPU adapter");
        assert_eq!(result.status.code(), Some(2), "{stderr}");
        assert!(stderr.contains("no GPU adapter") && !out.exists(), "{stderr}");
    }
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn tumble_verify_prints_the_table_and_passes() {
    let result = Command::new(env!("CARGO_BIN_EXE_tumble")).arg("verify").output().unwrap();
    let text = String::from_utf8_lossy(&result.stdout);
    assert_eq!(result.status.code(), Some(0), "{text}");
    assert!(text.contains("all verification checks passed") && !text.contains("FAIL"));
    // One row per expectation plus the single-step checks.
    assert!(text.lines().filter(|l| l.ends_with("pass")).count() >= tumble::verify::expectations().len() + 7, "{text}");
}

#[test]
fn tumble_plan_into_a_closed_pipe_exits_quietly() {
    // `tumble plan SCENE | head` once panicked with "failed printing to stdout: Broken pipe".
    let mut child = Command::new(env!("CARGO_BIN_EXE_tumble"))
        .args(["plan", "scenes/box_settle.toml"])
        .current_dir(env!("CARGO_MANIFEST_DIR"))
        .stdout(std::process::Stdio::piped())
        .stderr(std::process::Stdio::piped())
        .spawn()
        .unwrap();
    // The reader goes before the plan is compiled, let alone written.
    drop(child.stdout.take());
    let result = child.wait_with_output().unwrap();
    let stderr = String::from_utf8_lossy(&result.stderr);
    assert!(result.status.success() && !stderr.contains("panicked"), "{:?}: {stderr}", result.status);
}

#[test]
fn tumble_run_refuses_thousands_of_threads_and_writes_nothing() {
    // --threads 5000 once stalled the run (and panicked where threads ran out).
    let out = std::env::temp_dir().join(format!("tumble-threads-{}", std::process::id()));
    let result = Command::new(env!("CARGO_BIN_EXE_tumble"))
        .args(["run", "scenes/box_settle.toml", "--threads", "5000", "--out"])
        .arg(&out)
        .current_dir(env!("CARGO_MANIFEST_DIR"))
        .output()
        .unwrap();
    let stderr = String::from_utf8_lossy(&result.stderr);
    assert_eq!(result.status.code(), Some(2), "{stderr}");
    assert!(stderr.contains("--threads 5000") && stderr.contains("use at most") && stderr.lines().count() == 1, "{stderr}");
    assert!(!out.exists());
}

/// The drum of scenes/test/drum_one_ball.toml as `edit` changes it, written to a file of its own.
fn drum_scene(name: &str, edit: impl Fn(String) -> String) -> std::path::PathBuf {
    let dir = tmp(name);
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join("scene.toml");
    std::fs::write(&path, edit(scene_file("scenes/test/drum_one_ball.toml"))).unwrap();
    path
}

/// `tumble plan` prints the plan's warnings and `tumble run` tells them before its first step;
/// `after_run` are told only when the run has ended.
fn plan_and_run_warn(scene: &Path, expected: &[&str], after_run: &[&str]) {
    let plan = Command::new(env!("CARGO_BIN_EXE_tumble")).arg("plan").arg(scene).output().unwrap();
    let stdout = String::from_utf8_lossy(&plan.stdout);
    assert!(plan.status.success(), "{}", String::from_utf8_lossy(&plan.stderr));
    let out = scene.parent().unwrap().join("out");
    let run =
        Command::new(env!("CARGO_BIN_EXE_tumble")).arg("run").arg(scene).args(["--duration", "0.01", "--quiet", "--out"]).arg(&out).output().unwrap();
    let stderr = String::from_utf8_lossy(&run.stderr);
    assert!(run.status.success(), "{stderr}");
    for e in expected {
        assert!(stdout.lines().any(|l| l.starts_with("warning: ") && l.contains(e)), "plan lacks {e:?}: {stdout}");
        assert!(stderr.lines().any(|l| l.starts_with("warning: ") && l.contains(e)), "run lacks {e:?}: {stderr}");
    }
    for e in after_run {
        assert!(stderr.lines().any(|l| l.starts_with("warning: ") && l.contains(e)), "run lacks {e:?}: {stderr}");
    }
    let _ = std::fs::remove_dir_all(scene.parent().unwrap());
}

#[test]
fn a_motion_or_a_source_starting_after_the_end_is_warned() {
    let scene = drum_scene("late", |text| {
        text.replace("rpm = 10.0 } }", "rpm = 10.0 }, start = 1000.0 }")
            + "[[sources]]\nname = \"feed\"\nmaterial = \"steel\"\nshape = { sphere = { diameter = 0.02 } }\n\
               region = { box = { min = [-0.1, -0.1, 0.0], max = [0.1, 0.1, 0.1] } }\nrate = { particles_per_second = 10.0 }\nstart = 5.0\n"
    });
    plan_and_run_warn(
        &scene,
        &[
            "walls[0].motion.start = 1000 s is not before the end of the run",
            "wall \"shell\" never moves",
            "sources[0].start = 5 s is not before the end of the run",
            "source \"feed\" inserts nothing",
        ],
        &["source \"feed\" inserted no particle: its first insertion, at t = ", "was not reached before the run ended"],
    );
}

#[test]
fn a_source_behind_an_end_plate_is_warned_before_and_after_the_run() {
    let scene = drum_scene("behind-plate", |text| {
        text.replace("[run]\n", "[run]\nallow_idle_sources = true\n")
            + "[[walls]]\nname = \"plate\"\nmaterial = \"steel\"\nplane = { point = [0.0, 0.0, 0.0], normal = [0.0, 0.0, 1.0] }\n\
                [[sources]]\nname = \"feed\"\nmaterial = \"steel\"\nshape = { sphere = { diameter = 0.02 } }\n\
                region = { box = { min = [-0.1, -0.1, -0.09], max = [0.1, 0.1, -0.01] } }\nrate = { particles_per_second = 100.0 }\n"
    });
    plan_and_run_warn(
        &scene,
        &[
            "source \"feed\" has no room: none of 200 places drawn in its region is clear of the walls and inside the domain (200 overlap wall \"plate\")",
        ],
        &["source \"feed\" inserted no particle: at each of its"],
    );
}

#[test]
fn a_flow_plane_beyond_the_outlet_is_warned() {
    let scene = drum_scene("flow-beyond-outlet", |text| {
        text + "[[outlets]]\nname = \"bin\"\nplane = { point = [0.0, -0.32, 0.0], normal = [0.0, -1.0, 0.0] }\n\
                [output]\nflow_planes = [{ name = \"below\", point = [0.0, -0.34, 0.0], normal = [0.0, -1.0, 0.0] }]\n"
    });
    plan_and_run_warn(
        &scene,
        &[
            "output.flow_planes[0] (\"below\") lies 2.0000e-2 m beyond outlet \"bin\", on the side the outlet deletes: particles are deleted before they reach it",
        ],
        &[],
    );
}

#[test]
fn densities_in_grams_per_cubic_centimetre_and_a_long_output_interval_are_warned() {
    let scene =
        drum_scene("units", |text| text.replace("density = 7800.0", "density = 7.8").replace("integrator = \"verlet\"", "output_interval = 5.0"));
    plan_and_run_warn(
        &scene,
        &[
            "materials[0].density = 7.8 kg/m³ is lighter than any solid particle: densities are in kg/m³, and this looks like g/cm³ (7.8 g/cm³ is 7800 kg/m³)",
            "run.output_interval = 5 s is longer than the run",
        ],
        &[],
    );
}

#[test]
fn gravity_in_millimetres_per_square_second_is_warned() {
    let scene = parse_scene(&scene_file("scenes/test/drum_one_ball.toml").replace("-9.81", "-9810.0")).unwrap();
    let warnings = compile(&scene).unwrap().plan.report.warnings;
    let expected = "gravity.acceleration has magnitude 9810 m/s² (1000 times Earth's): accelerations are in m/s², and this looks like mm/s²";
    assert!(warnings.iter().any(|w| w.contains(expected)), "{warnings:?}");
}

#[test]
fn negative_numbers_reach_our_own_checks() {
    // clap once took `-1` for an option and refused it as an unexpected argument.
    let out = tmp("negative");
    for (args, expected) in [
        (["--duration", "-1"], "--duration -1: must be a positive number of seconds"),
        (["--dt", "-1e-5"], "run.dt: must be a positive number, got -0.00001"),
        (["--checkpoint-interval", "-2"], "--checkpoint-interval -2: must be a positive number of seconds"),
    ] {
        let result = Command::new(env!("CARGO_BIN_EXE_tumble"))
            .args(["run", "scenes/box_settle.toml"])
            .args(args)
            .arg("--out")
            .arg(&out)
            .current_dir(env!("CARGO_MANIFEST_DIR"))
            .output()
            .unwrap();
        let stderr = String::from_utf8_lossy(&result.stderr);
        assert_eq!(result.status.code(), Some(2), "{stderr}");
        assert!(stderr.contains(expected) && stderr.lines().count() == 1, "{args:?}: {stderr}");
    }
    assert!(!out.exists());
}

/// Ten million spheres under a 1.5 GiB address-space limit (`ulimit -v`, as a batch scheduler
/// sets it) are refused before any is made, naming the limit, where reading MemAvailable alone
/// let them abort in allocation.
#[test]
fn the_memory_check_reads_the_address_space_limit() {
    let dir = tmp("rlimit");
    std::fs::create_dir_all(&dir).unwrap();
    let scene = dir.join("ten_million.toml");
    std::fs::write(
        &scene,
        r#"name = "ten-million"
[run]
duration = 0.001
[domain]
min = [0.0, 0.0, 0.0]
max = [2.2, 2.2, 2.2]
[[materials]]
name = "glass"
density = 2500.0
[contact]
normal = { model = "linear", stiffness = 1.0e4 }
restitution = 0.5
[[particles]]
material = "glass"
shape = { sphere = { diameter = 0.009 } }
lattice = { min = [0.0, 0.0, 0.0], max = [2.2, 2.2, 2.2], spacing = 0.01 }
"#,
    )
    .unwrap();
    let limited = format!("ulimit -v 1572864 && exec '{}' plan '{}'", env!("CARGO_BIN_EXE_tumble"), scene.display());
    let o = Command::new("sh").arg("-c").arg(&limited).output().unwrap();
    let stderr = String::from_utf8_lossy(&o.stderr);
    println!("{stderr}");
    assert_eq!(o.status.code(), Some(2), "{stderr}");
    assert!(stderr.contains("particles[0].lattice") && stderr.contains("ulimit -v") && stderr.trim().lines().count() == 1, "{stderr}");
    let _ = std::fs::remove_dir_all(&dir);
}

/// An outlet plane whose normal points into three of four particles (the compile check refuses
/// only an outlet that holds them all): the run writes its first rows, then stops with exit
/// status 3 naming the outlet, the share it deleted and the remedy; with
/// `run.max_outlet_fraction = 1` the same run completes.
#[test]
fn an_outlet_that_deletes_most_particles_at_once_stops_the_run() {
    let text = scene_file("tests/bad_scenes/outlet_normal_points_at_the_bed.toml")
        .replace("[0.04, 0.0, 0.0]]", "[0.04, 0.0, 0.0], [0.0, 0.0, -0.05]]")
        .replace("point = [0.0, 0.0, -0.08]", "point = [0.0, 0.0, -0.02]");
    let dir = tmp("outlet-flood");
    std::fs::create_dir_all(&dir).unwrap();
    let run = |name: &str, text: &str| {
        let scene = dir.join(format!("{name}.toml"));
        std::fs::write(&scene, text).unwrap();
        let out = dir.join(name);
        let o = Command::new(env!("CARGO_BIN_EXE_tumble")).arg("run").arg(&scene).args(["--quiet", "--out"]).arg(&out).output().unwrap();
        (o.status.code(), String::from_utf8_lossy(&o.stderr).to_string(), out)
    };
    let (code, stderr, out) = run("flood", &text);
    assert_eq!(code, Some(3), "{stderr}");
    let error: Vec<&str> = stderr.lines().filter(|l| l.starts_with("error: ")).collect();
    assert!(
        error.len() == 1 && error[0].contains("outlet \"bin\" deleted 3 of 4 particles (75.0 %)") && error[0].contains("run.max_outlet_fraction = 1"),
        "{stderr}"
    );
    let summary = std::fs::read_to_string(out.join("summary.json")).unwrap();
    assert!(summary.contains("\"status\": \"stopped\""), "{summary}");
    let (code, stderr, _) = run("intended", &text.replace("[run]\n", "[run]\nmax_outlet_fraction = 1.0\n"));
    assert_eq!(code, Some(0), "{stderr}");
    let _ = std::fs::remove_dir_all(&dir);
}

/// The same source behind the end plate, without `run.allow_idle_sources`: the run writes its
/// outputs and then fails with exit status 3, naming the source, and summary.json says stopped.
#[test]
fn a_source_that_never_found_room_fails_the_run() {
    let scene = drum_scene("idle-source", |text| {
        text + "[[walls]]\nname = \"plate\"\nmaterial = \"steel\"\nplane = { point = [0.0, 0.0, 0.0], normal = [0.0, 0.0, 1.0] }\n\
                [[sources]]\nname = \"feed\"\nmaterial = \"steel\"\nshape = { sphere = { diameter = 0.02 } }\n\
                region = { box = { min = [-0.1, -0.1, -0.09], max = [0.1, 0.1, -0.01] } }\nrate = { particles_per_second = 100.0 }\n"
    });
    let out = scene.parent().unwrap().join("out");
    let run = Command::new(env!("CARGO_BIN_EXE_tumble"))
        .arg("run")
        .arg(&scene)
        .args(["--duration", "0.01", "--quiet", "--out"])
        .arg(&out)
        .output()
        .unwrap();
    let stderr = String::from_utf8_lossy(&run.stderr);
    assert_eq!(run.status.code(), Some(3), "{stderr}");
    let error: Vec<&str> = stderr.lines().filter(|l| l.starts_with("error: ")).collect();
    assert!(error.len() == 1 && error[0].contains("source \"feed\" inserted no particle") && error[0].contains("run.allow_idle_sources"), "{stderr}");
    let summary = std::fs::read_to_string(out.join("summary.json")).unwrap();
    assert!(summary.contains("\"status\": \"stopped\""), "{summary}");
    let _ = std::fs::remove_dir_all(scene.parent().unwrap());
}
