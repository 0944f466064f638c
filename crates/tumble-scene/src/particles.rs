//! Turning particle groups (explicit, lattice, random) into initial particle arrays.

use crate::compile::non_negative;
use crate::rng::Rng;
use crate::schema::{DomainSection, FlowSection, LatticeSection, NamedVelocity, OrientationSpec, ParticleGroup, ShapeSection, V3, VelocitySpec};
use crate::shapes::{ParticleShape, SPHERE};
use crate::sizes::CheckDiameter;
use crate::{Scene, SceneError};
use glam::{DQuat, DVec3};
use std::collections::HashMap;
use tumble_contact::FlowField;
use tumble_geom::PeriodicBox;
pub use tumble_plan::InitialParticles;

/// Generates every group's particles; `material_index` maps names to table indices and
/// `group_shape` gives each group's entry in `shapes` (None for spheres).
pub fn generate(
    scene: &Scene,
    material_index: &HashMap<String, u16>,
    group_shape: &[Option<u16>],
    shapes: &[ParticleShape],
) -> Result<InitialParticles, SceneError> {
    check_counts(scene)?;
    let mut out = InitialParticles::default();
    let mut rng = Rng::new(scene.run.seed);
    for (g, group) in scene.particles.iter().enumerate() {
        let field = |f: &str| format!("particles[{g}].{f}");
        let material = *material_index.get(&group.material).ok_or_else(|| {
            let known: Vec<&str> = scene.materials.iter().map(|m| m.name.as_str()).collect();
            SceneError::field(field("material"), format!("unknown material \"{}\"; defined materials: {}", group.material, known.join(", ")))
        })?;
        let shape = group_shape[g].map(|k| (k, &shapes[k as usize]));
        let sphere = match &group.shape {
            ShapeSection::Sphere(s) => Some(s),
            _ => None,
        };
        let mut diameter = |rng: &mut Rng| match (shape, sphere) {
            (Some((_, s)), _) => 2.0 * s.body.bounding_radius(),
            (None, Some(sphere)) => sphere.diameter.sample(rng),
            (None, None) => unreachable!("every non-sphere group has a shape"),
        };
        if shape.is_none() && group.orientation.is_some() {
            return Err(SceneError::field(field("orientation"), "spheres have no orientation; remove it (it is for polyhedra)"));
        }
        // ⟨d³⟩ of the group's (bounding) diameters, for the random fill check.
        let mean_cube = match (shape, sphere) {
            (Some((_, s)), _) => (2.0 * s.body.bounding_radius()).powi(3),
            (None, Some(sphere)) => sphere.diameter.mean_cube(),
            (None, None) => unreachable!("every non-sphere group has a shape"),
        };
        if let Some(r) = &group.random {
            check_region(field("random.region"), r.region.min, r.region.max, &scene.domain)?;
        }
        if let Some(l) = &group.lattice {
            check_region(field("lattice"), l.min, l.max, &scene.domain)?;
        }
        let centres = group_positions(group, g, &mut rng, &mut diameter, mean_cube)?;
        // velocity = "flow": the fluid velocity where each particle starts.
        let flow = match (&group.velocity, scene.fluid.as_ref().map(|f| &f.flow)) {
            (Some(VelocitySpec::Named(NamedVelocity::Flow)), Some(FlowSection::Uniform(u))) => Some(FlowField::Uniform(DVec3::from(*u))),
            (Some(VelocitySpec::Named(NamedVelocity::Flow)), Some(FlowSection::TaylorGreen(tg))) => {
                Some(FlowField::TaylorGreen { amplitude: tg.amplitude, frequency: tg.frequency })
            }
            (Some(VelocitySpec::Named(NamedVelocity::Flow)), None) => {
                return Err(SceneError::field(field("velocity"), "velocity = \"flow\" needs a [fluid] section with a flow"));
            }
            _ => None,
        };
        let given = given_orientation(group.orientation, &field("orientation"))?;
        for (x, d) in centres {
            let effect = match sphere.map(|s| (s.effect_diameter, s.effect_ratio)) {
                Some((Some(de), _)) => de,
                Some((None, Some(ratio))) => ratio * d,
                _ => d,
            };
            let (shape_index, volume, orientation) = match shape {
                None => (SPHERE, std::f64::consts::PI / 6.0 * d * d * d, DQuat::IDENTITY),
                Some((k, s)) => {
                    let user = match group.orientation {
                        Some(OrientationSpec::Named(_)) => rng.rotation(),
                        _ => given.unwrap_or(DQuat::IDENTITY),
                    };
                    (k, s.body.volume(), (user * s.as_given).normalize())
                }
            };
            let v = match &group.velocity {
                None => DVec3::ZERO,
                Some(VelocitySpec::Vector(v)) => DVec3::from(*v),
                Some(VelocitySpec::Random(r)) => rng.direction() * (r.random.mean_speed + r.random.std * rng.normal()),
                Some(VelocitySpec::Named(NamedVelocity::Flow)) => flow.map_or(DVec3::ZERO, |f| f.velocity(x)),
            };
            out.position.push(x);
            out.velocity.push(if group.fixed { DVec3::ZERO } else { v });
            out.angular_velocity.push(if group.fixed { DVec3::ZERO } else { DVec3::from(group.angular_velocity.unwrap_or_default()) });
            out.radius.push(0.5 * d);
            out.volume.push(volume);
            out.shape.push(shape_index);
            out.orientation.push(orientation);
            out.effect_radius.push(0.5 * effect);
            out.material.push(material);
            out.group.push(g as u16);
            out.fixed.push(group.fixed);
            out.track.push(group.track);
        }
    }
    Ok(out)
}

/// The particle groups' shapes and their generated particles, validated and inside the
/// domain (overlaps are checked with the walls, in `start`).
pub(crate) fn compile_particles(
    scene: &Scene,
    material_index: &HashMap<String, u16>,
    domain: &PeriodicBox,
) -> Result<(InitialParticles, Vec<ParticleShape>), SceneError> {
    let mut shapes = Vec::new();
    let mut group_shape = Vec::with_capacity(scene.particles.len());
    for (g, group) in scene.particles.iter().enumerate() {
        group_shape.push(crate::shapes::group_shape(group, g)?.map(|s| {
            shapes.push(s);
            (shapes.len() - 1) as u16
        }));
    }
    // Sizes and speeds are checked before any particle is placed: a NaN or negative diameter
    // passes the random-fill check and would place every particle of the group.
    for (g, group) in scene.particles.iter().enumerate() {
        let ShapeSection::Sphere(s) = &group.shape else { continue };
        let f = |x: &str| format!("particles[{g}].shape.sphere.{x}");
        s.diameter.check(&f("diameter"))?;
        if let Some(de) = s.effect_diameter {
            let d_max = s.diameter.max();
            if !(de >= d_max) {
                return Err(SceneError::field(f("effect_diameter"), format!("must be at least the body diameter {d_max}, got {de}")));
            }
        }
        if let Some(ratio) = s.effect_ratio
            && !(ratio >= 1.0)
        {
            return Err(SceneError::field(f("effect_ratio"), format!("must be at least 1, got {ratio}")));
        }
        if let Some(VelocitySpec::Random(r)) = &group.velocity {
            non_negative(&format!("particles[{g}].velocity.random.mean_speed"), r.random.mean_speed)?;
            non_negative(&format!("particles[{g}].velocity.random.std"), r.random.std)?;
        }
    }
    let particles = generate(scene, material_index, &group_shape, &shapes)?;
    if particles.is_empty() && scene.sources.is_empty() && scene.sph.is_none() {
        return Err(SceneError::field("particles", "the scene has no particles; add a [[particles]] group, a [[sources]] entry or an [sph] fluid"));
    }
    for i in 0..particles.len() {
        if !particles.position[i].is_finite() || !particles.velocity[i].is_finite() {
            return Err(SceneError::field(format!("particles[{}]", particles.group[i]), "positions and velocities must be finite numbers"));
        }
        if !domain.contains(particles.position[i]) {
            let p = particles.position[i];
            return Err(SceneError::field(
                format!("particles[{}]", particles.group[i]),
                format!("particle at [{}, {}, {}] lies outside the domain [{:?} .. {:?}]", p.x, p.y, p.z, scene.domain.min, scene.domain.max),
            ));
        }
    }
    Ok((particles, shapes))
}

/// A fixed orientation `[w, x, y, z]` normalised, or None for `"random"` or none given.
pub(crate) fn given_orientation(spec: Option<OrientationSpec>, field: &str) -> Result<Option<DQuat>, SceneError> {
    match spec {
        Some(OrientationSpec::Quaternion(q)) => {
            let q = DQuat::from_xyzw(q[1], q[2], q[3], q[0]);
            if !q.is_finite() || q.length() < 1e-12 {
                return Err(SceneError::field(field, "must be a non-zero quaternion [w, x, y, z] or \"random\""));
            }
            Ok(Some(q.normalize()))
        }
        _ => Ok(None),
    }
}

/// The most particles a scene may hold: ids are 32-bit.
const MAX_PARTICLES: f64 = u32::MAX as f64;

/// Bytes per particle that setting up and running a scene needs at the least (the initial
/// arrays, the state, a neighbour list), for the check against the memory available.
const SETUP_BYTES_PER_PARTICLE: f64 = 512.0;

/// How many particles group `group` asks for, before any is made (NaN-free; 0 where the
/// group's own checks will refuse it).
fn requested_count(group: &ParticleGroup) -> f64 {
    if let Some(list) = &group.positions {
        return list.len() as f64;
    }
    if let Some(l) = &group.lattice {
        if l.spacing.is_nan() || l.spacing <= 0.0 {
            return 0.0;
        }
        return lattice_counts(l).iter().product::<f64>().min(f64::MAX);
    }
    group.random.as_ref().map_or(0.0, |r| r.count as f64)
}

/// Lattice sites along each axis of `l` (whole spacings in max − min; `l.spacing` > 0).
fn lattice_counts(l: &LatticeSection) -> [f64; 3] {
    std::array::from_fn(|k| ((l.max[k] - l.min[k]) / l.spacing + 1e-9).floor().max(0.0))
}

/// The memory a run may still take, bytes, and what sets it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Available {
    pub bytes: f64,
    pub limit: &'static str,
}

impl std::fmt::Display for Available {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{:.1} GiB available ({})", self.bytes / (1u64 << 30) as f64, self.limit)
    }
}

/// The smallest of what Linux says is free (MemAvailable), what the process's address-space
/// limit leaves (`ulimit -v`, RLIMIT_AS, as batch schedulers set it, less what the process
/// already maps) and what its cgroup's memory.max leaves; None where none is known.
pub(crate) fn available_memory() -> Option<Available> {
    let read = |path: &str| std::fs::read_to_string(path).ok();
    let field = |text: &str, name: &str| -> Option<f64> {
        let line = text.lines().find(|l| l.starts_with(name))?;
        line.split_whitespace().nth(1)?.parse().ok()
    };
    let mut limits: Vec<Available> = Vec::new();
    if let Some(kib) = read("/proc/meminfo").and_then(|t| field(&t, "MemAvailable:")) {
        limits.push(Available { bytes: kib * 1024.0, limit: "this machine's free memory, MemAvailable" });
    }
    // "Max address space   <soft>   <hard>   bytes": a number where limited.
    let soft = read("/proc/self/limits").and_then(|t| {
        let line = t.lines().find(|l| l.starts_with("Max address space"))?.to_string();
        line["Max address space".len()..].split_whitespace().next()?.parse::<f64>().ok()
    });
    if let Some(soft) = soft {
        let mapped = read("/proc/self/status").and_then(|t| field(&t, "VmSize:")).map_or(0.0, |kib| kib * 1024.0);
        limits.push(Available { bytes: (soft - mapped).max(0.0), limit: "the address-space limit, ulimit -v" });
    }
    let cgroup = |name: &str| read(&format!("/sys/fs/cgroup/{name}")).and_then(|t| t.trim().parse::<f64>().ok());
    if let Some(max) = cgroup("memory.max") {
        limits.push(Available { bytes: (max - cgroup("memory.current").unwrap_or(0.0)).max(0.0), limit: "the cgroup's memory.max" });
    }
    limits.into_iter().min_by(|a, b| a.bytes.total_cmp(&b.bytes))
}

/// Refuses scenes whose groups ask for more particles than ids allow or memory holds, before
/// allocating any.
fn check_counts(scene: &Scene) -> Result<(), SceneError> {
    let counts: Vec<f64> = scene.particles.iter().map(requested_count).collect();
    let total: f64 = counts.iter().sum();
    let largest = counts.iter().enumerate().max_by(|a, b| a.1.total_cmp(b.1)).map_or(0, |(g, _)| g);
    let field = match scene.particles.get(largest) {
        Some(g) if g.lattice.is_some() => format!("particles[{largest}].lattice"),
        Some(g) if g.random.is_some() => format!("particles[{largest}].random.count"),
        _ => format!("particles[{largest}].positions"),
    };
    if total > MAX_PARTICLES {
        return Err(SceneError::field(
            field,
            format!("the groups ask for {total:.3e} particles; a scene holds at most {MAX_PARTICLES:.0} (32-bit ids)"),
        ));
    }
    if let Some(available) = available_memory()
        && total * SETUP_BYTES_PER_PARTICLE > available.bytes
    {
        return Err(SceneError::field(
            field,
            format!(
                "the groups ask for {total:.3e} particles, which need at least {:.1} GiB; there is {available}",
                total * SETUP_BYTES_PER_PARTICLE / (1u64 << 30) as f64,
            ),
        ));
    }
    Ok(())
}

/// Refuses a `random` region or a lattice that is not a box inside the domain before any
/// particle is placed in it (one far outside would place every particle before the domain check).
fn check_region(field: String, min: V3, max: V3, domain: &DomainSection) -> Result<(), SceneError> {
    let inside = (0..3).all(|k| {
        let slack = 1e-9 * (domain.max[k] - domain.min[k]).abs();
        min[k] < max[k] && min[k] >= domain.min[k] - slack && max[k] <= domain.max[k] + slack
    });
    if inside {
        return Ok(());
    }
    Err(SceneError::field(
        field,
        format!("[{min:?} .. {max:?}] must be a box (min < max on every axis) inside the domain [{:?} .. {:?}]", domain.min, domain.max),
    ))
}

/// Random sequential placement of equal spheres jams at a 38.4 % volume fraction and slows
/// as the gap to it cubed: 200,000 spheres take seconds at 30 % and a minute at 35 %.
const RANDOM_FILL_LIMIT: f64 = 0.30;

/// The share of a region of `size` that `count` spheres of mean cubed diameter `mean_cube` fill.
fn fill(count: usize, mean_cube: f64, size: DVec3) -> f64 {
    count as f64 * std::f64::consts::PI / 6.0 * mean_cube / (size.x * size.y * size.z).abs().max(f64::MIN_POSITIVE)
}

/// Refuses a `random` group of `count` whose (bounding) spheres, of mean cubed diameter
/// `mean_cube`, would fill more of the region of `size` than random placement can reach.
fn check_random_fill(g: usize, count: usize, mean_cube: f64, size: DVec3) -> Result<(), SceneError> {
    let fill = fill(count, mean_cube, size);
    if fill > RANDOM_FILL_LIMIT {
        return Err(SceneError::field(
            format!("particles[{g}].random.count"),
            format!(
                "{count} particles would fill {:.0} % of the region, more than the 30 % random placement without overlaps reaches quickly (it jams at 38 %); lower the count, enlarge random.region, use a lattice or pour them in with a [[sources]] entry",
                100.0 * fill
            ),
        ));
    }
    Ok(())
}

/// Particles allowed to overlap still may not crowd their region without end: once their
/// (bounding) spheres hold more than twice its volume, every particle overlaps many others
/// deeply, and the start's overlap check would pair thousands per cell for minutes.
fn check_overlapping_fill(g: usize, count: usize, mean_cube: f64, size: DVec3) -> Result<(), SceneError> {
    let fill = fill(count, mean_cube, size);
    if fill > OVERLAPPING_FILL_LIMIT {
        return Err(SceneError::field(
            format!("particles[{g}].random.count"),
            format!(
                "{count} particles' (bounding) spheres hold {fill:.3e} times the volume of random.region, more than the {OVERLAPPING_FILL_LIMIT} times overlapping placement allows; lower the count, enlarge random.region (lengths are in metres), or pour them in with a [[sources]] entry"
            ),
        ));
    }
    Ok(())
}

/// How many times its region's volume an overlapping random group's spheres may hold.
const OVERLAPPING_FILL_LIMIT: f64 = 2.0;

/// The cell of the placement grid: the largest diameter the group can draw (`first` is one
/// drawn), so that any sphere that overlaps a candidate lies in the 27 cells around it.
fn placement_cell(group: &ParticleGroup, first: f64) -> f64 {
    match group.shape {
        ShapeSection::Sphere(ref s) => s.diameter.max(),
        // Polyhedra are placed by their bounding spheres, all of one size.
        _ => first,
    }
}

/// A dense grid over the placement region of the spheres placed so far, each cell listing
/// them in placement order: the rejection test reads 27 cells without hashing.
struct PlacementGrid {
    min: DVec3,
    cell: f64,
    dims: [usize; 3],
    /// First sphere of each cell in `next`'s chains (`usize::MAX`: none).
    head: Vec<usize>,
    next: Vec<usize>,
}

impl PlacementGrid {
    fn new(min: DVec3, max: DVec3, cell: f64, count: usize) -> Self {
        let size = max - min;
        // Cells no smaller than a diameter, and not many more than the spheres to be placed.
        let sparse = (size.x * size.y * size.z / (4.0 * count.max(1) as f64 + 64.0)).cbrt();
        let mut cell = cell.max(sparse).max(f64::MIN_POSITIVE);
        let dims_for = |cell: f64| [size.x, size.y, size.z].map(|l| ((l / cell).floor() as usize).clamp(1, 1 << 20));
        let cells_for = |d: [usize; 3]| d[0].saturating_mul(d[1]).saturating_mul(d[2]);
        // A region flat on one axis has fewer cells along it than its volume suggests.
        while cells_for(dims_for(cell)) > 16 * count + 4096 {
            cell *= 2.0;
        }
        let dims = dims_for(cell);
        let cells = cells_for(dims);
        PlacementGrid { min, cell, dims, head: vec![usize::MAX; cells], next: Vec::with_capacity(count) }
    }

    fn coords(&self, x: DVec3) -> [usize; 3] {
        let c = (x - self.min) / self.cell;
        [
            (c.x.floor().max(0.0) as usize).min(self.dims[0] - 1),
            (c.y.floor().max(0.0) as usize).min(self.dims[1] - 1),
            (c.z.floor().max(0.0) as usize).min(self.dims[2] - 1),
        ]
    }

    fn index(&self, [i, j, k]: [usize; 3]) -> usize {
        (k * self.dims[1] + j) * self.dims[0] + i
    }

    /// Whether a sphere of diameter `d` at `x` overlaps none of `placed`.
    fn is_clear(&self, x: DVec3, d: f64, placed: &[(DVec3, f64)]) -> bool {
        let c = self.coords(x);
        let span = |a: usize, n: usize| a.saturating_sub(1)..=(a + 1).min(n - 1);
        for k in span(c[2], self.dims[2]) {
            for j in span(c[1], self.dims[1]) {
                for i in span(c[0], self.dims[0]) {
                    let mut s = self.head[self.index([i, j, k])];
                    while s != usize::MAX {
                        let (y, e) = placed[s];
                        if (x - y).length() < 0.5 * (d + e) {
                            return false;
                        }
                        s = self.next[s];
                    }
                }
            }
        }
        true
    }

    fn insert(&mut self, x: DVec3, sphere: usize) {
        let cell = self.index(self.coords(x));
        self.next.push(self.head[cell]);
        self.head[cell] = sphere;
    }
}

fn group_positions(
    group: &ParticleGroup,
    g: usize,
    rng: &mut Rng,
    diameter: &mut impl FnMut(&mut Rng) -> f64,
    mean_cube: f64,
) -> Result<Vec<(DVec3, f64)>, SceneError> {
    let field = |f: &str| format!("particles[{g}].{f}");
    let given = [group.positions.is_some(), group.lattice.is_some(), group.random.is_some()];
    if given.iter().filter(|&&b| b).count() != 1 {
        return Err(SceneError::field(
            format!("particles[{g}]"),
            "give exactly one of positions = [[x, y, z], …], lattice = { min, max, spacing } or random = { count, region }",
        ));
    }
    if let Some(list) = &group.positions {
        return Ok(list.iter().map(|p| (DVec3::from(*p), diameter(rng))).collect());
    }
    if let Some(l) = &group.lattice {
        let min = DVec3::from(l.min);
        if l.spacing <= 0.0 {
            return Err(SceneError::field(field("lattice.spacing"), format!("must be positive, got {}", l.spacing)));
        }
        if !(0.0..0.5).contains(&l.jitter) {
            return Err(SceneError::field(field("lattice.jitter"), format!("must be in [0, 0.5) of the spacing, got {}", l.jitter)));
        }
        let [nx, ny, nz] = lattice_counts(l).map(|c| c as usize);
        if nx * ny * nz == 0 {
            return Err(SceneError::field(field("lattice"), "the region holds no lattice site; make max − min at least one spacing on every axis"));
        }
        let mut out = Vec::with_capacity(nx * ny * nz);
        for k in 0..nz {
            for j in 0..ny {
                for i in 0..nx {
                    let site = min + DVec3::new(i as f64 + 0.5, j as f64 + 0.5, k as f64 + 0.5) * l.spacing;
                    let jitter = DVec3::new(rng.range(-1.0, 1.0), rng.range(-1.0, 1.0), rng.range(-1.0, 1.0)) * (l.jitter * l.spacing);
                    out.push((site + jitter, diameter(rng)));
                }
            }
        }
        return Ok(out);
    }
    let r = group.random.as_ref().unwrap();
    let (min, max) = (DVec3::from(r.region.min), DVec3::from(r.region.max));
    if r.no_overlap {
        check_random_fill(g, r.count, mean_cube, max - min)?;
    } else {
        check_overlapping_fill(g, r.count, mean_cube, max - min)?;
    }
    let mut out: Vec<(DVec3, f64)> = Vec::with_capacity(r.count);
    // Every diameter is drawn first and the largest placed first: a large sphere drawn late
    // finds no room between small ones, and redrawing it would bias the sizes small.
    let mut sizes: Vec<f64> = (0..r.count).map(|_| diameter(rng)).collect();
    let mixed = sizes.windows(2).any(|w| w[0] != w[1]);
    if r.no_overlap && mixed {
        sizes.sort_by(|a, b| b.total_cmp(a));
    }
    let mut grid = r.no_overlap.then(|| PlacementGrid::new(min, max, placement_cell(group, sizes.first().copied().unwrap_or(0.0)), r.count));
    let mut attempts = 0usize;
    // Attempts since the last sphere was placed: a jammed region places none, however long it is tried.
    let mut since_placed = 0usize;
    let stall = 10_000 + 10 * r.count;
    while out.len() < r.count {
        attempts += 1;
        since_placed += 1;
        if attempts > 1000 * r.count + 10_000 || since_placed > stall {
            return Err(SceneError::field(
                field("random.count"),
                format!(
                    "placed only {} of {} non-overlapping spheres in the region ({since_placed} tries in a row found no room); enlarge random.region or lower the count",
                    out.len(),
                    r.count
                ),
            ));
        }
        let d = sizes[out.len()];
        let half = DVec3::splat(0.5 * d);
        let x = DVec3::new(
            rng.range(min.x + half.x, max.x - half.x),
            rng.range(min.y + half.y, max.y - half.y),
            rng.range(min.z + half.z, max.z - half.z),
        );
        if let Some(grid) = &mut grid {
            if !grid.is_clear(x, d, &out) {
                continue;
            }
            grid.insert(x, out.len());
        }
        since_placed = 0;
        out.push((x, d));
    }
    if r.no_overlap && mixed {
        // Fisher–Yates, so that particle order (ids) does not follow size.
        for k in (1..out.len()).rev() {
            let m = ((rng.uniform() * (k + 1) as f64) as usize).min(k);
            out.swap(k, m);
        }
    }
    Ok(out)
}
