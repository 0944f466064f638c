//! `cargo xtask chute`: the periodic inclined chute of scenes/chute.toml run under the
//! instability monitor, its steady velocity profile v_x(z) against Bagnold's shape
//! v ∝ h^{3/2} − (h − z)^{3/2} (Silbert et al., Phys. Rev. E 64, 051302, 2001), and the mass
//! flux through its periodic flow plane against M ⟨v_x⟩ / L_x. Writes docs/charts/chute_profile.{svg,csv}.

use crate::svg::{LinearAxis, Shape, Style, Svg, YAxis, linear_frame};
use std::fmt::Write as _;
use std::path::Path;
use std::time::Instant;
use tumble::{FlowCounter, Monitor, Observables, Plan, Simulation, State, compile, read_scene};

/// Flowing-sphere diameter (mean), m.
const D: f64 = 0.001;
/// Profile bins, in diameters.
const BIN: f64 = 0.5;

fn root() -> std::path::PathBuf {
    match std::env::var_os("TUMBLE_ROOT") {
        Some(r) => r.into(),
        None => Path::new(env!("CARGO_MANIFEST_DIR")).join(".."),
    }
}

fn arg<T: std::str::FromStr>(args: &[String], name: &str) -> Option<T> {
    args.iter().position(|a| a == name).and_then(|k| args.get(k + 1)).and_then(|v| v.parse().ok())
}

/// The monitor's potential-energy range, as the run loop computes it: Σ m |g| × the extent along g.
fn potential_range(plan: &Plan, s: &State) -> f64 {
    let height = (plan.model.domain.extent() * plan.model.gravity.abs()).element_sum();
    (0..s.len()).filter(|&i| s.inv_mass[i] != 0.0).map(|i| s.mass[i] * height).sum()
}

/// Sums of the profile over the sampled states: per bin the samples' count and Σ v_x.
#[derive(Default)]
struct Profile {
    count: Vec<f64>,
    sum_vx: Vec<f64>,
    samples: usize,
}

impl Profile {
    fn add(&mut self, s: &State, base: f64) {
        for i in (0..s.len()).filter(|&i| s.inv_mass[i] != 0.0) {
            let k = ((s.pos[i].z - base) / (BIN * D)).floor();
            if k < 0.0 {
                continue;
            }
            let k = k as usize;
            if k >= self.count.len() {
                self.count.resize(k + 1, 0.0);
                self.sum_vx.resize(k + 1, 0.0);
            }
            self.count[k] += 1.0;
            self.sum_vx[k] += s.vel[i].x;
        }
        self.samples += 1;
    }
}

/// The measured profile and its fits.
struct Fit {
    /// (z above the base in d, number density over the bulk's, mean v_x m/s) per bin.
    rows: Vec<(f64, f64, f64)>,
    /// Flow height h above the base (where the density falls to half the bulk's), in d.
    h: f64,
    /// Bagnold amplitude A of v = A (h^{3/2} − (h − z)^{3/2}) (z, h in d), and the RMS deviation over v(h).
    bagnold: (f64, f64),
    /// A linear profile v = B z fitted the same way, for comparison.
    linear: (f64, f64),
}

fn bagnold_shape(h: f64, z: f64) -> f64 {
    h.powf(1.5) - (h - z).max(0.0).powf(1.5)
}

/// One-parameter least squares of v ≈ A f(z) over the bins inside the flow; returns A and
/// the RMS deviation over A f(h).
fn fit_shape(rows: &[(f64, f64, f64)], h: f64, f: impl Fn(f64) -> f64) -> (f64, f64) {
    let inside: Vec<&(f64, f64, f64)> = rows.iter().filter(|r| r.0 > 0.5 && r.0 < h).collect();
    let (num, den) = inside.iter().fold((0.0, 0.0), |(n, d), r| (n + f(r.0) * r.2, d + f(r.0) * f(r.0)));
    let a = num / den;
    let rms = (inside.iter().map(|r| (r.2 - a * f(r.0)).powi(2)).sum::<f64>() / inside.len() as f64).sqrt();
    (a, rms / (a * f(h)))
}

fn fit(p: &Profile) -> Fit {
    let rows: Vec<(f64, f64, f64)> =
        (0..p.count.len()).filter(|&k| p.count[k] > 0.0).map(|k| ((k as f64 + 0.5) * BIN, p.count[k], p.sum_vx[k] / p.count[k])).collect();
    // The bulk density: the median bin count of the lower half of the filled bins.
    let mut lower: Vec<f64> = rows.iter().take(rows.len() / 2).map(|r| r.1).collect();
    lower.sort_by(f64::total_cmp);
    let bulk = lower[lower.len() / 2];
    let rows: Vec<(f64, f64, f64)> = rows.into_iter().map(|(z, c, v)| (z, c / bulk, v)).collect();
    // The free surface: the first bin above the bulk where the density falls below half, interpolated.
    let top = rows.iter().rposition(|r| r.1 >= 0.5).unwrap_or(0);
    let h = match rows.get(top + 1) {
        Some(next) => rows[top].0 + BIN * (rows[top].1 - 0.5) / (rows[top].1 - next.1),
        None => rows[top].0 + 0.5 * BIN,
    };
    let bagnold = fit_shape(&rows, h, |z| bagnold_shape(h, z));
    let linear = fit_shape(&rows, h, |z| z);
    Fit { rows, h, bagnold, linear }
}

pub fn chute(args: &[String]) -> i32 {
    let duration: f64 = arg(args, "--duration").unwrap_or(1.0);
    let from: f64 = arg(args, "--from").unwrap_or(0.5);
    let threads: usize = arg(args, "--threads").unwrap_or(2);
    let path = root().join("scenes").join("chute.toml");
    let mut scene = read_scene(&path).unwrap_or_else(|e| panic!("{e}"));
    scene.run.duration = duration;
    let compiled = compile(&scene).unwrap_or_else(|e| panic!("{e}"));
    let n = compiled.particles.len();
    let mut sim = Simulation::new(compiled, threads);
    let plan = sim.plan().clone();
    let (dt, steps, l) = (plan.model.dt, plan.run.steps, plan.model.domain.extent());
    let theta = plan.model.gravity.x.atan2(-plan.model.gravity.z).to_degrees();
    let s0 = sim.state().into_owned();
    let base = {
        let fixed: Vec<f64> = (0..s0.len()).filter(|&i| s0.inv_mass[i] == 0.0).map(|i| s0.pos[i].z).collect();
        fixed.iter().sum::<f64>() / fixed.len() as f64
    };
    let flowing = (0..s0.len()).filter(|&i| s0.inv_mass[i] != 0.0).count();
    let monitor = Monitor::new(&plan, &sim.observables(), potential_range(&plan, &s0));
    let mut flow = FlowCounter::new(&sim);
    let sample_every = (0.01 / dt).round() as u64;
    let mut profile = Profile::default();
    let (mut window_mass, mut window_mass_vx, mut window_ke) = (0.0, 0.0, Vec::new());
    let mut mass_at_from = None;
    let start = Instant::now();
    while sim.steps() < steps {
        sim.advance(sample_every.min(steps - sim.steps()));
        let o: Observables = sim.observables();
        if let Err(e) = monitor.check(sim.steps(), &o) {
            eprintln!("the monitor stopped the chute: {e}");
            return 1;
        }
        let (_, mass) = flow.update(&sim)[0];
        if sim.time() >= from - 0.5 * dt {
            let s = sim.state();
            profile.add(&s, base);
            for i in (0..s.len()).filter(|&i| s.inv_mass[i] != 0.0) {
                window_mass += s.mass[i];
                window_mass_vx += s.mass[i] * s.vel[i].x;
            }
            window_ke.push((sim.time(), o.kinetic_energy));
            mass_at_from.get_or_insert((sim.time(), mass));
        }
        if sim.steps() % (10 * sample_every) == 0 {
            eprintln!("t = {:.2} s, KE = {:.3e} J, {:.0} s", sim.time(), o.kinetic_energy, start.elapsed().as_secs_f64());
        }
    }
    let wall = start.elapsed().as_secs_f64();
    let (t_from, m_from) = mass_at_from.expect("the window holds samples");
    let (_, m_end) = (sim.time(), flow.mass[0]);
    let flux = (m_end - m_from) / (sim.time() - t_from);
    let mean_vx = window_mass_vx / window_mass;
    let movable_mass: f64 = (0..s0.len()).filter(|&i| s0.inv_mass[i] != 0.0).map(|i| s0.mass[i]).sum();
    let flux_from_velocity = movable_mass * mean_vx / l.x;
    let half = window_ke.len() / 2;
    let mean = |v: &[(f64, f64)]| v.iter().map(|p| p.1).sum::<f64>() / v.len() as f64;
    let (ke_first, ke_second) = (mean(&window_ke[..half]), mean(&window_ke[half..]));
    let f = fit(&profile);

    let mut csv = format!(
        "# scenes/chute.toml: {flowing} glass spheres (d = 0.95-1.05 mm) on a rough base of {} fixed ones, theta = {theta:.1} deg, periodic {:.0} d x {:.0} d; \
         dt = {dt:.3e} s, {steps} steps, {duration} s under the monitor in {wall:.0} s wall ({threads} threads)\n",
        n - flowing,
        l.x / D,
        l.y / D
    );
    let _ = writeln!(
        csv,
        "# profile: mean v_x of the flowing spheres per {BIN} d bin above the base's centres, {} states from t = {t_from:.2} s",
        profile.samples
    );
    let _ = writeln!(csv, "# flow height h = {:.2} d (density half the bulk's)", f.h);
    let _ = writeln!(
        csv,
        "# Bagnold fit v = A (h^1.5 - (h - z)^1.5), z and h in d: A = {:.4e} m/s, RMS deviation {:.3} of v(h)",
        f.bagnold.0, f.bagnold.1
    );
    let _ = writeln!(csv, "# linear fit v = B z: B = {:.4e} m/s, RMS deviation {:.3} of v(h)", f.linear.0, f.linear.1);
    let _ = writeln!(
        csv,
        "# mass flux through the periodic plane {flux:.5e} kg/s; M <v_x> / L_x = {flux_from_velocity:.5e} kg/s (mean v_x {mean_vx:.4} m/s); \
         kinetic energy over the window's halves {ke_first:.4e} J, {ke_second:.4e} J"
    );
    csv.push_str("z_over_d,density_over_bulk,vx_m_s,bagnold_m_s,linear_m_s\n");
    for &(z, rho, v) in &f.rows {
        let _ = writeln!(csv, "{z:.2},{rho:.3},{v:.5},{:.5},{:.5}", f.bagnold.0 * bagnold_shape(f.h, z), f.linear.0 * z);
    }
    print!("{csv}");
    let svg = chart(&f, theta);
    let dir = root().join("docs").join("charts");
    for (ext, text) in [("svg", svg), ("csv", csv)] {
        let out = dir.join(format!("chute_profile.{ext}"));
        if let Err(e) = std::fs::write(&out, text) {
            eprintln!("cannot write {}: {e}", out.display());
            return 1;
        }
        eprintln!("wrote {}", out.display());
    }
    0
}

fn chart(f: &Fit, theta: f64) -> String {
    let (w, h) = (720.0, 520.0);
    let mut doc = Svg::titled(w, h, &format!("Periodic chute at {theta:.0}°: velocity profile against Bagnold's"));
    let vmax = f.rows.iter().map(|r| r.2).fold(0.0, f64::max);
    let zmax = f.rows.iter().map(|r| r.0).fold(0.0, f64::max);
    let step = if vmax > 0.5 { 0.1 } else { 0.05 };
    let xa = LinearAxis { lo: 0.0, hi: ((vmax / step).ceil() + 1.0) * step, step, p0: 90.0, p1: 680.0 };
    let ya = LinearAxis { lo: 0.0, hi: zmax.ceil() + 1.0, step: 1.0, p0: 450.0, p1: 60.0 };
    linear_frame(&mut doc, xa, YAxis::Linear(ya), "mean v_x, m/s", "height above the base z / d");
    let curve = |g: &dyn Fn(f64) -> f64| -> Vec<(f64, f64)> { (0..=100).map(|k| f.h * k as f64 / 100.0).map(|z| (xa.px(g(z)), ya.px(z))).collect() };
    doc.polyline(&curve(&|z| f.bagnold.0 * bagnold_shape(f.h, z)), "#D55E00", 2.0, None, 1.0);
    doc.polyline(&curve(&|z| f.linear.0 * z), "#999999", 1.5, Some("5,3"), 1.0);
    for r in &f.rows {
        doc.marker(Shape::Circle, xa.px(r.2), ya.px(r.0), 8.0, "#0072B2", r.0 >= f.h);
    }
    doc.line((xa.p0, ya.px(f.h)), (xa.p1, ya.px(f.h)), "#555555", 1.0, Some("2,3"));
    let entries = vec![
        (Style { colour: "#0072B2", shape: Shape::Circle, dashed: false }, "measured (hollow: above the surface h)".to_string()),
        (Style { colour: "#D55E00", shape: Shape::Cross, dashed: false }, format!("Bagnold, RMS {:.1} % of v(h)", 100.0 * f.bagnold.1)),
        (Style { colour: "#999999", shape: Shape::Cross, dashed: true }, format!("linear, RMS {:.1} % of v(h)", 100.0 * f.linear.1)),
    ];
    doc.legend(100.0, 70.0, &entries, true, 11.0);
    doc.finish()
}
