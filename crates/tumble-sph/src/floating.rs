//! Floating rigid bodies: a box or a cylinder whose wall particles the fluid pushes, moved as one
//! rigid body by the force and torque it gathers (Newton–Euler), stepped in the fluid's own
//! symplectic scheme.

use tumble_geom::{Cylinder, DQuat, DVec3};

use crate::kernel::Dimension;
use crate::particles::{Aabb, cylinder_fill, lattice_points};

/// What a floating body is made of: a solid box (axis-aligned at the start) or a solid cylinder.
#[derive(Clone, Debug, PartialEq)]
pub enum BodyShape {
    Box(Aabb),
    Cylinder(Cylinder),
}

impl BodyShape {
    /// Volume in 3D; area of the x–z section in 2D (per metre of span).
    pub fn volume(&self, dimension: Dimension) -> f64 {
        let plane = dimension == Dimension::Two;
        match self {
            BodyShape::Box(b) => {
                let e = b.max - b.min;
                if plane { e.x * e.z } else { e.x * e.y * e.z }
            }
            BodyShape::Cylinder(c) => {
                let disc = std::f64::consts::PI * c.radius * c.radius;
                if plane { disc } else { disc * c.length }
            }
        }
    }

    /// The centre of the shape (its centre of mass: the body is uniform).
    pub fn centre(&self, dimension: Dimension) -> DVec3 {
        let mut x = match self {
            BodyShape::Box(b) => 0.5 * (b.min + b.max),
            BodyShape::Cylinder(c) => c.point + 0.5 * c.length * c.axis,
        };
        if dimension == Dimension::Two {
            x.y = 0.0;
        }
        x
    }

    /// The inertia tensor of a uniform body of `mass` about its centre, as three columns. In 2D
    /// only the moment about y means anything: a box's M (a² + c²)/12, a disc's M R²/2.
    pub fn inertia(&self, mass: f64, dimension: Dimension) -> [DVec3; 3] {
        match self {
            BodyShape::Box(b) => {
                let e = b.max - b.min;
                let (a2, b2, c2) = (e.x * e.x, e.y * e.y, e.z * e.z);
                let k = mass / 12.0;
                [DVec3::new(k * (b2 + c2), 0.0, 0.0), DVec3::new(0.0, k * (a2 + c2), 0.0), DVec3::new(0.0, 0.0, k * (a2 + b2))]
            }
            BodyShape::Cylinder(c) => {
                let r2 = c.radius * c.radius;
                let (along, across) = match dimension {
                    Dimension::Two => (0.5 * mass * r2, 0.5 * mass * r2),
                    Dimension::Three => (0.5 * mass * r2, mass * (3.0 * r2 + c.length * c.length) / 12.0),
                };
                // I = across · 1 + (along − across) a ⊗ a.
                let a = c.axis;
                std::array::from_fn(|j| {
                    let mut col = (along - across) * a[j] * a;
                    col[j] += across;
                    col
                })
            }
        }
    }

    /// The body's wall particles: its lattice (a box's, anchored at its corner) or its rings (a
    /// cylinder's) Δp/2 inside its surface, kept where they lie less than `layers` spacings deep,
    /// so that a fluid particle touching the body has a full kernel of them and the body's core
    /// costs nothing.
    pub fn particles(&self, layers: usize, dp: f64, dimension: Dimension) -> Vec<DVec3> {
        let depth = layers as f64 * dp;
        let plane = dimension == Dimension::Two;
        match self {
            BodyShape::Box(b) => lattice_points(*b, b.min, dp, dimension)
                .into_iter()
                .filter(|x| (0..3).filter(|&k| !(plane && k == 1)).any(|k| x[k] - b.min[k] < depth || b.max[k] - x[k] < depth))
                .collect(),
            BodyShape::Cylinder(c) => cylinder_fill(c, dp, dimension)
                .into_iter()
                .map(|(x, _)| x)
                .filter(|&x| {
                    let d = x - c.point;
                    let s = d.dot(c.axis);
                    let radial = if plane { DVec3::new(d.x, 0.0, d.z) } else { d - s * c.axis };
                    c.radius - radial.length() < depth || (!plane && (s < depth || c.length - s < depth))
                })
                .collect(),
        }
    }

    /// Whether `x` lies inside the body grown by `margin` (fluid there is cleared at the start).
    pub fn covers(&self, x: DVec3, margin: f64, dimension: Dimension) -> bool {
        let plane = dimension == Dimension::Two;
        match self {
            BodyShape::Box(b) => (0..3).all(|k| (plane && k == 1) || (x[k] > b.min[k] - margin && x[k] < b.max[k] + margin)),
            BodyShape::Cylinder(c) => {
                let d = x - c.point;
                let s = d.dot(c.axis);
                let radial = if plane { DVec3::new(d.x, 0.0, d.z) } else { d - s * c.axis };
                radial.length() < c.radius + margin && (plane || (s > -margin && s < c.length + margin))
            }
        }
    }
}

/// A floating body as the fluid's settings hold it: its mass, its inertia and how it starts.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FloatingBody {
    /// kg (in 2D per metre of span).
    pub mass: f64,
    /// The inertia tensor about the centre of mass in the starting orientation, as columns.
    pub inertia: [DVec3; 3],
    pub start: BodyState,
}

impl FloatingBody {
    /// A uniform body of `density` with the shape's mass and inertia, at rest.
    pub fn uniform(shape: &BodyShape, density: f64, dimension: Dimension) -> Self {
        let mass = density * shape.volume(dimension);
        FloatingBody { mass, inertia: shape.inertia(mass, dimension), start: BodyState::at_rest(shape.centre(dimension)) }
    }
}

/// Where a floating body is and how it moves, with the fluid's loads at the last evaluation.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct BodyState {
    /// The centre of mass (not wrapped into a periodic domain).
    pub centre: DVec3,
    /// The rotation from the starting orientation.
    pub orientation: DQuat,
    pub velocity: DVec3,
    pub angular_velocity: DVec3,
    /// The fluid's force on the body and its torque about the centre, N and N m (2D: per metre).
    pub fluid_force: DVec3,
    pub fluid_torque: DVec3,
    /// The accelerations the last loads gave, which the walls' condition reads as the wall's own.
    pub acceleration: DVec3,
    pub angular_acceleration: DVec3,
}

impl BodyState {
    pub fn at_rest(centre: DVec3) -> Self {
        BodyState {
            centre,
            orientation: DQuat::IDENTITY,
            velocity: DVec3::ZERO,
            angular_velocity: DVec3::ZERO,
            fluid_force: DVec3::ZERO,
            fluid_torque: DVec3::ZERO,
            acceleration: DVec3::ZERO,
            angular_acceleration: DVec3::ZERO,
        }
    }

    /// Velocity of the body's material at offset `r` from its centre.
    pub fn velocity_at(&self, r: DVec3) -> DVec3 {
        self.velocity + self.angular_velocity.cross(r)
    }

    /// Acceleration of the body's material at offset `r` from its centre.
    pub fn acceleration_at(&self, r: DVec3) -> DVec3 {
        let w = self.angular_velocity;
        self.acceleration + self.angular_acceleration.cross(r) + w.cross(w.cross(r))
    }

    /// ½ M V² + ½ ω·I ω, J (2D: per metre of span).
    pub fn kinetic_energy(&self, body: &FloatingBody) -> f64 {
        let w = self.orientation.inverse() * self.angular_velocity;
        let iw = body.inertia[0] * w.x + body.inertia[1] * w.y + body.inertia[2] * w.z;
        0.5 * body.mass * self.velocity.length_squared() + 0.5 * w.dot(iw)
    }

    /// −M g·X, J: the potential energy of the centre of mass in `gravity`.
    pub fn potential_energy(&self, body: &FloatingBody, gravity: DVec3) -> f64 {
        -body.mass * gravity.dot(self.centre)
    }

    /// Takes the fluid's force and torque and the accelerations they give with gravity
    /// (Newton–Euler about the centre of mass, the inertia turned with the body). In 2D the
    /// body moves in x–z and turns about y only.
    pub fn load(&mut self, body: &FloatingBody, force: DVec3, torque: DVec3, gravity: DVec3, dimension: Dimension) {
        self.fluid_force = force;
        self.fluid_torque = torque;
        let turn = |v: DVec3| self.orientation * v;
        let back = |v: DVec3| self.orientation.inverse() * v;
        // I_world ω = R I R^T ω, and α from I_world α = τ − ω × I_world ω, solved in the body frame.
        let inertia = |v: DVec3| {
            let b = back(v);
            turn(body.inertia[0] * b.x + body.inertia[1] * b.y + body.inertia[2] * b.z)
        };
        let w = self.angular_velocity;
        let net = torque - w.cross(inertia(w));
        let columns = glam::DMat3::from_cols(body.inertia[0], body.inertia[1], body.inertia[2]);
        self.acceleration = force / body.mass + gravity;
        self.angular_acceleration = turn(columns.inverse() * back(net));
        if dimension == Dimension::Two {
            self.acceleration.y = 0.0;
            self.angular_acceleration = DVec3::new(0.0, torque.y / body.inertia[1].y, 0.0);
        }
    }
}

/// How a floating body carries its particles over a drift: from centre `from` to centre `to`,
/// turned by `turn` about the centre, ending with `state`'s velocities.
#[derive(Clone, Copy, Debug)]
pub struct BodyMove {
    pub from: DVec3,
    pub to: DVec3,
    pub turn: DQuat,
    pub state: BodyState,
}

impl BodyMove {
    /// The first half of a step: the centre and orientation drift by the starting velocities,
    /// the velocities kick by the starting accelerations.
    pub fn first_half(s: &BodyState, half: f64) -> Self {
        let turn = DQuat::from_scaled_axis(half * s.angular_velocity);
        let mut state = *s;
        state.centre = s.centre + half * s.velocity;
        state.orientation = (turn * s.orientation).normalize();
        state.velocity = s.velocity + half * s.acceleration;
        state.angular_velocity = s.angular_velocity + half * s.angular_acceleration;
        BodyMove { from: s.centre, to: state.centre, turn, state }
    }

    /// The second half: the velocities at the end of the step from those at its start and the
    /// accelerations at its middle (`middle`), then the drift by them.
    pub fn second_half(start: &BodyState, middle: &BodyState, dt: f64) -> Self {
        let half = 0.5 * dt;
        let mut state = *middle;
        state.velocity = start.velocity + dt * middle.acceleration;
        state.angular_velocity = start.angular_velocity + dt * middle.angular_acceleration;
        let turn = DQuat::from_scaled_axis(half * state.angular_velocity);
        state.centre = middle.centre + half * state.velocity;
        state.orientation = (turn * middle.orientation).normalize();
        BodyMove { from: middle.centre, to: state.centre, turn, state }
    }

    /// The displacement of the body's material at offset `r` from the starting centre, and its
    /// velocity at the end.
    pub fn carry(&self, r: DVec3) -> (DVec3, DVec3) {
        let r_end = self.turn * r;
        (self.to - self.from + (r_end - r), self.state.velocity_at(r_end))
    }
}
