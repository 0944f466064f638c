//! `tumble resume`: continuing a run from the newest checkpoint in its folder, appending to its
//! files (docs/cli.md, "Checkpoints and resume").

use crate::checkpoint::{self, Checkpoint};
use crate::run::{RunError, RunOptions, RunSummary, checkpoint_every, compile_text, io, set_up};
use crate::run_loop::{Books, Outputs, Run};
use crate::summary::running_json;
use std::path::Path;
use tumble_scene::schema::BackendName;

/// Continues the run in `dir` from its newest checkpoint, appending to its files.
///
/// The scene is the one the run started with (recorded in the checkpoint); `options.duration`
/// may extend it, `options.threads` is free (the CPU's results do not depend on it), and the
/// backend must be the one that wrote the checkpoint. A refusal changes nothing in `dir`.
pub fn resume_run(dir: &Path, options: &RunOptions) -> Result<RunSummary, RunError> {
    let refuse = RunError::Resume;
    if !dir.join(crate::outdir::MARKER).is_file() {
        return Err(refuse(format!("{}: not the output folder of a tumble run (no {} marker)", dir.display(), crate::outdir::MARKER)));
    }
    let (path, Checkpoint { header: cp, snapshot }) = checkpoint::newest(dir).map_err(refuse)?;
    let shown = path.display();
    let Some(mut record) = cp.scene.clone() else {
        return Err(refuse(format!(
            "{shown}: the checkpoint records no scene (the run was started through the library's run_compiled); run_scene_file records it"
        )));
    };
    if let Ok(now) = std::fs::read_to_string(&record.path)
        && now != record.text
    {
        return Err(refuse(format!(
            "{}: the scene file changed since the run in {} started, and a run continues only the scene it started with; restore the file, or start a new run with tumble run",
            record.path.display(),
            dir.display()
        )));
    }
    if let Some(why) = record.changed_input() {
        return Err(refuse(format!(
            "{why} since the run in {} started (a mesh of its scene), and a run continues only the geometry it started with; restore the file, or start a new run with tumble run",
            dir.display()
        )));
    }
    if options.dt.is_some_and(|dt| Some(dt) != record.dt) {
        return Err(refuse(format!("{shown}: a resumed run keeps the dt it started with; leave out --dt")));
    }
    let Some(backend) = BackendName::from_name(&cp.backend) else {
        return Err(refuse(format!("{shown}: written by an unknown backend `{}`", cp.backend)));
    };
    if options.backend.is_some_and(|b| b != backend) {
        return Err(refuse(format!("{shown}: written by the {} backend; a run continues on the backend that started it", backend.name())));
    }
    if options.duration.is_some() {
        record.duration = options.duration;
    }
    if options.checkpoint_interval.is_some() {
        record.checkpoint_interval = options.checkpoint_interval;
    }
    let compiled = compile_text(&record.text, &record.path, record.duration, record.dt).map_err(RunError::Scene)?;
    let plan_text = compiled.plan.describe(compiled.particles.len());
    let books: Books = postcard::from_bytes(&cp.books).map_err(|e| refuse(format!("{shown}: the run's books cannot be decoded: {e}")))?;
    let folder_scene = std::fs::read_to_string(dir.join("summary.json"))
        .ok()
        .and_then(|t| serde_json::from_str::<serde_json::Value>(&t).ok())
        .and_then(|v| v["scene"].as_str().map(str::to_string));
    if let Some(name) = folder_scene
        && name != snapshot.scene
    {
        return Err(refuse(format!("{shown}: a checkpoint of scene `{}`, but the run in {} is scene `{name}`", snapshot.scene, dir.display())));
    }
    // The restore replaces every particle on the CPU; a device's arrays are sized to the seed's
    // particles, so a seeded GPU run is set up seeded again (its seed must still be there).
    let (mut sim, _) = set_up(backend, compiled, options.threads, backend == BackendName::Gpu)?;
    sim.restore(&snapshot).map_err(|e| refuse(format!("{shown}: {e}")))?;
    let phases = sim.all_phases().count();
    if books.phases.len() != phases {
        return Err(refuse(format!("{shown}: the checkpoint holds {} phases (the particles' included), the scene {phases}", books.phases.len())));
    }
    for (phase, bytes) in sim.all_phases_mut().zip(&books.phases) {
        phase.restore(bytes).map_err(|e| refuse(format!("{shown}: {e}")))?;
    }
    let total = sim.plan().run.steps;
    if sim.steps() >= total {
        return Err(refuse(format!(
            "{shown}: the run already reached its end (step {}, t = {:.6e} s); pass --duration longer than {} s to continue it",
            sim.steps(),
            sim.time(),
            sim.plan().run.duration
        )));
    }
    check_files(dir, &books).map_err(refuse)?;
    io(dir, checkpoint::remove_unfinished(dir))?;
    let outputs = io(dir, Outputs::open(dir, &sim, Some(&books)))?;
    io(dir, crate::outdir::write_atomic(&dir.join("summary.json"), &running_json(&sim, &plan_text)))?;
    let checkpoint_every = checkpoint_every(sim.plan(), record.checkpoint_interval);
    let mut run = Run::new(sim, dir.to_path_buf(), options, books, outputs, Some(record), plan_text, Some(cp.step), checkpoint_every);
    if cp.tumble_version != env!("CARGO_PKG_VERSION") {
        run.warnings.push(format!(
            "resumed from a checkpoint of tumble {} with tumble {}: the continuation is not guaranteed to be bit-identical",
            cp.tumble_version,
            env!("CARGO_PKG_VERSION")
        ));
    }
    run.go(None, false)
}

/// Refuses a folder whose output files are shorter than the checkpoint says they were.
fn check_files(dir: &Path, books: &Books) -> Result<(), String> {
    for (name, len) in &books.files {
        let path = dir.join(name);
        let now = std::fs::metadata(&path).map_err(|e| format!("{}: {e}; the output folder was changed after the checkpoint", path.display()))?.len();
        if now < *len {
            return Err(format!("{}: {now} bytes, but {len} at the checkpoint; the output folder was changed after the checkpoint", path.display()));
        }
    }
    Ok(())
}
