//! Mesh walls in the engine: a triangulated wall must move a sphere exactly as the analytic
//! wall it approximates does, whatever the triangulation (docs/meshes.md).

use glam::DVec3;
use std::path::PathBuf;
use tumble::{Simulation, compile, parse_scene};
use tumble_geom::box_triangles_subdivided;

/// A folder of its own for this test's mesh files.
fn folder(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("tumble-meshes-{name}-{}", std::process::id()));
    std::fs::create_dir_all(&d).unwrap();
    d
}

/// Writes an OBJ file (shortest round-trip decimals, so every coordinate reads back exactly).
fn write_obj(path: &std::path::Path, vertices: &[DVec3], triangles: &[[u32; 3]]) {
    let mut text = String::new();
    for v in vertices {
        text += &format!("v {} {} {}\n", v.x, v.y, v.z);
    }
    for t in triangles {
        text += &format!("f {} {} {}\n", t[0] + 1, t[1] + 1, t[2] + 1);
    }
    std::fs::write(path, text).unwrap();
}

/// One steel sphere (Hertz, tangential springs, EPSD2 rolling springs) with `walls`.
fn scene(domain: (DVec3, DVec3), gravity: DVec3, start: (DVec3, DVec3, DVec3), friction: f64, duration: f64, walls: &str) -> String {
    let v = |x: DVec3| format!("[{}, {}, {}]", x.x, x.y, x.z);
    let (x, u, w) = start;
    format!(
        r#"name = "mesh-test"
[run]
duration = {duration}
integrator = "verlet"
dt = 2.0e-6
output_interval = {duration}
[domain]
min = {}
max = {}
[gravity]
acceleration = {}
[[materials]]
name = "steel"
density = 7800.0
youngs_modulus = 2.0e9
poisson_ratio = 0.3
[contact]
normal = {{ model = "hertz" }}
restitution = 0.7
tangential = {{ model = "history", friction = {friction} }}
rolling_friction = 0.02
rolling_model = "epsd2"
[[particles]]
material = "steel"
shape = {{ sphere = {{ diameter = 0.02 }} }}
positions = [{}]
velocity = {}
angular_velocity = {}
{walls}
"#,
        v(domain.0),
        v(domain.1),
        v(gravity),
        v(x),
        v(u),
        v(w)
    )
}

/// Position, velocity and spin of the sphere at `samples` equal times, and the most contacts it had at once.
fn trajectory(text: &str, samples: usize) -> (Vec<[DVec3; 3]>, u64) {
    let compiled = compile(&parse_scene(text).unwrap()).unwrap_or_else(|e| panic!("{e}"));
    let mut s = Simulation::new(compiled, 1);
    let chunk = s.plan().run.steps / samples as u64;
    let mut out = Vec::new();
    let mut most = 0;
    for _ in 0..samples {
        for _ in 0..chunk / 5 {
            s.advance(5);
            most = most.max(s.observables().contacts);
        }
        let st = s.cpu().state();
        out.push([st.pos[0], st.vel[0], st.omega[0]]);
    }
    (out, most)
}

/// Largest difference of `b` from `a` relative to each quantity's largest magnitude in `a`.
fn worst(a: &[[DVec3; 3]], b: &[[DVec3; 3]]) -> [f64; 3] {
    let mut out = [0.0; 3];
    for q in 0..3 {
        let scale = a.iter().map(|s| s[q].length()).fold(0.0, f64::max);
        out[q] = a.iter().zip(b).map(|(x, y)| (x[q] - y[q]).length()).fold(0.0, f64::max) / scale;
    }
    out
}

#[test]
fn a_sphere_bouncing_in_a_triangulated_box_follows_the_analytic_box() {
    let d = folder("container");
    let (lo, hi) = (DVec3::ZERO, DVec3::new(0.2, 0.15, 0.1));
    let wall = |shape: &str| format!("[[walls]]\nname = \"box\"\nmaterial = \"steel\"\n{shape}\n");
    let mut files = Vec::new();
    for n in [1, 4] {
        let (v, mut t) = box_triangles_subdivided(lo, hi, n);
        // A container: every triangle faces inward.
        t.iter_mut().for_each(|t| t.swap(1, 2));
        let file = d.join(format!("box{n}.obj"));
        write_obj(&file, &v, &t);
        files.push((file, t.len()));
    }
    // Thrown with spin so that it arrives at all the walls it aims at at once (t = 0.04 s): into
    // the corner at the origin (three faces), and into the edge of the floor and the +x wall.
    let throws = [
        ("corner", 3, DVec3::new(0.05, 0.04, 0.03), DVec3::new(-1.0, -0.75, -0.3038)),
        ("edge", 2, DVec3::new(0.12, 0.07, 0.03), DVec3::new(1.75, 0.2, -0.3038)),
    ];
    for (what, walls, x, u) in throws {
        let start = (x, u, DVec3::new(20.0, -30.0, 10.0));
        let text = |shape: &str| scene((lo, hi), DVec3::new(0.0, 0.0, -9.81), start, 0.3, 0.12, &wall(shape));
        let (analytic, most) = trajectory(&text("box = { min = [0.0, 0.0, 0.0], max = [0.2, 0.15, 0.1] }"), 24);
        assert_eq!(most, walls, "the {what} throw must reach {walls} walls at once");
        for (file, triangles) in &files {
            let (mesh, most) = trajectory(&text(&format!("mesh = {{ file = \"{}\", closed = true }}", file.display())), 24);
            let [x, u, w] = worst(&analytic, &mesh);
            println!("{what}, container of {triangles} triangles: position {x:.1e}, velocity {u:.1e}, spin {w:.1e}; at most {most} contacts");
            assert_eq!(most, walls);
            assert!(x < 1e-9 && u < 1e-9 && w < 1e-9, "{what}, {triangles} triangles: {x:e} {u:e} {w:e}");
        }
    }
}

/// Uniform numbers in [0, 1) from a 64-bit linear congruential generator seeded with `seed`.
fn uniform(seed: u64) -> impl FnMut() -> f64 {
    let mut s = seed;
    move || {
        s = s.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
        (s >> 11) as f64 / (1u64 << 53) as f64
    }
}

/// A flat sheet over [x0, x1] × [y0, y1] at z = 0: an nx × ny grid with its inner vertices
/// moved at random within the plane and each square cut along a random diagonal.
fn random_sheet(x: (f64, f64), y: (f64, f64), nx: usize, ny: usize, seed: u64) -> (Vec<DVec3>, Vec<[u32; 3]>) {
    let mut u = uniform(seed);
    let (dx, dy) = ((x.1 - x.0) / nx as f64, (y.1 - y.0) / ny as f64);
    let mut vertices = Vec::new();
    for j in 0..=ny {
        for i in 0..=nx {
            let inner = i > 0 && i < nx && j > 0 && j < ny;
            let jitter = |d: f64, r: f64| if inner { (r - 0.5) * 0.6 * d } else { 0.0 };
            vertices.push(DVec3::new(x.0 + i as f64 * dx + jitter(dx, u()), y.0 + j as f64 * dy + jitter(dy, u()), 0.0));
        }
    }
    let triangles = cut_at_random(nx, ny, |i, j| (i + j * (nx + 1)) as u32, &mut u);
    (vertices, triangles)
}

/// The quads (i, j)–(i + 1, j + 1) of an nu × nv grid whose corner (i, j) is vertex `at(i, j)`,
/// each cut into two triangles along a diagonal drawn at random.
fn cut_at_random(nu: usize, nv: usize, at: impl Fn(usize, usize) -> u32, u: &mut impl FnMut() -> f64) -> Vec<[u32; 3]> {
    let mut triangles = Vec::new();
    for j in 0..nv {
        for i in 0..nu {
            let (a, b, c, d) = (at(i, j), at(i + 1, j), at(i + 1, j + 1), at(i, j + 1));
            if u() < 0.5 {
                triangles.extend([[a, b, c], [a, c, d]]);
            } else {
                triangles.extend([[a, b, d], [b, c, d]]);
            }
        }
    }
    triangles
}

#[test]
fn a_sphere_rolling_or_sliding_down_a_randomly_triangulated_incline_moves_as_on_the_plane() {
    let d = folder("incline");
    let (v, t) = random_sheet((-0.2, 0.8), (-0.3, 0.3), 24, 14, 7);
    let file = d.join("sheet.obj");
    write_obj(&file, &v, &t);
    // The plane tilted 25° by tilting gravity; the sphere starts on it, moving across the slope.
    let theta = 25f64.to_radians();
    let g = DVec3::new(theta.sin(), 0.0, -theta.cos()) * 9.81;
    let start = (DVec3::new(0.0, -0.1, 0.00999), DVec3::new(0.0, 0.4, 0.0), DVec3::ZERO);
    let domain = (DVec3::new(-0.2, -0.3, -0.05), DVec3::new(0.8, 0.3, 0.1));
    let wall = |shape: &str| format!("[[walls]]\nname = \"floor\"\nmaterial = \"steel\"\n{shape}\n");
    // μ = 0.5 rolls without slipping ((2/7) tan θ = 0.13); μ = 0.05 slides.
    for (what, friction) in [("rolling", 0.5), ("sliding", 0.05)] {
        let text = |shape: &str| scene(domain, g, start, friction, 0.5, &wall(shape));
        let (plane, _) = trajectory(&text("plane = { point = [0.0, 0.0, 0.0], normal = [0.0, 0.0, 1.0] }"), 15);
        let (mesh, _) = trajectory(&text(&format!("mesh = {{ file = \"{}\" }}", file.display())), 15);
        let [x, u, w] = worst(&plane, &mesh);
        let end = plane.last().unwrap();
        println!("{what} over {} triangles to {:.3?}: position {x:.1e}, velocity {u:.1e}, spin {w:.1e}", t.len(), end[0]);
        // It crossed many triangles, and moved as the mechanics of the incline say.
        assert!(end[0].x > 0.25, "{what}: {}", end[0]);
        let along = end[1].x / (9.81 * theta.sin() * 0.5);
        // Rolling: a = (5/7) g (sin θ − μ_r cos θ) with the rolling resistance μ_r = 0.02; sliding: a = g (sin θ − μ cos θ).
        let expected = if friction > 0.1 { 5.0 / 7.0 * (1.0 - 0.02 / theta.tan()) } else { 1.0 - friction / theta.tan() };
        assert!((along - expected).abs() < 0.02, "{what}: v/(g sin θ t) = {along}, expected {expected}");
        assert!(x < 1e-9 && u < 1e-9 && w < 1e-9, "{what}: {x:e} {u:e} {w:e}");
    }
}

/// The inside of an n-sided pipe along x over [x0, x1], its flat faces tangent to the circle of
/// radius `apothem` about the line y = 0, z = `apothem` (one face lies on z = 0, facing up): each
/// face cut into nx quads between its two edges, each edge's points moved at random along x and
/// each quad cut along a random diagonal.
fn random_pipe(x: (f64, f64), apothem: f64, sides: usize, nx: usize, seed: u64) -> (Vec<DVec3>, Vec<[u32; 3]>) {
    let mut u = uniform(seed);
    let half = std::f64::consts::PI / sides as f64;
    let corner = apothem / half.cos();
    let dx = (x.1 - x.0) / nx as f64;
    let mut vertices = Vec::new();
    for k in 0..sides {
        let phi = -std::f64::consts::FRAC_PI_2 - half + 2.0 * half * k as f64;
        for i in 0..=nx {
            let jitter = if i > 0 && i < nx { (u() - 0.5) * 0.6 * dx } else { 0.0 };
            vertices.push(DVec3::new(x.0 + i as f64 * dx + jitter, corner * phi.cos(), apothem + corner * phi.sin()));
        }
    }
    // Corner (i, k) is point i along the edge between faces k − 1 and k.
    let triangles = cut_at_random(nx, sides, |i, k| ((k % sides) * (nx + 1) + i) as u32, &mut u);
    (vertices, triangles)
}

#[test]
fn a_sphere_rolling_or_sliding_along_a_randomly_triangulated_pipe_moves_as_in_the_cylinder() {
    let d = folder("pipe");
    let apothem = 0.05;
    let (v, t) = random_pipe((-0.25, 0.85), apothem, 36, 40, 11);
    let file = d.join("pipe.obj");
    write_obj(&file, &v, &t);
    // The pipe tilted 25° by tilting gravity; the sphere starts on its lowest line, moving down it.
    let theta = 25f64.to_radians();
    let g = DVec3::new(theta.sin(), 0.0, -theta.cos()) * 9.81;
    let start = (DVec3::new(0.0, 0.0, 0.00999), DVec3::new(0.1, 0.0, 0.0), DVec3::new(0.0, 10.0, 0.0));
    let domain = (DVec3::new(-0.25, -0.06, -0.01), DVec3::new(0.85, 0.06, 0.11));
    let wall = |shape: &str| format!("[[walls]]\nname = \"pipe\"\nmaterial = \"steel\"\n{shape}\n");
    let cylinder =
        format!("cylinder = {{ point = [-0.25, 0.0, {apothem}], axis = [1.0, 0.0, 0.0], radius = {apothem}, length = 1.1, inside = true }}");
    for (what, friction) in [("rolling", 0.5), ("sliding", 0.05)] {
        let text = |shape: &str| scene(domain, g, start, friction, 0.4, &wall(shape));
        let (analytic, _) = trajectory(&text(&cylinder), 10);
        let (mesh, _) = trajectory(&text(&format!("mesh = {{ file = \"{}\" }}", file.display())), 10);
        let [x, u, w] = worst(&analytic, &mesh);
        let end = analytic.last().unwrap();
        println!("{what} along a pipe of {} triangles to {:.3?}: position {x:.1e}, velocity {u:.1e}, spin {w:.1e}", t.len(), end[0]);
        // It crossed many triangles, stayed on the lowest line, and moved as the incline's mechanics say.
        assert!(end[0].x > 0.2 && end[0].y.abs() < 1e-9, "{what}: {}", end[0]);
        let along = (end[1].x - 0.1) / (9.81 * theta.sin() * 0.4);
        let expected = if friction > 0.1 { 5.0 / 7.0 * (1.0 - 0.02 / theta.tan()) } else { 1.0 - friction / theta.tan() };
        assert!((along - expected).abs() < 0.02, "{what}: Δv/(g sin θ t) = {along}, expected {expected}");
        assert!(x < 1e-9 && u < 1e-9 && w < 1e-9, "{what}: {x:e} {u:e} {w:e}");
    }
}

/// The lifter bars of a scene written as one mesh: each prism's six outward faces, two
/// triangles each. Returns the number of triangles.
fn lifters_as_mesh(scene: &str, file: &std::path::Path) -> usize {
    let plan = compile(&parse_scene(scene).unwrap()).unwrap().plan;
    let (mut vertices, mut triangles) = (Vec::new(), Vec::new());
    for w in &plan.model.walls {
        if let tumble_geom::SurfaceShape::Prism(p) = &w.shape {
            for c in p.corners() {
                let k = vertices.len() as u32;
                vertices.extend(c);
                triangles.extend([[k, k + 1, k + 2], [k, k + 2, k + 3]]);
            }
        }
    }
    write_obj(file, &vertices, &triangles);
    triangles.len()
}

#[test]
fn a_ball_in_a_turning_drum_meets_lifters_given_as_a_mesh_as_it_meets_the_analytic_lifters() {
    use tumble_testkit::scenes::{replaced, test_scene};
    let drum = replaced(&test_scene("drum_one_ball"), "rpm = 10.0", "rpm = 40.0");
    let drum = replaced(&drum, "duration = 3.0", "duration = 1.2");
    let lifters = "[[walls]]\nname = \"lifters\"\nmaterial = \"steel\"\n";
    let analytic =
        format!("{drum}\n{lifters}lifters = {{ on = \"shell\", count = 4, height = 0.05, width = 0.03, face_angle = 20.0, phase = 30.0 }}\n");
    let file = folder("lifters").join("lifters.obj");
    assert_eq!(lifters_as_mesh(&analytic, &file), 48);
    let motion = "motion = { rotate = { point = [0.0, 0.0, 0.0], axis = [0.0, 0.0, 1.0], rpm = 40.0 } }";
    let meshed = format!("{drum}\n{lifters}mesh = {{ file = \"{}\", closed = true }}\n{motion}\n", file.display());
    let run = |text: &str| {
        let mut s = Simulation::new(compile(&parse_scene(text).unwrap()).unwrap_or_else(|e| panic!("{e}")), 1);
        let chunk = s.plan().run.steps / 24;
        let mut out = Vec::new();
        for _ in 0..24 {
            s.advance(chunk);
            let st = s.cpu().state();
            out.push(([st.pos[0], st.vel[0], st.omega[0]], s.wall_work()[1]));
        }
        out
    };
    let (a, b) = (run(&analytic), run(&meshed));
    let states = |r: &[([DVec3; 3], f64)]| r.iter().map(|x| x.0).collect::<Vec<_>>();
    let [x, u, w] = worst(&states(&a), &states(&b));
    let work = a.iter().zip(&b).map(|(p, q)| (p.1 - q.1).abs()).fold(0.0, f64::max) / a.iter().map(|p| p.1.abs()).fold(0.0, f64::max);
    println!("lifters as a mesh: position {x:.1e}, velocity {u:.1e}, spin {w:.1e}, lifters' work {work:.1e} (of {:.3e} J)", a.last().unwrap().1);
    // The lifters did lift the ball.
    assert!(a.last().unwrap().1 > 1e-3, "{:?}", a.last());
    assert!(x < 1e-9 && u < 1e-9 && w < 1e-9 && work < 1e-9, "{x:e} {u:e} {w:e} {work:e}");
}

#[test]
fn a_ball_rolling_over_a_bar_given_as_a_mesh_moves_as_over_the_analytic_bar() {
    use tumble_testkit::scenes::{replaced, test_scene};
    // A still drum; one low bar with sloping sides (20° to the shell) just beside the bottom; the
    // ball rolls at it, up the slope and over both ridges of the top face, comes back and rests
    // against it. Its spring follows it off a ridge onto the next face (without that: 2e-4).
    let drum = replaced(&test_scene("drum_one_ball"), "motion = { rotate = { point = [0.0, 0.0, 0.0], axis = [0.0, 0.0, 1.0], rpm = 10.0 } }", "");
    let drum = replaced(&drum, "duration = 3.0", "duration = 0.7");
    let drum = replaced(
        &drum,
        "positions = [[0.0, -0.28, 0.1]]",
        "positions = [[0.1, -0.261, 0.1]]\nvelocity = [-0.3, -0.11, 0.0]\nangular_velocity = [0.0, 0.0, 16.0]",
    );
    let bar = |phase: f64| {
        format!(
            "{drum}\n[[walls]]\nname = \"bar\"\nmaterial = \"steel\"\nlifters = {{ on = \"shell\", count = 1, height = 0.003, width = 0.03, face_angle = 70.0, phase = {phase} }}\n"
        )
    };
    // Turn the bar to 4° past the bottom, whichever way the drum's frame runs.
    let at = |phase: f64| {
        let plan = compile(&parse_scene(&bar(phase)).unwrap()).unwrap().plan;
        let c = plan.model.walls.iter().find_map(|w| if let tumble_geom::SurfaceShape::Prism(p) = &w.shape { Some(p.centre) } else { None }).unwrap();
        c.y.atan2(c.x).to_degrees()
    };
    let turn = at(10.0) - at(0.0);
    let analytic = bar((-86.0 - at(0.0)) * 10.0 / turn);
    assert!((at((-86.0 - at(0.0)) * 10.0 / turn) + 86.0).abs() < 1e-6);
    let file = folder("bar").join("bar.obj");
    assert_eq!(lifters_as_mesh(&analytic, &file), 12);
    let meshed = format!("{drum}\n[[walls]]\nname = \"bar\"\nmaterial = \"steel\"\nmesh = {{ file = \"{}\", closed = true }}\n", file.display());
    let (a, _) = trajectory(&analytic, 40);
    let (b, _) = trajectory(&meshed, 40);
    let [x, u, w] = worst(&a, &b);
    println!("a bar as a mesh: position {x:.1e}, velocity {u:.1e}, spin {w:.1e}");
    assert!(x < 1e-9 && u < 1e-9 && w < 1e-9, "{x:e} {u:e} {w:e}");
}

/// Glass `particles` (a `[[particles]]` body) settled for 0.6 s in a closed mesh box from the
/// origin to `hi` (three squares a face, two triangles each), on the CPU: the run and the box's triangles.
fn settled_in_a_mesh_box(name: &str, hi: DVec3, particles: &str) -> (Simulation, Vec<[u32; 3]>) {
    let (file, t) = container(name, hi, 3);
    let text = format!(
        r#"name = "mesh-{name}"
[run]
duration = 0.6
integrator = "verlet"
[domain]
min = [0.0, 0.0, 0.0]
max = [{}, {}, {}]
[gravity]
acceleration = [0.0, 0.0, -9.81]
[[materials]]
name = "glass"
density = 2500.0
[contact]
normal = {{ model = "linear", stiffness = 2.0e3 }}
restitution = 0.2
tangential = {{ model = "history", friction = 0.4 }}
[[particles]]
material = "glass"
{particles}
[[walls]]
name = "box"
material = "glass"
mesh = {{ file = "{}", closed = true }}
"#,
        hi.x,
        hi.y,
        hi.z,
        file.display()
    );
    let mut s = Simulation::new(compile(&parse_scene(&text).unwrap()).unwrap(), 1);
    s.advance(s.plan().run.steps);
    (s, t)
}

#[test]
fn a_bed_at_rest_on_a_mesh_presses_its_weight_on_the_floor_triangles() {
    let particles =
        "shape = { sphere = { diameter = 0.015 } }\nlattice = { min = [0.01, 0.01, 0.01], max = [0.09, 0.09, 0.1], spacing = 0.02, jitter = 0.1 }";
    let (s, t) = settled_in_a_mesh_box("bed", DVec3::new(0.1, 0.1, 0.12), particles);
    let st = s.cpu().state();
    let weight = st.mass.iter().sum::<f64>() * 9.81;
    let loads = tumble_cpu::network::mesh_loads(&s.plan().model, st, s.cpu().walls());
    let total: DVec3 = loads[0].iter().sum();
    let pass = s.cpu().wall_force()[0];
    println!("{} spheres, weight {weight:.4} N: triangles carry {total:.4?}, the step's wall force {pass:.4?}", st.len());
    assert!((total.z + weight).abs() < 1e-3 * weight, "{total} against {weight}");
    assert!((total - pass).length() < 1e-3 * weight, "{total} against {pass}");
    // The floor's 18 triangles (normal +z) carry most of the weight, the side walls the rest by
    // friction (Janssen); every triangle is pressed, none pulled.
    let mesh = match &s.cpu().walls()[0].shape {
        tumble_geom::SurfaceShape::Mesh(m) => m.clone(),
        _ => unreachable!(),
    };
    let floor: f64 = (0..t.len()).filter(|&k| mesh.body.mesh.normals[k].z > 0.5).map(|k| -loads[0][k].z).sum();
    println!("the floor carries {:.1} % of the weight", 100.0 * floor / weight);
    assert!(floor > 0.9 * weight && floor < 1.001 * weight, "floor carries {floor} of {weight}");
    assert!((0..t.len()).all(|k| -loads[0][k].dot(mesh.body.mesh.normals[k]) >= 0.0));
    // And the snapshot's walls carry each triangle's pressure.
    let data = tumble::vtk::walls_vtp(s.plan(), s.cpu().walls(), Some(&loads));
    assert!(["force", "normal_force", "shear_force", "pressure", "shear_stress"].iter().all(|n| data.cell_data.iter().any(|a| a.name == *n)));
}

/// One glass cube (linear springs, tangential springs, overlap-volume contacts) with `walls`.
fn cube_scene(start: (DVec3, DVec3, DVec3), duration: f64, walls: &str) -> String {
    let v = |x: DVec3| format!("[{}, {}, {}]", x.x, x.y, x.z);
    let (x, u, w) = start;
    format!(
        r#"name = "mesh-cube"
[run]
duration = {duration}
integrator = "verlet"
dt = 2.0e-6
output_interval = {duration}
[domain]
min = [0.0, 0.0, 0.0]
max = [0.2, 0.15, 0.1]
[gravity]
acceleration = [0.0, 0.0, -9.81]
[[materials]]
name = "glass"
density = 2500.0
[contact]
normal = {{ model = "linear", stiffness = 2.0e4 }}
restitution = 0.5
tangential = {{ model = "history", friction = 0.3 }}
[[particles]]
material = "glass"
shape = {{ cube = {{ edge = 0.02 }} }}
positions = [{}]
velocity = {}
angular_velocity = {}
[[walls]]
name = "box"
material = "glass"
{walls}
"#,
        v(x),
        v(u),
        v(w)
    )
}

/// A box of `n`×`n` squares a face, two triangles each, facing inward.
fn container(name: &str, hi: DVec3, n: usize) -> (PathBuf, Vec<[u32; 3]>) {
    let (v, mut t) = box_triangles_subdivided(DVec3::ZERO, hi, n);
    t.iter_mut().for_each(|t| t.swap(1, 2));
    let file = folder(name).join(format!("box{n}.obj"));
    write_obj(&file, &v, &t);
    (file, t)
}

#[test]
fn a_cube_tumbling_in_a_triangulated_box_follows_the_analytic_box() {
    // Thrown with spin into the corner at the origin so that it strikes edges and corners of
    // several faces, then tumbles on the floor; the mesh's flat faces are one patch each, so the
    // overlap volume, its centroid and the contact's spring must be the analytic wall's.
    let start = (DVec3::new(0.05, 0.04, 0.03), DVec3::new(-1.0, -0.75, -0.3), DVec3::new(20.0, -30.0, 10.0));
    let analytic = trajectory(&cube_scene(start, 0.12, "box = { min = [0.0, 0.0, 0.0], max = [0.2, 0.15, 0.1] }"), 24);
    println!("analytic box: at most {} contacts", analytic.1);
    assert!(analytic.1 >= 2, "the throw must reach several walls at once");
    for n in [1, 4] {
        let (file, t) = container("cube", DVec3::new(0.2, 0.15, 0.1), n);
        let (mesh, most) = trajectory(&cube_scene(start, 0.12, &format!("mesh = {{ file = \"{}\", closed = true }}", file.display())), 24);
        let [x, u, w] = worst(&analytic.0, &mesh);
        println!("cube, container of {} triangles: position {x:.1e}, velocity {u:.1e}, spin {w:.1e}; at most {most} contacts", t.len());
        assert_eq!(most, analytic.1);
        assert!(x < 1e-9 && u < 1e-9 && w < 1e-9, "{} triangles: {x:e} {u:e} {w:e}", t.len());
    }
}

#[test]
fn a_bed_of_cubes_at_rest_on_a_mesh_presses_its_weight_on_the_floor_triangles() {
    let particles = "shape = { cube = { edge = 0.012 } }\norientation = \"random\"\nlattice = { min = [0.012, 0.012, 0.012], max = [0.19, 0.14, 0.06], spacing = 0.02 }";
    let (s, t) = settled_in_a_mesh_box("cube-bed", DVec3::new(0.2, 0.15, 0.1), particles);
    let st = s.cpu().state();
    let weight = st.mass.iter().sum::<f64>() * 9.81;
    let loads = tumble_cpu::network::mesh_loads(&s.plan().model, st, s.cpu().walls());
    let total: DVec3 = loads[0].iter().sum();
    let pass = s.cpu().wall_force()[0];
    println!(
        "{} cubes, weight {weight:.4} N: triangles carry {total:.4?} ({:.1e} of the weight off), the step's wall force {pass:.4?} ({:.1e} apart)",
        st.len(),
        (total.z + weight).abs() / weight,
        (total - pass).length() / weight
    );
    assert!((total.z + weight).abs() < 2e-3 * weight, "{total} against {weight}");
    // Recomputed from the state after the step, as for spheres: the springs have moved on by one step.
    assert!((total - pass).length() < 1e-3 * weight, "{total} against {pass}");
    let mesh = match &s.cpu().walls()[0].shape {
        tumble_geom::SurfaceShape::Mesh(m) => m.clone(),
        _ => unreachable!(),
    };
    let floor: f64 = (0..t.len()).filter(|&k| mesh.body.mesh.normals[k].z > 0.5).map(|k| -loads[0][k].z).sum();
    let pressed = (0..t.len()).filter(|&k| mesh.body.mesh.normals[k].z > 0.5 && loads[0][k].z < 0.0).count();
    println!("the floor carries {:.1} % of the weight on {pressed} of its 18 triangles", 100.0 * floor / weight);
    assert!(floor > 0.9 * weight && floor < 1.001 * weight, "floor carries {floor} of {weight}");
    assert!(pressed >= 12, "only {pressed} floor triangles pressed");
    assert!((0..t.len()).all(|k| -loads[0][k].dot(mesh.body.mesh.normals[k]) >= -1e-12 * weight));
}

/// A 2D (`dimension = 2`) or 3D water scene in the domain from (0, −hi.y, 0) to `hi` with
/// `walls`, its fluid filling `region`, and one pressure probe at `probe`.
fn fluid_scene(dimension: u8, spacing: f64, hi: DVec3, region: &str, probe: DVec3, walls: &str) -> String {
    let v = |x: DVec3| format!("[{}, {}, {}]", x.x, x.y, x.z);
    let lo = DVec3::new(0.0, -hi.y, 0.0);
    format!(
        r#"
name = "fluid mesh"
[run]
duration = 0.1
output_interval = 0.05
[domain]
min = {}
max = {}
[gravity]
acceleration = [0.0, 0.0, -9.81]
[sph]
dimension = {dimension}
spacing = {spacing}
density = 1000.0
viscosity = 1.0e-3
expected_speed = 1.0
[[sph.regions]]
{region}
[[sph.probes]]
name = "deep"
pressure = {}
{walls}
"#,
        v(lo),
        v(hi),
        v(probe)
    )
}

/// The fluid's particles of a compiled scene, each kind's positions sorted.
fn fluid_and_walls(text: &str) -> (Vec<DVec3>, Vec<DVec3>, f64) {
    let compiled = compile(&parse_scene(text).unwrap()).unwrap_or_else(|e| panic!("{e}"));
    let p = compiled.fluid.unwrap();
    let h = compiled.plan.sph.unwrap().settings.h;
    let of = |kind| {
        let mut x: Vec<DVec3> = (0..p.len()).filter(|&i| p.kind[i] == kind).map(|i| p.position[i]).collect();
        x.sort_by(|a, b| (a.z, a.y, a.x).partial_cmp(&(b.z, b.y, b.x)).unwrap());
        x
    };
    (of(tumble_sph::ParticleKind::Fluid), of(tumble_sph::ParticleKind::Wall), h)
}

/// The same points, to round-off.
fn same_points(a: &[DVec3], b: &[DVec3], what: &str) {
    assert_eq!(a.len(), b.len(), "{what}: {} against {} points", a.len(), b.len());
    for (x, y) in a.iter().zip(b) {
        assert!((*x - *y).length() < 1e-12, "{what}: {x} against {y}");
    }
}

/// The tank of the analytic box `lo`–`hi` as a mesh file: its faces cut `n` × `n`, normals
/// inward (a container: the fluid is on the side they point to).
fn mesh_tank(name: &str, lo: DVec3, hi: DVec3, n: usize) -> PathBuf {
    let (v, mut t) = box_triangles_subdivided(lo, hi, n);
    for tri in &mut t {
        tri.swap(1, 2);
    }
    let path = folder(name).join("tank.obj");
    write_obj(&path, &v, &t);
    path
}

/// A tank given as a mesh gives the fluid the wall particles the analytic box gives it wherever
/// a fluid particle can see them (within 2h), and the same fluid, in 2D and 3D; the corners
/// behind the walls differ only out of every fluid particle's reach (the mesh's layers are a
/// distance deep, the box's a lattice square).
#[test]
fn a_fluid_tank_given_as_a_mesh_starts_as_the_analytic_tank() {
    for (dimension, spacing, hi) in [(2, 0.005, DVec3::new(0.1, 0.01, 0.15)), (3, 0.01, DVec3::new(0.1, 0.03, 0.15))] {
        let lo = DVec3::new(0.0, -hi.y, 0.0);
        let region = format!("box = {{ min = [0.0, {}, 0.0], max = [0.1, {}, 0.08] }}", lo.y, hi.y);
        let probe = DVec3::new(0.05, 0.5 * (lo.y + hi.y), 0.02);
        let analytic = fluid_scene(
            dimension,
            spacing,
            hi,
            &region,
            probe,
            &format!("[[walls]]\nbox = {{ min = [0.0, {}, 0.0], max = [0.1, {}, 0.15] }}", lo.y, hi.y),
        );
        let tank = mesh_tank(&format!("fluid-tank-{dimension}d"), lo, hi, 3);
        let mesh = fluid_scene(dimension, spacing, hi, &region, probe, &format!("[[walls]]\nmesh = {{ file = \"{}\" }}", tank.display()));
        let (fluid_a, walls_a, h) = fluid_and_walls(&analytic);
        let (fluid_m, walls_m, _) = fluid_and_walls(&mesh);
        same_points(&fluid_a, &fluid_m, &format!("{dimension}D fluid"));
        let seen =
            |walls: &[DVec3]| -> Vec<DVec3> { walls.iter().copied().filter(|w| fluid_a.iter().any(|f| (*f - *w).length() < 2.0 * h)).collect() };
        let (seen_a, seen_m) = (seen(&walls_a), seen(&walls_m));
        println!(
            "{dimension}D: {} fluid, walls {} (analytic) and {} (mesh), {} seen by the fluid",
            fluid_a.len(),
            walls_a.len(),
            walls_m.len(),
            seen_a.len()
        );
        assert!(seen_a.len() > 50);
        same_points(&seen_a, &seen_m, &format!("{dimension}D walls within 2h of the fluid"));
    }
}

/// Water in a tank given as a mesh, at rest or shaken, reads the pressure it reads in the
/// analytic tank, to round-off, after 0.1 s (2D, 20 particles over its height).
#[test]
fn water_at_rest_in_a_mesh_tank_reads_the_analytic_tanks_pressure() {
    let hi = DVec3::new(0.1, 0.01, 0.15);
    let region = "box = { min = [0.0, -0.01, 0.0], max = [0.1, 0.01, 0.1] }";
    let probe = DVec3::new(0.05, 0.0, 0.02);
    let tank = mesh_tank("fluid-rest", DVec3::new(0.0, -0.01, 0.0), hi, 1);
    let read = |walls: &str| {
        let text = fluid_scene(2, 0.005, hi, region, probe, walls);
        let mut sim = Simulation::new(compile(&parse_scene(&text).unwrap()).unwrap(), 1);
        let steps = sim.plan().run.steps;
        sim.advance(steps);
        let tables = sim.fluid_phase().unwrap().tables();
        tables.iter().find(|t| t.file == "probe_deep.csv").unwrap().value("pressure").unwrap()
    };
    let hydrostatic = 1000.0 * 9.81 * 0.08;
    for motion in ["", "motion = { oscillate = { direction = [1.0, 0.0, 0.0], amplitude = 0.005, frequency = 2.0 } }"] {
        let analytic = read(&format!("[[walls]]\nbox = {{ min = [0.0, -0.01, 0.0], max = [0.1, 0.01, 0.15] }}\n{motion}"));
        let mesh = read(&format!("[[walls]]\nmesh = {{ file = \"{}\" }}\n{motion}", tank.display()));
        println!("{motion}: pressure 2 cm above the floor: {analytic} Pa (analytic tank), {mesh} Pa (mesh tank), rho g (H - z) = {hydrostatic} Pa");
        // At rest the water is near hydrostatic; shaken at up to 0.8 m/s² it is not.
        assert!(!motion.is_empty() || (analytic - hydrostatic).abs() < 0.05 * hydrostatic, "the analytic tank: {analytic} Pa");
        assert!((mesh - analytic).abs() < 1e-9 * hydrostatic, "{mesh} Pa in the mesh tank against {analytic} Pa in the analytic one");
    }
}

/// A closed prism of `sides` sides around the y axis through (x0, ·, z0), radius `r`, from
/// y = `y0` to `y1`, normals outward.
fn prism(sides: usize, x0: f64, z0: f64, r: f64, y0: f64, y1: f64) -> (Vec<DVec3>, Vec<[u32; 3]>) {
    let ring = |y: f64| {
        (0..sides).map(move |k| {
            let a = std::f64::consts::TAU * k as f64 / sides as f64;
            DVec3::new(x0 + r * a.cos(), y, z0 + r * a.sin())
        })
    };
    let mut v: Vec<DVec3> = ring(y0).chain(ring(y1)).collect();
    v.push(DVec3::new(x0, y0, z0));
    v.push(DVec3::new(x0, y1, z0));
    let (n, c0, c1) = (sides as u32, 2 * sides as u32, 2 * sides as u32 + 1);
    let mut t = Vec::new();
    for k in 0..n {
        let j = (k + 1) % n;
        // The side, and the two caps; corners counter-clockwise seen from outside.
        t.push([k, n + k, j]);
        t.push([j, n + k, n + j]);
        t.push([c0, k, j]);
        t.push([c1, n + j, n + k]);
    }
    (v, t)
}

/// The fluid fills the inside of a closed mesh (a 48-sided prism, 2D and 3D) to its volume within
/// the lattice's error, never outside it, and with a box only the part inside the box.
#[test]
fn a_fluid_region_inside_a_closed_mesh_fills_its_volume() {
    let (r, y0, y1) = (0.05, -0.03, 0.03);
    let (v, t) = prism(48, 0.06, 0.06, r, y0, y1);
    let (vol, area) = {
        let a = 0.5 * 48.0 * r * r * (std::f64::consts::TAU / 48.0).sin();
        (a * (y1 - y0), a)
    };
    let path = folder("fluid-region").join("prism.obj");
    write_obj(&path, &v, &t);
    let mut flipped = t.clone();
    for tri in &mut flipped {
        tri.swap(1, 2);
    }
    let flipped_path = folder("fluid-region").join("prism_inward.obj");
    write_obj(&flipped_path, &v, &flipped);
    for (dimension, spacing) in [(2u8, 0.0025), (3, 0.005)] {
        for file in [&path, &flipped_path] {
            let hi = DVec3::new(0.12, 0.04, 0.12);
            let region = format!("mesh = {{ file = \"{}\" }}", file.display());
            let text = fluid_scene(dimension, spacing, hi, &region, DVec3::new(0.06, 0.0, 0.03), "");
            let (fluid, walls, _) = fluid_and_walls(&text);
            assert!(walls.is_empty());
            let expected = if dimension == 2 { area / (spacing * spacing) } else { vol / spacing.powi(3) };
            let error = fluid.len() as f64 / expected - 1.0;
            println!(
                "{dimension}D {}: {} fluid particles against {expected:.1} from the volume ({:+.2} %)",
                file.display(),
                fluid.len(),
                100.0 * error
            );
            assert!(error.abs() < 0.02, "{dimension}D: {} particles for {expected:.1}", fluid.len());
            let apothem = r * (std::f64::consts::PI / 48.0).cos();
            assert!(fluid.iter().all(|x| (x.x - 0.06).hypot(x.z - 0.06) < r && x.y > y0 && x.y < y1));
            assert!(fluid.iter().any(|x| (x.x - 0.06).hypot(x.z - 0.06) > apothem - spacing));
            // Filled to a level: only the part below z = 0.06.
            let level = format!("{region}\nbox = {{ min = [0.0, {y0}, 0.0], max = [0.12, {y1}, 0.06] }}");
            let (half, _, _) = fluid_and_walls(&fluid_scene(dimension, spacing, hi, &level, DVec3::new(0.06, 0.0, 0.03), ""));
            assert!(
                half.iter().all(|x| x.z < 0.06) && (half.len() as f64 / fluid.len() as f64 - 0.5).abs() < 0.03,
                "{} of {}",
                half.len(),
                fluid.len()
            );
        }
    }
}

/// A 2D drum of radius 0.1 m full of water, started at 20 rpm about y, with `lifters` (a
/// `[[walls]]` entry, or nothing); its water's angular momentum about the axis over that of the
/// water turning with the drum as a solid, after 0.25 s.
fn drum_spin_up(lifters: &str) -> (f64, usize) {
    let text = format!(
        r#"
name = "fluid lifters"
[run]
duration = 0.25
output_interval = 0.05
[domain]
min = [-0.12, -0.01, -0.12]
max = [0.12, 0.01, 0.12]
[gravity]
acceleration = [0.0, 0.0, -9.81]
[sph]
dimension = 2
spacing = 0.005
density = 1000.0
viscosity = 1.0e-3
expected_speed = 0.5
viscosity_model = {{ model = "artificial", alpha = 0.1 }}
[[sph.regions]]
cylinder = {{ point = [0.0, -0.01, 0.0], axis = [0.0, 1.0, 0.0], radius = 0.1, length = 0.02 }}
[[walls]]
name = "drum"
cylinder = {{ point = [0.0, -0.01, 0.0], axis = [0.0, 1.0, 0.0], radius = 0.1, length = 0.02 }}
motion = {{ rotate = {{ point = [0.0, 0.0, 0.0], axis = [0.0, 1.0, 0.0], rpm = 20.0 }} }}
{lifters}
"#
    );
    let compiled = compile(&parse_scene(&text).unwrap()).unwrap_or_else(|e| panic!("{e}"));
    let fluid = compiled.fluid.as_ref().unwrap();
    let bars: Vec<tumble_geom::Prism> = compiled.plan.model.lifter_bars().cloned().collect();
    // No water starts inside a bar, nor within half a spacing of one.
    for (i, &x) in fluid.position.iter().enumerate() {
        if fluid.kind[i] == tumble_sph::ParticleKind::Fluid {
            for bar in &bars {
                let outside = bar.faces.iter().map(|q| (x - q.corners[0]).dot(q.normal)).fold(f64::NEG_INFINITY, f64::max);
                assert!(outside >= 0.0025 - 1e-12, "water at {x} starts {outside} outside a bar");
            }
        }
    }
    let mut sim = Simulation::new(compiled, 1);
    let steps = sim.plan().run.steps;
    sim.advance(steps);
    let points = sim.fluid_phase().unwrap().points();
    let of = |name: &str| &points.scalars.iter().find(|s| s.0 == name).unwrap().1;
    let kind = &points.integers.iter().find(|s| s.0 == "kind").unwrap().1;
    let velocity = &points.vectors.iter().find(|s| s.0 == "velocity").unwrap().1;
    let (mass, omega) = (of("mass"), 20.0 * std::f64::consts::TAU / 60.0);
    let (mut l, mut solid) = (0.0, 0.0);
    for i in (0..points.positions.len()).filter(|&i| kind[i] == 0) {
        let r = points.positions[i];
        // About +y, the drum's axis: r × v · ŷ = z vx − x vz.
        l += mass[i] * (r.z * velocity[i].x - r.x * velocity[i].z);
        solid += mass[i] * (r.x * r.x + r.z * r.z) * omega;
    }
    (l / solid, bars.len())
}

/// Lifters on a turning drum drag its water round, as paddles: 0.25 s after the drum starts at
/// 20 rpm (a twelfth of a turn) the water holds more than half the angular momentum it would
/// turning with the drum as a solid, and well over what the bare drum's wall, which only shears
/// it, has passed on (0.61 against 0.29 measured). Bars missing from the fluid, or standing
/// still, leave the two alike.
#[test]
fn lifters_on_a_turning_drum_drag_the_water_round() {
    let (bare, none) = drum_spin_up("");
    let (lifted, bars) = drum_spin_up("[[walls]]\nname = \"bars\"\nlifters = { on = \"drum\", count = 4, height = 0.025, width = 0.01 }");
    println!("angular momentum over the solid body's after 0.25 s: {bare:.3} (bare drum), {lifted:.3} (4 lifters)");
    assert_eq!((none, bars), (0, 4));
    assert!(lifted > 0.5, "with lifters: {lifted}");
    assert!(lifted > 1.6 * bare, "bare drum: {bare}, with lifters: {lifted}");
}
