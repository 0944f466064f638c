//! Checkpoints: a whole run frozen between two steps, in `checkpoints/` of its output folder,
//! for `tumble resume` and for seeding other runs (docs/cli.md, "Checkpoints and resume").
//!
//! A checkpoint holds the backend's [`Snapshot`](tumble_state::Snapshot) (bytes), the run loop's
//! books (monitor, wall-power and flow baselines, how long each output file was) and the scene
//! text with the command's overrides, so a resumed run needs nothing but the folder. Files are
//! written to a temporary name, synced and renamed: a run killed at any moment leaves complete
//! checkpoints only.

use serde::{Deserialize, Serialize};
use std::io::{BufWriter, Seek, SeekFrom, Write};
use std::path::{Path, PathBuf};
use tumble_state::Snapshot;

/// The layout of a checkpoint file; a reader refuses any other. 2: the scene's input files.
pub const CHECKPOINT_VERSION: u32 = 2;

/// The first bytes of a checkpoint file.
const MAGIC: &[u8; 8] = b"TUMBLECK";

/// Magic, layout version, CRC-32 of the body, body length.
const HEADER_BYTES: usize = 8 + 4 + 4 + 8;

/// The folder of checkpoints inside a run's output folder.
pub const FOLDER: &str = "checkpoints";

/// The scene a run was started with: what `tumble resume` compiles again.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct SceneRecord {
    /// The scene file as the command named it (for messages; the text below is what counts).
    pub path: PathBuf,
    pub text: String,
    /// `--duration` and `--dt` of the command that started the run.
    pub duration: Option<f64>,
    pub dt: Option<f64>,
    /// `--checkpoint-interval` of the command that started or last resumed the run.
    pub checkpoint_interval: Option<f64>,
    /// The other files the scene reads (meshes), with the CRC-32 of their bytes then: a
    /// resumed run must see the same geometry.
    pub inputs: Vec<(PathBuf, u32)>,
}

impl SceneRecord {
    /// The first input file that is missing or changed since the record was made, with why.
    pub fn changed_input(&self) -> Option<String> {
        self.inputs.iter().find_map(|(path, crc)| match std::fs::read(path) {
            Err(e) => Some(format!("{}: {e}", path.display())),
            Ok(bytes) if crc32fast::hash(&bytes) != *crc => Some(format!("{}: the file changed", path.display())),
            Ok(_) => None,
        })
    }
}

/// The files besides itself that a scene (its text, read from `path`) reads: its mesh walls',
/// mesh sources' and fluid mesh regions' files, with the CRC-32 of their bytes; files that
/// cannot be read are left to the compiler.
pub fn scene_inputs(text: &str, path: &Path) -> Vec<(PathBuf, u32)> {
    let Ok(scene) = tumble_scene::parse_scene(text) else { return Vec::new() };
    let folder = path.parent().unwrap_or(Path::new(""));
    let sources = scene.sources.iter().filter_map(|s| match &s.region {
        tumble_scene::schema::SourceRegion::Mesh(m) => Some(m),
        _ => None,
    });
    let fluid = scene.sph.iter().flat_map(|f| f.regions.iter().filter_map(|r| r.mesh.as_ref()));
    scene
        .walls
        .iter()
        .filter_map(|w| w.mesh.as_ref())
        .chain(sources)
        .chain(fluid)
        .filter_map(|m| {
            let file = std::fs::canonicalize(folder.join(&m.file)).ok()?;
            let bytes = std::fs::read(&file).ok()?;
            Some((file, crc32fast::hash(&bytes)))
        })
        .collect()
}

/// A checkpoint's record of the run: everything but the backend's snapshot.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct CheckpointHeader {
    /// The tumble release that wrote it (a different one may continue, not bit-identically).
    pub tumble_version: String,
    /// The scene, when the run was started from a file (a library run may have none).
    pub scene: Option<SceneRecord>,
    /// `cpu` or `gpu`.
    pub backend: String,
    pub step: u64,
    pub time: f64,
    /// The run loop's books, encoded by the run loop.
    pub books: Vec<u8>,
}

/// One checkpoint file's content.
#[derive(Clone, Debug)]
pub struct Checkpoint {
    pub header: CheckpointHeader,
    pub snapshot: Snapshot,
}

/// Counts and checksums what passes through to `inner`.
struct Hashing<W> {
    inner: W,
    crc: crc32fast::Hasher,
    len: u64,
}

impl<W: Write> Write for Hashing<W> {
    fn write(&mut self, buf: &[u8]) -> std::io::Result<usize> {
        let n = self.inner.write(buf)?;
        self.crc.update(&buf[..n]);
        self.len += n as u64;
        Ok(n)
    }

    fn flush(&mut self) -> std::io::Result<()> {
        self.inner.flush()
    }
}

impl Checkpoint {
    /// Writes the file's bytes into `w`: the header (magic, layout version, CRC-32 and length of
    /// the body) and the body (the postcard record, then the snapshot's own encoding), streamed
    /// so that no copy of a large state is made in memory.
    pub fn write_to<W: Write + Seek>(&self, w: W) -> std::io::Result<W> {
        write_parts(&self.header, |body| self.snapshot.write_to(body).map(|_| ()), w)
    }

    /// The file's bytes in memory.
    pub fn to_bytes(&self) -> Vec<u8> {
        self.write_to(std::io::Cursor::new(Vec::new())).expect("a checkpoint always encodes into memory").into_inner()
    }

    /// Decodes what [`Checkpoint::to_bytes`] wrote; a damaged, cut or foreign file says why.
    pub fn from_bytes(bytes: &[u8]) -> Result<Checkpoint, String> {
        if bytes.len() < HEADER_BYTES || &bytes[..8] != MAGIC {
            return Err("not a tumble checkpoint (no TUMBLECK header)".into());
        }
        let version = u32::from_le_bytes(bytes[8..12].try_into().unwrap());
        if version != CHECKPOINT_VERSION {
            return Err(format!(
                "checkpoint layout version {version}, but this tumble reads version {CHECKPOINT_VERSION}; resume with the tumble that wrote it"
            ));
        }
        let crc = u32::from_le_bytes(bytes[12..16].try_into().unwrap());
        let len = u64::from_le_bytes(bytes[16..24].try_into().unwrap());
        let body = &bytes[HEADER_BYTES..];
        if body.len() as u64 != len {
            return Err(format!("the file is cut or extended: its header gives {len} body bytes, the file has {}", body.len()));
        }
        if crc32fast::hash(body) != crc {
            return Err("the file is damaged: its checksum does not match its content".into());
        }
        let (header, rest) = postcard::take_from_bytes::<CheckpointHeader>(body).map_err(|e| format!("the record cannot be decoded: {e}"))?;
        let snapshot = Snapshot::from_bytes(rest).map_err(|e| e.to_string())?;
        Ok(Checkpoint { header, snapshot })
    }
}

/// Writes a checkpoint file's bytes into `w`: the header (magic, layout version, CRC-32 and
/// length of the body), then the body, `header`'s record followed by what `snapshot` streams (a
/// snapshot's encoding), through one buffer so that no copy of a large state is made in memory.
pub fn write_parts<W: Write + Seek>(
    header: &CheckpointHeader,
    snapshot: impl FnOnce(&mut dyn Write) -> std::io::Result<()>,
    mut w: W,
) -> std::io::Result<W> {
    let start = w.stream_position()?;
    w.write_all(&[0; HEADER_BYTES])?;
    let mut body = Hashing { inner: BufWriter::with_capacity(1 << 20, w), crc: crc32fast::Hasher::new(), len: 0 };
    postcard::to_io(header, &mut body).map_err(std::io::Error::other)?;
    snapshot(&mut body)?;
    body.flush()?;
    let (crc, len) = (body.crc.finalize(), body.len);
    let mut w = body.inner.into_inner().map_err(|e| e.into_error())?;
    w.seek(SeekFrom::Start(start))?;
    w.write_all(MAGIC)?;
    w.write_all(&CHECKPOINT_VERSION.to_le_bytes())?;
    w.write_all(&crc.to_le_bytes())?;
    w.write_all(&len.to_le_bytes())?;
    w.seek(SeekFrom::End(0))?;
    Ok(w)
}

/// Counts the bytes written through it.
struct Counting(u64);

impl Write for Counting {
    fn write(&mut self, buf: &[u8]) -> std::io::Result<usize> {
        self.0 += buf.len() as u64;
        Ok(buf.len())
    }

    fn flush(&mut self) -> std::io::Result<()> {
        Ok(())
    }
}

/// Bytes one spring in use adds to a checkpoint: its key and the spring (tangential and rolling,
/// with their energies).
pub const BYTES_PER_SPRING: u64 = 4 + 64;

/// The size of a checkpoint of `compiled` at its start, bytes, without contact springs (each
/// adds [`BYTES_PER_SPRING`]): the particle arrays, the neighbour list's reference positions and
/// the last contact pass's sums.
pub fn estimated_bytes(compiled: &tumble_scene::CompiledScene) -> u64 {
    let state = tumble_state::State::from_scene(compiled);
    let n = state.len() as u64;
    let mut count = Counting(0);
    postcard::to_io(&state, &mut count).expect("counting never fails");
    let mut sum = Counting(0);
    postcard::to_io(&tumble_state::ContactSum::default(), &mut sum).expect("counting never fails");
    count.0 + n * (24 + sum.0) + 1024
}

/// The file name of the checkpoint at `step`: names sort in step order.
fn file_name(step: u64) -> String {
    format!("step_{step:012}.ckpt")
}

/// The step of a checkpoint file name, if it is one.
fn step_of(name: &str) -> Option<u64> {
    name.strip_prefix("step_")?.strip_suffix(".ckpt")?.parse().ok()
}

/// The checkpoints in `out_dir`, oldest first (temporary files of an interrupted write are not among them).
pub fn list(out_dir: &Path) -> std::io::Result<Vec<(u64, PathBuf)>> {
    let dir = out_dir.join(FOLDER);
    let mut found = Vec::new();
    match std::fs::read_dir(&dir) {
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => return Ok(found),
        Err(e) => return Err(e),
        Ok(entries) => {
            for e in entries {
                let e = e?;
                if let Some(step) = e.file_name().to_str().and_then(step_of) {
                    found.push((step, e.path()));
                }
            }
        }
    }
    found.sort();
    Ok(found)
}

/// Writes a checkpoint of `header` and the snapshot `snapshot` streams atomically (temporary file, fsync, rename, fsync of the folder) and
/// keeps the newest `keep`; returns its path and size in bytes.
pub fn write(
    out_dir: &Path,
    header: &CheckpointHeader,
    snapshot: impl FnOnce(&mut dyn Write) -> std::io::Result<()>,
    keep: usize,
) -> std::io::Result<(PathBuf, u64)> {
    let dir = out_dir.join(FOLDER);
    std::fs::create_dir_all(&dir)?;
    let path = dir.join(file_name(header.step));
    let tmp = dir.join(format!(".{}.tmp", file_name(header.step)));
    let f = write_parts(header, snapshot, std::fs::File::create(&tmp)?)?;
    f.sync_all()?;
    let bytes = f.metadata()?.len();
    drop(f);
    std::fs::rename(&tmp, &path)?;
    // The rename itself is durable only once the folder is synced.
    std::fs::File::open(&dir)?.sync_all()?;
    let all = list(out_dir)?;
    for (_, old) in &all[..all.len().saturating_sub(keep.max(1))] {
        std::fs::remove_file(old)?;
    }
    Ok((path, bytes))
}

/// Removes the temporary files of checkpoint writes that a killed run left unfinished.
pub fn remove_unfinished(out_dir: &Path) -> std::io::Result<()> {
    let Ok(entries) = std::fs::read_dir(out_dir.join(FOLDER)) else { return Ok(()) };
    for e in entries {
        let e = e?;
        if e.file_name().to_str().is_some_and(|n| n.starts_with('.') && n.ends_with(".ckpt.tmp")) {
            std::fs::remove_file(e.path())?;
        }
    }
    Ok(())
}

/// Reads one checkpoint file; the message names the file.
pub fn read(path: &Path) -> Result<Checkpoint, String> {
    let bytes = std::fs::read(path).map_err(|e| format!("{}: cannot read the checkpoint: {e}", path.display()))?;
    Checkpoint::from_bytes(&bytes).map_err(|e| format!("{}: {e}", path.display()))
}

/// The newest checkpoint of the run in `out_dir`.
pub fn newest(out_dir: &Path) -> Result<(PathBuf, Checkpoint), String> {
    let all = list(out_dir).map_err(|e| format!("{}: cannot read the checkpoints: {e}", out_dir.join(FOLDER).display()))?;
    let Some((_, path)) = all.last() else {
        return Err(format!(
            "{}: no checkpoint to resume from (the run had no run.checkpoint_interval or --checkpoint-interval, or stopped before its first checkpoint)",
            out_dir.display()
        ));
    };
    match read(path) {
        Ok(c) => Ok((path.clone(), c)),
        Err(e) if all.len() > 1 => Err(format!("{e}; remove it to resume from the one before ({})", all[all.len() - 2].1.display())),
        Err(e) => Err(e),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A resumed run checks every mesh its scene reads: a wall's, a source region's and a fluid
    /// region's.
    #[test]
    fn the_record_holds_every_mesh_the_scene_reads() {
        let dir = std::env::temp_dir().join(format!("tumble-inputs-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        for name in ["wall", "source", "fluid"] {
            std::fs::write(dir.join(format!("{name}.obj")), format!("# {name}\nv 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n")).unwrap();
        }
        let text = r#"
name = "inputs"
[run]
duration = 0.1
[domain]
min = [0.0, 0.0, 0.0]
max = [1.0, 1.0, 1.0]
[[materials]]
name = "m"
density = 1000.0
[contact]
normal = { model = "linear", stiffness = 1000.0 }
restitution = 0.5
[[walls]]
mesh = { file = "wall.obj" }
[[sources]]
material = "m"
shape = { sphere = { diameter = 0.01 } }
region = { mesh = { file = "source.obj" } }
total = { particles = 1 }
[sph]
spacing = 0.01
density = 1000.0
viscosity = 1.0e-3
expected_speed = 1.0
[[sph.regions]]
mesh = { file = "fluid.obj" }
"#;
        let inputs = scene_inputs(text, &dir.join("scene.toml"));
        let names: Vec<String> = inputs.iter().map(|(p, _)| p.file_name().unwrap().to_string_lossy().into_owned()).collect();
        std::fs::remove_dir_all(&dir).unwrap();
        assert_eq!(names, ["wall.obj", "source.obj", "fluid.obj"]);
    }

    fn sample(step: u64) -> Checkpoint {
        let scene = crate::compile(&crate::parse_scene(SCENE).unwrap()).unwrap();
        let mut sim = crate::Simulation::new(scene, 1);
        sim.advance(step % 7);
        Checkpoint {
            header: CheckpointHeader {
                tumble_version: "0.1.0".into(),
                scene: Some(SceneRecord {
                    path: "a.toml".into(),
                    text: SCENE.into(),
                    duration: Some(1.0),
                    dt: None,
                    checkpoint_interval: None,
                    inputs: vec![("cone.stl".into(), 7)],
                }),
                backend: "cpu".into(),
                step,
                time: step as f64 * 1e-5,
                books: vec![1, 2, 3],
            },
            snapshot: sim.snapshot(),
        }
    }

    const SCENE: &str = "name = \"pair\"\n[run]\nduration = 0.01\ndt = 1e-4\n[domain]\nmin = [-1.0, -1.0, -1.0]\nmax = [1.0, 1.0, 1.0]\n\
        [[materials]]\nname = \"m\"\ndensity = 1000.0\n[contact]\nnormal = { model = \"linear\", stiffness = 1000.0 }\nrestitution = 0.5\n\
        [[particles]]\nmaterial = \"m\"\nshape = { sphere = { diameter = 0.1 } }\npositions = [[0.0, 0.0, 0.0], [0.2, 0.0, 0.0]]\nvelocity = [1.0, 0.0, 0.0]\n";

    fn fresh(tag: &str) -> PathBuf {
        let d = std::env::temp_dir().join(format!("tumble-checkpoint-{tag}-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&d);
        std::fs::create_dir_all(&d).unwrap();
        d
    }

    #[test]
    fn a_checkpoint_reads_back_as_written() {
        let c = sample(42);
        let back = Checkpoint::from_bytes(&c.to_bytes()).unwrap();
        assert_eq!(back.to_bytes(), c.to_bytes());
        assert_eq!(back.header.scene, c.header.scene);
        assert_eq!(back.snapshot, c.snapshot);
    }

    #[test]
    fn a_backend_streams_the_bytes_of_its_snapshot() {
        let scene = crate::compile(&crate::parse_scene(SCENE).unwrap()).unwrap();
        let mut sim = crate::Simulation::new(scene, 1);
        sim.advance(5);
        let mut streamed = Vec::new();
        sim.backend().write_snapshot(&mut streamed).unwrap();
        assert!(streamed == sim.snapshot().to_bytes(), "the borrowed snapshot encodes differently");
    }

    #[test]
    fn every_damaged_byte_and_every_cut_is_refused() {
        let bytes = sample(7).to_bytes();
        for k in 0..bytes.len() {
            let mut bad = bytes.clone();
            bad[k] ^= 0x10;
            assert!(Checkpoint::from_bytes(&bad).is_err(), "a flipped bit at byte {k} was accepted");
        }
        for n in 0..bytes.len() {
            assert!(Checkpoint::from_bytes(&bytes[..n]).is_err(), "a file cut to {n} bytes was accepted");
        }
        let e = Checkpoint::from_bytes(&bytes[..bytes.len() - 1]).unwrap_err();
        assert!(e.contains("cut"), "{e}");
    }

    #[test]
    fn only_the_newest_are_kept_and_no_temporary_file_is_left() {
        let d = fresh("keep");
        for step in [0, 100, 200, 300, 400] {
            let c = sample(step);
            write(&d, &c.header, |w| c.snapshot.write_to(w).map(|_| ()), 3).unwrap();
        }
        let steps: Vec<u64> = list(&d).unwrap().into_iter().map(|(s, _)| s).collect();
        assert_eq!(steps, vec![200, 300, 400]);
        let names: Vec<String> = std::fs::read_dir(d.join(FOLDER)).unwrap().map(|e| e.unwrap().file_name().into_string().unwrap()).collect();
        assert!(names.iter().all(|n| !n.ends_with(".tmp")), "{names:?}");
        assert_eq!(newest(&d).unwrap().1.header.step, 400);
    }

    #[test]
    fn a_damaged_newest_checkpoint_is_named_with_the_one_before() {
        let d = fresh("damaged");
        let (a, b) = (sample(100), sample(200));
        write(&d, &a.header, |w| a.snapshot.write_to(w).map(|_| ()), 3).unwrap();
        let (path, _) = write(&d, &b.header, |w| b.snapshot.write_to(w).map(|_| ()), 3).unwrap();
        let mut bytes = std::fs::read(&path).unwrap();
        let n = bytes.len();
        bytes[n - 3] ^= 1;
        std::fs::write(&path, bytes).unwrap();
        let e = newest(&d).unwrap_err();
        assert!(e.contains("step_000000000200.ckpt") && e.contains("damaged") && e.contains("step_000000000100.ckpt") && !e.contains('\n'), "{e}");
        let e = newest(&fresh("none")).unwrap_err();
        assert!(e.contains("no checkpoint"), "{e}");
    }
}
