//! The fluid's cell grid: tumble-broad's counting sort at the fluid's own cell size, 2h plus a
//! skin, rebuilt and the particles re-sorted once per step.

use rayon::prelude::*;
use tumble_broad::{CellGrid, permute};
use tumble_geom::{DVec3, PeriodicBox};

use crate::particles::{FluidParticles, ParticleKind};

/// Cells, and the neighbour lists, reach this much further than the kernel: 2h·SKIN = 2h + 0.4h.
/// The lists stay complete while no particle has moved more than (SKIN − 1)·2h/2 = 0.2h since
/// they were built. They are rebuilt (and the arrays re-sorted) before a step once some particle
/// has moved half of that, and a particle that moves more than the other half within one step
/// stops the run; so the lists last several steps and never miss a pair.
pub const SKIN: f64 = 1.2;

/// How far a particle may move between two list builds, in units of h.
pub fn rebuild_distance(h: f64) -> f64 {
    0.5 * (SKIN - 1.0) * h
}

/// `domain` with a flat axis (the y of a 2D run) widened to one cell of `cell`.
pub(crate) fn padded(domain: PeriodicBox, cell: f64) -> PeriodicBox {
    let mut padded = domain;
    for k in 0..3 {
        if padded.max[k] - padded.min[k] < cell {
            padded.max[k] = padded.min[k] + cell;
        }
    }
    padded
}

#[derive(Clone, Debug)]
pub struct FluidGrid {
    grid: CellGrid,
    /// The cell of each particle in its sorted position.
    cells: Vec<u32>,
    /// How many fluid particles precede each sorted slot (one more entry than particles), so a
    /// run of slots holding walls only is skipped whole by whoever gathers from the fluid.
    fluid_before: Vec<u32>,
    /// Each particle's neighbours within the cell size (2h plus the skin) at the last sort, in
    /// the grid's slot order: all particles for a fluid particle, the fluid for a wall particle.
    /// Built once per step, read by both of the step's evaluations.
    list_start: Vec<usize>,
    list: Vec<u32>,
    reach2: f64,
    /// The positions the lists were built from (sorted order).
    built: Vec<DVec3>,
    domain: PeriodicBox,
    any_periodic: bool,
}

impl FluidGrid {
    /// Bytes the grid's per-particle arrays and neighbour lists hold (the cell table aside).
    pub fn memory_bytes(&self) -> u64 {
        let size = |len: usize, each: usize| (len * each) as u64;
        size(self.cells.capacity(), 4)
            + size(self.fluid_before.capacity(), 4)
            + size(self.list_start.capacity(), 8)
            + size(self.list.capacity(), 4)
            + size(self.built.capacity(), 24)
    }

    /// A grid over `domain` for a kernel of reach `support` (2h). Periodic axes must hold two
    /// cells, so that the minimum image is the only image within reach.
    pub fn new(domain: PeriodicBox, support: f64) -> Result<Self, String> {
        let cell = support * SKIN;
        let extent = domain.extent();
        for k in 0..3 {
            if domain.periodic[k] && extent[k] < 2.0 * cell {
                return Err(format!(
                    "the periodic {} axis is {:.4e} m long; the fluid needs at least {:.4e} m (two cells of 2.4 h)",
                    ["x", "y", "z"][k],
                    extent[k],
                    2.0 * cell
                ));
            }
            if extent[k].is_nan() || extent[k] < 0.0 {
                return Err(format!("the fluid's domain is inverted along {}", ["x", "y", "z"][k]));
            }
        }
        Ok(FluidGrid {
            grid: CellGrid::new(&padded(domain, cell), cell),
            cells: Vec::new(),
            fluid_before: Vec::new(),
            list_start: Vec::new(),
            list: Vec::new(),
            reach2: cell * cell,
            built: Vec::new(),
            domain,
            any_periodic: domain.periodic.iter().any(|&p| p),
        })
    }

    /// Bins the particles, reorders every array of `particles` into cell order and builds the
    /// neighbour lists from their current positions.
    pub fn sort(&mut self, particles: &mut FluidParticles) {
        self.built.clone_from(&particles.position);
        self.index(particles);
    }

    /// Rebuilds the lists of `particles`, already in the cell order of a sort at positions
    /// `built`, as that sort built them: the stable counting sort of sorted arrays is the
    /// identity, so the lists come out the same (a restored phase continues bit-identically).
    pub fn rebuild_at(&mut self, particles: &mut FluidParticles, built: &[DVec3]) {
        self.built.clear();
        self.built.extend_from_slice(built);
        self.index(particles);
    }

    /// The positions the current lists were built from.
    pub fn built_positions(&self) -> &[DVec3] {
        &self.built
    }

    /// The largest distance a particle has moved since the lists were built.
    pub fn largest_displacement(&self, positions: &[DVec3]) -> f64 {
        positions.par_iter().zip(self.built.par_iter()).map(|(&x, &x0)| self.separation(x, x0).length()).reduce(|| 0.0, f64::max)
    }

    fn index(&mut self, particles: &mut FluidParticles) {
        self.grid.build(&self.built);
        let order = self.grid.order();
        self.cells.clear();
        self.cells.extend(order.iter().map(|&i| self.grid.cell_of(i as usize) as u32));
        permute(&mut particles.id, order);
        permute(&mut particles.kind, order);
        permute(&mut particles.position, order);
        permute(&mut particles.velocity, order);
        permute(&mut particles.density, order);
        permute(&mut particles.mass, order);
        permute(&mut particles.wall, order);
        permute(&mut self.built, order);
        self.fluid_before.clear();
        self.fluid_before.push(0);
        let mut count = 0u32;
        for &k in &particles.kind {
            count += (k == ParticleKind::Fluid) as u32;
            self.fluid_before.push(count);
        }
        self.build_lists(particles);
    }

    /// The neighbour lists, built by fixed chunks of particles in parallel and joined in order:
    /// the same lists for any number of threads.
    fn build_lists(&mut self, particles: &FluidParticles) {
        const CHUNK: usize = 256;
        let n = particles.len();
        let kind = &particles.kind;
        let position = &self.built;
        let this = &*self;
        let pieces: Vec<(Vec<u32>, Vec<u32>)> = (0..n.div_ceil(CHUNK))
            .into_par_iter()
            .map(|c| {
                let range = c * CHUNK..((c + 1) * CHUNK).min(n);
                let mut counts = Vec::with_capacity(range.len());
                let mut list = Vec::new();
                for i in range {
                    let before = list.len();
                    let xi = position[i];
                    let wall = kind[i] == ParticleKind::Wall;
                    this.grid.for_each_neighbour_run(this.cells[i] as usize, |start, end| {
                        if wall && this.fluid_before[end] == this.fluid_before[start] {
                            return;
                        }
                        for j in start..end {
                            if j != i && !(wall && kind[j] != ParticleKind::Fluid) && this.separation(xi, position[j]).length_squared() < this.reach2
                            {
                                list.push(j as u32);
                            }
                        }
                    });
                    counts.push((list.len() - before) as u32);
                }
                (counts, list)
            })
            .collect();
        self.list_start.clear();
        self.list_start.push(0);
        let mut total = 0usize;
        for (counts, _) in &pieces {
            for &c in counts {
                total += c as usize;
                self.list_start.push(total);
            }
        }
        self.list.resize(total, 0);
        let mut rest = &mut self.list[..];
        let mut slices = Vec::with_capacity(pieces.len());
        for (_, piece) in &pieces {
            let (head, tail) = rest.split_at_mut(piece.len());
            slices.push(head);
            rest = tail;
        }
        slices.into_par_iter().zip(pieces.par_iter()).for_each(|(out, (_, piece))| out.copy_from_slice(piece));
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

    /// Sorted particle `i`'s neighbours in its list (within 2h plus the skin at the last sort;
    /// fluid only for a wall particle), in ascending slot order.
    #[inline]
    pub fn neighbours(&self, i: usize) -> &[u32] {
        &self.list[self.list_start[i]..self.list_start[i + 1]]
    }

    /// Calls `f(j)` for every particle in the cells around an arbitrary point (a probe).
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
