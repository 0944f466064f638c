//! Host-side data for the device: the particle arrays in f32 (positions relative
//! to the domain's centre), the pair and wall tables, the cell grid and
//! the step parameters.

use bytemuck::{Pod, Zeroable};
use glam::DVec3;
use tumble_contact::{FlowField, NormalLaw, SpringLaw, TangentialLaw, ViscousParameter};
use tumble_geom::SurfaceShape;
use tumble_plan::Plan;
use tumble_state::State;

use crate::prisms::PrismHulls;
use tumble_shaders as codes;
pub use tumble_shaders::{FLAG_DEAD, FLAG_FIXED, SCAN_BLOCK, SCAN_THREADS, SHAPE_SHIFT, WORKGROUP};

/// Most workgroups along one dispatch axis.
pub const MAX_GROUPS_X: u32 = 65_535;

/// The step parameters, field for field common.wgsl's `Params` (uniform layout: a vec3 is
/// 16-byte aligned, so each is followed by a named pad; a test compares the offsets with naga's).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub struct Params {
    /// Particle slots (removed particles keep theirs, flagged).
    pub particles: u32,
    /// Live cells (the removed-particle bucket is index `cells`).
    pub cells: u32,
    pub walls: u32,
    pub materials: u32,
    /// Contact-history slots per particle (0 without history).
    pub history_slots: u32,
    /// Wall groups (moving walls: power is booked per group).
    pub wall_groups: u32,
    /// The first word of the shape table in the tables buffer (polyhedra).
    pub shape_base: u32,
    /// Threads per dispatch row (x groups × WORKGROUP).
    pub row_threads: u32,
    /// Cells per axis.
    pub dims: [u32; 3],
    pub _pad_dims: u32,
    /// 1 where the axis is periodic.
    pub periodic: [u32; 3],
    pub _pad_periodic: u32,
    pub dt: f32,
    pub taylor_green_amplitude: f32,
    pub taylor_green_frequency: f32,
    pub _pad_scalars: f32,
    /// Inverse cell widths per axis.
    pub inv_cell: [f32; 3],
    pub _pad_inv_cell: f32,
    /// Domain extent per axis (positions span [−extent/2, extent/2]).
    pub extent: [f32; 3],
    pub _pad_extent: f32,
    pub gravity: [f32; 3],
    pub _pad_gravity: f32,
    /// Uniform flow velocity (zero for a Taylor–Green flow).
    pub flow: [f32; 3],
    pub _pad_flow: f32,
    /// The domain's centre in world coordinates (for the flow field).
    pub origin: [f32; 3],
    pub _pad_origin: f32,
    /// Outlets, and the first vec4 entry of their table in the tables buffer.
    pub outlets: u32,
    pub outlet_base: u32,
    pub _pad_outlets0: u32,
    pub _pad_outlets1: u32,
}

/// One level of the scan (scan.wgsl `ScanParams`).
#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable)]
pub struct ScanParams {
    /// Values at this level.
    pub n: u32,
    /// 1 when the sums hold block offsets.
    pub offsets: u32,
    /// Threads per dispatch row.
    pub row: u32,
    pub _pad: u32,
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
        let extent = plan.model.domain.extent();
        // A hair wider than the largest interaction diameter, so f32 rounding never hides a neighbour.
        let width = (plan.tuning.cell_size * (1.0 + 1e-4)).max(1e-12);
        let mut dims = [0, 1, 2].map(|k| ((extent[k] / width).floor()).clamp(1.0, (1u32 << 20) as f64));
        // Eight cells per particle at most: the binning passes sweep every cell each step, which
        // would cost a few particles in a large domain far more than their contacts do.
        let max_cells = (8.0 * particles as f64).max(512.0);
        let total: f64 = dims.iter().product();
        if total > max_cells {
            let shrink = (total / max_cells).cbrt();
            dims = dims.map(|d| (d / shrink).floor().max(1.0));
        }
        Grid::with_dims(plan, dims.map(|d| d as u32))
    }

    /// The grid for a run starting with `first_ids` particle ids: sized for its capacity (those
    /// and every particle the sources may insert), so growing the arrays never changes it.
    pub fn planned(plan: &Plan, first_ids: u64) -> Grid {
        Grid::new(plan, (first_ids + plan.inserted_at_most()).min(u32::MAX as u64) as usize)
    }

    /// The grid of `dims` cells over the plan's domain.
    pub fn with_dims(plan: &Plan, dims: [u32; 3]) -> Grid {
        let extent = plan.model.domain.extent();
        Grid { dims, inv_width: [0, 1, 2].map(|k| dims[k] as f64 / extent[k]) }
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

/// The tables (walls, shapes, outlets) and the step parameters for `slots` slots on `grid`.
pub fn tables_and_params(
    plan: &Plan,
    hulls: &crate::prisms::PrismHulls,
    grid: &Grid,
    slots: u32,
) -> Result<(Vec<[f32; 4]>, Params), crate::GpuError> {
    let (mut tables, shape_base) = tables_with_shapes(plan, hulls)?;
    let mut params = params(plan, grid, slots, shape_base);
    params.outlet_base = tables.len() as u32;
    tables.extend(outlet_table(plan));
    Ok((tables, params))
}

/// The step parameters; `shape_base`: the first word of the shape table in the tables buffer.
pub fn params(plan: &Plan, grid: &Grid, slots: u32, shape_base: usize) -> Params {
    let f3 = |v: DVec3| [v.x as f32, v.y as f32, v.z as f32];
    let (flow, taylor_green) = match plan.model.fluid.map(|f| f.flow) {
        Some(FlowField::Uniform(u)) => (f3(u), [0.0; 2]),
        Some(FlowField::TaylorGreen { amplitude, frequency }) => ([0.0; 3], [amplitude as f32, frequency as f32]),
        None => ([0.0; 3], [0.0; 2]),
    };
    Params {
        particles: slots,
        cells: grid.cells(),
        walls: plan.model.walls.len() as u32,
        materials: plan.model.materials.len() as u32,
        history_slots: history_slots(plan) as u32,
        wall_groups: plan.model.wall_groups.len() as u32,
        shape_base: shape_base as u32,
        row_threads: MAX_GROUPS_X * WORKGROUP,
        dims: grid.dims,
        periodic: plan.model.domain.periodic.map(u32::from),
        dt: plan.model.dt as f32,
        taylor_green_amplitude: taylor_green[0],
        taylor_green_frequency: taylor_green[1],
        inv_cell: grid.inv_width.map(|w| w as f32),
        extent: f3(plan.model.domain.extent()),
        gravity: f3(plan.model.gravity),
        flow,
        origin: f3(centre(plan)),
        outlets: plan.model.outlets.len() as u32,
        ..Params::default()
    }
}

// A deleted particle's flags hold its outlet's index + 1 in the 8 bits from OUTLET_SHIFT, below the shape index.
const _: () = assert!(tumble_plan::MAX_OUTLETS < 256 && codes::OUTLET_SHIFT + 8 <= codes::SHAPE_SHIFT);

/// The outlets as the device reads them (relative to the domain's centre), OUTLET_ENTRIES each.
pub fn outlet_table(plan: &Plan) -> Vec<[f32; 4]> {
    let origin = centre(plan);
    let f4 = |v: DVec3| [v.x as f32, v.y as f32, v.z as f32, 0.0];
    let mut t = Vec::new();
    for o in &plan.model.outlets {
        match o.region {
            tumble_plan::OutletRegion::Box { min, max } => t.extend([[code(codes::OUTLET_BOX), 0.0, 0.0, 0.0], f4(min - origin), f4(max - origin)]),
            tumble_plan::OutletRegion::Beyond { point, normal } => {
                t.extend([[code(codes::OUTLET_PLANE), 0.0, 0.0, 0.0], f4(point - origin), f4(normal)])
            }
        }
    }
    t
}

/// Contact-history slots per particle on the device (0 without history).
pub fn history_slots(plan: &Plan) -> usize {
    if plan.model.history { plan.tuning.history_slots } else { 0 }
}

/// The domain's centre: device positions are relative to it (f32 precision is best near 0).
pub fn centre(plan: &Plan) -> DVec3 {
    0.5 * (plan.model.domain.min + plan.model.domain.max)
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
    /// Periodic images (xyz, w unused) by ORIGINAL id, scenes with a periodic axis only (empty otherwise).
    pub image: Vec<[i32; 4]>,
}

impl ParticleArrays {
    /// Empty slots for particles inserted later, flagged dead, up to `capacity` slots: they
    /// hold, in increasing order, the ids below `capacity` that no slot holds yet, so every id
    /// below the slot count has exactly one slot (ids at or above `next_id` wait for insertion).
    pub fn pad_to(&mut self, capacity: usize, plan: &Plan) {
        let mut held = vec![false; capacity];
        for p in &self.props {
            held[p[2] as usize] = true;
        }
        let mut free = (0..capacity as u32).filter(|&id| !held[id as usize]);
        while self.pos.len() < capacity {
            let id = free.next().expect("ids below the capacity for every empty slot");
            self.pos.push([0.0; 4]);
            self.vel.push([0.0; 4]);
            self.omega.push([0.0; 4]);
            self.acc.push([0.0; 4]);
            self.alpha.push([0.0; 4]);
            self.props.push([0, 0, id, FLAG_DEAD]);
            self.energy.push([0.0; 4]);
            if plan.model.polyhedra {
                self.orient.push([0.0, 0.0, 0.0, 1.0]);
            }
        }
        if plan.model.domain.periodic.iter().any(|&p| p) {
            self.image.resize(capacity, [0; 4]);
        }
    }

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
            if plan.model.polyhedra {
                // The shape index (SPHERE = 0xffff for spheres) in the high 16 bits.
                flags |= (s.shape[i] as u32) << SHAPE_SHIFT;
                let q = s.orient[i];
                a.orient.push([q.x as f32, q.y as f32, q.z as f32, q.w as f32]);
            }
            a.props.push([(s.reach[i] as f32).to_bits(), s.material[i] as u32, s.id[i], flags]);
            a.energy.push([0.0; 4]);
        }
        if !s.image.is_empty() {
            a.image = vec![[0; 4]; s.id.iter().map(|&id| id as usize + 1).max().unwrap_or(0)];
            for i in 0..s.len() {
                let n = s.image[i];
                a.image[s.id[i] as usize] = [n[0], n[1], n[2], 0];
            }
        }
        a
    }
}

/// The polyhedron shapes of a plan as the device takes them: its particle shapes, then its
/// lifter bars' hulls (prisms.rs).
pub fn plan_shapes(plan: &Plan, hulls: &PrismHulls) -> Result<Vec<[f32; 4]>, crate::GpuError> {
    let bodies: Vec<tumble_geom::Polyhedron> = plan.model.shapes.iter().map(|s| s.body.clone()).chain(hulls.shapes().cloned()).collect();
    if plan.model.polyhedra && plan.model.polyhedron_contact == tumble_plan::PolyhedronContact::Volume {
        crate::shapes::check_volume_limits(&bodies).map_err(|e| crate::GpuError::Feature(e.0))?;
    }
    crate::shapes::shape_table(&bodies).map_err(|e| crate::GpuError::Feature(e.0))
}

/// The pair table (3 vec4 per material pair) followed by the wall section (6 vec4 per wall, then
/// the walls' extras: motion, prism faces; see [`wall_table`]), then the shape table (shapes.rs)
/// when the plan has polyhedra; see forces.wgsl. Returns the tables and the first entry of the
/// shape table, which follows everything the walls append so the two regions never overlap.
pub fn tables_with_shapes(plan: &Plan, hulls: &PrismHulls) -> Result<(Vec<[f32; 4]>, usize), crate::GpuError> {
    let mut t = tables(plan, hulls);
    if !plan.model.polyhedra {
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

/// A code of tumble-shaders' layout as the f32 tables hold it: an exact small whole number
/// (the shaders read it back with `u32()`).
fn code(c: u32) -> f32 {
    c as f32
}

/// The pair table: PAIR_ENTRY_WORDS vec4 per material pair (forces.wgsl).
pub fn pair_table(plan: &Plan) -> Vec<[f32; 4]> {
    let mut t = Vec::new();
    for p in &plan.model.pairs {
        let e = p.normal.restitution();
        let factor = (std::f64::consts::PI.powi(2) + e.ln().powi(2)).sqrt();
        t.push(match p.normal {
            NormalLaw::Linear { stiffness, damping_ratio, .. } => [code(codes::NORMAL_LINEAR), stiffness as f32, damping_ratio as f32, factor as f32],
            NormalLaw::Hertz { e_star, beta, .. } => [code(codes::NORMAL_HERTZ), e_star as f32, beta as f32, factor as f32],
        });
        t.push(match p.tangential {
            TangentialLaw::None => [code(codes::TANGENTIAL_NONE), 0.0, 0.0, 0.0],
            TangentialLaw::ViscousCoulomb { friction, viscous: ViscousParameter::Coefficient(c) } => {
                [code(codes::TANGENTIAL_VISCOUS_COULOMB), friction as f32, c as f32, 0.0]
            }
            TangentialLaw::ViscousCoulomb { friction, viscous: ViscousParameter::Stiffness(k) } => {
                [code(codes::TANGENTIAL_VISCOUS_COULOMB), friction as f32, k as f32, 1.0]
            }
            TangentialLaw::StickLimited { friction } => [code(codes::TANGENTIAL_STICK_LIMITED), friction as f32, 0.0, 0.0],
            TangentialLaw::DynamicOnly { friction } => [code(codes::TANGENTIAL_DYNAMIC_ONLY), friction as f32, 0.0, 0.0],
            TangentialLaw::History { friction, spring: SpringLaw::Linear { stiffness, damping_ratio, .. } } => {
                [code(codes::TANGENTIAL_HISTORY_LINEAR), friction as f32, stiffness as f32, damping_ratio as f32]
            }
            TangentialLaw::History { friction, spring: SpringLaw::Mindlin { g_star, beta } } => {
                [code(codes::TANGENTIAL_HISTORY_MINDLIN), friction as f32, g_star as f32, beta as f32]
            }
        });
        let history_damping = match p.tangential {
            TangentialLaw::History { spring: SpringLaw::Linear { damping, .. }, .. } => damping,
            _ => 0.0,
        };
        t.push([p.cohesion as f32, if p.no_attraction { 1.0 } else { 0.0 }, p.rolling as f32, history_damping as f32]);
    }
    t
}

/// True when some wall's material moves, by a motion or a conveyor's surface velocity (the MOVING
/// switch: wall velocities, poses uploaded every step, wall power and work).
pub fn moving_walls(plan: &Plan) -> bool {
    plan.model.walls.iter().any(|w| w.motion.is_some() || w.surface_velocity != DVec3::ZERO)
}

/// The wall section of the table (it follows the pair table, at `PAIR_ENTRY_WORDS · materials²`)
/// with every wall in its pose at time `t`: WALL_ENTRY_WORDS vec4 per wall (geometry.wgsl), then each wall's extras
/// (walls_moving.wgsl: its motion when some wall moves, a prism's faces and, with polyhedral
/// particles, its hull's pose), whose first index is the entry's w0.w.
pub fn wall_table(plan: &Plan, t: f64, hulls: &PrismHulls) -> Vec<[f32; 4]> {
    let entry_words = codes::WALL_ENTRY_WORDS as usize;
    let walls_base = codes::PAIR_ENTRY_WORDS as usize * plan.model.pairs.len();
    let moving = moving_walls(plan);
    let origin = centre(plan);
    let mut main = Vec::with_capacity(entry_words * plan.model.walls.len());
    let mut extras = Vec::new();
    for (k, w) in plan.model.walls.iter().enumerate() {
        let extra = (walls_base + entry_words * plan.model.walls.len() + extras.len()) as f32;
        let first_extra = extras.len();
        // A moving wall at t: its pose, and the velocities of that instant (timed and oscillating motions).
        let posed;
        let w = if w.motion.is_some() {
            posed = w.posed(t);
            &posed
        } else {
            w
        };
        if moving {
            // ω and the velocity at the domain's centre: v(x) = ω × (x − centre) + v(centre).
            let spin = w.angular_velocity();
            extras.push([spin.x as f32, spin.y as f32, spin.z as f32, w.group as f32]);
            // A conveyor has no motion: its surface velocity, flagged so the part along the normal is dropped.
            let v = w.velocity_at(origin) + w.surface_velocity;
            extras.push([v.x as f32, v.y as f32, v.z as f32, (w.surface_velocity != DVec3::ZERO) as u8 as f32]);
            debug_assert_eq!(extras.len() - first_extra, codes::WALL_MOTION_WORDS as usize);
        }
        let mut entry = wall_entry(&w.shape, w.material as usize, origin);
        if let SurfaceShape::Prism(p) = &w.shape {
            let rel = |p: DVec3| {
                let x = p - origin;
                [x.x as f32, x.y as f32, x.z as f32, 0.0]
            };
            let dir = |v: DVec3| [v.x as f32, v.y as f32, v.z as f32, 0.0];
            let prism_start = extras.len();
            let centre = rel(p.centre);
            extras.push([centre[0], centre[1], centre[2], p.bound as f32]);
            let axis_point = rel(p.axis_point);
            extras.push([axis_point[0], axis_point[1], axis_point[2], p.inner as f32]);
            extras.push(dir(p.axis));
            for f in &p.faces {
                extras.extend(f.corners.map(rel));
                extras.push(dir(f.normal));
            }
            debug_assert_eq!(extras.len() - prism_start, codes::PRISM_HULL as usize);
            if let Some((hull, pose)) = hulls.pose(k, p) {
                // The hull's centre (w: its shape index) and orientation, for polyhedral particles.
                let x = rel(pose.position);
                extras.push([x[0], x[1], x[2], hull as f32]);
                let q = pose.rotation;
                extras.push([q.x as f32, q.y as f32, q.z as f32, q.w as f32]);
            }
        }
        // w0.w: the first index of this wall's extras; w5.w: its group (walls_moving.wgsl).
        entry[0][3] = extra;
        entry[5][3] = w.group as f32;
        main.extend_from_slice(&entry);
    }
    main.extend(extras);
    main
}

/// The kind code of a wall surface (geometry.wgsl's `wall_kind`); a new surface does not compile until it has one.
pub fn wall_kind(shape: &SurfaceShape) -> u32 {
    match shape {
        SurfaceShape::Plane(_) => codes::WALL_PLANE,
        SurfaceShape::Quad(_) => codes::WALL_QUAD,
        SurfaceShape::Cylinder(_) => codes::WALL_CYLINDER,
        SurfaceShape::Prism(_) => codes::WALL_PRISM,
        SurfaceShape::Mesh(_) => unreachable!("unsupported_walls refuses mesh walls before any table is built"),
    }
}

/// One wall's table entry (WALL_ENTRY_WORDS vec4, geometry.wgsl), coordinates relative to
/// `origin`; w0.w (the extras' index) is left 0 for [`wall_table`] to fill.
pub fn wall_entry(shape: &SurfaceShape, material: usize, origin: DVec3) -> [[f32; 4]; codes::WALL_ENTRY_WORDS as usize] {
    let rel = |p: DVec3| {
        let x = p - origin;
        [x.x as f32, x.y as f32, x.z as f32, 0.0]
    };
    let dir = |v: DVec3| [v.x as f32, v.y as f32, v.z as f32, 0.0];
    let m = material as f32;
    let flag = |b: bool| if b { 1.0 } else { 0.0 };
    let mut entry = [[0.0f32; 4]; codes::WALL_ENTRY_WORDS as usize];
    entry[0] = [code(wall_kind(shape)), m, 0.0, 0.0];
    match shape {
        SurfaceShape::Plane(p) => {
            entry[1] = rel(p.point);
            entry[5] = dir(p.normal);
        }
        SurfaceShape::Quad(q) => {
            entry[0][2] = flag(q.two_sided);
            for k in 0..4 {
                entry[1 + k] = rel(q.corners[k]);
            }
            entry[5] = dir(q.normal);
        }
        SurfaceShape::Cylinder(c) => {
            entry[0][2] = flag(c.inside);
            entry[1] = rel(c.point);
            entry[2] = dir(c.axis);
            entry[3] = [c.radius as f32, c.length as f32, 0.0, 0.0];
        }
        // A prism's geometry lives in the wall's extras (wall_table, walls_moving.wgsl).
        SurfaceShape::Prism(_) | SurfaceShape::Mesh(_) => {}
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

    /// The members (name, offset) and size of a WGSL struct, as naga lays it out.
    fn wgsl_struct(module: &str, name: &str) -> (Vec<(String, usize)>, usize) {
        let source = crate::shaders::sources().into_iter().find(|s| s.name == module).unwrap().source;
        let parsed = naga::front::wgsl::parse_str(&source).unwrap();
        let ty = parsed.types.iter().find(|(_, t)| t.name.as_deref() == Some(name)).unwrap().1;
        let naga::TypeInner::Struct { members, span } = &ty.inner else { panic!("{name} is not a struct") };
        (members.iter().map(|m| (m.name.clone().unwrap(), m.offset as usize)).collect(), *span as usize)
    }

    #[test]
    fn params_is_the_wgsl_struct_field_for_field() {
        use std::mem::offset_of;
        let host = [
            ("particles", offset_of!(Params, particles)),
            ("cells", offset_of!(Params, cells)),
            ("walls", offset_of!(Params, walls)),
            ("materials", offset_of!(Params, materials)),
            ("history_slots", offset_of!(Params, history_slots)),
            ("wall_groups", offset_of!(Params, wall_groups)),
            ("shape_base", offset_of!(Params, shape_base)),
            ("row_threads", offset_of!(Params, row_threads)),
            ("dims", offset_of!(Params, dims)),
            ("_pad_dims", offset_of!(Params, _pad_dims)),
            ("periodic", offset_of!(Params, periodic)),
            ("_pad_periodic", offset_of!(Params, _pad_periodic)),
            ("dt", offset_of!(Params, dt)),
            ("taylor_green_amplitude", offset_of!(Params, taylor_green_amplitude)),
            ("taylor_green_frequency", offset_of!(Params, taylor_green_frequency)),
            ("_pad_scalars", offset_of!(Params, _pad_scalars)),
            ("inv_cell", offset_of!(Params, inv_cell)),
            ("_pad_inv_cell", offset_of!(Params, _pad_inv_cell)),
            ("extent", offset_of!(Params, extent)),
            ("_pad_extent", offset_of!(Params, _pad_extent)),
            ("gravity", offset_of!(Params, gravity)),
            ("_pad_gravity", offset_of!(Params, _pad_gravity)),
            ("flow", offset_of!(Params, flow)),
            ("_pad_flow", offset_of!(Params, _pad_flow)),
            ("origin", offset_of!(Params, origin)),
            ("_pad_origin", offset_of!(Params, _pad_origin)),
            ("outlets", offset_of!(Params, outlets)),
            ("outlet_base", offset_of!(Params, outlet_base)),
            ("_pad_outlets0", offset_of!(Params, _pad_outlets0)),
            ("_pad_outlets1", offset_of!(Params, _pad_outlets1)),
        ]
        .map(|(n, o)| (n.to_string(), o));
        for module in ["broad", "reorder", "forces", "integrate"] {
            assert_eq!(wgsl_struct(module, "Params"), (host.to_vec(), std::mem::size_of::<Params>()), "{module}");
        }
        let scan = [
            ("n", offset_of!(ScanParams, n)),
            ("offsets", offset_of!(ScanParams, offsets)),
            ("row", offset_of!(ScanParams, row)),
            ("_pad", offset_of!(ScanParams, _pad)),
        ]
        .map(|(n, o)| (n.to_string(), o));
        assert_eq!(wgsl_struct("scan", "ScanParams"), (scan.to_vec(), std::mem::size_of::<ScanParams>()));
    }

    #[test]
    fn every_surface_has_its_kind_code_in_the_entry() {
        use tumble_geom::{Cylinder, Plane};
        let plane = SurfaceShape::Plane(Plane { point: DVec3::ZERO, normal: DVec3::Z });
        assert_eq!(wall_entry(&plane, 3, DVec3::ZERO)[0], [codes::WALL_PLANE as f32, 3.0, 0.0, 0.0]);
        let drum = SurfaceShape::Cylinder(Cylinder { point: DVec3::ZERO, axis: DVec3::Z, radius: 1.0, length: 2.0, inside: true });
        assert_eq!(wall_entry(&drum, 1, DVec3::ZERO)[0], [codes::WALL_CYLINDER as f32, 1.0, 1.0, 0.0]);
    }
}
