//! A snapshot piece as plain data: points, cells (vertices, lines, polygons) and named arrays
//! per point and per cell, as VTK's PolyData holds them. A phase gives its snapshot series in
//! this form; the application encodes it (VTK XML, ASCII or appended binary).

/// The values of one data array.
#[derive(Clone, Debug, PartialEq)]
pub enum Values {
    F64(Vec<f64>),
    I32(Vec<i32>),
    I64(Vec<i64>),
}

impl Values {
    /// The VTK type name (`Float64`, `Int32`, `Int64`).
    pub fn vtk_type(&self) -> &'static str {
        match self {
            Values::F64(_) => "Float64",
            Values::I32(_) => "Int32",
            Values::I64(_) => "Int64",
        }
    }

    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    pub fn len(&self) -> usize {
        match self {
            Values::F64(v) => v.len(),
            Values::I32(v) => v.len(),
            Values::I64(v) => v.len(),
        }
    }

    /// The values as little-endian bytes.
    pub fn le_bytes(&self) -> Vec<u8> {
        match self {
            Values::F64(v) => v.iter().flat_map(|x| x.to_le_bytes()).collect(),
            Values::I32(v) => v.iter().flat_map(|x| x.to_le_bytes()).collect(),
            Values::I64(v) => v.iter().flat_map(|x| x.to_le_bytes()).collect(),
        }
    }

    /// The k-th value as text; f64 in Rust's shortest form that parses back to the same bits.
    pub fn text(&self, k: usize) -> String {
        match self {
            Values::F64(v) => v[k].to_string(),
            Values::I32(v) => v[k].to_string(),
            Values::I64(v) => v[k].to_string(),
        }
    }
}

/// A named data array of `components` values per point or cell.
#[derive(Clone, Debug, PartialEq)]
pub struct Array {
    pub name: String,
    pub components: usize,
    pub values: Values,
}

impl Array {
    pub fn f64(name: &str, components: usize, values: Vec<f64>) -> Array {
        Array { name: name.into(), components, values: Values::F64(values) }
    }
    pub fn i32(name: &str, values: Vec<i32>) -> Array {
        Array { name: name.into(), components: 1, values: Values::I32(values) }
    }
    pub fn i64(name: &str, values: Vec<i64>) -> Array {
        Array { name: name.into(), components: 1, values: Values::I64(values) }
    }
}

/// One cell section (verts, lines or polys): each cell's point indices end at its offset.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Cells {
    pub connectivity: Vec<i64>,
    pub offsets: Vec<i64>,
}

impl Cells {
    /// Cells of the given point lists.
    pub fn of<I: IntoIterator<Item = usize>>(cells: impl IntoIterator<Item = I>) -> Cells {
        let mut c = Cells::default();
        for cell in cells {
            c.connectivity.extend(cell.into_iter().map(|k| k as i64));
            c.offsets.push(c.connectivity.len() as i64);
        }
        c
    }

    pub fn is_empty(&self) -> bool {
        self.offsets.is_empty()
    }

    pub fn len(&self) -> usize {
        self.offsets.len()
    }
}

/// One PolyData piece: points, cells and their data arrays.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct PolyData {
    /// x, y, z per point.
    pub points: Vec<f64>,
    pub verts: Cells,
    pub lines: Cells,
    pub polys: Cells,
    pub point_data: Vec<Array>,
    pub cell_data: Vec<Array>,
    /// The default arrays ParaView colours by: (`Scalars`, `Vectors`) of the point and of the cell data.
    pub point_attributes: (Option<String>, Option<String>),
    pub cell_attributes: (Option<String>, Option<String>),
}
