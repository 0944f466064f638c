//! The SPH fluid as a phase of a run: tumble-sph's [`FluidPhase`] stepped on the run's threads,
//! its sums and probes as output tables (`fluid.csv`, `probe_<name>.csv`), its particles as the
//! `fluid` snapshot series.

use tumble_scene::{SphPlan, SphProbe, SphProbeKind};
use tumble_sph::{FluidParticles, FluidPhase, FluidSnapshot, ParticleKind};
use tumble_state::{Phase, PhasePoints, PhaseTable};

/// A fluid phase and what the scene measures in it.
pub struct SphPhase {
    phase: FluidPhase,
    probes: Vec<SphProbe>,
    fluid_particles: usize,
    pool: rayon::ThreadPool,
}

impl SphPhase {
    /// The phase of `plan` over its starting `particles`, stepped on `threads` threads (its
    /// results do not depend on how many).
    pub fn new(plan: &SphPlan, particles: FluidParticles, threads: usize) -> Result<Self, String> {
        let pool = rayon::ThreadPoolBuilder::new().num_threads(threads.max(1)).build().map_err(|e| format!("the fluid's threads: {e}"))?;
        let fluid_particles = particles.fluid_count();
        Ok(SphPhase { phase: FluidPhase::new(plan.settings.clone(), particles)?, probes: plan.probes.clone(), fluid_particles, pool })
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
        PhaseTable { file: format!("probe_{}.csv", probe.name), columns: columns.iter().map(|c| c.to_string()).collect(), values }
    }
}

impl Phase for SphPhase {
    fn name(&self) -> &'static str {
        "fluid"
    }

    fn advance(&mut self, steps: u64, dt: f64) -> Result<(), String> {
        let phase = &mut self.phase;
        self.pool.install(|| (0..steps).try_for_each(|_| phase.step(dt))).map_err(|e| e.to_string())
    }

    fn particles(&self) -> usize {
        self.fluid_particles
    }

    fn memory_bytes(&self) -> u64 {
        self.phase.memory_bytes()
    }

    fn tables(&self) -> Vec<PhaseTable> {
        let o = self.pool.install(|| self.phase.observables());
        let limit = self.pool.install(|| self.phase.time_step_limits());
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
            limit.dt(),
        ];
        let fluid = PhaseTable { file: "fluid.csv".into(), columns: columns.iter().map(|c| c.to_string()).collect(), values };
        std::iter::once(fluid).chain(self.probes.iter().map(|q| self.probe_table(q))).collect()
    }

    fn points(&self) -> PhasePoints {
        let p = self.phase.particles();
        let eos = self.phase.equation_of_state();
        let walls = self.phase.pressure();
        // Sorted by id, as the particles' snapshots are.
        let mut order: Vec<usize> = (0..p.len()).collect();
        order.sort_by_key(|&i| p.id[i]);
        let pressure = |i: usize| match p.kind[i] {
            ParticleKind::Fluid => eos.pressure(p.density[i]),
            ParticleKind::Wall => walls.get(i).copied().unwrap_or(0.0),
        };
        PhasePoints {
            positions: order.iter().map(|&i| p.position[i]).collect(),
            scalars: vec![
                ("pressure", order.iter().map(|&i| pressure(i)).collect()),
                ("density", order.iter().map(|&i| p.density[i]).collect()),
                ("mass", order.iter().map(|&i| p.mass[i]).collect()),
            ],
            vectors: vec![("velocity", order.iter().map(|&i| p.velocity[i]).collect())],
            integers: vec![
                ("kind", order.iter().map(|&i| if p.kind[i] == ParticleKind::Fluid { 0 } else { 1 }).collect()),
                ("id", order.iter().map(|&i| p.id[i] as i32).collect()),
            ],
        }
    }

    fn snapshot(&self) -> Vec<u8> {
        postcard::to_stdvec(&self.phase.snapshot()).expect("a fluid snapshot always encodes")
    }

    fn restore(&mut self, bytes: &[u8]) -> Result<(), String> {
        let snapshot: FluidSnapshot = postcard::from_bytes(bytes).map_err(|e| format!("the fluid's section cannot be decoded: {e}"))?;
        self.phase.restore(&snapshot)
    }
}
