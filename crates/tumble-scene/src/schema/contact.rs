//! The `[contact]` table and its per-pair overrides: the force laws between particles and walls.

use serde::Deserialize;

#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ContactSection {
    pub normal: NormalSection,
    pub restitution: f64,
    #[serde(default)]
    pub tangential: TangentialSection,
    pub cohesion: Option<CohesionSection>,
    /// Clamp the normal force so it never pulls (F_n·n ≥ 0).
    #[serde(default)]
    pub no_attraction: bool,
    /// Rolling resistance μ_r (constant directional torque μ_r R* |F_n|).
    pub rolling_friction: Option<f64>,
    /// How rolling_friction acts: "constant" (default) or "epsd2" (elastic–plastic spring, needs history).
    pub rolling_model: Option<RollingModelName>,
    /// How polyhedra meet: "volume" (default; a potential of the overlap volume, energy-conserving)
    /// or "depth" (the separating-axis depth at the manifold's depth-weighted point).
    pub polyhedron_model: Option<PolyhedronModelName>,
    /// Contacts with history each particle can hold (tangential model "history").
    pub history_slots: Option<u32>,
    #[serde(default)]
    pub pairs: Vec<PairSection>,
}

/// The rolling resistance models `contact.rolling_model` names.
#[derive(Clone, Copy, Debug, Deserialize, PartialEq, Eq)]
#[serde(rename_all = "kebab-case")]
pub enum RollingModelName {
    Constant,
    Epsd2,
}

/// The polyhedron contact models `contact.polyhedron_model` names.
#[derive(Clone, Copy, Debug, Deserialize, PartialEq, Eq)]
#[serde(rename_all = "kebab-case")]
pub enum PolyhedronModelName {
    Volume,
    Depth,
}

/// Per material pair overrides of the default contact.
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PairSection {
    pub materials: [String; 2],
    pub normal: Option<NormalSection>,
    pub restitution: Option<f64>,
    pub tangential: Option<TangentialSection>,
    pub cohesion: Option<CohesionSection>,
    pub rolling_friction: Option<f64>,
}

#[derive(Clone, Debug, Deserialize, PartialEq)]
#[serde(tag = "model", rename_all = "kebab-case", deny_unknown_fields)]
pub enum NormalSection {
    Linear { stiffness: f64 },
    Hertz {},
}

#[derive(Clone, Debug, Default, Deserialize, PartialEq)]
#[serde(tag = "model", rename_all = "kebab-case", deny_unknown_fields)]
pub enum TangentialSection {
    #[default]
    None,
    ViscousCoulomb {
        friction: f64,
        /// k_f in N/m (c_t = k_f t_col).
        stiffness: Option<f64>,
        /// c_t in N s/m.
        viscous: Option<f64>,
    },
    StickLimited {
        friction: f64,
    },
    DynamicOnly {
        friction: f64,
    },
    /// Tangential spring with history: Cundall–Strack with a linear normal law,
    /// Mindlin (k_t from G*) with Hertz unless a stiffness is given.
    History {
        friction: f64,
        /// k_t in N/m (linear default: 2/7 k_n).
        stiffness: Option<f64>,
        /// η_t in N s/m (linear default: the normal damping η_n of the pair).
        damping: Option<f64>,
    },
}

#[derive(Clone, Debug, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct CohesionSection {
    /// k_c in N/m; or give `stickiness_number` instead.
    pub stiffness: Option<f64>,
    /// Target Sy: k_c is derived from it (restitution, L_e = d_e − d_b, m*, collision speed).
    pub stickiness_number: Option<f64>,
    /// Collision speed of Sy in m/s (default: the Taylor–Green flow's mean speed u_0).
    pub collision_speed: Option<f64>,
}
