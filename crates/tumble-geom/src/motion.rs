//! Prescribed rigid motions (of walls): rotation, translation and oscillation, and when they
//! run. The DEM's walls and the fluid's wall particles move by the same definitions.

use glam::{DQuat, DVec3};

/// Prescribed rigid motion of a wall.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Motion {
    /// Rotation about the axis through `point` along unit `axis` at `omega` rad/s (right-handed).
    Rotate {
        point: DVec3,
        axis: DVec3,
        omega: f64,
    },
    Translate {
        velocity: DVec3,
    },
    /// x(t) = amplitude · sin(omega t) along unit `direction`.
    Oscillate {
        direction: DVec3,
        amplitude: f64,
        omega: f64,
    },
}

impl Motion {
    /// Velocity of the wall material at `x` (an oscillation at its phase 0: use [`Wall::posed`]).
    #[inline]
    pub fn velocity_at(&self, x: DVec3) -> DVec3 {
        match *self {
            Motion::Rotate { point, axis, omega } => (axis * omega).cross(x - point),
            Motion::Translate { velocity } => velocity,
            Motion::Oscillate { direction, amplitude, omega } => direction * (amplitude * omega),
        }
    }

    /// (pivot, rotation about the pivot, shift) taking the t = 0 pose to motion time `tau`.
    pub fn pose(&self, tau: f64) -> (DVec3, DQuat, DVec3) {
        match *self {
            Motion::Rotate { point, axis, omega } => (point, DQuat::from_axis_angle(axis, omega * tau), DVec3::ZERO),
            Motion::Translate { velocity } => (DVec3::ZERO, DQuat::IDENTITY, velocity * tau),
            Motion::Oscillate { direction, amplitude, omega } => (DVec3::ZERO, DQuat::IDENTITY, direction * (amplitude * (omega * tau).sin())),
        }
    }

    /// The motion at motion time `tau` running at `rate` of its full speed, as a constant-velocity
    /// motion with that instant's velocities.
    pub fn instant(&self, tau: f64, rate: f64) -> Motion {
        match *self {
            Motion::Rotate { point, axis, omega } => Motion::Rotate { point, axis, omega: omega * rate },
            Motion::Translate { velocity } => Motion::Translate { velocity: velocity * rate },
            Motion::Oscillate { direction, amplitude, omega } => {
                Motion::Translate { velocity: direction * (amplitude * omega * (omega * tau).cos() * rate) }
            }
        }
    }

    /// Where the material point at `x` at motion time `tau0` is at motion time `tau1`.
    pub fn advance(&self, x: DVec3, tau0: f64, tau1: f64) -> DVec3 {
        match *self {
            Motion::Rotate { point, axis, omega } => point + DQuat::from_axis_angle(axis, omega * (tau1 - tau0)) * (x - point),
            Motion::Translate { velocity } => x + velocity * (tau1 - tau0),
            Motion::Oscillate { direction, amplitude, omega } => x + direction * (amplitude * ((omega * tau1).sin() - (omega * tau0).sin())),
        }
    }

    /// Acceleration of the material point at `x` at motion time `tau`, the motion running at
    /// `rate` of its full speed and that rate changing by `rate_change` per second.
    pub fn acceleration_at(&self, x: DVec3, tau: f64, rate: f64, rate_change: f64) -> DVec3 {
        match *self {
            Motion::Rotate { point, axis, omega } => {
                let r = x - point;
                let w = axis * (omega * rate);
                (axis * (omega * rate_change)).cross(r) + w.cross(w.cross(r))
            }
            Motion::Translate { velocity } => velocity * rate_change,
            Motion::Oscillate { direction, amplitude, omega } => {
                let phase = omega * tau;
                direction * (amplitude * omega * (phase.cos() * rate_change - omega * phase.sin() * rate * rate))
            }
        }
    }

    /// Largest speed of the motion itself (a rotation's is ω times the radius: see the walls' speeds).
    pub fn peak_speed(&self) -> f64 {
        match *self {
            Motion::Rotate { omega, .. } => omega.abs(),
            Motion::Translate { velocity } => velocity.length(),
            Motion::Oscillate { amplitude, omega, .. } => amplitude * omega.abs(),
        }
    }
}

/// When a wall's motion runs: it starts at `start`, reaches full speed linearly over `ramp`
/// and stops at `stop`, where the wall stays.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Timing {
    pub start: f64,
    pub ramp: f64,
    pub stop: f64,
}

impl Timing {
    /// A motion that runs from t = 0 at full speed, for ever.
    pub const ALWAYS: Timing = Timing { start: 0.0, ramp: 0.0, stop: f64::INFINITY };

    /// The share of its full speed the motion runs at at time `t`.
    #[inline]
    pub fn rate(&self, t: f64) -> f64 {
        if t < self.start || t >= self.stop {
            0.0
        } else if t < self.start + self.ramp {
            (t - self.start) / self.ramp
        } else {
            1.0
        }
    }

    /// How fast the rate changes at time `t`, per second (1/ramp while ramping up, else 0).
    #[inline]
    pub fn rate_change(&self, t: f64) -> f64 {
        if t >= self.start && t < self.start + self.ramp && t < self.stop { 1.0 / self.ramp } else { 0.0 }
    }

    /// Motion time at `t`: the integral of [`Timing::rate`] from 0 (t itself for [`Timing::ALWAYS`]).
    #[inline]
    pub fn elapsed(&self, t: f64) -> f64 {
        let t = t.min(self.stop);
        if t <= self.start {
            0.0
        } else if t < self.start + self.ramp {
            (t - self.start) * (t - self.start) / (2.0 * self.ramp)
        } else {
            t - self.start - 0.5 * self.ramp
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn an_untimed_motion_runs_on_time_itself() {
        for t in [0.0, 1e-300, 3.7e-5, 0.1, 12.5, 1e9] {
            assert_eq!(Timing::ALWAYS.elapsed(t).to_bits(), t.to_bits());
            assert_eq!(Timing::ALWAYS.rate(t), 1.0);
        }
    }

    #[test]
    fn motion_time_is_the_integral_of_the_rate() {
        let timing = Timing { start: 0.2, ramp: 0.3, stop: 0.9 };
        let (n, end) = (200_000, 1.2);
        let h = end / n as f64;
        let mut integral = 0.0;
        for k in 0..n {
            // Midpoint rule, exact for the piecewise-linear rate away from its kinks.
            integral += timing.rate((k as f64 + 0.5) * h) * h;
            let t = (k + 1) as f64 * h;
            assert!((integral - timing.elapsed(t)).abs() < 1e-8, "t = {t}: ∫ rate = {integral}, elapsed {}", timing.elapsed(t));
        }
        assert_eq!(timing.elapsed(0.1), 0.0);
        assert!((timing.elapsed(2.0) - (0.9 - 0.2 - 0.15)).abs() < 1e-15, "stopped where it stood at 0.9 s");
    }

    /// A point carried by `advance` moves at the velocity the motion reports, and that velocity
    /// changes at the acceleration it reports, through a ramp and after it, for each motion.
    #[test]
    fn advanced_points_move_and_accelerate_as_reported() {
        let timing = Timing { start: 0.1, ramp: 0.2, stop: 0.8 };
        let motions = [
            Motion::Rotate { point: DVec3::new(0.1, 0.0, 0.2), axis: DVec3::new(0.0, 1.0, 0.0), omega: 3.0 },
            Motion::Translate { velocity: DVec3::new(0.0, 0.0, 0.68) },
            Motion::Oscillate { direction: DVec3::X, amplitude: 0.01, omega: 20.0 },
        ];
        let x0 = DVec3::new(0.3, 0.0, -0.1);
        for m in motions {
            let at = |t: f64| m.advance(x0, 0.0, timing.elapsed(t));
            let velocity = |t: f64| m.instant(timing.elapsed(t), timing.rate(t)).velocity_at(at(t));
            for t in [0.15, 0.22, 0.5, 0.7] {
                let h = 1e-5;
                let v = (at(t + h) - at(t - h)) / (2.0 * h);
                assert!((v - velocity(t)).length() < 1e-6, "{m:?} at {t}: moves at {v}, reports {}", velocity(t));
                let a = (velocity(t + h) - velocity(t - h)) / (2.0 * h);
                let reported = m.acceleration_at(at(t), timing.elapsed(t), timing.rate(t), timing.rate_change(t));
                assert!((a - reported).length() < 1e-4 * (1.0 + a.length()), "{m:?} at {t}: accelerates at {a}, reports {reported}");
            }
        }
    }
}
