use super::*;
use std::collections::BTreeSet;

/// Module-scope constants the WGSL files declare themselves: sentinels no host code sees.
const SHADER_LOCAL: &[&str] = &[
    "POLY_BIG",
    "POLY_NONE",
    "REDUCE_KINETIC",
    "REDUCE_ROTATIONAL",
    "REDUCE_POTENTIAL",
    "REDUCE_MASS",
    "REDUCE_ELASTIC",
    "REDUCE_DISSIPATED",
    "REDUCE_FLUID",
    "VC_SHAPE",
    "VC_PLANES",
    "VC_CYLINDER",
    "CANDIDATES",
];

/// Names of the module-scope `const` declarations of a WGSL text (function-scope ones are indented).
fn module_constants(text: &str) -> Vec<&str> {
    text.lines().filter_map(|l| l.strip_prefix("const ")).map(|rest| rest.split(|c: char| c == ':' || c.is_whitespace()).next().unwrap()).collect()
}

#[test]
fn the_prelude_declares_every_shared_constant_with_its_host_value() {
    let prelude = prelude();
    for (name, value) in SHARED {
        assert!(prelude.contains(&format!("const {name}: u32 = {value}u;\n")), "{name}");
    }
    assert_eq!(module_constants(&prelude).len(), SHARED.len() + SHARED_F32.len());
    let names: BTreeSet<&str> = SHARED.iter().map(|(n, _)| *n).collect();
    assert_eq!(names.len(), SHARED.len(), "a shared constant is listed twice");
    assert_eq!((FLAG_FIXED, FLAG_DEAD, SHAPE_SHIFT, SPHERE_SHAPE, WALL_KEY), (1, 2, 16, 0xffff, 0x8000_0000));
    assert_eq!((WORKGROUP, SCAN_THREADS, SCAN_BLOCK, PRISM_HULL), (64, 256, 1024, 33));
}

#[test]
fn wgsl_files_declare_only_their_own_sentinels_and_no_bindings() {
    // A constant the host shares belongs in layout.rs (the prelude declares it); one the host
    // does not know goes in SHADER_LOCAL, so adding a constant on one side only fails here.
    let shared: BTreeSet<&str> = SHARED.iter().map(|(n, _)| *n).chain(SHARED_F32.iter().map(|(n, _)| *n)).collect();
    for (file, text) in FILES {
        for name in module_constants(text) {
            assert!(!shared.contains(name), "{file} declares {name}, which the prelude declares from layout.rs");
            assert!(
                SHADER_LOCAL.contains(&name),
                "{file} declares const {name}: move it to layout.rs if the host shares it, else list it in SHADER_LOCAL"
            );
        }
        assert!(!text.contains("@binding("), "{file} declares a binding; bindings.rs generates them");
    }
}

#[test]
fn codes_of_one_kind_are_distinct() {
    let groups: [&[u32]; 6] = [
        &[WALL_PLANE, WALL_QUAD, WALL_CYLINDER, WALL_PRISM],
        &[NORMAL_LINEAR, NORMAL_HERTZ],
        &[
            TANGENTIAL_NONE,
            TANGENTIAL_VISCOUS_COULOMB,
            TANGENTIAL_STICK_LIMITED,
            TANGENTIAL_DYNAMIC_ONLY,
            TANGENTIAL_HISTORY_LINEAR,
            TANGENTIAL_HISTORY_MINDLIN,
        ],
        &[INTEGRATOR_EULER, INTEGRATOR_SYMPLECTIC_EULER, INTEGRATOR_VERLET, INTEGRATOR_IMPLICIT_DRAG, INTEGRATOR_IMPLICIT_DRAG_SYMPLECTIC],
        &[DRAG_NONE, DRAG_STOKES, DRAG_QUADRATIC],
        &[QUERY_POLYHEDRA, QUERY_SPHERE, QUERY_WALL],
    ];
    for codes in groups {
        assert_eq!(codes.iter().collect::<BTreeSet<_>>().len(), codes.len(), "{codes:?}");
    }
    assert_eq!(FLAG_FIXED & FLAG_DEAD, 0);
    assert!(FLAG_FIXED.max(FLAG_DEAD) < 1 << SHAPE_SHIFT && SPHERE_SHAPE < 1 << (32 - SHAPE_SHIFT));
}

#[test]
fn every_wall_kind_is_a_case_of_the_sphere_dispatch_and_unknown_kinds_touch_nothing() {
    for kind in ["WALL_PLANE", "WALL_QUAD", "WALL_CYLINDER", "WALL_PRISM"] {
        assert!(GEOMETRY.contains(&format!("case {kind}: {{")), "{kind}");
    }
    for kind in ["WALL_PLANE", "WALL_QUAD", "WALL_CYLINDER"] {
        assert!(POLYHEDRON_WALLS.contains(&format!("case {kind}: {{")), "{kind}");
    }
    for text in [GEOMETRY, POLYHEDRON_WALLS] {
        assert!(text.contains("default: {\n            return no_"), "the default case returns no contact");
    }
}

#[test]
fn bindings_are_numbered_by_position_and_a_feature_that_is_off_gets_a_private_stand_in() {
    let forces = MODULES.iter().find(|m| m.name == "forces").unwrap();
    let all = bindings::declarations(forces.bindings, |_| true);
    for (k, b) in forces.bindings.iter().enumerate() {
        assert!(all.contains(&format!("@binding({k}) var<")) && all.contains(&format!(" {}: {};", b.name, b.ty)), "{}", b.name);
    }
    let none = bindings::declarations(forces.bindings, |f| f == Feature::Always);
    assert!(none.contains("var<private> orient: array<vec4<f32>, 1>;") && !none.contains("@binding(18)"));
    assert_eq!(forces.storage_buffers(|_| true), 18);
    assert_eq!(forces.storage_buffers(|f| f == Feature::Always), 13);
    for m in MODULES.iter().chain(FLUID_MODULES).chain([&POLYHEDRA_TEST_MODULE]) {
        let names: BTreeSet<&str> = m.bindings.iter().map(|b| b.name).collect();
        assert_eq!(names.len(), m.bindings.len(), "{}: a binding name twice", m.name);
        assert!(m.source(|_| true).starts_with(&prelude()), "{}", m.name);
    }
}

#[test]
fn entry_points_are_unique_across_modules() {
    // The host looks pipelines up by entry point name alone.
    let mut seen = BTreeSet::new();
    for m in MODULES.iter().chain(FLUID_MODULES) {
        for e in m.entry_points {
            assert!(seen.insert(*e), "entry point {e} of module {} is also another module's", m.name);
        }
    }
}
