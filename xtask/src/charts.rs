//! `cargo xtask charts` writes three charts as SVG, each with its data as CSV
//! beside it, into docs/charts/:
//!
//! - `speed_vs_accuracy`: error against cost (particle-steps) per verification case,
//!   with the Pareto front;
//! - `stability_map`: stable/unstable by Δt/t_col for integrator × contact model on a
//!   resting contact, with the theoretical limits;
//! - `convergence`: error against Δt per integrator with the fitted order;
//! - the friction charts of `friction_charts.rs` (`cargo xtask charts friction` writes only those).

use crate::svg::{self, Anchor, LogAxis, Shape, Style, Svg};
use std::fmt::Write as _;
use std::path::{Path, PathBuf};
use std::time::Instant;
use tumble::Simulation;
use tumble::verify::{self as tv, ErrorRow, fitted_order};
use tumble_integrate::Integrator;

const WIDTH: f64 = 1200.0;

pub fn run(args: &[String]) -> i32 {
    let start = Instant::now();
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("..").join("docs").join("charts");
    if let Err(e) = std::fs::create_dir_all(&dir) {
        eprintln!("cannot create {}: {e}", dir.display());
        return 1;
    }
    let friction = crate::friction_charts::charts();
    eprintln!("friction studies: {:.1} s", start.elapsed().as_secs_f64());
    if let Err(code) = write_charts(&dir, friction) {
        return code;
    }
    if args.first().map(String::as_str) == Some("friction") {
        return 0;
    }
    let rows = crate::verify::all_rows();
    let series = series(&rows);
    eprintln!("verification cases: {:.1} s", start.elapsed().as_secs_f64());
    let t = Instant::now();
    let stability = stability_runs();
    eprintln!("stability runs: {:.1} s", t.elapsed().as_secs_f64());
    let outputs =
        [("speed_vs_accuracy", speed_vs_accuracy(&series)), ("convergence", convergence(&series)), ("stability_map", stability_map(&stability))]
            .map(|(name, (svg, csv))| (name, svg, csv));
    if let Err(code) = write_charts(&dir, outputs.into()) {
        return code;
    }
    eprintln!("total: {:.1} s", start.elapsed().as_secs_f64());
    0
}

/// Writes each chart's SVG and CSV (and a PNG when it can) into `dir`.
fn write_charts(dir: &Path, charts: Vec<(&str, String, String)>) -> Result<(), i32> {
    for (name, svg, csv) in charts {
        for (ext, text) in [("svg", svg), ("csv", csv)] {
            let path: PathBuf = dir.join(format!("{name}.{ext}"));
            if let Err(e) = std::fs::write(&path, text) {
                eprintln!("cannot write {}: {e}", path.display());
                return Err(1);
            }
            println!("wrote docs/charts/{name}.{ext}");
        }
        png(dir, name);
    }
    Ok(())
}

/// A PNG beside the SVG, for readers who would rather look than read, when
/// `rsvg-convert` (Debian: librsvg2-bin) is installed; the SVG is the source.
fn png(dir: &Path, name: &str) {
    let (svg, png) = (dir.join(format!("{name}.svg")), dir.join(format!("{name}.png")));
    match std::process::Command::new("rsvg-convert").args(["-w", "1200", "-o"]).arg(&png).arg(&svg).status() {
        Ok(s) if s.success() => println!("wrote docs/charts/{name}.png"),
        _ => eprintln!("skipping {name}.png: rsvg-convert (apt-get install librsvg2-bin) is not available"),
    }
}

/// Colour, marker and dash per integrator (Okabe–Ito colours; the implicit-drag
/// variants are dashed: without a fluid implicit-drag-symplectic is symplectic Euler).
fn style(i: Integrator) -> Style {
    match i {
        Integrator::Euler => Style { colour: "#D55E00", shape: Shape::Circle, dashed: false },
        Integrator::SymplecticEuler => Style { colour: "#0072B2", shape: Shape::Square, dashed: false },
        Integrator::Verlet => Style { colour: "#009E73", shape: Shape::Triangle, dashed: false },
        Integrator::ImplicitDrag => Style { colour: "#E69F00", shape: Shape::Diamond, dashed: true },
        Integrator::ImplicitDragSymplectic => Style { colour: "#CC79A7", shape: Shape::TriangleDown, dashed: true },
    }
}

fn integrator_legend() -> Vec<(Style, String)> {
    Integrator::ALL.iter().map(|&i| (style(i), i.name().to_string())).collect()
}

/// The rows of one (case, measure), all integrators and steps.
struct Series<'a> {
    case: &'static str,
    measure: &'static str,
    rows: Vec<&'a ErrorRow>,
}

impl Series<'_> {
    fn title(&self) -> String {
        format!("{} \u{2014} {}", self.case, self.measure)
    }

    /// Rows of one integrator, coarsest Δt first.
    fn of(&self, i: Integrator) -> Vec<&ErrorRow> {
        let mut v: Vec<&ErrorRow> = self.rows.iter().copied().filter(|r| r.integrator == i).collect();
        v.sort_by(|a, b| a.steps_per_scale.total_cmp(&b.steps_per_scale));
        v
    }
}

fn series(rows: &[ErrorRow]) -> Vec<Series<'_>> {
    let mut out: Vec<Series> = Vec::new();
    for r in rows {
        match out.iter_mut().find(|s| s.case == r.case && s.measure == r.measure) {
            Some(s) => s.rows.push(r),
            None => out.push(Series { case: r.case, measure: r.measure, rows: vec![r] }),
        }
    }
    out
}

/// Panel origins of a grid of `cols` columns below `top`.
fn panel_origin(k: usize, cols: usize, w: f64, h: f64, top: f64) -> (f64, f64) {
    ((k % cols) as f64 * w, top + (k / cols) as f64 * h)
}

fn header(svg: &mut Svg, title: &str, subtitles: &[&str]) {
    svg.bold(WIDTH / 2.0, 28.0, 19.0, Anchor::Middle, title);
    for (k, s) in subtitles.iter().enumerate() {
        svg.text(WIDTH / 2.0, 49.0 + 16.0 * k as f64, 12.0, Anchor::Middle, "#444444", s);
    }
}

/// Indices of the Pareto front of (cost, error): each point has a lower error than
/// every point of lower or equal cost before it. Errors ≤ 0 are left out.
fn pareto(points: &[(f64, f64)]) -> Vec<usize> {
    let mut idx: Vec<usize> = (0..points.len()).filter(|&k| points[k].1 > 0.0).collect();
    idx.sort_by(|&a, &b| points[a].0.total_cmp(&points[b].0).then(points[a].1.total_cmp(&points[b].1)));
    let mut best = f64::INFINITY;
    let mut front = Vec::new();
    for k in idx {
        if points[k].1 < best {
            best = points[k].1;
            front.push(k);
        }
    }
    front
}

/// Chart 1: |error| against particle-steps, one panel per case/measure.
fn speed_vs_accuracy(series: &[Series]) -> (String, String) {
    let (cols, pw, ph, top) = (3usize, WIDTH / 3.0, 300.0, 88.0);
    let panels = series.len() + 1;
    let height = top + panels.div_ceil(cols) as f64 * ph + 10.0;
    let mut svg = Svg::new(WIDTH, height);
    header(
        &mut svg,
        "Speed vs accuracy: error against cost, per verification case",
        &[
            "Δt = T/8 … T/256 (T = the case's time scale). Cost = particle-steps (equal for all integrators at one Δt; markers are dodged sideways).",
            "Grey line and black rings: Pareto front (lowest error at no more cost). |error| against the closed form; zero errors not drawn.",
        ],
    );
    let mut csv = format!("{},pareto\n", ErrorRow::CSV_HEADER);
    for (k, s) in series.iter().enumerate() {
        let (x0, y0) = panel_origin(k, cols, pw, ph, top);
        let (left, right, ptop, bottom) = (x0 + 68.0, x0 + pw - 14.0, y0 + 30.0, y0 + ph - 50.0);
        let x = LogAxis::covering(s.rows.iter().map(|r| r.particle_steps as f64), left, right);
        let y = LogAxis::covering(s.rows.iter().map(|r| r.error.abs()), bottom, ptop);
        let x = LogAxis { lo: x.lo - 0.15, hi: x.hi + 0.15, ..x };
        svg.bold(0.5 * (left + right), y0 + 20.0, 12.5, Anchor::Middle, &s.title());
        svg::log_log_frame(&mut svg, x, y, "particle-steps", "|error|");
        let points: Vec<(f64, f64)> = s.rows.iter().map(|r| (r.particle_steps as f64, r.error.abs())).collect();
        let front = pareto(&points);
        let dodge = |r: &ErrorRow| {
            let k = Integrator::ALL.iter().position(|&i| i == r.integrator).unwrap_or(0) as f64;
            (k - 2.0) * 5.0
        };
        let at = |r: &ErrorRow| (x.px(r.particle_steps as f64) + dodge(r), y.px(r.error.abs()));
        let line: Vec<(f64, f64)> = front.iter().map(|&k| at(s.rows[k])).collect();
        svg.polyline(&line, "#333333", 5.0, None, 0.25);
        for r in s.rows.iter().filter(|r| r.error != 0.0) {
            let (px, py) = at(r);
            let st = style(r.integrator);
            svg.marker(st.shape, px, py, 7.5, st.colour, false);
        }
        for &k in &front {
            let (px, py) = at(s.rows[k]);
            svg.marker(Shape::Circle, px, py, 14.0, "#000000", true);
        }
        for (k, r) in s.rows.iter().enumerate() {
            let _ = writeln!(csv, "{},{}", r.csv(), front.contains(&k));
        }
    }
    // The free grid cell holds the legend.
    let (x0, y0) = panel_origin(series.len(), cols, pw, ph, top);
    let entries = integrator_legend();
    svg.legend(x0 + 70.0, y0 + 40.0, &entries, false, 13.0);
    let ly = y0 + 40.0 + 19.0 * entries.len() as f64 + 30.0;
    svg.polyline(&[(x0 + 72.0, ly), (x0 + 104.0, ly)], "#333333", 5.0, None, 0.25);
    svg.marker(Shape::Circle, x0 + 88.0, ly, 14.0, "#000000", true);
    svg.text(x0 + 112.0, ly + 4.5, 13.0, Anchor::Start, "#222222", "Pareto front (per case)");
    (svg.finish(), csv)
}

/// Chart 3: |error| against Δt/T per integrator with the fitted order of the four finest steps.
fn convergence(series: &[Series]) -> (String, String) {
    let (cols, pw, ph, top) = (2usize, WIDTH / 2.0, 280.0, 88.0);
    let panels = series.len() + 1;
    let height = top + panels.div_ceil(cols) as f64 * ph + 10.0;
    let mut svg = Svg::new(WIDTH, height);
    header(
        &mut svg,
        "Convergence: error against time step, per verification case",
        &[
            "|error| against the closed form at Δt = T/8 … T/256. Legend: p = least-squares slope of log error against log Δt over the four finest steps.",
            "implicit-drag variants are dashed. Without a fluid implicit-drag-symplectic equals symplectic-euler; implicit-drag updates x with the mean velocity. Zero errors not drawn.",
        ],
    );
    let mut csv = String::from("case,measure,integrator,steps_per_scale,dt_over_T,dt,error,fitted_order_4_finest\n");
    for (k, s) in series.iter().enumerate() {
        let (x0, y0) = panel_origin(k, cols, pw, ph, top);
        let (left, right, ptop, bottom) = (x0 + 68.0, x0 + pw - 250.0, y0 + 30.0, y0 + ph - 50.0);
        let x = LogAxis::range(1.0 / 400.0, 1.0 / 6.0, left, right);
        let y = LogAxis::covering(s.rows.iter().map(|r| r.error.abs()), bottom, ptop);
        svg.bold(x0 + 0.5 * pw, y0 + 20.0, 12.5, Anchor::Middle, &s.title());
        svg::log_log_frame(&mut svg, x, y, "Δt / T", "|error|");
        let mut entries = Vec::new();
        for &i in &Integrator::ALL {
            let rows = s.of(i);
            if rows.is_empty() {
                continue;
            }
            let finest = &rows[rows.len().saturating_sub(4)..];
            let order = fitted_order(finest);
            let st = style(i);
            let pts: Vec<(f64, f64)> = rows.iter().filter(|r| r.error != 0.0).map(|r| (x.px(1.0 / r.steps_per_scale), y.px(r.error.abs()))).collect();
            svg.polyline(&pts, st.colour, 2.0, st.dashed.then_some("6,4"), 0.9);
            for &(px, py) in &pts {
                svg.marker(st.shape, px, py, 7.0, st.colour, false);
            }
            let p = if order.is_finite() { format!("{order:.2}") } else { "n/a".to_string() };
            entries.push((st, format!("{}  p = {p}", i.name())));
            for r in &rows {
                let _ = writeln!(
                    csv,
                    "{},{},{},{},{},{},{},{}",
                    r.case,
                    r.measure,
                    i.name(),
                    r.steps_per_scale,
                    1.0 / r.steps_per_scale,
                    r.dt,
                    r.error,
                    order
                );
            }
        }
        svg.legend(right + 12.0, ptop + 4.0, &entries, true, 11.0);
    }
    let (x0, y0) = panel_origin(series.len(), cols, pw, ph, top);
    svg.legend(x0 + 80.0, y0 + 40.0, &integrator_legend(), true, 13.0);
    (svg.finish(), csv)
}

// ---------------------------------------------------------------------------
// Stability map

/// Δt/t_col values: 17 log-spaced from 0.03 to 3.
fn ratios() -> Vec<f64> {
    (0..17).map(|k| 0.03 * 10f64.powf(k as f64 / 8.0)).collect()
}

const CONTACT_DURATIONS: f64 = 200.0;
const DIAMETER: f64 = 0.1;
const DENSITY: f64 = 10.0;
const GRAVITY: f64 = 9.81;
const HERTZ_E: f64 = 1.0e7;
const HERTZ_NU: f64 = 0.3;
/// Energy growth (in m g d) above which a run that passes the criterion is drawn as drifting.
const DRIFT: f64 = 1.0e-3;
const CRITERION: &str = "unstable if at any step within 200 t_col: a non-finite state, the particle leaving the domain, max overlap/r > 0.5, or (E_mech + E_dissipated) − E_0 > 0.1·(½ m v0² + m g d) = 0.1 m g d (v0 = 0)";

struct Model {
    label: &'static str,
    text: String,
    /// Theoretical limits in seconds, with their names.
    limits: Vec<(String, f64)>,
    t_col: f64,
}

struct Probe {
    ratio: f64,
    dt: f64,
    stable: bool,
    reason: &'static str,
    steps: u64,
    max_growth: f64,
    max_overlap: f64,
}

fn sphere_mass() -> f64 {
    DENSITY * std::f64::consts::PI / 6.0 * DIAMETER.powi(3)
}

fn replace_checked(text: &str, from: &str, to: &str) -> String {
    assert!(text.contains(from), "verification scene no longer contains {from:?}");
    text.replace(from, to)
}

/// The sliding scene turned into a sphere released at rest, just touching the floor,
/// with friction off: a resting contact that oscillates about m g / k.
fn models() -> Vec<Model> {
    let base = replace_checked(tv::SLIDING, "tangential = { model = \"viscous-coulomb\", friction = 0.6, stiffness = 1.0e5 }\n", "");
    let base = replace_checked(&base, "positions = [[0.0, 0.0, 0.04999948636]]", "positions = [[0.0, 0.0, 0.05]]");
    let base = replace_checked(&base, "velocity = [1.0, 0.0, 0.0]", "velocity = [0.0, 0.0, 0.0]");
    let undamped = replace_checked(&base, "restitution = 0.8", "restitution = 1.0");
    let hertz = replace_checked(&undamped, "normal = { model = \"linear\", stiffness = 1.0e5 }", "normal = { model = \"hertz\" }");
    let hertz = replace_checked(&hertz, "density = 10.0", &format!("density = 10.0\nyoungs_modulus = {HERTZ_E:e}\npoisson_ratio = {HERTZ_NU}"));
    let mut out = Vec::new();
    for (label, text) in [("linear, e = 1 (undamped)", undamped), ("linear, e = 0.8 (damped)", base), ("Hertz, e = 1", hertz)] {
        let plan = tv::scene_with(&text, Integrator::Verlet, None).plan;
        let t_col = plan.report.timescales.collision_time.expect("contact scene has a collision time");
        let limit = plan.report.timescales.stability_limit.expect("contact scene has a stability limit");
        let mut limits = Vec::new();
        if plan.report.timescales.rayleigh_time.is_some() {
            limits.push(("plan limit Δt_R (Rayleigh)".to_string(), limit));
            // Linearised at the resting overlap: k = 2 E* √(R δ_eq), 4/3 E* √R δ_eq^1.5 = m g.
            let (m, r) = (sphere_mass(), 0.5 * DIAMETER);
            let e_star = HERTZ_E / (2.0 * (1.0 - HERTZ_NU * HERTZ_NU));
            let delta = (m * GRAVITY / (4.0 / 3.0 * e_star * r.sqrt())).powf(2.0 / 3.0);
            let k = 2.0 * e_star * (r * delta).sqrt();
            limits.push(("2/ω at rest (tangent stiffness)".to_string(), 2.0 / (k / m).sqrt()));
        } else {
            limits.push(("plan limit 2/ω".to_string(), limit));
        }
        out.push(Model { label, text, limits, t_col });
    }
    out
}

fn probe(model: &Model, integrator: Integrator, ratio: f64) -> Probe {
    let dt = ratio * model.t_col;
    let steps = (CONTACT_DURATIONS / ratio).ceil() as u64;
    let text = replace_checked(&model.text, "duration = 0.25", &format!("duration = {:e}", 1.01 * steps as f64 * dt));
    let mut sim = Simulation::new(tv::scene_with(&text, integrator, Some(dt)), 1);
    let o0 = sim.observables();
    let e0 = o0.mechanical_energy() + o0.dissipated_energy;
    let e_ref = sphere_mass() * GRAVITY * DIAMETER;
    let mut p = Probe { ratio, dt, stable: true, reason: "", steps: 0, max_growth: f64::NEG_INFINITY, max_overlap: 0.0 };
    for _ in 0..steps {
        sim.advance(1);
        p.steps += 1;
        if sim.particles() == 0 {
            (p.stable, p.reason) = (false, "left domain");
            break;
        }
        let o = sim.observables();
        let growth = (o.mechanical_energy() + o.dissipated_energy - e0) / e_ref;
        p.max_overlap = p.max_overlap.max(o.max_overlap_ratio);
        if !o.finite || !growth.is_finite() {
            (p.stable, p.reason) = (false, "non-finite");
            break;
        }
        p.max_growth = p.max_growth.max(growth);
        if o.max_overlap_ratio > 0.5 {
            (p.stable, p.reason) = (false, "overlap");
            break;
        }
        if growth > 0.1 {
            (p.stable, p.reason) = (false, "energy");
            break;
        }
    }
    p
}

/// Per contact model, per integrator, the probes at every Δt/t_col.
type StabilityRuns = Vec<(Model, Vec<(Integrator, Vec<Probe>)>)>;

fn stability_runs() -> StabilityRuns {
    models()
        .into_iter()
        .map(|m| {
            let rows = Integrator::ALL.iter().map(|&i| (i, ratios().into_iter().map(|r| probe(&m, i, r)).collect())).collect();
            (m, rows)
        })
        .collect()
}

/// Chart 2: stable/unstable by Δt/t_col, rows integrator × contact model.
fn stability_map(runs: &StabilityRuns) -> (String, String) {
    let (left, right, top, row_h, header_h, gap) = (250.0, WIDTH - 150.0, 108.0, 26.0, 30.0, 14.0);
    let rows: usize = runs.iter().map(|r| r.1.len()).sum();
    let band_bottom = top + runs.len() as f64 * (header_h + gap) + rows as f64 * row_h;
    let height = band_bottom + 110.0;
    let mut svg = Svg::new(WIDTH, height);
    header(
        &mut svg,
        "Stability map: resting contact, integrator × contact model",
        &[
            "Sphere d = 0.1 m, ρ = 10 kg/m³ released at rest touching a floor (gravity on, rotation and friction off), run for 200 t_col at each Δt.",
            "Unstable if at any step: non-finite state, particle leaves the domain, max overlap/r > 0.5, or E_mech + E_diss − E_0 > 0.1·(½ m v0² + m g d), v0 = 0.",
            "t_col = the plan's collision time (Hertz: at the plan's characteristic speed). Vertical lines: theoretical limits in units of t_col.",
        ],
    );
    let rs = ratios();
    let x = LogAxis::range(rs[0] / 1.15, rs[rs.len() - 1] * 1.15, left, right);
    let mut csv = format!(
        "# {CRITERION}\n# t_col from plan.report.timescales.collision_time; limit_over_tcol from plan.report.timescales.stability_limit (Hertz: Rayleigh time; also 2/omega at the resting overlap)\n# drawn as drifting: stable by the criterion but max_energy_growth_over_mgd > 1e-3\nmodel,integrator,dt_over_tcol,dt,t_col,limits_over_tcol,stable,reason,steps_run,max_energy_growth_over_mgd,max_overlap_ratio\n"
    );
    // Band backgrounds and labels first, axis grid over them, then markers.
    let mut y = top;
    let mut layout = Vec::new();
    for (model, integ) in runs {
        svg.bold(12.0, y + 20.0, 13.5, Anchor::Start, model.label);
        let band_top = y + header_h;
        for (k, (i, _)) in integ.iter().enumerate() {
            let cy = band_top + row_h * (k as f64 + 0.5);
            if k % 2 == 0 {
                svg.rect(left, cy - 0.5 * row_h, right - left, row_h, "#f4f4f4", "none");
            }
            let st = style(*i);
            svg.marker(st.shape, 30.0, cy, 8.0, st.colour, false);
            svg.text(42.0, cy + 4.5, 12.5, Anchor::Start, "#222222", i.name());
        }
        layout.push((band_top, band_top + row_h * integ.len() as f64));
        y = band_top + row_h * integ.len() as f64 + gap;
    }
    svg::log_x_axis(&mut svg, x, top + header_h - 4.0, band_bottom - gap + 4.0, "Δt / t_col");
    svg.text(right + 10.0, top + header_h - 8.0, 11.0, Anchor::Start, "#444444", "largest stable");
    for ((model, integ), (band_top, band_bottom)) in runs.iter().zip(&layout) {
        // The band's header line, over the grid.
        let limits: Vec<String> = model.limits.iter().map(|(n, l)| format!("{n} = {:.3} t_col", l / model.t_col)).collect();
        svg.rect(left, band_top - header_h, right - left, header_h - 3.0, "#ffffff", "none");
        svg.text(
            left,
            band_top - header_h + 20.0,
            11.5,
            Anchor::Start,
            "#444444",
            &format!("t_col = {:.3} ms;  {}", model.t_col * 1e3, limits.join(";  ")),
        );
        for (n, (name, limit)) in model.limits.iter().enumerate() {
            let r = limit / model.t_col;
            let dash = if n == 0 { None } else { Some("6,4") };
            if x.contains(r) {
                let px = x.px(r);
                svg.line((px, band_top - 3.0), (px, band_bottom + 3.0), "#222222", 2.0, dash);
            } else {
                svg.text(right - 4.0, band_bottom + 12.0, 10.0, Anchor::End, "#444444", &format!("{name} off scale"));
            }
        }
        for (k, (i, probes)) in integ.iter().enumerate() {
            let cy = band_top + row_h * (k as f64 + 0.5);
            for p in probes {
                let px = x.px(p.ratio);
                if p.stable && p.max_growth > DRIFT {
                    svg.marker(Shape::Circle, px, cy, 10.0, "#e08214", true);
                } else if p.stable {
                    svg.marker(Shape::Circle, px, cy, 11.0, "#1a9850", false);
                } else {
                    svg.marker(Shape::Cross, px, cy, 10.0, "#d73027", false);
                }
                let limits: Vec<String> = model.limits.iter().map(|(_, l)| format!("{:.4}", l / model.t_col)).collect();
                let _ = writeln!(
                    csv,
                    "\"{}\",{},{:.4},{:e},{:e},{},{},{},{},{:.3e},{:.3e}",
                    model.label,
                    i.name(),
                    p.ratio,
                    p.dt,
                    model.t_col,
                    limits.join(" "),
                    p.stable,
                    if p.stable { "-" } else { p.reason },
                    p.steps,
                    p.max_growth,
                    p.max_overlap
                );
            }
            // Largest Δt below which every probe was stable.
            let best = probes.iter().take_while(|p| p.stable).last().map_or("none".to_string(), |p| format!("{:.3}", p.ratio));
            svg.text(right + 10.0, cy + 4.0, 11.5, Anchor::Start, "#222222", &best);
        }
    }
    let ly = band_bottom + 56.0;
    svg.marker(Shape::Circle, left + 10.0, ly, 11.0, "#1a9850", false);
    svg.text(left + 22.0, ly + 4.0, 12.0, Anchor::Start, "#222222", "stable");
    svg.marker(Shape::Circle, left + 90.0, ly, 10.0, "#e08214", true);
    svg.text(
        left + 102.0,
        ly + 4.0,
        12.0,
        Anchor::Start,
        "#222222",
        "stable by the criterion, but energy grew > 0.001 m g d (≈ 400× the linear resting contact's energy)",
    );
    svg.marker(Shape::Cross, left + 10.0, ly + 24.0, 10.0, "#d73027", false);
    svg.text(left + 22.0, ly + 28.0, 12.0, Anchor::Start, "#222222", "unstable (reason in the CSV)");
    svg.line((left + 220.0, ly + 24.0), (left + 250.0, ly + 24.0), "#222222", 2.0, None);
    svg.text(left + 256.0, ly + 28.0, 12.0, Anchor::Start, "#222222", "plan stability limit");
    svg.line((left + 400.0, ly + 24.0), (left + 430.0, ly + 24.0), "#222222", 2.0, Some("6,4"));
    svg.text(left + 436.0, ly + 28.0, 12.0, Anchor::Start, "#222222", "Hertz: 2/ω linearised at the resting overlap");
    (svg.finish(), csv)
}
