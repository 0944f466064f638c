use tumble_geom::{DVec3, PeriodicBox};

/// A uniform cell grid over a domain, rebuilt by counting sort.
#[derive(Clone, Debug)]
pub struct CellGrid {
    origin: DVec3,
    inv_cell: DVec3,
    cell: DVec3,
    dims: [usize; 3],
    periodic: [bool; 3],
    cell_of: Vec<u32>,
    cell_start: Vec<u32>,
    order: Vec<u32>,
}

impl CellGrid {
    /// A grid whose cells are at least `min_cell` wide on every axis.
    ///
    /// Periodic axes are tiled exactly, so cell widths are L/n ≥ `min_cell`.
    pub fn new(domain: &PeriodicBox, min_cell: f64) -> Self {
        let (dims, cell) = Self::layout(domain, min_cell);
        CellGrid {
            origin: domain.min,
            inv_cell: DVec3::ONE / cell,
            cell,
            dims,
            periodic: domain.periodic,
            cell_of: Vec::new(),
            cell_start: vec![0; dims.iter().product::<usize>() + 1],
            order: Vec::new(),
        }
    }

    /// Cells per axis and cell widths of the grid [`CellGrid::new`] builds: the one rule the
    /// memory estimate of a plan shares with the grid.
    pub fn layout(domain: &PeriodicBox, min_cell: f64) -> ([usize; 3], DVec3) {
        assert!(min_cell > 0.0, "cell size must be positive");
        let extent = domain.extent();
        let mut dims = [1usize; 3];
        let mut cell = DVec3::ZERO;
        for k in 0..3 {
            // Keep the grid bounded: at most ~2^21 cells per axis and 2^26 in all.
            dims[k] = ((extent[k] / min_cell).floor() as usize).clamp(1, 1 << 21);
            cell[k] = extent[k] / dims[k] as f64;
        }
        while dims.iter().product::<usize>() > 1 << 26 {
            let k = (0..3).max_by_key(|&k| dims[k]).unwrap();
            dims[k] = dims[k].div_ceil(2);
            cell[k] = extent[k] / dims[k] as f64;
        }
        (dims, cell)
    }

    pub fn dims(&self) -> [usize; 3] {
        self.dims
    }

    pub fn cell_size(&self) -> DVec3 {
        self.cell
    }

    pub fn cell_count(&self) -> usize {
        self.cell_start.len() - 1
    }

    /// Cell coordinates of a position (clamped into the grid).
    #[inline]
    pub fn cell_coords(&self, x: DVec3) -> [usize; 3] {
        let s = (x - self.origin) * self.inv_cell;
        let mut c = [0usize; 3];
        for k in 0..3 {
            c[k] = (s[k].floor().max(0.0) as usize).min(self.dims[k] - 1);
        }
        c
    }

    #[inline]
    fn linear(&self, c: [usize; 3]) -> usize {
        c[0] + self.dims[0] * (c[1] + self.dims[1] * c[2])
    }

    /// Bins `positions` by counting sort: cell of each particle, cell ranges, sorted order.
    pub fn build(&mut self, positions: &[DVec3]) {
        let n = positions.len();
        let mut cell_of = std::mem::take(&mut self.cell_of);
        cell_of.clear();
        cell_of.extend(positions.iter().map(|&x| self.linear(self.cell_coords(x)) as u32));
        self.cell_of = cell_of;
        self.cell_start.fill(0);
        for &c in &self.cell_of {
            self.cell_start[c as usize + 1] += 1;
        }
        for c in 0..self.cell_count() {
            self.cell_start[c + 1] += self.cell_start[c];
        }
        self.order.resize(n, 0);
        // Scatter with a running cursor per cell; stable in particle index.
        let mut cursor = self.cell_start[..self.cell_count()].to_vec();
        for (i, &c) in self.cell_of.iter().enumerate() {
            let slot = &mut cursor[c as usize];
            self.order[*slot as usize] = i as u32;
            *slot += 1;
        }
    }

    /// Particle indices sorted by cell.
    pub fn order(&self) -> &[u32] {
        &self.order
    }

    /// Cell index of particle `i` from the last build.
    #[inline]
    pub fn cell_of(&self, i: usize) -> usize {
        self.cell_of[i] as usize
    }

    /// Sorted slots `start..end` holding the particles of cell `c`.
    #[inline]
    pub fn cell_range(&self, c: usize) -> (usize, usize) {
        (self.cell_start[c] as usize, self.cell_start[c + 1] as usize)
    }

    /// Calls `f(start, end)` for each run of sorted slots in the cells around `cell`
    /// (itself included), each slot exactly once.
    #[inline]
    pub fn for_each_neighbour_run(&self, cell: usize, mut f: impl FnMut(usize, usize)) {
        let [nx, ny, _] = self.dims;
        let cx = cell % nx;
        let cy = (cell / nx) % ny;
        let cz = cell / (nx * ny);
        let mut ys = [0usize; 3];
        let mut zs = [0usize; 3];
        let ny_used = self.axis_neighbours(1, cy, &mut ys);
        let nz_used = self.axis_neighbours(2, cz, &mut zs);
        let mut xs = [0usize; 3];
        let nx_used = self.axis_neighbours(0, cx, &mut xs);
        // Three consecutive x cells form one contiguous run of slots.
        let contiguous = nx_used == 3 && xs[0] + 1 == xs[1] && xs[1] + 1 == xs[2];
        for &z in &zs[..nz_used] {
            for &y in &ys[..ny_used] {
                let row = nx * (y + ny * z);
                if contiguous {
                    f(self.cell_start[row + xs[0]] as usize, self.cell_start[row + xs[2] + 1] as usize);
                } else {
                    for &x in &xs[..nx_used] {
                        let c = row + x;
                        f(self.cell_start[c] as usize, self.cell_start[c + 1] as usize);
                    }
                }
            }
        }
    }

    /// Distinct neighbour coordinates along axis `k`, ascending; returns how many.
    #[inline]
    fn axis_neighbours(&self, k: usize, c: usize, out: &mut [usize; 3]) -> usize {
        let n = self.dims[k];
        let mut m = 0;
        let mut push = |v: usize, m: &mut usize| {
            if !out[..*m].contains(&v) {
                out[*m] = v;
                *m += 1;
            }
        };
        if c > 0 {
            push(c - 1, &mut m);
        } else if self.periodic[k] {
            push(n - 1, &mut m);
        }
        push(c, &mut m);
        if c + 1 < n {
            push(c + 1, &mut m);
        } else if self.periodic[k] {
            push(0, &mut m);
        }
        out[..m].sort_unstable();
        m
    }
}

/// Reorders `data` so that `data[k]` becomes the old `data[order[k]]`.
pub fn permute<T: Copy>(data: &mut Vec<T>, order: &[u32]) {
    debug_assert_eq!(data.len(), order.len());
    let sorted: Vec<T> = order.iter().map(|&i| data[i as usize]).collect();
    *data = sorted;
}
