//! VTK XML PolyData in the three encodings of the VTK file-format standard (VTK User's Guide,
//! "VTK File Formats", XML formats): inline ASCII, appended raw binary and zlib-compressed
//! appended binary (docs/cli.md, "Snapshots").
//!
//! Binary files declare `byte_order="LittleEndian"` and `header_type="UInt64"`; the data sit in
//! one `<AppendedData encoding="raw">` block after a `_`, each array at its `offset` (counted
//! from the byte after the `_`). Raw: a UInt64 byte count, then the values. Compressed
//! (`compressor="vtkZLibDataCompressor"`): the values are cut into blocks of [`BLOCK_SIZE`]
//! bytes, each compressed with zlib, behind the header [blocks, block size, size of the last
//! block (0 when it is full), compressed size of each block], all UInt64.

use std::fmt::Write as _;
use std::io::Write as _;
use tumble_scene::schema::SnapshotFormat;
pub use tumble_state::{Array, Cells, PolyData, Values};

/// Uncompressed bytes per zlib block (VTK's own default).
pub const BLOCK_SIZE: usize = 32768;

/// Collects the appended block while the XML is written.
struct Writer {
    format: SnapshotFormat,
    xml: String,
    appended: Vec<u8>,
}

impl Writer {
    fn array(&mut self, ty: &str, name: &str, components: usize, values: &Values) {
        let _ = write!(self.xml, "        <DataArray type=\"{ty}\" Name=\"{name}\" NumberOfComponents=\"{components}\" format=");
        if self.format == SnapshotFormat::Ascii {
            self.xml.push_str("\"ascii\">");
            for k in 0..values.len() {
                self.xml.push_str(if k % (6 * components.max(1)) == 0 { "\n          " } else { " " });
                self.xml.push_str(&values.text(k));
            }
            self.xml.push_str("\n        </DataArray>\n");
            return;
        }
        let _ = writeln!(self.xml, "\"appended\" offset=\"{}\"/>", self.appended.len());
        let bytes = values.le_bytes();
        if self.format == SnapshotFormat::Compressed {
            let blocks: Vec<Vec<u8>> = bytes.chunks(BLOCK_SIZE).map(zlib).collect();
            let last = bytes.len() % BLOCK_SIZE;
            for word in [blocks.len(), BLOCK_SIZE, last].into_iter().chain(blocks.iter().map(Vec::len)) {
                self.appended.extend((word as u64).to_le_bytes());
            }
            blocks.iter().for_each(|b| self.appended.extend(b));
        } else {
            self.appended.extend((bytes.len() as u64).to_le_bytes());
            self.appended.extend(bytes);
        }
    }

    fn data(&mut self, tag: &str, attributes: &(Option<String>, Option<String>), arrays: &[Array]) {
        if arrays.is_empty() {
            return;
        }
        let _ = write!(self.xml, "      <{tag}");
        if let Some(s) = &attributes.0 {
            let _ = write!(self.xml, " Scalars=\"{s}\"");
        }
        if let Some(v) = &attributes.1 {
            let _ = write!(self.xml, " Vectors=\"{v}\"");
        }
        self.xml.push_str(">\n");
        for a in arrays {
            self.array(a.values.vtk_type(), &a.name, a.components, &a.values);
        }
        let _ = writeln!(self.xml, "      </{tag}>");
    }

    fn cells(&mut self, tag: &str, cells: &Cells) {
        if cells.is_empty() {
            return;
        }
        let _ = writeln!(self.xml, "      <{tag}>");
        self.array("Int64", "connectivity", 1, &Values::I64(cells.connectivity.clone()));
        self.array("Int64", "offsets", 1, &Values::I64(cells.offsets.clone()));
        let _ = writeln!(self.xml, "      </{tag}>");
    }
}

fn zlib(block: &[u8]) -> Vec<u8> {
    let mut z = flate2::write::ZlibEncoder::new(Vec::with_capacity(block.len() / 2), flate2::Compression::default());
    z.write_all(block).expect("writing to memory");
    z.finish().expect("writing to memory")
}

/// The piece as a complete .vtp file in `format`.
pub fn encode(p: &PolyData, format: SnapshotFormat) -> Vec<u8> {
    let mut w = Writer { format, xml: String::with_capacity(4096), appended: Vec::new() };
    let compressor = if format == SnapshotFormat::Compressed { " compressor=\"vtkZLibDataCompressor\"" } else { "" };
    let _ = writeln!(w.xml, "<?xml version=\"1.0\"?>");
    let _ = writeln!(w.xml, "<VTKFile type=\"PolyData\" version=\"1.0\" byte_order=\"LittleEndian\" header_type=\"UInt64\"{compressor}>");
    let _ = writeln!(w.xml, "  <PolyData>");
    let _ = writeln!(
        w.xml,
        "    <Piece NumberOfPoints=\"{}\" NumberOfVerts=\"{}\" NumberOfLines=\"{}\" NumberOfStrips=\"0\" NumberOfPolys=\"{}\">",
        p.points.len() / 3,
        p.verts.len(),
        p.lines.len(),
        p.polys.len()
    );
    w.data("PointData", &p.point_attributes, &p.point_data);
    w.data("CellData", &p.cell_attributes, &p.cell_data);
    let _ = writeln!(w.xml, "      <Points>");
    w.array("Float64", "position", 3, &Values::F64(p.points.clone()));
    let _ = writeln!(w.xml, "      </Points>");
    w.cells("Verts", &p.verts);
    w.cells("Lines", &p.lines);
    w.cells("Polys", &p.polys);
    let _ = writeln!(w.xml, "    </Piece>\n  </PolyData>");
    let mut out = std::mem::take(&mut w.xml).into_bytes();
    if format != SnapshotFormat::Ascii {
        out.extend_from_slice(b"  <AppendedData encoding=\"raw\">\n   _");
        out.extend_from_slice(&w.appended);
        out.extend_from_slice(b"\n  </AppendedData>\n");
    }
    out.extend_from_slice(b"</VTKFile>\n");
    out
}
