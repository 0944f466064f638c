//! The pair table: the contact laws of every material pair, from [contact] and its
//! per-pair overrides. Cohesion given as a stickiness number is resolved once the particles
//! (their effect length and mass) and the flow (its speed) are known.

use super::materials::MaterialTable;
use super::{non_negative, positive};
use crate::SceneError;
use crate::plan::{Material, PairParams};
use crate::schema::*;
use crate::targets::{MovableMeans, Stickiness, cohesion_for_stickiness_number};
use tumble_contact::{
    MIN_CLIPPED_RESTITUTION, NormalLaw, RollingModel, SpringLaw, TangentialLaw, ViscousParameter, clipped_damping_ratio, clipped_hertz_beta,
    hertz_effective_moduli, stickiness_number,
};

/// Cohesion of a pair as the scene gives it.
#[derive(Clone, Copy, Debug)]
enum CohesionInput {
    None,
    Stiffness {
        stiffness: f64,
        collision_speed: Option<f64>,
    },
    /// k_c from the stickiness number Sy, at the collision speed (or the flow's mean speed).
    Stickiness {
        number: f64,
        collision_speed: Option<f64>,
    },
}

impl CohesionInput {
    fn collision_speed(&self) -> Option<f64> {
        match *self {
            CohesionInput::None => None,
            CohesionInput::Stiffness { collision_speed, .. } | CohesionInput::Stickiness { collision_speed, .. } => collision_speed,
        }
    }
}

/// The validated laws of one material pair, before cohesion is resolved.
pub(super) struct PairLaw {
    /// Where its parameters come from: "contact" or "contact.pairs[k]".
    root: String,
    normal: NormalLaw,
    tangential: TangentialLaw,
    cohesion: CohesionInput,
    no_attraction: bool,
    rolling: f64,
    rolling_model: RollingModel,
}

/// The laws of every material pair, row-major [a * materials + b], and a check that each
/// [[contact.pairs]] entry names defined materials.
pub(super) fn pair_laws(scene: &Scene, table: &MaterialTable) -> Result<Vec<PairLaw>, SceneError> {
    let materials = &table.materials;
    let n_mat = materials.len();
    let mut laws = Vec::with_capacity(n_mat * n_mat);
    let contact = scene.contact();
    for a in 0..n_mat {
        for b in 0..n_mat {
            let over = contact.pairs.iter().enumerate().find(|(_, p)| {
                let (x, y) = (p.materials[0].as_str(), p.materials[1].as_str());
                (x == materials[a].name && y == materials[b].name) || (y == materials[a].name && x == materials[b].name)
            });
            let field_root = over.map_or("contact".to_string(), |(k, _)| format!("contact.pairs[{k}]"));
            let p = over.map(|(_, p)| p);
            let normal = p.and_then(|p| p.normal.as_ref()).unwrap_or(&contact.normal);
            let e = p.and_then(|p| p.restitution).unwrap_or(contact.restitution);
            let tangential = p.and_then(|p| p.tangential.as_ref()).unwrap_or(&contact.tangential);
            let cohesion = p.and_then(|p| p.cohesion.as_ref()).or(contact.cohesion.as_ref());
            let mut law = pair_law(&field_root, normal, e, tangential, cohesion, contact.no_attraction, &materials[a], &materials[b])?;
            let rolling_root = if p.and_then(|p| p.rolling_friction).is_some() { field_root.as_str() } else { "contact" };
            law.rolling = non_negative(
                &format!("{rolling_root}.rolling_friction"),
                p.and_then(|p| p.rolling_friction).or(contact.rolling_friction).unwrap_or(0.0),
            )?;
            law.rolling_model = rolling_model(scene, &law)?;
            laws.push(law);
        }
    }
    for (k, p) in contact.pairs.iter().enumerate() {
        for (s, name) in p.materials.iter().enumerate() {
            table.lookup(scene, format!("contact.pairs[{k}].materials[{s}]"), name)?;
        }
    }
    Ok(laws)
}

/// The pair table with every cohesion stiffness known, and the stickiness number of the
/// representative pair (the first movable particle's material with itself). `flow_speed` is
/// the Taylor–Green mean speed u_0, when there is one.
pub(super) fn pair_table(
    laws: &[PairLaw],
    means: &MovableMeans,
    first_material: Option<u16>,
    n_materials: usize,
    flow_speed: Option<f64>,
) -> Result<(Vec<PairParams>, Option<Stickiness>), SceneError> {
    let u0 = flow_speed.filter(|&u| u > 0.0);
    let mut pairs = Vec::with_capacity(laws.len());
    for law in laws {
        let root = &law.root;
        let speed = match law.cohesion.collision_speed() {
            Some(u) => Some(positive(&format!("{root}.cohesion.collision_speed"), u)?),
            None => u0,
        };
        let cohesion = match law.cohesion {
            CohesionInput::None => 0.0,
            CohesionInput::Stiffness { stiffness, .. } => stiffness,
            CohesionInput::Stickiness { number: sy, .. } => {
                let field = format!("{root}.cohesion.stickiness_number");
                positive(&field, sy)?;
                let e = law.normal.restitution();
                if sy * e >= 1.0 {
                    return Err(SceneError::field(
                        field,
                        format!("Sy = {sy} with restitution e = {e} is out of reach: Sy < 1/e = {:.4} for any k_c (lower Sy or e)", 1.0 / e),
                    ));
                }
                let effect_length = means.effect_length;
                if effect_length.is_nan() || effect_length <= 0.0 {
                    return Err(SceneError::field(field, "needs an effect_diameter larger than the body diameter (L_e = d_e − d_b > 0)"));
                }
                let Some(u) = speed else {
                    return Err(SceneError::field(
                        field,
                        format!("needs {root}.cohesion.collision_speed (m/s), or a Taylor–Green flow whose mean speed u_0 is taken"),
                    ));
                };
                cohesion_for_stickiness_number(sy, e, effect_length, u, means.reduced_mass)
            }
        };
        let pair = PairParams {
            normal: law.normal,
            tangential: law.tangential,
            cohesion,
            no_attraction: law.no_attraction,
            rolling: law.rolling,
            rolling_model: law.rolling_model,
        };
        if let Some((k_c, k_n)) = pair.cohesion_over_stiffness() {
            return Err(SceneError::field(
                format!("{root}.cohesion"),
                format!(
                    "k_c = {k_c:.4e} N/m is not below the normal stiffness k_n = {k_n:.4e} N/m: the attraction k_c (δ + L_e) would outgrow the repulsion k_n δ and pull the particles through each other whatever the dt; use k_c < k_n (they then rest at δ = k_c L_e / (k_n − k_c))"
                ),
            ));
        }
        pairs.push(pair);
    }
    let stickiness = first_material.and_then(|m| {
        let k = m as usize * (n_materials + 1);
        let pair = &pairs[k];
        let speed = laws[k].cohesion.collision_speed().or(u0);
        let (effect_length, m_star) = (means.effect_length, means.reduced_mass);
        if pair.cohesion > 0.0
            && effect_length > 0.0
            && let Some(u) = speed
        {
            let e = pair.normal.restitution();
            Some(Stickiness {
                number: stickiness_number(effect_length, pair.cohesion, e, u, m_star),
                stiffness: pair.cohesion,
                collision_speed: u,
                effect_length,
                reduced_mass: m_star,
                restitution: e,
            })
        } else {
            None
        }
    });
    Ok((pairs, stickiness))
}

#[allow(clippy::too_many_arguments)]
fn pair_law(
    root: &str,
    normal: &NormalSection,
    e: f64,
    tangential: &TangentialSection,
    cohesion: Option<&CohesionSection>,
    no_attraction: bool,
    a: &Material,
    b: &Material,
) -> Result<PairLaw, SceneError> {
    if !(e > 0.0 && e <= 1.0) {
        return Err(SceneError::field(format!("{root}.restitution"), format!("must lie in (0, 1], got {e}")));
    }
    let normal = match normal {
        NormalSection::Linear { stiffness } => NormalLaw::linear(positive(&format!("{root}.normal.stiffness"), *stiffness)?, e),
        NormalSection::Hertz {} => {
            let need = |m: &Material| -> Result<(f64, f64), SceneError> {
                match (m.youngs_modulus, m.poisson_ratio) {
                    (Some(y), Some(nu)) => Ok((y, nu)),
                    _ => Err(SceneError::field(
                        format!("{root}.normal"),
                        format!("the Hertz model needs youngs_modulus and poisson_ratio on material \"{}\"", m.name),
                    )),
                }
            };
            let ((ea, na), (eb, nb)) = (need(a)?, need(b)?);
            let (e_star, g_star) = hertz_effective_moduli(ea, na, eb, nb);
            NormalLaw::hertz(e_star, g_star, e)
        }
    };
    if no_attraction && e < MIN_CLIPPED_RESTITUTION {
        return Err(SceneError::field(
            format!("{root}.restitution"),
            format!(
                "with no_attraction the restitution must be at least {MIN_CLIPPED_RESTITUTION:e} (a clipped dashpot cannot absorb more), got {e}"
            ),
        ));
    }
    // A clipped dashpot loses less than a pulling one: its coefficient is recomputed to keep e.
    let normal = match normal {
        NormalLaw::Linear { stiffness, restitution, .. } if no_attraction => {
            NormalLaw::Linear { stiffness, restitution, damping_ratio: clipped_damping_ratio(restitution) }
        }
        NormalLaw::Hertz { e_star, g_star, restitution, .. } if no_attraction => {
            NormalLaw::Hertz { e_star, g_star, restitution, beta: clipped_hertz_beta(restitution) }
        }
        law => law,
    };
    let mu = |f: f64| -> Result<f64, SceneError> { non_negative(&format!("{root}.tangential.friction"), f) };
    let tangential = match tangential {
        TangentialSection::None => TangentialLaw::None,
        TangentialSection::ViscousCoulomb { friction, stiffness, viscous } => {
            let viscous = match (stiffness, viscous) {
                (Some(k), None) => ViscousParameter::Stiffness(positive(&format!("{root}.tangential.stiffness"), *k)?),
                (None, Some(c)) => ViscousParameter::Coefficient(positive(&format!("{root}.tangential.viscous"), *c)?),
                _ => {
                    return Err(SceneError::field(
                        format!("{root}.tangential"),
                        "viscous-coulomb needs exactly one of stiffness (k_f, N/m) or viscous (c_t, N s/m)",
                    ));
                }
            };
            TangentialLaw::ViscousCoulomb { friction: mu(*friction)?, viscous }
        }
        TangentialSection::StickLimited { friction } => TangentialLaw::StickLimited { friction: mu(*friction)? },
        TangentialSection::DynamicOnly { friction } => TangentialLaw::DynamicOnly { friction: mu(*friction)? },
        TangentialSection::History { friction, stiffness, damping } => {
            let stiffness = stiffness.map(|k| positive(&format!("{root}.tangential.stiffness"), k)).transpose()?;
            let damping = damping.map(|c| non_negative(&format!("{root}.tangential.damping"), c)).transpose()?;
            let spring = match (normal, stiffness) {
                (NormalLaw::Hertz { g_star, beta, .. }, None) => {
                    if damping.is_some() {
                        return Err(SceneError::field(
                            format!("{root}.tangential.damping"),
                            "Hertz–Mindlin derives η_t from G* and e; give damping only with an explicit stiffness (Cundall–Strack)",
                        ));
                    }
                    SpringLaw::Mindlin { g_star, beta }
                }
                (NormalLaw::Linear { stiffness: k_n, damping_ratio, .. }, k_t) => {
                    linear_spring(k_t.unwrap_or(2.0 / 7.0 * k_n), damping, damping_ratio)
                }
                (NormalLaw::Hertz { beta, .. }, Some(k_t)) => linear_spring(k_t, damping, -beta),
            };
            TangentialLaw::History { friction: mu(*friction)?, spring }
        }
    };
    let cohesion = match cohesion {
        Some(CohesionSection { stiffness: Some(k), stickiness_number: None, collision_speed }) => {
            CohesionInput::Stiffness { stiffness: positive(&format!("{root}.cohesion.stiffness"), *k)?, collision_speed: *collision_speed }
        }
        Some(CohesionSection { stiffness: None, stickiness_number: Some(sy), collision_speed }) => {
            CohesionInput::Stickiness { number: *sy, collision_speed: *collision_speed }
        }
        Some(_) => {
            return Err(SceneError::field(format!("{root}.cohesion"), "give exactly one of stiffness (k_c, N/m) or stickiness_number (Sy)"));
        }
        None => CohesionInput::None,
    };
    Ok(PairLaw { root: root.to_string(), normal, tangential, cohesion, no_attraction, rolling: 0.0, rolling_model: RollingModel::Constant })
}

/// The rolling model of a pair: EPSD2 stores its torque with the tangential spring, so a pair
/// with rolling friction under it needs the history law.
fn rolling_model(scene: &Scene, law: &PairLaw) -> Result<RollingModel, SceneError> {
    match scene.contact().rolling_model {
        None | Some(RollingModelName::Constant) => Ok(RollingModel::Constant),
        Some(RollingModelName::Epsd2) if law.rolling == 0.0 || law.tangential.has_history() => Ok(RollingModel::Epsd2),
        Some(RollingModelName::Epsd2) => Err(SceneError::field(
            "contact.rolling_model",
            format!(
                "\"epsd2\" keeps a rolling spring beside the tangential one and needs {}.tangential model = \"history\"; use rolling_model = \"constant\" (valid: \"constant\", \"epsd2\")",
                law.root
            ),
        )),
    }
}

/// Cundall–Strack spring: the given η_t, or the normal law's damping ratio applied to k_t.
fn linear_spring(stiffness: f64, damping: Option<f64>, damping_ratio: f64) -> SpringLaw {
    match damping {
        Some(damping) => SpringLaw::Linear { stiffness, damping, damping_ratio: 0.0 },
        None => SpringLaw::Linear { stiffness, damping: 0.0, damping_ratio },
    }
}
