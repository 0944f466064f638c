//! Behaviours both backends must show, each written once as a function of the backend and
//! checked against a closed form or an exact invariant with [`Tolerance`](crate::Tolerance)'s
//! per-precision tolerances; [`testgen!`](crate::testgen) makes one trial of each per backend.
//!
//! - `verification`: a projectile (exact for Verlet), the linear spring-dashpot collision
//!   (x(t) at second order, the rebound at e |u0|), the Hertz impact (case 7), a sphere
//!   resting on a plane at m g / k;
//! - `history`: tangential springs and rolling resistance (case 8, oblique impacts, inclines);
//! - `invariants`: exactly opposite pair forces;
//! - `walls`: a drum's drive power, flow planes and moving-wall series, a sphere on a belt, a
//!   sphere riding a floor that starts oscillating at a given time;
//! - `polyhedra`: a tumbling box (E and L), a cube resting face-down, an elastic
//!   octahedron–cube impact, a cube struck by a plate and dragged by a belt;
//! - `determinism`: two runs bit-identical (and on the CPU one and two threads);
//! - `restore`: a run continued from a snapshot bit-identical to the one that wrote it; a run
//!   stopped and resumed from its checkpoints writing the files of one that went straight through;
//! - `periodic`: energy across wraps of a periodic axis, a flow plane on one, image counts
//!   through a snapshot;
//! - `sources`: insertion on the rate's schedule and clear of every particle, outlets deleting
//!   at the step a projectile's closed form gives; a run with both continued from a snapshot
//!   bit-identically.
//!
//! Each stays at CI size: a few thousand steps, on scenes whose GPU shader variants the
//! backends binary compiles anyway (docs/verification.md lists what each measures).

mod determinism;
mod history;
mod invariants;
mod periodic;
mod polyhedra;
mod restore;
mod sources;
mod verification;
mod walls;

pub use sources::streams;

use crate::harness::{cpu_trial, gpu_trial};
use libtest_mimic::Trial;
use tumble_scene::schema::BackendName;

/// Lists behaviours once: their names come from their paths.
macro_rules! behaviours {
    ($($module:ident :: $name:ident),* $(,)?) => {
        /// Every behaviour of the suite: (name, test on a backend).
        pub const BEHAVIOURS: &[(&str, fn(BackendName))] = &[$((concat!(stringify!($module), "::", stringify!($name)), $module::$name)),*];
    };
}

behaviours![
    verification::a_projectile_follows_its_parabola_exactly,
    verification::a_damped_linear_contact_follows_the_oscillator_at_second_order,
    verification::linear_collisions_rebound_at_e_times_the_impact_speed,
    verification::a_hertz_impact_meets_hertz_theory,
    verification::a_sphere_set_on_a_plane_rests_at_m_g_over_k,
    history::slide_to_roll_at_five_sevenths,
    history::oblique_impacts_follow_coulomb_theory_while_sliding,
    history::damped_hertz_mindlin_impacts_slide_at_the_coulomb_limit,
    history::a_spring_holds_a_sphere_on_an_incline,
    history::rolls_at_five_sevenths_g_sin_theta,
    history::rolling_resistance_holds_below_tan_theta_equal_mu_r_and_rolls_above,
    invariants::pair_forces_are_exactly_equal_and_opposite,
    walls::a_drum_drive_power_is_torque_times_omega,
    walls::flow_planes_count_the_mass_through_and_moving_walls_write_a_series,
    walls::a_belt_drags_a_rolling_sphere_until_its_contact_point_moves_with_it,
    walls::a_bed_at_rest_in_a_box_puts_its_weight_on_the_walls,
    walls::a_sphere_on_an_oscillating_floor_rides_it_from_its_start_time,
    polyhedra::a_box_spun_about_its_intermediate_axis_tumbles_keeping_energy_and_momentum,
    polyhedra::a_cube_set_face_down_on_a_plane_rests_at_m_g_over_k,
    polyhedra::an_octahedron_striking_a_cube_face_rebounds_elastically,
    polyhedra::a_plate_striking_a_cube_face_on_throws_it_at_twice_its_speed,
    polyhedra::a_belt_drags_a_cube_to_its_speed,
    determinism::two_runs_of_a_scene_are_bit_identical,
    restore::a_run_continued_from_a_snapshot_is_bit_identical,
    restore::a_resumed_run_writes_the_files_of_an_uninterrupted_one,
    periodic::a_sphere_sliding_round_a_periodic_incline_keeps_its_energy,
    periodic::a_flow_plane_on_a_periodic_axis_measures_the_mass_flux_of_a_stream,
    periodic::a_periodic_run_continued_from_a_snapshot_keeps_its_image_counts,
    sources::sources_insert_on_schedule_and_outlets_delete_at_the_projectile_step,
    sources::a_run_with_sources_continued_from_a_snapshot_is_bit_identical,
];

/// One trial per behaviour on `backend`, named `backend::module::behaviour`.
pub fn trials(backend: BackendName) -> Vec<Trial> {
    BEHAVIOURS
        .iter()
        .map(|&(name, test)| match backend {
            BackendName::Cpu => cpu_trial(format!("cpu::{name}"), move || test(backend)),
            BackendName::Gpu => gpu_trial(format!("gpu::{name}"), move || test(backend)),
        })
        .collect()
}
