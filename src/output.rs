//! Output files: observables.csv and tracks.csv (scene-and-cli.md, "Outputs").

use crate::{Observables, TrackRow};
use std::fs::File;
use std::io::{BufWriter, Write};
use std::path::Path;

/// observables.csv, one row per output interval.
pub struct ObservablesCsv(BufWriter<File>);

impl ObservablesCsv {
    pub fn create(dir: &Path, fluid: bool) -> std::io::Result<Self> {
        let mut w = BufWriter::new(File::create(dir.join("observables.csv"))?);
        write!(w, "t,kinetic_energy,rotational_energy,potential_energy,elastic_energy,dissipated_energy,contacts,max_overlap_ratio")?;
        if fluid {
            write!(w, ",fluid_work")?;
        }
        writeln!(w)?;
        Ok(ObservablesCsv(w))
    }

    pub fn row(&mut self, o: &Observables, fluid: bool) -> std::io::Result<()> {
        write!(
            self.0,
            "{},{},{},{},{},{},{},{}",
            o.time, o.kinetic_energy, o.rotational_energy, o.potential_energy, o.elastic_energy, o.dissipated_energy, o.contacts, o.max_overlap_ratio
        )?;
        if fluid {
            write!(self.0, ",{}", o.fluid_work)?;
        }
        writeln!(self.0)?;
        // Flushed every row so an interrupted or stopped run leaves complete rows.
        self.0.flush()
    }
}

/// tracks.csv, one row per tracked particle per output interval.
pub struct TracksCsv(BufWriter<File>);

impl TracksCsv {
    pub fn create(dir: &Path) -> std::io::Result<Self> {
        let mut w = BufWriter::new(File::create(dir.join("tracks.csv"))?);
        writeln!(w, "t,id,x,y,z,vx,vy,vz,wx,wy,wz")?;
        Ok(TracksCsv(w))
    }

    pub fn rows(&mut self, t: f64, rows: &[TrackRow]) -> std::io::Result<()> {
        for r in rows {
            let (x, v, w) = (r.position, r.velocity, r.angular_velocity);
            writeln!(self.0, "{t},{},{},{},{},{},{},{},{},{},{}", r.id, x.x, x.y, x.z, v.x, v.y, v.z, w.x, w.y, w.z)?;
        }
        self.0.flush()
    }
}

/// agglomerates.csv, one row per output interval (see `crate::agglomerates::csv_header`).
pub struct AgglomeratesCsv {
    w: BufWriter<File>,
    bins: usize,
}

impl AgglomeratesCsv {
    pub fn create(dir: &Path, particles: usize) -> std::io::Result<Self> {
        let mut w = BufWriter::new(File::create(dir.join("agglomerates.csv"))?);
        writeln!(w, "{}", crate::agglomerates::csv_header(particles))?;
        Ok(AgglomeratesCsv { w, bins: crate::agglomerates::histogram_bins(particles) })
    }

    pub fn row(&mut self, t: f64, s: &crate::agglomerates::AgglomerateStats) -> std::io::Result<()> {
        writeln!(self.w, "{}", crate::agglomerates::csv_row(t, s, self.bins))?;
        self.w.flush()
    }
}
