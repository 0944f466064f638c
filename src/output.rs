//! The phases' output tables as CSV files (observables.csv, tracks.csv, fluid.csv,
//! probe_<name>.csv, …; docs/cli.md, "Outputs"): each file starts with its header `t,<columns>`
//! and takes each output row's lines, flushed as they are written.

use std::fs::File;
use std::io::{BufWriter, Write};
use std::path::{Path, PathBuf};
use tumble_state::PhaseTable;

/// Every table's file, each opened at its first row.
pub struct TableFiles {
    dir: PathBuf,
    /// Each file and, once opened, its writer; a resumed run's files are known (and appended
    /// to) from the start.
    files: Vec<(String, Option<BufWriter<File>>)>,
}

/// A cell: the value in Rust's shortest form that reads back to the same bits, or an empty
/// cell where it is undefined (not finite).
struct Cell(f64);

impl std::fmt::Display for Cell {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        if self.0.is_finite() { write!(f, "{}", self.0) } else { Ok(()) }
    }
}

impl TableFiles {
    /// New files in `dir`, or a resumed run's `files` there (already cut back to its
    /// checkpoint's rows), appended to.
    pub fn open(dir: &Path, files: &[(String, u64)]) -> Self {
        TableFiles { dir: dir.to_path_buf(), files: files.iter().map(|(name, _)| (name.clone(), None)).collect() }
    }

    /// The writer of `table`'s file: opened for appending when the run knows it, else a new
    /// file started with its header.
    fn writer(&mut self, table: &PhaseTable) -> std::io::Result<&mut BufWriter<File>> {
        let k = match self.files.iter().position(|(f, _)| *f == table.file) {
            Some(k) => k,
            None => {
                let mut w = BufWriter::new(File::create(self.dir.join(&table.file))?);
                writeln!(w, "t,{}", table.columns.join(","))?;
                self.files.push((table.file.clone(), Some(w)));
                self.files.len() - 1
            }
        };
        let (name, w) = &mut self.files[k];
        if w.is_none() {
            *w = Some(BufWriter::new(std::fs::OpenOptions::new().append(true).open(self.dir.join(name))?));
        }
        Ok(w.as_mut().expect("opened above"))
    }

    /// The lines of each table at time `t`.
    pub fn write(&mut self, t: f64, tables: &[PhaseTable]) -> std::io::Result<()> {
        for table in tables {
            let w = self.writer(table)?;
            for line in &table.rows {
                write!(w, "{t}")?;
                for &v in line {
                    write!(w, ",{}", Cell(v))?;
                }
                writeln!(w)?;
            }
            // Flushed every row so an interrupted or stopped run leaves complete rows.
            w.flush()?;
        }
        Ok(())
    }

    /// The length of each file now (every row is flushed as it is written).
    pub fn lengths(&self) -> std::io::Result<Vec<(String, u64)>> {
        self.files.iter().map(|(n, _)| Ok((n.clone(), std::fs::metadata(self.dir.join(n))?.len()))).collect()
    }
}
