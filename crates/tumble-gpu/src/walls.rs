//! Moving world geometry on the host side: the walls' current pose, wall power and
//! work (summed in f64 in id order from the device's per-particle entries) and the
//! drum charge profiles (from read-back state).

use crate::GpuSimulation;
use tumble_cpu::DrumProfile;
use tumble_scene::Wall;

impl GpuSimulation {
    /// The walls in the pose of the last contact pass (moving walls at that pass's time).
    pub fn walls(&self) -> Vec<Wall> {
        self.plan.walls.iter().map(|w| if w.motion.is_some() { Wall { shape: w.shape_at(self.wall_time), ..w.clone() } } else { w.clone() }).collect()
    }

    /// Per wall group, the sum over particles (in id order, f64) of `entry(id, group)`.
    fn group_sums<T: bytemuck::Pod>(&self, buffer: &wgpu::Buffer, value: impl Fn(&T) -> f64) -> Vec<f64> {
        let groups = self.plan.wall_groups.len();
        let mut out = vec![0.0; groups];
        if !self.moving || groups == 0 {
            return out;
        }
        let all: Vec<T> = self.read(buffer, self.slots as usize * groups);
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
        self.group_sums(&self.buffers.wall_power, |p: &f32| *p as f64)
    }

    /// Work done on the particles by each wall group since t = 0 (Σ power Δt over committed passes).
    pub fn wall_work(&self) -> Vec<f64> {
        self.group_sums(&self.buffers.wall_work, |w: &[f32; 2]| w[0] as f64 - w[1] as f64)
    }

    /// The charge profile of each drum of the plan, from the read-back state.
    pub fn drum_profiles(&self) -> Vec<DrumProfile> {
        if self.plan.drums.is_empty() {
            return Vec::new();
        }
        tumble_cpu::drum_profiles(&self.plan, &self.state())
    }
}
