use crate::{Scene, SceneError};
use std::path::Path;

/// Parses a scene from TOML text; syntax and type errors carry line and column.
pub fn parse_scene(text: &str) -> Result<Scene, SceneError> {
    toml::from_str::<Scene>(text).map_err(|e| {
        let line_col = e.span().map(|span| line_col(text, span.start));
        let mut message = e.message().trim().replace('\n', " ");
        // Untagged forms say only that no form matched: name the valid ones.
        for (name, forms) in UNTAGGED_FORMS {
            if message.contains(&format!("untagged enum {name}")) {
                message += &format!("; {forms}");
            }
        }
        SceneError { file: None, line_col, field: None, message }
    })
}

const UNTAGGED_FORMS: [(&str, &str); 3] = [
    ("VelocitySpec", "velocity is [vx, vy, vz], { random = { mean_speed = …, std = … } } or \"flow\""),
    ("ViscositySpec", "viscosity is a number in Pa s or { stokes_number = … }"),
    ("DtSpec", "dt is a number in seconds or { collision_fraction = … }"),
];

/// Reads and parses a scene file.
pub fn read_scene(path: &Path) -> Result<Scene, SceneError> {
    let text = std::fs::read_to_string(path).map_err(|e| SceneError {
        file: Some(path.to_path_buf()),
        line_col: None,
        field: None,
        message: format!("cannot read the scene file: {e}"),
    })?;
    parse_scene(&text).map_err(|e| e.in_file(path))
}

fn line_col(text: &str, offset: usize) -> (usize, usize) {
    let before = &text[..offset.min(text.len())];
    let line = before.matches('\n').count() + 1;
    let col = before.len() - before.rfind('\n').map_or(0, |p| p + 1) + 1;
    (line, col)
}
