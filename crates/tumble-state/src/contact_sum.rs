//! What the last contact pass gave each particle.

use glam::DVec3;
use serde::{Deserialize, Serialize};

/// One particle's share of a contact pass: its own force and torque, and the
/// energy books of the contacts it owns.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct ContactSum {
    pub force: DVec3,
    pub torque: DVec3,
    /// Elastic energy of the contacts this particle owns (pairs where it has the lower id, and walls).
    pub elastic: f64,
    /// Power dissipated (≥ 0) in the contacts this particle owns.
    pub dissipation: f64,
    /// Body contacts this particle owns.
    pub contacts: u32,
    /// Largest δ / min(r_i, r_j) over all of its contacts.
    pub max_overlap_ratio: f64,
    /// Contacts holding a tangential spring (may exceed the slots: then the run stops).
    pub springs: u32,
}
