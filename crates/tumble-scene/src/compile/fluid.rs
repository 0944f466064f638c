//! The [fluid] section: drag law and flow field, with the viscosity a target Stokes number
//! asks for, and the Taylor–Green scales the plan reports.

use super::{finite3, positive};
use crate::SceneError;
use crate::plan::{Drag, Fluid};
use crate::schema::*;
use crate::targets::{MovableMeans, TaylorGreenNumbers, taylor_green_mean_speed, viscosity_for_stokes_number};
use std::f64::consts::PI;
use tumble_contact::FlowField;

/// The fluid and, in a Taylor–Green flow, its scales and the particles' Stokes number.
pub(super) fn fluid(scene: &Scene, means: &MovableMeans) -> Result<(Option<Fluid>, Option<TaylorGreenNumbers>), SceneError> {
    let Some(fl) = &scene.fluid else { return Ok((None, None)) };
    // None: Stokes drag whose viscosity comes from the target Stokes number.
    let given_drag = match fl.drag {
        DragName::Stokes => match fl.viscosity {
            Some(ViscositySpec::PascalSeconds(mu)) => Some(Drag::Stokes { viscosity: positive("fluid.viscosity", mu)? }),
            Some(ViscositySpec::Target(_)) => None,
            None => {
                return Err(SceneError::field("fluid.viscosity", "Stokes drag needs the dynamic viscosity in Pa s or { stokes_number = Stk }"));
            }
        },
        DragName::Quadratic => Some(Drag::Quadratic {
            coefficient: positive(
                "fluid.coefficient",
                fl.coefficient.ok_or_else(|| SceneError::field("fluid.coefficient", "quadratic drag needs the coefficient α in kg/m"))?,
            )?,
        }),
    };
    let flow = match &fl.flow {
        FlowSection::Uniform(u) => FlowField::Uniform(finite3("fluid.flow.uniform", *u)?),
        FlowSection::TaylorGreen(tg) => FlowField::TaylorGreen {
            amplitude: finite3("fluid.flow.taylor_green.amplitude", V3([tg.amplitude, 0.0, 0.0]))?.x,
            frequency: positive("fluid.flow.taylor_green.frequency", tg.frequency)?,
        },
    };
    // u_0 and l_0 of the vortex.
    let scales = match flow {
        FlowField::TaylorGreen { amplitude, frequency } => Some((taylor_green_mean_speed(amplitude), PI / frequency)),
        _ => None,
    };
    let drag = match fl.viscosity {
        Some(ViscositySpec::Target(t)) => {
            let field = "fluid.viscosity.stokes_number";
            let stk = positive(field, t.stokes_number)?;
            let Some((u0, l0)) = scales else {
                return Err(SceneError::field(field, "needs flow = { taylor_green = { … } } (u_0 and l_0 come from the vortex)"));
            };
            if fl.drag != DragName::Stokes {
                return Err(SceneError::field(field, "needs drag = \"stokes\" (the Stokes number is defined by Stokes drag)"));
            }
            if u0 == 0.0 || means.none {
                return Err(SceneError::field(field, "needs a non-zero flow amplitude and movable particles"));
            }
            Drag::Stokes { viscosity: viscosity_for_stokes_number(stk, means.rho_d2, u0, l0) }
        }
        _ => given_drag.expect("only a target Stokes number leaves the drag open"),
    };
    let taylor_green = scales.map(|(u0, l0)| {
        let viscosity = match drag {
            Drag::Stokes { viscosity } => Some(viscosity),
            Drag::Quadratic { .. } => None,
        };
        let stokes_number = viscosity.filter(|_| !means.none).map(|mu| means.rho_d2 * u0 / (18.0 * mu * l0));
        TaylorGreenNumbers { mean_flow_speed: u0, vortex_size: l0, stokes_number, viscosity }
    });
    Ok((Some(Fluid { drag, flow }), taylor_green))
}
