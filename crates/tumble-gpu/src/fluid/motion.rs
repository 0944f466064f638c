//! The fluid's moving walls and floating bodies on the GPU: the motion table the host writes
//! for each half step, and the step with floating bodies, which the host integrates in f64 between
//! the device's evaluations from the forces and moments the device sums.

use glam::DVec3;
use tumble_sph::BodyMove;

use super::{GpuFluid, body_centre_row, v4};
use crate::readback::read_back;
use crate::upload::{WORKGROUP, dispatch};

impl GpuFluid {
    /// One step with floating bodies. As tumble-sph does, the host integrates the bodies in f64
    /// between the evaluations, from the forces and moments the device sums: two read-backs a
    /// step, where a fluid without bodies submits many steps at once.
    pub(super) fn step_with_bodies(&mut self, dt: f64) {
        let half = 0.5 * dt;
        let t0 = self.time;
        let particles = dispatch(self.n, WORKGROUP);
        // The evaluation at the step's start, with the bodies' accelerations of their last loads.
        self.write_motions(&self.motion_table(t0, half, None));
        let mut encoder = self.gpu.device.create_command_encoder(&wgpu::CommandEncoderDescriptor { label: Some("fluid step") });
        self.record_sort(&mut encoder);
        self.record_evaluation(&mut encoder);
        self.gpu.queue.submit([encoder.finish()]);
        self.load_bodies();
        let start = self.bodies.clone();
        let moves: Vec<BodyMove> = self.bodies.iter().map(|b| BodyMove::first_half(b, half)).collect();
        self.write_motions(&self.motion_table(t0, half, Some(&moves)));
        self.submit_pass("fluid_first_half", particles);
        self.bodies = moves.iter().map(|m| m.state).collect();
        // The evaluation at the middle, then the second half.
        self.write_motions(&self.motion_table(t0 + half, half, None));
        let mut encoder = self.gpu.device.create_command_encoder(&wgpu::CommandEncoderDescriptor { label: Some("fluid step") });
        self.record_evaluation(&mut encoder);
        self.gpu.queue.submit([encoder.finish()]);
        self.load_bodies();
        let moves: Vec<BodyMove> = start.iter().zip(&self.bodies).map(|(s, m)| BodyMove::second_half(s, m, dt)).collect();
        self.write_motions(&self.motion_table(t0 + half, half, Some(&moves)));
        self.submit_pass("fluid_second_half", particles);
        self.bodies = moves.iter().map(|m| m.state).collect();
        self.time += dt;
    }

    /// The walls' states and the rates, and with floating bodies the fluid's loads on them.
    pub(super) fn record_evaluation(&self, encoder: &mut wgpu::CommandEncoder) {
        let particles = dispatch(self.n, WORKGROUP);
        self.pass(encoder, "fluid_wall_state", &self.step_group, particles);
        self.pass(encoder, "fluid_rates", &self.step_group, particles);
        if !self.bodies.is_empty() {
            self.pass(encoder, "fluid_body_sums", &self.step_group, (self.bodies.len() as u32, 1));
        }
    }

    fn submit_pass(&self, entry: &'static str, groups: (u32, u32)) {
        let mut encoder = self.gpu.device.create_command_encoder(&wgpu::CommandEncoderDescriptor { label: Some(entry) });
        self.pass(&mut encoder, entry, &self.step_group, groups);
        self.gpu.queue.submit([encoder.finish()]);
    }

    /// Writes the motion table the next submission reads.
    fn write_motions(&self, table: &[[f32; 4]]) {
        if !table.is_empty() {
            self.gpu.queue.write_buffer(&self.buffers.motions, 0, bytemuck::cast_slice(table));
        }
    }

    /// Reads the device's sums of the fluid's loads on the bodies and gives each body its
    /// accelerations.
    fn load_bodies(&mut self) {
        let parts = read_back(&self.gpu, |_| {}, &[(&self.buffers.body_sums, 32 * self.bodies.len() as u64)]);
        let sums: Vec<[f32; 4]> = bytemuck::pod_collect_to_vec(&parts[0]);
        let d3 = |a: [f32; 4]| DVec3::new(a[0] as f64, a[1] as f64, a[2] as f64);
        let s = &self.settings;
        for (k, (state, body)) in self.bodies.iter_mut().zip(&s.floating).enumerate() {
            state.load(body, d3(sums[2 * k]), d3(sums[2 * k + 1]), s.gravity, s.dimension);
        }
    }

    /// The motion table for the half step from `t0` to `t0 + half`, in device coordinates
    /// (positions relative to the domain's centre): per moving wall, then per floating body, the
    /// move, the velocity at the end and the acceleration at the start, each as three rows of an
    /// affine map fitted exactly (the motions are rigid) from the answers at the centre and a
    /// metre along each axis; then each body's centre. A body's move is `moves`' (before its loads
    /// are known, its move and velocity rows are zero: the evaluation reads only its
    /// acceleration and centre).
    pub(super) fn motion_table(&self, t0: f64, half: f64, moves: Option<&[BodyMove]>) -> Vec<[f32; 4]> {
        let c = self.centre;
        let affine = |f: &dyn Fn(DVec3) -> DVec3| {
            let origin = f(c);
            let columns = [DVec3::X, DVec3::Y, DVec3::Z].map(|e| f(c + e) - origin);
            [0, 1, 2].map(|r| [columns[0][r] as f32, columns[1][r] as f32, columns[2][r] as f32, origin[r] as f32])
        };
        let mut table = Vec::with_capacity(body_centre_row(&self.settings) as usize + self.bodies.len());
        for wall in &self.settings.moving_walls {
            let t1 = t0 + half;
            table.extend(affine(&|x| wall.advance(x, t0, t1) - c));
            table.extend(affine(&|x| wall.velocity_at(x, t1)));
            table.extend(affine(&|x| wall.acceleration_at(x, t0)));
        }
        for (k, body) in self.bodies.iter().enumerate() {
            match moves.map(|m| m[k]) {
                Some(m) => {
                    table.extend(affine(&|x| x + m.carry(x - m.from).0 - c));
                    table.extend(affine(&|x| m.state.velocity_at(x - m.to)));
                }
                None => table.extend([[0.0; 4]; 6]),
            }
            table.extend(affine(&|x| body.acceleration_at(x - body.centre)));
        }
        table.extend(self.bodies.iter().map(|b| v4(b.centre - c, 0.0)));
        table
    }
}
