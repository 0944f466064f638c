//! The backend-neutral state of a tumble simulation.
//!
//! Every backend answers in these types: the particle arrays in f64
//! structure-of-arrays form ([`State`], contact springs keyed by partner in
//! [`HistorySlots`]), the observables of an output row ([`Observables`],
//! [`TrackRow`], [`DrumProfile`]), faults ([`Fault`]) and the [`Snapshot`] a
//! run continues from bit-identically. The [`Backend`] trait is the seam the
//! run loop holds.
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
mod snapshot;
mod state;

pub use backend::{AdapterInfo, Backend, BackendInfo, Frame};
pub use contact_sum::ContactSum;
pub use fault::Fault;
pub use history::{HistoryOverflow, HistorySlots, MESH_KEY, RollingHalf, Spring, TangentialHalf, WALL_KEY};
pub use observables::{DrumFrame, DrumProfile, Observables, TrackRow, drum_profiles, no_drum_profile, quantile_rank, tracks};
pub use phase::{Phase, PhasePoints, PhaseTable};
pub use snapshot::{
    DeviceImage, NeighbourState, NeighbourStateRef, OutletTally, SNAPSHOT_VERSION, ServoState, Snapshot, SnapshotError, SnapshotRef, WallState,
};
pub use state::State;
