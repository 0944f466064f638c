//! Moving world geometry on the host side: the walls' current pose, and wall power, work and
//! drum charge profiles as the output row has them (reduced on the device, reduce.rs).

use crate::GpuSimulation;
use glam::DVec3;
use tumble_plan::Wall;
use tumble_state::DrumProfile;

impl GpuSimulation {
    /// The walls in the pose of the last contact pass (moving walls at that pass's time).
    pub fn walls(&self) -> Vec<Wall> {
        self.plan.model.walls.iter().map(|w| w.posed(self.wall_time)).collect()
    }

    /// Bytes of the per-(id, group) wall entries of `element_bytes` each (zero without moving walls).
    pub(crate) fn wall_entry_bytes(&self, element_bytes: u64) -> u64 {
        if self.moving { element_bytes * self.slots as u64 * self.plan.model.wall_groups.len() as u64 } else { 0 }
    }

    /// Bytes of the per-(id, group) wall loads (two vec4 each; zero without walls).
    pub(crate) fn wall_load_bytes(&self) -> u64 {
        32 * self.slots as u64 * self.plan.model.wall_groups.len() as u64
    }

    /// Per wall group, the sums over particles (in id order, f64) of the wall loads read back as
    /// `bytes`: power, force, and torque about the device's origin (the host's oracle sums).
    pub(crate) fn group_loads(&self, bytes: &[u8]) -> (Vec<f64>, Vec<DVec3>, Vec<DVec3>) {
        let groups = self.plan.model.wall_groups.len();
        let (mut power, mut force, mut torque) = (vec![0.0; groups], vec![DVec3::ZERO; groups], vec![DVec3::ZERO; groups]);
        if bytes.is_empty() || groups == 0 {
            return (power, force, torque);
        }
        let all: Vec<[[f32; 4]; 2]> = bytemuck::pod_collect_to_vec(bytes);
        let v3 = |v: [f32; 4]| DVec3::new(v[0] as f64, v[1] as f64, v[2] as f64);
        for per_id in all.chunks(groups) {
            for (g, [load, couple]) in per_id.iter().enumerate() {
                power[g] += load[3] as f64;
                force[g] += v3(*load);
                torque[g] += v3(*couple);
            }
        }
        (power, force, torque)
    }

    /// Torques about the device's origin (the domain's centre o) moved to each group's reference
    /// point r: Σ (p − r) × F = Σ (p − o) × F + (o − r) × Σ F.
    pub(crate) fn torques_about_references(&self, about_origin: &[DVec3], force: &[DVec3]) -> Vec<DVec3> {
        let origin = crate::upload::centre(&self.plan);
        (0..about_origin.len()).map(|g| about_origin[g] + (origin - self.plan.model.wall_group_reference(g)).cross(force[g])).collect()
    }

    /// Per wall group, the sum over particles (in id order, f64) of `entry(id, group)` read back as `bytes` (the host's oracle sums).
    pub(crate) fn group_sums_of<T: bytemuck::Pod>(&self, bytes: &[u8], value: impl Fn(&T) -> f64) -> Vec<f64> {
        let groups = self.plan.model.wall_groups.len();
        let mut out = vec![0.0; groups];
        if bytes.is_empty() || groups == 0 {
            return out;
        }
        let all: Vec<T> = bytemuck::pod_collect_to_vec(bytes);
        for per_id in all.chunks(groups) {
            for (o, e) in out.iter_mut().zip(per_id) {
                *o += value(e);
            }
        }
        out
    }

    /// Power delivered to the particles by each wall group at the last force pass,
    /// Σ F_on_particle · v_wall at the contact point (+ Ω_wall · the rolling and, for polyhedra,
    /// twisting couples); zero for static walls.
    pub fn wall_power(&self) -> Vec<f64> {
        self.frame(false).wall_power
    }

    /// Work done on the particles by each wall group since t = 0 (Σ power Δt over committed passes).
    pub fn wall_work(&self) -> Vec<f64> {
        self.frame(false).wall_work
    }

    /// The charge profile of each drum of the plan.
    pub fn drum_profiles(&self) -> Vec<DrumProfile> {
        self.frame(false).drums
    }
}

/// One (id, group) entry of the wall work buffer: a Kahan pair (sum, compensation).
pub(crate) fn wall_work_value(w: &[f32; 2]) -> f64 {
    w[0] as f64 - w[1] as f64
}

/// Why the GPU backend cannot run the plan's walls, if it cannot.
pub(crate) fn unsupported_walls(plan: &tumble_plan::Plan, hulls: &crate::prisms::PrismHulls) -> Option<String> {
    let mesh = |w: &Wall| matches!(w.shape, tumble_geom::SurfaceShape::Mesh(_));
    let groups = &plan.model.wall_groups;
    if let Some(w) = plan.model.walls.iter().find(|w| mesh(w) || groups[w.group as usize].servo.is_some()) {
        let what = if mesh(w) { "mesh walls" } else { "servo walls" };
        return Some(format!("{what} (\"{}\") run on the CPU backend only for now", groups[w.group as usize].name));
    }
    // The contact pass books each group's load once, walking the walls in group order from group 0.
    if plan.model.walls.first().is_some_and(|w| w.group != 0) || plan.model.walls.windows(2).any(|w| w[1].group < w[0].group) {
        return Some("its wall surfaces are not in wall-group order".into());
    }
    // Table indices are stored as f32 (exact below 2^24).
    let entries = tumble_shaders::PAIR_ENTRY_WORDS as usize * plan.model.pairs.len() + crate::upload::wall_table(plan, 0.0, hulls).len();
    if entries >= 1 << 24 {
        return Some(format!("its pair and wall tables have {entries} entries (at most 2^24)"));
    }
    None
}
