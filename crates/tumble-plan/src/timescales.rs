//! Time scales of a scene as the plan reports them: contact durations, stability limits and the
//! step the plan picks (docs/physics.md, "Time step").

/// Time scales that fix and bound the step.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Timescales {
    /// Shortest contact duration (linear: t_col; Hertz: at the characteristic speed).
    pub collision_time: Option<f64>,
    /// Hertz: shortest Rayleigh time.
    pub rayleigh_time: Option<f64>,
    /// Largest stable Δt (2/ω for linear contacts, Δt_R for Hertz, 2τ_p for explicit drag).
    pub stability_limit: Option<f64>,
    /// Shortest drag relaxation time τ_p.
    pub drag_time: Option<f64>,
    /// Shortest relaxation time m*_t / c_t of the viscous tangential force.
    pub tangential_time: Option<f64>,
    /// The Δt the plan would choose by itself.
    pub default_dt: f64,
    /// The impact speed the contact times are taken at.
    pub impact: ImpactSpeed,
}

/// Steps per shortest collision the default Δt aims at (linear t_col, Hertz t_H at the impact speed).
pub const STEPS_PER_COLLISION: f64 = 50.0;

/// Fewer steps per collision than this and the plan warns that results are inaccurate.
pub const ACCURATE_STEPS_PER_COLLISION: f64 = 10.0;

/// The default Δt is at most this share of the viscous tangential relaxation time; above it the plan warns.
pub const TANGENTIAL_STEP_SHARE: f64 = 1.0 / 6.0;

/// An estimate of the fastest impact (docs/physics.md, "Time step"): two of the fastest particles
/// (initial speed after the deepest fall under gravity the domain allows) meeting head on, or one
/// hit by the fastest wall point.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct ImpactSpeed {
    /// max(2 v_p, v_p + v_wall) with v_p = √(v_0² + 2 g h), at least 0.1 m/s.
    pub speed: f64,
    /// Fastest initial speed of a movable particle.
    pub initial: f64,
    /// The drop h: a movable particle's height above the domain's lowest side along g (the
    /// whole extent along g when a wall moves, since walls lift particles).
    pub drop_height: f64,
    /// Fastest point of a moving wall.
    pub wall: f64,
}
