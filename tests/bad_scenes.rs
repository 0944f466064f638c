//! The bad-scene corpus: every file under tests/bad_scenes/ must fail with one
//! line naming the field or line (its `# expect:` comment), exit non-zero and
//! create or overwrite nothing.

use std::path::{Path, PathBuf};
use std::process::Command;

fn corpus() -> Vec<(PathBuf, String)> {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/bad_scenes");
    let mut files: Vec<(PathBuf, String)> = std::fs::read_dir(&dir)
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|e| e == "toml"))
        .map(|p| {
            let text = std::fs::read_to_string(&p).unwrap();
            let expect = text
                .lines()
                .next()
                .and_then(|l| l.strip_prefix("# expect: "))
                .unwrap_or_else(|| panic!("{} lacks # expect:", p.display()))
                .to_string();
            (p, expect)
        })
        .collect();
    files.sort();
    files
}

#[test]
fn corpus_is_large_enough() {
    assert!(corpus().len() >= 25);
}

#[test]
fn every_bad_scene_names_its_problem_on_one_line() {
    for (path, expect) in corpus() {
        let Err(err) = tumble::load_scene(&path, None, None) else { panic!("{} must be rejected", path.display()) };
        let err = err.to_string();
        println!("{err}");
        assert!(err.contains(&expect), "{}: message {err:?} lacks {expect:?}", path.display());
        assert!(!err.contains('\n'), "{}: message spans lines: {err:?}", path.display());
        assert!(err.starts_with(&path.display().to_string()), "{}: message must start with the file: {err:?}", path.display());
    }
}

#[test]
fn the_command_line_refuses_bad_scenes_and_writes_nothing() {
    let tmp = std::env::temp_dir().join(format!("tumble-bad-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&tmp);
    std::fs::create_dir_all(&tmp).unwrap();
    // An earlier run's output that a bad scene must not overwrite.
    let existing = tmp.join("existing");
    std::fs::create_dir_all(&existing).unwrap();
    std::fs::write(existing.join("summary.json"), "{\"kept\": true}\n").unwrap();
    let mut cases = corpus();
    cases.push((tmp.join("no-such-scene.toml"), "cannot read the scene file".into()));
    for (k, (path, expect)) in cases.iter().enumerate() {
        let out = if k % 2 == 0 { tmp.join(format!("out{k}")) } else { existing.clone() };
        let result = Command::new(env!("CARGO_BIN_EXE_tumble")).arg("run").arg(path).arg("--out").arg(&out).arg("--quiet").output().unwrap();
        let stderr = String::from_utf8_lossy(&result.stderr);
        assert!(!result.status.success(), "{}: exit status {:?}", path.display(), result.status);
        assert_eq!(stderr.trim_end().lines().count(), 1, "{}: {stderr}", path.display());
        assert!(stderr.contains(expect.as_str()), "{}: {stderr}", path.display());
        if k % 2 == 0 {
            assert!(!out.exists(), "{}: created {}", path.display(), out.display());
        }
    }
    assert_eq!(std::fs::read_to_string(existing.join("summary.json")).unwrap(), "{\"kept\": true}\n");
    assert_eq!(std::fs::read_dir(&existing).unwrap().count(), 1);
    let _ = std::fs::remove_dir_all(&tmp);
}
