//! `cargo xtask chung-ooi`: the Chung & Ooi (2011) impact benchmarks 1–8 for the
//! Hertz–Mindlin ("history") and viscous-Coulomb models. Writes into docs/charts/
//! `chung_ooi_normal.csv` (tests 1–3), `chung_ooi_oblique.{svg,csv}` (tests 4–8: β against 1/χ
//! with rigid-body theory) and `chung_ooi_test4.{svg,csv}` (v_t'/v_t and Rω'/v_t against angle),
//! and the tables between the markers of docs/chung-ooi.md.

use crate::svg::{self, Anchor, LinearAxis, Shape, Style, Svg, YAxis};

use std::fmt::Write as _;
use std::path::Path;
use tumble::verify::FrictionModel::{self, History, ViscousCoulomb};
use tumble::verify::chung_ooi::*;
use tumble::verify::coulomb_impact;

const BEGIN: &str = "<!-- chung-ooi tables: written by cargo xtask chung-ooi -->";
const END: &str = "<!-- end chung-ooi tables -->";

fn style(m: FrictionModel, no_attraction: bool) -> Style {
    match (m, no_attraction) {
        (History, true) => Style { colour: "#009E73", shape: Shape::Triangle, dashed: false },
        (History, false) => Style { colour: "#56B4E9", shape: Shape::Diamond, dashed: false },
        (_, true) => Style { colour: "#0072B2", shape: Shape::Square, dashed: false },
        (_, false) => Style { colour: "#E69F00", shape: Shape::Circle, dashed: false },
    }
}

pub fn run(_args: &[String]) -> i32 {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("..");
    let charts = root.join("docs").join("charts");
    let (normal_csv, normal_md) = normal_tests();
    let (oblique_svg, oblique_csv, oblique_md) = oblique_tests();
    let (t4_svg, t4_csv) = test4_curves();
    let files = [
        ("chung_ooi_normal.csv", normal_csv),
        ("chung_ooi_oblique.csv", oblique_csv),
        ("chung_ooi_oblique.svg", oblique_svg),
        ("chung_ooi_test4.csv", t4_csv),
        ("chung_ooi_test4.svg", t4_svg),
    ];
    for (name, text) in files {
        if let Err(e) = std::fs::write(charts.join(name), text) {
            eprintln!("cannot write {name}: {e}");
            return 1;
        }
    }
    let doc = root.join("docs").join("chung-ooi.md");
    let Ok(text) = std::fs::read_to_string(&doc) else {
        eprintln!("cannot read docs/chung-ooi.md");
        return 1;
    };
    let (Some(a), Some(b)) = (text.find(BEGIN), text.find(END)) else {
        eprintln!("docs/chung-ooi.md lacks the table markers");
        return 1;
    };
    let new = format!("{}{BEGIN}\n\n{normal_md}\n{oblique_md}\n{}", &text[..a], &text[b..]);
    if let Err(e) = std::fs::write(&doc, new) {
        eprintln!("cannot write docs/chung-ooi.md: {e}");
        return 1;
    }
    println!("{normal_md}\n{oblique_md}");
    0
}

/// Tests 1–3: (CSV, markdown table).
fn normal_tests() -> (String, String) {
    let pair = |m: Material, ra: f64, rb: f64, v: f64| {
        let a = Body::new(m, ra, DVec3::new(0.0, 0.0, -v), DVec3::ZERO);
        let b = Body::new(m, rb, DVec3::new(0.0, 0.0, v), DVec3::ZERO);
        ImpactSetup::new(History, 0.35, 1.0, a, Some(b))
    };
    let wall = |m: Material, r: f64, v: f64, e: f64, no_attraction: bool| {
        let a = Body::new(m, r, DVec3::new(0.0, 0.0, -v), DVec3::ZERO);
        ImpactSetup { no_attraction, ..ImpactSetup::new(History, 0.0, e, a, None) }
    };
    let mut cases = vec![
        ("1", "glass, R = 10 mm, ±10 m/s".to_string(), pair(GLASS, 0.01, 0.01, 10.0)),
        ("1", "limestone, R = 10 mm, ±10 m/s".to_string(), pair(LIMESTONE, 0.01, 0.01, 10.0)),
        ("2", "aluminium alloy on wall, R = 0.1 m, 0.2 m/s".to_string(), wall(ALUMINIUM_ALLOY, 0.1, 0.2, 1.0, false)),
        ("2", "magnesium alloy on wall, R = 0.1 m, 0.2 m/s".to_string(), wall(MAGNESIUM_ALLOY, 0.1, 0.2, 1.0, false)),
        ("3", "glass R = 10 mm on R = 20 mm, ±5 m/s".to_string(), pair(GLASS, 0.01, 0.02, 5.0)),
    ];
    for e in [0.2, 0.5, 0.8, 0.95] {
        for na in [false, true] {
            let what = format!("aluminium oxide on wall, 3.9 m/s, e = {e}{}", if na { ", no_attraction" } else { "" });
            cases.push(("2e", what, wall(ALUMINIUM_OXIDE, OXIDE_RADIUS, 3.9, e, na)));
        }
    }
    let mut csv = String::from("test,case,contact_time,hertz_time,max_overlap,hertz_overlap,max_force,hertz_force,restitution,set_restitution\n");
    let mut md = String::from("| test | case | t_c / t_H − 1 | δ_max / δ_H − 1 | F_max / F_H − 1 | e measured (set) |\n|---|---|---|---|---|---|\n");
    for (test, what, s) in cases {
        let r = s.run();
        let (t, d, f) = s.hertz();
        let _ = writeln!(csv, "{test},{what},{},{t},{},{d},{},{f},{},{}", r.contact_time, r.max_overlap, r.max_force, r.restitution, s.restitution);
        let rel = |a: f64, b: f64| if s.restitution == 1.0 { format!("{:+.1e}", a / b - 1.0) } else { "(damped)".into() };
        let _ = writeln!(
            md,
            "| {test} | {what} | {} | {} | {} | {:.4} ({}) |",
            rel(r.contact_time, t),
            rel(r.max_overlap, d),
            rel(r.max_force, f),
            r.restitution,
            s.restitution
        );
    }
    (csv, md)
}

/// The impacts of tests 4–8, each with a label.
fn oblique_setups(m: FrictionModel, e: f64) -> Vec<(&'static str, String, ImpactSetup)> {
    let mut v = Vec::new();
    for a in [5.0, 10.0, 20.0, 30.0, 40.0, 60.0, 80.0] {
        v.push(("4", format!("θ = {a}°"), oblique_at_angle(m, e, a)));
    }
    for vt in [0.5, 2.0, 5.0, 10.0] {
        v.push(("5", format!("v_t = {vt} m/s"), oblique_with_tangential(m, e, vt)));
    }
    for w in [100.0, 500.0, 2000.0, 4000.0] {
        v.push(("6", format!("ω = {w} rad/s"), spinning_onto_wall(m, e, w)));
    }
    for w in [1.0, 5.0, 10.0, 20.0] {
        v.push(("7", format!("ω = {w} rad/s"), spinning_pair(m, e, w)));
    }
    for w in [3.0, 10.0, -10.0] {
        v.push(("8", format!("v_t = 0.1 m/s, ω = {w} rad/s"), unequal_spinning_pair(m, e, 0.1, w)));
    }
    v
}

/// Tests 4–8: (svg, csv, markdown).
fn oblique_tests() -> (String, String, String) {
    let mut csv = String::from("test,case,model,restitution,no_attraction,chi,beta,rigid_beta,jt_over_mu_jn,jt_over_mu_compressive\n");
    let mut md = String::from(
        "| test | case | model, e | χ | β (no_attraction) | χ − 1 or 0 | J_t/μJ_n (no_attraction) | β (attraction kept) | J_t/μ∫max(F_n,0)dt |\n|---|---|---|---|---|---|---|---|---|\n",
    );
    let mut points: Vec<(FrictionModel, bool, f64, f64)> = Vec::new();
    for (m, e) in [(History, 0.98), (History, 0.5), (ViscousCoulomb, 0.98), (ViscousCoulomb, 0.5)] {
        for (test, what, s) in oblique_setups(m, e) {
            let mut row = Vec::new();
            for na in [true, false] {
                let s = ImpactSetup { no_attraction: na, ..s };
                let r = s.run();
                let chi = s.chi(r.restitution);
                let comp = r.tangential_impulse.abs() / (s.friction * r.compressive_impulse);
                let _ = writeln!(
                    csv,
                    "{test},{what},{},{e},{na},{chi},{},{},{},{comp}",
                    m.name(),
                    r.beta(),
                    rigid_beta(chi),
                    r.friction_ratio(s.friction)
                );
                points.push((m, na, 1.0 / chi, r.beta()));
                row.push((chi, r.beta(), r.friction_ratio(s.friction), comp));
            }
            let _ = writeln!(
                md,
                "| {test} | {what} | {}, {e} | {:.3} | {:+.4} | {:+.4} | {:.4} | {:+.4} | {:.4} |",
                m.name(),
                row[0].0,
                row[0].1,
                rigid_beta(row[0].0),
                row[0].2,
                row[1].1,
                row[1].3
            );
        }
    }
    let (w, h) = (1000.0, 600.0);
    let mut doc = Svg::titled(w, h, "Chung & Ooi tests 4–8: β = −V_st'/V_st against 1/χ, Hertz–Mindlin and viscous-Coulomb, e = 0.98 and 0.5");
    let x = LinearAxis { lo: 0.0, hi: 6.0, step: 1.0, p0: 90.0, p1: 700.0 };
    let y = LinearAxis { lo: -1.0, hi: 0.6, step: 0.2, p0: h - 90.0, p1: 60.0 };
    svg::linear_frame(&mut doc, x, YAxis::Linear(y), "1/χ = V_st K_n / (μ (1 + e) V_n K_t)", "β = −V_st' / V_st");
    let theory: Vec<(f64, f64)> = (1..=600).map(|k| k as f64 / 100.0).map(|u| (x.px(u), y.px(rigid_beta(1.0 / u).max(-1.0)))).collect();
    doc.polyline(&theory, "#222222", 1.5, Some("6,4"), 1.0);
    doc.text(x.px(1.05), y.px(0.05), 10.0, Anchor::Start, "#555555", "gross sliding: β = χ − 1");
    for &(m, na, u, b) in &points {
        if u <= x.hi && (y.lo..=y.hi).contains(&b) {
            let s = style(m, na);
            doc.marker(s.shape, x.px(u), y.px(b), 7.0, s.colour, m == ViscousCoulomb);
        }
    }
    let legend = vec![
        (style(History, true), "Hertz–Mindlin, no_attraction".to_string()),
        (style(History, false), "Hertz–Mindlin".to_string()),
        (style(ViscousCoulomb, true), "viscous-Coulomb, no_attraction".to_string()),
        (style(ViscousCoulomb, false), "viscous-Coulomb".to_string()),
        (Style { colour: "#222222", shape: Shape::Cross, dashed: true }, "rigid-body theory".to_string()),
    ];
    doc.legend(715.0, 70.0, &legend, false, 11.0);
    (doc.finish(), csv, md)
}

/// Test 4 curves: v_t'/v_t and Rω'/v_t against angle, e = 0.98, with rigid-body theory.
fn test4_curves() -> (String, String) {
    let angles: Vec<f64> = (1..=17).map(|k| 5.0 * k as f64).collect();
    let mut csv = String::from("model,angle_deg,tangential_ratio,spin_ratio,theory_tangential,theory_spin\n");
    let mut data = Vec::new();
    for m in [History, ViscousCoulomb] {
        let mut rows = Vec::new();
        for &a in &angles {
            let s = oblique_at_angle(m, 0.98, a);
            let r = s.run();
            let v_t = s.a.velocity.x;
            let (tv, ts) = coulomb_impact(a, OXIDE_FRICTION, r.restitution);
            let (vt_ratio, spin_ratio) = (r.a.velocity.x / v_t, OXIDE_RADIUS * r.a.angular_velocity.y / v_t);
            let _ = writeln!(csv, "{},{a},{vt_ratio},{spin_ratio},{tv},{ts}", m.name());
            rows.push((a, vt_ratio, spin_ratio));
        }
        data.push((m, rows));
    }
    let (w, h) = (1200.0, 560.0);
    let mut doc = Svg::titled(w, h, "Chung & Ooi test 4: aluminium oxide on a wall at 3.9 m/s, μ = 0.092, e = 0.98");
    let panels: [(&str, usize, fn((f64, f64)) -> f64, (f64, f64, f64)); 2] =
        [("rebound tangential velocity v_t' / v_t", 1, |t| t.0, (-0.6, 1.0, 0.2)), ("rebound spin R ω' / v_t", 2, |t| t.1, (0.0, 2.0, 0.25))];
    for (k, (label, col, theory, (lo, hi, step))) in panels.into_iter().enumerate() {
        let (left, right) = (90.0 + k as f64 * 590.0, 560.0 + k as f64 * 590.0);
        let x = LinearAxis { lo: 0.0, hi: 90.0, step: 15.0, p0: left, p1: right };
        let y = LinearAxis { lo, hi, step, p0: h - 90.0, p1: 60.0 };
        svg::linear_frame(&mut doc, x, YAxis::Linear(y), "impact angle from the wall normal (degrees)", label);
        let clamp = |v: f64| y.px(v.clamp(lo, hi));
        let pts: Vec<(f64, f64)> =
            (10..=890).map(|a| a as f64 / 10.0).map(|a| (x.px(a), clamp(theory(coulomb_impact(a, OXIDE_FRICTION, 0.98))))).collect();
        doc.polyline(&pts, "#222222", 1.5, Some("6,4"), 1.0);
        for (m, rows) in &data {
            let s = style(*m, false);
            let pts: Vec<(f64, f64)> = rows.iter().map(|r| (x.px(r.0), clamp(if col == 1 { r.1 } else { r.2 }))).collect();
            doc.polyline(&pts, s.colour, 1.6, None, 0.8);
            for p in pts {
                doc.marker(s.shape, p.0, p.1, 7.0, s.colour, false);
            }
        }
    }
    let legend = vec![
        (style(History, false), "Hertz–Mindlin".to_string()),
        (style(ViscousCoulomb, false), "viscous-Coulomb".to_string()),
        (Style { colour: "#222222", shape: Shape::Cross, dashed: true }, "rigid-body Coulomb theory (5/7 if sticking)".to_string()),
    ];
    doc.legend(300.0, 350.0, &legend, true, 12.0);
    (doc.finish(), csv)
}
