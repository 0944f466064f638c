//! The DEM's output tables: observables.csv (the fixed columns, then the walls', drums', flow
//! planes', sources' and outlets'), tracks.csv and agglomerates.csv (docs/cli.md, "Outputs").

use crate::flow::FlowCounter;
use crate::{DrumProfile, Observables, TrackRow};
use glam::DVec3;
use serde::{Deserialize, Serialize};
use tumble_scene::Plan;
use tumble_state::{Backend, Frame, OutletTally, PhaseTable};

/// The columns observables.csv adds for moving walls, drums and flow planes.
#[derive(Clone, Debug, Default)]
pub struct ExtraColumns {
    /// Per moving wall group: mean power over the output interval, W.
    pub power: Vec<f64>,
    /// Per servo wall: its offset along the servo's direction from its t = 0 pose, m.
    pub servo: Vec<f64>,
    /// Per wearing mesh wall: the volume worn off it since t = 0, m³.
    pub wear: Vec<f64>,
    /// Per wall group (all of them): force on it and torque about its reference point at the
    /// row's force pass, N and N·m.
    pub wall_loads: Vec<(DVec3, DVec3)>,
    pub drums: Vec<DrumProfile>,
    /// Per flow plane: (rate kg/s over the output interval, net mass since t = 0 kg).
    pub flow: Vec<(f64, f64)>,
    /// Per source: particles inserted and their mass since t = 0.
    pub inserted: Vec<(u64, f64)>,
    /// Per outlet: particles deleted and their mass since t = 0, and the mass rate over the
    /// output interval, kg/s.
    pub outlets: Vec<(u64, f64, f64)>,
    /// Why the run stops: an outlet deleted more than `run.max_outlet_fraction` of the particles
    /// in the interval (not a column).
    pub flood: Option<String>,
}

/// observables.csv's columns after `t`: the fixed ones, `fluid_work` with a prescribed fluid,
/// then `power_<wall>` per moving wall group and `wall_work`, `servo_<wall>` per servo wall,
/// `wear_<wall>` per wearing mesh, per wall group `fx_<g>,fy_<g>,fz_<g>,tx_<g>,ty_<g>,tz_<g>`,
/// per drum `charge_mass_<d>,com_angle_<d>,com_radius_<d>,toe_<d>,shoulder_<d>,torque_arm_power_<d>`,
/// per flow plane `flow_<p>,mass_<p>`, per source `inserted_<s>,inserted_mass_<s>`, per outlet
/// `deleted_<o>,deleted_mass_<o>,outlet_rate_<o>`.
pub fn observables_columns(plan: &Plan) -> Vec<String> {
    let mut c: Vec<String> = [
        "kinetic_energy",
        "rotational_energy",
        "potential_energy",
        "elastic_energy",
        "dissipated_energy",
        "contacts",
        "max_overlap_ratio",
        "removed",
    ]
    .iter()
    .map(|s| s.to_string())
    .collect();
    let m = &plan.model;
    if m.fluid.is_some() {
        c.push("fluid_work".into());
    }
    let moving: Vec<&str> = m.wall_groups.iter().filter(|g| g.moving).map(|g| g.name.as_str()).collect();
    c.extend(moving.iter().map(|g| format!("power_{g}")));
    if !moving.is_empty() {
        c.push("wall_work".into());
    }
    c.extend(m.wall_groups.iter().filter(|g| g.servo.is_some()).map(|g| format!("servo_{}", g.name)));
    c.extend(m.walls.iter().filter(|w| w.wear > 0.0).map(|w| format!("wear_{}", w.name)));
    for g in &m.wall_groups {
        c.extend(["fx", "fy", "fz", "tx", "ty", "tz"].map(|k| format!("{k}_{}", g.name)));
    }
    for d in &m.drums {
        c.extend(["charge_mass", "com_angle", "com_radius", "toe", "shoulder", "torque_arm_power"].map(|k| format!("{k}_{}", d.name)));
    }
    for p in &m.flow_planes {
        c.extend(["flow", "mass"].map(|k| format!("{k}_{}", p.name)));
    }
    for s in &m.sources {
        c.extend(["inserted", "inserted_mass"].map(|k| format!("{k}_{}", s.name)));
    }
    for o in &m.outlets {
        c.extend(["deleted", "deleted_mass", "outlet_rate"].map(|k| format!("{k}_{}", o.name)));
    }
    c
}

/// observables.csv's line: `removed` counts the particles that have left the domain since
/// t = 0. A drum's undefined value (no charge, or too few particles in its shell layer for a
/// toe and shoulder) is NaN: an empty cell.
pub fn observables_table(plan: &Plan, o: &Observables, removed: usize, extra: &ExtraColumns) -> PhaseTable {
    let mut v = vec![
        o.kinetic_energy,
        o.rotational_energy,
        o.potential_energy,
        o.elastic_energy,
        o.dissipated_energy,
        o.contacts as f64,
        o.max_overlap_ratio,
        removed as f64,
    ];
    if plan.model.fluid.is_some() {
        v.push(o.fluid_work);
    }
    v.extend(&extra.power);
    if !extra.power.is_empty() {
        v.push(o.wall_work);
    }
    v.extend(extra.servo.iter().chain(&extra.wear));
    for (f, t) in &extra.wall_loads {
        v.extend([f.x, f.y, f.z, t.x, t.y, t.z]);
    }
    for d in &extra.drums {
        v.extend([d.charge_mass, d.com_angle, d.com_radius, d.toe, d.shoulder, d.torque_arm_power]);
    }
    for (rate, mass) in &extra.flow {
        v.extend([*rate, *mass]);
    }
    for (count, mass) in &extra.inserted {
        v.extend([*count as f64, *mass]);
    }
    for (count, mass, rate) in &extra.outlets {
        v.extend([*count as f64, *mass, *rate]);
    }
    PhaseTable { file: "observables.csv".into(), columns: observables_columns(plan), rows: vec![v] }
}

/// tracks.csv: a line per tracked particle. Scenes with polyhedra append the orientation
/// quaternion `qw,qx,qy,qz`.
pub fn tracks_table(plan: &Plan, rows: &[TrackRow]) -> PhaseTable {
    let orientation = plan.model.polyhedra;
    let mut columns = vec!["id", "x", "y", "z", "vx", "vy", "vz", "wx", "wy", "wz"];
    if orientation {
        columns.extend(["qw", "qx", "qy", "qz"]);
    }
    let lines = rows
        .iter()
        .map(|r| {
            let (x, v, w) = (r.position, r.velocity, r.angular_velocity);
            let mut line = vec![r.id as f64, x.x, x.y, x.z, v.x, v.y, v.z, w.x, w.y, w.z];
            if orientation {
                let q = r.orientation;
                line.extend([q.w, q.x, q.y, q.z]);
            }
            line
        })
        .collect();
    PhaseTable { file: "tracks.csv".into(), columns: columns.iter().map(|c| c.to_string()).collect(), rows: lines }
}

/// Wall power (mean over the output interval), drum profiles, flow-plane counts, sources and outlets.
#[derive(Serialize, Deserialize)]
pub(crate) struct ExtraRows {
    moving: Vec<usize>,
    last: Option<(f64, Vec<f64>)>,
    flow: Option<FlowCounter>,
    /// The outlets' books at the last row.
    last_outlets: Option<OutletBooks>,
}

/// What the outlets had deleted by the last row.
#[derive(Serialize, Deserialize)]
struct OutletBooks {
    time: f64,
    /// Per outlet: particles deleted and their mass since t = 0.
    deleted: Vec<(u64, f64)>,
}

/// Per outlet of `backend`'s plan: particles deleted so far and their mass.
pub(crate) fn outlet_tallies(backend: &dyn Backend) -> Vec<OutletTally> {
    if backend.plan().model.outlets.is_empty() { Vec::new() } else { backend.outlet_tallies() }
}

impl ExtraRows {
    pub(crate) fn new(plan: &Plan) -> Self {
        let moving = (0..plan.model.wall_groups.len()).filter(|&g| plan.model.wall_groups[g].moving).collect();
        ExtraRows { moving, last: None, flow: None, last_outlets: None }
    }

    /// Why the run must stop because an outlet deleted more than `run.max_outlet_fraction` of
    /// the particles since the last row (of those there would be now had no outlet deleted
    /// any): an outlet whose normal points into the particles, or whose box holds them.
    fn outlet_flood(&self, plan: &Plan, tallies: &[OutletTally], particles: usize, t: f64) -> Option<String> {
        let before = |k: usize| self.last_outlets.as_ref().map_or((0, 0.0), |last| last.deleted[k]);
        let since: Vec<u64> = tallies.iter().enumerate().map(|(k, o)| o.count - before(k).0).collect();
        let present = particles as u64 + since.iter().sum::<u64>();
        let limit = plan.run.max_outlet_fraction;
        let (k, &deleted) = since.iter().enumerate().max_by_key(|(_, d)| **d)?;
        if deleted as f64 <= limit * present as f64 {
            return None;
        }
        let from = self.last_outlets.as_ref().map_or(0.0, |last| last.time);
        Some(format!(
            "outlet \"{}\" deleted {deleted} of {present} particles ({:.1} %) between t = {from:.6e} and {t:.6e} s, more than run.max_outlet_fraction = {limit} allows: check that its plane's normal points away from the particles, or its box lies where they leave (set run.max_outlet_fraction = 1 if emptying the domain at once is intended)",
            plan.model.outlets[k].name,
            100.0 * deleted as f64 / present as f64
        ))
    }

    /// The extra columns of `backend`'s row now (the first row starts the flow count);
    /// `inserted`: per source, particles inserted and their mass.
    pub(crate) fn row(&mut self, backend: &dyn Backend, inserted: Vec<(u64, f64)>, frame: &Frame) -> ExtraColumns {
        let (plan, t) = (backend.plan(), backend.time());
        let tallies = outlet_tallies(backend);
        let outlets = tallies
            .iter()
            .enumerate()
            .map(|(k, o)| {
                let rate = match &self.last_outlets {
                    Some(last) if t > last.time => (o.mass - last.deleted[k].1) / (t - last.time),
                    _ => 0.0,
                };
                (o.count, o.mass, rate)
            })
            .collect();
        let flood = self.outlet_flood(plan, &tallies, frame.observables.particles, t);
        if !tallies.is_empty() {
            self.last_outlets = Some(OutletBooks { time: t, deleted: tallies.iter().map(|o| (o.count, o.mass)).collect() });
        }
        // Nothing else to add.
        if plan.model.wall_groups.is_empty() && plan.model.drums.is_empty() && plan.model.flow_planes.is_empty() {
            return ExtraColumns { inserted, outlets, flood, ..Default::default() };
        }
        let work = &frame.wall_work;
        let power = match &self.last {
            // Mean power since the last row: Δ(work) / Δt.
            Some((t0, w0)) if t > *t0 => self.moving.iter().map(|&g| (work[g] - w0[g]) / (t - t0)).collect(),
            // The first row: the power of the initial force pass.
            _ => self.moving.iter().map(|&g| frame.wall_power[g]).collect(),
        };
        self.last = Some((t, work.clone()));
        let flow = match (frame.state.as_deref(), plan.model.flow_planes.is_empty()) {
            (Some(s), false) => match self.flow.as_mut() {
                Some(f) => f.update_state(plan, s, t),
                None => {
                    let f = self.flow.insert(FlowCounter::from_state(plan, s, t));
                    f.mass.iter().map(|&m| (0.0, m)).collect()
                }
            },
            _ => Vec::new(),
        };
        let wall_loads = frame.wall_force.iter().copied().zip(frame.wall_torque.iter().copied()).collect();
        let servo = plan.model.wall_groups.iter().enumerate().filter(|(_, g)| g.servo.is_some()).map(|(k, _)| frame.servo_offset[k]).collect();
        let wear = backend.mesh_wear().iter().zip(&plan.model.walls).filter(|(_, w)| w.wear > 0.0).map(|(t, _)| t.iter().sum()).collect();
        ExtraColumns { power, servo, wear, wall_loads, drums: frame.drums.clone(), flow, inserted, outlets, flood }
    }
}
