//! The shared test scenes of `scenes/test/`, read by every crate's tests, and the checked
//! edits that derive a variant from one.

use tumble::{CompiledScene, compile, parse_scene};

/// The repository's root folder.
pub fn repository() -> std::path::PathBuf {
    std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../..")
}

/// The text of a scene file below the repository root (`scenes/verify/07_hertz_impact.toml`).
pub fn file(path: &str) -> String {
    let full = repository().join(path);
    std::fs::read_to_string(&full).unwrap_or_else(|e| panic!("{}: {e}", full.display()))
}

/// The text of the test scene `scenes/test/{name}.toml`.
pub fn test_scene(name: &str) -> String {
    file(&format!("scenes/test/{name}.toml"))
}

/// `text` with `from` replaced by `to`; panics when `from` is not there, so that a scene edit
/// can never silently do nothing.
pub fn replaced(text: &str, from: &str, to: &str) -> String {
    assert!(text.contains(from), "the scene has no {from:?} to replace");
    text.replace(from, to)
}

/// A scene text compiled; a bad scene fails the test with its message.
pub fn compiled(text: &str) -> CompiledScene {
    compile(&parse_scene(text).unwrap_or_else(|e| panic!("{e}"))).unwrap_or_else(|e| panic!("{e}"))
}

/// `scenes/test/spinning.toml`: a free body of `shape` (a TOML inline table) spinning at `omega`.
pub fn spinning(shape: &str, omega: [f64; 3], dt: f64, duration: f64) -> String {
    let text = test_scene("spinning");
    let text = replaced(&text, "duration = 10.0", &format!("duration = {duration}"));
    let text = replaced(&text, "dt = 0.002", &format!("dt = {dt}"));
    let text = replaced(&text, "shape = { box = { size = [0.1, 0.2, 0.3] } }", &format!("shape = {shape}"));
    replaced(&text, "angular_velocity = [0.001, 5.0, 0.001]", &format!("angular_velocity = [{}, {}, {}]", omega[0], omega[1], omega[2]))
}

/// `scenes/test/cube_drop.toml`: its cube at `position` turned by the quaternion `orientation`
/// ([w, x, y, z]), with `restitution`, for `duration`.
pub fn cube_drop(position: [f64; 3], orientation: [f64; 4], restitution: f64, duration: f64) -> String {
    let text = test_scene("cube_drop");
    let text = replaced(&text, "duration = 1.0", &format!("duration = {duration}"));
    let text = replaced(&text, "restitution = 0.5", &format!("restitution = {restitution}"));
    let text = replaced(&text, "positions = [[0.0, 0.0, 0.05]]", &format!("positions = [{position:?}]"));
    replaced(&text, "orientation = [1.0, 0.0, 0.0, 0.0]", &format!("orientation = {orientation:?}"))
}

/// A scene text compiled to run only its first `steps` steps, at the step its whole run would take.
pub fn shortened(text: &str, steps: u64) -> CompiledScene {
    let dt = dt(&compiled(text));
    let mut scene = parse_scene(text).unwrap_or_else(|e| panic!("{e}"));
    scene.run.duration = steps as f64 * dt;
    scene.run.dt = Some(tumble_scene::schema::DtSpec::Seconds(dt));
    compile(&scene).unwrap_or_else(|e| panic!("{e}"))
}

/// The number of steps a compiled scene's plan runs.
pub fn steps(scene: &CompiledScene) -> u64 {
    scene.plan.run.steps
}

/// The time step of a compiled scene's plan.
pub fn dt(scene: &CompiledScene) -> f64 {
    scene.plan.model.dt
}
