//! Scene fuzzing: malformed and extreme scenes, made from the shipped and bad scenes by the
//! generator in tests/fuzz/, go through the parser, the compiler, the plan's memory estimate
//! and a few CPU steps, each case under a watchdog. No case may panic or hang, and every
//! refusal must be one bounded line naming a field or a line:column.
//!
//! `TUMBLE_FUZZ_CASES` (default 10,000), `TUMBLE_FUZZ_SEED` (default below) and
//! `TUMBLE_FUZZ_THREADS` choose the run; `TUMBLE_FUZZ_CASE=k` runs case k alone and prints it.

mod fuzz;

use std::collections::BTreeMap;
use std::panic::{AssertUnwindSafe, catch_unwind};
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicU64, AtomicUsize, Ordering};
use std::sync::{Arc, mpsc};
use std::time::{Duration, Instant};
use tumble::{CompiledScene, SceneError, Simulation};
use tumble_scene::schema::BackendName;

const DEFAULT_SEED: u64 = 0x7475_6d62_6c65; // "tumble"
const DEFAULT_CASES: u64 = 10_000;

/// A case that runs longer than this is a hang.
const WATCHDOG: Duration = Duration::from_secs(20);

/// The longest refusal a terminal line should carry (file name not counted): a field path and
/// a message, each capped by `SceneError`'s display, and a line and column.
const MAX_MESSAGE_CHARS: usize = 450;

/// Compiled cases with at most this many particles (polyhedra) take a few CPU steps: a
/// mutated size can put every pair in contact, and n² contacts in a debug build take long.
const MAX_STEPPED_PARTICLES: usize = 500;
const MAX_STEPPED_POLYHEDRA: usize = 100;
const STEPS: u64 = 3;

/// Scenes that validly ask for more particles than this are not compiled: a debug build places
/// a million in seconds (minutes where they fill a quarter of their region), and such a scene is
/// big rather than malformed. Those that ask for more than memory holds or ids allow are
/// compiled, to see them refused.
const MAX_COMPILED_PARTICLES: f64 = 2e5;

fn env_u64(name: &str) -> Option<u64> {
    let v = std::env::var(name).ok()?;
    let v = v.trim();
    Some(v.strip_prefix("0x").map_or_else(|| v.parse(), |h| u64::from_str_radix(h, 16)).unwrap_or_else(|_| panic!("{name}={v} is not a number")))
}

/// What a case came to: an outcome class, or the problem that fails the test.
type Verdict = Result<String, String>;

/// One refusal is one line, bounded, free of control characters, naming a field path or a
/// line:column.
fn check_refusal(e: &SceneError, text: &str) -> Result<(), String> {
    let shown = e.to_string();
    let message = match &e.file {
        Some(f) => shown.strip_prefix(&f.display().to_string()).unwrap_or(&shown).to_string(),
        None => shown.clone(),
    };
    if shown.contains('\n') || shown.contains('\r') {
        return Err(format!("message spans lines: {shown:?}"));
    }
    if let Some(c) = shown.chars().find(|c| c.is_control()) {
        return Err(format!("message carries control character {c:?}: {shown:?}"));
    }
    if message.chars().count() > MAX_MESSAGE_CHARS {
        return Err(format!("message is {} characters (at most {MAX_MESSAGE_CHARS}): {shown:?}", message.chars().count()));
    }
    if e.message.trim().is_empty() {
        return Err(format!("empty message: {shown:?}"));
    }
    match (&e.field, e.line_col) {
        (None, None) => return Err(format!("names neither a field nor a line: {shown:?}")),
        (Some(f), _) if f.is_empty() || !f.chars().all(|c| c.is_ascii_alphanumeric() || "_-.[]".contains(c)) => {
            return Err(format!("field {f:?} is not a field path: {shown:?}"));
        }
        _ => {}
    }
    if let Some((line, col)) = e.line_col
        && (line == 0 || col == 0 || line > text.lines().count() + 1)
    {
        return Err(format!("line {line}, column {col} is not in the {}-line text: {shown:?}", text.lines().count()));
    }
    Ok(())
}

/// The class of a parse refusal: a TOML syntax error, or which part of the schema it breaks.
fn parse_class(text: &str, e: &SceneError) -> String {
    if text.parse::<toml::Table>().is_err() {
        return "refused: TOML syntax".into();
    }
    let m = &e.message;
    let kind = if m.contains("unknown field") {
        "unknown field"
    } else if m.contains("missing field") {
        "missing field"
    } else if m.contains("unknown variant") {
        "unknown variant"
    } else if m.contains("invalid type") || m.contains("did not match any variant") || m.contains("invalid value") || m.contains("invalid length") {
        "wrong type or length"
    } else {
        "other schema"
    };
    format!("refused: {kind}")
}

/// The class of a compile refusal: a limit (counts, memory, steps, capacities) or a value.
fn compile_class(e: &SceneError) -> String {
    let m = &e.message;
    let section = e.field.as_deref().unwrap_or("?").split(['.', '[']).next().unwrap_or("?").to_string();
    let limit = section != "name" && ["at most", "GiB", "32-bit", "steps, more than", "jams", "placed only"].iter().any(|k| m.contains(k));
    format!("refused: {} ({section})", if limit { "limit" } else { "value" })
}

/// The plan's GPU estimate, as `tumble plan` prints it: no device is touched.
fn gpu_plan_estimate(c: &CompiledScene) -> u64 {
    let n = c.particles.len();
    let grid = tumble_gpu::Grid::new(&c.plan, n);
    let slots = if c.plan.model.history { c.plan.tuning.history_slots } else { 0 };
    let text = c.plan.describe(n);
    assert!(!text.is_empty());
    tumble_gpu::memory_bytes(n as u64, &grid, slots)
        + n as u64 * tumble_gpu::wall_bytes_per_particle(&c.plan)
        + tumble_gpu::bytes_per_particle(&c.plan)
}

/// How many particles a scene's groups ask for (the compiler's own count, before it places any).
fn requested_particles(scene: &tumble::Scene) -> f64 {
    let group = |g: &tumble_scene::schema::ParticleGroup| {
        if let Some(list) = &g.positions {
            list.len() as f64
        } else if let Some(l) = &g.lattice {
            (0..3).map(|k| ((l.max[k] - l.min[k]) / l.spacing + 1e-9).floor().max(0.0)).product::<f64>()
        } else {
            g.random.as_ref().map_or(0.0, |r| r.count as f64)
        }
    };
    let fluid = scene.sph.as_ref().map_or(0.0, |s| {
        // The SPH fluid's regions on their lattice (in 2D, x and z).
        let axes: &[usize] = if s.dimension == 2 { &[0, 2] } else { &[0, 1, 2] };
        let region =
            |b: &tumble_scene::schema::SphBoxSection| axes.iter().map(|&k| ((b.max[k] - b.min[k]) / s.spacing).floor().max(0.0)).product::<f64>();
        s.regions.iter().filter_map(|r| r.box_.as_ref()).map(region).filter(|n| n.is_finite()).sum::<f64>()
    });
    scene.particles.iter().map(group).filter(|n| n.is_finite()).sum::<f64>() + fluid
}

/// Linux's MemAvailable in bytes (0 where unknown, so every scene is compiled).
fn available_memory() -> f64 {
    let info = std::fs::read_to_string("/proc/meminfo").unwrap_or_default();
    let kib = info.lines().find(|l| l.starts_with("MemAvailable:")).and_then(|l| l.split_whitespace().nth(1)?.parse::<f64>().ok());
    kib.map_or(0.0, |k| k * 1024.0)
}

fn run_case(bytes: &[u8], scratch: &Path) -> Verdict {
    let text = match std::str::from_utf8(bytes) {
        Ok(t) => t,
        Err(_) => {
            // Not UTF-8: only a file can hold it, so it goes the way the command line reads it.
            std::fs::write(scratch, bytes).unwrap();
            return match tumble::read_scene(scratch) {
                Ok(_) => Err("text that is not UTF-8 was accepted".into()),
                Err(e) => check_refusal(&e, &String::from_utf8_lossy(bytes)).map(|_| "refused: not UTF-8".into()),
            };
        }
    };
    let scene = match tumble::parse_scene(text) {
        Ok(s) => s,
        Err(e) => return check_refusal(&e, text).map(|_| parse_class(text, &e)),
    };
    let asked = requested_particles(&scene);
    if asked > MAX_COMPILED_PARTICLES && asked <= u32::MAX as f64 && asked * 512.0 <= available_memory() {
        // A big scene the compiler would place particle by particle: slow, not malformed.
        return Ok("not compiled: asks for over 200,000 particles".into());
    }
    let compiled = match tumble::compile(&scene) {
        Ok(c) => c,
        Err(e) => return check_refusal(&e, text).map(|_| compile_class(&e)),
    };
    gpu_plan_estimate(&compiled);
    let n = compiled.particles.len() + compiled.fluid.as_ref().map_or(0, |f| f.len());
    if n > if compiled.plan.model.polyhedra { MAX_STEPPED_POLYHEDRA } else { MAX_STEPPED_PARTICLES } {
        return Ok("compiled (too many particles to step)".into());
    }
    let steps = compiled.plan.run.steps.min(STEPS);
    let mut sim = Simulation::on(BackendName::Cpu, compiled, 1).map_err(|e| format!("the CPU backend refused a compiled scene: {e}"))?;
    sim.advance(steps);
    let observables = sim.observables();
    let _ = observables.kinetic_energy;
    Ok(match sim.fault() {
        Some(_) => "compiled, stepped, stopped by a fault".into(),
        None => "compiled and stepped".into(),
    })
}

thread_local! {
    static LAST_PANIC: std::cell::RefCell<Option<String>> = const { std::cell::RefCell::new(None) };
}

/// Fuzz workers keep their panic's message and place for the report instead of printing it.
fn install_panic_hook() {
    let default = std::panic::take_hook();
    std::panic::set_hook(Box::new(move |info| {
        if std::thread::current().name().is_some_and(|n| n.starts_with("fuzz-")) {
            let message = info
                .payload()
                .downcast_ref::<&str>()
                .map(|s| s.to_string())
                .or_else(|| info.payload().downcast_ref::<String>().cloned())
                .unwrap_or_else(|| "(non-text panic)".into());
            let place = info.location().map_or(String::new(), |l| format!(" at {}:{}", l.file(), l.line()));
            LAST_PANIC.with(|p| *p.borrow_mut() = Some(format!("panicked{place}: {message}")));
        } else {
            default(info);
        }
    }));
}

struct Worker {
    /// The case it is on (u64::MAX between cases) and when it began, ms after the start.
    case: AtomicU64,
    since_ms: AtomicU64,
}

struct Finding {
    index: u64,
    problem: String,
}

fn report_case(corpus: &[fuzz::Seed], seed: u64, index: u64) -> String {
    let case = fuzz::case(corpus, seed, index);
    let text = String::from_utf8_lossy(&case.bytes);
    let shown: String = text.chars().take(16_000).collect();
    format!(
        "case {index} of seed {seed:#x} (rerun: TUMBLE_FUZZ_SEED={seed:#x} TUMBLE_FUZZ_CASE={index} cargo test --test fuzz_scenes -- --nocapture)\n\
         from {}, mutations: {}\n--- scene ---\n{shown}\n--- end ---",
        case.base.display(),
        case.steps.join("; ")
    )
}

#[test]
fn malformed_and_extreme_scenes_are_refused_on_one_line_or_run() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let corpus = Arc::new(fuzz::corpus(root));
    assert!(corpus.len() >= 100, "corpus of {} scenes", corpus.len());
    let seed = env_u64("TUMBLE_FUZZ_SEED").unwrap_or(DEFAULT_SEED);
    let only = env_u64("TUMBLE_FUZZ_CASE");
    let (first, cases) = match only {
        Some(k) => (k, 1),
        None => (0, env_u64("TUMBLE_FUZZ_CASES").unwrap_or(DEFAULT_CASES)),
    };
    if let Some(k) = only {
        println!("{}", report_case(&corpus, seed, k));
    }
    let threads = env_u64("TUMBLE_FUZZ_THREADS").map_or_else(|| std::thread::available_parallelism().map_or(2, |n| n.get()).min(4), |t| t as usize);
    install_panic_hook();
    let scratch = std::env::temp_dir().join(format!("tumble-fuzz-{}", std::process::id()));
    std::fs::create_dir_all(&scratch).unwrap();

    let start = Instant::now();
    let next = Arc::new(AtomicUsize::new(0));
    let workers: Arc<Vec<Worker>> = Arc::new((0..threads).map(|_| Worker { case: AtomicU64::new(u64::MAX), since_ms: AtomicU64::new(0) }).collect());
    let (send, results) = mpsc::channel::<(u64, Verdict, Duration)>();
    for w in 0..threads {
        let (corpus, next, workers, send) = (corpus.clone(), next.clone(), workers.clone(), send.clone());
        let file: PathBuf = scratch.join(format!("w{w}.toml"));
        std::thread::Builder::new()
            .name(format!("fuzz-{w}"))
            .spawn(move || {
                loop {
                    let k = next.fetch_add(1, Ordering::Relaxed) as u64;
                    if k >= cases {
                        break;
                    }
                    let index = first + k;
                    workers[w].since_ms.store(start.elapsed().as_millis() as u64, Ordering::Relaxed);
                    workers[w].case.store(index, Ordering::Relaxed);
                    let began = Instant::now();
                    let case = fuzz::case(&corpus, seed, index);
                    let verdict = catch_unwind(AssertUnwindSafe(|| run_case(&case.bytes, &file)))
                        .unwrap_or_else(|_| Err(LAST_PANIC.with(|p| p.borrow_mut().take()).unwrap_or_else(|| "panicked".into())));
                    workers[w].case.store(u64::MAX, Ordering::Relaxed);
                    if send.send((index, verdict, began.elapsed())).is_err() {
                        break;
                    }
                }
            })
            .unwrap();
    }
    drop(send);

    let mut classes: BTreeMap<String, u64> = BTreeMap::new();
    let mut findings: Vec<Finding> = Vec::new();
    let mut slowest = (Duration::ZERO, 0u64);
    let mut done = 0u64;
    while done < cases {
        match results.recv_timeout(Duration::from_millis(250)) {
            Ok((index, verdict, took)) => {
                done += 1;
                if took > slowest.0 {
                    slowest = (took, index);
                }
                match verdict {
                    Ok(class) => *classes.entry(class).or_default() += 1,
                    Err(problem) => {
                        *classes.entry("FAILED".into()).or_default() += 1;
                        findings.push(Finding { index, problem });
                    }
                }
            }
            Err(mpsc::RecvTimeoutError::Disconnected) => panic!("fuzz workers stopped after {done} of {cases} cases"),
            Err(mpsc::RecvTimeoutError::Timeout) => {}
        }
        let now = start.elapsed().as_millis() as u64;
        for w in workers.iter() {
            let index = w.case.load(Ordering::Relaxed);
            let since = w.since_ms.load(Ordering::Relaxed);
            if index != u64::MAX && now.saturating_sub(since) > WATCHDOG.as_millis() as u64 {
                panic!("HANG: no progress for {} s\n{}", WATCHDOG.as_secs(), report_case(&corpus, seed, index));
            }
        }
    }
    let _ = std::fs::remove_dir_all(&scratch);

    let elapsed = start.elapsed();
    println!("fuzz: {done} cases of seed {seed:#x} from {} scenes in {:.1} s on {threads} threads", corpus.len(), elapsed.as_secs_f64());
    println!("fuzz: slowest case {} took {:.2} s", slowest.1, slowest.0.as_secs_f64());
    for (class, n) in &classes {
        println!("  {n:>6}  {class}");
    }
    findings.sort_by_key(|f| f.index);
    for f in findings.iter().take(8) {
        // A single case was printed before it ran.
        let case = if only.is_some() { String::new() } else { report_case(&corpus, seed, f.index) };
        println!("\nFINDING: {}\n{case}", f.problem);
    }
    if findings.len() > 8 {
        for f in &findings[8..] {
            println!("FINDING case {}: {}", f.index, f.problem);
        }
    }
    assert!(findings.is_empty(), "{} of {done} cases failed (see FINDING above)", findings.len());
}

/// Regression (fuzz seed 2): spheres of 2e-308 m in a 1 m box ask for 2^63 search cells, and
/// the plan's memory estimate overflowed multiplying them.
#[test]
fn the_memory_estimate_of_vanishing_spheres_in_a_large_box_is_finite() {
    let text = std::fs::read_to_string(Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/test/sparse_lattice.toml")).unwrap();
    let text = text.replace("diameter = 0.004", "diameter = 2.2250738585072014e-308");
    let compiled = tumble::compile(&tumble::parse_scene(&text).unwrap()).unwrap();
    let n = compiled.particles.len();
    assert_eq!(n, 52 * 52 * 52);
    let cells_bytes = compiled.plan.memory_bytes(n) - n * compiled.plan.tuning.bytes_per_particle;
    assert_eq!(cells_bytes, ((1 << 26) + 1) * 4, "the CPU grid's 2^26 cells of 4 bytes");
    assert!(gpu_plan_estimate(&compiled) > 0);
}
