//! PLY (Stanford polygon files), as Mitsuba's `<shape type="ply">` reads them: ASCII, binary
//! little-endian and binary big-endian; the `vertex` element's `x`, `y`, `z`, normals `nx`,
//! `ny`, `nz` and texture coordinates (`u`/`v`, `s`/`t` or `texture_u`/`texture_v`), any
//! numeric type each; the `face` element's `vertex_indices` (or `vertex_index`) list, polygons
//! fanned into triangles; the vertex and face attributes a caller asks for, grouped and named
//! as Mitsuba's reader does (`attribute_groups`); every other element and property is
//! skipped.
//!
//! # Robustness
//!
//! Each element count of the header is checked against the bytes after the header before any
//! allocation: an element needs at least the bytes of its fixed-size properties (binary) or
//! two characters per property (ASCII), so a header declaring 10¹² vertices is refused at once.
//! Errors name the byte offset (and the line, for the header and ASCII data): a face index past
//! the declared vertex count, a list shorter than 3, a non-finite coordinate, a file ending
//! early, and a file holding more than its header declares (ASCII: anything but whitespace
//! after the last declared element; binary: any byte after it but the line end some writers
//! add), which would otherwise load
//! part of the file without a word. The finished mesh goes through the same check as the
//! serialized reader's ([`super::mesh_bytes::check_mesh`]).
//!
//! A second `vertex` or `face` element is refused (naming it and its header line): the mesh
//! has one vertex array and one face list, and no reading of two is right (appending would
//! shift the second's indices, replacing would drop the first). Mitsuba's reader does not
//! merge them either; refusing says so instead of loading something else.
//!
//! # Why not `ply-rs`
//!
//! The maintained `ply-rs` (and its fork `ply-rs-bw`) parse each element into a hash map of
//! named properties (an allocation per vertex, slow on million-vertex scans), report binary
//! errors without a byte offset, and read element counts without relating them to the file's
//! size. This reader is a single pass over the file's bytes into the mesh arrays.

use super::mesh_bytes::{Bytes, MeshData, MeshFileError, check_mesh};
use opticks_core::math::{Rgb, Vec2, Vec3};
use opticks_core::scene::MeshAttribute;

/// A PLY scalar type.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Scalar {
    I8,
    U8,
    I16,
    U16,
    I32,
    U32,
    F32,
    F64,
}

impl Scalar {
    fn parse(s: &str) -> Option<Scalar> {
        Some(match s {
            "char" | "int8" => Scalar::I8,
            "uchar" | "uint8" => Scalar::U8,
            "short" | "int16" => Scalar::I16,
            "ushort" | "uint16" => Scalar::U16,
            "int" | "int32" => Scalar::I32,
            "uint" | "uint32" => Scalar::U32,
            "float" | "float32" => Scalar::F32,
            "double" | "float64" => Scalar::F64,
            _ => return None,
        })
    }

    fn bytes(self) -> usize {
        match self {
            Scalar::I8 | Scalar::U8 => 1,
            Scalar::I16 | Scalar::U16 => 2,
            Scalar::I32 | Scalar::U32 | Scalar::F32 => 4,
            Scalar::F64 => 8,
        }
    }
}

/// A property: a scalar, or a list (count type, item type).
#[derive(Clone, Debug)]
struct Property {
    name: String,
    scalar: Scalar,
    list: Option<Scalar>,
}

#[derive(Clone, Debug)]
struct ElementDef {
    name: String,
    count: u64,
    properties: Vec<Property>,
    /// Offset and line of its header line.
    offset: u64,
    line: u32,
}

#[derive(Clone, Copy, Debug, PartialEq)]
enum Format {
    Ascii,
    Binary { big_endian: bool },
}

/// The header's longest accepted length: real headers are a few hundred bytes.
const MAX_HEADER: usize = 1 << 20;

/// Parses a PLY file's bytes (no attributes).
pub fn parse_ply(data: &[u8]) -> Result<MeshData, MeshFileError> {
    parse_ply_with(data, &[])
}

/// Parses a PLY file's bytes, keeping the attributes named in `wanted` (Mitsuba's names,
/// `vertex_color`, `face_weight`, …) that the file has.
pub fn parse_ply_with(data: &[u8], wanted: &[String]) -> Result<MeshData, MeshFileError> {
    let (format, elements, body) = header(data)?;
    for name in ["vertex", "face"] {
        if let Some(second) = elements.iter().filter(|e| e.name == name).nth(1) {
            return Err(MeshFileError {
                offset: second.offset,
                line: second.line,
                message: format!(
                    "a second `{name}` element: a PLY mesh has one `{name}` element (the file declares several)"
                ),
            });
        }
    }
    let mut mesh = MeshData::default();
    let vertex_count = elements.iter().find(|e| e.name == "vertex").map_or(0, |e| e.count);
    if vertex_count > u32::MAX as u64 {
        let e = elements.iter().find(|e| e.name == "vertex").expect("found");
        return Err(MeshFileError {
            offset: e.offset,
            line: e.line,
            message: format!("{vertex_count} vertices is more than a mesh can index (2³²)"),
        });
    }
    let mut input = match format {
        Format::Ascii => Input::Ascii(Ascii { data, pos: body, line: header_lines(data, body) }),
        Format::Binary { big_endian } => Input::Binary(Bytes::new(&data[body..], body as u64, big_endian)),
    };
    for e in &elements {
        input.check_count(e)?;
        match e.name.as_str() {
            "vertex" => vertices(&mut input, e, wanted, &mut mesh)?,
            "face" => faces(&mut input, e, vertex_count, wanted, &mut mesh)?,
            _ => {
                for _ in 0..e.count {
                    for p in &e.properties {
                        input.skip(p)?;
                    }
                }
            }
        }
    }
    input.check_end()?;
    check_mesh(&mesh, body as u64)?;
    Ok(mesh)
}

/// The header: format, elements, and the offset of the first body byte.
fn header(data: &[u8]) -> Result<(Format, Vec<ElementDef>, usize), MeshFileError> {
    let mut pos = 0;
    let mut line = 0;
    let mut format = None;
    let mut elements: Vec<ElementDef> = Vec::new();
    loop {
        line += 1;
        let start = pos;
        let err = |message: String| MeshFileError { offset: start as u64, line, message };
        if pos >= data.len() || pos > MAX_HEADER {
            return Err(err("the header has no end_header line".into()));
        }
        let end = data[pos..].iter().position(|&b| b == b'\n').map_or(data.len(), |i| pos + i);
        let text = std::str::from_utf8(&data[pos..end]).map_err(|_| err("the header is not text".into()))?;
        pos = (end + 1).min(data.len());
        let words: Vec<&str> = text.split_ascii_whitespace().collect();
        if line == 1 {
            if words != ["ply"] {
                return Err(err("not a PLY file (the first line must be \"ply\")".into()));
            }
            continue;
        }
        match words.as_slice() {
            ["format", f, v] => {
                if !v.starts_with('1') {
                    return Err(err(format!("PLY format version {v} is not supported (1.0)")));
                }
                format = Some(match *f {
                    "ascii" => Format::Ascii,
                    "binary_little_endian" => Format::Binary { big_endian: false },
                    "binary_big_endian" => Format::Binary { big_endian: true },
                    _ => return Err(err(format!("unknown PLY format \"{f}\""))),
                });
            }
            ["comment", ..] | ["obj_info", ..] | [] => {}
            ["element", name, count] => {
                let count = count
                    .parse::<u64>()
                    .map_err(|_| err(format!("element count \"{count}\" is not a number")))?;
                elements.push(ElementDef {
                    name: name.to_string(),
                    count,
                    properties: Vec::new(),
                    offset: start as u64,
                    line,
                });
            }
            ["property", rest @ ..] => {
                let e = elements.last_mut().ok_or_else(|| err("a property before any element".into()))?;
                let ty =
                    |s: &str| Scalar::parse(s).ok_or_else(|| err(format!("unknown property type \"{s}\"")));
                let p = match rest {
                    ["list", count, item, name] => {
                        let count = ty(count)?;
                        if matches!(count, Scalar::F32 | Scalar::F64) {
                            return Err(err("a list's count type must be an integer type".into()));
                        }
                        Property { name: name.to_string(), scalar: ty(item)?, list: Some(count) }
                    }
                    [t, name] => Property { name: name.to_string(), scalar: ty(t)?, list: None },
                    _ => return Err(err(format!("malformed property line \"{}\"", text.trim()))),
                };
                e.properties.push(p);
            }
            ["end_header"] => break,
            _ => return Err(err(format!("unexpected header line \"{}\"", text.trim()))),
        }
    }
    let format = format.ok_or_else(|| MeshFileError {
        offset: 0,
        line: 2,
        message: "the header has no format line".into(),
    })?;
    Ok((format, elements, pos))
}

/// The line number of the first body line (the header's lines plus one).
fn header_lines(data: &[u8], body: usize) -> u32 {
    data[..body].iter().filter(|&&b| b == b'\n').count() as u32 + 1
}

/// Mitsuba's grouping of an element's scalar properties into attributes (`ply.h`'s
/// `find_other_fields`), named `kind` (`vertex_` or `face_`) + the group's name: `r g b [a]`
/// (or `red green blue [alpha]`) anywhere is `color`; otherwise consecutive properties
/// `PREFIX_c` whose one-letter suffixes run through one of `x y z w`, `r g b a`, `0 1 2 3`,
/// `1 2 3 4` from its start, with 1 or 3 members (other counts are ignored, as Mitsuba does),
/// are `PREFIX` (`PREFIX_color` for the `r g b a` suffixes). `reserved` properties (positions,
/// normals, texture coordinates) take part in none. Returns (name, property indices).
fn attribute_groups(kind: &str, props: &[Property], reserved: &[usize]) -> Vec<(String, Vec<usize>)> {
    const SUFFIXES: [&str; 4] = ["xr01", "yg12", "zb23", "wa34"];
    let scalar = |n: &str| props.iter().position(|p| p.name == n && p.list.is_none());
    let mut groups = Vec::new();
    let mut taken: Vec<usize> = reserved.to_vec();
    for names in [["r", "g", "b", "a"], ["red", "green", "blue", "alpha"]] {
        if let (Some(r), Some(g), Some(b)) = (scalar(names[0]), scalar(names[1]), scalar(names[2])) {
            let mut members = vec![r, g, b];
            members.extend(scalar(names[3]));
            taken.extend(&members);
            groups.push((format!("{kind}color"), members));
            break;
        }
    }
    taken.extend(["r", "g", "b", "a"].iter().filter_map(|n| scalar(n)));
    let mut seen: Vec<String> = Vec::new();
    // The group being read: prefix, suffix column, members.
    let mut current: Option<(String, usize, Vec<usize>)> = None;
    let mut flush = |current: &mut Option<(String, usize, Vec<usize>)>, seen: &mut Vec<String>| {
        if let Some((prefix, column, members)) = current.take()
            && matches!(members.len(), 1 | 3)
        {
            let colour = if column == 1 { "_color" } else { "" };
            groups.push((format!("{kind}{prefix}{colour}"), members));
            seen.push(prefix);
        }
    };
    for (i, p) in props.iter().enumerate() {
        if taken.contains(&i) || p.list.is_some() {
            continue;
        }
        let Some((prefix, suffix)) = p.name.rsplit_once('_').filter(|(_, s)| s.len() == 1) else {
            flush(&mut current, &mut seen);
            continue;
        };
        let c = suffix.as_bytes()[0];
        if current.as_ref().is_some_and(|(cp, _, _)| cp != prefix) {
            flush(&mut current, &mut seen);
        }
        match &mut current {
            None => {
                if seen.iter().any(|s| s == prefix) {
                    continue;
                }
                if let Some(column) = SUFFIXES[0].bytes().position(|x| x == c) {
                    current = Some((prefix.to_string(), column, vec![i]));
                }
            }
            Some((_, column, members)) => {
                match SUFFIXES.get(members.len()) {
                    Some(row) if row.as_bytes()[*column] == c => members.push(i),
                    _ => current = None, // a broken sequence: the attribute is ignored
                }
            }
        }
    }
    flush(&mut current, &mut seen);
    groups
}

/// The wanted attributes among `groups`: (index in `groups`, the attribute with room for `n`
/// values).
fn wanted_groups(
    groups: &[(String, Vec<usize>)],
    wanted: &[String],
    n: usize,
) -> Vec<(usize, MeshAttribute)> {
    groups
        .iter()
        .enumerate()
        .filter(|(_, (name, _))| wanted.contains(name))
        .map(|(k, (name, members))| {
            let attribute = MeshAttribute {
                name: name.clone(),
                channels: members.len() as u8,
                values: Vec::with_capacity(n),
            };
            (k, attribute)
        })
        .collect()
}

/// The value of a group of properties `members` in the element's `values` (a one-channel value
/// in every component; a fourth channel is dropped, the core refuses such attributes by their
/// channel count).
fn group_value(members: &[usize], values: &[f64]) -> Rgb {
    let v = |k: usize| values[members[k.min(members.len() - 1)]] as f32;
    Rgb::new(v(0), v(1), v(2))
}

fn vertices(
    input: &mut Input,
    e: &ElementDef,
    wanted: &[String],
    mesh: &mut MeshData,
) -> Result<(), MeshFileError> {
    let find = |n: &str| e.properties.iter().position(|p| p.name == n && p.list.is_none());
    let (Some(x), Some(y), Some(z)) = (find("x"), find("y"), find("z")) else {
        return Err(MeshFileError {
            offset: e.offset,
            line: e.line,
            message: "the vertex element has no x, y, z properties".into(),
        });
    };
    let normal = match (find("nx"), find("ny"), find("nz")) {
        (Some(a), Some(b), Some(c)) => Some([a, b, c]),
        _ => None,
    };
    let uv = [("u", "v"), ("s", "t"), ("texture_u", "texture_v")]
        .iter()
        .find_map(|(u, v)| Some([find(u)?, find(v)?]));
    let n = e.count as usize; // checked against the file's size
    let mut reserved: Vec<usize> = [x, y, z].into();
    reserved.extend(["nx", "ny", "nz"].iter().filter_map(|n| find(n)));
    reserved.extend(uv.into_iter().flatten());
    reserved.extend(["u", "v"].iter().filter_map(|n| find(n)));
    let groups = attribute_groups("vertex_", &e.properties, &reserved);
    let mut attributes = wanted_groups(&groups, wanted, n);
    mesh.positions = Vec::with_capacity(n);
    if normal.is_some() {
        mesh.normals = Vec::with_capacity(n);
    }
    if uv.is_some() {
        mesh.uvs = Vec::with_capacity(n);
    }
    let mut values = vec![0.0f64; e.properties.len()];
    for i in 0..n {
        let at = input.place();
        for (k, p) in e.properties.iter().enumerate() {
            values[k] = match p.list {
                None => input.scalar(p.scalar)?,
                Some(_) => {
                    input.skip(p)?;
                    0.0
                }
            };
        }
        let v3 = |[a, b, c]: [usize; 3]| Vec3::new(values[a] as f32, values[b] as f32, values[c] as f32);
        let p = v3([x, y, z]);
        if !p.is_finite() {
            return Err(at.error(format!("vertex {i} has a non-finite position {p}")));
        }
        mesh.positions.push(p);
        if let Some(nm) = normal {
            let nv = v3(nm);
            if !nv.is_finite() {
                return Err(at.error(format!("vertex {i} has a non-finite normal {nv}")));
            }
            mesh.normals.push(nv);
        }
        if let Some([u, v]) = uv {
            let t = Vec2::new(values[u] as f32, values[v] as f32);
            if !t.is_finite() {
                return Err(at.error(format!("vertex {i} has non-finite texture coordinates {t}")));
            }
            mesh.uvs.push(t);
        }
        for (k, a) in &mut attributes {
            let v = group_value(&groups[*k].1, &values);
            if !v.is_finite() {
                return Err(at.error(format!("vertex {i} has a non-finite {} {v}", a.name)));
            }
            a.values.push(v);
        }
    }
    mesh.attributes.extend(attributes.into_iter().map(|(_, a)| a));
    Ok(())
}

fn faces(
    input: &mut Input,
    e: &ElementDef,
    vertex_count: u64,
    wanted: &[String],
    mesh: &mut MeshData,
) -> Result<(), MeshFileError> {
    let index = e
        .properties
        .iter()
        .position(|p| p.list.is_some() && (p.name == "vertex_indices" || p.name == "vertex_index"))
        .ok_or_else(|| MeshFileError {
            offset: e.offset,
            line: e.line,
            message: "the face element has no vertex_indices (or vertex_index) list".into(),
        })?;
    mesh.triangles = Vec::with_capacity(e.count as usize); // checked against the file's size
    let groups = attribute_groups("face_", &e.properties, &[index]);
    let mut attributes = wanted_groups(&groups, wanted, e.count as usize);
    let mut values = vec![0.0f64; e.properties.len()];
    let mut corners: Vec<u32> = Vec::new();
    for f in 0..e.count {
        let at = input.place();
        for (k, p) in e.properties.iter().enumerate() {
            if k != index {
                match p.list {
                    None if !attributes.is_empty() => values[k] = input.scalar(p.scalar)?,
                    _ => input.skip(p)?,
                }
                continue;
            }
            let at = input.place();
            let len = input.scalar(p.list.expect("a list"))?;
            if !(3.0..=1e6).contains(&len) || len.fract() != 0.0 {
                return Err(at.error(format!("face {f} has {len} corners (3 to 10⁶ accepted)")));
            }
            corners.clear();
            for _ in 0..len as usize {
                let at = input.place();
                let i = input.scalar(p.scalar)?;
                if !(0.0..vertex_count as f64).contains(&i) || i.fract() != 0.0 {
                    return Err(at.error(format!(
                        "face {f} refers to vertex {i}, but the file declares {vertex_count} vertices"
                    )));
                }
                corners.push(i as u32);
            }
            for j in 1..corners.len() - 1 {
                mesh.triangles.push([corners[0], corners[j], corners[j + 1]]);
            }
        }
        // A polygon's value on each of its triangles.
        let triangles = corners.len() - 2;
        for (k, a) in &mut attributes {
            let v = group_value(&groups[*k].1, &values);
            if !v.is_finite() {
                return Err(at.error(format!("face {f} has a non-finite {} {v}", a.name)));
            }
            a.values.extend(std::iter::repeat_n(v, triangles));
        }
    }
    mesh.attributes.extend(attributes.into_iter().map(|(_, a)| a));
    Ok(())
}

/// The body being read, ASCII or binary.
enum Input<'a> {
    Ascii(Ascii<'a>),
    Binary(Bytes<'a>),
}

/// Where a value starts, for errors.
struct Place {
    offset: u64,
    line: u32,
}

impl Place {
    fn error(&self, message: String) -> MeshFileError {
        MeshFileError { offset: self.offset, line: self.line, message }
    }
}

impl Input<'_> {
    fn place(&mut self) -> Place {
        match self {
            Input::Ascii(a) => {
                a.skip_space();
                Place { offset: a.pos as u64, line: a.line }
            }
            Input::Binary(b) => Place { offset: b.offset(), line: 0 },
        }
    }

    /// An error unless `e.count` elements can fit in what is left.
    fn check_count(&mut self, e: &ElementDef) -> Result<(), MeshFileError> {
        let fixed: usize = e.properties.iter().map(|p| p.list.unwrap_or(p.scalar).bytes()).sum();
        let (min, remaining) = match self {
            Input::Ascii(a) => ((2 * e.properties.len()).saturating_sub(1) as u64, a.data.len() - a.pos),
            Input::Binary(b) => (fixed as u64, b.remaining()),
        };
        if min == 0 {
            return Ok(()); // nothing to read however many there are
        }
        if e.count.checked_mul(min).is_none_or(|n| n > remaining as u64) {
            return Err(MeshFileError {
                offset: e.offset,
                line: e.line,
                message: format!(
                    "element {} declares {} elements of at least {min} bytes each, but only {remaining} bytes follow the header",
                    e.name, e.count
                ),
            });
        }
        Ok(())
    }

    /// An error if anything but ASCII whitespace (in a binary file: a trailing line end or other
    /// whitespace some writers add) follows the last declared element.
    fn check_end(&mut self) -> Result<(), MeshFileError> {
        let at = self.place();
        let extra = match self {
            Input::Ascii(a) => a.data.len() - a.pos,
            Input::Binary(b) if b.rest().iter().all(u8::is_ascii_whitespace) => 0,
            Input::Binary(b) => b.remaining(),
        };
        if extra == 0 {
            return Ok(());
        }
        Err(at.error(format!(
            "{extra} bytes follow the last element the header declares (a PLY file holds exactly what its header declares)"
        )))
    }

    fn scalar(&mut self, s: Scalar) -> Result<f64, MeshFileError> {
        match self {
            Input::Ascii(a) => a.number(),
            Input::Binary(b) => Ok(match s {
                Scalar::I8 => b.signed(1)? as f64,
                Scalar::I16 => b.signed(2)? as f64,
                Scalar::I32 => b.signed(4)? as f64,
                Scalar::U8 => b.u8()? as f64,
                Scalar::U16 => b.u16()? as f64,
                Scalar::U32 => b.u32()? as f64,
                Scalar::F32 => b.f32()? as f64,
                Scalar::F64 => b.f64()?,
            }),
        }
    }

    fn skip(&mut self, p: &Property) -> Result<(), MeshFileError> {
        let Some(count) = p.list else { return self.scalar(p.scalar).map(|_| ()) };
        let at = self.place();
        let n = self.scalar(count)?;
        if n < 0.0 || n.fract() != 0.0 || n > 1e9 {
            return Err(at.error(format!("list property {} has length {n}", p.name)));
        }
        match self {
            Input::Binary(b) => b.take(n as usize * p.scalar.bytes()).map(|_| ()),
            Input::Ascii(_) => (0..n as usize).try_for_each(|_| self.scalar(p.scalar).map(|_| ())),
        }
    }
}

/// ASCII body: whitespace-separated numbers.
struct Ascii<'a> {
    data: &'a [u8],
    pos: usize,
    line: u32,
}

impl Ascii<'_> {
    fn skip_space(&mut self) {
        while let Some(&c) = self.data.get(self.pos).filter(|c| c.is_ascii_whitespace()) {
            if c == b'\n' {
                self.line += 1;
            }
            self.pos += 1;
        }
    }

    fn number(&mut self) -> Result<f64, MeshFileError> {
        self.skip_space();
        let start = self.pos;
        while self.data.get(self.pos).is_some_and(|c| !c.is_ascii_whitespace()) {
            self.pos += 1;
        }
        let err = |message: String| MeshFileError { offset: start as u64, line: self.line, message };
        if start == self.pos {
            return Err(err("the file ends here (more values expected)".into()));
        }
        let t = std::str::from_utf8(&self.data[start..self.pos]).unwrap_or("?");
        t.parse::<f64>().map_err(|_| err(format!("\"{t}\" is not a number")))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn binary(big_endian: bool) -> Vec<u8> {
        let mut d = format!(
            "ply\r\nformat binary_{}_endian 1.0\ncomment made by hand\nelement vertex 4\nproperty float x\n\
             property float y\nproperty float z\nproperty float nx\nproperty float ny\nproperty float nz\n\
             property float u\nproperty float v\nelement face 1\nproperty uchar intensity\n\
             property list uchar int vertex_indices\nend_header\n",
            if big_endian { "big" } else { "little" }
        )
        .into_bytes();
        let f =
            |d: &mut Vec<u8>, x: f32| d.extend(if big_endian { x.to_be_bytes() } else { x.to_le_bytes() });
        for (x, y) in [(0.0, 0.0), (1.0, 0.0), (1.0, 1.0), (0.0, 1.0)] {
            for v in [x, y, 0.0, 0.0, 0.0, 1.0, x, y] {
                f(&mut d, v);
            }
        }
        d.extend([7u8, 4]);
        for i in 0..4i32 {
            d.extend(if big_endian { i.to_be_bytes() } else { i.to_le_bytes() });
        }
        d
    }

    #[test]
    fn reads_every_encoding_alike() {
        let ascii = b"ply\nformat ascii 1.0\nelement vertex 4\nproperty double x\nproperty double y\n\
                      property double z\nproperty double nx\nproperty double ny\nproperty double nz\n\
                      property double s\nproperty double t\nelement face 1\nproperty uchar intensity\n\
                      property list uchar int vertex_indices\nend_header\n0 0 0 0 0 1 0 0\n1 0 0 0 0 1 1 0\n\
                      1 1 0 0 0 1 1 1\n0 1 0 0 0 1 0 1\n7 4 0 1 2 3\n";
        let a = parse_ply(ascii).unwrap();
        assert_eq!(a.triangles, [[0, 1, 2], [0, 2, 3]]);
        assert_eq!(a.positions[2], Vec3::new(1.0, 1.0, 0.0));
        assert_eq!(a.normals, [Vec3::Z; 4]);
        assert_eq!(a.uvs[3], Vec2::new(0.0, 1.0));
        assert_eq!(parse_ply(&binary(false)).unwrap(), a);
        assert_eq!(parse_ply(&binary(true)).unwrap(), a);
    }

    #[test]
    fn huge_counts_are_refused_before_allocating() {
        let d = b"ply\nformat binary_little_endian 1.0\nelement vertex 1000000000000\nproperty float x\n\
                  property float y\nproperty float z\nend_header\n\0\0\0\0";
        let e = parse_ply(d).unwrap_err();
        assert_eq!((e.offset, e.line), (36, 3), "{e:?}");
        assert!(e.message.contains("1000000000000 vertices is more than a mesh can index"), "{e:?}");
        let d = String::from_utf8_lossy(d).replace("1000000000000", "4000000000");
        let e = parse_ply(d.as_bytes()).unwrap_err();
        assert_eq!((e.offset, e.line), (36, 3), "{e:?}");
        assert!(
            e.message.contains("declares 4000000000 elements of at least 12 bytes each, but only 4 bytes"),
            "{e:?}"
        );
        let d = b"ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n\
                  property float z\nelement face 99999999999\nproperty list uchar int vertex_indices\nend_header\n\
                  0 0 0 1 0 0 0 1 0\n3 0 1 2\n";
        assert!(parse_ply(d).unwrap_err().message.contains("element face declares 99999999999"));
    }

    #[test]
    fn bad_data_is_located() {
        let mut d = binary(false);
        let body = d.len() - 4 * 4 - 2 - 4 * 32;
        // Face index 3 → 9.
        let n = d.len();
        d[n - 4..].copy_from_slice(&9i32.to_le_bytes());
        let e = parse_ply(&d).unwrap_err();
        assert_eq!(e.offset, (n - 4) as u64);
        assert!(e.message.contains("refers to vertex 9, but the file declares 4 vertices"), "{e:?}");
        // A NaN coordinate in vertex 1.
        let mut d = binary(false);
        d[body + 32..body + 36].copy_from_slice(&f32::NAN.to_le_bytes());
        let e = parse_ply(&d).unwrap_err();
        assert_eq!(e.offset, (body + 32) as u64);
        assert!(e.message.contains("vertex 1 has a non-finite position"), "{e:?}");
        // Truncated.
        let d = binary(true);
        let e = parse_ply(&d[..d.len() - 3]).unwrap_err();
        assert!(e.message.contains("the file ends here"), "{e:?}");
        // ASCII: line numbers.
        let d = b"ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n\
                  property float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n\
                  0 0 0\n1 0 zero\n0 1 0\n3 0 1 2\n";
        let e = parse_ply(d).unwrap_err();
        assert_eq!(e.line, 11, "{e:?}");
        assert!(e.message.contains("\"zero\" is not a number"));
        let d = b"ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\nproperty float z\n\
                  element face 1\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n2 0 0\n";
        assert!(parse_ply(d).unwrap_err().message.contains("face 0 has 2 corners"));
        for (bad, msg) in [
            (&b"plyx\n"[..], "not a PLY file"),
            (b"ply\nformat ascii 2.0\nend_header\n", "version 2.0"),
            (b"ply\nformat ascii 1.0\nproperty float x\nend_header\n", "before any element"),
            (
                b"ply\nformat ascii 1.0\nelement vertex 1\nproperty half x\nend_header\n",
                "unknown property type",
            ),
            (b"ply\nformat ascii 1.0\nelement vertex 1\n", "no end_header"),
            (b"ply\nelement vertex 0\nend_header\n", "no format line"),
            (b"ply\nformat ascii 1.0\nelement vertex 1\nproperty float y\nend_header\n1\n", "no x, y, z"),
        ] {
            let e = parse_ply(bad).unwrap_err();
            assert!(e.message.contains(msg), "{msg}: {e:?}");
        }
    }

    #[test]
    fn attributes_are_grouped_and_named_as_mitsubas_reader() {
        // What Mitsuba 3.9.1 makes of this header (checked with its `ply` plugin): red green
        // blue → vertex_color (integers kept as written), foo_x → vertex_foo, face_q_0..2 →
        // face_face_q; bar_x bar_y (two members) is ignored.
        let d = b"ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n\
                  property float z\nproperty uchar red\nproperty uchar green\nproperty uchar blue\n\
                  property float foo_x\nproperty float bar_x\nproperty float bar_y\nelement face 1\n\
                  property list uchar int vertex_indices\nproperty float face_q_0\nproperty float face_q_1\n\
                  property float face_q_2\nend_header\n0 0 0 255 128 0 0.5 1 1\n1 0 0 64 10 200 0.25 1 1\n\
                  0 1 0 0 0 0 1 1 1\n4 0 1 2 0 0.1 0.2 0.3\n";
        let names = ["vertex_color", "vertex_foo", "face_face_q", "vertex_bar"].map(String::from);
        let m = parse_ply_with(d, &names).unwrap();
        let got: Vec<(&str, u8)> = m.attributes.iter().map(|a| (a.name.as_str(), a.channels)).collect();
        assert_eq!(got, [("vertex_color", 3), ("vertex_foo", 1), ("face_face_q", 3)]);
        assert_eq!(m.attributes[0].values[0], Rgb::new(255.0, 128.0, 0.0));
        assert_eq!(m.attributes[1].values[1], Rgb::splat(0.25));
        // The quad's two triangles share its value.
        assert_eq!(m.attributes[2].values, [Rgb::new(0.1, 0.2, 0.3); 2]);
        // Nothing asked, nothing kept.
        assert!(parse_ply(d).unwrap().attributes.is_empty());
        let groups = |names: &[&str]| {
            let props: Vec<Property> = names
                .iter()
                .map(|n| Property { name: n.to_string(), scalar: Scalar::F32, list: None })
                .collect();
            attribute_groups("vertex_", &props, &[]).into_iter().map(|g| g.0).collect::<Vec<_>>()
        };
        assert_eq!(
            groups(&["c_r", "c_g", "c_b", "w_1", "w_2", "w_3", "k_1"]),
            ["vertex_c_color", "vertex_w", "vertex_k"]
        );
        assert_eq!(groups(&["a_x", "a_z", "b_0"]), ["vertex_b"]);
        assert_eq!(groups(&["r", "g", "b", "alpha"]), ["vertex_color"]);
    }

    const TRIANGLE: &str = "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n\
                            property float z\nelement face 1\nproperty list uchar int vertex_indices\n";

    /// Issue 26: a second `vertex` element replaced the positions while faces were checked
    /// against the first's count (a panic later, in the normals); a second `face` element
    /// replaced the first.
    #[test]
    fn a_second_vertex_or_face_element_is_refused() {
        let d = format!(
            "{TRIANGLE}element vertex 1\nproperty float x\nproperty float y\nproperty float z\nend_header\n\
             0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n5 5 5\n"
        );
        let e = parse_ply(d.as_bytes()).unwrap_err();
        assert_eq!(e.line, 9, "{e:?}");
        assert!(e.message.contains("a second `vertex` element"), "{e:?}");
        let d = format!(
            "{TRIANGLE}element face 1\nproperty list uchar int vertex_indices\nend_header\n\
             0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n3 2 1 0\n"
        );
        let e = parse_ply(d.as_bytes()).unwrap_err();
        assert_eq!((e.line, e.offset), (9, TRIANGLE.len() as u64), "{e:?}");
        assert!(e.message.contains("a second `face` element"), "{e:?}");
    }

    /// Issue 26: more faces and garbage than the header declares loaded without a word.
    #[test]
    fn data_beyond_the_declared_elements_is_refused() {
        let ok = format!("{TRIANGLE}end_header\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n \n\n");
        assert_eq!(parse_ply(ok.as_bytes()).unwrap().triangles, [[0, 1, 2]]);
        let d = format!("{ok}3 2 1 0\ngarbage\n");
        let e = parse_ply(d.as_bytes()).unwrap_err();
        assert_eq!((e.line, e.offset), (16, ok.len() as u64), "{e:?}");
        assert!(e.message.contains("16 bytes follow the last element the header declares"), "{e:?}");
        let mut d = binary(false);
        let end = d.len();
        d.push(b'\n');
        assert!(parse_ply(&d).is_ok(), "a trailing line end is not data");
        d.extend([1, 2]);
        let e = parse_ply(&d).unwrap_err();
        assert_eq!(e.offset, end as u64, "{e:?}");
        assert!(e.message.contains("3 bytes follow"), "{e:?}");
    }
}
