//! Pictures on the GPU (`tumble render`): a sphere covers π r² of the frame under the known
//! orthographic projection and lands where the camera puts it, it shows its field's colour-map
//! colour, nearer surfaces hide farther ones by their true per-pixel depth, a polyhedral body
//! covers exactly the pixels of its projected faces in its particle's colour, and the images
//! are identical run to run.

use glam::DVec3;
use std::path::{Path, PathBuf};
use tumble::render::colour::{unit, viridis};
use tumble::render::gpu::{AMBIENT, BACKGROUND, DIFFUSE, LIGHT};
use tumble::render::{Camera, Picture, RenderOptions, Renderer, Sphere, Triangle, View, render_run};

/// x right, y up, looking down −z: the frame shows [−2, 2] × [−1.5, 1.5] and depths within ±2.
fn camera() -> Camera {
    Camera { right: DVec3::X, up: DVec3::Y, back: DVec3::Z, centre: DVec3::ZERO, half_width: 2.0, half_height: 1.5, depth: 2.0 }
}

fn pixel(rgba: &[u8], width: u32, (x, y): (f64, f64)) -> [u8; 3] {
    let at = 4 * (y as usize * width as usize + x as usize);
    [rgba[at], rgba[at + 1], rgba[at + 2]]
}

fn to_u8(c: [f32; 3], shade: f32) -> [u8; 3] {
    c.map(|v| (v * shade * 255.0).round() as u8)
}

fn close(a: [u8; 3], b: [u8; 3], tolerance: u8) -> bool {
    a.iter().zip(&b).all(|(a, b)| a.abs_diff(*b) <= tolerance)
}

/// Pixels that are not background: their count and their centroid (pixel centres).
fn covered(rgba: &[u8], width: u32) -> (usize, (f64, f64)) {
    let (mut n, mut sx, mut sy) = (0usize, 0.0, 0.0);
    for (k, p) in rgba.chunks_exact(4).enumerate() {
        if p != BACKGROUND {
            n += 1;
            sx += (k % width as usize) as f64 + 0.5;
            sy += (k / width as usize) as f64 + 0.5;
        }
    }
    (n, (sx / n.max(1) as f64, sy / n.max(1) as f64))
}

pub fn a_sphere_covers_pi_r_squared_where_the_camera_puts_it() {
    let (w, h) = (400, 300);
    let renderer = Renderer::new(w, h).unwrap();
    let camera = camera();
    for (centre, radius) in [(DVec3::new(0.3, -0.2, 0.0), 0.5), (DVec3::new(-1.1, 0.7, 0.9), 0.1), (DVec3::new(0.9, 0.2, -1.2), 0.75)] {
        let picture = Picture { spheres: vec![Sphere { centre, radius, colour: viridis(0.3) }], ..Default::default() };
        let rgba = renderer.draw(&picture, &camera);
        let (n, (cx, cy)) = covered(&rgba, w);
        let expected = std::f64::consts::PI * radius * radius / (4.0 * camera.half_width * camera.half_height);
        let fraction = n as f64 / (w * h) as f64;
        let error = fraction / expected - 1.0;
        let (px, py) = camera.pixel(centre, w, h);
        println!(
            "r = {radius} ({:.0} px): covered fraction {fraction:.5}, π r²/area {expected:.5}, error {:+.3} %; centroid off by ({:+.3}, {:+.3}) px",
            radius * 100.0,
            100.0 * error,
            cx - px,
            cy - py
        );
        assert!(error.abs() < if radius < 0.2 { 0.03 } else { 0.01 }, "r = {radius}: covered {fraction}, expected {expected}");
        assert!((cx - px).abs() < 0.1 && (cy - py).abs() < 0.1, "the disc's centroid ({cx}, {cy}) is not at the sphere's pixel ({px}, {py})");
    }
}

/// A run folder with one snapshot of the given particles (centre, radius, velocity), in the
/// ASCII layout src/vtk/mod.rs writes.
fn run_folder(name: &str, particles: &[(DVec3, f64, DVec3)]) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("tumble-render-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(dir.join("snapshots")).unwrap();
    let join = |f: &dyn Fn(&(DVec3, f64, DVec3)) -> String| particles.iter().map(f).collect::<Vec<_>>().join(" ");
    let array = |ty: &str, name: &str, n: usize, values: String| {
        format!("<DataArray type=\"{ty}\" Name=\"{name}\" NumberOfComponents=\"{n}\" format=\"ascii\">\n{values}\n</DataArray>\n")
    };
    let n = particles.len();
    let vtp = format!(
        "<?xml version=\"1.0\"?>\n<VTKFile type=\"PolyData\" version=\"1.0\" byte_order=\"LittleEndian\" header_type=\"UInt64\">\n<PolyData>\n<Piece NumberOfPoints=\"{n}\" NumberOfVerts=\"{n}\" NumberOfPolys=\"0\">\n<PointData Scalars=\"radius\">\n{}{}{}</PointData>\n<Points>\n{}</Points>\n</Piece>\n</PolyData>\n</VTKFile>\n",
        array("Float64", "radius", 1, join(&|p| p.1.to_string())),
        array("Float64", "velocity", 3, join(&|p| format!("{} {} {}", p.2.x, p.2.y, p.2.z))),
        array("Int64", "id", 1, (0..n).map(|i| i.to_string()).collect::<Vec<_>>().join(" ")),
        array("Float64", "position", 3, join(&|p| format!("{} {} {}", p.0.x, p.0.y, p.0.z))),
    );
    std::fs::write(dir.join("snapshots").join("particles_000000.vtp"), vtp).unwrap();
    let pvd = "<?xml version=\"1.0\"?>\n<VTKFile type=\"Collection\" version=\"0.1\">\n  <Collection>\n    <DataSet timestep=\"0\" part=\"0\" file=\"snapshots/particles_000000.vtp\"/>\n  </Collection>\n</VTKFile>\n";
    std::fs::write(dir.join("particles.pvd"), pvd).unwrap();
    dir
}

fn read_png(path: &Path) -> (u32, u32, Vec<u8>) {
    let decoder = png::Decoder::new(std::io::BufReader::new(std::fs::File::open(path).unwrap()));
    let mut reader = decoder.read_info().unwrap();
    let mut rgba = vec![0; reader.output_buffer_size().unwrap()];
    let info = reader.next_frame(&mut rgba).unwrap();
    assert_eq!(info.color_type, png::ColorType::Rgba);
    (info.width, info.height, rgba)
}

pub fn a_rendered_snapshot_shows_its_sphere_in_the_colour_of_its_speed() {
    // Speed 5 in the range [0, 8]: viridis(0.625).
    let (centre, radius) = (DVec3::new(0.01, 0.02, 0.03), 0.004);
    let dir = run_folder("colour", &[(centre, radius, DVec3::new(3.0, 0.0, 4.0))]);
    let options = RenderOptions {
        view: View::Front,
        up_axis: 1,
        range: Some((0.0, 8.0)),
        legend: false,
        fps: 0,
        width: 320,
        height: 240,
        ..Default::default()
    };
    let report = render_run(&dir, &options).unwrap();
    assert_eq!(report.frames, vec![dir.join("render").join("frame_000000.png")]);
    let (w, h, rgba) = read_png(&report.frames[0]);
    assert_eq!((w, h), (320, 240));
    // Automatic framing: the sphere's box with the 4 % margin, widened to 4:3.
    let camera = Camera::framing(View::Front, 1, centre - radius, centre + radius, 4.0 / 3.0);
    let expected = std::f64::consts::PI * radius * radius / (4.0 * camera.half_width * camera.half_height);
    let fraction = covered(&rgba, w).0 as f64 / (w * h) as f64;
    println!("framed sphere: covered fraction {fraction:.5}, π r²/area {expected:.5}, error {:+.3} %", 100.0 * (fraction / expected - 1.0));
    assert!((fraction / expected - 1.0).abs() < 0.01);
    let colour = viridis(unit(5.0, (0.0, 8.0)));
    assert_eq!(colour, viridis(0.625));
    // Where the surface faces the light the pixel is the colour-map colour itself; at the centre it is shaded.
    let r_px = radius / camera.half_height * 0.5 * h as f64;
    let (cx, cy) = camera.pixel(centre, w, h);
    let lit = (cx + LIGHT[0] as f64 * r_px, cy - LIGHT[1] as f64 * r_px);
    println!("lit pixel {:?} against {:?}; centre pixel {:?}", pixel(&rgba, w, lit), to_u8(colour, 1.0), pixel(&rgba, w, (cx, cy)));
    assert!(close(pixel(&rgba, w, lit), to_u8(colour, 1.0), 2), "the lit pixel is not viridis(0.625)");
    assert!(close(pixel(&rgba, w, (cx, cy)), to_u8(colour, AMBIENT + DIFFUSE * LIGHT[2]), 2), "the centre pixel is not viridis(0.625) shaded");
    // A colour outside the range is clamped to the map's end.
    let slow = render_run(&dir, &RenderOptions { range: Some((6.0, 9.0)), ..options }).unwrap();
    let (_, _, rgba) = read_png(&slow.frames[0]);
    assert!(close(pixel(&rgba, w, lit), to_u8(viridis(0.0), 1.0), 2));
    let _ = std::fs::remove_dir_all(&dir);
}

pub fn nearer_surfaces_hide_farther_ones_by_their_per_pixel_depth() {
    let (w, h) = (400, 300);
    let renderer = Renderer::new(w, h).unwrap();
    let camera = camera();
    let (far, near) = (viridis(0.0), viridis(1.0));
    // A big sphere and a small one whose centre sits in front of the big one's surface but
    // whose nearest point (z = 0.9) is behind the big one's (z = 1): only a per-pixel depth
    // shows the small one at its centre and the big one just inside the small one's edge.
    let big = Sphere { centre: DVec3::ZERO, radius: 1.0, colour: far };
    let small = Sphere { centre: DVec3::new(0.8, 0.0, 0.6), radius: 0.3, colour: near };
    // An opaque triangle behind both fills the frame's corners.
    let backdrop = Triangle {
        corners: [DVec3::new(-9.0, -9.0, -1.5), DVec3::new(9.0, -9.0, -1.5), DVec3::new(0.0, 9.0, -1.5)],
        colour: viridis(0.5),
        alpha: 1.0,
    };
    let mut images = Vec::new();
    for spheres in [vec![big, small], vec![small, big]] {
        let picture = Picture { spheres, triangles: vec![backdrop], ..Default::default() };
        let rgba = renderer.draw(&picture, &camera);
        let at = |x: f64, y: f64| pixel(&rgba, w, camera.pixel(DVec3::new(x, y, 0.0), w, h));
        // Small's surface at x = 0.55 is at z = 0.6 + √(0.09 − 0.0625) = 0.77, big's at √(1 − 0.3025) = 0.84.
        let small_centre = at(0.8, 0.0);
        let inside_edge = at(0.56, 0.0);
        assert!(small_centre[0] > 100 && small_centre[1] > 100, "the small sphere is hidden at its centre: {small_centre:?}");
        assert!(inside_edge[0] < 80, "the big sphere does not hide the small one's edge: {inside_edge:?}");
        // The backdrop at a corner, shaded by its normal (0, 0, ±1).
        assert!(close(at(1.9, -1.4), to_u8(viridis(0.5), AMBIENT + DIFFUSE * LIGHT[2]), 1), "{:?}", at(1.9, -1.4));
        images.push(rgba);
    }
    assert!(images[0] == images[1], "the image depends on the drawing order");
    // Half-transparent in front: the sphere shows through, blended.
    let veil =
        Triangle { corners: [DVec3::new(-9.0, -9.0, 1.5), DVec3::new(9.0, -9.0, 1.5), DVec3::new(0.0, 9.0, 1.5)], colour: [1.0; 3], alpha: 0.5 };
    let rgba = renderer.draw(&Picture { spheres: vec![big], triangles: vec![veil], ..Default::default() }, &camera);
    let shade = AMBIENT + DIFFUSE * LIGHT[2];
    let blended = far.map(|c| 0.5 * c * shade + 0.5 * shade);
    let seen = pixel(&rgba, w, camera.pixel(DVec3::ZERO, w, h));
    assert!(close(seen, to_u8(blended, 1.0), 2), "{seen:?} against {:?}", to_u8(blended, 1.0));
}

pub fn pictures_are_identical_run_to_run() {
    // 3,000 spheres in a box from a fixed LCG, and a wall.
    let mut seed: u64 = 12345;
    let mut next = || {
        seed = seed.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
        (seed >> 11) as f64 / (1u64 << 53) as f64
    };
    let spheres: Vec<Sphere> = (0..3000)
        .map(|_| Sphere { centre: DVec3::new(next() - 0.5, next() - 0.5, next() - 0.5), radius: 0.01 + 0.02 * next(), colour: viridis(next()) })
        .collect();
    let wall = Triangle {
        corners: [DVec3::new(-0.6, -0.6, -0.2), DVec3::new(0.6, -0.6, 0.3), DVec3::new(0.0, 0.6, 0.0)],
        colour: [0.6, 0.7, 0.8],
        alpha: 0.3,
    };
    let picture = Picture { spheres, triangles: vec![wall], ..Default::default() };
    let renderer = Renderer::new(640, 480).unwrap();
    let camera = Camera::framing(View::Iso, 2, DVec3::splat(-0.55), DVec3::splat(0.55), 640.0 / 480.0);
    let first = renderer.draw(&picture, &camera);
    let start = std::time::Instant::now();
    let repeats = 5;
    for _ in 0..repeats {
        assert!(renderer.draw(&picture, &camera) == first, "a second drawing differs");
    }
    println!("3,000 spheres at 640×480: {:.1} ms per frame (draw and read back)", 1e3 * start.elapsed().as_secs_f64() / repeats as f64);
    assert!(covered(&first, 640).0 > 640 * 480 / 10, "the spheres are drawn");
    // Through the files too: two renders of one run write the same bytes.
    let particles: Vec<(DVec3, f64, DVec3)> =
        picture.spheres.iter().take(500).enumerate().map(|(i, s)| (s.centre, s.radius, DVec3::new(i as f64, 0.0, 0.0))).collect();
    let dir = run_folder("determinism", &particles);
    let options = RenderOptions { view: View::Iso, fps: 4, ..Default::default() };
    let a = render_run(&dir, &options).unwrap();
    let bytes = |p: &Path| std::fs::read(p).unwrap();
    let (frame, animation) = (bytes(&a.frames[0]), bytes(a.animation.as_ref().unwrap()));
    let b = render_run(&dir, &options).unwrap();
    assert!(bytes(&b.frames[0]) == frame && bytes(b.animation.as_ref().unwrap()) == animation, "a second render wrote other bytes");
    let _ = std::fs::remove_dir_all(&dir);
}

/// A column of water at rest from a scene of fluid alone (its snapshots are `fluid.pvd` only)
/// drawn by its pressure: the highest pressure's colour (viridis(1)) shows at the bottom of the
/// picture and the lowest's (viridis(0)) at the top, each on the lit side of some particle.
pub fn a_fluid_is_drawn_in_the_colour_of_its_pressure() {
    let dir = std::env::temp_dir().join(format!("tumble-render-fluid-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    let scene = r#"
name = "column"
[run]
duration = 1.0e-4
snapshot_interval = 1.0e-4
[domain]
min = [0.0, -0.01, 0.0]
max = [0.1, 0.01, 0.15]
[gravity]
acceleration = [0.0, 0.0, -9.81]
[sph]
dimension = 2
spacing = 0.01
density = 1000.0
viscosity = 1.0e-3
expected_speed = 1.4
[[sph.regions]]
box = { min = [0.0, 0.0, 0.0], max = [0.1, 0.0, 0.1] }
"#;
    let compiled = tumble::compile(&tumble::parse_scene(scene).unwrap()).unwrap();
    tumble::run_compiled(compiled, &tumble::RunOptions { out_dir: Some(dir.clone()), threads: 1, ..Default::default() }).unwrap();
    assert!(!dir.join("particles.pvd").exists() && dir.join("fluid.pvd").exists());
    // The starting snapshot only: hydrostatic by construction.
    let options = RenderOptions {
        view: View::Front,
        up_axis: 2,
        field: "pressure".into(),
        legend: false,
        fps: 0,
        every: 2,
        width: 320,
        height: 240,
        ..Default::default()
    };
    let report = render_run(&dir, &options).unwrap();
    println!("pressure range {:?} Pa", report.range);
    assert!(report.range.0 > 0.0 && (report.range.1 - 1000.0 * 9.81 * 0.095).abs() < 5.0, "{:?}", report.range);
    let (w, _, rgba) = read_png(&report.frames[0]);
    let rows_of = |colour: [u8; 3]| -> Vec<usize> {
        rgba.chunks_exact(4).enumerate().filter(|(_, p)| close([p[0], p[1], p[2]], colour, 2)).map(|(k, _)| k / w as usize).collect()
    };
    let (high, low) = (rows_of(to_u8(viridis(1.0), 1.0)), rows_of(to_u8(viridis(0.0), 1.0)));
    let mean = |r: &[usize]| r.iter().sum::<usize>() as f64 / r.len().max(1) as f64;
    println!("viridis(1) on {} pixels at mean row {:.1}; viridis(0) on {} at mean row {:.1}", high.len(), mean(&high), low.len(), mean(&low));
    assert!(!high.is_empty() && !low.is_empty(), "both ends of the pressure range are drawn");
    assert!(mean(&high) > mean(&low) + 50.0, "the highest pressure is drawn below the lowest");
    // With the legend: the colour bar's title and the frame's time stamp in the legend's ink, in
    // the top left corner (empty background without the legend) and above the bar.
    let ink_in = |rgba: &[u8], x: std::ops::Range<usize>, y: std::ops::Range<usize>| {
        y.flat_map(|row| x.clone().map(move |col| (row, col))).filter(|&(row, col)| rgba[4 * (row * w as usize + col)..][..3] == [40, 40, 40]).count()
    };
    let corner = |rgba: &[u8]| ink_in(rgba, 0..60, 0..12);
    assert_eq!(corner(&rgba), 0, "ink in the corner without a legend");
    let report = render_run(&dir, &RenderOptions { legend: true, ..options }).unwrap();
    let (_, _, rgba) = read_png(&report.frames[0]);
    let (stamp, title) = (corner(&rgba), ink_in(&rgba, 200..320, 20..42));
    println!("legend ink: time stamp {stamp} pixels, title {title} pixels");
    assert!(stamp > 20 && title > 20, "time stamp {stamp}, title {title} pixels of ink");
    let _ = std::fs::remove_dir_all(&dir);
}

/// A folder without snapshots, or an unknown field: one line, and nothing written.
pub fn bad_input_is_refused_in_one_line() {
    let empty = std::env::temp_dir().join(format!("tumble-render-empty-{}", std::process::id()));
    std::fs::create_dir_all(&empty).unwrap();
    let e = render_run(&empty, &RenderOptions::default()).unwrap_err();
    assert!(e.contains("no particles.pvd or fluid.pvd") && e.contains("run.snapshot_interval") && !e.contains('\n'), "{e}");
    let dir = run_folder("field", &[(DVec3::ZERO, 0.1, DVec3::X)]);
    let e = render_run(&dir, &RenderOptions { field: "temperature".into(), ..Default::default() }).unwrap_err();
    assert!(e.contains("particles_000000.vtp") && e.contains("--color temperature") && e.contains("valid: speed, radius, velocity, id"), "{e}");
    assert!(!dir.join("render").exists(), "nothing is written for bad input");
    let _ = std::fs::remove_dir_all(&dir);
    let _ = std::fs::remove_dir_all(&empty);
}

/// A cube of edge `a` at `centre` (axis-aligned) as bodies_000000.vtp, its particle shape 0.
fn add_cube_body(dir: &Path, centre: DVec3, a: f64, id: i64) {
    let corners: Vec<DVec3> =
        (0..8).map(|k| centre + 0.5 * a * DVec3::new([-1.0, 1.0][k & 1], [-1.0, 1.0][(k >> 1) & 1], [-1.0, 1.0][(k >> 2) & 1])).collect();
    let faces = [[0, 1, 3, 2], [4, 5, 7, 6], [0, 1, 5, 4], [2, 3, 7, 6], [0, 2, 6, 4], [1, 3, 7, 5]];
    let points: Vec<String> = corners.iter().map(|p| format!("{} {} {}", p.x, p.y, p.z)).collect();
    let connectivity: Vec<String> = faces.iter().flatten().map(|i| i.to_string()).collect();
    let vtp = format!(
        "<?xml version=\"1.0\"?>\n<VTKFile type=\"PolyData\" version=\"1.0\" byte_order=\"LittleEndian\" header_type=\"UInt64\">\n<PolyData>\n<Piece NumberOfPoints=\"8\" NumberOfPolys=\"6\">\n<CellData Scalars=\"id\">\n<DataArray type=\"Int64\" Name=\"id\" NumberOfComponents=\"1\" format=\"ascii\">{}</DataArray>\n</CellData>\n<Points>\n<DataArray type=\"Float64\" Name=\"position\" NumberOfComponents=\"3\" format=\"ascii\">{}</DataArray>\n</Points>\n<Polys>\n<DataArray type=\"Int64\" Name=\"connectivity\" NumberOfComponents=\"1\" format=\"ascii\">{}</DataArray>\n<DataArray type=\"Int64\" Name=\"offsets\" NumberOfComponents=\"1\" format=\"ascii\">4 8 12 16 20 24</DataArray>\n</Polys>\n</Piece>\n</PolyData>\n</VTKFile>\n",
        vec![id.to_string(); 6].join(" "),
        points.join(" "),
        connectivity.join(" ")
    );
    std::fs::write(dir.join("snapshots").join("bodies_000000.vtp"), vtp).unwrap();
    let pvd = std::fs::read_to_string(dir.join("particles.pvd")).unwrap().replace("particles_", "bodies_");
    std::fs::write(dir.join("bodies.pvd"), pvd).unwrap();
    // The particle becomes polyhedron 0: drawn as its faces, not as a sphere.
    let particles = dir.join("snapshots").join("particles_000000.vtp");
    let text = std::fs::read_to_string(&particles)
        .unwrap()
        .replace("</PointData>", "<DataArray type=\"Int32\" Name=\"shape\" NumberOfComponents=\"1\" format=\"ascii\">0</DataArray>\n</PointData>");
    std::fs::write(particles, text).unwrap();
}

pub fn a_polyhedral_body_is_drawn_as_its_faces_in_its_particles_colour() {
    // A cube of edge 2 cm face-on from the front (z up, looking along +y) covers a² of the frame.
    let (centre, a) = (DVec3::new(0.1, 0.2, 0.3), 0.02);
    let circumradius = 0.5 * a * 3f64.sqrt();
    let dir = run_folder("cube", &[(centre, circumradius, DVec3::new(0.0, 0.0, -2.0))]);
    add_cube_body(&dir, centre, a, 0);
    let options = RenderOptions {
        view: View::Front,
        up_axis: 2,
        range: Some((0.0, 4.0)),
        legend: false,
        fps: 0,
        width: 320,
        height: 240,
        ..Default::default()
    };
    let report = render_run(&dir, &options).unwrap();
    let (w, h, rgba) = read_png(&report.frames[0]);
    let camera = Camera::framing(View::Front, 2, centre - circumradius, centre + circumradius, 4.0 / 3.0);
    let expected = a * a / (4.0 * camera.half_width * camera.half_height);
    let fraction = covered(&rgba, w).0 as f64 / (w * h) as f64;
    println!("cube face-on: covered fraction {fraction:.5}, a²/area {expected:.5}, error {:+.3} %", 100.0 * (fraction / expected - 1.0));
    assert!(
        (fraction / expected - 1.0).abs() < 0.02,
        "a sphere of the circumradius would cover {:.3}",
        std::f64::consts::PI * circumradius.powi(2) / (a * a)
    );
    // Exactly: the pixels whose centres fall inside the projected square.
    let (x0, y0) = camera.pixel(centre + DVec3::new(-0.5 * a, 0.0, 0.5 * a), w, h);
    let (x1, y1) = camera.pixel(centre + DVec3::new(0.5 * a, 0.0, -0.5 * a), w, h);
    let centres = |lo: f64, hi: f64| ((hi - 0.5).ceil() - (lo - 0.5).ceil()) as usize;
    let (nx, ny) = (centres(x0, x1), centres(y0, y1));
    let n = covered(&rgba, w).0;
    println!("cube face-on: {n} pixels covered, {nx} × {ny} = {} pixel centres inside the square", nx * ny);
    assert!(n.abs_diff(nx * ny) <= nx + ny, "{n} pixels against {}", nx * ny);
    // Speed 2 in [0, 4]; the face looks at the viewer: n · light = light.z.
    let seen = pixel(&rgba, w, camera.pixel(centre, w, h));
    assert!(close(seen, to_u8(viridis(0.5), AMBIENT + DIFFUSE * LIGHT[2]), 2), "{seen:?}");
    let _ = std::fs::remove_dir_all(&dir);
}
