use std::fmt;
use std::path::{Path, PathBuf};

/// A scene that cannot run, with where and why, on one line.
#[derive(Clone, Debug, PartialEq)]
pub struct SceneError {
    pub file: Option<PathBuf>,
    /// 1-based line and column for syntax and type errors.
    pub line_col: Option<(usize, usize)>,
    /// Dotted path of the offending field (`contact.normal.stiffness`), when known.
    pub field: Option<String>,
    pub message: String,
}

impl SceneError {
    pub fn field(field: impl Into<String>, message: impl Into<String>) -> Self {
        SceneError { file: None, line_col: None, field: Some(field.into()), message: message.into() }
    }

    pub fn in_file(mut self, file: &Path) -> Self {
        self.file = Some(file.to_path_buf());
        self
    }
}

impl fmt::Display for SceneError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        if let Some(file) = &self.file {
            write!(f, "{}", file.display())?;
            if let Some((l, c)) = self.line_col {
                write!(f, ":{l}:{c}")?;
            }
            write!(f, ": ")?;
        } else if let Some((l, c)) = self.line_col {
            write!(f, "line {l}, column {c}: ")?;
        }
        if let Some(field) = &self.field {
            write!(f, "{field}: ")?;
        }
        write!(f, "{}", self.message)
    }
}

impl std::error::Error for SceneError {}
