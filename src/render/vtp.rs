//! A reader for the VTK XML PolyData files a run writes (and ParaView reads): points, their
//! point data, polygons and their cell data, in any of the three standard encodings: inline
//! ASCII, appended raw binary, and appended zlib-compressed binary (`vtkZLibDataCompressor`).
//!
//! Appended data follows `<AppendedData encoding="raw">` and a `_`; each `DataArray` names its
//! `offset` from just after the `_`. Uncompressed, an array is a byte count (`header_type`,
//! UInt32 or UInt64) and the bytes; compressed, it is a block header `[blocks, block size, last
//! block size, compressed size of each block]` (each a `header_type` integer) and the blocks,
//! each one zlib stream (VTK's file-format documentation, "Appended data" and "Compressed data").

use std::collections::BTreeMap;
use std::io::Read as _;
use std::path::Path;

/// One named array: `values` has `components` numbers per tuple, widened to f64.
#[derive(Clone, Debug, PartialEq)]
pub struct DataArray {
    pub name: String,
    pub components: usize,
    pub values: Vec<f64>,
}

impl DataArray {
    /// The number of tuples (points or cells).
    pub fn len(&self) -> usize {
        self.values.len() / self.components.max(1)
    }

    pub fn is_empty(&self) -> bool {
        self.values.is_empty()
    }

    /// Tuple `i` as a scalar: the value itself, or the Euclidean norm of a vector.
    pub fn scalar(&self, i: usize) -> f64 {
        let tuple = &self.values[i * self.components..(i + 1) * self.components];
        if self.components == 1 { tuple[0] } else { tuple.iter().map(|v| v * v).sum::<f64>().sqrt() }
    }
}

/// The contents of one `.vtp` file (its first piece).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct PolyData {
    pub points: Vec<[f64; 3]>,
    pub point_data: Vec<DataArray>,
    pub cell_data: Vec<DataArray>,
    /// Each polygon as indices into `points`.
    pub polys: Vec<Vec<usize>>,
}

impl PolyData {
    pub fn point_array(&self, name: &str) -> Option<&DataArray> {
        self.point_data.iter().find(|a| a.name == name)
    }

    pub fn cell_array(&self, name: &str) -> Option<&DataArray> {
        self.cell_data.iter().find(|a| a.name == name)
    }
}

/// Reads and decodes `path`; errors name the file and what is wrong in one line.
pub fn read(path: &Path) -> Result<PolyData, String> {
    let bytes = std::fs::read(path).map_err(|e| format!("{}: {e}", path.display()))?;
    parse(&bytes).map_err(|e| format!("{}: {e}", path.display()))
}

/// A start tag: its name and attributes.
#[derive(Debug)]
struct Tag {
    name: String,
    attributes: BTreeMap<String, String>,
    /// Byte range of the element's text (up to its end tag); empty for `<…/>`.
    text: std::ops::Range<usize>,
}

impl Tag {
    fn attribute(&self, key: &str) -> Option<&str> {
        self.attributes.get(key).map(String::as_str)
    }
}

/// The element structure of the XML part (everything before the appended data): a flat list
/// of start tags in document order, each with its parent's index.
fn tags(xml: &str) -> Result<Vec<(Option<usize>, Tag)>, String> {
    let mut out: Vec<(Option<usize>, Tag)> = Vec::new();
    let mut open: Vec<usize> = Vec::new();
    let mut at = 0;
    while let Some(start) = xml[at..].find('<').map(|k| at + k) {
        let end = xml[start..].find('>').map(|k| start + k).ok_or("an XML tag is not closed")?;
        let inner = &xml[start + 1..end];
        at = end + 1;
        if inner.starts_with('?') || inner.starts_with('!') {
            continue;
        }
        if let Some(name) = inner.strip_prefix('/') {
            let k = open.pop().ok_or_else(|| format!("</{name}> closes nothing"))?;
            if out[k].1.name != name.trim() {
                return Err(format!("<{}> is closed by </{}>", out[k].1.name, name.trim()));
            }
            out[k].1.text.end = start;
            continue;
        }
        let empty = inner.ends_with('/');
        let inner = inner.trim_end_matches('/');
        let name_end = inner.find(char::is_whitespace).unwrap_or(inner.len());
        let mut tag = Tag { name: inner[..name_end].to_string(), attributes: BTreeMap::new(), text: at..at };
        let mut rest = &inner[name_end..];
        while let Some(eq) = rest.find('=') {
            let key = rest[..eq].trim().to_string();
            let after = rest[eq + 1..].trim_start();
            let quote =
                after.chars().next().filter(|c| *c == '"' || *c == '\'').ok_or_else(|| format!("<{}>: attribute {key} is not quoted", tag.name))?;
            let close = after[1..].find(quote).ok_or_else(|| format!("<{}>: attribute {key} is not closed", tag.name))?;
            tag.attributes.insert(key, after[1..1 + close].to_string());
            rest = &after[close + 2..];
        }
        out.push((open.last().copied(), tag));
        if !empty {
            open.push(out.len() - 1);
        }
    }
    Ok(out)
}

/// How the appended block stores its arrays.
struct Appended<'a> {
    bytes: &'a [u8],
    header_u64: bool,
    little_endian: bool,
    zlib: bool,
}

impl Appended<'_> {
    fn header_size(&self) -> usize {
        if self.header_u64 { 8 } else { 4 }
    }

    fn header(&self, at: usize) -> Result<usize, String> {
        let n = self.header_size();
        let b = self.bytes.get(at..at + n).ok_or("the appended data ends inside an array's header")?;
        let value = match (self.header_u64, self.little_endian) {
            (true, true) => u64::from_le_bytes(b.try_into().unwrap()),
            (true, false) => u64::from_be_bytes(b.try_into().unwrap()),
            (false, true) => u32::from_le_bytes(b.try_into().unwrap()) as u64,
            (false, false) => u32::from_be_bytes(b.try_into().unwrap()) as u64,
        };
        usize::try_from(value).map_err(|_| "an array's size does not fit in memory".to_string())
    }

    /// The raw (uncompressed) bytes of the array at `offset`.
    fn array(&self, offset: usize) -> Result<Vec<u8>, String> {
        let h = self.header_size();
        if !self.zlib {
            let n = self.header(offset)?;
            let start = offset + h;
            return self
                .bytes
                .get(start..start + n)
                .map(<[u8]>::to_vec)
                .ok_or_else(|| format!("the appended data ends inside an array of {n} bytes at offset {offset}"));
        }
        let blocks = self.header(offset)?;
        let block_size = self.header(offset + h)?;
        let last_size = self.header(offset + 2 * h)?;
        let mut at = offset + (3 + blocks) * h;
        let mut out = Vec::with_capacity(blocks.saturating_mul(block_size).min(1 << 30));
        for b in 0..blocks {
            let compressed = self.header(offset + (3 + b) * h)?;
            let data = self
                .bytes
                .get(at..at + compressed)
                .ok_or_else(|| format!("the appended data ends inside compressed block {b} at offset {offset}"))?;
            let expected = if b + 1 == blocks && last_size != 0 { last_size } else { block_size };
            let before = out.len();
            flate2::read::ZlibDecoder::new(data).read_to_end(&mut out).map_err(|e| format!("compressed block {b} at offset {offset}: {e}"))?;
            if out.len() - before != expected {
                return Err(format!("compressed block {b} at offset {offset} inflates to {} bytes, the header says {expected}", out.len() - before));
            }
            at += compressed;
        }
        Ok(out)
    }
}

/// Bytes per value of a VTK `type`, or None for a type this reader does not know.
fn type_size(ty: &str) -> Option<usize> {
    Some(match ty {
        "Int8" | "UInt8" => 1,
        "Int16" | "UInt16" => 2,
        "Int32" | "UInt32" | "Float32" => 4,
        "Int64" | "UInt64" | "Float64" => 8,
        _ => return None,
    })
}

/// Binary values of type `ty` as f64.
fn decode(ty: &str, bytes: &[u8], little_endian: bool) -> Vec<f64> {
    let size = type_size(ty).unwrap_or(1);
    bytes
        .chunks_exact(size)
        .map(|c| {
            let mut b = [0u8; 8];
            b[..size].copy_from_slice(c);
            if !little_endian {
                b[..size].reverse();
            }
            match ty {
                "Int8" => b[0] as i8 as f64,
                "UInt8" => b[0] as f64,
                "Int16" => i16::from_le_bytes([b[0], b[1]]) as f64,
                "UInt16" => u16::from_le_bytes([b[0], b[1]]) as f64,
                "Int32" => i32::from_le_bytes(b[..4].try_into().unwrap()) as f64,
                "UInt32" => u32::from_le_bytes(b[..4].try_into().unwrap()) as f64,
                "Float32" => f32::from_le_bytes(b[..4].try_into().unwrap()) as f64,
                "Int64" => i64::from_le_bytes(b) as f64,
                "UInt64" => u64::from_le_bytes(b) as f64,
                _ => f64::from_le_bytes(b),
            }
        })
        .collect()
}

/// Decodes the bytes of a whole `.vtp` file.
pub fn parse(bytes: &[u8]) -> Result<PolyData, String> {
    // The XML part ends where appended binary data begins (after its `_` marker).
    let appended_tag = find(bytes, b"<AppendedData");
    let xml_end = match appended_tag {
        Some(at) => at + find(&bytes[at..], b">").ok_or("<AppendedData> is not closed")? + 1,
        None => bytes.len(),
    };
    let xml = std::str::from_utf8(&bytes[..xml_end]).map_err(|_| "the XML part is not UTF-8")?;
    // <AppendedData> and its parents stay open here: their end tags lie past the binary bytes.
    let tags = tags(xml)?;
    let file = tags.iter().find(|(_, t)| t.name == "VTKFile").map(|(_, t)| t).ok_or("no <VTKFile> element")?;
    if file.attribute("type") != Some("PolyData") {
        return Err(format!("a VTKFile of type {:?}; valid: PolyData", file.attribute("type").unwrap_or("none")));
    }
    let little_endian = match file.attribute("byte_order").unwrap_or("LittleEndian") {
        "LittleEndian" => true,
        "BigEndian" => false,
        other => return Err(format!("byte_order \"{other}\"; valid: LittleEndian, BigEndian")),
    };
    let header_u64 = match file.attribute("header_type").unwrap_or("UInt32") {
        "UInt32" => false,
        "UInt64" => true,
        other => return Err(format!("header_type \"{other}\"; valid: UInt32, UInt64")),
    };
    let zlib = match file.attribute("compressor") {
        None | Some("") => false,
        Some("vtkZLibDataCompressor") => true,
        Some(other) => return Err(format!("compressor \"{other}\"; valid: vtkZLibDataCompressor or none")),
    };
    let appended = match appended_tag {
        Some(_) => {
            let tag = tags.iter().find(|(_, t)| t.name == "AppendedData").map(|(_, t)| t).unwrap();
            if tag.attribute("encoding") != Some("raw") {
                return Err(format!("<AppendedData encoding=\"{}\">; valid: raw", tag.attribute("encoding").unwrap_or("")));
            }
            let underscore = find(&bytes[xml_end..], b"_").ok_or("<AppendedData> has no '_' before its data")?;
            Some(Appended { bytes: &bytes[xml_end + underscore + 1..], header_u64, little_endian, zlib })
        }
        None => None,
    };
    let piece = tags.iter().position(|(_, t)| t.name == "Piece").ok_or("no <Piece> element")?;
    let count = |key: &str| -> Result<usize, String> {
        tags[piece]
            .1
            .attribute(key)
            .unwrap_or("0")
            .trim()
            .parse()
            .map_err(|_| format!("<Piece {key}=\"{}\"> is not a count", tags[piece].1.attribute(key).unwrap_or("")))
    };
    let (n_points, n_polys) = (count("NumberOfPoints")?, count("NumberOfPolys")?);
    // The section (Points, PointData, CellData, Polys, …) each array of the piece sits in.
    let section = |k: usize| -> Option<&str> {
        let mut at = tags[k].0;
        while let Some(p) = at {
            if tags[p].0 == Some(piece) {
                return Some(tags[p].1.name.as_str());
            }
            at = tags[p].0;
        }
        None
    };
    let mut data = PolyData::default();
    let (mut connectivity, mut offsets) = (None, None);
    for (k, (_, tag)) in tags.iter().enumerate().filter(|(_, (_, t))| t.name == "DataArray") {
        let Some(section) = section(k) else { continue };
        let array = read_array(tag, xml, appended.as_ref(), little_endian)?;
        match section {
            "Points" => {
                if array.components != 3 || array.len() != n_points {
                    return Err(format!("<Points> holds {} values, not 3 × {n_points}", array.values.len()));
                }
                data.points = array.values.chunks_exact(3).map(|c| [c[0], c[1], c[2]]).collect();
            }
            "PointData" => data.point_data.push(array),
            "CellData" => data.cell_data.push(array),
            "Polys" if array.name == "connectivity" => connectivity = Some(array),
            "Polys" if array.name == "offsets" => offsets = Some(array),
            _ => {}
        }
    }
    for a in &data.point_data {
        if a.len() != n_points || a.values.len() % a.components != 0 {
            return Err(format!("point array \"{}\" has {} values, not {} × {n_points}", a.name, a.values.len(), a.components));
        }
    }
    if n_polys > 0 {
        let (Some(connectivity), Some(offsets)) = (connectivity, offsets) else {
            return Err("<Polys> lacks its connectivity or offsets array".into());
        };
        let mut start = 0usize;
        for &end in &offsets.values {
            let end = end as usize;
            let poly = connectivity.values.get(start..end).ok_or("<Polys> offsets run past the connectivity")?;
            let poly: Vec<usize> = poly.iter().map(|&i| i as usize).collect();
            if let Some(bad) = poly.iter().find(|&&i| i >= n_points) {
                return Err(format!("a polygon names point {bad} of {n_points}"));
            }
            data.polys.push(poly);
            start = end;
        }
        if data.polys.len() != n_polys {
            return Err(format!("<Polys> has {} offsets for NumberOfPolys=\"{n_polys}\"", data.polys.len()));
        }
    }
    for a in &data.cell_data {
        if a.len() != n_polys {
            return Err(format!("cell array \"{}\" has {} tuples for {n_polys} polygons", a.name, a.len()));
        }
    }
    Ok(data)
}

fn read_array(tag: &Tag, xml: &str, appended: Option<&Appended>, little_endian: bool) -> Result<DataArray, String> {
    let name = tag.attribute("Name").unwrap_or("").to_string();
    let ty = tag.attribute("type").unwrap_or("");
    if type_size(ty).is_none() {
        return Err(format!("DataArray \"{name}\" has type \"{ty}\"; valid: Int8 … Int64, UInt8 … UInt64, Float32, Float64"));
    }
    let components = tag.attribute("NumberOfComponents").unwrap_or("1").trim().parse::<usize>().ok().filter(|&c| c > 0);
    let components = components.ok_or_else(|| format!("DataArray \"{name}\": NumberOfComponents is not a positive count"))?;
    let values = match tag.attribute("format").unwrap_or("ascii") {
        "ascii" => xml[tag.text.clone()]
            .split_ascii_whitespace()
            .map(|v| v.parse::<f64>().map_err(|_| format!("DataArray \"{name}\": \"{v}\" is not a number")))
            .collect::<Result<Vec<_>, _>>()?,
        "appended" => {
            let appended = appended.ok_or_else(|| format!("DataArray \"{name}\" is appended but the file has no <AppendedData>"))?;
            let offset = tag
                .attribute("offset")
                .and_then(|o| o.trim().parse().ok())
                .ok_or_else(|| format!("DataArray \"{name}\" is appended without an offset"))?;
            let raw = appended.array(offset).map_err(|e| format!("DataArray \"{name}\": {e}"))?;
            if raw.len() % type_size(ty).unwrap() != 0 {
                return Err(format!("DataArray \"{name}\": {} bytes is not a whole number of {ty} values", raw.len()));
            }
            decode(ty, &raw, little_endian)
        }
        other => return Err(format!("DataArray \"{name}\" has format \"{other}\"; valid: ascii, appended")),
    };
    Ok(DataArray { name, components, values })
}

fn find(haystack: &[u8], needle: &[u8]) -> Option<usize> {
    haystack.windows(needle.len()).position(|w| w == needle)
}

/// The `(time, file)` entries of a `.pvd` collection, in file order, paths relative to the .pvd's folder.
pub fn read_pvd(path: &Path) -> Result<Vec<(f64, String)>, String> {
    let text = std::fs::read_to_string(path).map_err(|e| format!("{}: {e}", path.display()))?;
    let tags = tags(&text).map_err(|e| format!("{}: {e}", path.display()))?;
    tags.iter()
        .filter(|(_, t)| t.name == "DataSet")
        .map(|(_, t)| {
            let file = t.attribute("file").ok_or_else(|| format!("{}: a <DataSet> without a file", path.display()))?;
            let time = t
                .attribute("timestep")
                .unwrap_or("0")
                .parse()
                .map_err(|_| format!("{}: timestep \"{}\" is not a number", path.display(), t.attribute("timestep").unwrap_or("")))?;
            Ok((time, file.to_string()))
        })
        .collect()
}

#[cfg(test)]
#[path = "vtp_tests.rs"]
mod tests;
