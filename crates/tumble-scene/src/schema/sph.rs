//! The `[sph]` table: a fluid simulated with smoothed particle hydrodynamics (docs/sph.md),
//! as opposed to `[fluid]`, a flow field prescribed around the particles.

use super::*;

#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SphSection {
    /// 2 (plane flow in the x–z plane, per metre of span) or 3.
    #[serde(default = "three")]
    pub dimension: u8,
    /// Initial particle spacing Δp, m.
    pub spacing: f64,
    /// h / Δp (default 1.5).
    pub smoothing_ratio: Option<f64>,
    /// Rest density ρ₀, kg/m³.
    pub density: f64,
    /// Dynamic viscosity μ, Pa s.
    pub viscosity: f64,
    /// Reference sound speed c₀, m/s; or give `expected_speed`.
    pub sound_speed: Option<f64>,
    /// The largest flow speed expected, m/s: c₀ = sound_speed_factor × this.
    pub expected_speed: Option<f64>,
    /// c₀ / expected_speed (default 10: density within about 1 %).
    pub sound_speed_factor: Option<f64>,
    #[serde(default)]
    pub viscosity_model: SphViscositySection,
    #[serde(default)]
    pub density_diffusion: DensityDiffusionSection,
    /// Monaghan's tensile-instability correction (needs density diffusion to help).
    #[serde(default)]
    pub tensile_correction: bool,
    /// XSPH coefficient ε (0: off).
    #[serde(default)]
    pub xsph: f64,
    /// An acceleration on the fluid alone, m/s² (drives a periodic channel).
    #[serde(default)]
    pub body_force: V3,
    /// Where the fluid starts.
    #[serde(default)]
    pub regions: Vec<SphRegionSection>,
    /// Measurements written to their own CSV at every output row.
    #[serde(default)]
    pub probes: Vec<SphProbeSection>,
    /// Rigid bodies the fluid moves (floating_<name>.csv at every output row).
    #[serde(default)]
    pub floating: Vec<SphFloatingSection>,
    /// Open boundaries where fluid enters at a set velocity.
    #[serde(default)]
    pub inflows: Vec<SphInflowSection>,
    /// Open boundaries where fluid leaves at a set pressure.
    #[serde(default)]
    pub outflows: Vec<SphOutflowSection>,
    /// How the scene's particles and this fluid act on each other (a 3D fluid with particles).
    #[serde(default)]
    pub coupling: SphCouplingSection,
}

/// The unresolved SPH–DEM coupling (docs/sph.md, "Coupling the particles").
#[derive(Clone, Copy, Debug, Default, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SphCouplingSection {
    /// The drag correlation.
    #[serde(default)]
    pub drag: SphDragLaw,
    /// A direction along which coupling.csv reports the particles' front (their largest
    /// extent), as a `front` probe does the fluid's.
    #[serde(default)]
    pub front: Option<V3>,
}

/// A drag correlation of the coupling.
#[derive(Clone, Copy, Debug, Default, Deserialize, PartialEq, Eq)]
#[serde(rename_all = "snake_case")]
pub enum SphDragLaw {
    /// Ergun below ε = 0.8, Wen & Yu above (Gidaspow 1994).
    #[default]
    Gidaspow,
    /// Di Felice (1994).
    DiFelice,
}

/// An inflow buffer: an axis-aligned box whose particles move at `velocity` (along one axis)
/// and become fluid as they pass the box's face that velocity points to.
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SphInflowSection {
    #[serde(rename = "box")]
    pub box_: SphBoxSection,
    /// m/s, along x, y or z: the mean over the open face.
    pub velocity: V3,
    /// How the speed varies across the face.
    #[serde(default)]
    pub profile: SphInflowProfile,
    /// Seconds over which the speed rises from 0 to full (0: full from the start).
    #[serde(default)]
    pub ramp: f64,
}

/// An inflow's profile across its open face.
#[derive(Clone, Copy, Debug, Default, Deserialize, PartialEq, Eq)]
#[serde(rename_all = "lowercase")]
pub enum SphInflowProfile {
    #[default]
    Uniform,
    Parabolic,
}

/// An outflow buffer: fluid entering the box through the face opposite `direction` leaves the
/// fluid, held at `pressure`.
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SphOutflowSection {
    #[serde(rename = "box")]
    pub box_: SphBoxSection,
    /// The direction the fluid leaves in, along x, y or z.
    pub direction: V3,
    /// Pa (gauge), default 0.
    #[serde(default)]
    pub pressure: f64,
}

/// A floating rigid body: a solid box or cylinder of uniform density, moved by the fluid's
/// pressure and viscosity and by gravity.
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SphFloatingSection {
    pub name: String,
    #[serde(rename = "box")]
    pub box_: Option<SphBoxSection>,
    pub cylinder: Option<SphCylinderSection>,
    /// kg/m³.
    pub density: f64,
    /// Of the centre of mass at the start, m/s.
    #[serde(default)]
    pub velocity: V3,
    /// At the start, rad/s.
    #[serde(default)]
    pub angular_velocity: V3,
}

fn three() -> u8 {
    3
}

/// How momentum diffuses: the laminar term with the fluid's viscosity, or artificial viscosity.
#[derive(Clone, Debug, Deserialize, PartialEq)]
#[serde(tag = "model", rename_all = "kebab-case", deny_unknown_fields)]
pub enum SphViscositySection {
    Laminar {},
    Artificial { alpha: f64 },
}

impl Default for SphViscositySection {
    fn default() -> Self {
        SphViscositySection::Artificial { alpha: 0.02 }
    }
}

/// The δ-SPH term of the continuity equation.
#[derive(Clone, Debug, Deserialize, PartialEq)]
#[serde(tag = "model", rename_all = "kebab-case", deny_unknown_fields)]
pub enum DensityDiffusionSection {
    None {},
    MolteniColagrossi { delta: f64 },
    Fourtakas { delta: f64 },
}

impl Default for DensityDiffusionSection {
    fn default() -> Self {
        DensityDiffusionSection::Fourtakas { delta: 0.1 }
    }
}

/// A region filled with fluid on the lattice of spacing Δp, at rest in hydrostatic balance
/// below its own free surface, or moving at `velocity`.
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SphRegionSection {
    #[serde(rename = "box")]
    pub box_: Option<SphBoxSection>,
    /// The inside of a cylinder, filled in rings that follow its surface (with `box`: only the
    /// part inside the box, a drum filled to a level).
    pub cylinder: Option<SphCylinderSection>,
    /// The inside of a closed mesh (with `box`: only the part inside the box, a tank filled to
    /// a level).
    pub mesh: Option<MeshSection>,
    #[serde(default)]
    pub velocity: V3,
}

#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SphCylinderSection {
    /// The centre of one end.
    pub point: V3,
    pub axis: V3,
    pub radius: f64,
    pub length: f64,
}

#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SphBoxSection {
    pub min: V3,
    pub max: V3,
}

/// One measurement: exactly one of `pressure`, `velocity`, `gauge` or `front`.
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SphProbeSection {
    pub name: String,
    /// Pressure at this point (kernel-interpolated, Shepard-normalised), Pa.
    pub pressure: Option<V3>,
    /// Velocity at this point, m/s.
    pub velocity: Option<V3>,
    /// Water height along the vertical line from `from` up to `to_z`, m.
    pub gauge: Option<GaugeSection>,
    /// The fluid's furthest extent along this direction, m.
    pub front: Option<V3>,
}

#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct GaugeSection {
    pub from: V3,
    pub to_z: f64,
}
