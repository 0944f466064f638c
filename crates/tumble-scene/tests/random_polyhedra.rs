//! Random placement of polyhedral particles. Regression: a `random` group of cubes, boxes or
//! prisms crashed the scene compiler with a segmentation fault (an enum's inner match hoisted
//! by LLVM above the check of its variant, see particles.rs).

use tumble_scene::{compile, parse_scene};

fn scene(shape: &str, count: usize) -> String {
    format!(
        r#"
name = "random-polyhedra"
[run]
duration = 0.01
[domain]
min = [0.0, 0.0, 0.0]
max = [0.1, 0.1, 0.1]
[gravity]
acceleration = [0.0, 0.0, -9.81]
[[materials]]
name = "glass"
density = 2500.0
[contact]
normal = {{ model = "linear", stiffness = 1.0e3 }}
restitution = 0.5
[[particles]]
material = "glass"
shape = {shape}
orientation = "random"
random = {{ count = {count}, region = {{ min = [0.01, 0.01, 0.01], max = [0.09, 0.09, 0.09] }} }}
"#
    )
}

#[test]
fn random_groups_of_every_polyhedron_shape_are_placed_apart_inside_the_region() {
    let shapes = [
        "{ cube = { edge = 0.01 } }",
        "{ box = { size = [0.01, 0.005, 0.008] } }",
        "{ prism = { sides = 6, radius = 0.005, height = 0.01 } }",
        "{ platonic = { kind = \"dodecahedron\", radius = 0.006 } }",
        "{ polyhedron = { vertices = [[0.0, 0.0, 0.0], [0.01, 0.0, 0.0], [0.0, 0.01, 0.0], [0.0, 0.0, 0.01]] } }",
    ];
    for shape in shapes {
        for count in [1, 40] {
            let compiled = compile(&parse_scene(&scene(shape, count)).unwrap()).unwrap_or_else(|e| panic!("{shape}: {e}"));
            let p = &compiled.particles;
            assert_eq!(p.position.len(), count, "{shape}");
            let r = compiled.plan.model.shapes[0].body.bounding_radius();
            for (i, x) in p.position.iter().enumerate() {
                assert!(x.min_element() >= 0.01 + r - 1e-12 && x.max_element() <= 0.09 - r + 1e-12, "{shape}: particle {i} at {x} leaves the region");
                for y in &p.position[..i] {
                    assert!((*x - *y).length() >= 2.0 * r - 1e-12, "{shape}: bounding spheres overlap");
                }
            }
        }
    }
}
