//! Scenes that would run to the end and mean nothing: the plan warns about each likely
//! mistake with its cause (`tumble plan`, and `tumble run` before its first step).

use crate::plan::PhysicsModel;
use crate::schema::Scene;

/// Warnings about schedules the run never reaches.
pub(super) fn warnings(scene: &Scene, model: &PhysicsModel) -> Vec<String> {
    let mut warnings = Vec::new();
    schedules_after_the_end(scene, model, &mut warnings);
    warnings
}

/// A motion or a source that starts at or after the end of the run never acts: the drum
/// never turns, nothing is inserted.
fn schedules_after_the_end(scene: &Scene, model: &PhysicsModel, warnings: &mut Vec<String>) {
    let end = scene.run.duration;
    for (k, w) in scene.walls.iter().enumerate() {
        if let Some(m) = &w.motion
            && m.start >= end
        {
            warnings.push(format!(
                "walls[{k}].motion.start = {} s is not before the end of the run (run.duration = {end} s): wall \"{}\" never moves",
                m.start, model.wall_groups[k].name
            ));
        }
    }
    for (k, s) in scene.sources.iter().enumerate() {
        if s.start >= end {
            warnings.push(format!(
                "sources[{k}].start = {} s is not before the end of the run (run.duration = {end} s): source \"{}\" inserts nothing",
                s.start, model.sources[k].name
            ));
        }
    }
}
