//! The run's options a scene file names directly: which backend, how snapshots are encoded,
//! the instability monitor's thresholds and when a run ends early. They carry serde's derive so
//! the scene format reads them as they are; nothing else of the format is here.

use serde::Deserialize;

/// Encoding of the VTK XML snapshot files.
#[derive(Clone, Copy, Debug, Default, Deserialize, PartialEq, Eq)]
#[serde(rename_all = "lowercase")]
pub enum SnapshotFormat {
    /// Appended raw binary (little-endian, UInt64 headers).
    #[default]
    Binary,
    /// Appended binary, zlib-compressed in blocks (vtkZLibDataCompressor).
    Compressed,
    /// Inline ASCII.
    Ascii,
}

/// When a run ends before its duration.
#[derive(Clone, Copy, Debug, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct EndWhenSection {
    /// The particles' kinetic energy (translational + rotational) at an output row below this, J.
    pub kinetic_energy_below: f64,
    /// Not before this time, s (the particles may start at rest).
    #[serde(default)]
    pub after: f64,
}

#[derive(Clone, Copy, Debug, Default, Deserialize, PartialEq, Eq)]
#[serde(rename_all = "kebab-case")]
pub enum BackendName {
    #[default]
    Cpu,
    Gpu,
}

impl BackendName {
    /// The name scene files and the command line give it.
    pub fn name(self) -> &'static str {
        match self {
            BackendName::Cpu => "cpu",
            BackendName::Gpu => "gpu",
        }
    }

    /// The backend of that name (`cpu`, `gpu`), as [`BackendName::name`] gives it.
    pub fn from_name(name: &str) -> Option<BackendName> {
        [BackendName::Cpu, BackendName::Gpu].into_iter().find(|b| b.name() == name)
    }
}

/// Instability monitor thresholds.
#[derive(Clone, Copy, Debug, Deserialize, PartialEq)]
#[serde(deny_unknown_fields, default)]
pub struct MonitorSection {
    pub enabled: bool,
    /// Largest allowed overlap δ/r before the run stops.
    pub max_overlap_ratio: f64,
    /// Largest allowed energy gain without a source, as a fraction of the largest kinetic + elastic energy seen.
    pub energy_growth: f64,
}

impl Default for MonitorSection {
    fn default() -> Self {
        MonitorSection { enabled: true, max_overlap_ratio: 0.5, energy_growth: 0.25 }
    }
}
