//! The starting state checked before step 1: overlaps between particles (every group) and
//! with walls, particles inside solid walls, and scales that point to a unit mistake.
//! A scene that fails gets one line naming the group or wall, how many and the worst case.

use crate::SceneError;
use crate::particles::InitialParticles;
use crate::plan::{Wall, WallGroup};
use crate::schema::{Scene, StartSection};
use crate::shapes::{ParticleShape, SPHERE};
use glam::DVec3;
use tumble_broad::CellGrid;
use tumble_geom::{PeriodicBox, Pose, polyhedron_polyhedron, sphere_polyhedron};

/// Fastest initial speed accepted, m/s: beyond it a scene is in the wrong units, not a DEM study.
pub(crate) const MAX_INITIAL_SPEED: f64 = 1.0e4;

/// Runs every starting-state check in a fixed order.
pub(crate) fn check_starting_state(
    scene: &Scene,
    p: &InitialParticles,
    shapes: &[ParticleShape],
    walls: &[Wall],
    groups: &[WallGroup],
    domain: &PeriodicBox,
) -> Result<(), SceneError> {
    check_scales(scene, p, domain)?;
    check_walls_near_domain(walls, groups, domain, scene.run.duration)?;
    let start = &scene.run.start;
    if start.allow_overlap {
        return Ok(());
    }
    check_pair_overlaps(scene, p, shapes, domain, start)?;
    check_wall_overlaps(scene, p, shapes, walls, groups, start)
}

/// Name of group `g` for messages: `particles[g]` with its name when it has one.
/// A name over 24 characters is cut to its first 20, so that a refusal naming two groups
/// still has room for its remedy.
fn group_label(scene: &Scene, g: u16) -> String {
    match &scene.particles[g as usize].name {
        Some(n) if n.chars().count() > 24 => format!("particles[{g}] (\"{}…\")", n.chars().take(20).collect::<String>()),
        Some(n) => format!("particles[{g}] (\"{n}\")"),
        None => format!("particles[{g}]"),
    }
}

/// The diameter the overlap tolerance is measured in: a sphere's, or a polyhedron's
/// sphere of equal volume.
fn size(p: &InitialParticles, shapes: &[ParticleShape], i: usize) -> f64 {
    match p.shape[i] {
        SPHERE => 2.0 * p.radius[i],
        k => 2.0 * shapes[k as usize].equivalent_radius,
    }
}

fn check_scales(scene: &Scene, p: &InitialParticles, domain: &PeriodicBox) -> Result<(), SceneError> {
    let extent = domain.extent();
    let smallest = extent.min_element();
    let mut largest: Option<(usize, f64)> = None;
    for i in 0..p.len() {
        let d = 2.0 * p.radius[i];
        if largest.is_none_or(|(_, l)| d > l) {
            largest = Some((i, d));
        }
        // The largest component where the length overflows.
        let magnitude = |v: DVec3| if v.length().is_finite() { v.length() } else { v.abs().max_element() };
        let speed = magnitude(p.velocity[i]) + magnitude(p.angular_velocity[i]) * p.radius[i];
        if !(speed <= MAX_INITIAL_SPEED) {
            return Err(SceneError::field(
                format!("particles[{}].velocity", p.group[i]),
                format!(
                    "a particle of {} starts at {speed:.3e} m/s (centre plus spin at its surface); speeds are in m/s and at most {MAX_INITIAL_SPEED:.0e} m/s are accepted",
                    group_label(scene, p.group[i])
                ),
            ));
        }
    }
    if let Some((i, d)) = largest
        && d >= smallest
    {
        let axis = ["x", "y", "z"][(0..3).min_by(|&a, &b| extent[a].total_cmp(&extent[b])).unwrap_or(0)];
        let what = if p.shape[i] == SPHERE { "diameter" } else { "bounding diameter" };
        return Err(SceneError::field(
            format!("particles[{}].shape", p.group[i]),
            format!(
                "a particle of {} has a {what} of {} m, not smaller than the domain ({} m along {axis}); lengths are in metres, not millimetres",
                group_label(scene, p.group[i]),
                number(d),
                number(smallest)
            ),
        ));
    }
    Ok(())
}

/// Poses at which a moving wall is measured against the domain, evenly over the run.
const WALL_POSES: usize = 16;

/// A wall further from the domain than the domain is large touches nothing: a unit or sign
/// mistake. A moving wall counts by its nearest pose over the run (a piston may start away).
fn check_walls_near_domain(walls: &[Wall], groups: &[WallGroup], domain: &PeriodicBox, duration: f64) -> Result<(), SceneError> {
    let (lo, hi) = (domain.min, domain.max);
    let size = (hi - lo).length();
    for w in walls {
        let poses = if w.motion.is_some() { WALL_POSES } else { 0 };
        let distance = (0..=poses)
            .map(|i| if poses == 0 { w.shape.clone() } else { w.shape_at(duration * i as f64 / poses as f64) })
            .map(|shape| distance_to_box(&shape, lo, hi))
            .fold(f64::INFINITY, f64::min);
        if distance > size {
            let g = w.group as usize;
            return Err(SceneError::field(
                format!("walls[{g}]"),
                format!(
                    "wall \"{}\" lies {distance:.3e} m outside the domain [{:?} .. {:?}], more than the domain's own size; check its position and units (metres)",
                    groups[g].name,
                    lo.to_array(),
                    hi.to_array()
                ),
            ));
        }
    }
    Ok(())
}

/// How far a wall's surface stays from the box [lo, hi] (0 where it passes through), at
/// least: the nearest corner, vertex or bounding sphere.
fn distance_to_box(shape: &tumble_geom::SurfaceShape, lo: DVec3, hi: DVec3) -> f64 {
    use tumble_geom::SurfaceShape;
    let size = (hi - lo).length();
    // Distance from the domain box to a point (0 inside).
    let to_box = |x: DVec3| (x.clamp(lo, hi) - x).length();
    match shape {
        SurfaceShape::Plane(pl) => {
            // The plane misses the box when every corner lies on one side; the gap is the nearest corner's.
            let d: Vec<f64> = (0..8)
                .map(|c| DVec3::new([lo.x, hi.x][c & 1], [lo.y, hi.y][(c >> 1) & 1], [lo.z, hi.z][c >> 2]))
                .map(|x| pl.normal.dot(x - pl.point))
                .collect();
            let (min, max) = d.iter().fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), &v| (a.min(v), b.max(v)));
            if min > 0.0 {
                min
            } else if max < 0.0 {
                -max
            } else {
                0.0
            }
        }
        SurfaceShape::Quad(q) => q.corners.iter().map(|&c| to_box(c)).fold(f64::INFINITY, f64::min),
        SurfaceShape::Prism(pr) => (to_box(pr.centre) - pr.bound).max(0.0),
        SurfaceShape::Mesh(m) => (crate::mesh_walls::nearest_distance(m, 0.5 * (lo + hi)) - 0.5 * size).max(0.0),
        SurfaceShape::Cylinder(c) => {
            // The axis's closest approach to the box centre: the shell is far when it passes
            // beyond the box, or encloses it with room to spare (a drum of radius 150 in a 0.3 m domain).
            let centre = 0.5 * (lo + hi);
            let r = centre - c.point;
            let off_axis = (r - c.axis * c.axis.dot(r)).length();
            (off_axis - c.radius - 0.5 * size).max(c.radius - off_axis - 0.5 * size).max(0.0)
        }
    }
}

/// Overlapping pairs counted before the pair check stops looking.
const MAX_COUNTED: usize = 10_000;

/// The deepest overlaps found by one check: how many exceed the tolerance, and the worst.
#[derive(Default)]
struct Overlaps {
    count: usize,
    /// (depth over the smaller size, depth m, particle a, particle b or wall index)
    worst: Option<(f64, f64, usize, usize)>,
}

impl Overlaps {
    fn add(&mut self, ratio: f64, depth: f64, a: usize, b: usize) {
        self.count += 1;
        if self.worst.is_none_or(|(r, ..)| ratio > r) {
            self.worst = Some((ratio, depth, a, b));
        }
    }
}

/// A length to six significant digits, in exponent form when very large or small.
fn number(x: f64) -> String {
    if (1e-4..1e6).contains(&x.abs()) { format!("{:.5e}", x).parse::<f64>().unwrap_or(x).to_string() } else { format!("{x:.5e}") }
}

/// A position to six significant digits: `[-0.0775, 0.0925, 0]`.
fn shown(x: DVec3) -> String {
    let c = x.to_array().map(|v| format!("{:.5e}", v).parse::<f64>().unwrap_or(v).to_string());
    format!("[{}]", c.join(", "))
}

/// The advice every overlap error ends with.
fn overlap_advice(start: &StartSection) -> String {
    format!(
        "the start allows run.start.max_overlap = {} of the smaller diameter: space them further apart, raise it, or set run.start.allow_overlap = true",
        start.max_overlap
    )
}

fn check_pair_overlaps(
    scene: &Scene,
    p: &InitialParticles,
    shapes: &[ParticleShape],
    domain: &PeriodicBox,
    start: &StartSection,
) -> Result<(), SceneError> {
    let n = p.len();
    if n == 0 {
        return Ok(());
    }
    let r_max = p.radius.iter().fold(0.0f64, |a, &r| a.max(r));
    // Cells fit all but the largest hundredth of the particles: cells one largest diameter
    // wide would put a bed of small spheres around a few large bodies in a handful of cells,
    // and the check would test every pair. A particle wider than a cell is checked against
    // every cell its reach covers.
    let mut radii = p.radius.clone();
    radii.sort_by(f64::total_cmp);
    let r_cell = radii[(n - 1) * 99 / 100];
    // The grid spans the particles (a large domain around a small bed would put them all in a
    // few cells), with cells about one particle each.
    let (lo, hi) = p.position.iter().fold((DVec3::INFINITY, DVec3::NEG_INFINITY), |(a, b), &x| (a.min(x), b.max(x)));
    let mut bounds = *domain;
    for k in 0..3 {
        if !domain.periodic[k] {
            bounds.min[k] = lo[k];
            bounds.max[k] = hi[k].max(lo[k] + 2.0 * r_max);
        }
    }
    let volume = bounds.extent().element_product();
    let min_cell = (2.0 * r_cell).max((volume / n as f64).cbrt());
    let large = |i: usize| 2.0 * p.radius[i] > min_cell;
    let mut grid = CellGrid::new(&bounds, min_cell);
    grid.build(&p.position);
    let order = grid.order();
    // Groups whose random placement was asked to allow overlaps keep them among themselves.
    let overlapping_group = |g: u16| scene.particles[g as usize].random.as_ref().is_some_and(|r| !r.no_overlap);
    let mut found = Overlaps::default();
    let check = |i: usize, j: usize, found: &mut Overlaps| {
        if p.group[i] == p.group[j] && overlapping_group(p.group[i]) {
            return;
        }
        let d = domain.minimum_image(p.position[i] - p.position[j]);
        let sphere_overlap = p.radius[i] + p.radius[j] - d.length();
        if sphere_overlap <= 0.0 {
            return;
        }
        let depth = body_overlap(p, shapes, i, j, d, sphere_overlap);
        let smaller = size(p, shapes, i).min(size(p, shapes, j));
        if depth > start.max_overlap * smaller {
            found.add(depth / smaller, depth, i, j);
        }
    };
    for &i in order {
        // Deep overlaps pack many particles per cell: past the cap the count is a lower bound.
        if found.count >= MAX_COUNTED {
            break;
        }
        let i = i as usize;
        if large(i) {
            continue;
        }
        grid.for_each_neighbour_run(grid.cell_of(i), |s0, s1| {
            for &j in &order[s0..s1] {
                let j = j as usize;
                // Each pair once.
                if j > i && !large(j) {
                    check(i, j, &mut found);
                }
            }
        });
    }
    let (dims, cell) = (grid.dims(), grid.cell_size());
    for i in (0..n).filter(|&i| large(i)) {
        if found.count >= MAX_COUNTED {
            break;
        }
        // Every cell within the largest reach of particle i, each once.
        let c = grid.cell_coords(p.position[i]);
        let axis = |k: usize| -> Vec<usize> {
            let reach = ((p.radius[i] + r_max) / cell[k]).ceil() as usize + 1;
            if 2 * reach + 1 >= dims[k] {
                return (0..dims[k]).collect();
            }
            let (c, n) = (c[k] as isize, dims[k] as isize);
            let wrap = |v: isize| if domain.periodic[k] { Some(v.rem_euclid(n) as usize) } else { (0..n).contains(&v).then_some(v as usize) };
            (-(reach as isize)..=reach as isize).filter_map(|o| wrap(c + o)).collect()
        };
        let (xs, ys, zs) = (axis(0), axis(1), axis(2));
        for &z in &zs {
            for &y in &ys {
                for &x in &xs {
                    let (s0, s1) = grid.cell_range(x + dims[0] * (y + dims[1] * z));
                    for &j in &order[s0..s1] {
                        let j = j as usize;
                        // A pair of large particles once, from the lower index.
                        if j != i && (!large(j) || j > i) {
                            check(i, j, &mut found);
                        }
                    }
                }
            }
        }
    }
    let Some((ratio, depth, i, j)) = found.worst else { return Ok(()) };
    let (gi, gj) = (p.group[i].min(p.group[j]), p.group[i].max(p.group[j]));
    let between = if gi == gj {
        format!("within {}", group_label(scene, gi))
    } else {
        format!("between {} and {}", group_label(scene, gi), group_label(scene, gj))
    };
    let how_many = match found.count {
        1 => "a pair of particles overlaps at the start".to_string(),
        n if n >= MAX_COUNTED => format!("at least {n} pairs of particles overlap at the start; the worst of those"),
        n => format!("{n} pairs of particles overlap at the start; the worst"),
    };
    Err(SceneError::field(
        format!("particles[{gj}]"),
        format!(
            "{how_many} ({between}) by {depth:.3e} m = {ratio:.3} of the smaller diameter, at {} and {}; {}",
            shown(p.position[i]),
            shown(p.position[j]),
            overlap_advice(start)
        ),
    ))
}

/// Depth of the body overlap of i and j at separation `d` = x_i − x_j (the bounding spheres
/// overlap by `sphere_overlap`); polyhedra by their separating-axis contact.
pub(crate) fn body_overlap(p: &InitialParticles, shapes: &[ParticleShape], i: usize, j: usize, d: DVec3, sphere_overlap: f64) -> f64 {
    let pose = |k: usize, x: DVec3| (&shapes[p.shape[k] as usize].body, Pose::new(x, p.orientation[k]));
    let (xi, xj) = (p.position[i], p.position[i] - d);
    let contact = match (p.shape[i] != SPHERE, p.shape[j] != SPHERE) {
        (false, false) => return sphere_overlap,
        (true, true) => {
            let ((a, pa), (b, pb)) = (pose(i, xi), pose(j, xj));
            polyhedron_polyhedron(a, &pa, b, &pb)
        }
        (true, false) => {
            let (a, pa) = pose(i, xi);
            sphere_polyhedron(xj, p.radius[j], a, &pa)
        }
        (false, true) => {
            let (b, pb) = pose(j, xj);
            sphere_polyhedron(xi, p.radius[i], b, &pb)
        }
    };
    contact.map_or(-1.0, |c| c.depth)
}

fn check_wall_overlaps(
    scene: &Scene,
    p: &InitialParticles,
    shapes: &[ParticleShape],
    walls: &[Wall],
    groups: &[WallGroup],
    start: &StartSection,
) -> Result<(), SceneError> {
    let mut found = Overlaps::default();
    for (k, w) in walls.iter().enumerate() {
        let shape = w.shape_at(0.0);
        for i in 0..p.len() {
            let depth = match p.shape[i] {
                SPHERE => shape.sphere_contact(p.position[i], p.radius[i]).map_or(0.0, |c| c.overlap),
                s => {
                    if shape.sphere_contact(p.position[i], p.radius[i]).is_none() {
                        continue;
                    }
                    let pose = Pose::new(p.position[i], p.orientation[i]);
                    shape.polyhedron_depth(&shapes[s as usize].body, &pose).unwrap_or(0.0)
                }
            };
            let d = size(p, shapes, i);
            if depth > start.max_overlap * d {
                found.add(depth / d, depth, i, k);
            }
        }
    }
    let Some((ratio, depth, i, k)) = found.worst else { return Ok(()) };
    let g = walls[k].group as usize;
    let inside = if ratio >= 1.0 { " (inside the wall's solid side)" } else { "" };
    let how_many = match found.count {
        1 => "a particle overlaps a wall at the start".to_string(),
        n => format!("{n} particle–wall overlaps at the start; the worst"),
    };
    Err(SceneError::field(
        format!("walls[{g}]"),
        format!(
            "{how_many}: a particle of {} at {} overlaps wall \"{}\" by {depth:.3e} m = {ratio:.3} of its diameter{inside}; {}",
            group_label(scene, p.group[i]),
            shown(p.position[i]),
            groups[g].name,
            overlap_advice(start)
        ),
    ))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A few large spheres among many small ones (a periodic axis, one large sphere across its
    /// boundary): the pair check counts exactly the overlapping pairs every pair tested directly
    /// counts. Cells sized for the largest sphere made this check test every pair of a 140,000
    /// particle bed (44 s, found by the scene fuzzer).
    #[test]
    fn large_bodies_among_small_spheres_find_every_overlapping_pair() {
        let text = r#"
name = "mixed"
[run]
duration = 0.001
start = { allow_overlap = true }
[domain]
min = [0.0, 0.0, 0.0]
max = [0.4, 0.3, 0.3]
periodic = [true, false, false]
[[materials]]
name = "m"
density = 1000.0
[contact]
normal = { model = "linear", stiffness = 1000.0 }
restitution = 0.5
[[particles]]
material = "m"
shape = { sphere = { diameter = 0.12 } }
positions = [[0.01, 0.15, 0.15], [0.2, 0.1, 0.1], [0.25, 0.2, 0.2]]
[[particles]]
material = "m"
shape = { sphere = { diameter = 0.01 } }
lattice = { min = [0.005, 0.005, 0.005], max = [0.395, 0.295, 0.295], spacing = 0.02, jitter = 0.1 }
"#;
        let mut scene = crate::parse_scene(text).unwrap();
        let compiled = crate::compile(&scene).unwrap();
        let (p, domain) = (&compiled.particles, &compiled.plan.model.domain);
        scene.run.start.allow_overlap = false;
        let start = &scene.run.start;
        let mut direct = 0;
        for i in 0..p.len() {
            for j in i + 1..p.len() {
                let depth = p.radius[i] + p.radius[j] - domain.minimum_image(p.position[i] - p.position[j]).length();
                direct += usize::from(depth > start.max_overlap * 2.0 * p.radius[i].min(p.radius[j]));
            }
        }
        let why = check_pair_overlaps(&scene, p, &compiled.plan.model.shapes, domain, start).unwrap_err().to_string();
        println!("{} particles: {direct} overlapping pairs; {why}", p.len());
        assert!(direct > 100 && direct < MAX_COUNTED, "the scene must overlap, below the cap: {direct}");
        assert!(why.contains(&format!(" {direct} pairs of particles overlap")), "{why}");
    }
}
