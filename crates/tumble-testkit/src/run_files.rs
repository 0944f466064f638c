//! A run's output folder: its CSV columns, and its files as bytes for tests that compare runs
//! file by file.

use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};

/// A fresh, empty folder `tumble-<prefix>-<name>-<pid>` under the system's temporary folder.
pub fn scratch_dir(prefix: &str, name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("tumble-{prefix}-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

/// Column `name` of the CSV file at `path`, every row, as numbers.
pub fn csv_column(path: &Path, name: &str) -> Vec<f64> {
    let text = std::fs::read_to_string(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    let mut lines = text.lines();
    let k = lines.next().unwrap().split(',').position(|h| h == name).unwrap_or_else(|| panic!("{}: no column {name}", path.display()));
    lines.map(|l| l.split(',').nth(k).unwrap().parse().unwrap_or_else(|e| panic!("{}: {name}: {e}", path.display()))).collect()
}

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

/// Runs `scene` with the `tumble` executable `exe` (in the folder `cwd`) to `full` seconds on 1
/// and on 2 threads, and to `half` on 2 threads then resumed to `full` on 1, checkpointing every
/// `every` seconds, each run in a folder of `dir`; fails unless all three wrote the same files.
/// Answers the first run's folder.
pub fn assert_thread_independent_and_resumable(exe: &Path, cwd: &Path, scene: &Path, dir: &Path, [half, full, every]: [&str; 3]) -> PathBuf {
    let tumble = |args: &[&str]| {
        let o = Command::new(exe).args(args).current_dir(cwd).stdin(Stdio::null()).output().unwrap();
        assert!(o.status.success(), "tumble {}: {}", args.join(" "), String::from_utf8_lossy(&o.stderr));
    };
    let scene = scene.to_str().unwrap();
    let run = |out: &Path, duration: &str, threads: &str| {
        tumble(&[
            "run",
            scene,
            "--quiet",
            "--duration",
            duration,
            "--threads",
            threads,
            "--checkpoint-interval",
            every,
            "--out",
            out.to_str().unwrap(),
        ])
    };
    let (one, two, halves) = (dir.join("one"), dir.join("two"), dir.join("halves"));
    run(&one, full, "1");
    run(&two, full, "2");
    assert_same_files(&one, &two);
    run(&halves, half, "2");
    tumble(&["resume", halves.to_str().unwrap(), "--quiet", "--duration", full, "--threads", "1"]);
    assert_same_files(&one, &halves);
    one
}
