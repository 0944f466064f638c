//! How closely each observable must meet its reference, per precision, in one table.
//!
//! The f32 (GPU) values cover the backend's rounding over the tests' short runs; the f64
//! (CPU) values are what the same runs measure with a margin. Each stays far below the
//! error a wrong sign or a missing factor would give (noted per row).

use tumble_scene::schema::BackendName;

/// The floating-point precision a backend computes in.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Precision {
    F32,
    F64,
}

impl Precision {
    /// The precision of a backend: the CPU's f64, the GPU's f32.
    pub fn of(backend: BackendName) -> Precision {
        match backend {
            BackendName::Cpu => Precision::F64,
            BackendName::Gpu => Precision::F32,
        }
    }
}

/// A checked quantity, each with its own tolerance.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Observable {
    /// A speed ratio against its closed form (5/7 after slide-to-roll, v_t'/v_t of an impact), absolute.
    SpeedRatio,
    /// The tangential speed ratio v_t'/v_t of an oblique impact against Coulomb theory, relative.
    TangentialRatio,
    /// A spin ratio Rω'/v_t of an oblique impact against Coulomb theory, relative.
    SpinRatio,
    /// Normal restitution v_n'/v_n against the scene's e, absolute.
    Restitution,
    /// The sliding deceleration against μ g, relative.
    SlidingDeceleration,
    /// The time rolling starts against theory, relative.
    RollTime,
    /// The creep speed of a sphere held by a tangential spring, m/s.
    CreepSpeed,
    /// A free rolling acceleration against 5/7 g sin θ, relative.
    RollingAcceleration,
    /// A rolling acceleration with rolling resistance against 5/7 g (sin θ − μ_r cos θ), relative.
    ResistedRollingAcceleration,
    /// Slip speed of a rolling sphere, m/s.
    SlipSpeed,
    /// Mass through a flow plane against the particles' mass, relative (f32 masses on the GPU).
    Mass,
    /// A wall's drive power against torque × ω, relative.
    WallPower,
}

/// The tolerance table.
pub struct Tolerance;

impl Tolerance {
    /// The tolerance of `observable` in `precision`.
    pub fn of(observable: Observable, precision: Precision) -> f64 {
        use Observable::*;
        use Precision::*;
        match (observable, precision) {
            // 5/7 vs the 1 of no rolling: 0.29. Measured 2e-6 (f64), 1.1e-5 (f32, lavapipe).
            (SpeedRatio, F64) => 1e-4,
            (SpeedRatio, F32) => 2e-3,
            (TangentialRatio, _) => 5e-3,
            // Coulomb's spin: the contact's finite duration leaves ~1 %; a missing factor 5/2 is 150 %.
            (SpinRatio, _) => 1.5e-2,
            (Restitution, F64) => 2e-3,
            (Restitution, F32) => 3e-3,
            // Measured 2e-8 (f64), 2.7e-5 (f32).
            (SlidingDeceleration, F64) => 1e-6,
            (SlidingDeceleration, F32) => 5e-3,
            // Measured 7e-5 (f64), 1.3e-2 (f32: the f32 slip crosses zero later).
            (RollTime, F64) => 1e-3,
            (RollTime, F32) => 2e-2,
            // The normal settling transient of the short runs; viscous-Coulomb creeps at 1.8e-4 m/s.
            (CreepSpeed, _) => 5e-6,
            // A missing 5/7 is 40 %, a wrong sign of μ_r cos θ 70 % at 10°. Measured 2.7e-7 and
            // 7e-6 (f64), 6.2e-5 and 5.8e-5 (f32).
            (RollingAcceleration, F64) => 1e-5,
            (RollingAcceleration, F32) => 2e-3,
            (ResistedRollingAcceleration, F64) => 1e-4,
            (ResistedRollingAcceleration, F32) => 1e-2,
            (SlipSpeed, _) => 1e-3,
            // Measured 4e-16 (f64), 5.6e-8 (f32).
            (Mass, F64) => 1e-12,
            (Mass, F32) => 1e-6,
            // Measured 5.5e-16 (f64), 1.9e-7 (f32).
            (WallPower, F64) => 1e-9,
            (WallPower, F32) => 2e-3,
        }
    }

    /// The tolerance of `observable` on `backend`'s precision.
    pub fn on(observable: Observable, backend: BackendName) -> f64 {
        Self::of(observable, Precision::of(backend))
    }
}
