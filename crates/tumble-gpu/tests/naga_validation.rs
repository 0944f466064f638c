//! Every WGSL module parses and validates with naga, and so does every variant
//! the plan's switches can produce (its bindings declared or stood in for, override
//! constants substituted and the module validated again); every constant of the
//! prelude has its host value in every module. Needs no GPU.

use naga::valid::{Capabilities, ValidationFlags, Validator};
use std::collections::{BTreeMap, BTreeSet};
use tumble_gpu::shaders::{MODULES, ShaderSource, Switches, sources};

fn validator() -> Validator {
    Validator::new(ValidationFlags::all(), Capabilities::all())
}

#[test]
fn every_shader_module_validates() {
    for shader in sources() {
        let module = naga::front::wgsl::parse_str(&shader.source).unwrap_or_else(|e| panic!("{}: {}", shader.name, e.emit_to_string(&shader.source)));
        validator().validate(&module).unwrap_or_else(|e| panic!("{}: {}", shader.name, e.emit_to_string(&shader.source)));
        for entry in shader.entry_points {
            assert!(module.entry_points.iter().any(|e| e.name == *entry), "{}: no entry point {entry}", shader.name);
        }
    }
}

#[test]
fn the_fluid_modules_validate() {
    for module in tumble_shaders::FLUID_MODULES {
        let source = module.source(|_| true);
        let parsed = naga::front::wgsl::parse_str(&source).unwrap_or_else(|e| panic!("{}: {}", module.name, e.emit_to_string(&source)));
        validator().validate(&parsed).unwrap_or_else(|e| panic!("{}: {}", module.name, e.emit_to_string(&source)));
        for entry in module.entry_points {
            assert!(parsed.entry_points.iter().any(|e| e.name == *entry), "{}: no entry point {entry}", module.name);
        }
    }
}

#[test]
fn every_shader_variant_validates() {
    let mut checked = 0;
    for module in MODULES {
        // Distinct (source, override set) pairs this module sees across every plan: the source
        // differs by the buffers the plan's features bind.
        let mut variants: BTreeMap<String, BTreeSet<Vec<(&str, u64)>>> = BTreeMap::new();
        for switches in Switches::all() {
            let shader = ShaderSource::new(module, &switches);
            let constants = switches.constants_for(&shader).into_iter().map(|(k, v)| (k, v.to_bits())).collect();
            variants.entry(shader.source).or_default().insert(constants);
        }
        for (source, sets) in &variants {
            let parsed = naga::front::wgsl::parse_str(source).unwrap_or_else(|e| panic!("{}: {}", module.name, e.emit_to_string(source)));
            let info = validator().validate(&parsed).unwrap_or_else(|e| panic!("{}: {}", module.name, e.emit_to_string(source)));
            for variant in sets {
                let mut constants = naga::back::PipelineConstants::default();
                for (name, bits) in variant {
                    constants.insert(name.to_string(), f64::from_bits(*bits));
                }
                let (specialised, _) = naga::back::pipeline_constants::process_overrides(&parsed, &info, None, &constants)
                    .unwrap_or_else(|e| panic!("{} {variant:?}: {e}", module.name));
                validator().validate(&specialised).unwrap_or_else(|e| panic!("{} {variant:?}: {e:?}", module.name));
                checked += 1;
            }
        }
        // The contact pass has one source per subset of history and polyhedra, times no walls,
        // static walls (the wall loads) or moving walls (their work too).
        if module.name == "forces" {
            assert_eq!(variants.len(), 12, "forces sources");
        }
    }
    println!("{checked} shader variants validated");
    assert!(checked > 100);
}

/// The value of every named `u32` constant of a parsed module.
fn u32_constants(module: &naga::Module) -> BTreeMap<String, u32> {
    module
        .constants
        .iter()
        .filter_map(|(_, c)| match (&c.name, &module.global_expressions[c.init]) {
            (Some(name), naga::Expression::Literal(naga::Literal::U32(v))) => Some((name.clone(), *v)),
            _ => None,
        })
        .collect()
}

#[test]
fn every_shared_constant_has_its_host_value_in_every_module() {
    let mut sources: Vec<(String, String)> = sources().into_iter().map(|s| (s.name.to_string(), s.source)).collect();
    sources.push(("polyhedra test".into(), tumble_gpu::shaders::polyhedra_test_source()));
    for (name, source) in sources {
        let module = naga::front::wgsl::parse_str(&source).unwrap();
        let values = u32_constants(&module);
        for (constant, host) in tumble_shaders::SHARED {
            assert_eq!(values.get(*constant), Some(host), "{name}: {constant}");
        }
    }
    // Twins the host keeps in other crates.
    assert_eq!(tumble_shaders::WALL_KEY, tumble_state::WALL_KEY);
    assert_eq!(tumble_shaders::SPHERE_SHAPE, tumble_scene::SPHERE as u32);
}

#[test]
fn moving_wall_and_lifter_variants_are_validated_and_static_scenes_compile_none_of_them() {
    let forces = sources().into_iter().find(|s| s.name == "forces").unwrap();
    let variants: BTreeSet<Vec<(&str, u64)>> =
        Switches::all().iter().map(|s| s.constants_for(&forces).into_iter().map(|(k, v)| (k, v.to_bits())).collect()).collect();
    // The contact pass is specialised on both switches, alone and together (every_shader_variant_validates checks each).
    for (moving, prisms) in [(false, false), (true, false), (false, true), (true, true)] {
        let on = |set: &Vec<(&str, u64)>, name: &str| set.iter().any(|(k, v)| *k == name && f64::from_bits(*v) == 1.0);
        assert!(variants.iter().any(|v| on(v, "MOVING") == moving && on(v, "PRISMS") == prisms), "MOVING {moving} PRISMS {prisms}");
    }
    // A static box compiles without either; the ball mill needs both.
    let scene = |path: &str| {
        let text = std::fs::read_to_string(format!("{}/../../{path}", env!("CARGO_MANIFEST_DIR"))).unwrap();
        tumble_scene::compile(&tumble_scene::parse_scene(&text).unwrap()).unwrap()
    };
    let settle = Switches::from_plan(&scene("scenes/box_settle.toml").plan);
    assert!(settle.walls && !settle.moving && !settle.prisms, "{settle:?}");
    let mill = Switches::from_plan(&scene("scenes/ball_mill.toml").plan);
    assert!(mill.moving && mill.prisms, "{mill:?}");
}

#[test]
fn the_polyhedra_module_validates() {
    let source = tumble_gpu::shaders::polyhedra_test_source();
    let module = naga::front::wgsl::parse_str(&source).unwrap_or_else(|e| panic!("polyhedra: {}", e.emit_to_string(&source)));
    validator().validate(&module).unwrap_or_else(|e| panic!("polyhedra: {}", e.emit_to_string(&source)));
    assert!(module.entry_points.iter().any(|e| e.name == "evaluate"));
}

#[test]
fn polyhedra_with_moving_walls_and_lifters_have_their_variants_validated() {
    let forces = sources().into_iter().find(|s| s.name == "forces").unwrap();
    let variants: BTreeSet<Vec<(&str, u64)>> =
        Switches::all().iter().map(|s| s.constants_for(&forces).into_iter().map(|(k, v)| (k, v.to_bits())).collect()).collect();
    let on = |set: &Vec<(&str, u64)>, name: &str| set.iter().any(|(k, v)| *k == name && f64::from_bits(*v) == 1.0);
    // The contact pass is specialised on POLYHEDRA with each of MOVING and PRISMS, alone and together.
    for (moving, prisms) in [(false, false), (true, false), (false, true), (true, true)] {
        assert!(
            variants.iter().any(|v| on(v, "POLYHEDRA") && on(v, "MOVING") == moving && on(v, "PRISMS") == prisms),
            "POLYHEDRA with MOVING {moving} PRISMS {prisms}"
        );
    }
    // The drum of cubes needs all three.
    let text = std::fs::read_to_string(format!("{}/../../scenes/drum_cubes.toml", env!("CARGO_MANIFEST_DIR"))).unwrap();
    let drum = Switches::from_plan(&tumble_scene::compile(&tumble_scene::parse_scene(&text).unwrap()).unwrap().plan);
    assert!(drum.polyhedra && drum.moving && drum.prisms, "{drum:?}");
}
