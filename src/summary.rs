//! summary.json: what runs while it runs, and how it ended (docs/cli.md, "Outputs").

use crate::{RunSummary, Simulation};

/// summary.json while the run goes on: what runs, and that it has not finished.
pub(crate) fn running_json(sim: &Simulation, plan_text: &str) -> String {
    let plan = sim.plan();
    let value = serde_json::json!({
        "scene": plan.run.name,
        "status": "running",
        "backend": sim.backend_name(),
        "particles": sim.particles(),
        "steps": plan.run.steps,
        "dt": plan.model.dt,
        "plan": { "text": plan_text },
    });
    serde_json::to_string_pretty(&value).unwrap() + "\n"
}

fn finite_or_null(x: f64) -> serde_json::Value {
    if x.is_finite() { serde_json::json!(x) } else { serde_json::Value::Null }
}

pub(crate) fn summary_json(sim: &Simulation, s: &RunSummary, plan_text: &str, status: &str, stopped: Option<String>) -> String {
    let plan = sim.plan();
    let o = &s.final_observables;
    let features: serde_json::Map<String, serde_json::Value> =
        plan.report.features.iter().map(|f| (f.name.to_string(), serde_json::json!({ "active": f.active, "reason": f.reason }))).collect();
    let value = serde_json::json!({
        "scene": plan.run.name,
        "status": status,
        "backend": sim.backend_name(),
        "device": sim.device_name(),
        "precision": sim.precision(),
        "particles": s.particles,
        "steps": s.steps,
        "dt": plan.model.dt,
        "simulated_time": sim.time(),
        "wall_seconds": s.wall_seconds,
        "particle_steps_per_second": finite_or_null(s.particle_steps_per_second),
        "removed_particles": sim.removed(),
        "max_lost_fraction": plan.run.max_lost_fraction,
        "max_outlet_fraction": plan.run.max_outlet_fraction,
        "sources": plan.model.sources.iter().zip(sim.inserted()).map(|(src, (n, m))| serde_json::json!({ "name": src.name, "inserted": n, "mass": m })).collect::<Vec<_>>(),
        "outlets": plan.model.outlets.iter().zip(sim.outlet_tallies()).map(|(o, t)| serde_json::json!({ "name": o.name, "deleted": t.count, "mass": t.mass })).collect::<Vec<_>>(),
        "warnings": s.warnings,
        "neighbour_list_builds": sim.neighbour_builds(),
        "adapter": sim.adapter().map(|a| serde_json::json!({ "name": a.name, "backend": a.backend, "driver": a.driver, "device_type": a.device_type })),
        "memory_bytes": sim.memory_bytes(),
        "bytes_per_particle": sim.bytes_per_particle(),
        "plan": {
            "integrator": plan.model.integrator.name(),
            "collision_time": plan.report.timescales.collision_time,
            "stability_limit": plan.report.timescales.stability_limit,
            "steps_per_collision": plan.steps_per_collision(),
            "cell_size": plan.tuning.cell_size,
            "memory_bytes": plan.memory_bytes(s.particles),
            "features": features,
            "text": plan_text,
        },
        "final": {
            "kinetic_energy": finite_or_null(o.kinetic_energy),
            "rotational_energy": finite_or_null(o.rotational_energy),
            "potential_energy": finite_or_null(o.potential_energy),
            "elastic_energy": finite_or_null(o.elastic_energy),
            "dissipated_energy": finite_or_null(o.dissipated_energy),
            "contacts": o.contacts,
        },
        "stopped": stopped,
    });
    let mut value = value;
    if let Some(why) = &s.ended_early {
        value["ended_early"] = serde_json::json!(why);
    }
    if let Some(t) = &s.step_seconds {
        value["step_seconds"] = serde_json::json!({ "fluid": t.fluid, "coupling": t.coupling, "particles": t.particles });
    }
    if let Some(step) = s.resumed_from_step {
        value["resumed_from_step"] = serde_json::json!(step);
    }
    for phase in sim.phases() {
        // Each phase's particles, memory and final row (its first table), under its name.
        let last: serde_json::Map<String, serde_json::Value> = phase.summary().into_iter().map(|(c, v)| (c, finite_or_null(v))).collect();
        value[phase.name()] = serde_json::json!({ "particles": phase.particles(), "memory_bytes": phase.memory_bytes(), "final": last });
    }
    if let Some(c) = &s.checkpoints {
        value["checkpoints"] = serde_json::json!({
            "every_steps": c.every_steps,
            "written": c.written,
            "last": c.last.as_ref().map(|p| p.display().to_string()),
            "last_bytes": c.last_bytes,
            "write_seconds": c.seconds,
        });
    }
    if let Some(a) = &s.final_agglomerates {
        value["agglomerates"] = serde_json::json!({
            "count": a.count,
            "mean_size": a.mean_size,
            "weighted_mean_size": a.weighted_mean_size,
            "max_size": a.max_size,
            "mean_void_fraction": a.mean_void_fraction,
            "mean_void_fraction_multi": a.mean_void_fraction_multi,
            "wrapping": a.wrapping,
        });
    }
    if let Some(tg) = &plan.report.targets.taylor_green {
        value["plan"]["mean_flow_speed"] = serde_json::json!(tg.mean_flow_speed);
        value["plan"]["vortex_size"] = serde_json::json!(tg.vortex_size);
        value["plan"]["stokes_number"] = serde_json::json!(tg.stokes_number);
    }
    if let Some(sy) = &plan.report.targets.stickiness {
        value["plan"]["stickiness_number"] = serde_json::json!(sy.number);
        value["plan"]["cohesion_stiffness"] = serde_json::json!(sy.stiffness);
    }
    serde_json::to_string_pretty(&value).unwrap() + "\n"
}
