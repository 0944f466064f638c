//! Agglomerates (issue 7): detection on known configurations, periodic images, and the
//! stickiness threshold of a cohesive head-on pair, through full runs and agglomerates.csv.

use glam::DVec3;
use std::path::{Path, PathBuf};
use tumble::agglomerates::{agglomerate_list, agglomerates};
use tumble::{RunOptions, compile, parse_scene, run_compiled};
use tumble_geom::PeriodicBox;
use tumble_testkit::scenes::{replaced, test_scene};

fn out_dir(tag: &str) -> PathBuf {
    std::env::temp_dir().join(format!("tumble-agglo-{}-{tag}", std::process::id()))
}

/// The last data row of agglomerates.csv as (header name → value).
fn last_row(dir: &Path) -> Vec<(String, f64)> {
    let text = std::fs::read_to_string(dir.join("agglomerates.csv")).unwrap();
    let mut lines = text.lines();
    let header: Vec<String> = lines.next().unwrap().split(',').map(String::from).collect();
    let last = lines.last().unwrap();
    header.into_iter().zip(last.split(',').map(|v| v.parse::<f64>().unwrap())).collect()
}

fn column(row: &[(String, f64)], name: &str) -> f64 {
    row.iter().find(|(k, _)| k == name).unwrap_or_else(|| panic!("no column {name}")).1
}

#[test]
fn two_pressed_spheres_are_one_agglomerate_with_the_closed_form_void_fraction() {
    let r = 0.025;
    // Pressed by δ = 1e-9 m: one agglomerate of 2; the enclosing sphere has radius r + |d|/2.
    let d = 2.0 * r - 1e-9;
    let x = [DVec3::new(0.3, 0.2, 0.1), DVec3::new(0.3 + d, 0.2, 0.1)];
    let s = agglomerates(&x, &[r, r], None);
    assert_eq!((s.count, s.max_size, s.multi_count), (1, 2, 1));
    let exact = 1.0 - 2.0 * r.powi(3) / (r + 0.5 * d).powi(3);
    assert!((s.mean_void_fraction - exact).abs() < 1e-12, "{} vs {exact}", s.mean_void_fraction);
    // Two touching spheres: 1 − 2·(4/3)πr³ / ((4/3)π(2r)³) = 0.75.
    assert!((s.mean_void_fraction - 0.75).abs() < 1e-6);
    // Just apart (δ < 0): two single particles, void fraction 0.
    let apart = [x[0], DVec3::new(0.3 + 2.0 * r + 1e-9, 0.2, 0.1)];
    let s = agglomerates(&apart, &[r, r], None);
    assert_eq!((s.count, s.max_size, s.mean_void_fraction), (2, 1, 0.0));
}

#[test]
fn an_agglomerate_across_a_periodic_boundary_is_counted_once() {
    let l = 1.0;
    let b = PeriodicBox { min: DVec3::ZERO, max: DVec3::splat(l), periodic: [true; 3] };
    let r = 0.05;
    // A pair straddling the x seam, a triple around the corner (0, 0, 0) and a lone particle.
    let x = [
        DVec3::new(0.01, 0.5, 0.5),
        DVec3::new(l - 0.0899, 0.5, 0.5),
        DVec3::new(0.02, 0.02, 0.02),
        DVec3::new(l - 0.05, 0.02, 0.02),
        DVec3::new(0.02, l - 0.05, 0.02),
        DVec3::new(0.5, 0.2, 0.8),
    ];
    let radii = [r; 6];
    let s = agglomerates(&x, &radii, Some(&b));
    assert_eq!((s.count, s.max_size), (3, 3));
    assert_eq!(s.histogram, vec![1, 2, 0]);
    let list = agglomerate_list(&x, &radii, Some(&b));
    // The unwrapped pair is two touching spheres: void fraction ≈ 0.75, not a box-sized sphere.
    let pair = list.iter().find(|a| a.members == vec![0, 1]).unwrap();
    assert!((pair.void_fraction - 0.75).abs() < 2e-3 && pair.radius < 0.1 + 1e-9, "{pair:?}");
    // Without periodic images the same particles are six single ones.
    assert_eq!(agglomerates(&x, &radii, None).count, 6);
}

/// `scenes/test/cohesive_head_on.toml`: two cohesive spheres approaching head-on at relative
/// speed u, with k_c from a target Sy.
fn head_on_pair(sy: f64) -> String {
    let text = replaced(&test_scene("cohesive_head_on"), "name = \"head-on-sy-1.25\"", &format!("name = \"head-on-sy-{sy}\""));
    replaced(&text, "stickiness_number = 1.25", &format!("stickiness_number = {sy}"))
}

/// The threshold is sharp: Sy = 1.02 sticks and 0.98 separates too (checked by hand; 5 % margins kept here).
#[test]
fn a_cohesive_head_on_pair_sticks_above_sy_1_and_separates_below() {
    for (sy, stuck) in [(1.25, true), (1.05, true), (0.95, false), (0.8, false)] {
        let compiled = compile(&parse_scene(&head_on_pair(sy)).unwrap()).unwrap();
        assert!(compiled.plan.run.agglomerates, "cohesion turns agglomerates.csv on");
        let reported = compiled.plan.report.targets.stickiness.expect("the plan reports Sy").number;
        assert!((reported - sy).abs() < 1e-12, "plan Sy {reported} vs {sy}");
        assert!(compiled.plan.describe(2).contains(&format!("Sy = {sy:.6}")));
        let out = out_dir(&format!("pair-{sy}"));
        let summary = run_compiled(compiled, &RunOptions { out_dir: Some(out.clone()), threads: 1, ..Default::default() }).unwrap();
        let row = last_row(&out);
        let (count, max) = (column(&row, "agglomerates"), column(&row, "max_size"));
        if stuck {
            assert_eq!((count, max), (1.0, 2.0), "Sy = {sy} must end as one agglomerate");
            assert!((column(&row, "mean_void_fraction") - 0.75).abs() < 0.01);
        } else {
            assert_eq!((count, max), (2.0, 1.0), "Sy = {sy} must end as two");
        }
        assert_eq!(summary.final_agglomerates.unwrap().count, count as usize);
        let json: serde_json::Value = serde_json::from_str(&std::fs::read_to_string(out.join("summary.json")).unwrap()).unwrap();
        assert_eq!(json["agglomerates"]["count"], serde_json::json!(count as usize));
        let _ = std::fs::remove_dir_all(&out);
    }
}

#[test]
fn stokes_number_target_and_flow_velocity() {
    let text = test_scene("tg_targets");
    let c = compile(&parse_scene(&text).unwrap()).unwrap();
    let tg = c.plan.report.targets.taylor_green.unwrap();
    assert!((tg.stokes_number.unwrap() - 5.0).abs() < 1e-12);
    assert!((tg.vortex_size - std::f64::consts::PI / 3.0).abs() < 1e-15);
    assert!((tg.mean_flow_speed - 5.0 * tumble_scene::targets::taylor_green_mean_speed_factor()).abs() < 1e-15);
    // μ = ρ d² u_0 / (18 Stk l_0).
    let mu = 2000.0 * 0.05f64.powi(2) * tg.mean_flow_speed / (18.0 * 5.0 * tg.vortex_size);
    assert!((tg.viscosity.unwrap() - mu).abs() < 1e-15 * mu);
    // Sy at the default collision speed u_0.
    let sy = c.plan.report.targets.stickiness.unwrap();
    assert!((sy.number - 0.6).abs() < 1e-12 && sy.collision_speed == tg.mean_flow_speed);
    let text = c.plan.describe(50);
    assert!(text.contains("Stk = 5.000000") && text.contains("Sy = 0.600000"), "{text}");
    // velocity = "flow": every particle starts with the local fluid velocity.
    let flow = c.plan.model.fluid.unwrap().flow;
    for i in 0..c.particles.len() {
        assert_eq!(c.particles.velocity[i], flow.velocity(c.particles.position[i]));
    }
}

#[test]
fn the_example_scene_reports_stk_and_sy() {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/agglomeration_tg.toml");
    let c = tumble::load_scene(&path, None, None).unwrap();
    assert_eq!(c.particles.len(), 10_000);
    let text = c.plan.describe(c.particles.len());
    assert!(text.contains("Stk = ") && text.contains("Sy = "), "{text}");
    assert!(c.plan.run.agglomerates);
}

#[test]
fn tumble_plan_prints_stk_and_sy() {
    let scene = Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/agglomeration_tg.toml");
    let out = std::process::Command::new(env!("CARGO_BIN_EXE_tumble")).arg("plan").arg(&scene).output().unwrap();
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(out.status.success());
    assert!(text.contains("u_0 = 3.899708 m/s") && text.contains("Stk = 1.000000") && text.contains("Sy = 0.486138"), "{text}");
    assert!(text.contains("agglomerates on"), "{text}");
}
