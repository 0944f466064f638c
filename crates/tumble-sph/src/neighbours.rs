//! The fluid's cell grid: tumble-broad's counting sort at the fluid's own cell size, 2h plus a
//! skin, rebuilt and the particles re-sorted once per step.

use tumble_broad::{CellGrid, permute};
use tumble_geom::{DVec3, PeriodicBox};

use crate::particles::{FluidParticles, ParticleKind};

/// Cells are this much wider than the kernel's reach, so the grid of a step's start still finds
/// every pair within 2h at the step's half and end, as long as no particle moves more than
/// (SKIN − 1)·h in one step (checked after every step).
pub const SKIN: f64 = 1.1;

#[derive(Clone, Debug)]
pub struct FluidGrid {
    grid: CellGrid,
    /// The cell of each particle in its sorted position.
    cells: Vec<u32>,
    /// How many fluid particles precede each sorted slot (one more entry than particles), so a
    /// run of slots holding walls only is skipped whole by whoever gathers from the fluid.
    fluid_before: Vec<u32>,
    domain: PeriodicBox,
    any_periodic: bool,
}

impl FluidGrid {
    /// A grid over `domain` for a kernel of reach `support` (2h). Periodic axes must hold two
    /// cells, so that the minimum image is the only image within reach.
    pub fn new(domain: PeriodicBox, support: f64) -> Result<Self, String> {
        let cell = support * SKIN;
        let extent = domain.extent();
        for k in 0..3 {
            if domain.periodic[k] && extent[k] < 2.0 * cell {
                return Err(format!(
                    "the periodic {} axis is {:.4e} m long; the fluid needs at least {:.4e} m (twice 2.2 h)",
                    ["x", "y", "z"][k],
                    extent[k],
                    2.0 * cell
                ));
            }
            if extent[k].is_nan() || extent[k] < 0.0 {
                return Err(format!("the fluid's domain is inverted along {}", ["x", "y", "z"][k]));
            }
        }
        // A flat axis (the y of a 2D run) gets one cell.
        let mut padded = domain;
        for k in 0..3 {
            if padded.max[k] - padded.min[k] < cell {
                padded.max[k] = padded.min[k] + cell;
            }
        }
        Ok(FluidGrid {
            grid: CellGrid::new(&padded, cell),
            cells: Vec::new(),
            fluid_before: Vec::new(),
            domain,
            any_periodic: domain.periodic.iter().any(|&p| p),
        })
    }

    /// Bins the particles and reorders every array of `particles` into cell order.
    pub fn sort(&mut self, particles: &mut FluidParticles) {
        self.grid.build(&particles.position);
        let order = self.grid.order();
        self.cells.clear();
        self.cells.extend(order.iter().map(|&i| self.grid.cell_of(i as usize) as u32));
        permute(&mut particles.id, order);
        permute(&mut particles.kind, order);
        permute(&mut particles.position, order);
        permute(&mut particles.velocity, order);
        permute(&mut particles.density, order);
        permute(&mut particles.mass, order);
        self.fluid_before.clear();
        self.fluid_before.push(0);
        let mut count = 0u32;
        for &k in &particles.kind {
            count += (k == ParticleKind::Fluid) as u32;
            self.fluid_before.push(count);
        }
    }

    /// r_a − r_b, the minimum image along periodic axes.
    #[inline]
    pub fn separation(&self, a: DVec3, b: DVec3) -> DVec3 {
        let d = a - b;
        if self.any_periodic { self.domain.minimum_image(d) } else { d }
    }

    /// Wraps a position into the domain along its periodic axes.
    #[inline]
    pub fn wrap(&self, x: DVec3) -> DVec3 {
        if self.any_periodic { self.domain.wrap(x) } else { x }
    }

    /// Calls `f(j)` for every particle (sorted index) in the cells around sorted particle `i`'s
    /// cell, `i` included, in ascending slot order within each run.
    #[inline]
    pub fn for_each_candidate(&self, i: usize, mut f: impl FnMut(usize)) {
        self.grid.for_each_neighbour_run(self.cells[i] as usize, |start, end| {
            for j in start..end {
                f(j)
            }
        });
    }

    /// Like [`FluidGrid::for_each_candidate`], but only the fluid particles among them; runs of
    /// slots holding walls only cost one comparison.
    #[inline]
    pub fn for_each_fluid_candidate(&self, i: usize, kind: &[ParticleKind], mut f: impl FnMut(usize)) {
        self.grid.for_each_neighbour_run(self.cells[i] as usize, |start, end| {
            if self.fluid_before[end] == self.fluid_before[start] {
                return;
            }
            for j in start..end {
                if kind[j] == ParticleKind::Fluid {
                    f(j)
                }
            }
        });
    }

    /// Like [`FluidGrid::for_each_candidate`] around an arbitrary point (a probe).
    pub fn for_each_candidate_near(&self, x: DVec3, mut f: impl FnMut(usize)) {
        let c = self.grid.cell_coords(self.wrap(x));
        let [nx, ny, _] = self.grid.dims();
        let cell = c[0] + nx * (c[1] + ny * c[2]);
        self.grid.for_each_neighbour_run(cell, |start, end| {
            for j in start..end {
                f(j)
            }
        });
    }
}
