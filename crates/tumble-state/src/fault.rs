//! Why a backend stopped short of the steps it was asked for.

use crate::HistoryOverflow;
use serde::{Deserialize, Serialize};

/// A fixed capacity ran out: the run cannot go on without losing state.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub enum Fault {
    /// A particle had more contacts with a tangential spring than it has slots.
    HistoryOverflow(HistoryOverflow),
}

impl std::fmt::Display for Fault {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Fault::HistoryOverflow(o) => o.fmt(f),
        }
    }
}

impl From<HistoryOverflow> for Fault {
    fn from(o: HistoryOverflow) -> Self {
        Fault::HistoryOverflow(o)
    }
}
