//! What a `[[walls]]` entry may add to its shape besides a motion: a servo and wear.

use super::*;

/// A wall driven along `direction` at up to `max_speed` until the particles push back on it
/// with `force` (N); its speed is `gain` × (force − load), `gain` in m/s per N.
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ServoSection {
    pub direction: V3,
    pub force: f64,
    pub max_speed: f64,
    /// Default: max_speed / force (full speed unloaded, at rest at the target).
    pub gain: Option<f64>,
}

/// Archard's wear law: the volume worn off a surface is `coefficient` × normal force × sliding
/// distance / `hardness` (Archard 1953), accumulated per triangle of a mesh wall.
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct WearSection {
    /// Archard's dimensionless wear coefficient K.
    pub coefficient: f64,
    /// Hardness H of the wall's surface, Pa.
    pub hardness: f64,
}
