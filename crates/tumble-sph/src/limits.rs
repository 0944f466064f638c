//! What bounds the fluid's time step, and why a step could not be trusted.

use crate::settings::FluidSettings;

/// The three conditions on the fluid's time step (Monaghan 1992; Morris et al. 1997).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TimeStepLimits {
    /// Δt ≤ 0.25 h / (c₀ + v): a sound wave crosses a quarter of h per step.
    pub cfl: f64,
    /// Δt ≤ 0.125 h² ρ₀ / μ: momentum diffuses across an eighth of h² per step.
    pub viscous: f64,
    /// Δt ≤ 0.25 √(h / |a|).
    pub force: f64,
}

impl TimeStepLimits {
    /// The limits for a flow of speed `speed` whose particles accelerate at most at `acceleration`.
    pub fn new(settings: &FluidSettings, speed: f64, acceleration: f64) -> Self {
        let h = settings.h;
        TimeStepLimits {
            cfl: 0.25 * h / (settings.sound_speed + speed),
            viscous: if settings.mu > 0.0 { 0.125 * h * h * settings.rho0 / settings.mu } else { f64::INFINITY },
            force: if acceleration > 0.0 { 0.25 * (h / acceleration).sqrt() } else { f64::INFINITY },
        }
    }

    /// The limits a plan uses before the flow exists: the expected speed c₀/10 and the external
    /// acceleration.
    pub fn planned(settings: &FluidSettings) -> Self {
        Self::new(settings, 0.1 * settings.sound_speed, settings.external_acceleration().length())
    }

    pub fn dt(&self) -> f64 {
        self.cfl.min(self.viscous).min(self.force)
    }

    /// Which condition binds, in words.
    pub fn binding(&self) -> &'static str {
        let dt = self.dt();
        if dt == self.cfl {
            "the sound speed (CFL)"
        } else if dt == self.viscous {
            "the viscosity"
        } else {
            "the largest acceleration"
        }
    }
}

/// Why a fluid step could not be trusted.
#[derive(Clone, Debug, PartialEq)]
pub enum FluidFault {
    /// A fluid particle's position, velocity or density is not finite.
    NotFinite { id: u32, time: f64 },
    /// A particle moved further in one step than the grid's skin allows: the flow outran the
    /// sound speed the time step was chosen for.
    TooFast { id: u32, time: f64, speed: f64, sound_speed: f64, dt_that_works: f64 },
}

impl std::fmt::Display for FluidFault {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            FluidFault::NotFinite { id, time } => {
                write!(f, "fluid particle {id} has a non-finite position, velocity or density at t = {time:.6e} s")
            }
            FluidFault::TooFast { id, time, speed, sound_speed, dt_that_works } => write!(
                f,
                "fluid particle {id} moves at {speed:.4e} m/s at t = {time:.6e} s, {:.2} times the sound speed {sound_speed:.4e} m/s: \
                 the fluid is unstable; raise the sound speed or use a time step of at most {dt_that_works:.4e} s",
                speed / sound_speed
            ),
        }
    }
}

impl std::error::Error for FluidFault {}
