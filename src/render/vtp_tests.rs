//! The reader against hand-built files: the same two particles and one triangle written in
//! ASCII, appended raw (UInt64 and UInt32 headers, both byte orders) and appended zlib in
//! several blocks, each decoded to the same numbers.

use super::*;
use std::io::Write as _;

const POSITIONS: [f64; 9] = [0.5, -1.25, 2.0, 3.0, 0.0, -0.125, 1.0, 1.0, 1.0];
const RADII: [f32; 3] = [0.25, 0.5, 0.75];
const IDS: [i64; 3] = [7, 1 << 40, -3];
const VELOCITY: [f64; 9] = [3.0, 4.0, 0.0, 0.0, 0.0, 0.0, 1.0, 2.0, 2.0];
const WALL: [i32; 1] = [2];

/// One array as it goes into a file: section, name, VTK type, components, value bytes in `le`.
struct Spec {
    section: &'static str,
    name: &'static str,
    ty: &'static str,
    components: usize,
    bytes: Vec<u8>,
}

fn specs(little_endian: bool) -> Vec<Spec> {
    // Each value's bytes in the file's order.
    fn order<const N: usize>(b: [u8; N], le: bool) -> Vec<u8> {
        if le { b.to_vec() } else { b.iter().rev().copied().collect() }
    }
    let le = little_endian;
    let f64s = |v: &[f64]| v.iter().flat_map(|x| order(x.to_le_bytes(), le)).collect::<Vec<u8>>();
    vec![
        Spec {
            section: "PointData",
            name: "radius",
            ty: "Float32",
            components: 1,
            bytes: RADII.iter().flat_map(|x| order(x.to_le_bytes(), le)).collect(),
        },
        Spec { section: "PointData", name: "velocity", ty: "Float64", components: 3, bytes: f64s(&VELOCITY) },
        Spec { section: "PointData", name: "id", ty: "Int64", components: 1, bytes: IDS.iter().flat_map(|x| order(x.to_le_bytes(), le)).collect() },
        Spec { section: "CellData", name: "wall", ty: "Int32", components: 1, bytes: WALL.iter().flat_map(|x| order(x.to_le_bytes(), le)).collect() },
        Spec { section: "Points", name: "position", ty: "Float64", components: 3, bytes: f64s(&POSITIONS) },
        Spec { section: "Polys", name: "connectivity", ty: "UInt8", components: 1, bytes: vec![2, 0, 1] },
        Spec { section: "Polys", name: "offsets", ty: "Int16", components: 1, bytes: order(3i16.to_le_bytes(), le) },
    ]
}

fn head(extra: &str, little_endian: bool) -> String {
    format!(
        "<?xml version=\"1.0\"?>\n<VTKFile type=\"PolyData\" version=\"1.0\" byte_order=\"{}\" {extra}>\n  <PolyData>\n    <Piece NumberOfPoints=\"3\" NumberOfVerts=\"0\" NumberOfPolys=\"1\">\n",
        if little_endian { "LittleEndian" } else { "BigEndian" }
    )
}

/// The sections in file order, each array's start tag written by `tag`.
fn body(specs: &[Spec], mut tag: impl FnMut(&Spec) -> String) -> String {
    let mut out = String::new();
    for section in ["PointData", "CellData", "Points", "Polys"] {
        out += &format!("      <{section}>\n");
        for s in specs.iter().filter(|s| s.section == section) {
            out += &tag(s);
        }
        out += &format!("      </{section}>\n");
    }
    out + "    </Piece>\n  </PolyData>\n"
}

fn ascii_file() -> Vec<u8> {
    let text = |s: &Spec| -> String {
        let values: Vec<f64> = decode(s.ty, &s.bytes, true);
        values.iter().map(|v| v.to_string()).collect::<Vec<_>>().join(" ")
    };
    let body = body(&specs(true), |s| {
        format!(
            "        <DataArray type=\"{}\" Name=\"{}\" NumberOfComponents=\"{}\" format=\"ascii\">\n          {}\n        </DataArray>\n",
            s.ty,
            s.name,
            s.components,
            text(s)
        )
    });
    (head("header_type=\"UInt64\"", true) + &body + "</VTKFile>\n").into_bytes()
}

/// An appended file: each array's byte count (or zlib block header) and bytes after the `_`.
fn appended_file(header_u64: bool, little_endian: bool, zlib_block: Option<usize>) -> Vec<u8> {
    let header = |n: usize| -> Vec<u8> {
        match (header_u64, little_endian) {
            (true, true) => (n as u64).to_le_bytes().to_vec(),
            (true, false) => (n as u64).to_be_bytes().to_vec(),
            (false, true) => (n as u32).to_le_bytes().to_vec(),
            (false, false) => (n as u32).to_be_bytes().to_vec(),
        }
    };
    let specs = specs(little_endian);
    let mut blob = Vec::new();
    let mut offsets = Vec::new();
    for s in &specs {
        offsets.push(blob.len());
        match zlib_block {
            None => {
                blob.extend(header(s.bytes.len()));
                blob.extend(&s.bytes);
            }
            Some(block) => {
                let blocks: Vec<&[u8]> = s.bytes.chunks(block).collect();
                let compressed: Vec<Vec<u8>> = blocks
                    .iter()
                    .map(|b| {
                        let mut z = flate2::write::ZlibEncoder::new(Vec::new(), flate2::Compression::default());
                        z.write_all(b).unwrap();
                        z.finish().unwrap()
                    })
                    .collect();
                let last = s.bytes.len() % block;
                blob.extend(header(blocks.len()));
                blob.extend(header(block));
                blob.extend(header(last));
                for c in &compressed {
                    blob.extend(header(c.len()));
                }
                compressed.iter().for_each(|c| blob.extend(c));
            }
        }
    }
    let mut k = 0;
    let body = body(&specs, |s| {
        k += 1;
        format!(
            "        <DataArray type=\"{}\" Name=\"{}\" NumberOfComponents=\"{}\" format=\"appended\" offset=\"{}\"/>\n",
            s.ty,
            s.name,
            s.components,
            offsets[k - 1]
        )
    });
    let extra = format!(
        "header_type=\"{}\"{}",
        if header_u64 { "UInt64" } else { "UInt32" },
        if zlib_block.is_some() { " compressor=\"vtkZLibDataCompressor\"" } else { "" }
    );
    let mut out = (head(&extra, little_endian) + &body + "  <AppendedData encoding=\"raw\">\n   _").into_bytes();
    out.extend(blob);
    out.extend(b"\n  </AppendedData>\n</VTKFile>\n");
    out
}

/// Where the appended arrays begin: just after the `_` that follows `<AppendedData …>`.
fn data_start(file: &[u8]) -> usize {
    let tag = find(file, b"<AppendedData").unwrap();
    tag + find(&file[tag..], b"_").unwrap() + 1
}

fn check(data: &PolyData, what: &str) {
    let points: Vec<f64> = data.points.iter().flatten().copied().collect();
    assert_eq!(points, POSITIONS, "{what}: points");
    assert_eq!(data.point_array("radius").unwrap().values, RADII.map(f64::from), "{what}: radius");
    assert_eq!(data.point_array("id").unwrap().values, IDS.map(|i| i as f64), "{what}: id");
    let velocity = data.point_array("velocity").unwrap();
    assert_eq!((velocity.components, velocity.len()), (3, 3), "{what}: velocity shape");
    assert_eq!([0, 1, 2].map(|i| velocity.scalar(i)), [5.0, 0.0, 3.0], "{what}: |velocity|");
    assert_eq!(data.cell_array("wall").unwrap().values, vec![2.0], "{what}: wall");
    assert_eq!(data.polys, vec![vec![2, 0, 1]], "{what}: polygon");
}

#[test]
fn ascii_appended_raw_and_zlib_files_decode_to_the_same_numbers() {
    check(&parse(&ascii_file()).unwrap(), "ascii");
    for header_u64 in [true, false] {
        for little_endian in [true, false] {
            let what = format!("raw, UInt64 {header_u64}, little-endian {little_endian}");
            check(&parse(&appended_file(header_u64, little_endian, None)).unwrap(), &what);
        }
    }
    // 16-byte blocks: the 72-byte arrays take five with a partial last one, the 3-byte one a single partial block.
    for block in [16, 24, 4096] {
        check(&parse(&appended_file(true, true, Some(block))).unwrap(), &format!("zlib, {block}-byte blocks"));
    }
}

#[test]
fn the_raw_appended_bytes_are_where_the_format_puts_them() {
    // The radius array is first: an 8-byte count of 12 and three little-endian f32.
    let file = appended_file(true, true, None);
    let data_start = data_start(&file);
    assert_eq!(&file[data_start..data_start + 8], &12u64.to_le_bytes());
    assert_eq!(&file[data_start + 8..data_start + 12], &0.25f32.to_le_bytes());
}

#[test]
fn damaged_files_are_refused_with_the_array_named() {
    let raw = appended_file(true, true, None);
    let cut = &raw[..raw.len() - 40];
    let e = parse(cut).unwrap_err();
    assert!(e.contains("DataArray \"offsets\"") || e.contains("DataArray \"connectivity\""), "{e}");
    let mut zlib = appended_file(true, true, Some(16));
    let at = data_start(&zlib) + 3 * 8 + 8 + 2;
    zlib[at] ^= 0xff;
    let e = parse(&zlib).unwrap_err();
    assert!(e.contains("DataArray \"radius\"") && e.contains("compressed block 0"), "{e}");
    let zlib = appended_file(true, true, Some(16));
    let at = find(&zlib, b"vtkZLib").unwrap();
    let lz4 = [&zlib[..at], b"vtkLZ4", &zlib[at + 7..]].concat();
    let e = parse(&lz4).unwrap_err();
    assert!(e.contains("compressor \"vtkLZ4DataCompressor\""), "{e}");
    let bad = String::from_utf8(ascii_file()).unwrap().replace("0.5 -1.25", "0.5 x");
    assert!(parse(bad.as_bytes()).unwrap_err().contains("DataArray \"position\": \"x\" is not a number"));
}

#[test]
fn the_run_writers_particles_and_walls_are_read_back_in_every_encoding() {
    use tumble_scene::schema::SnapshotFormat;
    let text = std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/scenes/box_settle.toml")).unwrap();
    let compiled = crate::compile(&crate::parse_scene(&text).unwrap()).unwrap();
    let state = crate::State::from_scene(&compiled);
    let first = state.id.iter().enumerate().min_by_key(|(_, id)| **id).unwrap().0;
    let gravity = compiled.plan.model.gravity;
    for format in [SnapshotFormat::Binary, SnapshotFormat::Compressed, SnapshotFormat::Ascii] {
        let particles = parse(&crate::vtk::encode(&crate::vtk::particles_vtp(&state, gravity), format)).unwrap();
        assert_eq!(particles.points.len(), state.len(), "{format:?}");
        // Binary is bit-exact; ASCII uses Rust's shortest round-trip formatting: every number comes back exactly.
        assert_eq!(particles.points[0], state.pos[first].to_array(), "{format:?}");
        assert_eq!(particles.point_array("radius").unwrap().values[0], state.radius[first], "{format:?}");
        assert_eq!(particles.point_array("velocity").unwrap().components, 3, "{format:?}");
        let walls = parse(&crate::vtk::encode(&crate::vtk::walls_vtp(&compiled.plan, &compiled.plan.model.walls, None), format)).unwrap();
        assert!(!walls.polys.is_empty() && walls.polys.iter().all(|p| p.len() == 4), "{format:?}");
        assert_eq!(walls.cell_array("wall").unwrap().len(), walls.polys.len(), "{format:?}");
    }
}
