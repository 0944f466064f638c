//! A run's output folder as bytes, for tests that compare runs file by file.

use std::path::Path;

/// Every file a run wrote (CSV, .pvd, snapshots; summary.json, checkpoints and hidden files
/// aside), by path relative to `dir`, sorted.
pub fn run_files(dir: &Path) -> Vec<(String, Vec<u8>)> {
    let mut files = Vec::new();
    for sub in ["", "snapshots"] {
        for e in std::fs::read_dir(dir.join(sub)).unwrap() {
            let path = e.unwrap().path();
            let name = path.strip_prefix(dir).unwrap().to_string_lossy().into_owned();
            if path.is_file() && !name.starts_with('.') && name != "summary.json" {
                files.push((name, std::fs::read(&path).unwrap()));
            }
        }
    }
    files.sort();
    files
}

/// Fails unless the run in `dir` wrote the same files, byte for byte, as the uninterrupted run
/// in `reference`.
pub fn assert_same_files(reference: &Path, dir: &Path) {
    let (want, got) = (run_files(reference), run_files(dir));
    let shown = dir.display();
    assert_eq!(got.iter().map(|f| &f.0).collect::<Vec<_>>(), want.iter().map(|f| &f.0).collect::<Vec<_>>(), "{shown}: other files");
    for ((name, a), (_, b)) in want.iter().zip(&got) {
        assert!(a == b, "{shown}: {name} differs from the uninterrupted run's");
    }
}
