//! The output folder: never mixed with another run's files, replaced only when tumble made it.

use std::io::Write;
use std::path::Path;

/// The file that marks a folder as one tumble's run wrote (and `--overwrite` may clear).
pub const MARKER: &str = ".tumble-output";

/// Makes `dir` ready for a run's outputs: created when absent, used when empty; a non-empty
/// folder is cleared only with `overwrite` and only when it holds tumble's marker.
pub fn prepare(dir: &Path, overwrite: bool) -> Result<(), String> {
    let shown = dir.display();
    match std::fs::read_dir(dir) {
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => {}
        Err(e) => return Err(format!("{shown}: cannot read the output folder: {e}")),
        Ok(entries) => {
            let entries: Vec<_> = entries.filter_map(Result::ok).collect();
            if !entries.is_empty() {
                if !dir.join(MARKER).is_file() {
                    return Err(format!(
                        "{shown}: the output folder holds {} entries that no tumble run wrote (no {MARKER} marker); tumble will not mix its outputs with them or clear them: choose another --out",
                        entries.len()
                    ));
                }
                if !overwrite {
                    return Err(format!(
                        "{shown}: the output folder holds an earlier run's outputs; pass --overwrite to replace them, or choose another --out"
                    ));
                }
                for e in entries {
                    let path = e.path();
                    let removed = if e.file_type().is_ok_and(|t| t.is_dir()) { std::fs::remove_dir_all(&path) } else { std::fs::remove_file(&path) };
                    removed.map_err(|err| format!("{}: cannot clear the earlier run's output: {err}", path.display()))?;
                }
            }
        }
    }
    std::fs::create_dir_all(dir).map_err(|e| format!("{shown}: cannot create the output folder: {e}"))?;
    std::fs::write(dir.join(MARKER), "This folder holds the outputs of a tumble run; `tumble run --overwrite` may replace them.\n")
        .map_err(|e| format!("{shown}: cannot write to the output folder: {e}"))
}

/// Writes `text` to `path` through a temporary file and a rename, so readers never see a partial file.
pub fn write_atomic(path: &Path, text: &str) -> std::io::Result<()> {
    let tmp = path.with_extension("tmp");
    {
        let mut f = std::fs::File::create(&tmp)?;
        f.write_all(text.as_bytes())?;
        f.sync_all()?;
    }
    std::fs::rename(&tmp, path)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn fresh(tag: &str) -> std::path::PathBuf {
        let d = std::env::temp_dir().join(format!("tumble-outdir-{tag}-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&d);
        d
    }

    #[test]
    fn a_folder_of_other_files_is_never_used_or_cleared() {
        let d = fresh("foreign");
        std::fs::create_dir_all(&d).unwrap();
        std::fs::write(d.join("thesis.tex"), "keep me").unwrap();
        for overwrite in [false, true] {
            let e = prepare(&d, overwrite).unwrap_err();
            assert!(e.contains("no tumble run wrote") && !e.contains('\n'), "{e}");
        }
        assert_eq!(std::fs::read_to_string(d.join("thesis.tex")).unwrap(), "keep me");
        assert!(!d.join(MARKER).exists());
    }

    #[test]
    fn an_earlier_run_is_replaced_only_with_overwrite() {
        let d = fresh("earlier");
        prepare(&d, false).unwrap();
        assert!(d.join(MARKER).is_file(), "a new folder is marked");
        std::fs::create_dir_all(d.join("snapshots")).unwrap();
        std::fs::write(d.join("snapshots").join("particles_000009.vtp"), "stale").unwrap();
        std::fs::write(d.join("observables.csv"), "stale").unwrap();
        let e = prepare(&d, false).unwrap_err();
        assert!(e.contains("--overwrite"), "{e}");
        assert!(d.join("observables.csv").exists(), "a refusal changes nothing");
        prepare(&d, true).unwrap();
        let left: Vec<_> = std::fs::read_dir(&d).unwrap().map(|e| e.unwrap().file_name()).collect();
        assert_eq!(left, vec![std::ffi::OsString::from(MARKER)], "only the marker is left");
    }

    #[test]
    fn an_empty_folder_is_used() {
        let d = fresh("empty");
        std::fs::create_dir_all(&d).unwrap();
        prepare(&d, false).unwrap();
        assert!(d.join(MARKER).is_file());
    }

    #[test]
    fn an_atomic_write_leaves_no_temporary_file() {
        let d = fresh("atomic");
        std::fs::create_dir_all(&d).unwrap();
        write_atomic(&d.join("summary.json"), "{}\n").unwrap();
        write_atomic(&d.join("summary.json"), "{\"status\": \"completed\"}\n").unwrap();
        assert_eq!(std::fs::read_to_string(d.join("summary.json")).unwrap(), "{\"status\": \"completed\"}\n");
        assert!(!d.join("summary.tmp").exists());
    }
}
