//! Random placement of a size distribution near the fill limit. Regression: a sphere that
//! found no room was redrawn, so as the region filled the placed spheres grew smaller than the
//! distribution asked for.

use tumble_scene::{compile, parse_scene};

const SCENE: &str = r#"
name = "random-sizes"
[run]
duration = 0.01
[domain]
min = [0.0, 0.0, 0.0]
max = [0.3, 0.3, 0.3]
[[materials]]
name = "glass"
density = 2500.0
[contact]
normal = { model = "linear", stiffness = 1.0e3 }
restitution = 0.5
[[particles]]
material = "glass"
shape = { sphere = { diameter = { min = 0.005, max = 0.015 } } }
random = { count = 12000, region = { min = [0.0, 0.0, 0.0], max = [0.3, 0.3, 0.3] } }
"#;

#[test]
fn a_dense_random_fill_keeps_the_mean_cubed_diameter_it_was_asked_for() {
    let compiled = compile(&parse_scene(SCENE).unwrap()).unwrap();
    let p = &compiled.particles;
    assert_eq!(p.position.len(), 12_000);
    // 12,000 spheres of ⟨d³⟩ = 1.25e-6 m³ fill 29 % of the region, just under the limit.
    let mean_cube = p.radius.iter().map(|r| (2.0 * r).powi(3)).sum::<f64>() / p.radius.len() as f64;
    let expected = (0.015f64.powi(4) - 0.005f64.powi(4)) / (4.0 * 0.01);
    // The sample mean's standard error is 0.6 %; the redrawing bias was larger than 3 %.
    assert!((mean_cube / expected - 1.0).abs() < 0.02, "placed ⟨d³⟩ = {mean_cube:.4e}, asked for {expected:.4e}");
}
