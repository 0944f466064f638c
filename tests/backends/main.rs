//! Tests that need a backend, in one binary on the GPU-aware harness (`harness = false`):
//! the behavioural suite on the CPU and on the GPU (`testgen!`), and the GPU's own tests and
//! comparisons with the CPU. Without an adapter every GPU test is reported as ignored
//! (`TUMBLE_REQUIRE_GPU=1` makes that a failure); the end of the run reports the shader
//! variants compiled. GPU tests share one device and take turns on it.

/// The SPH fluid on the GPU against the CPU: one step, a dam break, a column at rest, a turning
/// drum; determinism and resumed scene runs; a GPU command's standard error.
mod fluid;
/// Moving walls on the GPU against the CPU: a mill, a belt, lifters; determinism.
mod moving_world;
/// The f32 polyhedra narrow phase against tumble-geom's f64 routines.
mod polyhedra_contact;
/// Polyhedra against moving walls and lifters on the GPU against the CPU.
mod polyhedra_moving;
/// Polyhedral particles settling in the GPU step against the CPU engine.
mod polyhedra_step;
/// The GPU's small output rows: device-reduced observables and gathered tracks.
mod reduced_rows;
/// Pictures of snapshots (`tumble render`): coverage, colour, depth, determinism.
mod render;
/// GPU runs continued from snapshots of the device's memory.
mod restore;
/// The backend seam on the GPU: one read-back per output row, tracked orientations.
mod seams;
mod support;
/// The GPU against the CPU on the verification and example scenes; springs.
mod volume_contact;
mod vs_cpu;

tumble_testkit::testgen!(cpu);
tumble_testkit::testgen!(gpu);

fn main() {
    let gpu_only = tumble_testkit::gpu_tests![
        vs_cpu::verification_scenes_end_where_the_cpu_ends,
        vs_cpu::every_integrator_matches_the_cpu_on_stokes_drag,
        vs_cpu::falling_bed_with_walls_agrees,
        vs_cpu::periodic_taylor_green_suspension_agrees,
        vs_cpu::cohesive_drum_inside_a_cylinder_agrees,
        vs_cpu::pipe_cascade_with_a_fixed_particle_and_a_periodic_axis_agrees,
        vs_cpu::hertz_contacts_on_two_sided_quads_agree,
        vs_cpu::forward_euler_with_dynamic_only_friction_agrees,
        vs_cpu::particles_leaving_the_domain_are_removed_as_on_the_cpu,
        vs_cpu::the_broad_phase_tables_are_a_sorted_counting_sort_with_a_three_level_scan,
        vs_cpu::falling_bed_with_history_and_rolling_resistance_agrees,
        vs_cpu::oblique_mindlin_collision_agrees,
        vs_cpu::history_runs_give_bit_identical_states_and_springs,
        vs_cpu::history_pair_forces_are_exactly_equal_and_opposite_and_the_spring_ends_with_the_contact,
        vs_cpu::springs_that_end_with_their_contact_are_booked_as_dissipated_as_on_the_cpu,
        vs_cpu::history_slot_overflow_is_reported,
        vs_cpu::a_sphere_with_more_neighbours_than_one_round_holds_feels_every_one,
        moving_world::a_small_mill_with_lifters_agrees_with_the_cpu,
        moving_world::spheres_on_a_belt_are_dragged_as_on_the_cpu,
        moving_world::moving_wall_runs_are_bit_identical,
        moving_world::lifters_are_one_contact_per_bar_as_on_the_cpu,
        polyhedra_contact::polyhedron_pairs_match_tumble_geom,
        polyhedra_contact::spheres_against_polyhedra_match_tumble_geom,
        polyhedra_contact::polyhedra_against_walls_match_tumble_geom,
        polyhedra_contact::polyhedra_against_lifter_prisms_as_table_shapes,
        polyhedra_contact::resting_and_crossed_configurations_are_exact_to_f32,
        volume_contact::volume_contacts_match_tumble_geom,
        polyhedra_moving::a_drum_turning_a_cube_draws_torque_times_omega,
        polyhedra_moving::a_small_drum_of_cubes_with_lifters_agrees_with_the_cpu,
        polyhedra_moving::the_drum_of_cubes_scene_runs_on_the_gpu,
        polyhedra_moving::turning_lifters_sweep_into_cubes_as_on_the_cpu,
        polyhedra_step::polyhedra_runs_give_bit_identical_states,
        polyhedra_step::a_mixture_of_spheres_and_cubes_settles_as_on_the_cpu,
        restore::a_snapshot_that_does_not_fit_is_refused_and_changes_nothing,
        restore::a_charge_settled_on_one_backend_seeds_the_other_with_its_springs,
        restore::arrays_grown_in_chunks_end_where_one_reservation_ends,
        seams::an_output_row_is_one_read_back,
        seams::tracked_polyhedra_carry_the_cpus_orientation,
        reduced_rows::device_reduced_rows_match_the_host_sums_of_the_full_arrays,
        reduced_rows::an_output_row_reads_back_the_same_few_bytes_whatever_the_particle_count,
        reduced_rows::device_reduced_rows_are_bit_identical_run_to_run,
        reduced_rows::drums_and_wall_groups_reduced_on_the_device_match_the_host_sums,
        render::a_sphere_covers_pi_r_squared_where_the_camera_puts_it,
        render::a_rendered_snapshot_shows_its_sphere_in_the_colour_of_its_speed,
        render::nearer_surfaces_hide_farther_ones_by_their_per_pixel_depth,
        render::pictures_are_identical_run_to_run,
        render::a_polyhedral_body_is_drawn_as_its_faces_in_its_particles_colour,
        render::a_fluid_is_drawn_in_the_colour_of_its_pressure,
        fluid::one_step_matches_the_cpu_with_every_switch,
        fluid::a_dam_break_on_the_gpu_follows_the_cpu,
        fluid::a_column_at_rest_on_the_gpu_keeps_its_hydrostatic_pressure,
        fluid::a_periodic_box_on_the_gpu_keeps_its_momentum,
        fluid::gpu_fluid_runs_are_bit_identical_and_restart_exactly,
        fluid::a_gpu_fluid_scene_resumes_bit_identically,
        fluid::a_turning_drum_on_the_gpu_drags_the_water_as_on_the_cpu,
        fluid::a_floating_box_on_the_gpu_moves_as_on_the_cpu,
        fluid::a_gpu_run_without_a_runtime_dir_prints_no_loader_error,
    ];
    let cpu_only = vec![tumble_testkit::harness::cpu_trial("render::bad_input_is_refused_in_one_line", render::bad_input_is_refused_in_one_line)];
    tumble_testkit::harness::run([cpu::trials(), gpu::trials(), gpu_only, cpu_only].into_iter().flatten().collect());
}
