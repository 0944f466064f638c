//! The fluid phase of tumble: weakly compressible smoothed particle hydrodynamics.
//!
//! A [`FluidPhase`] holds fluid and wall particles in one structure of arrays, sorted by its own
//! cell grid (tumble-broad's counting sort at 2h plus a skin), and steps them with the symplectic
//! position-Verlet scheme. Per evaluation each particle gathers its own sums over its neighbours in
//! slot order, so the results are bit-identical for any number of threads.
//!
//! The method (docs/sph.md): Wendland C2 kernel; continuity density with δ-SPH diffusion
//! (Molteni & Colagrossi 2009, or the hydrostatic-corrected form of Fourtakas et al. 2019); Tait
//! equation of state; Morris et al. (1997) laminar or Monaghan (1992) artificial viscosity;
//! Monaghan's (2000) tensile correction; XSPH; dummy wall particles with the condition of
//! Adami, Hu & Adams (2012) and a short-range repulsion; a true 2D mode (the x–z plane).

mod buffers;
pub mod cases;
pub mod coupling;
mod eos;
mod floating;
mod kernel;
mod limits;
mod neighbours;
mod particles;
mod pass;
mod phase;
mod probes;
mod rates;
mod settings;
mod setup;

pub use buffers::{BufferBooks, BufferBox, Inflow, InflowProfile, Outflow};
pub use eos::{GAMMA, Tait};
pub use floating::{BodyMove, BodyShape, BodyState, FloatingBody};
pub use kernel::{Dimension, WendlandC2};
pub use limits::{FluidFault, TimeStepLimits};
pub use neighbours::{SKIN, rebuild_distance};
pub use particles::{
    Aabb, ClosedSides, FluidParticles, ParticleKind, Rectangle, cylinder_fill, cylinder_shell, lattice_points, on_fluid_side, rectangle_layers,
    wall_shell,
};
pub use pass::PassConstants;
pub use phase::{CoupledSolids, FluidObservables, FluidPhase, FluidSnapshot};
pub use rates::Rates;
pub use settings::{DensityDiffusion, FluidSettings, MovingWall, Viscosity, WallRole};
pub use setup::{
    add_fluid_block, add_fluid_cylinder, add_fluid_points, add_inflow, add_wall_box, add_wall_cylinder, add_wall_rectangle, add_wall_slab,
    push_walls, wall_layers,
};
