//! `cargo xtask tidy`: two checks on the repository's text files.
//!
//! **References.** Every file or folder a text file cites exists. A citation is
//! - a markdown link `[text](target)` in a `.md` file, resolved from the citing file's folder
//!   (web links, `mailto:` and pure `#anchors` are not files; an `#anchor` is dropped);
//! - a path starting with `../`, resolved from the citing file's folder;
//! - a path `first/…` whose first folder exists in the citing file's folder, at the repository
//!   root or in a workspace package, resolved from any of those places: a file cited from its
//!   crate (`tests/backends/vs_cpu.rs`) or from the root (`crates/…`, `docs/…`) passes wherever it is;
//! - any name ending in `.md` (`ARCHITECTURE.md`, `docs/<page>.md`), also looked up in `docs/`.
//!
//! These are not citations: paths under folders the repository does not have (outputs such as
//! `out/<name>/`, build products under `target/`); paths with an extension no repository file has
//! (another project's sources); a path with a pattern character (`*`, `?`, `<`, `>`, `{`, `}`,
//! `$`, `…`), such as `scenes/verify/*.toml`; an optional argument of a usage line, `[name.md]`;
//! an absolute path or a URL's tail (`/usr/share/…`, `//host/…`).
//!
//! **Long files.** A file under `crates/` longer than [`LONG_FILE_LINES`] lines states why, in a
//! line starting with `// tidy: long file:` followed by the reason.

use std::collections::BTreeSet;
use std::path::{Path, PathBuf};
use std::process::Command;

/// Files under `crates/` longer than this must state a reason.
pub const LONG_FILE_LINES: usize = 600;

/// The line that excuses a long file: this marker, then the reason.
const LONG_FILE_MARK: &str = "// tidy: long file:";

/// Extensions of the files scanned for citations.
const SCANNED_EXTENSIONS: &[&str] = &["rs", "md", "toml", "wgsl", "sh"];

/// Scanned files without one of those extensions.
const SCANNED_FILES: &[&str] = &[".ci/run"];

/// Characters that make a path a pattern rather than a citation.
const PATTERN_CHARS: &[char] = &['*', '?', '<', '>', '{', '}', '$', '…'];

/// `cargo xtask tidy`: prints every dangling citation and unexplained long file; 1 if any.
pub fn run(args: &[String]) -> i32 {
    if !args.is_empty() {
        eprintln!("usage: cargo xtask tidy");
        return 2;
    }
    let tree = match Tree::from_git(&repository_root()) {
        Ok(t) => t,
        Err(e) => {
            eprintln!("error: {e}");
            return 2;
        }
    };
    let dangling = tree.dangling_references();
    let long = tree.long_files();
    for d in &dangling {
        println!("{d}");
    }
    for l in &long {
        println!("{l}");
    }
    println!(
        "tidy: {} text files, {} dangling references, {} files under crates/ over {LONG_FILE_LINES} lines without a `{LONG_FILE_MARK}` reason",
        tree.scanned().count(),
        dangling.len(),
        long.len()
    );
    i32::from(!dangling.is_empty() || !long.is_empty())
}

/// The workspace root (the folder above xtask/).
pub fn repository_root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).parent().expect("xtask lives in the workspace").to_path_buf()
}

/// A citation of a file that does not exist.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Dangling {
    /// The citing file, relative to the root.
    pub file: String,
    /// 1-based line of the citation.
    pub line: usize,
    /// The cited path as written.
    pub target: String,
}

impl std::fmt::Display for Dangling {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{}:{}: {} does not exist", self.file, self.line, self.target)
    }
}

/// A file under `crates/` over the limit without a reason.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct LongFile {
    pub file: String,
    pub lines: usize,
}

impl std::fmt::Display for LongFile {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "{}: {} lines (over {LONG_FILE_LINES}): split it by responsibility or state why in a line `{LONG_FILE_MARK} <reason>`",
            self.file, self.lines
        )
    }
}

/// How a path was cited.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum CitationKind {
    /// `[text](target)` in markdown: relative to the citing file.
    Link,
    /// A path in running text, code or a comment.
    Mention,
}

/// One path-like token of a text and where it stands.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Citation {
    pub line: usize,
    pub target: String,
    pub kind: CitationKind,
}

/// Path-like tokens of `text`: markdown link targets (when `markdown`) and runs of path characters
/// that contain a `/` or end in `.md`. Patterns, web links and anchors are already left out;
/// whether a mention names a repository path is up to [`Tree`].
pub fn citations(text: &str, markdown: bool) -> Vec<Citation> {
    let mut out = Vec::new();
    for (index, line) in text.lines().enumerate() {
        let number = index + 1;
        if markdown {
            for target in link_targets(line) {
                out.push(Citation { line: number, target, kind: CitationKind::Link });
            }
        }
        for token in path_tokens(line) {
            if !out.iter().any(|c: &Citation| c.line == number && c.target == token) {
                out.push(Citation { line: number, target: token, kind: CitationKind::Mention });
            }
        }
    }
    out
}

/// Targets of `[text](target)` links on one line that name files.
fn link_targets(line: &str) -> Vec<String> {
    let mut out = Vec::new();
    let mut rest = line;
    while let Some(start) = rest.find("](") {
        rest = &rest[start + 2..];
        let Some(end) = rest.find(')') else { break };
        let raw = rest[..end].split_whitespace().next().unwrap_or("").trim_matches(['<', '>']);
        rest = &rest[end..];
        let is_web = raw.contains("://") || raw.starts_with("mailto:");
        let path = raw.split(['#', '?']).next().unwrap_or("");
        if is_web || path.is_empty() || raw.contains("::") || path.contains(PATTERN_CHARS) {
            continue;
        }
        out.push(path.to_string());
    }
    out
}

fn is_path_char(c: char) -> bool {
    c.is_ascii_alphanumeric() || matches!(c, '_' | '-' | '.' | '/') || PATTERN_CHARS.contains(&c)
}

/// Runs of path characters on one line that may name a repository path.
fn path_tokens(line: &str) -> Vec<String> {
    let mut out = Vec::new();
    let mut chars = line.char_indices().peekable();
    while let Some((start, c)) = chars.next() {
        if !is_path_char(c) {
            continue;
        }
        let mut end = start + c.len_utf8();
        while let Some(&(i, c)) = chars.peek() {
            if !is_path_char(c) {
                break;
            }
            end = i + c.len_utf8();
            chars.next();
        }
        // A usage line's optional argument, `[out.md]`, names no file of the repository.
        if line[..start].ends_with('[') && line[end..].starts_with(']') && !line[end..].starts_with("](") {
            continue;
        }
        // A sentence may end right after a path.
        let token = line[start..end].trim_end_matches('.');
        let slash = token.contains('/');
        let markdown_name = token.ends_with(".md") && token.len() > 3;
        if (!slash && !markdown_name) || token.contains(PATTERN_CHARS) || token.starts_with('/') {
            continue;
        }
        out.push(token.to_string());
    }
    out
}

/// Joins `base` and the relative `path` with `.` and `..` resolved; None when it leaves the root.
fn join(base: &str, path: &str) -> Option<String> {
    let mut parts: Vec<&str> = base.split('/').filter(|p| !p.is_empty()).collect();
    for part in path.split('/') {
        match part {
            "" | "." => {}
            ".." => {
                parts.pop()?;
            }
            p => parts.push(p),
        }
    }
    Some(parts.join("/"))
}

/// Extension of the last component of `path`, if it has one (`.ci/run` has none).
fn extension(path: &str) -> Option<&str> {
    let name = path.rsplit('/').next().unwrap_or(path);
    name.rfind('.').filter(|&i| i > 0).map(|i| &name[i + 1..]).filter(|e| !e.is_empty())
}

/// Folder of a root-relative file path ("" at the root).
fn folder(file: &str) -> &str {
    file.rfind('/').map_or("", |i| &file[..i])
}

/// The repository's files: tracked, or untracked and not ignored, and present on disk.
pub struct Tree {
    root: PathBuf,
    files: BTreeSet<String>,
    folders: BTreeSet<String>,
    /// Folders holding a Cargo.toml ("" for the root package).
    packages: Vec<String>,
    /// Extensions of the repository's files: a mention with another one is not of a repository file.
    extensions: BTreeSet<String>,
}

impl Tree {
    /// The files `git ls-files` lists under `root` (built outputs and other ignored files are not part of the tree).
    pub fn from_git(root: &Path) -> Result<Tree, String> {
        let output = Command::new("git")
            .args(["ls-files", "-z", "--cached", "--others", "--exclude-standard"])
            .current_dir(root)
            .output()
            .map_err(|e| format!("could not run git ls-files in {}: {e}", root.display()))?;
        if !output.status.success() {
            return Err(format!("git ls-files failed in {}: {}", root.display(), String::from_utf8_lossy(&output.stderr).trim()));
        }
        let listed = String::from_utf8_lossy(&output.stdout);
        let files = listed.split('\0').filter(|f| !f.is_empty() && root.join(f).is_file()).map(str::to_string);
        Ok(Tree::from_files(root, files))
    }

    /// A tree of the given root-relative files (which need not exist on disk unless scanned).
    pub fn from_files(root: &Path, files: impl IntoIterator<Item = String>) -> Tree {
        let files: BTreeSet<String> = files.into_iter().collect();
        let mut folders = BTreeSet::new();
        for f in &files {
            let mut dir = folder(f);
            while !dir.is_empty() && folders.insert(dir.to_string()) {
                dir = folder(dir);
            }
        }
        let packages = files.iter().filter(|f| *f == "Cargo.toml" || f.ends_with("/Cargo.toml")).map(|f| folder(f).to_string()).collect();
        let extensions = files.iter().filter_map(|f| extension(f)).map(str::to_string).collect();
        Tree { root: root.to_path_buf(), files, folders, packages, extensions }
    }

    fn exists(&self, path: &str) -> bool {
        path.is_empty() || self.files.contains(path) || self.folders.contains(path)
    }

    fn is_folder(&self, path: &str) -> bool {
        path.is_empty() || self.folders.contains(path)
    }

    /// The files scanned for citations.
    pub fn scanned(&self) -> impl Iterator<Item = &String> {
        self.files.iter().filter(|f| {
            SCANNED_FILES.contains(&f.as_str()) || Path::new(f).extension().and_then(|e| e.to_str()).is_some_and(|e| SCANNED_EXTENSIONS.contains(&e))
        })
    }

    /// Every dangling citation of every scanned file.
    pub fn dangling_references(&self) -> Vec<Dangling> {
        let mut out = Vec::new();
        for file in self.scanned() {
            match std::fs::read_to_string(self.root.join(file)) {
                Ok(text) => out.extend(self.dangling_in(file, &text)),
                Err(e) => out.push(Dangling { file: file.clone(), line: 0, target: format!("(unreadable: {e})") }),
            }
        }
        out
    }

    /// The dangling citations of `text`, the contents of the root-relative file `file`.
    pub fn dangling_in(&self, file: &str, text: &str) -> Vec<Dangling> {
        citations(text, file.ends_with(".md"))
            .into_iter()
            .filter(|c| self.resolves(file, c) == Some(false))
            .map(|c| Dangling { file: file.to_string(), line: c.line, target: c.target })
            .collect()
    }

    /// Some(true) when the citation names an existing path, Some(false) when it names a missing
    /// one, None when the token is not a citation of a repository path.
    fn resolves(&self, file: &str, citation: &Citation) -> Option<bool> {
        let here = folder(file);
        let target = citation.target.as_str();
        if citation.kind == CitationKind::Link || target.starts_with("../") {
            let found = match target.strip_prefix('/') {
                Some(from_root) => join("", from_root),
                None => join(here, target),
            };
            return Some(found.is_some_and(|p| self.exists(&p)));
        }
        let target = target.trim_start_matches("./");
        let markdown = target.ends_with(".md");
        if !markdown && extension(target).is_some_and(|e| !self.extensions.contains(e)) {
            return None;
        }
        let mut bases: Vec<&str> = vec![here, ""];
        bases.extend(self.packages.iter().map(String::as_str));
        if markdown {
            bases.push("docs");
        }
        let first = target.split('/').next().unwrap_or("");
        let names_a_folder = target.contains('/') && bases.iter().any(|b| join(b, first).is_some_and(|p| self.is_folder(&p)));
        if !names_a_folder && !markdown {
            return None;
        }
        Some(bases.iter().any(|b| join(b, target).is_some_and(|p| self.exists(&p))))
    }

    /// Files under `crates/` over [`LONG_FILE_LINES`] lines without a `// tidy: long file:` reason.
    pub fn long_files(&self) -> Vec<LongFile> {
        self.scanned()
            .filter(|f| f.starts_with("crates/"))
            .filter_map(|f| {
                let text = std::fs::read_to_string(self.root.join(f)).ok()?;
                let lines = text.lines().count();
                (lines > LONG_FILE_LINES && !states_long_file_reason(&text)).then(|| LongFile { file: f.clone(), lines })
            })
            .collect()
    }
}

/// True when some line is `// tidy: long file: <reason>` with a reason.
fn states_long_file_reason(text: &str) -> bool {
    text.lines().any(|l| l.trim_start().strip_prefix(LONG_FILE_MARK).is_some_and(|reason| !reason.trim().is_empty()))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Synthetic trees and texts with the citations each must report (a .txt file: the check does not scan it).
    const FIXTURE: &str = include_str!("tidy_fixture.txt");

    /// (citing file, text, expected "line:target" of each dangling citation) of every case in the fixture.
    fn cases() -> (Tree, Vec<(String, String, Vec<String>)>) {
        let mut files = Vec::new();
        let mut cases = Vec::new();
        for section in FIXTURE.split("\n=== ").skip(1) {
            let (header, body) = section.split_once('\n').unwrap_or((section, ""));
            if header == "tree" {
                files.extend(body.lines().filter(|l| !l.is_empty()).map(String::from));
            } else if let Some(file) = header.strip_prefix("text ") {
                let (text, expected) = body.split_once("--- dangling\n").expect("a case lists what it must report");
                cases.push((file.to_string(), text.to_string(), expected.lines().filter(|l| !l.is_empty()).map(String::from).collect()));
            }
        }
        (Tree::from_files(Path::new("/nowhere"), files), cases)
    }

    #[test]
    fn the_extractor_reports_exactly_the_dangling_citations_of_the_fixture() {
        let (tree, cases) = cases();
        assert!(cases.len() >= 3, "fixture not read: {} cases", cases.len());
        for (file, text, expected) in cases {
            let found: Vec<String> = tree.dangling_in(&file, &text).into_iter().map(|d| format!("{}:{}", d.line, d.target)).collect();
            assert_eq!(found, expected, "citations of the fixture text cited from {file}");
        }
    }

    #[test]
    fn a_long_file_needs_a_stated_reason() {
        assert!(!states_long_file_reason("fn a() {}\n// tidy: long file:\n"));
        assert!(states_long_file_reason("fn a() {}\n    // tidy: long file: one table of cases, read top to bottom\n"));
    }

    /// The tree as committed: every citation in a code, doc, scene or shader file names a file that exists.
    #[test]
    fn the_repository_has_no_dangling_references() {
        let tree = Tree::from_git(&repository_root()).expect("the tidy check lists the repository's files with git");
        assert!(tree.scanned().count() > 100, "too few files found: {}", tree.scanned().count());
        let dangling = tree.dangling_references();
        let listing: Vec<String> = dangling.iter().map(|d| d.to_string()).collect();
        assert!(dangling.is_empty(), "dangling references (cargo xtask tidy):\n{}", listing.join("\n"));
    }

    /// The tree as committed: every file under `crates/` over the limit states why.
    #[test]
    fn every_long_file_under_crates_states_why() {
        let tree = Tree::from_git(&repository_root()).expect("the tidy check lists the repository's files with git");
        let listing: Vec<String> = tree.long_files().iter().map(|l| l.to_string()).collect();
        assert!(listing.is_empty(), "long files (cargo xtask tidy):\n{}", listing.join("\n"));
    }
}
