//! Output files: observables.csv and tracks.csv (docs/cli.md, "Outputs").

use crate::{DrumProfile, Observables, TrackRow};
use std::fs::File;
use std::io::{BufWriter, Write};
use std::path::Path;
use tumble_scene::Plan;

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
    pub wall_loads: Vec<(glam::DVec3, glam::DVec3)>,
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

/// Opens `name` in `dir`: a new file that `header` starts, or, for a resumed run, the file
/// as it is (already cut back to the checkpoint's rows) for appending.
fn open_csv(
    dir: &Path,
    name: &str,
    append: bool,
    header: impl FnOnce(&mut BufWriter<File>) -> std::io::Result<()>,
) -> std::io::Result<BufWriter<File>> {
    let path = dir.join(name);
    if append {
        return Ok(BufWriter::new(std::fs::OpenOptions::new().append(true).open(path)?));
    }
    let mut w = BufWriter::new(File::create(path)?);
    header(&mut w)?;
    w.flush()?;
    Ok(w)
}

/// observables.csv, one row per output interval.
pub struct ObservablesCsv(BufWriter<File>);

impl ObservablesCsv {
    /// Header: the fixed columns, `fluid_work` with a fluid, then `power_<wall>` per moving wall
    /// and `wall_work`, `servo_<wall>` per servo wall, `wear_<wall>` per wearing mesh, then per wall group `fx_<g>,fy_<g>,fz_<g>,tx_<g>,ty_<g>,tz_<g>`, then per drum `charge_mass_<d>,com_angle_<d>,com_radius_<d>,toe_<d>,shoulder_<d>,torque_arm_power_<d>`,
    /// then per flow plane `flow_<p>,mass_<p>`, per source `inserted_<s>,inserted_mass_<s>`, per
    /// outlet `deleted_<o>,deleted_mass_<o>,outlet_rate_<o>`.
    /// The file, new or (`append`) continued.
    pub fn open(dir: &Path, plan: &Plan, append: bool) -> std::io::Result<Self> {
        open_csv(dir, "observables.csv", append, |w| Self::header(w, plan)).map(ObservablesCsv)
    }

    fn header(w: &mut BufWriter<File>, plan: &Plan) -> std::io::Result<()> {
        write!(w, "t,kinetic_energy,rotational_energy,potential_energy,elastic_energy,dissipated_energy,contacts,max_overlap_ratio,removed")?;
        if plan.model.fluid.is_some() {
            write!(w, ",fluid_work")?;
        }
        let moving: Vec<&str> = plan.model.wall_groups.iter().filter(|g| g.moving).map(|g| g.name.as_str()).collect();
        for g in &moving {
            write!(w, ",power_{g}")?;
        }
        if !moving.is_empty() {
            write!(w, ",wall_work")?;
        }
        for g in plan.model.wall_groups.iter().filter(|g| g.servo.is_some()) {
            write!(w, ",servo_{}", g.name)?;
        }
        for wall in plan.model.walls.iter().filter(|w| w.wear > 0.0) {
            write!(w, ",wear_{}", wall.name)?;
        }
        for g in &plan.model.wall_groups {
            write!(w, ",fx_{0},fy_{0},fz_{0},tx_{0},ty_{0},tz_{0}", g.name)?;
        }
        for d in &plan.model.drums {
            let n = &d.name;
            write!(w, ",charge_mass_{n},com_angle_{n},com_radius_{n},toe_{n},shoulder_{n},torque_arm_power_{n}")?;
        }
        for p in &plan.model.flow_planes {
            write!(w, ",flow_{0},mass_{0}", p.name)?;
        }
        for s in &plan.model.sources {
            write!(w, ",inserted_{0},inserted_mass_{0}", s.name)?;
        }
        for o in &plan.model.outlets {
            write!(w, ",deleted_{0},deleted_mass_{0},outlet_rate_{0}", o.name)?;
        }
        writeln!(w)
    }

    /// One row; `removed` counts the particles that have left the domain since t = 0.
    pub fn row(&mut self, o: &Observables, fluid: bool, removed: usize, extra: &ExtraColumns) -> std::io::Result<()> {
        write!(
            self.0,
            "{},{},{},{},{},{},{},{},{removed}",
            o.time, o.kinetic_energy, o.rotational_energy, o.potential_energy, o.elastic_energy, o.dissipated_energy, o.contacts, o.max_overlap_ratio
        )?;
        if fluid {
            write!(self.0, ",{}", o.fluid_work)?;
        }
        for p in &extra.power {
            write!(self.0, ",{p}")?;
        }
        if !extra.power.is_empty() {
            write!(self.0, ",{}", o.wall_work)?;
        }
        for x in extra.servo.iter().chain(&extra.wear) {
            write!(self.0, ",{x}")?;
        }
        for (f, t) in &extra.wall_loads {
            write!(self.0, ",{},{},{},{},{},{}", f.x, f.y, f.z, t.x, t.y, t.z)?;
        }
        for d in &extra.drums {
            let c = |x: f64| Cell(x);
            write!(self.0, ",{},{},{},{},{},{}", c(d.charge_mass), c(d.com_angle), c(d.com_radius), c(d.toe), c(d.shoulder), c(d.torque_arm_power))?;
        }
        for (rate, mass) in &extra.flow {
            write!(self.0, ",{rate},{mass}")?;
        }
        for (count, mass) in &extra.inserted {
            write!(self.0, ",{count},{mass}")?;
        }
        for (count, mass, rate) in &extra.outlets {
            write!(self.0, ",{count},{mass},{rate}")?;
        }
        writeln!(self.0)?;
        // Flushed every row so an interrupted or stopped run leaves complete rows.
        self.0.flush()
    }
}

/// A drum column's value, or an empty cell where it is undefined (NaN: no charge in the drum,
/// or too few particles in its shell layer for a toe and shoulder).
struct Cell(f64);

impl std::fmt::Display for Cell {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        if self.0.is_finite() { write!(f, "{}", self.0) } else { Ok(()) }
    }
}

/// tracks.csv, one row per tracked particle per output interval.
/// Scenes with polyhedra append the orientation quaternion `qw,qx,qy,qz`.
pub struct TracksCsv {
    w: BufWriter<File>,
    orientation: bool,
}

impl TracksCsv {
    /// The file, new or (`append`) continued.
    pub fn open(dir: &Path, plan: &tumble_scene::Plan, append: bool) -> std::io::Result<Self> {
        let orientation = plan.model.polyhedra;
        let w =
            open_csv(dir, "tracks.csv", append, |w| writeln!(w, "t,id,x,y,z,vx,vy,vz,wx,wy,wz{}", if orientation { ",qw,qx,qy,qz" } else { "" }))?;
        Ok(TracksCsv { w, orientation })
    }

    pub fn rows(&mut self, t: f64, rows: &[TrackRow]) -> std::io::Result<()> {
        for r in rows {
            let (x, v, w) = (r.position, r.velocity, r.angular_velocity);
            write!(self.w, "{t},{},{},{},{},{},{},{},{},{},{}", r.id, x.x, x.y, x.z, v.x, v.y, v.z, w.x, w.y, w.z)?;
            if self.orientation {
                let q = r.orientation;
                write!(self.w, ",{},{},{},{}", q.w, q.x, q.y, q.z)?;
            }
            writeln!(self.w)?;
        }
        self.w.flush()
    }
}

/// agglomerates.csv, one row per output interval (see `crate::agglomerates::csv_header`).
pub struct AgglomeratesCsv {
    w: BufWriter<File>,
    bins: usize,
}

impl AgglomeratesCsv {
    /// The file, new or (`append`) continued; `particles` at the start sets the histogram's bins.
    pub fn open(dir: &Path, particles: usize, append: bool) -> std::io::Result<Self> {
        let w = open_csv(dir, "agglomerates.csv", append, |w| writeln!(w, "{}", crate::agglomerates::csv_header(particles)))?;
        Ok(AgglomeratesCsv { w, bins: crate::agglomerates::histogram_bins(particles) })
    }

    pub fn row(&mut self, t: f64, s: &crate::agglomerates::AgglomerateStats) -> std::io::Result<()> {
        writeln!(self.w, "{}", crate::agglomerates::csv_row(t, s, self.bins))?;
        self.w.flush()
    }
}

/// The phases' tables (`fluid.csv`, `probe_<name>.csv`): each file opened at its first row.
pub struct PhaseCsv {
    dir: std::path::PathBuf,
    append: bool,
    files: Vec<(String, BufWriter<File>)>,
}

impl PhaseCsv {
    /// Files in `dir`, new or (`append`) continued.
    pub fn open(dir: &Path, append: bool) -> Self {
        PhaseCsv { dir: dir.to_path_buf(), append, files: Vec::new() }
    }

    /// One row at time `t` in each table's file (header `t,<columns>` on a new file).
    pub fn row(&mut self, t: f64, tables: &[tumble_state::PhaseTable]) -> std::io::Result<()> {
        for table in tables {
            let k = match self.files.iter().position(|(f, _)| *f == table.file) {
                Some(k) => k,
                None => {
                    let w = open_csv(&self.dir, &table.file, self.append, |w| writeln!(w, "t,{}", table.columns.join(",")))?;
                    self.files.push((table.file.clone(), w));
                    self.files.len() - 1
                }
            };
            let w = &mut self.files[k].1;
            write!(w, "{t}")?;
            for v in &table.values {
                write!(w, ",{v}")?;
            }
            writeln!(w)?;
            w.flush()?;
        }
        Ok(())
    }

    /// The files written so far.
    pub fn names(&self) -> impl Iterator<Item = &str> {
        self.files.iter().map(|(f, _)| f.as_str())
    }
}
