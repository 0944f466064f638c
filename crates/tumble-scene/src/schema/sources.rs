//! `[[sources]]` (particles added during the run) and `[[outlets]]` (regions that delete them).

use super::*;

#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SourceSection {
    pub name: Option<String>,
    pub material: String,
    /// One shape (any particle shape; a sphere's diameter may be a distribution) …
    pub shape: Option<ShapeSection>,
    /// … or a mixture of shapes, each with its share of the particles by number.
    pub mixture: Option<Vec<MixtureEntry>>,
    /// Where the particles appear.
    pub region: SourceRegion,
    /// Velocity of every inserted particle (default at rest).
    pub velocity: Option<V3>,
    /// Polyhedra: `"random"` (default) or a fixed quaternion `[w, x, y, z]`.
    pub orientation: Option<OrientationSpec>,
    /// How fast: particles or kilograms per second (omit to insert the whole `total` at once).
    pub rate: Option<RateSpec>,
    /// How many in all: particles or kilograms; the source stops when it is reached.
    pub total: Option<TotalSpec>,
    /// Time of the first insertion, s.
    #[serde(default)]
    pub start: f64,
    /// Time after which nothing is inserted, s (default: the end of the run).
    pub stop: Option<f64>,
    /// Simulated seconds between insertions (default: the time to fall or travel the region's
    /// depth, at most 0.01 s).
    pub interval: Option<f64>,
}

#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct MixtureEntry {
    pub shape: ShapeSection,
    /// Share of the particles by number (normalised over the mixture).
    pub fraction: f64,
}

#[derive(Clone, Debug, Deserialize)]
#[serde(rename_all = "snake_case", deny_unknown_fields)]
pub enum SourceRegion {
    /// An axis-aligned box: `{ min, max }`.
    Box(RegionSection),
    /// A cylinder: `{ base, axis, radius, length }` (base = centre of one end face).
    Cylinder(SourceCylinder),
    /// A rectangle particles enter through (a factory): `{ point, normal, width, height }`; the
    /// particles' centres lie in the rectangle.
    Plane(SourcePlane),
    /// The inside of a closed mesh (STL or OBJ, placed as a mesh wall is): `{ file, scale,
    /// translate, rotate }`; either orientation of its normals.
    Mesh(MeshSection),
}

#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SourceCylinder {
    pub base: V3,
    pub axis: V3,
    pub radius: f64,
    pub length: f64,
}

#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SourcePlane {
    pub point: V3,
    pub normal: V3,
    /// Extent along the first in-plane direction (normal × z, or normal × x when the normal is ±z).
    pub width: f64,
    /// Extent along the second in-plane direction.
    pub height: f64,
}

#[derive(Clone, Copy, Debug, Deserialize, PartialEq)]
#[serde(rename_all = "snake_case", deny_unknown_fields)]
pub enum RateSpec {
    ParticlesPerSecond(f64),
    KgPerSecond(f64),
}

#[derive(Clone, Copy, Debug, Deserialize, PartialEq)]
#[serde(rename_all = "snake_case", deny_unknown_fields)]
pub enum TotalSpec {
    Particles(u64),
    Kg(f64),
}

#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct OutletSection {
    pub name: String,
    /// An axis-aligned box: particles whose centre enters it are deleted.
    #[serde(rename = "box")]
    pub box_: Option<RegionSection>,
    /// A plane: particles whose centre crosses to the side its normal points to are deleted.
    pub plane: Option<PlaneSection>,
}
