//! The plan's report: each feature and why it is on or off, and warnings about the step
//! and the model.

use super::model::Mechanics;
use crate::particles::InitialParticles;
use crate::plan::{Feature, Fluid, PairParams, PhysicsModel, RunSettings, Tuning, Wall};
use crate::schema::Scene;
use crate::timescales::{ACCURATE_STEPS_PER_COLLISION, STEPS_PER_COLLISION, TANGENTIAL_STEP_SHARE, Timescales};
use glam::DVec3;
use std::fmt::Write as _;
use tumble_contact::{NormalLaw, SpringLaw, TangentialLaw, ViscousParameter};

/// Every feature with its reason, in the order `tumble plan` lists them.
pub(super) fn features(scene: &Scene, model: &PhysicsModel, mechanics: &Mechanics, tuning: &Tuning, run: &RunSettings) -> Vec<Feature> {
    let PhysicsModel { rotation, polyhedra, cohesion, history, rolling, integrator, gravity, .. } = *model;
    let (shapes, fluid, walls, drums, domain, pairs) = (&model.shapes, &model.fluid, &model.walls, &model.drums, &model.domain, &model.pairs);
    let (cell_size, history_slots, agglomerates) = (tuning.cell_size, tuning.history_slots, run.agglomerates);
    let (any_friction, movable) = (mechanics.any_friction, mechanics.movable);
    let mut features = vec![
        Feature { name: "rotation", active: rotation, reason: mechanics.rotation_reason.clone() },
        Feature {
            name: "polyhedra",
            active: polyhedra,
            reason: if polyhedra {
                let names: Vec<String> = shapes.iter().map(|s| format!("{} ({} faces)", s.name, s.body.faces().len())).collect();
                format!("convex polyhedra: {}; bounding radius sets the search reach", names.join(", "))
            } else {
                "every particle is a sphere: no orientation or shape is carried".into()
            },
        },
        Feature { name: "polyhedron contact", active: polyhedra, reason: polyhedron_contact_reason(model) },
        Feature {
            name: "cohesion",
            active: cohesion,
            reason: if cohesion {
                format!("a contact has cohesion stiffness; the search reaches the effect diameter (cell {cell_size:.4e} m)")
            } else {
                "no cohesion in [contact]: the search stops at body contact".into()
            },
        },
        Feature {
            name: "drag",
            active: fluid.is_some(),
            reason: match &fluid {
                Some(f) => format!(
                    "[fluid] {:?}, {}",
                    f.drag,
                    if integrator.implicit_drag() { "integrated implicitly" } else { "added as an explicit force" }
                ),
                None => "no [fluid] section: no drag pass".into(),
            },
        },
        Feature {
            name: "gravity",
            active: gravity != DVec3::ZERO,
            reason: if gravity != DVec3::ZERO { format!("{:?} m/s²", gravity.to_array()) } else { "no [gravity] section".into() },
        },
        Feature {
            name: "walls",
            active: !walls.is_empty(),
            reason: {
                let servo = |w: &&Wall| model.wall_groups[w.group as usize].servo.is_some();
                let moving = walls.iter().filter(|w| w.motion.is_some()).count();
                let servos = walls.iter().filter(servo).count();
                let mut r = format!("{} static surfaces", walls.len() - moving - servos);
                if moving > 0 {
                    let _ = write!(r, ", {moving} moving (wall velocity enters the contact; rebuild when a wall sweeps skin/2)");
                }
                for g in model.wall_groups.iter().filter(|g| g.servo.is_some()) {
                    let s = g.servo.unwrap();
                    let _ = write!(
                        r,
                        "; servo {}: presses along {:?} to {} N at up to {} m/s, gain {:.4e} m/s per N",
                        g.name,
                        s.direction.to_array(),
                        s.force,
                        s.max_speed,
                        s.gain
                    );
                }
                if !drums.is_empty() {
                    let _ = write!(r, "; drums {}", drums.iter().map(|d| d.name.as_str()).collect::<Vec<_>>().join(", "));
                }
                for w in walls {
                    if let tumble_geom::SurfaceShape::Mesh(m) = &w.shape {
                        let mesh = &m.body.mesh;
                        let (cells, cell) = m.body.grid.layout();
                        let kind = if mesh.two_sided { "open sheet, two-sided" } else { "closed, one-sided" };
                        let _ = write!(
                            r,
                            "; mesh {}: {} triangles ({kind}), binned on {}x{}x{} cells of {cell:.3e} m",
                            w.name,
                            mesh.triangles.len(),
                            cells[0],
                            cells[1],
                            cells[2]
                        );
                    }
                }
                r
            },
        },
        Feature {
            name: "periodic",
            active: domain.periodic.iter().any(|&p| p),
            reason: format!("periodic axes {:?}; particles leaving other sides are removed", domain.periodic),
        },
        Feature { name: "normal", active: true, reason: describe_law(&pairs[0].normal) },
        Feature { name: "tangential", active: any_friction, reason: describe_tangential(&pairs[0].tangential) },
        Feature {
            name: "history",
            active: history,
            reason: if history {
                format!("tangential model \"history\": {history_slots} spring slots per particle, keyed by neighbour id")
            } else {
                "no tangential spring: no per-contact state is carried".into()
            },
        },
        Feature {
            name: "rolling",
            active: rolling,
            reason: if rolling {
                let epsd2 = pairs.iter().any(|p| p.rolling > 0.0 && p.rolling_model == tumble_contact::RollingModel::Epsd2);
                let how = if epsd2 {
                    "EPSD2 elastic–plastic rolling spring, k_r = 2.25 k_n μ_r² R*², kept with the tangential spring"
                } else {
                    "constant directional torque"
                };
                format!("rolling resistance μ_r = {} ({how})", pairs.iter().map(|p| p.rolling).fold(0.0, f64::max))
            } else {
                "no rolling_friction: no rolling torque".into()
            },
        },
    ];
    features.push(Feature {
        name: "agglomerates",
        active: agglomerates,
        reason: match scene.run.agglomerates {
            Some(true) => "run.agglomerates = true: agglomerates.csv at every output interval".into(),
            Some(false) => "run.agglomerates = false".into(),
            None if cohesion => "cohesion is on: agglomerates.csv at every output interval (run.agglomerates = false turns it off)".into(),
            None => "no cohesion (run.agglomerates = true writes agglomerates.csv anyway)".into(),
        },
    });
    if !movable {
        features.push(Feature { name: "motion", active: false, reason: "every particle is fixed".into() });
    }
    features
}

/// Warnings about the step and the model.
pub(super) fn warnings(model: &PhysicsModel, timescales: &Timescales, particles: &InitialParticles) -> Vec<String> {
    let (dt, pairs, gravity, walls, fluid) = (model.dt, &model.pairs, model.gravity, &model.walls, &model.fluid);
    let mut warnings = Vec::new();
    if let Some(t) = timescales.collision_time
        && t / dt < ACCURATE_STEPS_PER_COLLISION
    {
        warnings.push(format!("only {:.1} steps per collision; results will be inaccurate ({STEPS_PER_COLLISION} is the default)", t / dt));
    }
    if let Some(t) = timescales.tangential_time
        && dt > t * TANGENTIAL_STEP_SHARE * (1.0 + 1e-12)
    {
        warnings.push(format!(
                "dt is more than 1/6 of the viscous tangential relaxation time {t:.3e} s: dense packings may chatter (energy booked as dissipated while at rest); use dt <= {:.3e} or a smaller c_t",
                t * TANGENTIAL_STEP_SHARE
            ));
    }
    if looks_quasi_static(particles, pairs, gravity, walls, fluid.as_ref()) {
        warnings.push(
            "this scene looks quasi-static (gravity, walls, particles starting at rest, no fluid) but its friction is history-free: \
             piles and slopes creep at the speed where the viscous force balances gravity; use tangential model = \"history\" to hold static loads"
                .into(),
        );
    }
    warnings
}

/// Gravity pressing particles that start at rest onto walls, with history-free friction.
fn looks_quasi_static(p: &InitialParticles, pairs: &[PairParams], gravity: DVec3, walls: &[Wall], fluid: Option<&Fluid>) -> bool {
    let history_free = pairs.iter().any(|p| p.tangential.friction() > 0.0 && !p.tangential.has_history());
    let at_rest = p.velocity.iter().all(|v| *v == DVec3::ZERO);
    history_free && gravity != DVec3::ZERO && !walls.is_empty() && fluid.is_none() && at_rest
}

fn describe_law(law: &NormalLaw) -> String {
    match law {
        NormalLaw::Linear { stiffness, restitution, .. } => format!("linear spring-dashpot, k_n = {stiffness:e} N/m, e = {restitution}"),
        NormalLaw::Hertz { e_star, restitution, .. } => format!("Hertz with Tsuji damping, E* = {e_star:e} Pa, e = {restitution}"),
    }
}

fn describe_tangential(law: &TangentialLaw) -> String {
    match law {
        TangentialLaw::None => "none: no tangential force".into(),
        TangentialLaw::ViscousCoulomb { friction, viscous: ViscousParameter::Coefficient(c) } => {
            format!("viscous-Coulomb, μ = {friction}, c_t = {c:e} N s/m (history-free)")
        }
        TangentialLaw::ViscousCoulomb { friction, viscous: ViscousParameter::Stiffness(k) } => {
            format!("viscous-Coulomb, μ = {friction}, c_t = k_f t_col with k_f = {k:e} N/m (history-free)")
        }
        TangentialLaw::StickLimited { friction } => format!("stick-limited, μ = {friction} (history-free)"),
        TangentialLaw::DynamicOnly { friction } => format!("dynamic-only, μ = {friction}: oscillates around rest (a documented failure case)"),
        TangentialLaw::History { friction, spring: SpringLaw::Linear { stiffness, damping, damping_ratio } } => {
            let eta = if *damping_ratio > 0.0 { format!("damping ratio {damping_ratio:.4}") } else { format!("η_t = {damping:e} N s/m") };
            format!("history (Cundall–Strack), μ = {friction}, k_t = {stiffness:e} N/m, {eta}: a spring per contact holds static loads")
        }
        TangentialLaw::History { friction, spring: SpringLaw::Mindlin { g_star, .. } } => {
            format!("history (Hertz–Mindlin), μ = {friction}, k_t = 8 G* √(R* δ) with G* = {g_star:e} Pa: a spring per contact holds static loads")
        }
    }
}

/// How polyhedra meet, with the stiffness of each contact configuration per shape in the volume
/// model (multiples of the law's k, docs/polyhedra.md): a face on a larger face, an edge on a face,
/// a corner, and crossed edges (cone-like: the force grows as δ², its secant stiffness ρ δ k per
/// edge inside the other body, given at δ = 1 % of the volume-equivalent radius).
fn polyhedron_contact_reason(model: &PhysicsModel) -> String {
    if !model.polyhedra {
        return "no polyhedra".into();
    }
    match model.polyhedron_contact {
        crate::PolyhedronContact::Depth => {
            "\"depth\": the law at the separating-axis depth at the manifold's depth-weighted point, k in every configuration; not a potential (elastic contacts gain or lose energy)".into()
        }
        crate::PolyhedronContact::Volume => {
            let per_shape: Vec<String> = model
                .shapes
                .iter()
                .map(|s| {
                    let density = tumble_geom::edge_density(&s.body);
                    let longest = s.body.edges().iter().map(|e| (s.body.vertices()[e.vertices[1] as usize] - s.body.vertices()[e.vertices[0] as usize]).length()).fold(0.0, f64::max);
                    format!(
                        "{}: face on face {:.0} k, edge on face {:.1} k, corner 1 k, crossed edges {:.1e} k per edge at δ = 1 % of r",
                        s.name,
                        s.face_on_weight,
                        2.0 + longest * density,
                        density * 0.01 * s.equivalent_radius
                    )
                })
                .collect();
            format!(
                "\"volume\" (energy-conserving): the law on the overlap volume over the face area, at every corner inside and along every edge inside; {}",
                per_shape.join("; ")
            )
        }
    }
}
