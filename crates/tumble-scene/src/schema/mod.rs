//! The scene file as written by users. Every field is documented in docs/scene.md.

use serde::Deserialize;

mod contact;
mod run;
mod sources;
mod sph;
mod wall_options;
pub use contact::*;
pub use run::*;
pub use sources::*;
pub use sph::*;
pub use tumble_plan::{DiameterRange, DiameterSpec, LogNormalSize, LogNormalWrapper, NormalSize, NormalWrapper, SieveWrapper};
pub use wall_options::*;

/// A point or vector in a scene: exactly three numbers [x, y, z]. (A plain `[f64; 3]` would
/// take `[1, 2, 3, 4]` and drop the fourth without a word.)
#[derive(Clone, Copy, Default, PartialEq)]
pub struct V3(pub [f64; 3]);

/// Written as the scene writes it, `[x, y, z]`, in messages.
impl std::fmt::Debug for V3 {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        self.0.fmt(f)
    }
}

impl<'de> Deserialize<'de> for V3 {
    fn deserialize<D: serde::Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        let v = Vec::<f64>::deserialize(d)?;
        match v[..] {
            [x, y, z] => Ok(V3([x, y, z])),
            _ => Err(serde::de::Error::invalid_length(v.len(), &"three numbers [x, y, z]")),
        }
    }
}

impl std::ops::Deref for V3 {
    type Target = [f64; 3];
    fn deref(&self) -> &[f64; 3] {
        &self.0
    }
}

impl std::ops::DerefMut for V3 {
    fn deref_mut(&mut self) -> &mut [f64; 3] {
        &mut self.0
    }
}

impl From<V3> for glam::DVec3 {
    fn from(v: V3) -> Self {
        glam::DVec3::from_array(v.0)
    }
}

impl From<[f64; 3]> for V3 {
    fn from(v: [f64; 3]) -> Self {
        V3(v)
    }
}

#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Scene {
    pub name: String,
    pub run: RunSection,
    pub domain: DomainSection,
    pub gravity: Option<GravitySection>,
    /// A flow field prescribed around the particles (drag), not simulated.
    pub fluid: Option<FluidSection>,
    /// A fluid simulated with SPH.
    pub sph: Option<SphSection>,
    /// Needed by particles and the walls they meet; a scene of fluid alone may leave them out.
    #[serde(default)]
    pub materials: Vec<MaterialSection>,
    pub contact: Option<ContactSection>,
    #[serde(default)]
    pub particles: Vec<ParticleGroup>,
    #[serde(default)]
    pub walls: Vec<WallSection>,
    /// Particles added during the run.
    #[serde(default)]
    pub sources: Vec<SourceSection>,
    /// Regions that delete the particles entering them.
    #[serde(default)]
    pub outlets: Vec<OutletSection>,
    #[serde(default)]
    pub output: OutputSection,
    /// The folder of the scene file, where relative mesh paths start (the working folder
    /// when the scene was not read from a file).
    #[serde(skip)]
    pub folder: Option<std::path::PathBuf>,
}

impl Scene {
    /// The `[contact]` table; a scene without one (fluid alone: no particle ever touches) reads
    /// as frictionless unit springs that nothing uses.
    pub fn contact(&self) -> &ContactSection {
        static UNUSED: std::sync::LazyLock<ContactSection> = std::sync::LazyLock::new(|| ContactSection {
            normal: NormalSection::Linear { stiffness: 1.0 },
            restitution: 1.0,
            tangential: TangentialSection::None,
            cohesion: None,
            no_attraction: false,
            rolling_friction: None,
            rolling_model: None,
            polyhedron_model: None,
            history_slots: None,
            pairs: Vec::new(),
        });
        self.contact.as_ref().unwrap_or(&UNUSED)
    }

    /// Whether the scene holds DEM particles, at the start or from its sources.
    pub fn has_particles(&self) -> bool {
        !self.particles.is_empty() || !self.sources.is_empty()
    }
}

#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct DomainSection {
    pub min: V3,
    pub max: V3,
    #[serde(default)]
    pub periodic: [bool; 3],
}

#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct GravitySection {
    pub acceleration: V3,
}

#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct FluidSection {
    /// Dynamic viscosity μ_f in Pa s (Stokes drag), or `{ stokes_number = Stk }` (Taylor–Green flow).
    pub viscosity: Option<ViscositySpec>,
    #[serde(default)]
    pub drag: DragName,
    /// α in kg/m for quadratic drag.
    pub coefficient: Option<f64>,
    #[serde(default)]
    pub flow: FlowSection,
}

#[derive(Clone, Copy, Debug, Deserialize, PartialEq)]
#[serde(untagged)]
pub enum ViscositySpec {
    PascalSeconds(f64),
    Target(StokesTarget),
}

/// μ_f chosen so that the particles' Stokes number in the Taylor–Green flow is `stokes_number`.
#[derive(Clone, Copy, Debug, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct StokesTarget {
    pub stokes_number: f64,
}

#[derive(Clone, Copy, Debug, Default, Deserialize, PartialEq, Eq)]
#[serde(rename_all = "kebab-case")]
pub enum DragName {
    #[default]
    Stokes,
    Quadratic,
}

#[derive(Clone, Debug, Deserialize, PartialEq)]
#[serde(rename_all = "snake_case", deny_unknown_fields)]
pub enum FlowSection {
    Uniform(V3),
    TaylorGreen(TaylorGreenSection),
}

impl Default for FlowSection {
    fn default() -> Self {
        FlowSection::Uniform(V3::default())
    }
}

#[derive(Clone, Debug, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct TaylorGreenSection {
    pub amplitude: f64,
    pub frequency: f64,
}

#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct MaterialSection {
    pub name: String,
    pub density: f64,
    pub youngs_modulus: Option<f64>,
    pub poisson_ratio: Option<f64>,
}

#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ParticleGroup {
    pub name: Option<String>,
    pub material: String,
    pub shape: ShapeSection,
    #[serde(default)]
    pub fixed: bool,
    pub positions: Option<Vec<V3>>,
    pub lattice: Option<LatticeSection>,
    pub random: Option<RandomSection>,
    pub velocity: Option<VelocitySpec>,
    pub angular_velocity: Option<V3>,
    /// Initial orientation of polyhedra: `[w, x, y, z]` (normalised) or `"random"` (default: as given).
    pub orientation: Option<OrientationSpec>,
    #[serde(default)]
    pub track: bool,
}

#[derive(Clone, Copy, Debug, Deserialize, PartialEq)]
#[serde(untagged)]
pub enum OrientationSpec {
    Quaternion([f64; 4]),
    Named(NamedOrientation),
}

#[derive(Clone, Copy, Debug, Deserialize, PartialEq, Eq)]
#[serde(rename_all = "kebab-case")]
pub enum NamedOrientation {
    /// Uniformly random over all rotations, from the run's seed.
    Random,
}

#[derive(Clone, Debug, Deserialize)]
#[serde(rename_all = "snake_case", deny_unknown_fields)]
pub enum ShapeSection {
    Sphere(SphereSection),
    /// The convex hull of the given points; the particle's position is its centre of mass.
    Polyhedron(VertexListSection),
    Cube(CubeSection),
    /// A rectangular box: `size = [a, b, c]` (edge lengths).
    Box(BoxShapeSection),
    /// A regular solid: `kind` (tetrahedron, cube, octahedron, dodecahedron, icosahedron) and
    /// `edge` or `radius` (circumradius).
    Platonic(PlatonicSection),
    /// A right prism on a regular polygon: `sides`, `radius` (circumradius of the polygon), `height`.
    Prism(PrismShapeSection),
}

#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct VertexListSection {
    pub vertices: Vec<V3>,
}

#[derive(Clone, Copy, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct CubeSection {
    pub edge: f64,
}

#[derive(Clone, Copy, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct BoxShapeSection {
    pub size: V3,
}

#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PlatonicSection {
    pub kind: String,
    pub edge: Option<f64>,
    pub radius: Option<f64>,
}

#[derive(Clone, Copy, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PrismShapeSection {
    pub sides: u32,
    pub radius: f64,
    pub height: f64,
}

#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SphereSection {
    pub diameter: DiameterSpec,
    /// Absolute effect diameter d_e (cohesion range).
    pub effect_diameter: Option<f64>,
    /// Effect diameter as a multiple of each particle's diameter.
    pub effect_ratio: Option<f64>,
}

#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct LatticeSection {
    pub min: V3,
    pub max: V3,
    pub spacing: f64,
    #[serde(default)]
    pub jitter: f64,
}

#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RandomSection {
    pub count: usize,
    pub region: RegionSection,
    #[serde(default = "yes")]
    pub no_overlap: bool,
}

fn yes() -> bool {
    true
}

#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RegionSection {
    pub min: V3,
    pub max: V3,
}

#[derive(Clone, Debug, Deserialize, PartialEq)]
#[serde(untagged)]
pub enum VelocitySpec {
    Vector(V3),
    Random(RandomVelocityWrapper),
    /// `velocity = "flow"`: the local fluid velocity at each particle's position.
    Named(NamedVelocity),
}

#[derive(Clone, Copy, Debug, Deserialize, PartialEq, Eq)]
#[serde(rename_all = "kebab-case")]
pub enum NamedVelocity {
    Flow,
}

#[derive(Clone, Debug, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct RandomVelocityWrapper {
    pub random: RandomVelocity,
}

#[derive(Clone, Debug, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct RandomVelocity {
    pub mean_speed: f64,
    #[serde(default)]
    pub std: f64,
}

#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct WallSection {
    pub name: Option<String>,
    /// Needed where particles meet the wall; a wall of a scene of fluid alone may leave it out.
    pub material: Option<String>,
    pub plane: Option<PlaneSection>,
    pub quad: Option<QuadSection>,
    #[serde(rename = "box")]
    pub box_: Option<BoxSection>,
    pub cylinder: Option<CylinderSection>,
    pub lifters: Option<LiftersSection>,
    pub mesh: Option<MeshSection>,
    pub motion: Option<MotionSection>,
    /// A conveyor: the surface material moves at this velocity (its part along the contact
    /// normal dropped) while the geometry stays where it is.
    pub surface_velocity: Option<V3>,
    /// A servo wall: translated along a direction until the particles hold it with a target force.
    pub servo: Option<ServoSection>,
    /// Archard wear accumulated per triangle of a mesh wall.
    pub wear: Option<WearSection>,
}

/// A triangle mesh read from an STL (binary or ASCII) or OBJ file, placed as
/// x ↦ rotate(scale x) + translate.
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct MeshSection {
    /// The .stl or .obj file, relative to the scene file's folder.
    pub file: String,
    /// File units to metres (0.001 for a file in millimetres).
    #[serde(default = "unit_scale")]
    pub scale: f64,
    pub rotate: Option<MeshRotation>,
    #[serde(default)]
    pub translate: V3,
    /// Neighbours whose normals differ by less than this many degrees are one smooth surface.
    #[serde(default = "default_curvature_degrees")]
    pub curvature: f64,
    /// The mesh must be closed (a solid body or a container): open edges are refused.
    #[serde(default)]
    pub closed: bool,
}

/// A rotation about `axis` by `degrees` (right-handed).
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct MeshRotation {
    pub axis: V3,
    pub degrees: f64,
}

fn unit_scale() -> f64 {
    1.0
}

fn default_curvature_degrees() -> f64 {
    0.25
}

/// Lifter bars fixed inside a cylinder wall, moving with it.
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct LiftersSection {
    /// Number of rows at equal angular spacing.
    #[serde(alias = "rows")]
    pub count: u32,
    /// Radial height of a bar, m.
    pub height: f64,
    /// Width of the top face, m.
    pub width: f64,
    /// Angle of each side face from the radial direction, degrees (0 = rectangular, > 0 = trapezoidal).
    #[serde(default)]
    pub face_angle: f64,
    /// Angular position of the first row, degrees from the cylinder's reference direction.
    #[serde(default)]
    pub phase: f64,
    /// Name of the inside cylinder wall they are fixed to.
    pub on: String,
}

/// Prescribed wall motion: one of `rotate`, `translate`, `oscillate`, and when it runs.
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct MotionSection {
    pub rotate: Option<RotateSection>,
    pub translate: Option<TranslateSection>,
    pub oscillate: Option<OscillateSection>,
    /// Time the motion starts, s (the wall stands still before).
    #[serde(default)]
    pub start: f64,
    /// Time over which the speed rises linearly from 0 to its full value after `start`, s.
    #[serde(default)]
    pub ramp: f64,
    /// Time the motion stops, s (the wall stays where it is then).
    pub stop: Option<f64>,
}

/// Sinusoidal translation: x(t) = amplitude · sin(2π frequency t) along `direction`.
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct OscillateSection {
    pub direction: V3,
    /// m.
    pub amplitude: f64,
    /// Hz.
    pub frequency: f64,
}

#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RotateSection {
    /// A point on the rotation axis.
    pub point: V3,
    pub axis: V3,
    /// Revolutions per minute, right-handed about `axis` (negative turns the other way).
    pub rpm: f64,
}

#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct TranslateSection {
    pub velocity: V3,
}

#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PlaneSection {
    pub point: V3,
    pub normal: V3,
}

#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct QuadSection {
    pub corners: [V3; 4],
    #[serde(default = "yes")]
    pub two_sided: bool,
}

#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct BoxSection {
    pub min: V3,
    pub max: V3,
    /// Width of a square hole centred in the −z face (a flat-bottomed hopper's orifice), m.
    pub floor_hole: Option<f64>,
}

#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct CylinderSection {
    pub point: V3,
    pub axis: V3,
    pub radius: f64,
    pub length: f64,
    #[serde(default = "yes")]
    pub inside: bool,
}
