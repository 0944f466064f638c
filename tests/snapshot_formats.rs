//! Snapshot files in the three VTK XML encodings read back, by an independent reader of the
//! VTK file-format standard written here, to exactly the state's bits; per-particle force and
//! torque against known loads; the contact network of a resting column.

use glam::DVec3;
use std::io::Read as _;
use std::path::{Path, PathBuf};
use tumble::vtk::{encode, particle_force, particle_torque, particles_vtp};
use tumble::{RunOptions, Simulation, compile, parse_scene, read_scene};
use tumble_scene::schema::{BackendName, SnapshotFormat};

fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

/// One data array as read back: its VTK type and the values' little-endian bytes.
#[derive(Debug, PartialEq)]
struct ReadArray {
    ty: String,
    components: usize,
    bytes: Vec<u8>,
}

fn attribute(tag: &str, name: &str) -> Option<String> {
    let key = format!(" {name}=\"");
    let start = tag.find(&key)? + key.len();
    Some(tag[start..].split('"').next()?.to_string())
}

fn width(ty: &str) -> usize {
    match ty {
        "Float64" | "Int64" | "UInt64" => 8,
        "Int32" | "Float32" => 4,
        other => panic!("unexpected type {other}"),
    }
}

/// Every data array of a .vtp file by name, decoded from ASCII, appended raw or zlib-compressed
/// appended data as the VTK XML format defines them.
fn read_vtp(file: &[u8]) -> Vec<(String, ReadArray)> {
    let xml_end = file.windows(13).position(|w| w == b"<AppendedData").unwrap_or(file.len());
    let xml = std::str::from_utf8(&file[..xml_end]).expect("the XML part is text");
    let head = &xml[xml.find("<VTKFile").unwrap()..];
    let head = &head[..head.find('>').unwrap()];
    assert_eq!(attribute(head, "byte_order").as_deref(), Some("LittleEndian"));
    assert_eq!(attribute(head, "header_type").as_deref(), Some("UInt64"));
    let compressed = match attribute(head, "compressor").as_deref() {
        None => false,
        Some("vtkZLibDataCompressor") => true,
        Some(other) => panic!("compressor {other}"),
    };
    let appended = (xml_end < file.len()).then(|| {
        let tag_end = xml_end + file[xml_end..].iter().position(|&b| b == b'>').unwrap();
        let tag = std::str::from_utf8(&file[xml_end..=tag_end]).unwrap();
        assert_eq!(attribute(tag, "encoding").as_deref(), Some("raw"));
        let underscore = tag_end + file[tag_end..].iter().position(|&b| b == b'_').unwrap();
        &file[underscore + 1..]
    });
    let u64_at = |data: &[u8], at: usize| u64::from_le_bytes(data[at..at + 8].try_into().unwrap()) as usize;
    let mut out = Vec::new();
    let mut rest = xml;
    while let Some(k) = rest.find("<DataArray") {
        rest = &rest[k..];
        let tag_end = rest.find('>').unwrap();
        let tag = &rest[..tag_end];
        let (ty, name) = (attribute(tag, "type").unwrap(), attribute(tag, "Name").unwrap());
        let components: usize = attribute(tag, "NumberOfComponents").unwrap().parse().unwrap();
        let bytes = match attribute(tag, "format").unwrap().as_str() {
            "ascii" => {
                let body = &rest[tag_end + 1..rest.find("</DataArray>").unwrap()];
                body.split_whitespace()
                    .flat_map(|v| match ty.as_str() {
                        "Float64" => v.parse::<f64>().unwrap().to_le_bytes().to_vec(),
                        "Int64" => v.parse::<i64>().unwrap().to_le_bytes().to_vec(),
                        "Int32" => v.parse::<i32>().unwrap().to_le_bytes().to_vec(),
                        _ => unreachable!(),
                    })
                    .collect()
            }
            "appended" => {
                let data = appended.expect("an AppendedData block");
                let at: usize = attribute(tag, "offset").unwrap().parse().unwrap();
                if compressed {
                    let (blocks, block_size, last) = (u64_at(data, at), u64_at(data, at + 8), u64_at(data, at + 16));
                    let sizes: Vec<usize> = (0..blocks).map(|b| u64_at(data, at + 24 + 8 * b)).collect();
                    let mut start = at + 24 + 8 * blocks;
                    let mut bytes = Vec::new();
                    for (b, &size) in sizes.iter().enumerate() {
                        let mut block = Vec::new();
                        flate2::read::ZlibDecoder::new(&data[start..start + size]).read_to_end(&mut block).unwrap();
                        let expected = if b + 1 == blocks && last != 0 { last } else { block_size };
                        assert_eq!(block.len(), expected, "{name}: block {b} of {blocks}");
                        bytes.extend(block);
                        start += size;
                    }
                    bytes
                } else {
                    let len = u64_at(data, at);
                    data[at + 8..at + 8 + len].to_vec()
                }
            }
            other => panic!("format {other}"),
        };
        assert_eq!(bytes.len() % (width(&ty) * components), 0, "{name}: whole tuples");
        out.push((name, ReadArray { ty, components, bytes }));
        rest = &rest[tag_end..];
    }
    out
}

fn array<'a>(arrays: &'a [(String, ReadArray)], name: &str) -> &'a ReadArray {
    &arrays.iter().find(|(n, _)| n == name).unwrap_or_else(|| panic!("no array {name}")).1
}

fn f64s(a: &ReadArray) -> Vec<u64> {
    assert_eq!(a.ty, "Float64");
    a.bytes.chunks(8).map(|c| u64::from_le_bytes(c.try_into().unwrap())).collect()
}

fn ints(a: &ReadArray) -> Vec<i64> {
    match a.ty.as_str() {
        "Int64" => a.bytes.chunks(8).map(|c| i64::from_le_bytes(c.try_into().unwrap())).collect(),
        "Int32" => a.bytes.chunks(4).map(|c| i32::from_le_bytes(c.try_into().unwrap()) as i64).collect(),
        other => panic!("{other}"),
    }
}

fn bits(v: impl IntoIterator<Item = f64>) -> Vec<u64> {
    v.into_iter().map(f64::to_bits).collect()
}

/// The pile of `scenes/test/pile.toml` (spinning, springs) after a few hundred steps.
fn pile_state() -> (Simulation, tumble::State) {
    let scene = read_scene(&root().join("scenes/test/pile.toml")).unwrap();
    let mut sim = Simulation::on(BackendName::Cpu, compile(&scene).unwrap(), 1).unwrap();
    sim.advance(300);
    let state = sim.state().into_owned();
    (sim, state)
}

#[test]
fn every_snapshot_encoding_reads_back_to_the_states_bits() {
    let (sim, s) = pile_state();
    let g = sim.plan().model.gravity;
    let mut order: Vec<usize> = (0..s.len()).collect();
    order.sort_by_key(|&i| s.id[i]);
    let vectors = |f: &dyn Fn(usize) -> DVec3| bits(order.iter().flat_map(|&i| f(i).to_array()));
    let piece = particles_vtp(&s, g);
    let mut sizes = Vec::new();
    for format in [SnapshotFormat::Ascii, SnapshotFormat::Binary, SnapshotFormat::Compressed] {
        let file = encode(&piece, format);
        sizes.push((format, file.len()));
        let arrays = read_vtp(&file);
        let check = |name: &str, expected: Vec<u64>| assert_eq!(f64s(array(&arrays, name)), expected, "{format:?}: {name}");
        check("position", vectors(&|i| s.pos[i]));
        check("velocity", vectors(&|i| s.vel[i]));
        check("angular_velocity", vectors(&|i| s.omega[i]));
        check("force", vectors(&|i| particle_force(&s, i, g)));
        check("torque", vectors(&|i| particle_torque(&s, i)));
        check("radius", bits(order.iter().map(|&i| s.radius[i])));
        assert_eq!(ints(array(&arrays, "id")), order.iter().map(|&i| s.id[i] as i64).collect::<Vec<_>>(), "{format:?}");
        assert_eq!(ints(array(&arrays, "group")), order.iter().map(|&i| s.group[i] as i64).collect::<Vec<_>>());
        assert_eq!(ints(array(&arrays, "material")), order.iter().map(|&i| s.material[i] as i64).collect::<Vec<_>>());
        assert_eq!(ints(array(&arrays, "connectivity")), (0..s.len() as i64).collect::<Vec<_>>());
        assert_eq!(ints(array(&arrays, "offsets")), (1..=s.len() as i64).collect::<Vec<_>>());
        assert_eq!(array(&arrays, "velocity").components, 3);
    }
    println!("{} particles: {sizes:?}", s.len());
    // Binary against ASCII depends on the values (a falling bed has many short zeros); zlib
    // always finds the zeros and the small integers.
    assert!(sizes[2].1 < sizes[1].1, "{sizes:?}");
}

/// More than one zlib block, a last block that is not full, and an empty array.
#[test]
fn compressed_arrays_span_blocks_and_empty_ones_read_back() {
    use tumble::vtk::{Array, Cells, PolyData};
    let n = 5000; // 3 × 8 × 5000 bytes: four blocks of 32 KiB, the last partly full.
    let points: Vec<f64> = (0..3 * n).map(|k| (k as f64).sin() * 1e3).collect();
    let piece = PolyData {
        points: points.clone(),
        verts: Cells::of((0..n).map(|k| [k])),
        point_data: vec![Array::f64("empty", 1, Vec::new()), Array::i32("odd", (0..n as i32).map(|k| k * 7 - 3).collect())],
        ..Default::default()
    };
    for format in [SnapshotFormat::Binary, SnapshotFormat::Compressed, SnapshotFormat::Ascii] {
        let arrays = read_vtp(&encode(&piece, format));
        assert_eq!(f64s(array(&arrays, "position")), bits(points.iter().copied()), "{format:?}");
        assert!(array(&arrays, "empty").bytes.is_empty());
        assert_eq!(ints(array(&arrays, "odd")), (0..n as i64).map(|k| k * 7 - 3).collect::<Vec<_>>());
    }
}

fn tmp(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("tumble-formats-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    dir
}

fn snapshot_bytes(dir: &Path) -> (u64, usize) {
    let files: Vec<_> =
        std::fs::read_dir(dir.join("snapshots")).unwrap().map(|e| e.unwrap().path()).filter(|p| p.to_string_lossy().contains("particles_")).collect();
    (files.iter().map(|p| std::fs::metadata(p).unwrap().len()).sum(), files.len())
}

/// The scene setting picks the encoding (binary by default); bytes per particle of each on a
/// shipped scene.
#[test]
fn the_scene_chooses_the_snapshot_encoding_and_bytes_per_particle_are_reported() {
    let mut per_particle = Vec::new();
    for (setting, format) in [
        ("", SnapshotFormat::Binary),
        ("snapshot_format = \"compressed\"", SnapshotFormat::Compressed),
        ("snapshot_format = \"ascii\"", SnapshotFormat::Ascii),
    ] {
        let text = std::fs::read_to_string(root().join("scenes/test/pile.toml")).unwrap();
        let text =
            text.replace("duration = 1.0", "duration = 0.02\nsnapshot_interval = 0.01\noutput_interval = 0.01") + &format!("[output]\n{setting}\n");
        let compiled = compile(&parse_scene(&text).unwrap()).unwrap();
        assert_eq!(compiled.plan.run.snapshot_format, format);
        let n = compiled.particles.len();
        let out = tmp(&format!("{format:?}"));
        tumble::run_compiled(compiled, &RunOptions { out_dir: Some(out.clone()), threads: 1, ..Default::default() }).unwrap();
        let (bytes, files) = snapshot_bytes(&out);
        let head = std::fs::read(out.join("snapshots/particles_000001.vtp")).unwrap();
        let arrays = read_vtp(&head);
        assert_eq!(array(&arrays, "position").bytes.len(), 24 * n);
        assert_eq!(read_vtp(&std::fs::read(out.join("walls.vtp")).unwrap()).len(), 6, "walls: three cell arrays, points, connectivity, offsets");
        per_particle.push((format, bytes as f64 / (files * n) as f64));
        let csv = std::fs::read_to_string(out.join("observables.csv")).unwrap();
        assert!(csv.lines().next().unwrap().ends_with(",fx_box,fy_box,fz_box,tx_box,ty_box,tz_box"), "every wall group's load: {csv}");
        assert!(csv.lines().skip(1).all(|l| l.split(',').count() == 15), "{csv}");
        let _ = std::fs::remove_dir_all(&out);
    }
    println!("pile ({} snapshots): bytes per particle {per_particle:?}", 3);
    let err = parse_scene("name = \"x\"\n[run]\nduration = 1\n[domain]\nmin = [0,0,0]\nmax = [1,1,1]\n[[materials]]\nname = \"m\"\ndensity = 1\n[contact]\nnormal = { model = \"linear\", stiffness = 1 }\nrestitution = 0.5\n[output]\nsnapshot_format = \"hdf5\"\n")
        .unwrap_err()
        .to_string();
    assert!(err.contains("snapshot_format") || err.contains("hdf5"), "{err}");
    assert!(err.contains("binary") && err.contains("compressed") && err.contains("ascii"), "names the valid values: {err}");
}

/// A floor scene of `diameter` 1 cm glass spheres at `positions`, linear contacts (k = 1e5),
/// restitution 0.5, frictionless.
fn floor_scene(positions: &str, duration: f64) -> String {
    format!(
        "name = \"floor\"\n[run]\nduration = {duration}\n[domain]\nmin = [-0.05, -0.05, 0.0]\nmax = [0.05, 0.05, 1.0]\n[gravity]\nacceleration = [0.0, 0.0, -9.81]\n\
         [[materials]]\nname = \"glass\"\ndensity = 2500.0\n[contact]\nnormal = {{ model = \"linear\", stiffness = 1.0e5 }}\nrestitution = 0.5\n\
         [[particles]]\nmaterial = \"glass\"\nshape = {{ sphere = {{ diameter = 0.01 }} }}\npositions = {positions}\n\
         [[walls]]\nname = \"floor\"\nmaterial = \"glass\"\nplane = {{ point = [0.0, 0.0, 0.0], normal = [0.0, 0.0, 1.0] }}\n"
    )
}

fn sphere_mass() -> f64 {
    2500.0 * std::f64::consts::PI / 6.0 * 0.01f64.powi(3)
}

/// A sphere resting on the floor feels m g up; one in free fall high above feels nothing.
#[test]
fn snapshot_force_is_the_floors_reaction_at_rest_and_zero_in_free_fall() {
    // Forty contact times (t_col = π √(m/k) / … about 0.4 ms): the rebound has decayed by e^40.
    let compiled = compile(&parse_scene(&floor_scene("[[0.0, 0.0, 0.005], [0.0, 0.0, 0.9]]", 0.02)).unwrap()).unwrap();
    let steps = compiled.plan.run.steps;
    let mut sim = Simulation::on(BackendName::Cpu, compiled, 1).unwrap();
    sim.advance(steps);
    let s = sim.state();
    let g = sim.plan().model.gravity;
    let by_id = |id: u32| s.id.iter().position(|&k| k == id).unwrap();
    let (rest, falling) = (by_id(0), by_id(1));
    let weight = sphere_mass() * 9.81;
    let f = particle_force(&s, rest, g);
    println!("resting: force {f} (m g = {weight}); falling: {}", particle_force(&s, falling, g));
    assert!((f - DVec3::new(0.0, 0.0, weight)).length() < 1e-6 * weight, "rest: {f} vs m g = {weight} up");
    assert!(s.vel[falling].z < -0.1, "still falling");
    assert_eq!(particle_force(&s, falling, g), DVec3::ZERO, "free fall: a = g exactly");
    assert_eq!(particle_torque(&s, rest), DVec3::ZERO, "no rotation in a frictionless scene");
}

/// The snapshot's force and torque, rebuilt from the state's accelerations, are the contact
/// pass's own sums: spheres and polyhedra with friction (world-frame R I Rᵀ α for a polyhedron).
#[test]
fn snapshot_force_and_torque_are_the_contact_passs_sums() {
    let scene = read_scene(&root().join("scenes/test/mixed_bed.toml")).unwrap();
    let compiled = compile(&scene).unwrap();
    let steps = compiled.plan.run.steps;
    let mut sim = Simulation::on(BackendName::Cpu, compiled, 2).unwrap();
    sim.advance(steps);
    let cpu = sim.backend().as_any().downcast_ref::<tumble_cpu::CpuSimulation>().unwrap();
    let (s, sums, g) = (cpu.state(), cpu.contact_sums(), sim.plan().model.gravity);
    let largest_torque = sums.iter().map(|c| c.torque.length()).fold(0.0, f64::max);
    let (mut touching, mut polyhedra) = (0, 0);
    for i in 0..s.len() {
        let (f, t) = (particle_force(s, i, g), particle_torque(s, i));
        assert!((f - sums[i].force).length() <= 1e-12 * (sums[i].force.length() + s.mass[i] * g.length()), "{i}: {f} vs {}", sums[i].force);
        assert!((t - sums[i].torque).length() <= 1e-10 * largest_torque, "{i}: {t} vs {}", sums[i].torque);
        touching += (sums[i].torque != DVec3::ZERO) as usize;
        polyhedra += (s.shape[i] != tumble_scene::SPHERE && sums[i].torque != DVec3::ZERO) as usize;
    }
    println!("{touching} of {} bodies under torque ({polyhedra} polyhedra), largest {largest_torque:e} N m", s.len());
    assert!(polyhedra > 10 && touching > 20, "the bed is in contact: {touching} bodies, {polyhedra} polyhedra");
}

/// A column of five spheres at rest on the floor: each contact carries the weight of the spheres
/// above it, in the recomputed network and in contacts_NNNNNN.vtp.
#[test]
fn the_contact_network_of_a_resting_column_carries_the_weight_above_each_contact() {
    let positions = "[[0.0, 0.0, 0.005], [0.0, 0.0, 0.015], [0.0, 0.0, 0.025], [0.0, 0.0, 0.035], [0.0, 0.0, 0.045]]";
    // The column's slowest mode decays at about 150/s: 0.2 s leaves 1e-13 of the drop.
    let text = floor_scene(positions, 0.2).replace("duration = 0.2", "duration = 0.2\nsnapshot_interval = 0.2") + "[output]\ncontacts = true\n";
    let compiled = compile(&parse_scene(&text).unwrap()).unwrap();
    let steps = compiled.plan.run.steps;
    let mut sim = Simulation::on(BackendName::Cpu, compiled.clone(), 1).unwrap();
    sim.advance(steps);
    let s = sim.state();
    let network = tumble::vtk::contacts::contact_network(sim.plan(), &s, &sim.walls());
    let weight = sphere_mass() * 9.81;
    assert_eq!(network.len(), 4, "four pairs touch: {network:?}");
    for p in &network {
        let (a, b) = (s.id[p.a], s.id[p.b]);
        assert_eq!(b, a + 1, "neighbours in the column, lower id first");
        let above = (4 - a) as f64 * weight;
        let normal = p.force.dot(p.normal);
        println!("contact {a}-{b}: normal force {normal:.9e} N, weight above {above:.9e} N");
        assert!((normal - above).abs() < 1e-6 * weight, "contact {a}-{b}: {normal} vs {above}");
        assert!((p.force - p.normal * normal).length() < 1e-9 * weight, "no tangential force");
    }
    // The run writes the same network at each snapshot.
    let out = tmp("contacts");
    tumble::run_compiled(compiled, &RunOptions { out_dir: Some(out.clone()), threads: 1, ..Default::default() }).unwrap();
    let arrays = read_vtp(&std::fs::read(out.join("snapshots/contacts_000001.vtp")).unwrap());
    let normal: Vec<f64> = f64s(array(&arrays, "normal_force")).into_iter().map(f64::from_bits).collect();
    let ids: Vec<i64> = ints(array(&arrays, "id_a"));
    assert_eq!(ids, vec![0, 1, 2, 3]);
    for (k, n) in normal.iter().enumerate() {
        assert!((n - (4 - k) as f64 * weight).abs() < 1e-6 * weight, "contacts.vtp {k}: {n}");
    }
    assert_eq!(array(&arrays, "tangential_force").components, 3);
    assert!(out.join("contacts.pvd").exists());
    let _ = std::fs::remove_dir_all(&out);
}
