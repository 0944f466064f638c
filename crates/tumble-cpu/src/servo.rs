//! Servo walls: a wall group translated along its servo's direction at the speed its controller
//! sets from the group's load at the last committed force pass (tumble_scene's `Servo`).
//!
//! Per step: the offset advances by the speed of the last pass (once, at the step's start),
//! the walls are placed there moving at that speed, and the committed pass sets the next speed.
//! The offset, the offset at the last list build and the speed are the whole state, saved in
//! the snapshot so a restart continues bit-identically.

use crate::CpuSimulation;
use tumble_plan::{Motion, Wall};
use tumble_state::ServoState;

impl CpuSimulation {
    /// True when some wall group has a servo.
    pub(crate) fn has_servos(&self) -> bool {
        self.plan.model.wall_groups.iter().any(|g| g.servo.is_some())
    }

    /// Moves every servo wall on by its speed over one step (at the start of the step).
    #[inline(never)]
    pub(crate) fn advance_servos(&mut self) {
        let dt = self.plan.model.dt;
        for s in &mut self.servos {
            s.offset += s.speed * dt;
        }
    }

    /// Sets each servo's speed from its group's load at the pass just committed.
    #[inline(never)]
    pub(crate) fn drive_servos(&mut self) {
        for ((group, s), force) in self.plan.model.wall_groups.iter().zip(&mut self.servos).zip(&self.group_force) {
            if let Some(servo) = &group.servo {
                s.speed = servo.speed(*force);
            }
        }
    }

    /// `now` (a servo wall of the plan's `wall`) at `offset` along its direction, moving at the
    /// servo's current speed.
    pub(crate) fn place_servo_wall(&self, now: &mut Wall, wall: &Wall, built: bool) {
        let Some(servo) = &self.plan.model.wall_groups[wall.group as usize].servo else { return };
        let state: &ServoState = &self.servos[wall.group as usize];
        let offset = if built { state.built_offset } else { state.offset };
        now.shape = wall.shape.moved(glam::DVec3::ZERO, glam::DQuat::IDENTITY, servo.direction * offset);
        now.motion = Some(Motion::Translate { velocity: servo.direction * state.speed });
    }

    /// Per wall group, the servo's offset from its t = 0 pose (zero without a servo).
    pub fn servo_offsets(&self) -> Vec<f64> {
        self.servos.iter().map(|s| s.offset).collect()
    }
}
