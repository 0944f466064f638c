//! `cargo xtask charts` (or `cargo xtask charts friction` alone) also writes the
//! friction charts into docs/charts/, each with its data as CSV:
//!
//! - `oblique_impact`: rebound tangential velocity ratio v_t'/v_t and spin Rω'/v_t
//!   against impact angle, per tangential model, with rigid-body Coulomb theory;
//! - `incline_creep`: creep speed of a sphere that cannot roll on an incline below
//!   atan μ, per model, with each history-free model's closed form.

use crate::svg::{self, Anchor, LinearAxis, LogAxis, Shape, Style, Svg, YAxis};
use std::fmt::Write as _;
use tumble::verify::{self as tv, FrictionModel};

const MU_IMPACT: f64 = 0.1;
const E: f64 = 0.8;
const MU_INCLINE: f64 = 0.5;

fn style(m: FrictionModel) -> Style {
    match m {
        FrictionModel::History => Style { colour: "#009E73", shape: Shape::Triangle, dashed: false },
        FrictionModel::ViscousCoulomb => Style { colour: "#0072B2", shape: Shape::Square, dashed: false },
        FrictionModel::StickLimited => Style { colour: "#E69F00", shape: Shape::Diamond, dashed: false },
        FrictionModel::DynamicOnly => Style { colour: "#D55E00", shape: Shape::Circle, dashed: false },
    }
}

const THEORY: Style = Style { colour: "#222222", shape: Shape::Cross, dashed: true };

/// Both charts: (name, svg, csv).
pub fn charts() -> Vec<(&'static str, String, String)> {
    vec![oblique_impact(), incline_creep()]
}

fn oblique_impact() -> (&'static str, String, String) {
    let angles: Vec<f64> = (1..=17).map(|k| 5.0 * k as f64).collect();
    let mut csv = String::from("model,angle_deg,tangential_ratio,spin_ratio,normal_ratio,theory_tangential,theory_spin\n");
    let mut data = Vec::new();
    for m in FrictionModel::ALL {
        let rows: Vec<tv::Impact> = angles.iter().map(|&a| tv::oblique_impact(m, false, MU_IMPACT, E, a)).collect();
        for r in &rows {
            let (t, s) = tv::coulomb_impact(r.angle_deg, MU_IMPACT, E);
            let _ = writeln!(csv, "{},{},{},{},{},{},{}", m.name(), r.angle_deg, r.tangential, r.spin, r.normal, t, s);
        }
        data.push((m, rows));
    }
    let (w, h) = (1200.0, 560.0);
    let mut doc = Svg::titled(w, h, &format!("Oblique impact on a wall: μ = {MU_IMPACT}, e = {E}, 1 m/s, linear normal law, rotation on"));
    let threshold = (3.5 * MU_IMPACT * (1.0 + E)).atan().to_degrees();
    let panels: [(&str, fn(&tv::Impact) -> f64, fn((f64, f64)) -> f64, (f64, f64, f64)); 2] = [
        ("rebound tangential velocity v_t' / v_t", |r| r.tangential, |t| t.0, (0.4, 1.0, 0.1)),
        ("rebound spin R ω' / v_t", |r| r.spin, |t| t.1, (0.0, 1.4, 0.2)),
    ];
    for (k, (label, value, theory, (lo, hi, step))) in panels.into_iter().enumerate() {
        let (left, right) = (90.0 + k as f64 * 590.0, 560.0 + k as f64 * 590.0);
        let x = LinearAxis { lo: 0.0, hi: 90.0, step: 15.0, p0: left, p1: right };
        let y = LinearAxis { lo, hi, step, p0: h - 90.0, p1: 60.0 };
        svg::linear_frame(&mut doc, x, YAxis::Linear(y), "impact angle from the wall normal (degrees)", label);
        let clamp = |v: f64| y.px(v.clamp(lo, hi));
        // The sliding threshold tan θ = 7/2 μ (1 + e).
        doc.line((x.px(threshold), y.p1), (x.px(threshold), y.p0), "#999999", 1.0, Some("2,3"));
        doc.text(x.px(threshold) + 4.0, y.p1 + 14.0, 10.0, Anchor::Start, "#555555", &format!("sliding throughout above {threshold:.1}°"));
        let theory_pts: Vec<(f64, f64)> =
            (10..=890).map(|a| a as f64 / 10.0).map(|a| (x.px(a), clamp(theory(tv::coulomb_impact(a, MU_IMPACT, E))))).collect();
        doc.polyline(&theory_pts, THEORY.colour, 1.5, Some("6,4"), 1.0);
        for (m, rows) in &data {
            let s = style(*m);
            let pts: Vec<(f64, f64)> = rows.iter().map(|r| (x.px(r.angle_deg), clamp(value(r)))).collect();
            doc.polyline(&pts, s.colour, 1.6, None, 0.8);
            for p in pts {
                doc.marker(s.shape, p.0, p.1, 7.0, s.colour, *m != FrictionModel::History);
            }
        }
    }
    let mut legend: Vec<(Style, String)> = FrictionModel::ALL.iter().map(|&m| (style(m), m.name().to_string())).collect();
    legend.push((THEORY, "Coulomb theory (5/7 if sticking)".into()));
    doc.legend(300.0, 350.0, &legend, true, 12.0);
    ("oblique_impact", doc.finish(), csv)
}

fn incline_creep() -> (&'static str, String, String) {
    let angles: Vec<f64> = (1..=10).map(|k| 2.5 * k as f64).collect();
    let dt = tv::floor_dt(E);
    let c_t = tv::viscous_coefficient(E);
    let theory = |m: FrictionModel, a: f64| -> Option<f64> {
        let s = a.to_radians().sin();
        match m {
            FrictionModel::ViscousCoulomb => Some(tv::sphere_mass() * tv::G * s / c_t),
            FrictionModel::StickLimited => Some(tv::G * s * dt),
            _ => None,
        }
    };
    let mut csv = String::from("model,angle_deg,creep_speed_m_per_s,closed_form_m_per_s\n");
    let mut data = Vec::new();
    for m in FrictionModel::ALL {
        let rows: Vec<(f64, f64)> = angles.iter().map(|&a| (a, tv::creep_speed(m, MU_INCLINE, a, 1.0))).collect();
        for &(a, v) in &rows {
            let _ = writeln!(csv, "{},{a},{v},{}", m.name(), theory(m, a).map_or(String::new(), |t| t.to_string()));
        }
        data.push((m, rows));
    }
    let (w, h) = (1000.0, 600.0);
    let mut doc = Svg::titled(w, h, &format!("Creep on an incline below atan μ (μ = {MU_INCLINE}, 26.6°), rotation off, 1 s"));
    let x = LinearAxis { lo: 0.0, hi: 27.5, step: 2.5, p0: 100.0, p1: 700.0 };
    let y = LogAxis { lo: -7.0, hi: -2.0, p0: h - 110.0, p1: 60.0 };
    svg::linear_frame(&mut doc, x, YAxis::Log(y), "incline angle (degrees)", "mean speed down the slope over 0.5–1 s (m/s)");
    // History holds: its measured speed is zero, drawn on a strip under the log axis.
    let held_y = y.p0 + 62.0;
    doc.text(x.p0 - 8.0, held_y + 4.0, 11.0, Anchor::End, "#333333", "0");
    for (m, rows) in &data {
        let s = style(*m);
        if let Some(a0) = angles.first().copied().filter(|&a| theory(*m, a).is_some()) {
            let pts: Vec<(f64, f64)> =
                (0..=100).map(|k| a0 + k as f64 * (angles[angles.len() - 1] - a0) / 100.0).map(|a| (x.px(a), y.px(theory(*m, a).unwrap()))).collect();
            doc.polyline(&pts, s.colour, 1.3, Some("6,4"), 0.9);
        }
        let mut pts = Vec::new();
        for &(a, v) in rows {
            let py = if v > 10f64.powf(y.lo) { y.px(v) } else { held_y };
            pts.push((x.px(a), py));
        }
        if pts.iter().all(|p| p.1 != held_y) {
            doc.polyline(&pts, s.colour, 1.6, None, 0.8);
        }
        for p in pts {
            doc.marker(s.shape, p.0, p.1, 8.0, s.colour, false);
        }
    }
    let mut legend: Vec<(Style, String)> = FrictionModel::ALL
        .iter()
        .map(|&m| {
            let note = match m {
                FrictionModel::History => " (holds: speed 0)",
                FrictionModel::ViscousCoulomb => " (dashed: m g sinθ / c_t)",
                FrictionModel::StickLimited => " (dashed: g sinθ Δt)",
                FrictionModel::DynamicOnly => " (oscillates around rest)",
            };
            (style(m), format!("{}{note}", m.name()))
        })
        .collect();
    legend.truncate(4);
    doc.legend(715.0, 70.0, &legend, true, 11.0);
    ("incline_creep", doc.finish(), csv)
}
