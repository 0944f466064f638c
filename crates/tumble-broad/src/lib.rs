//! Broad phase: which particles might touch.
//!
//! [`CellGrid`] bins particles into cubes at least one interaction diameter
//! wide with a counting sort, so each particle's candidates lie in the 27
//! cells around its own (fewer, deduplicated, on short periodic axes), visited
//! as at most nine contiguous runs of sorted slots. [`brute_force_pairs`] is
//! the O(N²) oracle the grid is tested against.
//!
//! ```
//! use tumble_broad::{CellGrid, brute_force_pairs, grid_pairs};
//! use tumble_geom::{DVec3, PeriodicBox};
//! let domain = PeriodicBox { min: DVec3::ZERO, max: DVec3::ONE, periodic: [true; 3] };
//! let x = vec![DVec3::new(0.01, 0.5, 0.5), DVec3::new(0.99, 0.5, 0.5), DVec3::splat(0.5)];
//! let r = vec![0.02; 3];
//! let mut grid = CellGrid::new(&domain, 0.04);
//! grid.build(&x);
//! assert_eq!(grid_pairs(&grid, &x, &r, &domain), vec![(0, 1)]);
//! assert_eq!(brute_force_pairs(&x, &r, &domain), vec![(0, 1)]);
//! ```

mod grid;
mod oracle;

pub use grid::{CellGrid, permute};
pub use oracle::{brute_force_pairs, grid_pairs};
