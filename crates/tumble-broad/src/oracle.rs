use crate::CellGrid;
use tumble_geom::{DVec3, PeriodicBox};

/// Every pair (i < j) with |x_i − x_j| < r_i + r_j (minimum image), by checking all pairs.
pub fn brute_force_pairs(positions: &[DVec3], reach: &[f64], domain: &PeriodicBox) -> Vec<(u32, u32)> {
    let mut pairs = Vec::new();
    for i in 0..positions.len() {
        for j in i + 1..positions.len() {
            let d = domain.minimum_image(positions[i] - positions[j]);
            if d.length() < reach[i] + reach[j] {
                pairs.push((i as u32, j as u32));
            }
        }
    }
    pairs
}

/// The same pair set found through a built [`CellGrid`], sorted.
pub fn grid_pairs(grid: &CellGrid, positions: &[DVec3], reach: &[f64], domain: &PeriodicBox) -> Vec<(u32, u32)> {
    let order = grid.order();
    let mut pairs = Vec::new();
    for i in 0..positions.len() {
        grid.for_each_neighbour_run(grid.cell_of(i), |start, end| {
            for &j in &order[start..end] {
                let j = j as usize;
                if j <= i {
                    continue;
                }
                let d = domain.minimum_image(positions[i] - positions[j]);
                if d.length() < reach[i] + reach[j] {
                    pairs.push((i as u32, j as u32));
                }
            }
        });
    }
    pairs.sort_unstable();
    pairs
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    fn config() -> impl Strategy<Value = (Vec<DVec3>, Vec<f64>, [bool; 3], DVec3)> {
        (
            prop::collection::vec((0.0f64..1.0, 0.0f64..1.0, 0.0f64..1.0, 0.2f64..1.0), 1..300),
            prop::array::uniform3(any::<bool>()),
            (0.5f64..3.0, 0.5f64..3.0, 0.5f64..3.0),
        )
            .prop_map(|(raw, periodic, (lx, ly, lz))| {
                let extent = DVec3::new(lx, ly, lz);
                let r_max = 0.08;
                let x = raw.iter().map(|&(a, b, c, _)| DVec3::new(a, b, c) * extent).collect();
                // Polydisperse reach up to 5:1.
                let r = raw.iter().map(|&(_, _, _, s)| r_max * s).collect();
                (x, r, periodic, extent)
            })
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(200))]
        #[test]
        fn grid_finds_exactly_the_brute_force_pairs((x, r, periodic, extent) in config()) {
            let domain = PeriodicBox { min: DVec3::new(-0.3, 0.1, 2.0), max: DVec3::new(-0.3, 0.1, 2.0) + extent, periodic };
            let x: Vec<DVec3> = x.into_iter().map(|p| p + domain.min).collect();
            let max_reach = r.iter().cloned().fold(0.0, f64::max);
            let mut grid = CellGrid::new(&domain, 2.0 * max_reach);
            grid.build(&x);
            prop_assert_eq!(grid_pairs(&grid, &x, &r, &domain), brute_force_pairs(&x, &r, &domain));
        }

        #[test]
        fn counting_sort_is_a_permutation_sorted_by_cell((x, _r, periodic, extent) in config()) {
            let domain = PeriodicBox { min: DVec3::ZERO, max: extent, periodic };
            let mut grid = CellGrid::new(&domain, 0.1);
            grid.build(&x);
            let mut seen = grid.order().to_vec();
            seen.sort_unstable();
            prop_assert_eq!(seen, (0..x.len() as u32).collect::<Vec<_>>());
            let cells: Vec<usize> = grid.order().iter().map(|&i| grid.cell_of(i as usize)).collect();
            prop_assert!(cells.windows(2).all(|w| w[0] <= w[1]));
            for c in 0..grid.cell_count() {
                let (s, e) = grid.cell_range(c);
                prop_assert!(grid.order()[s..e].iter().all(|&i| grid.cell_of(i as usize) == c));
            }
        }
    }

    #[test]
    fn periodic_neighbours_across_the_seam_with_two_cells() {
        // Two cells per axis: the -1 and +1 neighbours coincide and must be visited once.
        let domain = PeriodicBox { min: DVec3::ZERO, max: DVec3::ONE, periodic: [true; 3] };
        let x = vec![DVec3::new(0.05, 0.5, 0.5), DVec3::new(0.95, 0.5, 0.5)];
        let r = vec![0.1; 2];
        let mut grid = CellGrid::new(&domain, 0.4);
        grid.build(&x);
        assert_eq!(grid.dims(), [2, 2, 2]);
        assert_eq!(grid_pairs(&grid, &x, &r, &domain), vec![(0, 1)]);
    }
}
