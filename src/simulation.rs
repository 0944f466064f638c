//! The backend-independent handle on a running simulation: its phases on one clock, the DEM's
//! particles (a [`Backend`] behind [`DemPhase`]) first, then the phases beside them (an SPH
//! fluid).

use crate::coupler::Coupler;
use crate::dem::DemPhase;
use crate::feeder::FeederBooks;
use crate::sph_phase::SphPhase;
use glam::DVec3;
use std::borrow::Cow;
use std::time::Instant;
use tumble_cpu::CpuSimulation;
use tumble_gpu::{GpuError, GpuSimulation};
use tumble_scene::schema::BackendName;
use tumble_scene::{CompiledScene, Plan};
use tumble_state::{AdapterInfo, Backend, DrumProfile, Fault, Frame, Observables, Phase, PhaseStop, Snapshot, SnapshotError, State, TrackRow};

/// A simulation on one backend: the CPU reference (f64), the GPU (f32), or any other
/// [`Backend`], with the phases beside its particles.
pub struct Simulation {
    /// The DEM's particles; its backend keeps the run's clock.
    dem: DemPhase,
    /// The phases beside the particles (an SPH fluid), on the same clock.
    phases: Vec<Box<dyn Phase>>,
    /// How the particles and the fluid act on each other, when they do.
    coupler: Option<Coupler>,
    /// Why a phase stopped the run at its last advance, if one did.
    stop: Option<PhaseStop>,
}

impl Simulation {
    /// Sets up a compiled scene on the CPU backend with `threads` threads.
    pub fn new(mut scene: CompiledScene, threads: usize) -> Self {
        let phases = phases(&mut scene, threads);
        Self::with_backend(Box::new(CpuSimulation::new(scene, threads))).with_phases(phases)
    }

    /// Sets up a compiled scene on the GPU backend (the process's adapter).
    pub fn gpu(mut scene: CompiledScene) -> Result<Self, GpuError> {
        let phases = gpu_phases(&mut scene)?;
        Ok(Self::with_backend(Box::new(GpuSimulation::new(scene)?)).with_phases(phases))
    }

    /// Sets up a compiled scene on the named backend (`threads` is for the CPU).
    pub fn on(backend: BackendName, scene: CompiledScene, threads: usize) -> Result<Self, GpuError> {
        match backend {
            BackendName::Cpu => Ok(Self::new(scene, threads)),
            BackendName::Gpu => Self::gpu(scene),
        }
    }

    /// Sets up a compiled scene on the named backend starting from `state` (see
    /// [`CpuSimulation::from_state`]; the GPU takes the springs in f32).
    pub fn from_state(backend: BackendName, scene: CompiledScene, state: State, threads: usize) -> Result<Self, GpuError> {
        Ok(match backend {
            BackendName::Cpu => {
                let mut scene = scene;
                let phases = phases(&mut scene, threads);
                Self::with_backend(Box::new(CpuSimulation::from_state(scene, state, threads))).with_phases(phases)
            }
            BackendName::Gpu => {
                let mut scene = scene;
                let phases = gpu_phases(&mut scene)?;
                Self::with_backend(Box::new(GpuSimulation::from_state(scene, state)?)).with_phases(phases)
            }
        })
    }

    /// Adds phases beside the particles, stepped on the same clock; a fluid among them is
    /// coupled to the particles when the plan says so.
    pub fn with_phases(mut self, phases: Vec<Box<dyn Phase>>) -> Self {
        self.phases.extend(phases);
        if self.coupler.is_none() && self.fluid_phase().is_some() {
            self.coupler = Coupler::of(self.plan()).expect("compile checked the coupling");
            // The fluid starts filling only the space the particles leave.
            let Simulation { dem, phases, coupler, .. } = &mut self;
            if let (Some(coupler), Some(fluid)) = (coupler.as_mut(), fluid_mut(phases)) {
                fluid.couple(&mut coupler.with(&dem.backend().state()));
            }
        }
        self
    }

    /// The coupling of the particles and the fluid, when they act on each other.
    pub fn coupler(&self) -> Option<&Coupler> {
        self.coupler.as_ref()
    }

    /// The phases beside the particles.
    pub fn phases(&self) -> &[Box<dyn Phase>] {
        &self.phases
    }

    /// The phases, mutably (restoring a checkpoint).
    pub fn phases_mut(&mut self) -> &mut [Box<dyn Phase>] {
        &mut self.phases
    }

    /// Why a phase beside the particles stopped (its fault, with a Δt that works), if one did.
    pub fn phase_fault(&self) -> Option<&str> {
        match &self.stop {
            Some(PhaseStop::Failed(why)) => Some(why),
            _ => None,
        }
    }

    /// Why the last advance stopped short, if it did: a phase's fault, the particles' capacity.
    pub fn stop(&self) -> Option<&PhaseStop> {
        self.stop.as_ref()
    }

    /// Every phase, the particles first: what the run loop writes, checks and checkpoints.
    pub fn all_phases(&self) -> impl Iterator<Item = &dyn Phase> {
        std::iter::once(&self.dem as &dyn Phase).chain(self.phases.iter().map(|p| p.as_ref())).chain(self.coupler.iter().map(|c| c as &dyn Phase))
    }

    /// Every phase, mutably, the particles first.
    pub fn all_phases_mut(&mut self) -> impl Iterator<Item = &mut dyn Phase> {
        std::iter::once(&mut self.dem as &mut dyn Phase)
            .chain(self.phases.iter_mut().map(|p| p.as_mut() as &mut dyn Phase))
            .chain(self.coupler.iter_mut().map(|c| c as &mut dyn Phase))
    }

    /// The DEM phase.
    pub fn dem(&self) -> &DemPhase {
        &self.dem
    }

    /// The DEM phase, mutably (restoring its books).
    pub fn dem_mut(&mut self) -> &mut DemPhase {
        &mut self.dem
    }

    /// The SPH fluid, when the scene has one.
    pub fn fluid_phase(&self) -> Option<&crate::sph_phase::SphPhase> {
        self.phases.iter().find_map(|p| p.as_any().downcast_ref())
    }

    /// Particles of every phase: the DEM's and each other phase's moving ones.
    pub fn all_particles(&self) -> usize {
        self.particles() + self.phases.iter().map(|p| p.particles()).sum::<usize>()
    }

    /// Wraps any backend; the sources' events due at its current step run now.
    pub fn with_backend(backend: Box<dyn Backend>) -> Self {
        Simulation { dem: DemPhase::new(backend), phases: Vec::new(), coupler: None, stop: None }
    }

    /// The sources' books (inserted counts and masses, generator states).
    pub fn feeder_books(&self) -> Option<&FeederBooks> {
        self.dem.feeder_books()
    }

    /// Per source: particles inserted so far and their mass.
    pub fn inserted(&self) -> Vec<(u64, f64)> {
        self.dem.inserted()
    }

    /// Kinetic and potential energy the sources have brought in so far, J.
    pub fn inserted_energy(&self) -> f64 {
        self.dem.inserted_energy()
    }

    /// Per outlet: particles deleted so far and their mass.
    pub fn outlet_tallies(&self) -> Vec<tumble_state::OutletTally> {
        crate::dem::rows::outlet_tallies(self.backend())
    }

    /// Why a source could not insert (the backend's fixed capacity ran out), if it could not.
    pub fn feed_error(&self) -> Option<&str> {
        self.dem.feed_error()
    }

    /// The backend, for what this handle does not forward.
    pub fn backend(&self) -> &dyn Backend {
        self.dem.backend()
    }

    pub fn plan(&self) -> &Plan {
        self.dem.backend().plan()
    }

    pub fn backend_name(&self) -> &'static str {
        self.dem.backend().info().name
    }

    pub fn device_name(&self) -> String {
        self.dem.backend().info().device
    }

    /// The GPU adapter, on a GPU backend.
    pub fn adapter(&self) -> Option<AdapterInfo> {
        self.dem.backend().info().adapter
    }

    pub fn precision(&self) -> &'static str {
        self.dem.backend().info().precision
    }

    /// Advances every phase `steps` steps (the particles stop at each source's insertion steps
    /// to insert), or as far as the particles got when they stop short; [`Simulation::stop`]
    /// says why a phase stopped.
    pub fn advance(&mut self, steps: u64) {
        if self.coupler.is_some() {
            self.stop = self.advance_coupled(steps).err();
            return;
        }
        let (before, dt) = (self.steps(), self.plan().model.dt);
        let particles = self.dem.advance(steps, dt);
        let taken = self.steps() - before;
        // A fault of a phase beside the particles is reported before the particles' own.
        self.stop = self
            .phases
            .iter_mut()
            .find_map(|p| p.advance(taken, dt).err().map(|e| PhaseStop::Failed(format!("{}: {e}", p.name()))))
            .or(particles.err());
    }

    /// Advances a coupled run `steps` of the particles' steps: at the start of each fluid step
    /// (every `substeps` of theirs) the fluid steps first, evaluating the coupling on the
    /// particles as they are, and the particles then take their sub-steps to the same time
    /// holding the fluid's forces of that evaluation.
    fn advance_coupled(&mut self, steps: u64) -> Result<(), PhaseStop> {
        let dt = self.plan().model.dt;
        let end = self.steps() + steps;
        let Simulation { dem, phases, coupler, .. } = self;
        let coupler = coupler.as_mut().expect("a coupled run");
        let n = coupler.substeps();
        let fluid = fluid_mut(phases).expect("a coupled run has a fluid");
        while dem.backend().steps() < end {
            let now = dem.backend().steps();
            // Where the time goes: the particles' state read and their forces set are the
            // coupling's, the fluid's step less the coupling's evaluations the fluid's.
            let (mut fluid_seconds, mut exchange_seconds) = (0.0, 0.0);
            if now % n == 0 {
                let start = Instant::now();
                let solids = dem.backend().state();
                let read = start.elapsed().as_secs_f64();
                fluid.advance_coupled(n as f64 * dt, &mut coupler.with(&solids)).map_err(|e| match e {
                    PhaseStop::Failed(why) => PhaseStop::Failed(format!("fluid: {why}")),
                    other => other,
                })?;
                drop(solids);
                fluid_seconds = start.elapsed().as_secs_f64() - read;
                let set = Instant::now();
                dem.backend_mut().set_external_forces(coupler.forces()).map_err(PhaseStop::Failed)?;
                exchange_seconds = read + set.elapsed().as_secs_f64();
            }
            let next = (now / n + 1) * n;
            let start = Instant::now();
            dem.advance(next.min(end) - now, dt)?;
            coupler.book(fluid_seconds, exchange_seconds, start.elapsed().as_secs_f64());
            if dem.backend().steps() < next.min(end) {
                break;
            }
        }
        Ok(())
    }

    /// Why the backend stopped short of the requested steps (a fixed capacity ran out), if it did.
    pub fn fault(&self) -> Option<Fault> {
        self.dem.backend().fault()
    }

    pub fn steps(&self) -> u64 {
        self.dem.backend().steps()
    }

    pub fn time(&self) -> f64 {
        self.dem.backend().time()
    }

    pub fn particles(&self) -> usize {
        self.dem.backend().particles()
    }

    pub fn removed(&self) -> usize {
        self.dem.backend().removed()
    }

    /// Everything one output row needs, in one read-back on a device.
    pub fn frame(&self, with_state: bool) -> Frame<'_> {
        self.dem.backend().frame(with_state)
    }

    pub fn observables(&self) -> Observables {
        self.dem.backend().observables()
    }

    pub fn tracks(&self) -> Vec<TrackRow> {
        self.dem.backend().tracks()
    }

    /// Every particle still in the domain (a device's are read back and widened to f64, in id order).
    pub fn state(&self) -> Cow<'_, State> {
        self.dem.backend().state()
    }

    /// Power delivered to the particles by each wall group at the last force pass (zero for static walls).
    pub fn wall_power(&self) -> Vec<f64> {
        self.dem.backend().wall_power()
    }

    /// Work done on the particles by each wall group since t = 0.
    pub fn wall_work(&self) -> Vec<f64> {
        self.dem.backend().wall_work()
    }

    /// The charge profile of each drum of the plan.
    pub fn drum_profiles(&self) -> Vec<DrumProfile> {
        self.dem.backend().drum_profiles()
    }

    /// Per wall: the volume worn off each of its triangles since t = 0 (Archard; empty without wear).
    pub fn mesh_wear(&self) -> Vec<Vec<f64>> {
        self.dem.backend().mesh_wear()
    }

    /// The walls in their current pose.
    pub fn walls(&self) -> Cow<'_, [tumble_scene::Wall]> {
        self.dem.backend().walls()
    }

    /// Contact force on the particle with id `id` in the last force pass.
    pub fn contact_force(&self, id: u32) -> Option<DVec3> {
        self.dem.backend().contact_force(id)
    }

    /// Neighbour-list rebuilds (the CPU's Verlet list; the GPU bins every step).
    pub fn neighbour_builds(&self) -> Option<u64> {
        self.dem.backend().neighbour_builds()
    }

    /// Memory this simulation's particle and grid arrays take, bytes (GPU: device memory), with its phases'.
    pub fn memory_bytes(&self) -> u64 {
        self.dem.memory_bytes() + self.phases.iter().map(|p| p.memory_bytes()).sum::<u64>()
    }

    /// Bytes per particle of this backend's state.
    pub fn bytes_per_particle(&self) -> u64 {
        self.dem.backend().bytes_per_particle()
    }

    /// Everything needed to continue this run bit-identically.
    pub fn snapshot(&self) -> Snapshot {
        self.dem.backend().snapshot()
    }

    /// Continues from a snapshot of the same scene written by this backend.
    pub fn restore(&mut self, snapshot: &Snapshot) -> Result<(), SnapshotError> {
        self.dem.backend_mut().restore(snapshot)
    }

    /// A collective decision of the run (every part of a distributed backend answers the same).
    pub fn agree(&self, local: bool) -> bool {
        self.dem.backend().agree(local)
    }

    /// The concrete backend `B`, for tests and tools that need its internals.
    pub fn downcast<B: Backend>(&self) -> Option<&B> {
        self.dem.backend().as_any().downcast_ref::<B>()
    }

    /// The concrete backend `B`, mutably.
    pub fn downcast_mut<B: Backend>(&mut self) -> Option<&mut B> {
        self.dem.backend_mut().as_any_mut().downcast_mut::<B>()
    }

    /// The CPU simulation, for tests and tools that need its internals.
    ///
    /// # Panics
    /// On any other backend; use the backend-independent methods there.
    pub fn cpu(&self) -> &CpuSimulation {
        self.downcast::<CpuSimulation>().expect("Simulation::cpu() on a simulation that is not on the CPU backend")
    }

    /// The GPU simulation, on the GPU backend.
    pub fn gpu_simulation(&mut self) -> Option<&mut GpuSimulation> {
        self.downcast_mut::<GpuSimulation>()
    }
}

/// The SPH fluid among `phases`, when there is one.
fn fluid_mut(phases: &mut [Box<dyn Phase>]) -> Option<&mut SphPhase> {
    phases.iter_mut().find_map(|p| p.as_any_mut().downcast_mut())
}

/// The phases a compiled scene holds besides its particles (their starting particles taken from it).
fn phases(scene: &mut CompiledScene, threads: usize) -> Vec<Box<dyn Phase>> {
    match (&scene.plan.sph, scene.fluid.take()) {
        (Some(_), Some(particles)) => {
            let fluid = crate::sph_phase::SphPhase::new(&scene.plan, particles, threads).expect("compile checked the fluid's settings");
            vec![Box::new(fluid)]
        }
        _ => Vec::new(),
    }
}

/// The phases of a compiled scene on the GPU; refuses a fluid with what the GPU does not run yet.
fn gpu_phases(scene: &mut CompiledScene) -> Result<Vec<Box<dyn Phase>>, GpuError> {
    let Some(sph) = &scene.plan.sph else { return Ok(Vec::new()) };
    if sph.coupling.is_some() {
        return Err(GpuError::Feature("the particles and the fluid act on each other on the CPU backend only so far; use --backend cpu".into()));
    }
    if let Some(why) = tumble_gpu::fluid_gpu_refusal(&sph.settings) {
        return Err(GpuError::Feature(why));
    }
    match scene.fluid.take() {
        Some(particles) => {
            let fluid = crate::sph_phase::SphPhase::on(&scene.plan, particles, 1, true).map_err(GpuError::Feature)?;
            Ok(vec![Box::new(fluid)])
        }
        None => Ok(Vec::new()),
    }
}
