//! The SPH fluid as a phase of a run: tumble-sph's [`FluidPhase`] stepped on the run's threads,
//! its sums, probes and floating bodies as output tables (`fluid.csv`, `probe_<name>.csv`,
//! `floating_<name>.csv`), its particles as the `fluid` snapshot series.

use serde::{Deserialize, Serialize};
use tumble_scene::{Plan, SphPlan, SphProbe, SphProbeKind};
use tumble_sph::{DensityDiffusion, FluidObservables, FluidParticles, FluidPhase, FluidSettings, FluidSnapshot, ParticleKind, Viscosity, WallRole};
use tumble_state::{OutputRequest, Phase, PhaseOutput, PhasePoints, PhaseStop, PhaseTable, PolyData};

/// A fluid phase and what the scene measures in it.
pub struct SphPhase {
    /// The fluid on the CPU; on the GPU, the device's state as of the last advance (sorted by
    /// the CPU's grid), which the probes, rows and snapshots of points read.
    phase: FluidPhase,
    /// The fluid on the GPU, which steps it there.
    device: Option<Device>,
    probes: Vec<SphProbe>,
    floating: Vec<String>,
    fluid_particles: usize,
    pool: rayon::ThreadPool,
    /// The largest energy gain allowed, as a share of the energy scale; None: not watched.
    energy_growth: Option<f64>,
    energy: EnergyBooks,
}

/// The fluid's energy monitor: in a closed tank with static walls and no body force, the total
/// energy (kinetic + potential + elastic, and the floating bodies' kinetic and potential) only
/// falls (viscosity, δ-SPH), up to the time-step error; a gain beyond `energy_growth` times its
/// scale is an instability.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
struct EnergyBooks {
    /// The lowest total energy seen at an output row, J.
    lowest: f64,
    /// The energy scale: the largest kinetic + elastic energy seen, and at least a hundredth of
    /// the potential energy gravity can release from the start, J.
    scale: f64,
}

/// The GPU's fluid and what the host keeps of its last evaluation.
struct Device {
    fluid: tumble_gpu::GpuFluid,
    /// Each particle's pressure by id at the last evaluation (walls: extrapolated).
    pressure: Vec<f64>,
    /// The time-step limit of the last advance's end state.
    dt_limit: f64,
}

/// What a fluid's checkpoint section holds: the phase and its monitor's books.
#[derive(Serialize, Deserialize)]
struct SphSection {
    fluid: FluidSnapshot,
    energy: EnergyBooks,
}

fn total(o: &FluidObservables) -> f64 {
    o.kinetic_energy + o.potential_energy + o.elastic_energy
}

/// The floating bodies' kinetic and potential energy, J.
fn bodies_energy(phase: &FluidPhase) -> (f64, f64) {
    let s = phase.settings();
    s.floating
        .iter()
        .zip(phase.bodies())
        .fold((0.0, 0.0), |(k, u), (body, state)| (k + state.kinetic_energy(body), u + state.potential_energy(body, s.gravity)))
}

impl SphPhase {
    /// The phase of `plan` over its starting `particles`, stepped on `threads` threads (its
    /// results do not depend on how many).
    pub fn new(plan: &Plan, particles: FluidParticles, threads: usize) -> Result<Self, String> {
        Self::on(plan, particles, threads, false)
    }

    /// The phase of `plan` stepped on the process's GPU (f32), or on `threads` CPU threads.
    pub fn on(plan: &Plan, particles: FluidParticles, threads: usize, gpu: bool) -> Result<Self, String> {
        let sph: &SphPlan = plan.sph.as_ref().ok_or("the plan has no fluid")?;
        let pool = rayon::ThreadPoolBuilder::new().num_threads(threads.max(1)).build().map_err(|e| format!("the fluid's threads: {e}"))?;
        let fluid_particles = particles.fluid_count();
        // Potential energy gravity can release: each particle down to the domain's lowest point along g.
        let g = sph.settings.gravity;
        let domain = &plan.model.domain;
        let low = glam::DVec3::from_array(std::array::from_fn(|k| if g[k] > 0.0 { domain.max[k] } else { domain.min[k] }));
        let releasable: f64 = (0..particles.len())
            .filter(|&i| particles.kind[i] == ParticleKind::Fluid)
            .map(|i| particles.mass[i] * g.dot(low - particles.position[i]))
            .sum::<f64>()
            + sph.settings.floating.iter().map(|b| b.mass * g.dot(low - b.start.centre)).sum::<f64>();
        let phase = FluidPhase::new(sph.settings.clone(), particles)?;
        let o = phase.observables();
        let (body_kinetic, body_potential) = bodies_energy(&phase);
        let energy = EnergyBooks {
            lowest: total(&o) + body_kinetic + body_potential,
            scale: (o.kinetic_energy + o.elastic_energy + body_kinetic).max(0.01 * releasable.abs()),
        };
        let monitor = &plan.run.monitor;
        // A body force or a moving wall does work on the fluid, buffers bring energy in and
        // take it out, and coupled particles push it: its energy may grow, so it is not watched.
        let f = &sph.settings;
        let energy_growth = (monitor.enabled
            && f.body_force == glam::DVec3::ZERO
            && f.moving_walls.is_empty()
            && f.inflows.is_empty()
            && f.outflows.is_empty()
            && sph.coupling.is_none())
        .then_some(monitor.energy_growth);
        let device = if gpu {
            let fluid = tumble_gpu::GpuFluid::new(phase.settings(), phase.particles()).map_err(|e| e.to_string())?;
            let dt_limit = phase.time_step_limits().dt();
            Some(Device { fluid, pressure: Vec::new(), dt_limit })
        } else {
            None
        };
        let mut sph_phase =
            SphPhase { phase, device, probes: sph.probes.clone(), floating: sph.floating.clone(), fluid_particles, pool, energy_growth, energy };
        sph_phase.take_device_state(0.0)?;
        Ok(sph_phase)
    }

    /// Copies the GPU's state into the host's phase (sorted by its grid), with each particle's
    /// pressure; refuses a state that is not finite or moved faster than the grid allows, with
    /// the particle and a Δt that works.
    fn take_device_state(&mut self, dt: f64) -> Result<(), String> {
        let Some(device) = self.device.as_mut() else { return Ok(()) };
        let read = device.fluid.read();
        let mut snapshot = device.fluid.snapshot_of(read.particles);
        let p = &snapshot.particles;
        let time = snapshot.time;
        if let Some(i) = (0..p.len()).find(|&i| !(p.position[i].is_finite() && p.velocity[i].is_finite() && p.density[i].is_finite())) {
            return Err(tumble_sph::FluidFault::NotFinite { id: p.id[i], time }.to_string());
        }
        device.pressure = vec![0.0; p.len()];
        for (i, &id) in p.id.iter().enumerate() {
            device.pressure[id as usize] = read.pressures[i];
        }
        snapshot.list_positions = Some(p.position.clone());
        self.phase.restore(&snapshot)?;
        let fastest = read.fastest;
        device.dt_limit = read.limits.dt();
        // The device sorts every step: a particle may move 0.2 h per half step (the cells' skin);
        // a flow that fast has outrun the sound speed the step was chosen for.
        let settings = self.phase.settings();
        let skin = tumble_sph::rebuild_distance(settings.h);
        if let Some((id, speed)) = fastest
            && dt > 0.0
            && speed * dt > skin
        {
            return Err(
                tumble_sph::FluidFault::TooFast { id, time, speed, sound_speed: settings.sound_speed, dt_that_works: skin / speed }.to_string()
            );
        }
        Ok(())
    }

    /// One step of `dt` coupled to `solids` (on the CPU; see [`FluidPhase::step_coupled`]).
    pub fn advance_coupled(&mut self, dt: f64, solids: &mut dyn tumble_sph::CoupledSolids) -> Result<(), PhaseStop> {
        if self.device.is_some() {
            return Err(PhaseStop::Failed("the fluid couples to the particles on the CPU backend only so far".into()));
        }
        let phase = &mut self.phase;
        self.pool.install(|| phase.step_coupled(dt, solids)).map_err(|e| PhaseStop::Failed(e.to_string()))
    }

    /// Starts the fluid beside solids (see [`FluidPhase::couple`]).
    pub fn couple(&mut self, solids: &mut dyn tumble_sph::CoupledSolids) {
        let fraction = solids.fraction(self.phase.particles());
        self.phase.couple(fraction);
    }

    /// The fluid itself, for tests and tools.
    pub fn fluid(&self) -> &FluidPhase {
        &self.phase
    }

    fn probe_table(&self, probe: &SphProbe) -> PhaseTable {
        let p = &self.phase;
        let (columns, values): (&[&str], Vec<f64>) = match probe.kind {
            // A dry point reads zero gauge pressure and no velocity; its fluid fraction says so.
            SphProbeKind::Pressure(x) => (&["pressure", "fluid_fraction"], vec![p.pressure_at(x).unwrap_or(0.0), p.fluid_fraction(x)]),
            SphProbeKind::Velocity(x) => {
                let v = p.velocity_at(x).unwrap_or_default();
                (&["velocity_x", "velocity_y", "velocity_z", "fluid_fraction"], vec![v.x, v.y, v.z, p.fluid_fraction(x)])
            }
            SphProbeKind::Gauge { from, top } => (&["height"], vec![p.water_height(from, top)]),
            SphProbeKind::Front(d) => (&["front"], vec![p.front(d)]),
        };
        PhaseTable::line(format!("probe_{}.csv", probe.name), columns, values)
    }

    /// A floating body's row: where it is, how it is turned (the rotation vector from its start,
    /// rad), how it moves, and the fluid's force and torque on it.
    fn body_table(&self, k: usize) -> PhaseTable {
        let b = &self.phase.bodies()[k];
        let turn = b.orientation.to_scaled_axis();
        let columns = [
            "x",
            "y",
            "z",
            "rotation_x",
            "rotation_y",
            "rotation_z",
            "velocity_x",
            "velocity_y",
            "velocity_z",
            "angular_velocity_x",
            "angular_velocity_y",
            "angular_velocity_z",
            "force_x",
            "force_y",
            "force_z",
            "torque_x",
            "torque_y",
            "torque_z",
        ];
        let vectors = [b.centre, turn, b.velocity, b.angular_velocity, b.fluid_force, b.fluid_torque];
        PhaseTable::line(format!("floating_{}.csv", self.floating[k]), &columns, vectors.iter().flat_map(|v| v.to_array()).collect())
    }
}

impl SphPhase {
    /// Its tables now: fluid.csv, then each probe's and floating body's.
    pub fn tables(&self) -> Vec<PhaseTable> {
        let o = self.pool.install(|| self.phase.observables());
        let dt_limit = match &self.device {
            Some(device) => device.dt_limit,
            None => self.pool.install(|| self.phase.time_step_limits()).dt(),
        };
        let columns = [
            "fluid_particles",
            "mass",
            "kinetic_energy",
            "potential_energy",
            "elastic_energy",
            "total_energy",
            "momentum_x",
            "momentum_y",
            "momentum_z",
            "largest_density_deviation",
            "largest_speed",
            "dt_limit",
        ];
        let values = vec![
            o.fluid_particles as f64,
            o.mass,
            o.kinetic_energy,
            o.potential_energy,
            o.elastic_energy,
            o.kinetic_energy + o.potential_energy + o.elastic_energy,
            o.momentum.x,
            o.momentum.y,
            o.momentum.z,
            o.largest_density_deviation,
            o.largest_speed,
            dt_limit,
        ];
        let mut fluid = PhaseTable::line("fluid.csv", &columns, values);
        let s = self.phase.settings();
        if !(s.inflows.is_empty() && s.outflows.is_empty()) {
            // The fluid's mass changes by exactly mass_in − mass_out, its particles by particles_in − particles_out.
            let b = self.phase.buffer_books();
            let more = [("mass_in", b.inflow_mass), ("mass_out", b.outflow_mass)];
            let counts = [("particles_in", b.inflow_particles as f64), ("particles_out", b.outflow_particles as f64)];
            for (name, value) in more.into_iter().chain(counts) {
                fluid.columns.push(name.into());
                fluid.rows[0].push(value);
            }
        }
        std::iter::once(fluid)
            .chain(self.probes.iter().map(|q| self.probe_table(q)))
            .chain((0..self.floating.len()).map(|k| self.body_table(k)))
            .collect()
    }

    /// The fluid's energy monitor at an output row: why it must stop, if it must (the cause, and
    /// what would make it stable).
    fn check(&mut self) -> Result<(), String> {
        let o = self.pool.install(|| self.phase.observables());
        let (body_kinetic, body_potential) = bodies_energy(&self.phase);
        let e = total(&o) + body_kinetic + body_potential;
        let books = &mut self.energy;
        books.scale = books.scale.max(o.kinetic_energy + o.elastic_energy + body_kinetic);
        let gain = e - books.lowest;
        books.lowest = books.lowest.min(e);
        let Some(growth) = self.energy_growth else { return Ok(()) };
        if !e.is_finite() || gain <= growth * books.scale {
            return Ok(());
        }
        let s = self.phase.settings();
        let advice = match (s.density_diffusion, s.viscosity) {
            (DensityDiffusion::None, Viscosity::Laminar) => {
                "laminar viscosity without density diffusion lets pressure noise feed the flow; add density_diffusion = { model = \"fourtakas\", delta = 0.1 } or use the artificial viscosity"
            }
            (DensityDiffusion::None, _) => "add density_diffusion = { model = \"fourtakas\", delta = 0.1 }",
            _ => "raise the sound speed (sph.sound_speed_factor) or the artificial viscosity's alpha",
        };
        Err(format!(
            "the fluid's energy (kinetic + potential + elastic, with its floating bodies') grew by {gain:.4e} J by t = {:.6e} s, {:.2} times its scale {:.4e} J, without a source (run.monitor.energy_growth = {growth}): the method is unstable here; {advice}",
            self.phase.time(),
            gain / books.scale,
            books.scale
        ))
    }

    /// Its particles for a snapshot.
    pub fn points(&self) -> PhasePoints {
        let p = self.phase.particles();
        let eos = self.phase.equation_of_state();
        let walls = self.phase.pressure();
        let device_pressure = self.device.as_ref().map(|d| &d.pressure);
        let settings = self.phase.settings();
        // Sorted by id, as the particles' snapshots are.
        let mut order: Vec<usize> = (0..p.len()).collect();
        order.sort_by_key(|&i| p.id[i]);
        let pressure = |i: usize| match (p.kind[i], device_pressure) {
            (ParticleKind::Fluid, _) => eos.pressure(self.phase.intrinsic_density(i)),
            (ParticleKind::Wall, Some(by_id)) => by_id[p.id[i] as usize],
            (ParticleKind::Wall, None) => walls.get(i).copied().unwrap_or(0.0),
        };
        let mut points = PhasePoints {
            positions: order.iter().map(|&i| p.position[i]).collect(),
            scalars: vec![
                ("pressure", order.iter().map(|&i| pressure(i)).collect()),
                ("density", order.iter().map(|&i| p.density[i]).collect()),
                ("mass", order.iter().map(|&i| p.mass[i]).collect()),
                // Half the spacing: the particle as `tumble render` draws it.
                ("radius", vec![0.5 * self.phase.settings().spacing; order.len()]),
            ],
            vectors: vec![("velocity", order.iter().map(|&i| p.velocity[i]).collect())],
            integers: vec![
                // 0 fluid, 1 wall, 2 a floating body's, 3 an inflow's, 4 an outflow's particle.
                ("kind", order.iter().map(|&i| kind_number(p, i, settings)).collect()),
                ("id", order.iter().map(|&i| p.id[i] as i32).collect()),
            ],
        };
        let fraction = self.phase.fraction();
        if !fraction.is_empty() {
            points.scalars.push(("fluid_fraction", order.iter().map(|&i| fraction[i]).collect()));
        }
        points
    }
}

impl Phase for SphPhase {
    fn name(&self) -> &'static str {
        "fluid"
    }

    fn advance(&mut self, steps: u64, dt: f64) -> Result<(), PhaseStop> {
        if let Some(device) = self.device.as_mut() {
            device.fluid.advance(steps, dt);
            return self.take_device_state(dt).map_err(PhaseStop::Failed);
        }
        let phase = &mut self.phase;
        self.pool.install(|| (0..steps).try_for_each(|_| phase.step(dt))).map_err(|e| PhaseStop::Failed(e.to_string()))
    }

    fn particles(&self) -> usize {
        self.fluid_particles
    }

    fn memory_bytes(&self) -> u64 {
        self.phase.memory_bytes()
    }

    fn output(&mut self, request: OutputRequest) -> Result<PhaseOutput, PhaseStop> {
        // The starting state is written as it is.
        if request.row && !request.start {
            self.check().map_err(PhaseStop::Failed)?;
        }
        let tables = if request.row { self.tables() } else { Vec::new() };
        let series: Vec<(String, PolyData)> = if request.series { vec![("fluid".into(), self.points().poly_data())] } else { Vec::new() };
        Ok(PhaseOutput { tables, series, stop: None })
    }

    fn summary(&self) -> Vec<(String, f64)> {
        let tables = self.tables();
        let Some(fluid) = tables.first() else { return Vec::new() };
        fluid.columns.iter().cloned().zip(fluid.rows[0].iter().copied()).collect()
    }

    fn snapshot(&self) -> Vec<u8> {
        // On the GPU, the device's arrays in its order, so that it continues bit-identically.
        let fluid = match &self.device {
            Some(device) => device.fluid.snapshot(),
            None => self.phase.snapshot(),
        };
        postcard::to_stdvec(&SphSection { fluid, energy: self.energy }).expect("a fluid snapshot always encodes")
    }

    fn restore(&mut self, bytes: &[u8]) -> Result<(), String> {
        let section: SphSection = postcard::from_bytes(bytes).map_err(|e| format!("the fluid's section cannot be decoded: {e}"))?;
        match self.device.as_mut() {
            Some(device) => {
                device.fluid.restore(&section.fluid)?;
                self.take_device_state(0.0)?;
            }
            None => self.phase.restore(&section.fluid)?,
        }
        self.energy = section.energy;
        Ok(())
    }

    fn as_any(&self) -> &dyn std::any::Any {
        self
    }

    fn as_any_mut(&mut self) -> &mut dyn std::any::Any {
        self
    }
}

/// A particle's `kind` in the fluid's snapshots: 0 fluid, 1 wall, 2 a floating body's, 3 an
/// inflow buffer's, 4 an outflow buffer's particle.
fn kind_number(p: &FluidParticles, i: usize, settings: &FluidSettings) -> i32 {
    match (p.kind[i], settings.wall_role(p.wall[i])) {
        (ParticleKind::Fluid, _) => 0,
        (ParticleKind::Wall, WallRole::Fixed | WallRole::Moving(_)) => 1,
        (ParticleKind::Wall, WallRole::Body(_)) => 2,
        (ParticleKind::Wall, WallRole::Inflow(_)) => 3,
        (ParticleKind::Wall, WallRole::Outflow(_)) => 4,
    }
}
