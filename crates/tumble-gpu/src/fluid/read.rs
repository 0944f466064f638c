//! What the host reads of the GPU fluid after an advance: its particles, their pressures and the
//! time-step limits, in one read-back.

use glam::DVec3;
use tumble_shaders::SPH_FLUID;
use tumble_sph::{FluidParticles, ParticleKind, TimeStepLimits};

use super::GpuFluid;
use crate::readback::read_back;

/// What [`GpuFluid::read`] brings back in one read-back.
#[derive(Clone, Debug)]
pub struct FluidReadBack {
    /// The particles in the device's (sorted) order, in f64; wall particles carry their last
    /// extrapolated density.
    pub particles: FluidParticles,
    /// Each particle's pressure at the last evaluation (walls: extrapolated), in that order.
    pub pressures: Vec<f64>,
    /// The time-step limits at the fluid's largest speed and acceleration of the last evaluation.
    pub limits: TimeStepLimits,
    /// The fastest fluid particle's id and speed (the lowest id among equals).
    pub fastest: Option<(u32, f64)>,
}

impl GpuFluid {
    /// Everything the host reads of the device after an advance, in one read-back (one
    /// submission, one mapping): the particles, their pressures and the time-step limits.
    pub fn read(&self) -> FluidReadBack {
        let b = &self.buffers;
        let bytes = 16 * self.n as u64;
        let parts = read_back(&self.gpu, |_| {}, &[(&b.pos, bytes), (&b.vel, bytes), (&b.tags, bytes), (&b.state, bytes), (&b.rate, bytes)]);
        let [pos, vel, state, rate]: [Vec<[f32; 4]>; 4] = [0, 1, 3, 4].map(|k| bytemuck::pod_collect_to_vec(&parts[k]));
        let tags: Vec<[u32; 4]> = bytemuck::pod_collect_to_vec(&parts[2]);
        let d3 = |a: [f32; 4]| DVec3::new(a[0] as f64, a[1] as f64, a[2] as f64);
        let mut p = FluidParticles::default();
        for i in 0..self.n as usize {
            p.id.push(tags[i][1]);
            p.kind.push(if tags[i][0] == SPH_FLUID { ParticleKind::Fluid } else { ParticleKind::Wall });
            // Exactly the f32 coordinate plus the centre, so a restore gives back the same bits
            // whenever the centre is exact (it is for domains given in decimals of a few digits).
            p.position.push(d3(pos[i]) + self.centre);
            p.velocity.push(d3(vel[i]));
            p.density.push(vel[i][3] as f64);
            p.mass.push(pos[i][3] as f64);
            p.wall.push(tags[i][2] as u16);
        }
        // The fluid's largest speed and acceleration give the limits; the fastest particle is
        // the lowest id among equals.
        let (mut speed, mut acceleration, mut fastest) = (0.0f64, 0.0f64, None::<(u32, f64)>);
        for i in (0..self.n as usize).filter(|&i| tags[i][0] == SPH_FLUID) {
            let v = d3(vel[i]).length();
            speed = speed.max(v);
            acceleration = acceleration.max(d3(rate[i]).length());
            if fastest.is_none_or(|(id, s)| v > s || (v == s && tags[i][1] < id)) {
                fastest = Some((tags[i][1], v));
            }
        }
        let limits = TimeStepLimits::new(&self.settings, speed, acceleration.max(self.settings.external_acceleration().length()));
        FluidReadBack { particles: p, pressures: state.iter().map(|s| s[0] as f64).collect(), limits, fastest }
    }

    /// The device's particles in its (sorted) order, in f64; wall particles carry their last
    /// extrapolated density.
    pub fn particles(&self) -> FluidParticles {
        self.read().particles
    }

    /// The pressure of each particle at the last evaluation (walls: extrapolated), in the
    /// device's order.
    pub fn pressures(&self) -> Vec<f64> {
        self.read().pressures
    }
}
