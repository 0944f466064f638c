//! `cargo xtask coupling`: the particles in a fluid at full size, the table in docs/sph.md
//! ("The coupling in a run") and docs/charts/coupling.csv.
//!
//! - A glass sphere settling through a liquid at rest, in the Stokes regime (the shipped
//!   `scenes/settling_sphere.toml`, Re = 0.02) and near Re = 100 (`scenes/settling_sphere_water.toml`),
//!   each at two fluid spacings (h/d stated): its speed against its drag law's terminal velocity.
//! - A uniform suspension settling (`scenes/hindered_settling.toml`): the mean velocity of the
//!   spheres in its middle against the drag law's hindered settling velocity (and Richardson &
//!   Zaki's).
//! - Water driven through a fixed bed (`scenes/packed_bed_flow.toml`) by four body forces: the
//!   superficial velocity against Ergun's pressure drop.
//!
//! `--quick` runs the short cases only (the Stokes sphere and the bed); `--only NAME` the cases
//! named stokes, water, hindered or bed.

use std::fmt::Write as _;
use std::time::Instant;
use tumble::Simulation;

/// The liquid a sphere settles through, and its own size and density.
struct Settling {
    name: &'static str,
    scene: &'static str,
    /// (the scene's fluid spacing line, the one it is replaced by).
    spacing: (&'static str, &'static str),
    diameter: f64,
    density: f64,
    fluid_density: f64,
    viscosity: f64,
    /// The speed is averaged over the rows after this time, s.
    from: f64,
    duration: f64,
}

impl Settling {
    /// A glass sphere (2500 kg/m³) of `diameter` in a liquid of 1000 kg/m³ and `viscosity`.
    fn glass(
        name: &'static str,
        scene: &'static str,
        spacing: (&'static str, &'static str),
        diameter: f64,
        viscosity: f64,
        window: (f64, f64),
    ) -> Self {
        Settling { name, scene, spacing, diameter, density: 2500.0, fluid_density: 1000.0, viscosity, from: window.0, duration: window.1 }
    }
}

/// The terminal velocity of a sphere of `diameter` and `density` in a fluid of `rho` and `mu`
/// under Gidaspow's law at ε = 1 (Wen & Yu: Schiller & Naumann's C_D), and its Reynolds number,
/// by fixed-point iteration.
fn terminal_velocity(rho: f64, mu: f64, diameter: f64, density: f64) -> (f64, f64) {
    let d = diameter;
    let mut v: f64 = 1e-3;
    for _ in 0..500 {
        let re = rho * d * v / mu;
        v = (density - rho).abs() * 9.81 * d * d / (18.0 * mu * (1.0 + 0.15 * re.powf(0.687)));
    }
    (v, rho * d * v / mu)
}

fn compiled(scene: &str, replace: &[(&str, &str)]) -> Result<tumble::CompiledScene, String> {
    let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("..");
    let mut text = std::fs::read_to_string(root.join(scene)).map_err(|e| format!("{scene}: {e}"))?;
    for (from, to) in replace {
        if !text.contains(from) {
            return Err(format!("{scene} has no {from}"));
        }
        text = text.replace(from, to);
    }
    let parsed = tumble::parse_scene(&text).map_err(|e| format!("{scene}: {e}"))?;
    tumble::compile(&parsed).map_err(|e| format!("{scene}: {e}"))
}

/// One row of the table: case, h/d, Re, measured, expected, error %, wall seconds.
struct Row {
    case: String,
    h_over_d: f64,
    re: f64,
    measured: f64,
    expected: f64,
    unit: &'static str,
    seconds: f64,
}

fn settle(c: &Settling) -> Result<Row, String> {
    let scene = compiled(c.scene, &[(c.spacing.0, c.spacing.1)])?;
    let h = scene.plan.sph.as_ref().map(|s| s.settings.h).unwrap_or(f64::NAN);
    let mut sim = Simulation::new(scene, 2);
    let every = sim.plan().run.output_every;
    let start = Instant::now();
    let (mut sum, mut rows) = (0.0, 0);
    while sim.time() < c.duration - 1e-12 {
        sim.advance(every);
        if let Some(stop) = sim.stop() {
            return Err(format!("{}: stopped: {stop:?}", c.name));
        }
        if sim.time() > c.from {
            sum += sim.state().vel[0].z.abs();
            rows += 1;
        }
    }
    let (vt, re) = terminal_velocity(c.fluid_density, c.viscosity, c.diameter, c.density);
    Ok(Row {
        case: format!("{}, mean speed over {:.3}–{:.3} s", c.name, c.from, c.duration),
        h_over_d: h / c.diameter,
        re,
        measured: sum / rows.max(1) as f64,
        expected: vt,
        unit: "m/s",
        seconds: start.elapsed().as_secs_f64(),
    })
}

/// The hindered settling velocity of a suspension of fluid fraction `e` under Gidaspow's law
/// (Wen & Yu above ε = 0.8): in a closed column the fluid's pressure gradient carries the
/// mixture's weight, so each sphere's drag carries ε (ρ_p − ρ) g V, and the volume flux being
/// zero, the slip is v_s/ε.
fn hindered_velocity(rho: f64, mu: f64, d: f64, rho_p: f64, e: f64) -> f64 {
    let mut w: f64 = 1e-3;
    for _ in 0..500 {
        let re = rho * d * e * w / mu;
        let k = 0.75 * 24.0 * mu * (1.0 + 0.15 * re.powf(0.687)) / (rho * d * e) * rho * e.powf(-1.65) / d;
        w = e * (rho_p - rho) * 9.81 / k;
    }
    e * w
}

/// The shipped suspension: the mean downward velocity of the spheres between 25 and 45 mm
/// above the floor over 0.05–0.2 s, against the drag law's hindered settling velocity at the
/// lattice's fluid fraction.
fn hindered_settling() -> Result<Row, String> {
    let (rho, mu, d, rho_p) = (1000.0, 0.1, 0.003, 2500.0);
    let e = 1.0 - std::f64::consts::PI / 6.0 * (d / 0.0048f64).powi(3);
    let scene = compiled("scenes/hindered_settling.toml", &[])?;
    let h = scene.plan.sph.as_ref().map(|s| s.settings.h).unwrap_or(f64::NAN);
    let mut sim = Simulation::new(scene, 2);
    let every = sim.plan().run.output_every;
    let start = Instant::now();
    let (mut sum, mut rows) = (0.0, 0);
    while sim.time() < 0.2 - 1e-12 {
        sim.advance(every);
        if let Some(stop) = sim.stop() {
            return Err(format!("hindered settling: stopped: {stop:?}"));
        }
        if sim.time() > 0.05 {
            let s = sim.state();
            let band: Vec<usize> = (0..s.len()).filter(|&i| s.pos[i].z > 0.025 && s.pos[i].z < 0.045).collect();
            sum += -band.iter().map(|&i| s.vel[i].z).sum::<f64>() / band.len().max(1) as f64;
            rows += 1;
        }
    }
    let lone = terminal_velocity(rho, mu, d, rho_p);
    let expected = hindered_velocity(rho, mu, d, rho_p, e);
    // Richardson & Zaki's exponent at the lone sphere's Re (Garside & Al-Dibouni 1977).
    let rt = lone.1.powf(0.75);
    let n = (4.7 + 0.41 * rt) / (1.0 + 0.175 * rt);
    Ok(Row {
        case: format!(
            "hindered settling, ε = {e:.3}: mean speed over 0.05–0.2 s (lone sphere {:.4e} m/s; Richardson–Zaki n = {n:.2}: {:.4e} m/s)",
            lone.0,
            lone.0 * e.powf(n)
        ),
        h_over_d: h / d,
        re: lone.1,
        measured: sum / rows.max(1) as f64,
        expected,
        unit: "m/s",
        seconds: start.elapsed().as_secs_f64(),
    })
}

/// The packed bed driven by `g` for `duration`: Ergun's G at the superficial velocity and the
/// fraction the spheres read, against ρ g.
fn packed_bed(g: f64, expected_speed: f64, duration: f64) -> Result<Row, String> {
    let (rho, mu, d, side) = (1000.0, 1.0e-3, 0.002, 0.0264);
    let scene = compiled(
        "scenes/packed_bed_flow.toml",
        &[
            ("acceleration = [1.56, 0.0, 0.0]", &format!("acceleration = [{g}, 0.0, 0.0]")),
            ("expected_speed = 0.06", &format!("expected_speed = {expected_speed}")),
            ("duration = 0.2", &format!("duration = {duration}")),
        ],
    )?;
    let h = scene.plan.sph.as_ref().map(|s| s.settings.h).unwrap_or(f64::NAN);
    let mut sim = Simulation::new(scene, 2);
    let start = Instant::now();
    let steps = sim.plan().run.steps;
    sim.advance(steps);
    if let Some(stop) = sim.stop() {
        return Err(format!("packed bed at g = {g}: stopped: {stop:?}"));
    }
    let u = sim.fluid_phase().ok_or("no fluid")?.fluid().observables().momentum.x / (rho * side * side * side);
    let e = sim.coupler().ok_or("not coupled")?.sums().mean_fraction;
    let ergun = 150.0 * mu * (1.0 - e).powi(2) * u / (e.powi(3) * d * d) + 1.75 * rho * (1.0 - e) * u * u / (e.powi(3) * d);
    Ok(Row {
        case: format!("packed bed (ε = {e:.4}), g = {g} m/s²: Ergun's G at U = {u:.4e} m/s against ρ g"),
        h_over_d: h / d,
        re: rho * u * d / mu,
        measured: ergun,
        expected: rho * g,
        unit: "Pa/m",
        seconds: start.elapsed().as_secs_f64(),
    })
}

pub fn run(args: &[String]) -> i32 {
    let quick = args.iter().any(|a| a == "--quick");
    let stokes = |spacing: &'static str| {
        Settling::glass("3 mm glass in 1 Pa s (Stokes)", "scenes/settling_sphere.toml", ("spacing = 0.006", spacing), 0.003, 1.0, (0.00625, 0.03))
    };
    let water = |spacing: &'static str| {
        Settling::glass(
            "0.82 mm glass in water (Re ≈ 100)",
            "scenes/settling_sphere_water.toml",
            ("spacing = 0.001", spacing),
            0.00082,
            1.0e-3,
            (0.12, 0.15),
        )
    };
    type Case = Box<dyn Fn() -> Result<Row, String>>;
    let mut cases: Vec<(&str, Case)> =
        vec![("stokes", Box::new(move || settle(&stokes("spacing = 0.006")))), ("stokes", Box::new(move || settle(&stokes("spacing = 0.0045"))))];
    if !quick {
        cases.push(("water", Box::new(move || settle(&water("spacing = 0.001")))));
        cases.push(("water", Box::new(move || settle(&water("spacing = 0.0015")))));
        cases.push(("hindered", Box::new(hindered_settling)));
    }
    for (g, speed, duration) in [(0.083, 0.02, 0.45), (0.5, 0.03, 0.3), (2.0, 0.06, 0.2), (9.56, 0.12, 0.1)] {
        cases.push(("bed", Box::new(move || packed_bed(g, speed, duration))));
    }
    // `--only NAME`: just the cases named (stokes, water, hindered, bed); the CSV is left alone.
    let only = args.iter().position(|a| a == "--only").and_then(|k| args.get(k + 1)).cloned();
    cases.retain(|(name, _)| only.as_ref().is_none_or(|o| o == name));
    let mut table = String::from("| case | h/d | Re | measured | expected | error |\n|---|---|---|---|---|---|\n");
    let mut csv = String::from("case,h_over_d,re,measured,expected,unit,relative_error,wall_seconds\n");
    for (_, case) in cases {
        match case() {
            Ok(r) => {
                let error = r.measured / r.expected - 1.0;
                eprintln!(
                    "coupling: {} in {:.1} s: {:.5e} against {:.5e} {} ({:+.2} %)",
                    r.case,
                    r.seconds,
                    r.measured,
                    r.expected,
                    r.unit,
                    100.0 * error
                );
                let _ = writeln!(
                    table,
                    "| {} | {:.2} | {:.3} | {:.5e} {} | {:.5e} | {:+.2} % |",
                    r.case,
                    r.h_over_d,
                    r.re,
                    r.measured,
                    r.unit,
                    r.expected,
                    100.0 * error
                );
                let _ = writeln!(csv, "\"{}\",{},{},{},{},{},{},{:.1}", r.case, r.h_over_d, r.re, r.measured, r.expected, r.unit, error, r.seconds);
            }
            Err(e) => {
                eprintln!("coupling: {e}");
                return 1;
            }
        }
    }
    print!("{table}");
    let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("..");
    if !quick
        && only.is_none()
        && let Err(e) = std::fs::write(root.join("docs/charts/coupling.csv"), csv)
    {
        eprintln!("coupling: docs/charts/coupling.csv: {e}");
        return 1;
    }
    0
}
