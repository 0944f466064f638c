//! Scene builders shared by the integration tests.
#![allow(dead_code)]

use glam::DVec3;
use tumble::{CompiledScene, compile, parse_scene};

/// One particle of a generated scene.
#[derive(Clone, Debug)]
pub struct P {
    pub x: DVec3,
    pub v: DVec3,
    pub w: DVec3,
    pub d: f64,
    pub de: f64,
}

fn v3(v: DVec3) -> String {
    format!("[{:e}, {:e}, {:e}]", v.x, v.y, v.z)
}

/// A scene with one group per particle, friction, optional cohesion and rotation on.
pub fn scene_text(particles: &[P], cohesion: bool, periodic: bool, half_box: f64, extra_run: &str) -> String {
    let mut s = format!(
        "name = \"generated\"\n[run]\nduration = 1.0e-3\ndt = 1.0e-5\nintegrator = \"verlet\"\nrotation = \"on\"\n{extra_run}\n\
         [domain]\nmin = [{m}, {m}, {m}]\nmax = [{h}, {h}, {h}]\nperiodic = [{p}, {p}, {p}]\n\
         [[materials]]\nname = \"glass\"\ndensity = 2500.0\n\
         [contact]\nnormal = {{ model = \"linear\", stiffness = 1.0e4 }}\nrestitution = 0.7\n\
         tangential = {VISCOUS}\n",
        m = -half_box,
        h = half_box,
        p = periodic
    );
    if cohesion {
        s += "cohesion = { stiffness = 50.0 }\n";
    }
    for p in particles {
        s += &format!(
            "[[particles]]\nmaterial = \"glass\"\nshape = {{ sphere = {{ diameter = {:e}, effect_diameter = {:e} }} }}\npositions = [{}]\nvelocity = {}\nangular_velocity = {}\ntrack = true\n",
            p.d,
            p.de,
            v3(p.x),
            v3(p.v),
            v3(p.w)
        );
    }
    s
}

/// The tangential law [`scene_text`] writes, as a TOML inline table.
pub const VISCOUS: &str = "{ model = \"viscous-coulomb\", friction = 0.5, viscous = 2.0 }";
/// A tangential spring with history and rolling resistance, to swap in for [`VISCOUS`].
pub const HISTORY_ROLLING: &str = "{ model = \"history\", friction = 0.5 }\nrolling_friction = 0.05";

pub fn scene(particles: &[P], cohesion: bool, periodic: bool, half_box: f64, extra_run: &str) -> CompiledScene {
    scene_with_tangential(particles, cohesion, periodic, half_box, extra_run, VISCOUS)
}

/// [`scene`] with the tangential law (and what follows it in [contact]) replaced.
pub fn scene_with_tangential(particles: &[P], cohesion: bool, periodic: bool, half_box: f64, extra_run: &str, tangential: &str) -> CompiledScene {
    let text = scene_text(particles, cohesion, periodic, half_box, extra_run).replace(VISCOUS, tangential);
    let mut scene = parse_scene(&text).unwrap_or_else(|e| panic!("{e}\n{text}"));
    // Generated pairs may overlap on purpose.
    scene.run.allow_unstable_dt = true;
    compile(&scene).unwrap_or_else(|e| panic!("{e}"))
}
