//! Host-side data for the device: the particle arrays in f32 (positions relative
//! to the domain's centre), the pair and wall tables, the cell grid and
//! the step parameters.

use bytemuck::{Pod, Zeroable};
use glam::DVec3;
use tumble_contact::{FlowField, NormalLaw, SpringLaw, TangentialLaw, ViscousParameter};
use tumble_state::State;
use tumble_geom::SurfaceShape;
use tumble_scene::Plan;

use crate::prisms::PrismHulls;

/// Particle flags (common.wgsl).
pub const FLAG_FIXED: u32 = 1;
pub const FLAG_DEAD: u32 = 2;

/// props.w holds the shape index from this bit on (forces.wgsl `shape_of`).
pub const SHAPE_SHIFT: u32 = 16;

/// Threads per workgroup of the particle kernels (common.wgsl WORKGROUP).
pub const WORKGROUP: u32 = 64;
/// Values per workgroup of the scan (scan.wgsl BLOCK) and its threads.
pub const SCAN_BLOCK: u32 = 1024;
pub const SCAN_THREADS: u32 = 256;
/// Most workgroups along one dispatch axis.
pub const MAX_GROUPS_X: u32 = 65_535;

/// The step parameters (common.wgsl `Params`).
#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable)]
pub struct Params {
    pub counts: [u32; 4],
    pub dims: [u32; 4],
    pub periodic: [u32; 4],
    pub inv_cell: [f32; 4],
    pub extent: [f32; 4],
    pub gravity: [f32; 4],
    pub flow: [f32; 4],
    pub origin: [f32; 4],
}

/// One level of the scan (scan.wgsl `ScanParams`).
#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable)]
pub struct ScanParams {
    pub n: u32,
    pub offsets: u32,
    pub row: u32,
    pub pad: u32,
}

/// The uniform cell grid over the domain: cells at least one interaction
/// diameter wide, tiling periodic axes exactly, at most `max_cells` in all.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Grid {
    pub dims: [u32; 3],
    pub inv_width: [f64; 3],
}

impl Grid {
    pub fn new(plan: &Plan, particles: usize) -> Grid {
        let extent = plan.domain.extent();
        // A hair wider than the largest interaction diameter, so f32 rounding never hides a neighbour.
        let width = (plan.cell_size * (1.0 + 1e-4)).max(1e-12);
        let mut dims = [0, 1, 2].map(|k| ((extent[k] / width).floor()).clamp(1.0, (1u32 << 20) as f64));
        // Eight cells per particle at most: the binning passes sweep every cell each step, which
        // would cost a few particles in a large domain far more than their contacts do.
        let max_cells = (8.0 * particles as f64).max(512.0);
        let total: f64 = dims.iter().product();
        if total > max_cells {
            let shrink = (total / max_cells).cbrt();
            dims = dims.map(|d| (d / shrink).floor().max(1.0));
        }
        Grid { dims: dims.map(|d| d as u32), inv_width: [0, 1, 2].map(|k| dims[k] / extent[k]) }
    }

    pub fn cells(&self) -> u32 {
        self.dims.iter().product()
    }
}

/// Workgroups (x, y) covering `threads` invocations of `per_group` each; rows are `MAX_GROUPS_X` wide.
pub fn dispatch(threads: u32, per_group: u32) -> (u32, u32) {
    let groups = threads.div_ceil(per_group).max(1);
    let x = groups.min(MAX_GROUPS_X);
    (x, groups.div_ceil(x))
}

/// The step parameters; `shape_base`: the first word of the shape table in the tables buffer.
pub fn params(plan: &Plan, grid: &Grid, slots: u32, shape_base: usize) -> Params {
    let e = plan.domain.extent();
    let f4 = |v: DVec3, w: f64| [v.x as f32, v.y as f32, v.z as f32, w as f32];
    let flow = match plan.fluid.map(|f| f.flow) {
        Some(FlowField::Uniform(u)) => f4(u, 0.0),
        Some(FlowField::TaylorGreen { amplitude, frequency }) => [amplitude as f32, frequency as f32, 0.0, 0.0],
        None => [0.0; 4],
    };
    Params {
        counts: [slots, grid.cells(), plan.walls.len() as u32, plan.materials.len() as u32],
        dims: [grid.dims[0], grid.dims[1], grid.dims[2], MAX_GROUPS_X * WORKGROUP],
        periodic: [plan.domain.periodic[0] as u32, plan.domain.periodic[1] as u32, plan.domain.periodic[2] as u32, history_slots(plan) as u32],
        inv_cell: [grid.inv_width[0] as f32, grid.inv_width[1] as f32, grid.inv_width[2] as f32, plan.dt as f32],
        extent: f4(e, 0.0),
        gravity: f4(plan.gravity, shape_base as f64),
        flow,
        // w: wall groups (walls_moving.wgsl).
        origin: f4(centre(plan), plan.wall_groups.len() as f64),
    }
}

/// Contact-history slots per particle on the device (0 without history).
pub fn history_slots(plan: &Plan) -> usize {
    if plan.history { plan.history_slots } else { 0 }
}

/// The domain's centre: device positions are relative to it (f32 precision is best near 0).
pub fn centre(plan: &Plan) -> DVec3 {
    0.5 * (plan.domain.min + plan.domain.max)
}

/// The per-particle arrays, as the device holds them (upload.rs and the shaders agree on the packing).
#[derive(Clone, Debug, Default)]
pub struct ParticleArrays {
    /// Position relative to the domain's centre, radius.
    pub pos: Vec<[f32; 4]>,
    /// Velocity, inverse mass.
    pub vel: Vec<[f32; 4]>,
    /// Angular velocity, inverse moment of inertia.
    pub omega: Vec<[f32; 4]>,
    /// Acceleration, drag parameter (τ_p or α/m).
    pub acc: Vec<[f32; 4]>,
    /// Angular acceleration, mass.
    pub alpha: Vec<[f32; 4]>,
    /// Reach (f32 bits), material, id, flags.
    pub props: Vec<[u32; 4]>,
    /// Dissipated energy, fluid work, and their Kahan compensations.
    pub energy: Vec<[f32; 4]>,
    /// Orientation quaternion (x, y, z, w), polyhedra scenes only (empty otherwise).
    pub orient: Vec<[f32; 4]>,
}

impl ParticleArrays {
    pub fn from_state(s: &State, plan: &Plan) -> Self {
        let origin = centre(plan);
        let mut a = ParticleArrays::default();
        for i in 0..s.len() {
            let x = s.pos[i] - origin;
            let v = s.vel[i];
            let w = if s.omega.is_empty() { DVec3::ZERO } else { s.omega[i] };
            let inv_inertia = if s.inv_inertia.is_empty() {
                if s.inv_mass[i] == 0.0 { 0.0 } else { 1.0 / (0.4 * s.mass[i] * s.radius[i] * s.radius[i]) }
            } else {
                s.inv_inertia[i]
            };
            let drag = if s.drag.is_empty() { 0.0 } else { s.drag[i] };
            a.pos.push([x.x as f32, x.y as f32, x.z as f32, s.radius[i] as f32]);
            a.vel.push([v.x as f32, v.y as f32, v.z as f32, s.inv_mass[i] as f32]);
            a.omega.push([w.x as f32, w.y as f32, w.z as f32, inv_inertia as f32]);
            a.acc.push([0.0, 0.0, 0.0, drag as f32]);
            a.alpha.push([0.0, 0.0, 0.0, s.mass[i] as f32]);
            let mut flags = if s.inv_mass[i] == 0.0 { FLAG_FIXED } else { 0 };
            if plan.polyhedra {
                // The shape index (SPHERE = 0xffff for spheres) in the high 16 bits.
                flags |= (s.shape[i] as u32) << SHAPE_SHIFT;
                let q = s.orient[i];
                a.orient.push([q.x as f32, q.y as f32, q.z as f32, q.w as f32]);
            }
            a.props.push([(s.reach[i] as f32).to_bits(), s.material[i] as u32, s.id[i], flags]);
            a.energy.push([0.0; 4]);
        }
        a
    }
}

/// The polyhedron shapes of a plan as the device takes them: its particle shapes, then its
/// lifter bars' hulls (prisms.rs).
pub fn plan_shapes(plan: &Plan, hulls: &PrismHulls) -> Result<Vec<[f32; 4]>, crate::GpuError> {
    let bodies: Vec<tumble_geom::Polyhedron> = plan.shapes.iter().map(|s| s.body.clone()).chain(hulls.shapes().cloned()).collect();
    crate::shapes::shape_table(&bodies).map_err(|e| crate::GpuError::Feature(e.0))
}

/// The pair table (3 vec4 per material pair) followed by the wall section (6 vec4 per wall, then
/// the walls' extras: motion, prism faces; see [`wall_table`]), then the shape table (shapes.rs)
/// when the plan has polyhedra; see forces.wgsl. Returns the tables and the first entry of the
/// shape table, which follows everything the walls append so the two regions never overlap.
pub fn tables_with_shapes(plan: &Plan, hulls: &PrismHulls) -> Result<(Vec<[f32; 4]>, usize), crate::GpuError> {
    let mut t = tables(plan, hulls);
    if !plan.polyhedra {
        return Ok((t, 0));
    }
    let shapes = plan_shapes(plan, hulls)?;
    let base = t.len();
    t.extend_from_slice(&shapes);
    if t.len() * 4 >= 1 << 24 {
        return Err(crate::GpuError::Feature(format!("the shape table ends at word {}; indices must stay below 2^22", t.len())));
    }
    Ok((t, base))
}

/// The pair table (3 vec4 per material pair) followed by the walls at t = 0 (see [`wall_table`]).
pub fn tables(plan: &Plan, hulls: &PrismHulls) -> Vec<[f32; 4]> {
    let mut t = pair_table(plan);
    t.extend(wall_table(plan, 0.0, hulls));
    if t.is_empty() {
        t.push([0.0; 4]);
    }
    t
}

/// The pair table: 3 vec4 per material pair (forces.wgsl).
pub fn pair_table(plan: &Plan) -> Vec<[f32; 4]> {
    let mut t = Vec::new();
    for p in &plan.pairs {
        let e = p.normal.restitution();
        let factor = (std::f64::consts::PI.powi(2) + e.ln().powi(2)).sqrt();
        t.push(match p.normal {
            NormalLaw::Linear { stiffness, damping_ratio, .. } => [0.0, stiffness as f32, damping_ratio as f32, factor as f32],
            NormalLaw::Hertz { e_star, beta, .. } => [1.0, e_star as f32, beta as f32, factor as f32],
        });
        t.push(match p.tangential {
            TangentialLaw::None => [0.0; 4],
            TangentialLaw::ViscousCoulomb { friction, viscous: ViscousParameter::Coefficient(c) } => [1.0, friction as f32, c as f32, 0.0],
            TangentialLaw::ViscousCoulomb { friction, viscous: ViscousParameter::Stiffness(k) } => [1.0, friction as f32, k as f32, 1.0],
            TangentialLaw::StickLimited { friction } => [2.0, friction as f32, 0.0, 0.0],
            TangentialLaw::DynamicOnly { friction } => [3.0, friction as f32, 0.0, 0.0],
            TangentialLaw::History { friction, spring: SpringLaw::Linear { stiffness, damping_ratio, .. } } => {
                [4.0, friction as f32, stiffness as f32, damping_ratio as f32]
            }
            TangentialLaw::History { friction, spring: SpringLaw::Mindlin { g_star, beta } } => [5.0, friction as f32, g_star as f32, beta as f32],
        });
        let history_damping = match p.tangential {
            TangentialLaw::History { spring: SpringLaw::Linear { damping, .. }, .. } => damping,
            _ => 0.0,
        };
        t.push([p.cohesion as f32, if p.no_attraction { 1.0 } else { 0.0 }, p.rolling as f32, history_damping as f32]);
    }
    t
}

/// True when some wall moves (the MOVING switch: wall velocities, poses uploaded every step, wall power).
pub fn moving_walls(plan: &Plan) -> bool {
    plan.walls.iter().any(|w| w.motion.is_some())
}

/// The wall section of the table (it follows the pair table, at `3 · materials²`) with every
/// wall in its pose at time `t`: 6 vec4 per wall (geometry.wgsl), then each wall's extras
/// (walls_moving.wgsl: its motion when some wall moves, a prism's faces and, with polyhedral
/// particles, its hull's pose), whose first index is the entry's w0.w.
pub fn wall_table(plan: &Plan, t: f64, hulls: &PrismHulls) -> Vec<[f32; 4]> {
    let walls_base = 3 * plan.pairs.len();
    let moving = moving_walls(plan);
    let origin = centre(plan);
    let mut main = Vec::with_capacity(6 * plan.walls.len());
    let mut extras = Vec::new();
    for (k, w) in plan.walls.iter().enumerate() {
        let extra = (walls_base + 6 * plan.walls.len() + extras.len()) as f32;
        if moving {
            // ω and the velocity at the domain's centre: v(x) = ω × (x − centre) + v(centre).
            let spin = w.angular_velocity();
            extras.push([spin.x as f32, spin.y as f32, spin.z as f32, w.group as f32]);
            let v = w.velocity_at(origin);
            extras.push([v.x as f32, v.y as f32, v.z as f32, 0.0]);
        }
        let shape = if w.motion.is_some() { std::borrow::Cow::Owned(w.shape_at(t)) } else { std::borrow::Cow::Borrowed(&w.shape) };
        let mut entry = wall_entry(shape.as_ref(), w.material as usize, origin);
        if let SurfaceShape::Prism(p) = shape.as_ref() {
            let rel = |p: DVec3| {
                let x = p - origin;
                [x.x as f32, x.y as f32, x.z as f32, 0.0]
            };
            let dir = |v: DVec3| [v.x as f32, v.y as f32, v.z as f32, 0.0];
            let centre = rel(p.centre);
            extras.push([centre[0], centre[1], centre[2], p.bound as f32]);
            let axis_point = rel(p.axis_point);
            extras.push([axis_point[0], axis_point[1], axis_point[2], p.inner as f32]);
            extras.push(dir(p.axis));
            for f in &p.faces {
                extras.extend(f.corners.map(rel));
                extras.push(dir(f.normal));
            }
            if let Some((hull, pose)) = hulls.pose(k, p) {
                // The hull's centre (w: its shape index) and orientation, for polyhedral particles.
                let x = rel(pose.position);
                extras.push([x[0], x[1], x[2], hull as f32]);
                let q = pose.rotation;
                extras.push([q.x as f32, q.y as f32, q.z as f32, q.w as f32]);
            }
        }
        // w0.w: the first index of this wall's extras (walls_moving.wgsl).
        entry[0][3] = extra;
        main.extend_from_slice(&entry);
    }
    main.extend(extras);
    main
}

/// Why the GPU backend cannot run the plan's walls, if it cannot.
pub fn unsupported_walls(plan: &Plan, hulls: &PrismHulls) -> Option<String> {
    // The contact pass books each group's power once, walking the walls in group order.
    if moving_walls(plan) && plan.walls.windows(2).any(|w| w[1].group < w[0].group) {
        return Some("its wall surfaces are not in wall-group order".into());
    }
    // Table indices are stored as f32 (exact below 2^24).
    let entries = 3 * plan.pairs.len() + wall_table(plan, 0.0, hulls).len();
    if entries >= 1 << 24 {
        return Some(format!("its pair and wall tables have {entries} entries (at most 2^24)"));
    }
    None
}

/// One wall's table entry (6 vec4, geometry.wgsl), coordinates relative to `origin`; w0.w
/// (the extras' index) is left 0 for [`wall_table`] to fill.
pub fn wall_entry(shape: &SurfaceShape, material: usize, origin: DVec3) -> [[f32; 4]; 6] {
    let rel = |p: DVec3| {
        let x = p - origin;
        [x.x as f32, x.y as f32, x.z as f32, 0.0]
    };
    let dir = |v: DVec3| [v.x as f32, v.y as f32, v.z as f32, 0.0];
    let m = material as f32;
    let mut entry = [[0.0f32; 4]; 6];
    match shape {
        SurfaceShape::Plane(p) => {
            entry[0] = [0.0, m, 0.0, 0.0];
            entry[1] = rel(p.point);
            entry[5] = dir(p.normal);
        }
        SurfaceShape::Quad(q) => {
            entry[0] = [1.0, m, if q.two_sided { 1.0 } else { 0.0 }, 0.0];
            for k in 0..4 {
                entry[1 + k] = rel(q.corners[k]);
            }
            entry[5] = dir(q.normal);
        }
        SurfaceShape::Cylinder(c) => {
            entry[0] = [2.0, m, if c.inside { 1.0 } else { 0.0 }, 0.0];
            entry[1] = rel(c.point);
            entry[2] = dir(c.axis);
            entry[3] = [c.radius as f32, c.length as f32, 0.0, 0.0];
        }
        // A prism's geometry lives in the wall's extras (wall_table, walls_moving.wgsl).
        SurfaceShape::Prism(_) => entry[0] = [3.0, m, 0.0, 0.0],
    }
    entry
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn large_dispatches_go_two_dimensional() {
        assert_eq!(dispatch(100, WORKGROUP), (2, 1));
        assert_eq!(dispatch(MAX_GROUPS_X * WORKGROUP, WORKGROUP), (MAX_GROUPS_X, 1));
        // 10 million particles: more than 65,535 workgroups of 64.
        let (x, y) = dispatch(10_000_000, WORKGROUP);
        assert_eq!((x, y), (MAX_GROUPS_X, 3));
        assert!(x as u64 * y as u64 * WORKGROUP as u64 >= 10_000_000);
        assert_eq!(dispatch(0, WORKGROUP), (1, 1));
    }

    #[test]
    fn the_error_for_a_scene_too_large_states_needed_and_available_memory() {
        let e = crate::GpuError::TooLarge { needed: 3 << 30, largest_array: 1 << 30, available: 128 << 20, adapter: "test adapter".into() };
        let text = e.to_string();
        assert!(text.contains("3072.0 MiB") && text.contains("1024.0 MiB") && text.contains("128.0 MiB") && text.contains("test adapter"), "{text}");
    }
}
