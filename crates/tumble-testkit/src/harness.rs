//! A test harness (libtest-mimic) on which a GPU test is ignored at run time when there is
//! no adapter, rather than passing: `harness = false` test binaries end `main` in [`run`].
//!
//! Without an adapter every GPU trial is reported as ignored, with one line saying why,
//! unless `TUMBLE_REQUIRE_GPU=1`, under which they fail (CI sets it once it has installed
//! a software adapter). CPU trials run as usual beside them.

use libtest_mimic::{Arguments, Completion, Failed, Trial};
use std::sync::Mutex;
use std::time::Instant;

/// The variable that turns a missing adapter from "ignored" into a failure.
pub const REQUIRE_GPU: &str = "TUMBLE_REQUIRE_GPU";

/// One device for the whole process: GPU trials take turns on it.
static DEVICE: Mutex<()> = Mutex::new(());

/// Each finished trial's name and seconds, for the slowest to be named at the end: CI's time
/// is mostly a few trials, and this says which.
static TIMES: Mutex<Vec<(String, f64)>> = Mutex::new(Vec::new());

/// How many of the slowest trials the end of a run names.
const SLOWEST_NAMED: usize = 8;

fn timed(name: &str, test: impl FnOnce()) {
    let start = Instant::now();
    test();
    TIMES.lock().unwrap_or_else(|e| e.into_inner()).push((name.to_string(), start.elapsed().as_secs_f64()));
}

/// True when `TUMBLE_REQUIRE_GPU=1`.
pub fn gpu_required() -> bool {
    std::env::var(REQUIRE_GPU).is_ok_and(|v| v == "1")
}

/// Why there is no adapter, or None when the GPU backend can run.
pub fn missing_adapter() -> Option<String> {
    tumble_gpu::gpu().err().map(|e| e.to_string())
}

/// A test on the CPU: always runs.
pub fn cpu_trial(name: impl Into<String>, test: impl FnOnce() + Send + 'static) -> Trial {
    let name = name.into();
    Trial::test(name.clone(), move || {
        timed(&name, test);
        Ok(())
    })
}

/// A test that needs the GPU: runs with an adapter (one GPU trial at a time), is ignored
/// without one, and fails without one under `TUMBLE_REQUIRE_GPU=1`.
pub fn gpu_trial(name: impl Into<String>, test: impl FnOnce() + Send + 'static) -> Trial {
    let name = name.into();
    Trial::ignorable_test(name.clone(), move || match missing_adapter() {
        None => {
            let _turn = DEVICE.lock().unwrap_or_else(|e| e.into_inner());
            timed(&name, test);
            Ok(Completion::Completed)
        }
        Some(why) if gpu_required() => Err(Failed::from(format!("{REQUIRE_GPU}=1 but {why}"))),
        Some(_) => Ok(Completion::ignored_with("no GPU adapter")),
    })
    .with_kind("gpu")
}

/// Runs the trials with the command line's filters and exits with the outcome. Prints
/// beforehand why GPU trials are ignored (if they are), and afterwards the shader variants
/// this binary compiled and their compile time, and its slowest trials.
pub fn run(trials: Vec<Trial>) -> ! {
    let args = Arguments::from_args();
    let gpu_trials = trials.iter().filter(|t| t.kind() == "gpu" && !args.is_filtered_out(t)).count();
    if gpu_trials > 0 && !args.list {
        if let Some(why) = missing_adapter() {
            if gpu_required() {
                println!("{gpu_trials} GPU tests FAIL: {REQUIRE_GPU}=1 and {why}");
            } else {
                // The adapter error already names the package to install (mesa-vulkan-drivers).
                println!("{gpu_trials} GPU tests ignored: {why}; {REQUIRE_GPU}=1 makes a missing adapter fail");
            }
        }
    }
    let conclusion = libtest_mimic::run(&args, trials);
    if gpu_trials > 0 && !args.list {
        let s = tumble_gpu::shader_compile_stats();
        println!("shader variants compiled: {} distinct ({} pipelines) in {:.1} s", s.variants, s.pipelines, s.time.as_secs_f64());
    }
    let mut times = std::mem::take(&mut *TIMES.lock().unwrap_or_else(|e| e.into_inner()));
    times.sort_by(|a, b| b.1.total_cmp(&a.1));
    if times.len() > 1 {
        println!("slowest trials:");
        for (name, secs) in times.iter().take(SLOWEST_NAMED) {
            println!("  {secs:7.1} s  {name}");
        }
    }
    conclusion.exit()
}

/// Trials from a list of test functions: `gpu_tests![module::a, b]` gives GPU trials named
/// by their paths, `gpu_tests![cpu: a, b]` CPU trials.
#[macro_export]
macro_rules! gpu_tests {
    (cpu: $($($segment:ident)::+),* $(,)?) => {
        vec![$($crate::harness::cpu_trial(stringify!($($segment)::+).replace(' ', ""), $($segment)::+)),*]
    };
    ($($($segment:ident)::+),* $(,)?) => {
        vec![$($crate::harness::gpu_trial(stringify!($($segment)::+).replace(' ', ""), $($segment)::+)),*]
    };
}
