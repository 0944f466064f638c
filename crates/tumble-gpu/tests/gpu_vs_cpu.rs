//! The GPU backend against the CPU reference on small scenes, and run-to-run
//! determinism on the GPU. Without an adapter every test prints one skip line
//! and passes. Tests share one device and run one at a time.

use std::sync::Mutex;
use tumble_cpu::CpuSimulation;
use tumble_gpu::GpuSimulation;
use tumble_scene::{CompiledScene, compile, parse_scene};

static SERIAL: Mutex<()> = Mutex::new(());

/// Runs `f` on the GPU, or prints one skip line when there is no adapter.
fn on_gpu(name: &str, f: impl FnOnce()) {
    let _guard = SERIAL.lock().unwrap_or_else(|e| e.into_inner());
    match tumble_gpu::gpu() {
        Ok(_) => f(),
        Err(e) => println!("skipped {name}: no GPU adapter ({e})"),
    }
}

fn scene(text: &str) -> CompiledScene {
    compile(&parse_scene(text).unwrap()).unwrap()
}

fn verify_scene(file: &str) -> String {
    std::fs::read_to_string(format!("{}/../../scenes/verify/{file}", env!("CARGO_MANIFEST_DIR"))).unwrap()
}

fn example_scene(file: &str) -> String {
    std::fs::read_to_string(format!("{}/../../scenes/{file}", env!("CARGO_MANIFEST_DIR"))).unwrap()
}

/// Final tracked rows of both backends after the whole run.
fn both(scene: CompiledScene) -> (Vec<tumble_cpu::TrackRow>, Vec<tumble_cpu::TrackRow>) {
    let steps = scene.plan.steps;
    let mut cpu = CpuSimulation::new(scene.clone(), 1);
    let mut gpu = GpuSimulation::new(scene).unwrap();
    cpu.advance(steps);
    gpu.advance(steps);
    (cpu.tracks(), gpu.tracks())
}

#[test]
fn normal_collision_rebounds_as_on_the_cpu() {
    on_gpu("normal_collision_rebounds_as_on_the_cpu", || {
        let (c, g) = both(scene(&verify_scene("02_normal_collision.toml")));
        println!("cpu {:?}\ngpu {:?}", c[0], g[0]);
        assert!((c[0].velocity.x - g[0].velocity.x).abs() < 1e-4 * 1.6, "{} vs {}", c[0].velocity.x, g[0].velocity.x);
        assert!((c[0].position - g[0].position).length() < 1e-5);
    });
}

#[test]
fn explore_verification_scenes() {
    on_gpu("explore", || {
        for f in [
            "01_stokes_drag.toml",
            "02_elastic_collision.toml",
            "03_sliding.toml",
            "04_cohesive_collision.toml",
            "05_quadratic_drag.toml",
            "07_hertz_impact.toml",
            "08_slide_to_roll.toml",
        ] {
            let (c, g) = both(scene(&verify_scene(f)));
            for (a, b) in c.iter().zip(&g) {
                println!(
                    "{f} id {}: dx {:.3e} dv {:.3e} dw {:.3e} | v cpu {:?} gpu {:?}",
                    a.id,
                    (a.position - b.position).length(),
                    (a.velocity - b.velocity).length(),
                    (a.angular_velocity - b.angular_velocity).length(),
                    a.velocity.to_array(),
                    b.velocity.to_array()
                );
            }
        }
    });
}
