//! Triangles binned on a uniform grid, so a sphere tests only the triangles near it: the cost
//! of a mesh grows with the contacts, not with particles × triangles.

use crate::DVec3;
use crate::mesh::TriangleMesh;

/// Triangles by cell: each triangle is listed in every cell its bounding box overlaps.
#[derive(Clone, Debug)]
pub struct TriangleGrid {
    origin: DVec3,
    cell: f64,
    dims: [usize; 3],
    /// CSR offsets into `items`, one per cell plus one.
    start: Vec<u32>,
    items: Vec<u32>,
}

impl TriangleGrid {
    /// Bins `mesh` on cells of about `cell` (the particles' interaction diameter suits), or of
    /// twice the typical triangle's size when triangles are smaller than that (up to `cell`
    /// while the listing would hold more than 16 entries per triangle), so a sphere over fine
    /// triangles gathers few; the cells grow when the mesh's box would need more than 8 cells
    /// per triangle (and 4,096).
    pub fn new(mesh: &TriangleMesh, cell: f64) -> TriangleGrid {
        let (lo, hi) = mesh.vertices.iter().fold((DVec3::INFINITY, DVec3::NEG_INFINITY), |(lo, hi), &v| (lo.min(v), hi.max(v)));
        let extent = (hi - lo).max(DVec3::splat(f64::MIN_POSITIVE));
        let most = (8 * mesh.triangles.len()).max(4096) as f64;
        let bounds: Vec<(DVec3, DVec3)> = (0..mesh.triangles.len())
            .map(|t| {
                let c = mesh.corners(t);
                (c[0].min(c[1]).min(c[2]), c[0].max(c[1]).max(c[2]))
            })
            .collect();
        let mut sizes: Vec<f64> = bounds.iter().map(|(a, b)| (*b - *a).max_element()).collect();
        let mid = sizes.len() / 2;
        let typical = if sizes.is_empty() { cell } else { *sizes.select_nth_unstable_by(mid, f64::total_cmp).1 };
        // Entries each triangle's box puts in the grid at cell width `w`.
        let entries = |w: f64| bounds.iter().map(|(a, b)| ((*b - *a) / w + DVec3::ONE).ceil().to_array().iter().product::<f64>()).sum::<f64>();
        let mut fine = (2.0 * typical).min(cell);
        while fine < cell && entries(fine) > 16.0 * bounds.len() as f64 {
            fine *= 1.25;
        }
        let mut cell = fine.min(cell).max(extent.max_element() * 1e-6);
        while (extent / cell).ceil().max(DVec3::ONE).to_array().iter().product::<f64>() > most {
            cell *= 1.25;
        }
        let dims = (extent / cell).ceil().max(DVec3::ONE).to_array().map(|d| d as usize);
        let grid = TriangleGrid { origin: lo, cell, dims, start: Vec::new(), items: Vec::new() };
        let boxes: Vec<([usize; 3], [usize; 3])> = bounds.iter().map(|&(a, b)| (grid.cell_of(a), grid.cell_of(b))).collect();
        let cells = dims[0] * dims[1] * dims[2];
        let mut count = vec![0u32; cells + 1];
        let each = |(a, b): &([usize; 3], [usize; 3]), f: &mut dyn FnMut(usize)| {
            for z in a[2]..=b[2] {
                for y in a[1]..=b[1] {
                    for x in a[0]..=b[0] {
                        f(x + dims[0] * (y + dims[1] * z));
                    }
                }
            }
        };
        for b in &boxes {
            each(b, &mut |k| count[k + 1] += 1);
        }
        for k in 0..cells {
            count[k + 1] += count[k];
        }
        let mut items = vec![0u32; count[cells] as usize];
        let mut cursor = count[..cells].to_vec();
        // Triangles in index order, so each cell lists them ascending.
        for (t, b) in boxes.iter().enumerate() {
            each(b, &mut |k| {
                items[cursor[k] as usize] = t as u32;
                cursor[k] += 1;
            });
        }
        TriangleGrid { start: count, items, ..grid }
    }

    /// The cell holding `x`, clamped to the grid.
    fn cell_of(&self, x: DVec3) -> [usize; 3] {
        let c = ((x - self.origin) / self.cell).floor().to_array();
        [0, 1, 2].map(|k| (c[k].max(0.0) as usize).min(self.dims[k] - 1))
    }

    /// Every triangle whose bounding box may come within `reach` of `centre`, ascending and
    /// each once, into `out` (cleared first).
    pub fn candidates(&self, centre: DVec3, reach: f64, out: &mut Vec<u32>) {
        out.clear();
        let (a, b) = (self.cell_of(centre - DVec3::splat(reach)), self.cell_of(centre + DVec3::splat(reach)));
        for z in a[2]..=b[2] {
            for y in a[1]..=b[1] {
                for x in a[0]..=b[0] {
                    let k = x + self.dims[0] * (y + self.dims[1] * z);
                    out.extend_from_slice(&self.items[self.start[k] as usize..self.start[k + 1] as usize]);
                }
            }
        }
        out.sort_unstable();
        out.dedup();
    }

    /// The box the grid's cells cover (every triangle lies in it), in the mesh's frame.
    pub fn bounds(&self) -> (DVec3, DVec3) {
        let [x, y, z] = self.dims.map(|d| d as f64 * self.cell);
        (self.origin, self.origin + DVec3::new(x, y, z))
    }

    /// Cells along each axis and their width.
    pub fn layout(&self) -> ([usize; 3], f64) {
        (self.dims, self.cell)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::{DEFAULT_CURVATURE, box_triangles_subdivided};

    #[test]
    fn fine_triangles_shrink_the_cells_and_large_ones_keep_the_particles() {
        let cell_for = |n: usize| {
            let (v, t) = box_triangles_subdivided(DVec3::ZERO, DVec3::ONE, n);
            TriangleGrid::new(&TriangleMesh::new(&v, &t, DEFAULT_CURVATURE).unwrap().0, 0.1).layout().1
        };
        // Triangles 0.02 across under particles 0.1 across: cells twice the triangles.
        assert!((cell_for(50) - 0.04).abs() < 1e-12, "{}", cell_for(50));
        // Triangles 1 across: the particles' cells.
        assert_eq!(cell_for(1), 0.1);
    }

    #[test]
    fn the_grid_finds_every_triangle_a_sphere_touches_and_the_same_contacts() {
        let (v, t) = box_triangles_subdivided(DVec3::new(-0.3, 0.1, 0.0), DVec3::new(0.7, 0.6, 2.0), 12);
        let mesh = TriangleMesh::new(&v, &t, DEFAULT_CURVATURE).unwrap().0;
        let mut s = 11u64;
        let mut u = move || {
            s = s.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
            (s >> 11) as f64 / (1u64 << 53) as f64
        };
        for cell in [0.02, 0.1, 5.0] {
            let grid = TriangleGrid::new(&mesh, cell);
            let mut found = Vec::new();
            let (mut touched, mut listed) = (0, 0);
            for _ in 0..500 {
                let x = DVec3::new(u() * 1.4 - 0.5, u() * 0.9 - 0.1, u() * 2.4 - 0.2);
                let (r, reach) = (0.05 + 0.1 * u(), 0.01);
                grid.candidates(x, r + reach, &mut found);
                assert!(found.windows(2).all(|w| w[0] < w[1]));
                for tri in 0..mesh.triangles.len() {
                    if mesh.triangle_contact(tri, x, r, reach).is_some() {
                        touched += 1;
                        assert!(found.binary_search(&(tri as u32)).is_ok(), "cell {cell}: triangle {tri} within reach of {x} not listed");
                    }
                }
                listed += found.len();
                assert_eq!(mesh.sphere_contacts(x, r, reach, found.iter().copied()), mesh.sphere_contacts_all(x, r, reach));
            }
            println!("cell {cell}: {:?}; {touched} triangles within reach, {listed} listed", grid.layout());
            assert!(touched > 200);
            if cell < 1.0 {
                assert!(listed < 40 * touched, "the grid must narrow the search: {listed} listed for {touched}");
            }
        }
    }
}
