//! The backend-neutral state of a tumble simulation.
//!
//! Every backend answers in these types: the particle arrays in f64
//! structure-of-arrays form ([`State`], contact springs keyed by partner in
//! [`HistorySlots`]), the observables of an output row ([`Observables`],
//! [`TrackRow`], [`DrumProfile`]), faults ([`Fault`]) and the [`Snapshot`] a
//! run continues from bit-identically. The run loop holds every phase (the
//! DEM's particles, an SPH fluid) through the [`Phase`] trait; [`Backend`] is the
//! seam between the DEM phase and the code that steps its particles.
//!
//! ```
//! use tumble_state::{Snapshot, SnapshotError};
//! assert!(matches!(Snapshot::from_bytes(b"not a snapshot"), Err(SnapshotError::Corrupt(_))));
//! ```

mod backend;
mod contact_sum;
mod fault;
mod history;
mod observables;
mod phase;
mod poly_data;
mod snapshot;
mod state;

pub use backend::{AdapterInfo, Backend, BackendInfo, Frame};
pub use contact_sum::ContactSum;
pub use fault::Fault;
pub use history::{HistoryOverflow, HistorySlots, MESH_KEY, RollingHalf, Spring, TangentialHalf, WALL_KEY};
pub use observables::{DrumFrame, DrumProfile, Observables, TrackRow, drum_profiles, no_drum_profile, quantile_rank, tracks};
pub use phase::{Instability, OutputRequest, Phase, PhaseOutput, PhasePoints, PhaseStop, PhaseTable};
pub use poly_data::{Array, Cells, PolyData, Values};
pub use snapshot::{
    DeviceImage, NeighbourState, NeighbourStateRef, OutletTally, SNAPSHOT_VERSION, ServoState, Snapshot, SnapshotError, SnapshotRef, WallState,
};
pub use state::State;

#[cfg(test)]
mod tests {
    /// The `[dependencies]` table of a manifest, as the packages it names.
    fn dependencies(manifest: &str) -> Vec<String> {
        let table = manifest.split("\n[dependencies]\n").nth(1).unwrap_or("");
        let table = table.split("\n[").next().unwrap_or("");
        table.lines().filter_map(|l| l.split(['=', '.']).next()).map(|n| n.trim().to_string()).filter(|n| !n.is_empty()).collect()
    }

    /// The state crate and the backends read a plan's plain data (tumble-plan), never the scene
    /// format: tumble-scene may only be a backend's test dependency.
    #[test]
    fn neither_the_state_nor_a_backend_depends_on_the_scene_format() {
        let crates = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("..");
        let mut read = 0;
        for name in ["tumble-state", "tumble-cpu", "tumble-gpu"] {
            let Ok(manifest) = std::fs::read_to_string(crates.join(name).join("Cargo.toml")) else {
                // A packaged tumble-state has no sibling crates beside it.
                assert_ne!(name, "tumble-state", "tumble-state's own manifest must be readable");
                continue;
            };
            let deps = dependencies(&manifest);
            assert!(deps.iter().any(|d| d == "tumble-plan"), "{name} should read the plan from tumble-plan; its dependencies: {deps:?}");
            assert!(!deps.iter().any(|d| d == "tumble-scene"), "{name} depends on tumble-scene, the scene format: {deps:?}");
            read += 1;
        }
        assert!(read >= 1);
    }
}
