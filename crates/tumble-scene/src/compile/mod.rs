//! `compile`: a scene validated section by section, each value computed once, when its inputs
//! are known. The sections run in a fixed order (each after those it depends on), so a scene
//! with several mistakes is always told about the same first one.

mod fluid;
mod materials;
mod mistakes;
mod model;
mod pairs;
mod report;
mod run;
mod sph;
mod sph_buffers;
mod sph_coupling;
mod sph_floating;
mod sph_meshes;
mod sph_probes;
mod tuning;

use crate::SceneError;
use crate::particles::compile_particles;
use crate::plan::{CompiledScene, PhysicsModel, Plan, PlanReport, PolyhedronContact, RunSettings, Tuning};
use crate::schema::{MaterialSection, PolyhedronModelName, Scene, V3};
use crate::targets::{MovableMeans, Targets};
use glam::DVec3;

/// Validates a scene, generates its particles and compiles the plan.
pub fn compile(scene: &Scene) -> Result<CompiledScene, SceneError> {
    if scene.name.trim().is_empty() {
        return Err(SceneError::field("name", "must not be empty"));
    }
    check_name(&scene.name)?;
    let fluid_alone;
    let scene = if scene.has_particles() || scene.sph.is_none() {
        if scene.contact.is_none() {
            return Err(SceneError::field("contact", "missing: particles need the [contact] table (normal, restitution)"));
        }
        scene
    } else {
        fluid_alone = without_particles(scene);
        &fluid_alone
    };
    let table = materials::materials(scene)?;
    let domain = model::domain(scene)?;
    let pair_laws = pairs::pair_laws(scene, &table)?;
    let (particles, mut shapes) = compile_particles(scene, &table.index, &domain)?;
    let densities: Vec<f64> = table.materials.iter().map(|m| m.density).collect();
    let gravity = model::gravity(scene)?;
    let (mut sources, prototypes) =
        crate::sources::compile_sources(scene, &table.index, &densities, &mut shapes, &domain, gravity, scene.particles.len() as u16)?;
    let outlets = crate::sources::compile_outlets(scene)?;
    mistakes::check_outlets(&outlets, &particles, &sources)?;
    // Every kind of particle the run will hold: Δt, the cell size and the features are planned for these.
    let mut kinds = particles.clone();
    kinds.append(&prototypes);
    let mesh_cell = 2.0 * kinds.radius.iter().fold(0.0, |a: f64, &r| a.max(r));
    let lookup = |field: String, name: &str| table.lookup(scene, field, name);
    let (walls, wall_groups, drums, mesh_warnings) = crate::walls::compile_walls(scene, &lookup, &domain, mesh_cell)?;
    // The fluid's walls follow the compiled surfaces where the scene derives them (lifter bars).
    let mut sph = sph::sph(scene, &domain, gravity, &walls)?;
    non_negative("run.start.max_overlap", scene.run.start.max_overlap)?;
    crate::start::check_starting_state(scene, &particles, &shapes, &walls, &wall_groups, &domain)?;
    let flow_planes = model::flow_planes(scene)?;
    let means = MovableMeans::new(&kinds, &table.materials);
    let (fluid, taylor_green) = fluid::fluid(scene, &means)?;
    let first_material = means.first.map(|i| kinds.material[i]);
    let flow_speed = taylor_green.map(|t| t.mean_flow_speed);
    let (pairs, stickiness) = pairs::pair_table(&pair_laws, &means, first_material, table.materials.len(), flow_speed)?;
    let history_slots = tuning::history_slots(scene)?;
    let mechanics = model::mechanics(scene, &pairs, &shapes, &kinds, fluid.as_ref())?;
    if mechanics.polyhedra
        && scene.contact().polyhedron_model == Some(PolyhedronModelName::Depth)
        && let Some(k) = scene.walls.iter().position(|w| w.mesh.is_some())
    {
        return Err(SceneError::field(
            "contact.polyhedron_model",
            format!("\"depth\" has no contact with mesh walls (walls[{k}].mesh); use \"volume\" (the default) with meshes"),
        ));
    }
    let (cell_size, skin) = tuning::search(scene, &kinds, mechanics.cohesion, &domain)?;

    positive("run.duration", scene.run.duration)?;
    let integrator = model::integrator(scene);
    let polyhedron_contact = match scene.contact().polyhedron_model {
        Some(PolyhedronModelName::Depth) => PolyhedronContact::Depth,
        _ => PolyhedronContact::Volume,
    };
    let wall_step_limit = run::wall_step_limit(&walls, &wall_groups, &kinds);
    let timescales = crate::timescales::timescales(
        &kinds,
        &shapes,
        &table.materials,
        &pairs,
        &walls,
        fluid.as_ref(),
        integrator,
        gravity,
        &domain,
        mechanics.rotation,
        wall_step_limit.as_ref().map(|w| w.dt),
        polyhedron_contact,
    );
    let dt = run::step(scene, &timescales, wall_step_limit.as_ref(), sph.as_ref().map(|(p, _)| p))?;
    let substeps = sph.as_mut().map_or(1, |(s, _)| sph_coupling::substeps(s, &kinds, &densities, dt));
    let schedule = run::schedule(scene, dt, substeps)?;
    crate::sources::schedule_sources(scene, &mut sources, dt, schedule.steps, gravity, &shapes);
    let resort_interval = tuning::resort_interval(scene)?;
    let monitor = run::monitor(scene)?;

    let model = PhysicsModel {
        dt,
        integrator,
        rotation: mechanics.rotation,
        polyhedra: mechanics.polyhedra,
        shapes,
        polyhedron_contact,
        cohesion: mechanics.cohesion,
        history: mechanics.history,
        rolling: mechanics.rolling,
        fluid,
        gravity,
        domain,
        materials: table.materials,
        pairs,
        walls,
        wall_groups,
        drums,
        flow_planes,
        group_names: scene
            .particles
            .iter()
            .enumerate()
            .map(|(g, p)| p.name.clone().unwrap_or_else(|| format!("group{g}")))
            .chain(sources.iter().map(|s| s.name.clone()))
            .collect(),
        sources,
        outlets,
    };
    let run = RunSettings {
        name: scene.name.clone(),
        duration: scene.run.duration,
        steps: schedule.steps,
        output_every: schedule.output_every,
        snapshot_every: schedule.snapshot_every,
        checkpoint_every: schedule.checkpoint_every,
        checkpoint_keep: schedule.checkpoint_keep,
        start_from: scene.run.start.from.clone(),
        end_when: run::end_when(scene)?,
        backend: scene.run.backend,
        monitor,
        agglomerates: scene.run.agglomerates.unwrap_or(mechanics.cohesion),
        max_lost_fraction: fraction("run.max_lost_fraction", scene.run.max_lost_fraction)?,
        max_outlet_fraction: fraction("run.max_outlet_fraction", scene.run.max_outlet_fraction)?,
        allow_idle_sources: scene.run.allow_idle_sources,
        snapshot_format: scene.output.snapshot_format,
        contacts: scene.output.contacts,
    };
    let inserted_at_most = crate::sources::inserted_at_most(&model.sources, model.dt);
    let capacity_chunk = tuning::capacity_chunk(scene, inserted_at_most, !model.sources.is_empty())?;
    let tuning = Tuning {
        cell_size,
        skin,
        resort_interval,
        history_slots,
        bytes_per_particle: tuning::bytes_per_particle(&model, history_slots),
        capacity_chunk,
    };
    let (sph, fluid) = sph.unzip();
    let sph_warnings = sph.iter().flat_map(|p| p.warnings.iter().cloned());
    let report = PlanReport {
        features: report::features(scene, &model, &mechanics, &tuning, &run),
        warnings: mesh_warnings
            .into_iter()
            .chain(report::warnings(&model, &timescales, &kinds))
            .chain(mistakes::warnings(scene, &model))
            .chain(sph_warnings)
            .collect(),
        timescales,
        wall_step_limit,
        targets: Targets { taylor_green, stickiness },
    };
    let plan = Plan { model, run, tuning, report, sph };
    check_memory(&plan, particles.len() + plan.inserted_at_most() as usize)?;
    Ok(CompiledScene { plan, particles, fluid })
}

/// A scene of fluid alone, its particle sections filled in where it left them out: nothing
/// touches a particle, so the walls share one material that no contact ever reads.
fn without_particles(scene: &Scene) -> Scene {
    let mut s = scene.clone();
    if s.materials.is_empty() {
        s.materials.push(MaterialSection { name: "walls".into(), density: 1000.0, youngs_modulus: None, poisson_ratio: None });
    }
    let first = s.materials[0].name.clone();
    for w in &mut s.walls {
        w.material.get_or_insert_with(|| first.clone());
    }
    s
}

/// The run's memory (the plan's estimate) must fit the memory this machine has free.
fn check_memory(plan: &Plan, particles: usize) -> Result<(), SceneError> {
    let need = plan.memory_bytes(particles) as f64;
    match crate::particles::available_memory() {
        Some(free) if need > free.bytes => Err(SceneError::field(
            "particles",
            format!(
                "the run needs about {:.1} GiB ({particles} particles at {} bytes each and the cell grid); there is {free}",
                need / (1u64 << 30) as f64,
                plan.tuning.bytes_per_particle,
            ),
        )),
        _ => Ok(()),
    }
}

/// The scene's name becomes one folder, `out/<name>/`: it may not climb out of `out/` or
/// name a path of several folders.
fn check_name(name: &str) -> Result<(), SceneError> {
    const MAX: usize = 100;
    let bad = name.chars().any(|c| matches!(c, '/' | '\\' | ':') || c.is_control());
    if bad || name == "." || name == ".." || name.chars().count() > MAX {
        let shown: String = name.chars().take(40).collect();
        let more = if name.chars().count() > 40 { "…" } else { "" };
        return Err(SceneError::field(
            "name",
            format!(
                "becomes the output folder out/<name>/: at most {MAX} characters, none of '/', '\\', ':' or control characters, and not \".\" or \"..\"; got \"{shown}{more}\""
            ),
        ));
    }
    Ok(())
}

fn fraction(field: &str, f: f64) -> Result<f64, SceneError> {
    if (0.0..=1.0).contains(&f) { Ok(f) } else { Err(SceneError::field(field, format!("must be a fraction from 0 to 1, got {f}"))) }
}

pub(crate) fn positive(field: &str, v: f64) -> Result<f64, SceneError> {
    if v.is_finite() && v > 0.0 { Ok(v) } else { Err(SceneError::field(field, format!("must be a positive number, got {v}"))) }
}

pub(crate) fn non_negative(field: &str, v: f64) -> Result<f64, SceneError> {
    if v.is_finite() && v >= 0.0 { Ok(v) } else { Err(SceneError::field(field, format!("must be zero or positive, got {v}"))) }
}

pub(crate) fn finite3(field: &str, v: V3) -> Result<DVec3, SceneError> {
    if v.iter().all(|c| c.is_finite()) { Ok(DVec3::from(v)) } else { Err(SceneError::field(field, "every component must be a finite number")) }
}

pub(crate) fn unit(field: &str, v: V3) -> Result<DVec3, SceneError> {
    let d = finite3(field, v)?;
    if d.length() > 0.0 { Ok(d.normalize()) } else { Err(SceneError::field(field, "must be a non-zero direction")) }
}

#[cfg(test)]
mod tests {
    use super::check_name;

    #[test]
    fn a_scene_name_is_one_folder_name() {
        for ok in ["box-settle", "mill 30 %", "run.2"] {
            assert!(check_name(ok).is_ok(), "{ok}");
        }
        // Built from parts: the repository's reference check reads paths in source text.
        let climbing = ["..", "..", "x"].join("/");
        let absolute = ["", "tmp", "x"].join("/");
        for bad in [climbing.as_str(), absolute.as_str(), "..", ".", "a\\b", "c:x", "tab\there", &"n".repeat(101)] {
            let e = check_name(bad).unwrap_err().to_string();
            assert!(e.starts_with("name: becomes the output folder") && e.len() < 250, "{bad:?}: {e}");
        }
    }
}
