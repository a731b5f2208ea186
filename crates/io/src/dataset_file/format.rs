//! Byte layout of the header, chunk headers and end record (see `docs/dataset-format.md`).

use super::error::{RecordFault, SampleFault};
use super::{ALIGN, CHUNK_HEADER_LEN, CHUNK_MAGIC, DatasetError, END_MAGIC, FORMAT_VERSION};
use super::{MAGIC, OLDEST_VERSION, TRAILER_LEN};
use opticks_core::dataset::{DatasetHeader, Directions, PassMis, Roulette, Selection, TraceInfo, TracePass};
use opticks_core::dataset::{Heuristic, LightRecord, LightTable, MAX_PATHS, MisRecord, Sample, VcmClass};
use opticks_core::math::Rgb;
use opticks_core::scene::{Fingerprint, ObjectHash, ObjectKind};
use std::path::Path;

/// Size of the fixed part of the header, up to and including the pass count.
pub(crate) const FIXED_HEADER_LEN: usize = 52;
/// Smallest possible header: fixed part, label length 0, light count, CRC, padded.
pub(crate) const MIN_HEADER_LEN: usize = align_up(FIXED_HEADER_LEN + 4 + 4 + 4);
/// Bytes of a version-1 pass record: seed, stream, paths, roulette depth, seconds.
const PASS_RECORD_V1_LEN: usize = 8 + 8 + 8 + 4 + 4;
/// Bytes of a version-2 pass record besides its plan: the version-1 fields, roulette,
/// directions, selection, a zero byte, the plan's length.
const PASS_RECORD_LEN: usize = PASS_RECORD_V1_LEN + 4 + 4;
/// Bytes of a version-3 pass record besides its plan: the version-2 fields (the reserved byte
/// now the MIS heuristic) and the sampling signature.
const PASS_RECORD_V3_LEN: usize = PASS_RECORD_LEN + 4;
/// Bytes of one entry of a pass's plan: light table index, planned paths.
const PLAN_ENTRY_LEN: usize = 4 + 8;
/// Bytes of a light record besides its name: name length, shape hash, power, paths.
const LIGHT_RECORD_MIN: usize = 4 + 16 + 12 + 8;
/// Bytes of an object record (format 4) besides its name: kind, name length, hash.
const OBJECT_RECORD_MIN: usize = 1 + 4 + 16;

/// Why a header cannot be written: a count or length beyond its 32-bit field, or a value the
/// format cannot hold. The writer reports it as [`DatasetError::InvalidInput`].
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub(crate) enum Unwritable {
    /// More than 2^32 of something the header counts ("passes", "lights", …).
    #[error("more than 2^32 {0}")]
    TooMany(&'static str),
    /// The label does not fit its 32-bit length.
    #[error("label longer than 4 GiB")]
    LongLabel,
    /// Light `0`'s name does not fit its 32-bit length.
    #[error("light {0}: name longer than 4 GiB")]
    LongLightName(usize),
    /// Object `0`'s name does not fit its 32-bit length.
    #[error("object {0}: name longer than 4 GiB")]
    LongObjectName(usize),
    /// The whole header does not fit its 32-bit length.
    #[error("header longer than 4 GiB")]
    LongHeader,
    /// A pass has MIS records but sampling signature 0, which the file reads as "no records".
    #[error("a pass with MIS records has sampling signature 0")]
    ZeroSignature,
    /// A light's power is negative or not finite.
    #[error("light {light} ({name:?}) has invalid power {power:?}")]
    BadPower { light: usize, name: String, power: [f32; 3] },
}

pub(crate) const fn align_up(n: usize) -> usize {
    n.div_ceil(ALIGN) * ALIGN
}

/// Serialises the header: fields, zero padding, and the CRC-32 of everything before it in the
/// last 4 bytes, the whole a multiple of [`ALIGN`] long.
pub(crate) fn encode_header(h: &DatasetHeader) -> Result<Vec<u8>, Unwritable> {
    let mut b = Vec::with_capacity(256);
    b.extend_from_slice(&MAGIC);
    b.extend_from_slice(&FORMAT_VERSION.to_le_bytes());
    b.extend_from_slice(&0u32.to_le_bytes()); // header length, patched below
    b.extend_from_slice(&h.fingerprint.geometry);
    b.extend_from_slice(&h.fingerprint.lights);
    let passes = u32::try_from(h.trace.passes.len()).map_err(|_| Unwritable::TooMany("passes"))?;
    b.extend_from_slice(&passes.to_le_bytes());
    for p in &h.trace.passes {
        b.extend_from_slice(&p.seed.to_le_bytes());
        b.extend_from_slice(&p.stream.to_le_bytes());
        b.extend_from_slice(&p.paths.to_le_bytes());
        b.extend_from_slice(&p.rr_depth.to_le_bytes());
        b.extend_from_slice(&p.seconds.to_le_bytes());
        b.extend_from_slice(&[
            roulette_code(p.roulette),
            directions_code(p.directions),
            selection_code(p.selection),
            mis_code(p.mis.map(|m| m.heuristic)),
        ]);
        let signature = match p.mis {
            Some(m) if m.signature == 0 => {
                return Err(Unwritable::ZeroSignature);
            }
            Some(m) => m.signature,
            None => 0,
        };
        b.extend_from_slice(&signature.to_le_bytes());
        let planned = u32::try_from(p.planned.len()).map_err(|_| Unwritable::TooMany("planned lights"))?;
        b.extend_from_slice(&planned.to_le_bytes());
        for &(light, paths) in &p.planned {
            b.extend_from_slice(&light.to_le_bytes());
            b.extend_from_slice(&paths.to_le_bytes());
        }
    }
    let label_len = u32::try_from(h.label.len()).map_err(|_| Unwritable::LongLabel)?;
    b.extend_from_slice(&label_len.to_le_bytes());
    b.extend_from_slice(h.label.as_bytes());
    let n = u32::try_from(h.table.lights.len()).map_err(|_| Unwritable::TooMany("lights"))?;
    b.extend_from_slice(&n.to_le_bytes());
    for (k, l) in h.table.lights.iter().enumerate() {
        let len = u32::try_from(l.name.len()).map_err(|_| Unwritable::LongLightName(k))?;
        b.extend_from_slice(&len.to_le_bytes());
        b.extend_from_slice(l.name.as_bytes());
        b.extend_from_slice(&l.shape);
        for c in l.power.to_array() {
            b.extend_from_slice(&c.to_le_bytes());
        }
        b.extend_from_slice(&l.paths.to_le_bytes());
    }
    let n = u32::try_from(h.objects.len()).map_err(|_| Unwritable::TooMany("scene objects"))?;
    b.extend_from_slice(&n.to_le_bytes());
    for (i, o) in h.objects.iter().enumerate() {
        let len = u32::try_from(o.name.len()).map_err(|_| Unwritable::LongObjectName(i))?;
        b.push(object_code(o.kind));
        b.extend_from_slice(&len.to_le_bytes());
        b.extend_from_slice(o.name.as_bytes());
        b.extend_from_slice(&o.hash);
    }
    let total = align_up(b.len() + 4);
    let total32 = u32::try_from(total).map_err(|_| Unwritable::LongHeader)?;
    b[12..16].copy_from_slice(&total32.to_le_bytes());
    b.resize(total - 4, 0);
    let crc = crc32fast::hash(&b);
    b.extend_from_slice(&crc.to_le_bytes());
    Ok(b)
}

/// A decoded header and where things are.
pub(crate) struct DecodedHeader {
    pub header: DatasetHeader,
    /// Length of the header = offset of the first chunk.
    pub len: usize,
    /// Offset of each light's N_k field (for messages).
    pub paths_offsets: Vec<u64>,
    /// The file's format version.
    pub version: u32,
}

/// Reads and validates the header at the start of `file`.
///
/// Order: magic, header length within the file, header CRC, version, then the fields. Bytes
/// 0..16 (magic, version, header length) and the CRC in the header's last 4 bytes keep their
/// meaning in every format version, so the CRC is checked before the version is believed.
///
/// `file` holds the file's first bytes — at least its first 16 and, when the header fits in the
/// file, the whole header — and `file_len` is the file's length.
pub(crate) fn decode_header(
    path: &Path,
    file: &[u8],
    file_len: usize,
) -> Result<DecodedHeader, DatasetError> {
    let corrupt = |offset: usize, detail: String| DatasetError::Corrupt {
        path: path.to_owned(),
        offset: offset as u64,
        detail,
    };
    let truncated = |offset: usize, detail: String| DatasetError::Truncated {
        path: path.to_owned(),
        offset: offset as u64,
        detail,
    };
    let head = &file[..file.len().min(MAGIC.len())];
    if head != &MAGIC[..head.len()] || file_len == 0 {
        return Err(DatasetError::NotADataset {
            path: path.to_owned(),
            expected: &MAGIC,
            found: head.to_vec(),
        });
    }
    if file_len < 16 {
        return Err(truncated(file_len, "the file ends inside the 16-byte file signature".into()));
    }
    let version = u32::from_le_bytes(file[8..12].try_into().unwrap());
    let len = u32::from_le_bytes(file[12..16].try_into().unwrap()) as usize;
    if len < MIN_HEADER_LEN || !len.is_multiple_of(ALIGN) {
        return Err(corrupt(
            12,
            format!(
                "impossible header length {len} (must be a multiple of {ALIGN}, at least {MIN_HEADER_LEN})"
            ),
        ));
    }
    if len > file_len || len > file.len() {
        return Err(truncated(
            file_len,
            format!("the header is {len} bytes long but the file has only {file_len} bytes"),
        ));
    }
    let stored = u32::from_le_bytes(file[len - 4..len].try_into().unwrap());
    let computed = crc32fast::hash(&file[..len - 4]);
    if stored != computed {
        return Err(DatasetError::Checksum {
            path: path.to_owned(),
            offset: 0,
            what: "header".into(),
            stored,
            computed,
        });
    }
    if version > FORMAT_VERSION {
        return Err(DatasetError::NewerVersion {
            path: path.to_owned(),
            found: version,
            supported: FORMAT_VERSION,
        });
    }
    if version < OLDEST_VERSION {
        return Err(corrupt(8, format!("format version {version} does not exist")));
    }

    let body = &file[..len - 4];
    let mut c = Cursor { b: body, pos: 16, path, len };
    let mut fingerprint = Fingerprint::default();
    fingerprint.geometry.copy_from_slice(c.take(16, "geometry hash")?);
    fingerprint.lights.copy_from_slice(c.take(16, "light hash")?);
    let pass_count_at = c.pos;
    let pass_count = c.u32("pass count")? as usize;
    let record_len = match version {
        1 => PASS_RECORD_V1_LEN,
        2 => PASS_RECORD_LEN,
        _ => PASS_RECORD_V3_LEN,
    };
    if pass_count > (body.len() - c.pos) / record_len {
        return Err(corrupt(
            pass_count_at,
            format!(
                "pass count {pass_count} cannot fit in the {} bytes left in the header",
                body.len() - c.pos
            ),
        ));
    }
    let mut passes = Vec::with_capacity(pass_count);
    for i in 0..pass_count {
        let (seed, stream, paths) = (c.u64("pass seed")?, c.u64("pass stream")?, c.u64("pass paths")?);
        let rr_depth = c.u32("pass roulette depth")?;
        let seconds = f32::from_le_bytes(c.take(4, "pass seconds")?.try_into().unwrap());
        if !(seconds.is_finite() && seconds >= 0.0) {
            return Err(corrupt(
                c.pos - 4,
                format!("pass duration {seconds} is not a valid number of seconds"),
            ));
        }
        let mut pass = TracePass { seed, stream, paths, rr_depth, seconds, ..Default::default() };
        if version >= 2 {
            let at = c.pos;
            let codes = c.take(4, "pass strategy")?;
            let bad = |what: &str, code: u8| corrupt(at, format!("pass {i}: unknown {what} code {code}"));
            pass.roulette = roulette_from(codes[0]).ok_or_else(|| bad("roulette", codes[0]))?;
            pass.directions = directions_from(codes[1]).ok_or_else(|| bad("directions", codes[1]))?;
            pass.selection = selection_from(codes[2]).ok_or_else(|| bad("selection", codes[2]))?;
            if version == 2 && codes[3] != 0 {
                return Err(corrupt(at + 3, format!("pass {i}: non-zero reserved byte")));
            }
            if version >= 3 {
                let heuristic = mis_from(codes[3]).ok_or_else(|| bad("MIS heuristic", codes[3]))?;
                let signature_at = c.pos;
                let signature = c.u32("pass sampling signature")?;
                pass.mis = match (heuristic, signature) {
                    (None, 0) => None,
                    (Some(heuristic), s) if s != 0 => Some(PassMis { heuristic, signature: s }),
                    (None, s) => {
                        return Err(corrupt(
                            signature_at,
                            format!("pass {i}: sampling signature {s} for a pass without MIS records"),
                        ));
                    }
                    (Some(_), _) => {
                        return Err(corrupt(
                            signature_at,
                            format!("pass {i}: MIS records with sampling signature 0"),
                        ));
                    }
                };
            }
            let planned_at = c.pos;
            let n = c.u32("pass plan length")? as usize;
            if n > (body.len() - c.pos) / PLAN_ENTRY_LEN {
                return Err(corrupt(
                    planned_at,
                    format!(
                        "pass {i}: plan of {n} lights cannot fit in the {} bytes left",
                        body.len() - c.pos
                    ),
                ));
            }
            let mut planned = 0u64;
            for _ in 0..n {
                let light = c.u32("planned light")?;
                let paths = c.u64("planned paths")?;
                planned = planned.checked_add(paths).filter(|&t| t <= MAX_PATHS).ok_or_else(|| {
                    corrupt(c.pos - 8, format!("pass {i} plans more than the maximum of {MAX_PATHS} paths"))
                })?;
                pass.planned.push((light, paths));
            }
            if pass.paths > pass.planned_paths() {
                return Err(corrupt(
                    planned_at,
                    format!("pass {i} traced {} paths but planned only {}", pass.paths, pass.planned_paths()),
                ));
            }
        }
        passes.push(pass);
    }
    let label = c.string("scene label")?;
    let label_end = c.pos;
    let n = c.u32("light count")? as usize;
    // Never allocate from an unchecked count: each light needs at least LIGHT_RECORD_MIN bytes.
    if n > (body.len() - c.pos) / LIGHT_RECORD_MIN {
        return Err(corrupt(
            label_end,
            format!("light count {n} cannot fit in the {} bytes left in the header", body.len() - c.pos),
        ));
    }
    let mut lights = Vec::with_capacity(n);
    let mut paths_offsets = Vec::with_capacity(n);
    for k in 0..n {
        let name = c.string(&format!("name of light {k}"))?;
        let mut shape = [0u8; 16];
        shape.copy_from_slice(c.take(16, "light shape hash")?);
        let mut p = [0f32; 3];
        for x in &mut p {
            *x = f32::from_le_bytes(c.take(4, "light power")?.try_into().unwrap());
        }
        if !p.iter().all(|x| x.is_finite() && *x >= 0.0) {
            return Err(corrupt(c.pos - 12, format!("light {k} ({name:?}) has invalid power {p:?}")));
        }
        paths_offsets.push(c.pos as u64);
        let paths = c.u64("light path count")?;
        lights.push(LightRecord { name, shape, power: Rgb::from_array(p), paths });
    }
    let objects = if version >= 4 { decode_objects(&mut c, &corrupt)? } else { Vec::new() };
    for (i, p) in passes.iter().enumerate() {
        if let Some(&(light, _)) = p.planned.iter().find(|q| q.0 as usize >= n) {
            return Err(corrupt(
                pass_count_at,
                format!("pass {i} plans paths for light {light}, but the light table has {n} lights"),
            ));
        }
    }
    if align_up(c.pos + 4) != len {
        return Err(corrupt(
            12,
            format!("header length {len} disagrees with its contents ({} bytes + CRC, padded)", c.pos),
        ));
    }
    if let Some(i) = body[c.pos..].iter().position(|&x| x != 0) {
        return Err(corrupt(c.pos + i, "non-zero byte in the header padding".into()));
    }
    Ok(DecodedHeader {
        header: DatasetHeader {
            fingerprint,
            objects,
            label,
            trace: TraceInfo { passes },
            table: LightTable { lights },
        },
        len,
        paths_offsets,
        version,
    })
}

/// The object table of a format-4 header: a count, then per object its kind, name and hash.
fn decode_objects(
    c: &mut Cursor<'_>,
    corrupt: &dyn Fn(usize, String) -> DatasetError,
) -> Result<Vec<ObjectHash>, DatasetError> {
    let count_at = c.pos;
    let n = c.u32("object count")? as usize;
    // Never allocate from an unchecked count: each object needs OBJECT_RECORD_MIN bytes.
    if n > (c.b.len() - c.pos) / OBJECT_RECORD_MIN {
        return Err(corrupt(
            count_at,
            format!("object count {n} cannot fit in the {} bytes left in the header", c.b.len() - c.pos),
        ));
    }
    let mut objects = Vec::with_capacity(n);
    for i in 0..n {
        let at = c.pos;
        let code = c.take(1, "object kind")?[0];
        let kind =
            object_from(code).ok_or_else(|| corrupt(at, format!("object {i}: unknown kind code {code}")))?;
        let name = c.string(&format!("name of object {i}"))?;
        let mut hash = [0u8; 16];
        hash.copy_from_slice(c.take(16, "object hash")?);
        objects.push(ObjectHash { kind, name, hash });
    }
    Ok(objects)
}

fn object_code(k: ObjectKind) -> u8 {
    match k {
        ObjectKind::Mesh => 0,
        ObjectKind::Material => 1,
    }
}
fn object_from(c: u8) -> Option<ObjectKind> {
    [ObjectKind::Mesh, ObjectKind::Material].into_iter().find(|&k| object_code(k) == c)
}

// Strategy codes of a pass record (a closed set each; unknown codes are corruption).
fn roulette_code(r: Roulette) -> u8 {
    match r {
        Roulette::Energy => 0,
        Roulette::Fixed => 1,
    }
}
fn roulette_from(c: u8) -> Option<Roulette> {
    [Roulette::Energy, Roulette::Fixed].into_iter().find(|&r| roulette_code(r) == c)
}
fn directions_code(d: Directions) -> u8 {
    match d {
        Directions::Importance => 0,
        Directions::Uniform => 1,
    }
}
fn directions_from(c: u8) -> Option<Directions> {
    [Directions::Importance, Directions::Uniform].into_iter().find(|&d| directions_code(d) == c)
}
fn selection_code(s: Selection) -> u8 {
    match s {
        Selection::Single => 0,
        Selection::Priority => 1,
    }
}
fn selection_from(c: u8) -> Option<Selection> {
    [Selection::Single, Selection::Priority].into_iter().find(|&s| selection_code(s) == c)
}
/// The pass's MIS byte: 0 no records, 1 + [`Heuristic::code`] otherwise.
fn mis_code(h: Option<Heuristic>) -> u8 {
    h.map_or(0, |h| h.code() + 1)
}
/// `None` for an unknown code; `Some(None)` for "no records".
fn mis_from(c: u8) -> Option<Option<Heuristic>> {
    match c {
        0 => Some(None),
        c => Heuristic::from_code(c - 1).map(Some),
    }
}

struct Cursor<'a> {
    b: &'a [u8],
    pos: usize,
    path: &'a Path,
    len: usize,
}

impl<'a> Cursor<'a> {
    fn take(&mut self, n: usize, what: &str) -> Result<&'a [u8], DatasetError> {
        if n > self.b.len() - self.pos {
            return Err(DatasetError::Corrupt {
                path: self.path.to_owned(),
                offset: self.pos as u64,
                detail: format!("{what} ({n} bytes) runs past the end of the {}-byte header", self.len),
            });
        }
        let s = &self.b[self.pos..self.pos + n];
        self.pos += n;
        Ok(s)
    }
    fn u32(&mut self, what: &str) -> Result<u32, DatasetError> {
        Ok(u32::from_le_bytes(self.take(4, what)?.try_into().unwrap()))
    }
    fn u64(&mut self, what: &str) -> Result<u64, DatasetError> {
        Ok(u64::from_le_bytes(self.take(8, what)?.try_into().unwrap()))
    }
    fn string(&mut self, what: &str) -> Result<String, DatasetError> {
        let at = self.pos;
        let n = self.u32(what)? as usize;
        let bytes = self.take(n, what)?;
        String::from_utf8(bytes.to_vec()).map_err(|e| DatasetError::Corrupt {
            path: self.path.to_owned(),
            offset: (at + 4 + e.utf8_error().valid_up_to()) as u64,
            detail: format!("{what} is not valid UTF-8"),
        })
    }
}

/// A chunk header: 32 bytes. Version 3 splits version 2's u64 sample count into a u32 count
/// and a u32 of flags, of which bit 0 ([`RECORDS_FLAG`]) says that a block of MIS records
/// follows the samples (on a little-endian disk a version-3 header without records is a
/// version-2 header).
#[derive(Clone, Copy, Debug)]
pub(crate) struct ChunkHeader {
    pub light: u32,
    pub paths: u64,
    pub count: u64,
    /// Whether a record block follows the samples (version 3).
    pub records: bool,
    pub payload_crc: u32,
}

/// The flag of a version-3 chunk header whose samples are followed by their MIS records.
pub(crate) const RECORDS_FLAG: u32 = 1;

/// Why a chunk header does not decode.
pub(crate) enum ChunkHeaderError {
    /// Its CRC: (stored, computed).
    Checksum(u32, u32),
    /// Version 3: unknown flag bits (at byte 20 of the header).
    Flags(u32),
}

impl ChunkHeader {
    /// Encodes in the current format; `count` must fit 32 bits.
    pub(crate) fn encode(&self) -> [u8; CHUNK_HEADER_LEN] {
        debug_assert!(self.count <= u32::MAX as u64);
        let mut b = [0u8; CHUNK_HEADER_LEN];
        b[0..4].copy_from_slice(&CHUNK_MAGIC);
        b[4..8].copy_from_slice(&self.light.to_le_bytes());
        b[8..16].copy_from_slice(&self.paths.to_le_bytes());
        b[16..20].copy_from_slice(&(self.count as u32).to_le_bytes());
        b[20..24].copy_from_slice(&(if self.records { RECORDS_FLAG } else { 0 }).to_le_bytes());
        b[24..28].copy_from_slice(&self.payload_crc.to_le_bytes());
        let crc = crc32fast::hash(&b[..28]);
        b[28..32].copy_from_slice(&crc.to_le_bytes());
        b
    }

    /// Decodes a header of format `version` after the caller has checked the magic.
    pub(crate) fn decode(b: &[u8; CHUNK_HEADER_LEN], version: u32) -> Result<Self, ChunkHeaderError> {
        let stored = u32::from_le_bytes(b[28..32].try_into().unwrap());
        let computed = crc32fast::hash(&b[..28]);
        if stored != computed {
            return Err(ChunkHeaderError::Checksum(stored, computed));
        }
        let (count, records) = if version >= 3 {
            let flags = u32::from_le_bytes(b[20..24].try_into().unwrap());
            if flags & !RECORDS_FLAG != 0 {
                return Err(ChunkHeaderError::Flags(flags));
            }
            (u32::from_le_bytes(b[16..20].try_into().unwrap()) as u64, flags == RECORDS_FLAG)
        } else {
            (u64::from_le_bytes(b[16..24].try_into().unwrap()), false)
        };
        Ok(ChunkHeader {
            light: u32::from_le_bytes(b[4..8].try_into().unwrap()),
            paths: u64::from_le_bytes(b[8..16].try_into().unwrap()),
            count,
            records,
            payload_crc: u32::from_le_bytes(b[24..28].try_into().unwrap()),
        })
    }
}

/// Bytes of the record block of a chunk of `count` samples: the records, zero padding, and
/// the block's CRC-32 in its last 4 bytes, the whole a multiple of 32 (`None` on overflow).
pub(crate) fn record_block_len(count: u64) -> Option<u64> {
    let raw = count.checked_mul(size_of::<MisRecord>() as u64)?.checked_add(4)?;
    Some(raw.div_ceil(ALIGN as u64) * ALIGN as u64)
}

/// Appends the record block of `records` to `out`: the records, zero padding, CRC-32 of
/// everything before it. Built where it goes (the writer's buffer), not in a block of its own
/// copied there afterwards.
pub(crate) fn append_record_block(records: &[MisRecord], out: &mut Vec<u8>) {
    let len = record_block_len(records.len() as u64).expect("an in-memory slice's length fits") as usize;
    let start = out.len();
    out.reserve(len);
    out.extend_from_slice(bytemuck::cast_slice(records));
    out.resize(start + len - 4, 0);
    let crc = crc32fast::hash(&out[start..]);
    out.extend_from_slice(&crc.to_le_bytes());
}

/// The end record: 32 bytes.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) struct Trailer {
    pub chunks: u64,
    pub samples: u64,
    pub paths: u64,
}

impl Trailer {
    pub(crate) fn encode(&self) -> [u8; TRAILER_LEN] {
        let mut b = [0u8; TRAILER_LEN];
        b[0..4].copy_from_slice(&END_MAGIC);
        b[4..12].copy_from_slice(&self.chunks.to_le_bytes());
        b[12..20].copy_from_slice(&self.samples.to_le_bytes());
        b[20..28].copy_from_slice(&self.paths.to_le_bytes());
        let crc = crc32fast::hash(&b[..28]);
        b[28..32].copy_from_slice(&crc.to_le_bytes());
        b
    }

    pub(crate) fn decode(b: &[u8; TRAILER_LEN]) -> Result<Self, (u32, u32)> {
        let stored = u32::from_le_bytes(b[28..32].try_into().unwrap());
        let computed = crc32fast::hash(&b[..28]);
        if stored != computed {
            return Err((stored, computed));
        }
        Ok(Trailer {
            chunks: u64::from_le_bytes(b[4..12].try_into().unwrap()),
            samples: u64::from_le_bytes(b[12..20].try_into().unwrap()),
            paths: u64::from_le_bytes(b[20..28].try_into().unwrap()),
        })
    }
}

/// The first bad sample or record of a chunk ([`validate_samples`], [`validate_records`]): its
/// index in the chunk and what is wrong with it.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct Invalid<F> {
    /// Index within the chunk.
    pub(crate) index: usize,
    /// What is wrong.
    pub(crate) fault: F,
}

/// Checks what a checksum cannot: that every sample is physically possible (finite position,
/// finite non-negative β) and, given the scene's triangle count, names an existing triangle.
/// Returns the index of the first bad sample and what is wrong.
pub(crate) fn validate_samples(
    samples: &[Sample],
    triangles: Option<u32>,
) -> Result<(), Invalid<SampleFault>> {
    // All samples checked first without a branch per sample (what a render reads from a file
    // pays per sample); the first bad sample looked for only if there is one.
    let n = triangles.unwrap_or(u32::MAX);
    if samples.iter().fold(true, |ok, s| ok & values_possible(s) & (s.triangle() < n)) {
        return Ok(());
    }
    for (index, s) in samples.iter().enumerate() {
        if !values_possible(s) {
            let fault = SampleFault::NonFinite { position: s.position, beta: s.beta };
            return Err(Invalid { index, fault });
        }
        if let Some(n) = triangles.filter(|&n| s.triangle() >= n) {
            let fault = SampleFault::NoSuchTriangle { triangle: s.triangle(), triangles: n };
            return Err(Invalid { index, fault });
        }
    }
    Ok(())
}

/// Whether a sample's position is finite and its β finite and non-negative, on the bits and
/// without a branch: a float is finite iff its magnitude bits are below +∞'s; β ≥ 0 and < +∞
/// iff its bits are below +∞'s or it is −0 (NaN fails both).
#[inline(always)]
fn values_possible(s: &Sample) -> bool {
    const INF: u32 = 0x7f80_0000;
    let finite = |x: f32| (x.to_bits() & 0x7fff_ffff) < INF;
    let beta = |x: f32| (x.to_bits() < INF) | (x.to_bits() == 0x8000_0000);
    finite(s.position[0])
        & finite(s.position[1])
        & finite(s.position[2])
        & beta(s.beta[0])
        & beta(s.beta[1])
        & beta(s.beta[2])
}

/// Checks what a record block's checksum cannot: that every record is possible
/// ([`MisRecord::is_valid`]: each field ≥ 0 or +∞) and that its class agrees with its sample
/// (the emitter-hit class exactly on emission samples). Returns the index of the first bad
/// record and what is wrong.
pub(crate) fn validate_records(
    samples: &[Sample],
    records: &[MisRecord],
) -> Result<(), Invalid<RecordFault>> {
    // As `validate_samples`: every pair checked first on the bits, without a branch; the first
    // bad record looked for only if there is one.
    if samples.iter().zip(records).fold(true, |ok, (s, r)| ok & record_possible(s, r)) {
        return Ok(());
    }
    for (index, (s, r)) in samples.iter().zip(records).enumerate() {
        if !r.is_valid() {
            return Err(Invalid { index, fault: RecordFault::Quantity(*r) });
        }
        let hit = r.class() == VcmClass::Hit;
        if hit != s.is_emission() {
            let fault = if hit { RecordFault::HitOnReflection } else { RecordFault::EmissionWithoutHit };
            return Err(Invalid { index, fault });
        }
    }
    Ok(())
}

/// [`MisRecord::is_valid`] and a class that agrees with the sample, on the bits: a field
/// whose class bit is removed is ≥ 0 or +∞ unless it is a NaN (magnitude bits above +∞'s),
/// the other two as a sample's β (`values_possible`), and the class is the emitter hit's
/// exactly when `vc_hit`'s sign bit is set ([`MisRecord::class`]).
#[inline(always)]
fn record_possible(s: &Sample, r: &MisRecord) -> bool {
    const INF: u32 = 0x7f80_0000;
    let [vcm, vc_hit, vc_nee, vc_conn]: [u32; 4] = bytemuck::cast(*r);
    let magnitude = |x: u32| (x & 0x7fff_ffff) <= INF;
    let plain = |x: u32| (x <= INF) | (x == 0x8000_0000);
    magnitude(vcm)
        & magnitude(vc_hit)
        & plain(vc_nee)
        & plain(vc_conn)
        & ((vc_hit >> 31 != 0) == s.is_emission())
}

#[cfg(test)]
mod tests {
    use super::*;
    use opticks_core::math::Vec3;

    /// The writer's and reader's pass over the bits accepts exactly the records that
    /// `MisRecord::is_valid` does with a class agreeing with their sample, for every mix of
    /// zeros, numbers, infinities and NaNs of either sign.
    #[test]
    fn the_bitwise_record_check_is_the_field_check() {
        let values = [0.0f32, -0.0, 1.5, -1.5, f32::INFINITY, f32::NEG_INFINITY, f32::NAN, -f32::NAN];
        let sample =
            |emission: bool| Sample { prim: if emission { 1 << 31 } else { 3 }, ..Default::default() };
        for i in 0..values.len().pow(4) {
            let f = |k: u32| values[i / values.len().pow(k) % values.len()].to_bits();
            let r: MisRecord = bytemuck::cast([f(0), f(1), f(2), f(3)]);
            for emission in [false, true] {
                let s = sample(emission);
                let expected = r.is_valid() && (r.class() == VcmClass::Hit) == s.is_emission();
                assert_eq!(record_possible(&s, &r), expected, "{r:?}, emission {emission}");
                assert_eq!(validate_records(&[s], &[r]).is_ok(), expected, "{r:?}, emission {emission}");
            }
        }
    }

    /// The branch-free pass over whole blocks finds every kind of impossible sample wherever it
    /// sits (the first of a block, the last, past the first block), and names the first one.
    #[test]
    fn every_impossible_sample_is_found_and_named() {
        let good = |i: usize| {
            Sample::scattered(
                Vec3::new(i as f32, -1.0, 0.5),
                Vec3::Z,
                (i % 7) as u32,
                Rgb::new(0.5, 0.0, 2.0),
            )
        };
        let samples: Vec<Sample> = (0..200).map(good).collect();
        assert!(validate_samples(&samples, Some(7)).is_ok());
        let mut negative_zero = samples.clone();
        negative_zero[70].beta[1] = -0.0;
        assert!(validate_samples(&negative_zero, Some(7)).is_ok(), "−0 is a possible β");
        type Spoil = fn(&mut Sample);
        let faults: [(Spoil, bool); 7] = [
            (|s| s.position[0] = f32::NAN, false),
            (|s| s.position[2] = f32::NEG_INFINITY, false),
            (|s| s.beta[0] = -1e-30, false),
            (|s| s.beta[1] = f32::INFINITY, false),
            (|s| s.beta[2] = f32::NAN, false),
            (|s| s.prim = 7, true),
            (|s| s.prim = 1 << 30, true),
        ];
        for (spoil, names_triangle) in faults {
            for at in [0, 63, 64, 130, 199] {
                let mut bad = samples.clone();
                spoil(&mut bad[at]);
                spoil(&mut bad[(at + 5).min(199)]);
                let e = validate_samples(&bad, Some(7)).unwrap_err();
                assert_eq!(e.index, at);
                assert_eq!(matches!(e.fault, SampleFault::NoSuchTriangle { .. }), names_triangle);
                // Without the scene's triangle count, only the values are checked.
                assert_eq!(validate_samples(&bad, None).is_ok(), names_triangle);
            }
        }
    }
}
