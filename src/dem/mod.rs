//! The DEM's particles as a phase of a run: a [`Backend`] (the CPU's or the GPU's) that steps
//! them, the sources that insert particles at their steps, the instability monitor, and what
//! only particles have: walls' loads and power, drums, servos, wear, flow planes, outlets,
//! tracked particles, agglomerates, and the particles', bodies', walls' and contacts' snapshot
//! series.

pub mod rows;

use crate::agglomerates::AgglomerateStats;
use crate::feeder::{Feeder, FeederBooks};
use crate::monitor::Monitor;
use crate::vtk;
use rows::ExtraRows;
use serde::{Deserialize, Serialize};
use std::any::Any;
use tumble_scene::Plan;
use tumble_state::{Backend, Frame, OutputRequest, Phase, PhaseOutput, PhaseStop, PhaseTable, PolyData, State};

/// The DEM phase: its backend and the run's books of it.
pub struct DemPhase {
    backend: Box<dyn Backend>,
    /// The plan's particle sources (None without any).
    feeder: Option<Feeder>,
    /// Why an insertion was refused (the backend's capacity); the run stops there.
    feed_error: Option<String>,
    books: DemBooks,
    /// Flow planes and agglomerates need the particle arrays at every output row; nothing else does.
    rows_need_state: bool,
}

/// What the run keeps of the DEM besides its backend's state and its sources' books (the
/// checkpoint section holds both).
#[derive(Serialize, Deserialize)]
struct DemBooks {
    /// Particles at the run's start.
    initial_particles: usize,
    /// Set up from the run's first row.
    monitor: Option<Monitor>,
    extra: ExtraRows,
    last_agglomerates: Option<AgglomerateStats>,
}

impl DemPhase {
    /// The phase of `backend`; the sources' events due at its current step run now.
    pub fn new(backend: Box<dyn Backend>) -> Self {
        let plan = backend.plan();
        let rows_need_state = !plan.model.flow_planes.is_empty() || plan.run.agglomerates;
        let books = DemBooks { initial_particles: 0, monitor: None, extra: ExtraRows::new(plan), last_agglomerates: None };
        let feeder = Feeder::new(backend.as_ref());
        let mut dem = DemPhase { backend, feeder, feed_error: None, books, rows_need_state };
        dem.feed();
        dem
    }

    /// Runs the insertion events due now.
    fn feed(&mut self) {
        if let Some(f) = self.feeder.as_mut()
            && self.feed_error.is_none()
            && let Err(e) = f.feed(self.backend.as_mut())
        {
            self.feed_error = Some(e);
        }
    }

    pub fn backend(&self) -> &dyn Backend {
        self.backend.as_ref()
    }

    pub fn backend_mut(&mut self) -> &mut dyn Backend {
        self.backend.as_mut()
    }

    pub fn plan(&self) -> &Plan {
        self.backend.plan()
    }

    /// The sources' books (inserted counts and masses, generator states).
    pub fn feeder_books(&self) -> Option<&FeederBooks> {
        self.feeder.as_ref().map(Feeder::books)
    }

    /// Why a source could not insert (the backend's capacity ran out), if it could not.
    pub fn feed_error(&self) -> Option<&str> {
        self.feed_error.as_deref()
    }

    /// Per source: particles inserted so far and their mass.
    pub fn inserted(&self) -> Vec<(u64, f64)> {
        crate::feeder::inserted(self.feeder_books())
    }

    /// Kinetic and potential energy the sources have brought in so far, J.
    pub fn inserted_energy(&self) -> f64 {
        crate::feeder::inserted_energy(self.feeder_books())
    }

    /// Particles at the run's start (known from its first row).
    pub fn initial_particles(&self) -> usize {
        self.books.initial_particles
    }

    /// Agglomerate statistics at the last row, when the plan writes agglomerates.csv.
    pub fn last_agglomerates(&self) -> Option<&AgglomerateStats> {
        self.books.last_agglomerates.as_ref()
    }

    /// The snapshot series of the frame's particles (`state`) and the walls now.
    fn series(&self, state: &State, beside_fluid: bool) -> Vec<(String, PolyData)> {
        let plan = self.plan();
        let mut series = Vec::new();
        // A scene of fluid alone has no particle series.
        if !(beside_fluid && plan.model.sources.is_empty() && state.is_empty()) {
            let mut data = vtk::particles_vtp(state, plan.model.gravity);
            if plan.coupling().is_some() {
                // The coupled fluid's force on each particle (in id order, as the points are).
                let held = self.backend.external_forces();
                let mut ids = state.id.clone();
                ids.sort_unstable();
                let force = ids.iter().flat_map(|&id| held.get(id as usize).copied().unwrap_or_default().to_array()).collect();
                data.point_data.push(tumble_state::Array::f64("fluid_force", 3, force));
            }
            series.push(("particles".to_string(), data));
        }
        if plan.model.polyhedra {
            series.push(("bodies".to_string(), vtk::bodies_vtp(plan, state)));
        }
        let walls = self.backend.walls();
        if vtk::wall_series(plan) {
            let loads = tumble_cpu::network::mesh_loads(&plan.model, state, &walls);
            let mut data = vtk::walls_vtp(plan, &walls, Some(&loads));
            vtk::add_wear(&mut data, &walls, &self.backend.mesh_wear());
            series.push(("walls".to_string(), data));
        }
        if plan.run.contacts {
            series.push(("contacts".to_string(), vtk::contacts::contacts_vtp(plan, state, &walls)));
        }
        series
    }
}

impl Phase for DemPhase {
    fn name(&self) -> &'static str {
        "particles"
    }

    /// Steps, stopping at each source's insertion steps to insert.
    fn advance(&mut self, steps: u64, _dt: f64) -> Result<(), PhaseStop> {
        let end = self.backend.steps() + steps;
        while self.backend.steps() < end && self.feed_error.is_none() {
            let next = self.feeder.as_ref().and_then(|f| f.next_step(self.backend.plan())).filter(|&s| s > self.backend.steps());
            let stop = next.map_or(end, |s| s.min(end));
            self.backend.advance(stop - self.backend.steps());
            if self.backend.steps() != stop {
                break;
            }
            self.feed();
        }
        if let Some(fault) = self.backend.fault() {
            let why = fault.to_string();
            return Err(PhaseStop::Capacity(self.books.monitor.as_ref().map_or_else(|| why.clone(), |m| m.explain_fault(why.clone()))));
        }
        match &self.feed_error {
            Some(e) => Err(PhaseStop::Capacity(e.clone())),
            None => Ok(()),
        }
    }

    fn particles(&self) -> usize {
        self.backend.particles()
    }

    fn memory_bytes(&self) -> u64 {
        self.backend.memory_bytes()
    }

    fn output(&mut self, request: OutputRequest) -> Result<PhaseOutput, PhaseStop> {
        let start = request.start;
        // One frame (one read-back on a device) serves the monitor, the rows and the snapshot.
        let with_state = start || (request.row && self.rows_need_state) || request.series;
        let mut out = PhaseOutput::default();
        let frame = self.backend.frame(with_state);
        let o = frame.observables;
        let plan = self.backend.plan();
        if start {
            let state = frame.state.as_deref().expect("asked for the state");
            self.books.initial_particles = self.backend.particles();
            self.books.monitor = Some(Monitor::new(plan, &o, crate::run::potential_range(plan, state)));
        }
        if request.row {
            row_tables(self.backend.as_ref(), self.feeder.as_ref().map(Feeder::books), &mut self.books, &frame, start, &mut out)?;
        }
        // Never write NaN: a non-finite state is stopped by the monitor at the next output.
        if request.series
            && (o.finite || start)
            && !matches!(out.stop, Some(PhaseStop::Lost(_)))
            && let Some(state) = frame.state.as_deref()
        {
            out.series = self.series(state, plan.sph.is_some());
        }
        if start && let Some(Err(e)) = self.books.monitor.as_ref().map(|m| m.check(0, &o)) {
            // The starting state is written, then refused.
            out.stop = Some(PhaseStop::Unstable(e));
        }
        Ok(out)
    }

    fn fixed_series(&self) -> Vec<(String, PolyData)> {
        let plan = self.plan();
        if plan.model.walls.is_empty() || vtk::wall_series(plan) {
            return Vec::new();
        }
        vec![("walls.vtp".to_string(), vtk::walls_vtp(plan, &plan.model.walls, None))]
    }

    fn summary(&self) -> Vec<(String, f64)> {
        Vec::new()
    }

    fn snapshot(&self) -> Vec<u8> {
        postcard::to_stdvec(&(&self.books, self.feeder_books())).expect("the books always encode")
    }

    fn restore(&mut self, bytes: &[u8]) -> Result<(), String> {
        let (books, feeder): (DemBooks, Option<FeederBooks>) =
            postcard::from_bytes(bytes).map_err(|e| format!("the particles' books cannot be decoded: {e}"))?;
        if let (Some(f), Some(b)) = (self.feeder.as_mut(), feeder) {
            f.set_books(b);
        }
        self.books = books;
        Ok(())
    }

    fn as_any(&self) -> &dyn Any {
        self
    }

    fn as_any_mut(&mut self) -> &mut dyn Any {
        self
    }
}

/// The output row's tables from `frame`, after the checks a row makes (none at the start); a
/// stop found after the first table ends the list there.
fn row_tables(
    backend: &dyn Backend,
    feeder: Option<&FeederBooks>,
    books: &mut DemBooks,
    frame: &Frame,
    start: bool,
    out: &mut PhaseOutput,
) -> Result<(), PhaseStop> {
    let (o, plan) = (&frame.observables, backend.plan());
    let inserted = crate::feeder::inserted(feeder);
    if !start && let Some(monitor) = &books.monitor {
        monitor.check_with_inserted(backend.steps(), o, crate::feeder::inserted_energy(feeder)).map_err(PhaseStop::Unstable)?;
    }
    let inserted_count: usize = inserted.iter().map(|s| s.0 as usize).sum();
    let extra = books.extra.row(backend, inserted, frame);
    out.tables.push(rows::observables_table(plan, o, backend.removed(), &extra));
    if !start {
        if let Some(text) = extra.flood {
            out.stop = Some(PhaseStop::Lost(text));
            return Ok(());
        }
        if let Some(text) = crate::run::too_many_lost(plan, backend.removed(), books.initial_particles + inserted_count, o.time) {
            out.stop = Some(PhaseStop::Lost(text));
            return Ok(());
        }
        let energy = o.kinetic_energy + o.rotational_energy;
        out.stop = plan.run.end_when.filter(|e| o.time >= e.after && energy < e.kinetic_energy_below).map(|e| {
            PhaseStop::Ended(format!(
                "the particles' kinetic energy {energy:.3e} J fell below run.end_when.kinetic_energy_below = {:e} J at t = {:.6e} s",
                e.kinetic_energy_below, o.time
            ))
        });
    }
    out.tables.push(rows::tracks_table(plan, &frame.tracks));
    if let Some(state) = frame.state.as_deref().filter(|_| plan.run.agglomerates) {
        let a = crate::run::agglomerates_of(plan, state);
        let particles = books.initial_particles;
        let values = crate::agglomerates::csv_values(&a, crate::agglomerates::histogram_bins(particles));
        out.tables.push(PhaseTable { file: "agglomerates.csv".into(), columns: crate::agglomerates::csv_columns(particles), rows: vec![values] });
        books.last_agglomerates = Some(a);
    }
    Ok(())
}
