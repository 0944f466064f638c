//! `cargo xtask sph`: the fluid's validation at full resolution, tables and charts for docs/sph.md.
//! - The 2D dam break of Martin & Moyce (1952) at 20, 40 and 80 particles over the column's
//!   height 2a (a = 2.25 in, as in the experiment): the surge front against the experiment's,
//!   and the residual column's height at the left wall.
//! - Stability: the largest density error and the front at T = 2.5 against c₀/v_max from 3 to
//!   20, with and without δ-SPH and the tensile correction, at 40 particles over 2a.
//!
//! Writes docs/charts/sph_dam_break.{svg,csv} and docs/charts/sph_stability.{svg,csv}.

use std::fmt::Write as _;
use std::time::Instant;

use crate::svg::{LinearAxis, LogAxis, Shape, Style, Svg, YAxis, linear_frame};
use tumble_geom::DVec3;
use tumble_sph::cases::{ColumnInTank, G, MARTIN_MOYCE_FRONT, interpolate};
use tumble_sph::{DensityDiffusion, FluidPhase, ParticleKind, TimeStepLimits};

/// Martin & Moyce's column width, 2.25 in.
const A: f64 = 0.05715;
/// The dam break runs to T = t √(2g/a) = 4.1.
const T_END: f64 = 4.1;

/// One dam break's record: (T, front x/a, residual height / 2a, largest |ρ/ρ₀ − 1| so far).
struct Record {
    rows: Vec<(f64, f64, f64, f64)>,
    /// Why it stopped early, if it did.
    fault: Option<String>,
    fluid: usize,
    /// The highest fluid particle within Δp of the left wall at the end, / 2a.
    highest_at_wall: f64,
    steps: u64,
    seconds: f64,
}

/// The residual column's height: a wave gauge 2h from the left wall (a full kernel from it, so
/// the wall's missing fluid does not halve the fluid fraction there), ignoring the odd particle
/// that clings to the wall above the water.
fn residual_height(phase: &FluidPhase) -> f64 {
    let x = 2.0 * phase.settings().h;
    phase.water_height(DVec3::new(x, 0.0, 0.0), 1.5 * 2.0 * A)
}

/// The highest fluid particle within Δp of the left wall, to show how many cling to it.
fn highest_at_wall(phase: &FluidPhase) -> f64 {
    let p = phase.particles();
    let dp = phase.settings().spacing;
    (0..p.len()).filter(|&i| p.kind[i] == ParticleKind::Fluid && p.position[i].x < dp).map(|i| p.position[i].z + 0.5 * dp).fold(0.0, f64::max)
}

fn dam_break(case: ColumnInTank, t_star_end: f64) -> Record {
    let mut phase = case.build();
    let dt = TimeStepLimits::planned(phase.settings()).dt();
    let time_scale = (2.0 * G / A).sqrt();
    let t_end = t_star_end / time_scale;
    let fluid = phase.particles().fluid_count();
    let mut record = Record { rows: Vec::new(), fault: None, fluid, highest_at_wall: 0.0, steps: 0, seconds: 0.0 };
    let mut worst: f64 = 0.0;
    let start = Instant::now();
    let sample = |phase: &FluidPhase, worst: f64| (phase.time() * time_scale, phase.front(DVec3::X) / A, residual_height(phase) / (2.0 * A), worst);
    record.rows.push(sample(&phase, worst));
    while phase.time() < t_end {
        if let Err(e) = phase.step(dt) {
            record.fault = Some(e.to_string());
            break;
        }
        worst = worst.max(phase.observables().largest_density_deviation);
        record.rows.push(sample(&phase, worst));
    }
    record.steps = phase.steps();
    record.highest_at_wall = highest_at_wall(&phase) / (2.0 * A);
    record.seconds = start.elapsed().as_secs_f64();
    record
}

/// The record's value of column `f` at dimensionless time `t`, interpolated linearly.
fn at(record: &Record, t: f64, f: impl Fn(&(f64, f64, f64, f64)) -> f64) -> Option<f64> {
    interpolate(&record.rows, t, |r| r.0, f)
}

fn write(name: &str, text: &str) -> Result<(), String> {
    let out = crate::mill::root().join("docs").join("charts").join(name);
    std::fs::write(&out, text).map_err(|e| format!("cannot write {}: {e}", out.display()))?;
    eprintln!("wrote {}", out.display());
    Ok(())
}

pub fn run(args: &[String]) -> i32 {
    let resolutions: Vec<usize> = match args.iter().position(|a| a == "--resolutions") {
        Some(k) => args.get(k + 1).map(|v| v.split(',').filter_map(|s| s.parse().ok()).collect()).unwrap_or_default(),
        None => vec![20, 40, 80],
    };
    match study(&resolutions, !args.iter().any(|a| a == "--no-stability")) {
        Ok(()) => 0,
        Err(e) => {
            eprintln!("error: {e}");
            1
        }
    }
}

fn study(resolutions: &[usize], stability: bool) -> Result<(), String> {
    // Dam break at each resolution: a tank 6a long, the column a wide and 2a high.
    let mut records = Vec::new();
    for &n in resolutions {
        let case = ColumnInTank::plane(6.0 * A, A, 2.0 * A, n);
        let r = dam_break(case, T_END);
        println!(
            "dam break, {n} over 2a: {} fluid particles, {} steps in {:.1} s ({:.3e} fluid particle-steps/s){}",
            r.fluid,
            r.steps,
            r.seconds,
            r.fluid as f64 * r.steps as f64 / r.seconds,
            r.fault.as_ref().map(|f| format!(", STOPPED: {f}")).unwrap_or_default()
        );
        records.push((n, r));
    }
    let mut csv = String::from("particles_over_2a,T,Z_front,H_residual_over_2a,largest_density_deviation\n");
    for (n, r) in &records {
        for row in r.rows.iter().step_by(10) {
            let _ = writeln!(csv, "{n},{:.4},{:.5},{:.5},{:.3e}", row.0, row.1, row.2, row.3);
        }
    }
    println!("\n| T | experiment Z | {} |", resolutions.iter().map(|n| format!("Z, {n} over 2a")).collect::<Vec<_>>().join(" | "));
    println!("|---|---|{}", "---|".repeat(resolutions.len()));
    for &(t, z) in MARTIN_MOYCE_FRONT.iter().filter(|(t, _)| *t <= T_END) {
        let cells: Vec<String> = records
            .iter()
            .map(|(_, r)| at(r, t, |row| row.1).map(|v| format!("{v:.3} ({:+.1} %)", 100.0 * (v / z - 1.0))).unwrap_or("—".into()))
            .collect();
        println!("| {t:.3} | {z:.3} | {} |", cells.join(" | "));
    }
    println!(
        "\nhighest fluid particle within Δp of the left wall at T = {T_END}, / 2a: {}",
        records.iter().map(|(n, r)| format!("{:.3} ({n} over 2a)", r.highest_at_wall)).collect::<Vec<_>>().join(", ")
    );
    println!("\nresidual column height H/2a (a wave gauge 2h from the left wall):");
    println!("| T | {} |", resolutions.iter().map(|n| format!("{n} over 2a")).collect::<Vec<_>>().join(" | "));
    println!("|---|{}", "---|".repeat(resolutions.len()));
    for t in [0.5, 1.0, 1.5, 2.0, 2.5, 3.0] {
        let cells: Vec<String> = records.iter().map(|(_, r)| at(r, t, |row| row.2).map(|v| format!("{v:.3}")).unwrap_or("—".into())).collect();
        println!("| {t:.1} | {} |", cells.join(" | "));
    }
    write("sph_dam_break.csv", &csv)?;
    write("sph_dam_break.svg", &dam_break_chart(&records))?;
    if stability {
        stability_study()?;
    }
    Ok(())
}

const COLOURS: [&str; 4] = ["#0072B2", "#D55E00", "#009E73", "#CC79A7"];
const SHAPES: [Shape; 4] = [Shape::Circle, Shape::Square, Shape::Triangle, Shape::Diamond];

fn dam_break_chart(records: &[(usize, Record)]) -> String {
    let mut doc = Svg::titled(720.0, 520.0, "2D dam break: surge front against Martin & Moyce (1952), n² = 2");
    let xa = LinearAxis { lo: 0.0, hi: 4.5, step: 0.5, p0: 90.0, p1: 680.0 };
    let ya = LinearAxis { lo: 1.0, hi: 6.0, step: 1.0, p0: 450.0, p1: 60.0 };
    linear_frame(&mut doc, xa, YAxis::Linear(ya), "T = t √(2g/a)", "front Z = x / a");
    let mut entries = Vec::new();
    for (k, (n, r)) in records.iter().enumerate() {
        let points: Vec<(f64, f64)> = r.rows.iter().filter(|row| row.1 <= ya.hi && row.0 <= xa.hi).map(|row| (xa.px(row.0), ya.px(row.1))).collect();
        doc.polyline(&points, COLOURS[k % 4], 1.8, None, 1.0);
        entries.push((Style { colour: COLOURS[k % 4], shape: SHAPES[k % 4], dashed: false }, format!("tumble, {n} particles over 2a")));
    }
    for &(t, z) in &MARTIN_MOYCE_FRONT {
        if z <= ya.hi {
            doc.marker(Shape::Cross, xa.px(t), ya.px(z), 9.0, "#222222", false);
        }
    }
    entries.push((Style { colour: "#222222", shape: Shape::Cross, dashed: false }, "Martin & Moyce (1952), a = 2.25 in".into()));
    doc.legend(100.0, 70.0, &entries, true, 11.0);
    doc.finish()
}

/// The four variants of the stability study: (label, δ-SPH, tensile correction).
const VARIANTS: [(&str, bool, bool); 4] =
    [("no δ-SPH, no tensile", false, false), ("δ-SPH", true, false), ("tensile correction", false, true), ("δ-SPH + tensile", true, true)];
const SOUND_FACTORS: [f64; 5] = [3.0, 5.0, 7.0, 10.0, 20.0];

fn stability_study() -> Result<(), String> {
    let mut csv = String::from("variant,c_over_vmax,largest_density_deviation,front_T2.5,stopped\n");
    let mut table: Vec<Vec<(f64, f64, Option<f64>, bool)>> = Vec::new();
    println!("\nstability at 40 particles over 2a: largest |ρ/ρ₀ − 1| up to T = 3, front Z at T = 2.5");
    for (label, diffusion, tensile) in VARIANTS {
        let mut row = Vec::new();
        for factor in SOUND_FACTORS {
            let mut case = ColumnInTank::plane(6.0 * A, A, 2.0 * A, 40);
            case.sound_speed_factor = factor;
            case.tensile_correction = tensile;
            case.diffusion = if diffusion { DensityDiffusion::Fourtakas { delta: 0.1 } } else { DensityDiffusion::None };
            let r = dam_break(case, 3.0);
            let worst = r.rows.last().map(|x| x.3).unwrap_or(f64::NAN);
            let front = at(&r, 2.5, |row| row.1);
            let stopped = r.fault.is_some();
            println!(
                "  {label:<22} c/v_max {factor:>4}: density error {:>6.2} %, front {}{}",
                100.0 * worst,
                front.map(|f| format!("{f:.3}")).unwrap_or("—".into()),
                r.fault.as_ref().map(|f| format!(" (stopped: {f})")).unwrap_or_default()
            );
            let _ = writeln!(csv, "{label},{factor},{worst:.4e},{},{stopped}", front.map(|f| format!("{f:.4}")).unwrap_or_default());
            row.push((factor, worst, front, stopped));
        }
        table.push(row);
    }
    write("sph_stability.csv", &csv)?;
    write("sph_stability.svg", &stability_chart(&table))?;
    Ok(())
}

fn stability_chart(table: &[Vec<(f64, f64, Option<f64>, bool)>]) -> String {
    let mut doc = Svg::titled(720.0, 820.0, "Dam break stability against the sound-speed factor (40 particles over 2a)");
    let xa = LinearAxis { lo: 0.0, hi: 21.0, step: 2.0, p0: 90.0, p1: 680.0 };
    let ya = LogAxis::covering(table.iter().flatten().map(|r| r.1).filter(|v| v.is_finite() && *v > 0.0), 400.0, 60.0);
    linear_frame(&mut doc, xa, YAxis::Log(ya), "c₀ / v_max", "largest |ρ/ρ₀ − 1| up to T = 3");
    let fa = LinearAxis { lo: 2.5, hi: 4.0, step: 0.25, p0: 760.0, p1: 500.0 };
    linear_frame(&mut doc, xa, YAxis::Linear(fa), "c₀ / v_max", "front Z at T = 2.5");
    let mut entries = Vec::new();
    for (k, row) in table.iter().enumerate() {
        let (colour, shape) = (COLOURS[k], SHAPES[k]);
        let density: Vec<(f64, f64)> = row.iter().filter(|r| ya.contains(r.1)).map(|r| (xa.px(r.0), ya.px(r.1))).collect();
        doc.polyline(&density, colour, 1.5, None, 1.0);
        for r in row.iter().filter(|r| ya.contains(r.1)) {
            doc.marker(shape, xa.px(r.0), ya.px(r.1), 8.0, colour, r.3);
        }
        let fronts: Vec<(f64, f64)> = row.iter().filter_map(|r| r.2.filter(|f| *f >= fa.lo && *f <= fa.hi).map(|f| (xa.px(r.0), fa.px(f)))).collect();
        doc.polyline(&fronts, colour, 1.5, None, 1.0);
        for &(x, y) in &fronts {
            doc.marker(shape, x, y, 8.0, colour, false);
        }
        entries.push((Style { colour, shape, dashed: false }, VARIANTS[k].0.to_string()));
    }
    doc.line((xa.p0, fa.px(2.995)), (xa.p1, fa.px(2.995)), "#222222", 1.0, Some("4,3"));
    doc.text(xa.p1 - 4.0, fa.px(2.995) - 5.0, 11.0, crate::svg::Anchor::End, "#222222", "Martin & Moyce at T = 2.547: 2.995");
    entries.push((Style { colour: "#555555", shape: Shape::Circle, dashed: false }, "hollow: the run stopped (fault)".into()));
    doc.legend(420.0, 70.0, &entries, true, 11.0);
    doc.finish()
}
