//! Every WGSL module parses and validates with naga, and so does every variant
//! the plan's switches can produce (override constants substituted and the
//! module validated again). Needs no GPU.

use naga::valid::{Capabilities, ValidationFlags, Validator};
use std::collections::BTreeSet;
use tumble_gpu::shaders::{Switches, sources};

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
fn every_shader_variant_validates() {
    let mut checked = 0;
    for shader in sources() {
        let module = naga::front::wgsl::parse_str(&shader.source).unwrap();
        let info = validator().validate(&module).unwrap();
        // Distinct override sets this module sees across every plan.
        let variants: BTreeSet<Vec<(&str, u64)>> =
            Switches::all().iter().map(|s| s.constants_for(&shader).into_iter().map(|(k, v)| (k, v.to_bits())).collect()).collect();
        for variant in &variants {
            let mut constants = naga::back::PipelineConstants::default();
            for (name, bits) in variant {
                constants.insert(name.to_string(), f64::from_bits(*bits));
            }
            let (specialised, _) = naga::back::pipeline_constants::process_overrides(&module, &info, None, &constants)
                .unwrap_or_else(|e| panic!("{} {variant:?}: {e}", shader.name));
            validator().validate(&specialised).unwrap_or_else(|e| panic!("{} {variant:?}: {e:?}", shader.name));
            checked += 1;
        }
    }
    println!("{checked} shader variants validated");
    assert!(checked > 100);
}

#[test]
fn the_polyhedra_module_validates() {
    let source = tumble_gpu::shaders::polyhedra_test_source();
    let module = naga::front::wgsl::parse_str(&source).unwrap_or_else(|e| panic!("polyhedra: {}", e.emit_to_string(&source)));
    validator().validate(&module).unwrap_or_else(|e| panic!("polyhedra: {}", e.emit_to_string(&source)));
    assert!(module.entry_points.iter().any(|e| e.name == "evaluate"));
}
