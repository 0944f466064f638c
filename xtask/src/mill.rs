//! `cargo xtask mill` and `cargo xtask hopper`: the studies behind docs/mill.md and
//! docs/hopper.md, each writing a chart (SVG) and its data (CSV) into docs/charts/.
//!
//! - mill: scenes/ball_mill.toml at 30, 50 and 70 % of the critical speed and 20 and 30 %
//!   filling: drive power of shell, lifters and end plates (mean over the measuring window),
//!   the charge profile (toe, shoulder, centre of mass) and the torque-arm estimate
//!   P = M g r_com sin θ_com ω from the measured centre of mass;
//! - hopper: scenes/hopper.toml with orifice widths of 3 to 6 particle diameters: discharge
//!   rate through the outlet plane, with a Beverloo fit W = C ρ_b √g (L − k d)^{5/2}.

use crate::svg::{Anchor, LinearAxis, Shape, Style, Svg, YAxis, linear_frame};
use std::fmt::Write as _;
use std::path::Path;
use std::time::Instant;
use tumble::{FlowCounter, Simulation, compile, read_scene};
use tumble_scene::schema::MotionSection;

const THREADS: usize = 2;

fn root() -> std::path::PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("..")
}

fn write(name: &str, svg: String, csv: String) -> Result<(), i32> {
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
    /// Mean power per wall group: shell, lifters, back, front.
    power: [f64; 4],
    torque_arm: f64,
    com_angle: f64,
    com_radius: f64,
    toe: f64,
    shoulder: f64,
    seconds: f64,
    particle_steps: f64,
}

impl MillRow {
    fn total(&self) -> f64 {
        self.power.iter().sum()
    }

    /// Bond's ball-mill power (Rowland's metric form, kW per tonne of balls, no pulp, D < 3.3 m so no
    /// ball-size term): 4.879 D^0.3 (3.2 − 3 J) φ_c (1 − 0.1 / 2^(9 − 10 φ_c)), times the ball mass.
    fn bond(&self) -> f64 {
        let per_tonne = 4.879 * D_MILL.powf(0.3) * (3.2 - 3.0 * self.filling) * self.fraction * (1.0 - 0.1 / 2f64.powf(9.0 - 10.0 * self.fraction));
        per_tonne * 1000.0 * self.balls as f64 * 7800.0 * std::f64::consts::PI / 6.0 * D_BALL.powi(3) / 1000.0
    }
}

const D_MILL: f64 = 0.9;
const D_BALL: f64 = 0.05;
const SPIN_UP: f64 = 1.5;
const MEASURE: f64 = 2.5;

fn mill_run(fill_label: &'static str, (nx, ny): (usize, usize), fraction: f64) -> MillRow {
    let mut scene = read_scene(&root().join("scenes/ball_mill.toml")).unwrap();
    let critical = 42.3 / (D_MILL - D_BALL).sqrt();
    let rpm = fraction * critical;
    for w in &mut scene.walls {
        if let Some(MotionSection::Rotate(r)) = &mut w.motion {
            r.rpm = rpm;
        }
    }
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
    let mut sim = Simulation::new(compiled, THREADS);
    let dt = sim.plan().dt;
    let every = (0.05 / dt).round() as u64;
    let start = Instant::now();
    let (mut w0, mut t0) = (Vec::new(), 0.0);
    let mut samples = 0.0;
    let (mut arm, mut angle, mut radius, mut toe, mut shoulder) = (0.0, 0.0, 0.0, 0.0, 0.0);
    while sim.steps() < sim.plan().steps {
        sim.advance(every.min(sim.plan().steps - sim.steps()));
        if sim.time() < SPIN_UP - 1e-9 {
            continue;
        }
        if w0.is_empty() {
            (w0, t0) = (sim.cpu().wall_work().to_vec(), sim.time());
            continue;
        }
        let p = sim.cpu().drum_profiles()[0];
        samples += 1.0;
        arm += p.torque_arm_power;
        angle += p.com_angle;
        radius += p.com_radius;
        toe += p.toe;
        shoulder += p.shoulder;
    }
    let work = sim.cpu().wall_work();
    let span = sim.time() - t0;
    let power = [0, 1, 2, 3].map(|g| (work[g] - w0[g]) / span);
    let seconds = start.elapsed().as_secs_f64();
    MillRow {
        fill_label,
        balls,
        filling,
        fraction,
        rpm,
        power,
        torque_arm: arm / samples,
        com_angle: angle / samples,
        com_radius: radius / samples,
        toe: toe / samples,
        shoulder: shoulder / samples,
        seconds,
        particle_steps: balls as f64 * sim.steps() as f64,
    }
}

pub fn mill(_args: &[String]) -> i32 {
    let start = Instant::now();
    let mut rows = Vec::new();
    for (label, lattice) in [("20 %", (7, 8)), ("30 %", (9, 10))] {
        for fraction in [0.3, 0.5, 0.7] {
            let r = mill_run(label, lattice, fraction);
            eprintln!(
                "fill {label} ({} balls), {:.0} % of critical ({:.2} rpm): {:.1} W (shell {:.1}, lifters {:.1}, ends {:.1}), torque arm {:.1} W, toe {:.1}°, shoulder {:.1}°, COM {:.1}° at {:.3} m; {:.1} s",
                r.balls,
                100.0 * fraction,
                r.rpm,
                r.total(),
                r.power[0],
                r.power[1],
                r.power[2] + r.power[3],
                r.torque_arm,
                r.toe,
                r.shoulder,
                r.com_angle,
                r.com_radius,
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
        let _ = writeln!(
            csv,
            "{},{},{:.4},{},{:.4},{:.2},{:.2},{:.2},{:.2},{:.2},{:.2},{:.2},{:.2},{:.2},{:.4},{:.2},{:.4e}",
            r.fill_label.trim_end_matches(" %"),
            r.balls,
            r.filling,
            r.fraction,
            r.rpm,
            r.total(),
            r.power[0],
            r.power[1],
            r.power[2] + r.power[3],
            r.torque_arm,
            r.bond(),
            r.toe,
            r.shoulder,
            r.com_angle,
            r.com_radius,
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
    let mut doc = Svg::new(w, h);
    doc.bold(w / 2.0, 28.0, 16.0, Anchor::Middle, "Ball mill 0.9 m x 0.15 m, 8 lifters, 5 cm steel balls: power draw and charge profile");
    let x = |left: f64| LinearAxis { lo: 20.0, hi: 80.0, step: 10.0, p0: left, p1: left + 460.0 };
    let max_power = rows.iter().map(|r| r.total().max(r.torque_arm).max(r.bond())).fold(0.0, f64::max);
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
        let arm = pts(90.0, &|r| r.torque_arm, yp);
        doc.polyline(&arm, st.colour, 1.5, Some("5,3"), 1.0);
        arm.iter().for_each(|&(a, b)| doc.marker(st.shape, a, b, 9.0, st.colour, true));
        let bond = pts(90.0, &|r| r.bond(), yp);
        doc.polyline(&bond, st.colour, 1.0, Some("1,3"), 0.9);
        bond.iter().for_each(|&(a, b)| doc.marker(Shape::Diamond, a, b, 8.0, st.colour, true));
        let lift = pts(90.0, &|r| r.power[1], yp);
        doc.polyline(&lift, st.colour, 1.0, Some("2,3"), 0.8);
        lift.iter().for_each(|&(a, b)| doc.marker(Shape::Cross, a, b, 7.0, st.colour, false));
        for (f, shape) in [
            (&(|r: &MillRow| r.shoulder) as &dyn Fn(&MillRow) -> f64, Shape::Triangle),
            (&|r: &MillRow| r.com_angle, st.shape),
            (&|r: &MillRow| r.toe, Shape::TriangleDown),
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

/// Bulk density assumed for the Beverloo fit: random packing 0.6 of glass 2500 kg/m³.
const BULK: f64 = 0.6 * 2500.0;
const D_SPHERE: f64 = 0.01;
const HOPPER_T: f64 = 0.7;
const HOPPER_FROM: f64 = 0.25;

pub fn hopper(_args: &[String]) -> i32 {
    let start = Instant::now();
    let widths = [0.03, 0.04, 0.05, 0.06];
    let mut rows = Vec::new();
    for &width in &widths {
        let mut scene = read_scene(&root().join("scenes/hopper.toml")).unwrap();
        scene.walls[0].box_.as_mut().unwrap().floor_hole = Some(width);
        scene.run.duration = HOPPER_T;
        scene.run.snapshot_interval = None;
        let compiled = compile(&scene).unwrap_or_else(|e| panic!("{e}"));
        let n = compiled.particles.len();
        let mut sim = Simulation::new(compiled, THREADS);
        let every = (0.02 / sim.plan().dt).round() as u64;
        let mut flow = FlowCounter::new(&sim);
        let t = Instant::now();
        let mut m0 = None;
        let mut series = Vec::new();
        while sim.steps() < sim.plan().steps {
            sim.advance(every.min(sim.plan().steps - sim.steps()));
            let (_, mass) = flow.update(&sim)[0];
            series.push((sim.time(), mass));
            if m0.is_none() && sim.time() >= HOPPER_FROM - 1e-9 {
                m0 = Some((sim.time(), mass));
            }
        }
        let (t0, mass0) = m0.unwrap();
        let (t1, mass1) = *series.last().unwrap();
        let rate = (mass1 - mass0) / (t1 - t0);
        let secs = t.elapsed().as_secs_f64();
        eprintln!(
            "orifice {width} m: {rate:.4} kg/s ({:.0} spheres/s), {n} spheres, {secs:.1} s",
            rate / (2500.0 * std::f64::consts::PI / 6.0 * D_SPHERE.powi(3))
        );
        rows.push((width, rate, n, secs, sim.steps() as f64 * n as f64, series));
    }
    // Beverloo: W^{2/5} = (C ρ_b √g)^{2/5} (L − k d): a straight line in L.
    let xs: Vec<f64> = rows.iter().map(|r| r.0).collect();
    let ys: Vec<f64> = rows.iter().map(|r| r.1.powf(0.4)).collect();
    let (mx, my) = (xs.iter().sum::<f64>() / xs.len() as f64, ys.iter().sum::<f64>() / ys.len() as f64);
    let slope = xs.iter().zip(&ys).map(|(x, y)| (x - mx) * (y - my)).sum::<f64>() / xs.iter().map(|x| (x - mx).powi(2)).sum::<f64>();
    let intercept = my - slope * mx;
    let k = -intercept / slope / D_SPHERE;
    let c = slope.powf(2.5) / (BULK * 9.81f64.sqrt());
    let beverloo = |l: f64| c * BULK * 9.81f64.sqrt() * (l - k * D_SPHERE).max(0.0).powf(2.5);
    let mut csv = format!(
        "# scenes/hopper.toml: 12 cm square flat-bottomed box, 1 cm glass spheres, square orifice of width L; rate from the outlet plane between t = {HOPPER_FROM} s and {HOPPER_T} s\n\
         # Beverloo fit W = C rho_b sqrt(g) (L - k d)^(5/2) with rho_b = {BULK} kg/m3: C = {c:.3}, k = {k:.2}\n\
         orifice_m,orifice_over_d,rate_kg_s,spheres_per_s,beverloo_fit_kg_s,spheres,wall_seconds,particle_steps\n"
    );
    let m = 2500.0 * std::f64::consts::PI / 6.0 * D_SPHERE.powi(3);
    for r in &rows {
        let _ = writeln!(csv, "{},{:.1},{:.4},{:.1},{:.4},{},{:.1},{:.4e}", r.0, r.0 / D_SPHERE, r.1, r.1 / m, beverloo(r.0), r.2, r.3, r.4);
    }
    print!("{csv}");
    eprintln!("total: {:.1} s", start.elapsed().as_secs_f64());
    let (w, h) = (1200.0, 520.0);
    let mut doc = Svg::new(w, h);
    doc.bold(w / 2.0, 28.0, 16.0, Anchor::Middle, "Flat-bottomed hopper, 1 cm glass spheres: discharge through a square orifice");
    let top = (rows.iter().map(|r| r.1).fold(0.0, f64::max) * 10.0).ceil() / 10.0 + 0.1;
    let xa = LinearAxis { lo: 2.0, hi: 7.0, step: 1.0, p0: 90.0, p1: 550.0 };
    let ya = LinearAxis { lo: 0.0, hi: top, step: 0.2, p0: 450.0, p1: 60.0 };
    linear_frame(&mut doc, xa, YAxis::Linear(ya), "orifice width L / d", "discharge rate, kg/s");
    let fit: Vec<(f64, f64)> = (0..=100)
        .map(|i| 2.0 + 5.0 * i as f64 / 100.0)
        .filter(|&l| beverloo(l * D_SPHERE) <= top)
        .map(|l| (xa.px(l), ya.px(beverloo(l * D_SPHERE))))
        .collect();
    doc.polyline(&fit, "#555555", 1.5, Some("5,3"), 1.0);
    for r in &rows {
        doc.marker(Shape::Circle, xa.px(r.0 / D_SPHERE), ya.px(r.1), 10.0, "#0072B2", false);
    }
    doc.legend(
        100.0,
        70.0,
        &[
            (Style { colour: "#0072B2", shape: Shape::Circle, dashed: false }, "spheres (measured, outlet plane)".into()),
            (Style { colour: "#555555", shape: Shape::Cross, dashed: true }, format!("Beverloo fit, C = {c:.2}, k = {k:.2}")),
        ],
        true,
        11.0,
    );
    // Right: cumulative discharged mass against time.
    let xt = LinearAxis { lo: 0.0, hi: HOPPER_T, step: 0.1, p0: 690.0, p1: 1150.0 };
    let mmax = rows.iter().flat_map(|r| r.5.iter().map(|p| p.1)).fold(0.0, f64::max);
    let yt = LinearAxis { lo: 0.0, hi: (mmax * 10.0).ceil() / 10.0, step: 0.1, p0: 450.0, p1: 60.0 };
    linear_frame(&mut doc, xt, YAxis::Linear(yt), "time, s", "mass through the outlet plane, kg");
    let colours = ["#009E73", "#0072B2", "#E69F00", "#D55E00"];
    let mut entries = Vec::new();
    for (r, colour) in rows.iter().zip(colours) {
        let pts: Vec<(f64, f64)> = r.5.iter().map(|&(t, m)| (xt.px(t), yt.px(m))).collect();
        doc.polyline(&pts, colour, 2.0, None, 1.0);
        entries.push((Style { colour, shape: Shape::Circle, dashed: false }, format!("L = {:.0} d", r.0 / D_SPHERE)));
    }
    doc.legend(700.0, 70.0, &entries, true, 11.0);
    doc.text(
        w / 2.0,
        505.0,
        11.0,
        Anchor::Middle,
        "#555555",
        "Polyhedral particles (dodecahedra) come with the polyhedra branch; this chart has spheres only.",
    );
    match write("hopper_discharge", doc.finish(), csv) {
        Ok(()) => 0,
        Err(c) => c,
    }
}
