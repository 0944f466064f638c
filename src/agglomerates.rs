//! Agglomerate detection: particles in body contact (δ > 0) belong to one agglomerate.
//!
//! Backend-independent and pure: it takes positions and radii (any backend's read-back
//! state) and the periodic box, finds the connected components of the contact graph
//! (cell grid + union-find, deterministic), unwraps each component across periodic
//! boundaries (breadth-first from its lowest index along contact edges, each step by the
//! minimum image), and measures each with the smallest enclosing sphere of its
//! particles' spheres ([`tumble_geom::enclosing_sphere_of_spheres`]).
//!
//! ```
//! use tumble::agglomerates::agglomerates;
//! use tumble_geom::DVec3;
//! // Two touching (slightly pressed) spheres and a lone one.
//! let x = [DVec3::ZERO, DVec3::new(0.0999, 0.0, 0.0), DVec3::new(1.0, 0.0, 0.0)];
//! let s = agglomerates(&x, &[0.05; 3], None);
//! assert_eq!((s.count, s.max_size), (2, 2));
//! assert!((s.mean_void_fraction_multi - 0.75).abs() < 1e-3);
//! ```

use tumble_broad::CellGrid;
use tumble_geom::{DVec3, PeriodicBox, enclosing_sphere_of_spheres};

/// Statistics of the agglomerates at one instant (one row of agglomerates.csv).
#[derive(Clone, Debug, Default, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct AgglomerateStats {
    /// Particles looked at.
    pub particles: usize,
    /// Number of agglomerates (single particles count as agglomerates of size 1).
    pub count: usize,
    /// Number-mean size: particles / count.
    pub mean_size: f64,
    /// Mass-weighted (particle-weighted) mean size Σ s² / Σ s: the size of the agglomerate a random particle is in.
    pub weighted_mean_size: f64,
    pub max_size: usize,
    /// Mean over all agglomerates of 1 − ΣV_p / V_bs (single particles: 0).
    pub mean_void_fraction: f64,
    /// Agglomerates of two or more particles.
    pub multi_count: usize,
    /// Mean void fraction over the agglomerates of two or more particles (0 when there are none).
    pub mean_void_fraction_multi: f64,
    /// Agglomerates that wrap around a periodic axis (connected to their own periodic image: a
    /// box-spanning network, whose enclosing sphere is that of one unwrapped copy).
    pub wrapping: usize,
    /// Size histogram in log2 bins: `histogram[k]` counts agglomerates with 2^k ≤ size < 2^(k+1).
    pub histogram: Vec<usize>,
}

/// One agglomerate: its particles (indices, ascending) and its enclosing sphere.
#[derive(Clone, Debug, PartialEq)]
pub struct Agglomerate {
    pub members: Vec<u32>,
    /// Centre of the smallest enclosing sphere, in the unwrapped frame of the lowest member
    /// (may lie outside a periodic box).
    pub centre: DVec3,
    pub radius: f64,
    /// 1 − Σ V_p / V_bs (0 for a single particle).
    pub void_fraction: f64,
    /// Connected to its own periodic image (see [`AgglomerateStats::wrapping`]).
    pub wraps: bool,
}

/// Number of log2 histogram bins needed for up to `n` particles.
pub fn histogram_bins(n: usize) -> usize {
    (usize::BITS - n.max(1).leading_zeros()) as usize
}

/// Component label per particle: the lowest particle index of its agglomerate.
pub fn labels(positions: &[DVec3], radii: &[f64], periodic: Option<&PeriodicBox>) -> Vec<u32> {
    labels_from_pairs(positions.len(), &touching_pairs(positions, radii, periodic))
}

/// Every pair (i < j) of particles in body contact, |x_i − x_j| < r_i + r_j (minimum image), sorted.
pub fn touching_pairs(positions: &[DVec3], radii: &[f64], periodic: Option<&PeriodicBox>) -> Vec<(u32, u32)> {
    assert_eq!(positions.len(), radii.len());
    if positions.is_empty() {
        return Vec::new();
    }
    let domain = match periodic {
        Some(d) => *d,
        None => {
            let lo = positions.iter().fold(DVec3::splat(f64::INFINITY), |a, &p| a.min(p));
            let hi = positions.iter().fold(DVec3::splat(f64::NEG_INFINITY), |a, &p| a.max(p));
            PeriodicBox { min: lo, max: hi.max(lo + DVec3::splat(1e-9)) + DVec3::splat(1e-9), periodic: [false; 3] }
        }
    };
    let max_r = radii.iter().cloned().fold(0.0, f64::max);
    let mut grid = CellGrid::new(&domain, (2.0 * max_r).max(domain.extent().max_element() * 1e-6));
    grid.build(positions);
    tumble_broad::grid_pairs(&grid, positions, radii, &domain)
}

/// Every agglomerate (ordered by lowest member index) with its enclosing sphere.
pub fn agglomerate_list(positions: &[DVec3], radii: &[f64], periodic: Option<&PeriodicBox>) -> Vec<Agglomerate> {
    let n = positions.len();
    let pairs = touching_pairs(positions, radii, periodic);
    let label = labels_from_pairs(n, &pairs);
    // Contact adjacency (CSR) for the unwrapping walk.
    let mut start = vec![0usize; n + 1];
    for &(i, j) in &pairs {
        start[i as usize + 1] += 1;
        start[j as usize + 1] += 1;
    }
    for k in 0..n {
        start[k + 1] += start[k];
    }
    let mut fill = start.clone();
    let mut adj = vec![0u32; 2 * pairs.len()];
    for &(i, j) in &pairs {
        adj[fill[i as usize]] = j;
        fill[i as usize] += 1;
        adj[fill[j as usize]] = i;
        fill[j as usize] += 1;
    }
    // Members per component, in ascending index order.
    let mut members: Vec<Vec<u32>> = Vec::new();
    let mut slot = vec![u32::MAX; n];
    for (i, &root) in label.iter().enumerate() {
        let root = root as usize;
        if slot[root] == u32::MAX {
            slot[root] = members.len() as u32;
            members.push(Vec::new());
        }
        members[slot[root] as usize].push(i as u32);
    }
    let mut unwrapped = vec![DVec3::ZERO; n];
    // Unwrapped separations differ from contact separations by whole box lengths or not at all.
    let wrap_tolerance = periodic.map_or(f64::INFINITY, |b| 0.5 * b.extent().min_element());
    let mut seen = vec![false; n];
    let mut queue = std::collections::VecDeque::new();
    members
        .into_iter()
        .map(|m| {
            if m.len() == 1 {
                let i = m[0] as usize;
                return Agglomerate { members: m, centre: positions[i], radius: radii[i], void_fraction: 0.0, wraps: false };
            }
            let first = m[0] as usize;
            unwrapped[first] = positions[first];
            seen[first] = true;
            queue.push_back(first);
            let mut wraps = false;
            while let Some(i) = queue.pop_front() {
                for &j in &adj[start[i]..start[i + 1]] {
                    let j = j as usize;
                    let d = positions[j] - positions[i];
                    let step = periodic.map_or(d, |b| b.minimum_image(d));
                    if !seen[j] {
                        seen[j] = true;
                        unwrapped[j] = unwrapped[i] + step;
                        queue.push_back(j);
                    } else if (unwrapped[j] - unwrapped[i] - step).length() > wrap_tolerance {
                        // A contact that closes a loop around the box.
                        wraps = true;
                    }
                }
            }
            let x: Vec<DVec3> = m.iter().map(|&i| unwrapped[i as usize]).collect();
            let r: Vec<f64> = m.iter().map(|&i| radii[i as usize]).collect();
            let ball = enclosing_sphere_of_spheres(&x, &r);
            let solid: f64 = r.iter().map(|r| r.powi(3)).sum();
            let void_fraction = 1.0 - solid / ball.radius.powi(3);
            Agglomerate { members: m, centre: ball.centre, radius: ball.radius, void_fraction, wraps }
        })
        .collect()
}

/// Union-find over the pairs; the lower root wins, so every label is its component's lowest index.
fn labels_from_pairs(n: usize, pairs: &[(u32, u32)]) -> Vec<u32> {
    let mut parent: Vec<u32> = (0..n as u32).collect();
    fn find(parent: &mut [u32], mut i: u32) -> u32 {
        while parent[i as usize] != i {
            let up = parent[parent[i as usize] as usize];
            parent[i as usize] = up;
            i = up;
        }
        i
    }
    for &(i, j) in pairs {
        let (a, b) = (find(&mut parent, i), find(&mut parent, j));
        if a < b {
            parent[b as usize] = a;
        } else if b < a {
            parent[a as usize] = b;
        }
    }
    (0..n as u32).map(|i| find(&mut parent, i)).collect()
}

/// The statistics of a list of agglomerates over `particles` particles.
pub fn stats_of(list: &[Agglomerate], particles: usize) -> AgglomerateStats {
    let mut s = AgglomerateStats { particles, count: list.len(), histogram: vec![0; histogram_bins(particles)], ..Default::default() };
    if list.is_empty() {
        return s;
    }
    let (mut sum_void, mut sum_void_multi, mut sum_sq) = (0.0, 0.0, 0.0);
    for a in list {
        let size = a.members.len();
        s.max_size = s.max_size.max(size);
        sum_sq += (size * size) as f64;
        sum_void += a.void_fraction;
        s.wrapping += usize::from(a.wraps);
        if size > 1 {
            s.multi_count += 1;
            sum_void_multi += a.void_fraction;
        }
        let bin = histogram_bins(size) - 1;
        if bin >= s.histogram.len() {
            s.histogram.resize(bin + 1, 0);
        }
        s.histogram[bin] += 1;
    }
    let total: usize = list.iter().map(|a| a.members.len()).sum();
    s.mean_size = total as f64 / list.len() as f64;
    s.weighted_mean_size = sum_sq / total as f64;
    s.mean_void_fraction = sum_void / list.len() as f64;
    s.mean_void_fraction_multi = if s.multi_count > 0 { sum_void_multi / s.multi_count as f64 } else { 0.0 };
    s
}

/// Agglomerate statistics of particles at `positions` with body `radii`; `periodic` gives the
/// box whose periodic axes are wrapped (None: open space).
pub fn agglomerates(positions: &[DVec3], radii: &[f64], periodic: Option<&PeriodicBox>) -> AgglomerateStats {
    stats_of(&agglomerate_list(positions, radii, periodic), positions.len())
}

/// agglomerates.csv's columns after `t`, for a run that starts with `particles` particles:
/// the statistics, then the size histogram's bins (sizes 1, 2–3, 4–7, …).
pub fn csv_columns(particles: usize) -> Vec<String> {
    let mut c: Vec<String> = [
        "particles",
        "agglomerates",
        "mean_size",
        "weighted_mean_size",
        "max_size",
        "mean_void_fraction",
        "multi_agglomerates",
        "mean_void_fraction_multi",
        "wrapping",
    ]
    .iter()
    .map(|s| s.to_string())
    .collect();
    for k in 0..histogram_bins(particles) {
        let (lo, hi) = (1usize << k, (1usize << (k + 1)) - 1);
        c.push(if lo == hi { format!("size_{lo}") } else { format!("size_{lo}_{hi}") });
    }
    c
}

/// agglomerates.csv's header line.
pub fn csv_header(particles: usize) -> String {
    format!("t,{}", csv_columns(particles).join(","))
}

/// agglomerates.csv's line after `t` (bins beyond the header's are never produced: sizes ≤ particles).
pub fn csv_values(s: &AgglomerateStats, bins: usize) -> Vec<f64> {
    let mut v = vec![
        s.particles as f64,
        s.count as f64,
        s.mean_size,
        s.weighted_mean_size,
        s.max_size as f64,
        s.mean_void_fraction,
        s.multi_count as f64,
        s.mean_void_fraction_multi,
        s.wrapping as f64,
    ];
    v.extend((0..bins).map(|k| s.histogram.get(k).copied().unwrap_or(0) as f64));
    v
}

#[cfg(test)]
mod tests {
    use super::*;

    fn periodic_box() -> PeriodicBox {
        PeriodicBox { min: DVec3::ZERO, max: DVec3::ONE, periodic: [true; 3] }
    }

    #[test]
    fn histogram_bins_cover_sizes() {
        assert_eq!(histogram_bins(1), 1);
        assert_eq!(histogram_bins(2), 2);
        assert_eq!(histogram_bins(3), 2);
        assert_eq!(histogram_bins(4), 3);
        assert_eq!(histogram_bins(10_000), 14);
        assert!(csv_header(4).ends_with("size_1,size_2_3,size_4_7"));
    }

    #[test]
    fn a_chain_across_the_periodic_seam_is_unwrapped() {
        // Three touching spheres in a row across x = 0/1: the enclosing sphere spans 3 diameters.
        let x = [DVec3::new(0.96, 0.5, 0.5), DVec3::new(0.0, 0.5, 0.5), DVec3::new(0.04, 0.5, 0.5)];
        let list = agglomerate_list(&x, &[0.0205; 3], Some(&periodic_box()));
        assert_eq!(list.len(), 1);
        assert!((list[0].radius - (0.04 + 0.0205)).abs() < 1e-12, "{:?}", list[0]);
    }

    #[test]
    fn a_chain_around_the_box_wraps_and_a_short_one_does_not() {
        // 10 touching spheres of diameter 0.101 at spacing 0.0999 along x in a box of length 1: a ring through the seam.
        let ring: Vec<DVec3> = (0..10).map(|k| DVec3::new(0.05 + 0.0999 * k as f64, 0.5, 0.5)).collect();
        let r = 0.0505;
        let list = agglomerate_list(&ring, &[r; 10], Some(&periodic_box()));
        assert_eq!(list.len(), 1);
        assert!(list[0].wraps);
        assert_eq!(agglomerates(&ring, &[r; 10], Some(&periodic_box())).wrapping, 1);
        let chain = &ring[..9];
        let list = agglomerate_list(chain, &[r; 9], Some(&periodic_box()));
        assert!(list.len() == 1 && !list[0].wraps);
        // Open space never wraps.
        assert!(!agglomerate_list(&ring, &[r; 10], None)[0].wraps);
    }

    #[test]
    fn labels_are_lowest_indices_and_match_brute_force() {
        // A random dilute periodic configuration: grid components = brute-force components.
        let mut rng = tumble_scene::Rng::new(7);
        let n = 400;
        let x: Vec<DVec3> = (0..n).map(|_| DVec3::new(rng.range(0.0, 1.0), rng.range(0.0, 1.0), rng.range(0.0, 1.0))).collect();
        let r: Vec<f64> = (0..n).map(|_| rng.range(0.02, 0.04)).collect();
        let b = periodic_box();
        let l = labels(&x, &r, Some(&b));
        let brute = labels_from_pairs(n, &tumble_broad::brute_force_pairs(&x, &r, &b));
        assert_eq!(l, brute);
        assert!(l.iter().enumerate().all(|(i, &k)| k as usize <= i && l[k as usize] == k));
        let s = agglomerates(&x, &r, Some(&b));
        assert_eq!(s.histogram.iter().sum::<usize>(), s.count);
        assert!(s.count < n && s.max_size > 2);
    }
}
