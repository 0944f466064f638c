//! Test support for tumble, for test binaries of the facade package: a harness on which
//! GPU tests are ignored (never passed) without an adapter ([`harness`]), a behavioural suite
//! written once and instantiated per backend by [`testgen!`] ([`suite`]), the tolerances of
//! each observable in each precision ([`tolerance`]) and the shared test scenes ([`scenes`]).
//!
//! ```ignore
//! // tests/backends/main.rs, with `harness = false`
//! tumble_testkit::testgen!(cpu);
//! tumble_testkit::testgen!(gpu);
//! fn main() {
//!     tumble_testkit::harness::run([cpu::trials(), gpu::trials()].into_iter().flatten().collect());
//! }
//! ```

pub mod harness;
pub mod run_files;
pub mod scenes;
pub mod suite;
pub mod tolerance;

pub use libtest_mimic::Trial;
pub use tolerance::{Observable, Precision, Tolerance};
pub use tumble_scene::schema::BackendName;

/// Instantiates the behavioural suite ([`suite::BEHAVIOURS`]) for one backend as a module of
/// that name whose `trials()` gives one trial per behaviour, named `backend::behaviour`:
/// `testgen!(cpu)` runs everywhere, `testgen!(gpu)` is ignored without an adapter.
#[macro_export]
macro_rules! testgen {
    (cpu) => {
        $crate::testgen!(@instance cpu, Cpu);
    };
    (gpu) => {
        $crate::testgen!(@instance gpu, Gpu);
    };
    (@instance $module:ident, $backend:ident) => {
        /// The behavioural suite on this backend.
        pub mod $module {
            /// One trial per behaviour of the suite.
            pub fn trials() -> Vec<$crate::Trial> {
                $crate::suite::trials($crate::BackendName::$backend)
            }
        }
    };
}
