//! `cargo xtask mill`, `cargo xtask hopper` and `cargo xtask drum`: the studies behind docs/mill.md,
//! docs/hopper.md and docs/drum.md, each writing its data (CSV, and a chart for mill and hopper)
//! into docs/charts/.
//!
//! - mill: scenes/ball_mill.toml at 30, 50 and 70 % of the critical speed and 20 and 30 %
//!   filling: drive power of shell, lifters and end plates (mean over the measuring window),
//!   the charge profile (toe, shoulder, centre of mass) and the torque-arm estimate
//!   P = M g r_com sin θ_com ω from the measured centre of mass;
//! - hopper: scenes/hopper.toml (spheres) and scenes/hopper_dodecahedra.toml (dodecahedra of
//!   equal volume) with orifice widths of 3 to 6 particle diameters: discharge rate through the
//!   outlet plane, with a Beverloo fit W = C ρ_b √g (L − k d)^{5/2} per shape;
//! - drum: scenes/drum_cubes.toml with its cubes and with spheres of equal volume: charge
//!   profile, drive power and the energy balance.

use crate::svg::{Anchor, LinearAxis, Shape, Style, Svg, YAxis, linear_frame};
use std::fmt::Write as _;
use std::path::Path;
use std::time::Instant;
use tumble::{FlowCounter, Simulation, compile, read_scene};

/// Worker threads per run: `TUMBLE_THREADS` or 2 (results are bit-identical for any count).
pub(crate) fn threads() -> usize {
    std::env::var("TUMBLE_THREADS").ok().and_then(|s| s.parse().ok()).filter(|&n| n > 0).unwrap_or(2)
}

/// The repository: `TUMBLE_ROOT` (to run a copied binary elsewhere) or the source tree.
pub(crate) fn root() -> std::path::PathBuf {
    match std::env::var_os("TUMBLE_ROOT") {
        Some(r) => r.into(),
        None => Path::new(env!("CARGO_MANIFEST_DIR")).join(".."),
    }
}

/// Runs `f` over `items` on `jobs` concurrent threads (each run has its own worker pool),
/// returning the results in the items' order.
pub(crate) fn run_all<T: Sync, R: Send>(items: &[T], jobs: usize, f: impl Fn(&T) -> R + Sync) -> Vec<R> {
    let next = std::sync::atomic::AtomicUsize::new(0);
    let out: Vec<std::sync::Mutex<Option<R>>> = items.iter().map(|_| std::sync::Mutex::new(None)).collect();
    std::thread::scope(|sc| {
        for _ in 0..jobs.max(1).min(items.len()) {
            sc.spawn(|| {
                loop {
                    let k = next.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
                    if k >= items.len() {
                        break;
                    }
                    let r = f(&items[k]);
                    *out[k].lock().unwrap() = Some(r);
                }
            });
        }
    });
    out.into_iter().map(|m| m.into_inner().unwrap().unwrap()).collect()
}

/// `--name value` from the arguments.
pub(crate) fn arg<T: std::str::FromStr>(args: &[String], name: &str) -> Option<T> {
    args.iter().position(|a| a == name).and_then(|k| args.get(k + 1)).and_then(|v| v.parse().ok())
}

pub(crate) fn write(name: &str, svg: String, csv: String) -> Result<(), i32> {
    let dir = root().join("docs").join("charts");
    for (ext, text) in [("svg", svg), ("csv", csv)] {
        let path = dir.join(format!("{name}.{ext}"));
        if let Err(e) = std::fs::write(&path, text) {
            eprintln!("cannot write {}: {e}", path.display());
            return Err(1);
        }
        eprintln!("wrote {}", path.display());
    }
    Ok(())
}

/// One mill run, averaged over the measuring window.
#[derive(Clone, Debug)]
struct MillRow {
    fill_label: &'static str,
    balls: usize,
    filling: f64,
    fraction: f64,
    rpm: f64,
    /// Drive power and charge profile over the measuring window.
    means: ChargeMeans,
    seconds: f64,
    particle_steps: f64,
}

impl MillRow {
    fn total(&self) -> f64 {
        self.means.total_power()
    }

    /// Bond's ball-mill power (Rowland's metric form, kW per tonne of balls, no pulp, D < 3.3 m so no
    /// ball-size term): 4.879 D^0.3 (3.2 − 3 J) φ_c (1 − 0.1 / 2^(9 − 10 φ_c)), times the ball mass.
    fn bond(&self) -> f64 {
        let per_tonne = 4.879 * D_MILL.powf(0.3) * (3.2 - 3.0 * self.filling) * self.fraction * (1.0 - 0.1 / 2f64.powf(9.0 - 10.0 * self.fraction));
        per_tonne * 1000.0 * self.balls as f64 * 7800.0 * std::f64::consts::PI / 6.0 * D_BALL.powi(3) / 1000.0
    }
}

/// The laboratory mill's diameter and ball size (scenes/ball_mill.toml, scenes/lab_mill/), m.
pub(crate) const D_MILL: f64 = 0.9;
pub(crate) const D_BALL: f64 = 0.05;

/// Critical speed N_c = 42.3 / √(D − d), rpm.
pub(crate) fn critical_rpm() -> f64 {
    42.3 / (D_MILL - D_BALL).sqrt()
}

/// Every rotating wall of `scene` turns at `rpm` (shell, lifters and end plates turn together).
pub(crate) fn set_rpm(scene: &mut tumble_scene::schema::Scene, rpm: f64) {
    for w in &mut scene.walls {
        if let Some(r) = w.motion.as_mut().and_then(|m| m.rotate.as_mut()) {
            r.rpm = rpm;
        }
    }
}
const SPIN_UP: f64 = 1.5;
const MEASURE: f64 = 2.5;

/// Means over the measuring window of a drum or mill run: the drive power per wall group (shell,
/// lifters, back, front) and the first drum's charge profile.
#[derive(Clone, Debug)]
pub(crate) struct ChargeMeans {
    pub power: [f64; 4],
    pub torque_arm: f64,
    pub com_angle: f64,
    pub com_radius: f64,
    pub toe: f64,
    pub shoulder: f64,
}

impl ChargeMeans {
    /// Drive power summed over every wall group.
    pub(crate) fn total_power(&self) -> f64 {
        self.power.iter().sum()
    }

    /// The columns the studies print, in order: the power of the shell, the lifters and both end
    /// plates, the torque-arm estimate, toe, shoulder, and the centre of mass's angle and radius.
    fn columns(&self) -> [f64; 8] {
        let p = self.power;
        [p[0], p[1], p[2] + p[3], self.torque_arm, self.toe, self.shoulder, self.com_angle, self.com_radius]
    }
}

/// Runs `sim` to its end in samples of 0.05 s, calling `each` after every sample; from `spin_up`
/// on, averages the charge profile over the samples and the wall groups' work over the time.
pub(crate) fn charge_means(sim: &mut Simulation, spin_up: f64, mut each: impl FnMut(&Simulation)) -> ChargeMeans {
    let every = (0.05 / sim.plan().model.dt).round() as u64;
    let (mut w0, mut t0) = (Vec::new(), 0.0);
    let mut samples = 0.0;
    let (mut arm, mut angle, mut radius, mut toe, mut shoulder) = (0.0, 0.0, 0.0, 0.0, 0.0);
    while sim.steps() < sim.plan().run.steps {
        sim.advance(every.min(sim.plan().run.steps - sim.steps()));
        each(sim);
        if sim.time() < spin_up - 1e-9 {
            continue;
        }
        if w0.is_empty() {
            (w0, t0) = (sim.wall_work(), sim.time());
            continue;
        }
        let p = sim.drum_profiles()[0];
        samples += 1.0;
        arm += p.torque_arm_power;
        angle += p.com_angle;
        radius += p.com_radius;
        toe += p.toe;
        shoulder += p.shoulder;
    }
    let work = sim.wall_work();
    let span = sim.time() - t0;
    ChargeMeans {
        power: [0, 1, 2, 3].map(|g| (work[g] - w0[g]) / span),
        torque_arm: arm / samples,
        com_angle: angle / samples,
        com_radius: radius / samples,
        toe: toe / samples,
        shoulder: shoulder / samples,
    }
}

fn mill_run(fill_label: &'static str, (nx, ny): (usize, usize), fraction: f64) -> MillRow {
    let mut scene = read_scene(&root().join("scenes/ball_mill.toml")).unwrap();
    let rpm = fraction * critical_rpm();
    set_rpm(&mut scene, rpm);
    let lattice = scene.particles[0].lattice.as_mut().unwrap();
    let s = lattice.spacing;
    lattice.min[0] = -0.5 * nx as f64 * s;
    lattice.max[0] = 0.5 * nx as f64 * s;
    lattice.min[1] = -0.5 * ny as f64 * s;
    lattice.max[1] = 0.5 * ny as f64 * s;
    scene.run.duration = SPIN_UP + MEASURE;
    scene.run.snapshot_interval = None;
    let compiled = compile(&scene).unwrap_or_else(|e| panic!("{e}"));
    let balls = compiled.particles.len();
    let v_mill = std::f64::consts::PI * 0.25 * D_MILL * D_MILL * 0.15;
    let filling = balls as f64 * std::f64::consts::PI / 6.0 * D_BALL.powi(3) / (0.6 * v_mill);
    let mut sim = Simulation::new(compiled, threads());
    let start = Instant::now();
    let means = charge_means(&mut sim, SPIN_UP, |_| {});
    let seconds = start.elapsed().as_secs_f64();
    MillRow { fill_label, balls, filling, fraction, rpm, means, seconds, particle_steps: balls as f64 * sim.steps() as f64 }
}

pub fn mill(_args: &[String]) -> i32 {
    let start = Instant::now();
    let mut rows = Vec::new();
    for (label, lattice) in [("20 %", (7, 8)), ("30 %", (9, 10))] {
        for fraction in [0.3, 0.5, 0.7] {
            let r = mill_run(label, lattice, fraction);
            let [shell, lifters, ends, arm, toe, shoulder, angle, radius] = r.means.columns();
            eprintln!(
                "fill {label} ({} balls), {:.0} % of critical ({:.2} rpm): {:.1} W (shell {shell:.1}, lifters {lifters:.1}, ends {ends:.1}), torque arm {arm:.1} W, toe {toe:.1}°, shoulder {shoulder:.1}°, COM {angle:.1}° at {radius:.3} m; {:.1} s",
                r.balls,
                100.0 * fraction,
                r.rpm,
                r.total(),
                r.seconds
            );
            rows.push(r);
        }
    }
    let mut csv = String::from(
        "# scenes/ball_mill.toml: D = 0.9 m, L = 0.15 m, 8 lifters 4 x 4 cm, 5 cm steel balls; spin-up 1.5 s, mean over the next 2.5 s\n\
         # filling J = n V_ball / (0.6 V_mill); angles in degrees from straight down, positive on the rising side\n\
         fill,balls,filling,fraction_of_critical,rpm,power_total_w,power_shell_w,power_lifters_w,power_ends_w,torque_arm_power_w,bond_power_w,toe_deg,shoulder_deg,com_angle_deg,com_radius_m,wall_seconds,particle_steps\n",
    );
    for r in &rows {
        let [shell, lifters, ends, arm, toe, shoulder, angle, radius] = r.means.columns();
        let _ = writeln!(
            csv,
            "{},{},{:.4},{},{:.4},{:.2},{shell:.2},{lifters:.2},{ends:.2},{arm:.2},{:.2},{toe:.2},{shoulder:.2},{angle:.2},{radius:.4},{:.2},{:.4e}",
            r.fill_label.trim_end_matches(" %"),
            r.balls,
            r.filling,
            r.fraction,
            r.rpm,
            r.total(),
            r.bond(),
            r.seconds,
            r.particle_steps
        );
    }
    print!("{csv}");
    eprintln!("total: {:.1} s", start.elapsed().as_secs_f64());
    match write("mill_power", mill_chart(&rows), csv) {
        Ok(()) => 0,
        Err(c) => c,
    }
}

const FILL_STYLES: [Style; 2] =
    [Style { colour: "#0072B2", shape: Shape::Circle, dashed: false }, Style { colour: "#D55E00", shape: Shape::Square, dashed: false }];

fn mill_chart(rows: &[MillRow]) -> String {
    let (w, h) = (1200.0, 640.0);
    let mut doc = Svg::titled(w, h, "Ball mill 0.9 m x 0.15 m, 8 lifters, 5 cm steel balls: power draw and charge profile");
    let x = |left: f64| LinearAxis { lo: 20.0, hi: 80.0, step: 10.0, p0: left, p1: left + 460.0 };
    let max_power = rows.iter().map(|r| r.total().max(r.means.torque_arm).max(r.bond())).fold(0.0, f64::max);
    let step = if max_power > 800.0 { 200.0 } else { 100.0 };
    let top = (max_power / step).ceil() * step + step;
    let yp = LinearAxis { lo: 0.0, hi: top, step, p0: 470.0, p1: 60.0 };
    linear_frame(&mut doc, x(90.0), YAxis::Linear(yp), "speed, % of critical (N_c = 42.3/√(D − d) = 45.9 rpm)", "drive power, W");
    let ya = LinearAxis { lo: -60.0, hi: 180.0, step: 30.0, p0: 470.0, p1: 60.0 };
    linear_frame(&mut doc, x(690.0), YAxis::Linear(ya), "speed, % of critical", "angle from straight down, degrees");
    for (k, label) in ["20 %", "30 %"].iter().enumerate() {
        let st = FILL_STYLES[k];
        let sel: Vec<&MillRow> = rows.iter().filter(|r| r.fill_label == *label).collect();
        let xs = |left: f64| sel.iter().map(move |r| x(left).px(100.0 * r.fraction)).collect::<Vec<_>>();
        let pts = |left: f64, ys: &dyn Fn(&MillRow) -> f64, axis: LinearAxis| {
            xs(left).into_iter().zip(sel.iter().map(|r| axis.px(ys(r)))).collect::<Vec<_>>()
        };
        let total = pts(90.0, &|r| r.total(), yp);
        doc.polyline(&total, st.colour, 2.0, None, 1.0);
        total.iter().for_each(|&(a, b)| doc.marker(st.shape, a, b, 9.0, st.colour, false));
        let arm = pts(90.0, &|r| r.means.torque_arm, yp);
        doc.polyline(&arm, st.colour, 1.5, Some("5,3"), 1.0);
        arm.iter().for_each(|&(a, b)| doc.marker(st.shape, a, b, 9.0, st.colour, true));
        let bond = pts(90.0, &|r| r.bond(), yp);
        doc.polyline(&bond, st.colour, 1.0, Some("1,3"), 0.9);
        bond.iter().for_each(|&(a, b)| doc.marker(Shape::Diamond, a, b, 8.0, st.colour, true));
        let lift = pts(90.0, &|r| r.means.power[1], yp);
        doc.polyline(&lift, st.colour, 1.0, Some("2,3"), 0.8);
        lift.iter().for_each(|&(a, b)| doc.marker(Shape::Cross, a, b, 7.0, st.colour, false));
        for (f, shape) in [
            (&(|r: &MillRow| r.means.shoulder) as &dyn Fn(&MillRow) -> f64, Shape::Triangle),
            (&|r: &MillRow| r.means.com_angle, st.shape),
            (&|r: &MillRow| r.means.toe, Shape::TriangleDown),
        ] {
            let p = pts(690.0, f, ya);
            doc.polyline(&p, st.colour, 1.5, None, 1.0);
            p.iter().for_each(|&(a, b)| doc.marker(shape, a, b, 9.0, st.colour, false));
        }
    }
    doc.legend(
        100.0,
        525.0,
        &[
            (FILL_STYLES[0], "20 % filling: measured Σ F·v_wall (all walls)".into()),
            (FILL_STYLES[1], "30 % filling: measured".into()),
            (Style { colour: "#555555", shape: Shape::Circle, dashed: true }, "hollow, dashed: M g r_com sin θ_com ω".into()),
            (Style { colour: "#555555", shape: Shape::Cross, dashed: true }, "crosses: lifters alone".into()),
            (Style { colour: "#555555", shape: Shape::Diamond, dashed: true }, "diamonds, dotted: Bond (Rowland), kW/t x ball mass".into()),
        ],
        true,
        11.0,
    );
    doc.legend(
        700.0,
        525.0,
        &[
            (Style { colour: "#555555", shape: Shape::Triangle, dashed: false }, "shoulder (95th percentile, shell layer)".into()),
            (Style { colour: "#555555", shape: Shape::Circle, dashed: false }, "centre of mass θ_com".into()),
            (Style { colour: "#555555", shape: Shape::TriangleDown, dashed: false }, "toe (5th percentile)".into()),
            (FILL_STYLES[0], "20 % filling".into()),
            (FILL_STYLES[1], "30 % filling".into()),
        ],
        false,
        11.0,
    );
    doc.finish()
}

/// Bulk density assumed for the Beverloo fit: random packing 0.6 of glass 2500 kg/m³ (both shapes).
const BULK: f64 = 0.6 * 2500.0;
/// Diameter of the spheres, and of the sphere of equal volume for the dodecahedra.
const D_SPHERE: f64 = 0.01;
/// The study as documented (docs/hopper.md): the lowest 6 lattice layers, 0.35 s, rate over 0.15–0.35 s.
const HOPPER_LAYERS: usize = 6;
const HOPPER_T: f64 = 0.35;
const HOPPER_FROM: f64 = 0.15;
const WIDTHS: [f64; 4] = [0.03, 0.04, 0.05, 0.06];

/// A particle shape of the hopper study and its scene.
struct HopperShape {
    label: &'static str,
    scene: &'static str,
    colour: &'static str,
    marker: Shape,
}

const HOPPER_SHAPES: [HopperShape; 2] = [
    HopperShape { label: "spheres", scene: "scenes/hopper.toml", colour: "#0072B2", marker: Shape::Circle },
    HopperShape { label: "dodecahedra", scene: "scenes/hopper_dodecahedra.toml", colour: "#D55E00", marker: Shape::Square },
];

/// One hopper run.
struct HopperRow {
    shape: usize,
    width: f64,
    rate: f64,
    particles: usize,
    seconds: f64,
    particle_steps: f64,
    /// (time, mass through the outlet plane) at every output interval.
    series: Vec<(f64, f64)>,
}

/// Beverloo fit W = C ρ_b √g (L − k d)^{5/2} through the runs that discharged: W^{2/5} is a straight
/// line in L. None with fewer than two such runs.
fn beverloo_fit(rows: &[&HopperRow]) -> Option<(f64, f64)> {
    let flowing: Vec<&&HopperRow> = rows.iter().filter(|r| r.rate > 0.0).collect();
    if flowing.len() < 2 {
        return None;
    }
    let xs: Vec<f64> = flowing.iter().map(|r| r.width).collect();
    let ys: Vec<f64> = flowing.iter().map(|r| r.rate.powf(0.4)).collect();
    let (mx, my) = (xs.iter().sum::<f64>() / xs.len() as f64, ys.iter().sum::<f64>() / ys.len() as f64);
    let slope = xs.iter().zip(&ys).map(|(x, y)| (x - mx) * (y - my)).sum::<f64>() / xs.iter().map(|x| (x - mx).powi(2)).sum::<f64>();
    let intercept = my - slope * mx;
    let k = -intercept / slope / D_SPHERE;
    let c = slope.powf(2.5) / (BULK * 9.81f64.sqrt());
    Some((c, k))
}

fn beverloo(fit: (f64, f64), l: f64) -> f64 {
    fit.0 * BULK * 9.81f64.sqrt() * (l - fit.1 * D_SPHERE).max(0.0).powf(2.5)
}

/// `cargo xtask hopper [--shape spheres|dodecahedra|both] [--layers N (6)] [--duration T (0.35)] [--from T0 (0.15)] [--jobs J (1)]`:
/// the hopper of scenes/hopper.toml (spheres) and scenes/hopper_dodecahedra.toml (dodecahedra of
/// the spheres' volume) over orifice widths of 3 to 6 d; `--layers` keeps the lowest N lattice
/// layers of every scene (the full scenes: `--layers 15 --duration 0.7 --from 0.25`), `--jobs`
/// runs that many simulations at once (each on `TUMBLE_THREADS` threads, default 2).
pub fn hopper(args: &[String]) -> i32 {
    let start = Instant::now();
    let which: String = arg(args, "--shape").unwrap_or_else(|| "both".into());
    let shapes: Vec<usize> = match which.as_str() {
        "both" => vec![0, 1],
        "spheres" => vec![0],
        "dodecahedra" => vec![1],
        other => {
            eprintln!("--shape must be spheres, dodecahedra or both, got {other}");
            return 2;
        }
    };
    let layers: Option<usize> = Some(arg(args, "--layers").unwrap_or(HOPPER_LAYERS));
    let duration: f64 = arg(args, "--duration").unwrap_or(HOPPER_T);
    let from: f64 = arg(args, "--from").unwrap_or(HOPPER_FROM);
    let jobs: usize = arg(args, "--jobs").unwrap_or(1);
    let runs: Vec<(usize, f64)> = shapes.iter().flat_map(|&s| WIDTHS.iter().map(move |&w| (s, w))).collect();
    let rows = run_all(&runs, jobs, |&(shape, width)| hopper_run(shape, width, layers, duration, from));
    let m = 2500.0 * std::f64::consts::PI / 6.0 * D_SPHERE.powi(3);
    let fits: Vec<Option<(f64, f64)>> =
        (0..HOPPER_SHAPES.len()).map(|s| beverloo_fit(&rows.iter().filter(|r| r.shape == s).collect::<Vec<_>>())).collect();
    let n_first = |s: usize| rows.iter().find(|r| r.shape == s).map_or(0, |r| r.particles);
    let mut csv = format!(
        "# 12 cm square flat-bottomed box, glass spheres of d = 1 cm (scenes/hopper.toml, {} particles) and glass dodecahedra of the same volume \
         (edge 4.088 mm, random orientations; scenes/hopper_dodecahedra.toml, {} particles){}; square orifice of width L; rate from the outlet plane \
         between t = {from} s and {duration} s\n",
        n_first(0),
        n_first(1),
        layers.map_or(String::new(), |n| format!(", the lowest {n} lattice layers of each scene"))
    );
    for (s, fit) in fits.iter().enumerate() {
        if let Some((c, k)) = fit {
            let _ = writeln!(
                csv,
                "# {}: Beverloo fit W = C rho_b sqrt(g) (L - k d)^(5/2), rho_b = {BULK} kg/m3, d = 1 cm: C = {c:.3}, k = {k:.2}",
                HOPPER_SHAPES[s].label
            );
        }
    }
    csv.push_str("shape,orifice_m,orifice_over_d,rate_kg_s,particles_per_s,beverloo_fit_kg_s,particles,wall_seconds,particle_steps\n");
    for r in &rows {
        let fit = fits[r.shape].map_or(f64::NAN, |f| beverloo(f, r.width));
        let _ = writeln!(
            csv,
            "{},{},{:.1},{:.4},{:.1},{:.4},{},{:.1},{:.4e}",
            HOPPER_SHAPES[r.shape].label,
            r.width,
            r.width / D_SPHERE,
            r.rate,
            r.rate / m,
            fit,
            r.particles,
            r.seconds,
            r.particle_steps
        );
    }
    print!("{csv}");
    eprintln!("total: {:.1} s", start.elapsed().as_secs_f64());
    match write("hopper_discharge", hopper_chart(&rows, &fits, duration, from), csv) {
        Ok(()) => 0,
        Err(c) => c,
    }
}

fn hopper_run(shape: usize, width: f64, layers: Option<usize>, duration: f64, from: f64) -> HopperRow {
    let spec = &HOPPER_SHAPES[shape];
    let mut scene = read_scene(&root().join(spec.scene)).unwrap();
    scene.walls[0].box_.as_mut().unwrap().floor_hole = Some(width);
    if let Some(n) = layers {
        let l = scene.particles[0].lattice.as_mut().unwrap();
        l.max[2] = l.min[2] + (n as f64 + 0.5) * l.spacing;
    }
    scene.run.duration = duration;
    scene.run.snapshot_interval = None;
    let compiled = compile(&scene).unwrap_or_else(|e| panic!("{e}"));
    let n = compiled.particles.len();
    let mut sim = Simulation::new(compiled, threads());
    let every = (0.02 / sim.plan().model.dt).round() as u64;
    let mut flow = FlowCounter::new(&sim);
    let t = Instant::now();
    let mut m0 = None;
    let mut series = Vec::new();
    while sim.steps() < sim.plan().run.steps {
        sim.advance(every.min(sim.plan().run.steps - sim.steps()));
        let (_, mass) = flow.update(&sim)[0];
        series.push((sim.time(), mass));
        if m0.is_none() && sim.time() >= from - 1e-9 {
            m0 = Some((sim.time(), mass));
        }
        let o = sim.observables();
        assert!(o.finite, "{} at L = {width}: non-finite state at t = {}", spec.label, sim.time());
    }
    let (t0, mass0) = m0.unwrap();
    let (t1, mass1) = *series.last().unwrap();
    let rate = (mass1 - mass0) / (t1 - t0);
    let seconds = t.elapsed().as_secs_f64();
    eprintln!(
        "{} orifice {width} m: {rate:.4} kg/s ({:.0} particles/s), {n} particles, {:.3e} particle-steps, {seconds:.1} s",
        spec.label,
        rate / (2500.0 * std::f64::consts::PI / 6.0 * D_SPHERE.powi(3)),
        sim.steps() as f64 * n as f64
    );
    HopperRow { shape, width, rate, particles: n, seconds, particle_steps: sim.steps() as f64 * n as f64, series }
}

fn hopper_chart(rows: &[HopperRow], fits: &[Option<(f64, f64)>], duration: f64, from: f64) -> String {
    let (w, h) = (1200.0, 540.0);
    let mut doc = Svg::titled(w, h, "Flat-bottomed hopper: 1 cm glass spheres and dodecahedra of equal volume through a square orifice");
    let top = (rows.iter().map(|r| r.rate).fold(0.0, f64::max) * 10.0).ceil() / 10.0 + 0.1;
    let xa = LinearAxis { lo: 2.0, hi: 7.0, step: 1.0, p0: 90.0, p1: 550.0 };
    let ya = LinearAxis { lo: 0.0, hi: top, step: 0.2, p0: 450.0, p1: 60.0 };
    linear_frame(&mut doc, xa, YAxis::Linear(ya), "orifice width L / d (d = 1 cm, the equal-volume sphere diameter)", "discharge rate, kg/s");
    let mut entries = Vec::new();
    for (s, spec) in HOPPER_SHAPES.iter().enumerate() {
        if !rows.iter().any(|r| r.shape == s) {
            continue;
        }
        entries.push((Style { colour: spec.colour, shape: spec.marker, dashed: false }, format!("{} (measured, outlet plane)", spec.label)));
        if let Some(fit) = fits[s] {
            let curve: Vec<(f64, f64)> = (0..=100)
                .map(|i| 2.0 + 5.0 * i as f64 / 100.0)
                .filter(|&l| beverloo(fit, l * D_SPHERE) <= top)
                .map(|l| (xa.px(l), ya.px(beverloo(fit, l * D_SPHERE))))
                .collect();
            doc.polyline(&curve, spec.colour, 1.5, Some("5,3"), 1.0);
            entries.push((
                Style { colour: spec.colour, shape: Shape::Cross, dashed: true },
                format!("Beverloo fit, C = {:.2}, k = {:.2}", fit.0, fit.1),
            ));
        }
        for r in rows.iter().filter(|r| r.shape == s) {
            doc.marker(spec.marker, xa.px(r.width / D_SPHERE), ya.px(r.rate), 10.0, spec.colour, false);
        }
    }
    doc.legend(100.0, 70.0, &entries, true, 11.0);
    // Right: cumulative discharged mass against time, solid for spheres, dashed for dodecahedra.
    let xt = LinearAxis { lo: 0.0, hi: duration, step: 0.1, p0: 690.0, p1: 1150.0 };
    let mmax = rows.iter().flat_map(|r| r.series.iter().map(|p| p.1)).fold(0.0, f64::max);
    let yt = LinearAxis { lo: 0.0, hi: ((mmax * 10.0).ceil() / 10.0).max(0.1), step: 0.1, p0: 450.0, p1: 60.0 };
    linear_frame(&mut doc, xt, YAxis::Linear(yt), "time, s", "mass through the outlet plane, kg");
    let colours = ["#009E73", "#0072B2", "#E69F00", "#D55E00"];
    let mut entries = Vec::new();
    for (k, (&width, colour)) in WIDTHS.iter().zip(colours).enumerate() {
        for r in rows.iter().filter(|r| r.width == width) {
            let pts: Vec<(f64, f64)> = r.series.iter().map(|&(t, m)| (xt.px(t), yt.px(m))).collect();
            doc.polyline(&pts, colour, 2.0, (r.shape == 1).then_some("6,3"), 1.0);
        }
        entries.push((Style { colour, shape: Shape::Circle, dashed: false }, format!("L = {:.0} d", WIDTHS[k] / D_SPHERE)));
    }
    entries.push((Style { colour: "#555555", shape: Shape::Circle, dashed: false }, "solid: spheres".into()));
    entries.push((Style { colour: "#555555", shape: Shape::Square, dashed: true }, "dashed: dodecahedra".into()));
    doc.legend(700.0, 70.0, &entries, true, 11.0);
    doc.text(
        w / 2.0,
        505.0,
        11.0,
        Anchor::Middle,
        "#555555",
        &format!("rate = mass through the outlet plane (3 cm below the floor) between t = {from} s and {duration} s, divided by the interval"),
    );
    doc.finish()
}

/// One run of the drum study (scenes/drum_cubes.toml, or the same drum with spheres of equal volume).
struct DrumRow {
    label: &'static str,
    particles: usize,
    rpm: f64,
    /// Drive power and charge profile over the measuring window.
    means: ChargeMeans,
    /// Largest overlap / radius over the samples.
    max_overlap: f64,
    /// Unbooked energy change (mechanical + dissipated − wall work − initial) at the end, over the wall work.
    energy_residual: f64,
    seconds: f64,
    particle_steps: f64,
}

const DRUM_SPIN_UP: f64 = 1.5;
/// Diameter of the sphere with the volume of an 8 mm cube: e (6/π)^{1/3}.
const DRUM_SPHERE: f64 = 0.008 * 1.240_700_981_798_799;

fn drum_run(label: &'static str, duration: f64) -> DrumRow {
    use tumble_scene::schema::{DiameterSpec, ShapeSection, SphereSection};
    let mut scene = read_scene(&root().join("scenes/drum_cubes.toml")).unwrap();
    if label == "spheres" {
        for g in &mut scene.particles {
            g.shape = ShapeSection::Sphere(SphereSection { diameter: DiameterSpec::Fixed(DRUM_SPHERE), effect_diameter: None, effect_ratio: None });
            g.orientation = None;
        }
    }
    scene.run.duration = duration;
    scene.run.snapshot_interval = None;
    let compiled = compile(&scene).unwrap_or_else(|e| panic!("{e}"));
    let n = compiled.particles.len();
    let rpm = compiled.plan.model.drums[0].omega * 60.0 / std::f64::consts::TAU;
    let mut sim = Simulation::new(compiled, threads());
    let start = Instant::now();
    let initial = sim.observables();
    let mut max_overlap = 0.0f64;
    let means = charge_means(&mut sim, DRUM_SPIN_UP, |sim| {
        let o = sim.observables();
        assert!(o.finite, "{label}: non-finite state at t = {}", sim.time());
        max_overlap = max_overlap.max(o.max_overlap_ratio);
    });
    let o = sim.observables();
    let e0 = initial.mechanical_energy() + initial.dissipated_energy - initial.wall_work;
    let energy_residual = (o.mechanical_energy() + o.dissipated_energy - o.wall_work - e0) / o.wall_work;
    DrumRow {
        label,
        particles: n,
        rpm,
        means,
        max_overlap,
        energy_residual,
        seconds: start.elapsed().as_secs_f64(),
        particle_steps: n as f64 * sim.steps() as f64,
    }
}

/// `cargo xtask drum [--duration T (2.5)] [--jobs J]`: scenes/drum_cubes.toml with its cubes and with spheres
/// of equal volume: charge profile and drive power averaged after a 1.5 s spin-up (docs/drum.md),
/// CSV in docs/charts/drum_cubes.csv.
pub fn drum(args: &[String]) -> i32 {
    let start = Instant::now();
    let duration: f64 = arg(args, "--duration").unwrap_or(2.5);
    let jobs: usize = arg(args, "--jobs").unwrap_or(1);
    let rows = run_all(&["cubes", "spheres"], jobs, |&label| drum_run(label, duration));
    let mut csv = format!(
        "# scenes/drum_cubes.toml: D = 0.2 m, 6 cm long, 8 lifters 8 x 8 mm, glass cubes of 8 mm edge or spheres of equal volume (d = {:.2} mm); \
         spin-up {DRUM_SPIN_UP} s, mean over the next {} s; angles in degrees from straight down, positive on the rising side\n\
         shape,particles,rpm,power_total_w,power_shell_w,power_lifters_w,power_ends_w,torque_arm_power_w,toe_deg,shoulder_deg,com_angle_deg,com_radius_m,\
         max_overlap_ratio,energy_residual,wall_seconds,particle_steps\n",
        1e3 * DRUM_SPHERE,
        duration - DRUM_SPIN_UP
    );
    for r in &rows {
        let [shell, lifters, ends, arm, toe, shoulder, angle, radius] = r.means.columns();
        let _ = writeln!(
            csv,
            "{},{},{:.2},{:.4},{shell:.4},{lifters:.4},{ends:.4},{arm:.4},{toe:.2},{shoulder:.2},{angle:.2},{radius:.4},{:.4},{:.2e},{:.1},{:.4e}",
            r.label,
            r.particles,
            r.rpm,
            r.means.total_power(),
            r.max_overlap,
            r.energy_residual,
            r.seconds,
            r.particle_steps
        );
    }
    print!("{csv}");
    eprintln!("total: {:.1} s", start.elapsed().as_secs_f64());
    let path = root().join("docs/charts/drum_cubes.csv");
    if let Err(e) = std::fs::write(&path, csv) {
        eprintln!("cannot write {}: {e}", path.display());
        return 1;
    }
    eprintln!("wrote {}", path.display());
    0
}
