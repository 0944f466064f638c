use crate::{Scene, SceneError};
use std::path::Path;

/// Parses a scene from TOML text; syntax and type errors carry line and column.
pub fn parse_scene(text: &str) -> Result<Scene, SceneError> {
    toml::from_str::<Scene>(text).map_err(|e| {
        let line_col = e.span().map(|span| line_col(text, span.start));
        let field = e.span().and_then(|span| field_at(text, span.start));
        let mut message = e.message().trim().replace('\n', " ");
        // Untagged forms say only that no form matched: name the valid ones.
        for (name, forms) in UNTAGGED_FORMS {
            if message.contains(&format!("untagged enum {name}")) {
                message += &format!("; {forms}");
            }
        }
        SceneError { file: None, line_col, field, message }
    })
}

/// The dotted name of the key whose value starts at `offset` (`run.duration`,
/// `particles[1].material`), where the value sits on a `key = value` line of a table.
fn field_at(text: &str, offset: usize) -> Option<String> {
    let offset = offset.min(text.len());
    let line_start = text[..offset].rfind('\n').map_or(0, |p| p + 1);
    let (key, _) = text[line_start..offset].split_once('=')?;
    let key = key.trim();
    if key.is_empty() || !key.chars().all(|c| c.is_ascii_alphanumeric() || matches!(c, '_' | '-' | '.')) {
        return None;
    }
    let before = &text[..line_start];
    let Some(header) = before.lines().rev().map(str::trim).find(|l| l.starts_with('[')) else { return Some(key.to_string()) };
    let table = if let Some(name) = header.strip_prefix("[[").and_then(|h| h.split("]]").next()) {
        // A header without its closing brackets ("[[run") counts no entry: no table is named.
        let k = before.lines().filter(|l| l.trim().starts_with(&format!("[[{name}]]"))).count().checked_sub(1)?;
        format!("{}[{k}]", name.trim())
    } else {
        header.trim_start_matches('[').split(']').next()?.trim().to_string()
    };
    // A header that is itself broken names no table; the line and column still say where.
    if table.is_empty() || !table.chars().all(|c| c.is_ascii_alphanumeric() || "_-.[]".contains(c)) {
        return None;
    }
    Some(format!("{table}.{key}"))
}

const UNTAGGED_FORMS: [(&str, &str); 3] = [
    ("VelocitySpec", "velocity is [vx, vy, vz], { random = { mean_speed = …, std = … } } or \"flow\""),
    ("ViscositySpec", "viscosity is a number in Pa s or { stokes_number = … }"),
    ("DtSpec", "dt is a number in seconds or { collision_fraction = … }"),
];

/// Reads and parses a scene file.
pub fn read_scene(path: &Path) -> Result<Scene, SceneError> {
    let mut scene = parse_scene(&read_scene_text(path)?).map_err(|e| e.in_file(path))?;
    scene.folder = path.parent().map(Path::to_path_buf);
    Ok(scene)
}

/// Reads a scene file's text (a file that cannot be read, or is not UTF-8, is named with where).
pub fn read_scene_text(path: &Path) -> Result<String, SceneError> {
    let bytes = std::fs::read(path).map_err(|e| SceneError {
        file: Some(path.to_path_buf()),
        line_col: None,
        field: None,
        message: format!("cannot read the scene file: {e}"),
    })?;
    let text = std::str::from_utf8(&bytes).map_err(|e| {
        // Where the text stops being UTF-8, counted in the valid text before it.
        let valid = std::str::from_utf8(&bytes[..e.valid_up_to()]).unwrap_or_default();
        SceneError {
            file: Some(path.to_path_buf()),
            line_col: Some(line_col(valid, valid.len())),
            field: None,
            message: format!("byte {:#04x} is not UTF-8 text; a scene file is UTF-8", bytes[e.valid_up_to()]),
        }
    })?;
    Ok(text.to_string())
}

fn line_col(text: &str, offset: usize) -> (usize, usize) {
    let before = &text[..offset.min(text.len())];
    let line = before.matches('\n').count() + 1;
    let col = before.len() - before.rfind('\n').map_or(0, |p| p + 1) + 1;
    (line, col)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn error_of(text: &str) -> String {
        parse_scene(text).unwrap_err().to_string()
    }

    #[test]
    fn a_file_that_is_not_utf8_is_refused_at_its_line_and_column() {
        // Found by the scene fuzzer: the refusal named the file only.
        let path = std::env::temp_dir().join(format!("tumble-not-utf8-{}.toml", std::process::id()));
        std::fs::write(&path, b"name = \"a\"\n[run]\nintegrator = \"ver\xfflet\"\n").unwrap();
        let e = read_scene(&path).unwrap_err();
        let _ = std::fs::remove_file(&path);
        assert_eq!(e.line_col, Some((3, 18)));
        assert!(e.to_string().ends_with(":3:18: byte 0xff is not UTF-8 text; a scene file is UTF-8"), "{e}");
    }

    #[test]
    fn a_value_under_an_unclosed_array_of_tables_header_names_no_table() {
        // Found by the scene fuzzer: "[[" without its "]]" counted minus one entries.
        let text = "name = \"a\"\n[[run\nduration = 1.0\n";
        assert_eq!(field_at(text, text.find("1.0").unwrap()), None);
    }

    #[test]
    fn a_type_error_names_the_field_and_cuts_long_values() {
        let e = error_of("name = \"a\"\n[run]\nduration = \"long\"\n");
        assert!(e.starts_with("line 3, column 12: run.duration: invalid type: string \"long\", expected f64"), "{e}");
        let group = "shape = { sphere = { diameter = 0.1 } }\npositions = [[0.0, 0.0, 0.0]]\n";
        let text = format!("name = \"a\"\n[run]\nduration = 1.0\n[[particles]]\nmaterial = \"m\"\n{group}[[particles]]\nmaterial = 7\n{group}");
        let e = error_of(&text);
        assert!(e.contains("particles[1].material: invalid type: integer `7`"), "{e}");
        let e = error_of(&format!("name = \"a\"\n[run]\nduration = \"{}\"\n", "y".repeat(100_000)));
        assert!(e.len() < 200 && e.contains("(100000 characters)"), "{e}");
    }
}
