//! The messages of a cluster job (the CLI's `--features mpi` build, docs/cluster.md), as bytes:
//! tags, and the encoding of jobs, blocks and chunks. Pure bytes — the transport (MPI) is the
//! CLI's, so nothing here depends on it. Both ends run the same `opticks` binary, so the format
//! needs no versioning; numbers are little-endian, and samples travel in their compact 32-byte
//! form, exactly as the dataset file stores them (`opticks_core::dataset::Sample` is plain old
//! data), followed by their 16-byte MIS records when the pass stores them (`--mis-records`), so
//! the master writes the same format-3 chunks as a single process.
//!
//! A decoding error means a peer sent something this binary does not write: it is reported as
//! an error naming the message, never a panic.

use opticks_core::dataset::{
    Block, Chunk, Directions, Heuristic, LightPlan, MisRecord, Roulette, Sample, Selection, TraceSettings,
};
use opticks_core::scene::Fingerprint;

/// Master → worker: a trace job ([`TraceJob`]).
pub const JOB: i32 = 1;
/// Master → worker: the end of the session; the worker answers [`BYE`] and exits.
pub const QUIT: i32 = 2;
/// Master → worker: blocks to trace ([`encode_blocks`]); none = the job is over.
pub const BLOCKS: i32 = 3;
/// Worker → master: the job's scene is loaded; asks for blocks (payload: [`encode_ready`]).
pub const READY: i32 = 10;
/// Worker → master: the job cannot be done here (payload: the message, UTF-8).
pub const FAILED: i32 = 11;
/// Worker → master: traced chunks ([`encode_chunks`]).
pub const RESULT: i32 = 12;
/// Worker → master: a request for the next blocks, sent before it traces the ones it has, so
/// the answer is there when it is done (payload: how many, u64).
pub const REQUEST: i32 = 14;
/// Worker → master: the answer to [`QUIT`].
pub const BYE: i32 = 13;
/// Worker → master: one run's film of a distributed render (f64 pixels, sent as they are).
pub const FILM: i32 = 20;
/// Worker → master: this rank's share of a split verb is done (walk's frames; empty payload).
pub const DONE: i32 = 21;

/// A message that does not decode.
#[derive(Debug, thiserror::Error)]
#[error("malformed {what} message at byte {at}")]
pub struct Malformed {
    what: &'static str,
    at: usize,
}

/// Appends little-endian numbers and strings.
#[derive(Default)]
pub struct Writer(pub Vec<u8>);

impl Writer {
    fn u8(&mut self, v: u8) -> &mut Self {
        self.0.push(v);
        self
    }
    fn u32(&mut self, v: u32) -> &mut Self {
        self.0.extend_from_slice(&v.to_le_bytes());
        self
    }
    fn u64(&mut self, v: u64) -> &mut Self {
        self.0.extend_from_slice(&v.to_le_bytes());
        self
    }
    fn bytes(&mut self, v: &[u8]) -> &mut Self {
        self.u64(v.len() as u64);
        self.0.extend_from_slice(v);
        self
    }
}

/// Reads what [`Writer`] wrote, checking every length against what is there.
pub struct Reader<'a> {
    data: &'a [u8],
    at: usize,
    what: &'static str,
}

impl<'a> Reader<'a> {
    fn new(data: &'a [u8], what: &'static str) -> Self {
        Reader { data, at: 0, what }
    }
    fn take(&mut self, n: usize) -> Result<&'a [u8], Malformed> {
        let end = self.at.checked_add(n).filter(|&e| e <= self.data.len());
        let end = end.ok_or(Malformed { what: self.what, at: self.at })?;
        let s = &self.data[self.at..end];
        self.at = end;
        Ok(s)
    }
    fn u8(&mut self) -> Result<u8, Malformed> {
        Ok(self.take(1)?[0])
    }
    fn u32(&mut self) -> Result<u32, Malformed> {
        Ok(u32::from_le_bytes(self.take(4)?.try_into().expect("4 bytes")))
    }
    fn u64(&mut self) -> Result<u64, Malformed> {
        Ok(u64::from_le_bytes(self.take(8)?.try_into().expect("8 bytes")))
    }
    fn len(&mut self) -> Result<usize, Malformed> {
        let at = self.at;
        usize::try_from(self.u64()?).map_err(|_| Malformed { what: self.what, at })
    }
    fn bytes(&mut self) -> Result<&'a [u8], Malformed> {
        let n = self.len()?;
        self.take(n)
    }
    fn string(&mut self) -> Result<String, Malformed> {
        let at = self.at;
        let b = self.bytes()?;
        String::from_utf8(b.to_vec()).map_err(|_| Malformed { what: self.what, at })
    }
    fn end(&self) -> Result<(), Malformed> {
        match self.at == self.data.len() {
            true => Ok(()),
            false => Err(Malformed { what: self.what, at: self.at }),
        }
    }
    fn bad(&self) -> Malformed {
        Malformed { what: self.what, at: self.at }
    }
}

/// What a worker needs for a trace job: the scene to load (a path every rank can read, or
/// `builtin:cornell`) with its `-D` parameters, the fingerprint its scene must have, and the
/// pass's settings. The blocks themselves come one request at a time.
#[derive(Clone, Debug, PartialEq)]
pub struct TraceJob {
    /// Scene file (absolute path) or built-in scene.
    pub scene: String,
    /// The scene's parameters (`-D NAME=VALUE`), in the order given.
    pub defines: Vec<(String, String)>,
    /// The scene of a glTF file holding several (`--gltf-scene`), if one was chosen.
    pub gltf_scene: Option<String>,
    /// The master's memory limits on loading (`--max-texels`, `--max-mesh-expansion`), so a
    /// worker loads whatever the master loaded.
    pub limits: crate::scene_formats::LoadLimits,
    /// The master's scene fingerprint: a worker whose scene differs refuses the job.
    pub fingerprint: Fingerprint,
    /// Seed, stream and strategy.
    pub settings: TraceSettings,
}

/// Encodes a job.
pub fn encode_job(job: &TraceJob) -> Vec<u8> {
    let s = &job.settings;
    let mut w = Writer::default();
    w.bytes(job.scene.as_bytes()).u64(job.defines.len() as u64);
    for (name, value) in &job.defines {
        w.bytes(name.as_bytes()).bytes(value.as_bytes());
    }
    match &job.gltf_scene {
        None => w.u8(0),
        Some(name) => w.u8(1).bytes(name.as_bytes()),
    };
    w.u64(job.limits.max_texels).u64(job.limits.max_mesh_expansion);
    w.bytes(&job.fingerprint.geometry).bytes(&job.fingerprint.lights);
    w.u64(s.paths).u64(s.seed).u64(s.stream).u32(s.rr_depth);
    w.u8(match s.roulette {
        Roulette::Energy => 0,
        Roulette::Fixed => 1,
    });
    w.u8(match s.directions {
        Directions::Importance => 0,
        Directions::Uniform => 1,
    });
    w.u8(match s.selection {
        Selection::Single => 0,
        Selection::Priority => 1,
    });
    w.u8(s.mis.map_or(0, |h| 1 + h.code()));
    w.0
}

/// Decodes a job.
pub fn decode_job(data: &[u8]) -> Result<TraceJob, Malformed> {
    let mut r = Reader::new(data, "job");
    let scene = r.string()?;
    let n = r.len()?;
    // Each parameter takes at least its two lengths: a larger count is malformed, not allocated.
    if n > data.len() / 16 {
        return Err(r.bad());
    }
    let defines = (0..n).map(|_| Ok((r.string()?, r.string()?))).collect::<Result<Vec<_>, Malformed>>()?;
    let gltf_scene = match r.u8()? {
        0 => None,
        1 => Some(r.string()?),
        _ => return Err(r.bad()),
    };
    let limits = crate::scene_formats::LoadLimits { max_texels: r.u64()?, max_mesh_expansion: r.u64()? };
    let hash = |r: &mut Reader<'_>| -> Result<[u8; 16], Malformed> {
        r.bytes()?.try_into().map_err(|_| Malformed { what: "job", at: r.at })
    };
    let fingerprint = Fingerprint { geometry: hash(&mut r)?, lights: hash(&mut r)? };
    let (paths, seed, stream, rr_depth) = (r.u64()?, r.u64()?, r.u64()?, r.u32()?);
    let roulette = match r.u8()? {
        0 => Roulette::Energy,
        1 => Roulette::Fixed,
        _ => return Err(r.bad()),
    };
    let directions = match r.u8()? {
        0 => Directions::Importance,
        1 => Directions::Uniform,
        _ => return Err(r.bad()),
    };
    let selection = match r.u8()? {
        0 => Selection::Single,
        1 => Selection::Priority,
        _ => return Err(r.bad()),
    };
    let mis = match r.u8()? {
        0 => None,
        c => Some(Heuristic::from_code(c - 1).ok_or_else(|| r.bad())?),
    };
    r.end()?;
    let settings = TraceSettings { paths, seed, stream, rr_depth, roulette, directions, selection, mis };
    Ok(TraceJob { scene, defines, gltf_scene, limits, fingerprint, settings })
}

use opticks_core::dataset::NumberedBlock as Numbered;

/// Bytes of one encoded block.
const BLOCK_BYTES: usize = 44;

/// Encodes blocks to trace (none: the job is over for this worker).
pub fn encode_blocks(blocks: &[Numbered]) -> Vec<u8> {
    let mut w = Writer::default();
    w.u64(blocks.len() as u64);
    for (seq, b) in blocks {
        w.u64(*seq).u64(b.light.scene_light as u64).u32(b.light.table_index).u64(b.light.paths);
        w.u64(b.index).u64(b.paths);
    }
    w.0
}

/// Decodes blocks to trace.
pub fn decode_blocks(data: &[u8]) -> Result<Vec<Numbered>, Malformed> {
    let mut r = Reader::new(data, "blocks");
    let n = r.len()?;
    // A count larger than the message could hold is malformed, not allocated.
    if n > data.len() / BLOCK_BYTES {
        return Err(r.bad());
    }
    let mut blocks = Vec::with_capacity(n);
    for _ in 0..n {
        let seq = r.u64()?;
        let scene_light = usize::try_from(r.u64()?).map_err(|_| r.bad())?;
        let light = LightPlan { scene_light, table_index: r.u32()?, paths: r.u64()? };
        blocks.push((seq, Block { light, index: r.u64()?, paths: r.u64()? }));
    }
    r.end()?;
    Ok(blocks)
}

/// A worker's request for blocks: its host name and how many blocks it wants at a time.
pub fn encode_ready(host: &str, want: usize) -> Vec<u8> {
    let mut w = Writer::default();
    w.bytes(host.as_bytes()).u64(want as u64);
    w.0
}

/// Decodes a [`READY`] message.
pub fn decode_ready(data: &[u8]) -> Result<(String, usize), Malformed> {
    let mut r = Reader::new(data, "ready");
    let host = r.string()?;
    let want = r.len()?;
    r.end()?;
    Ok((host, want))
}

/// Bytes of a chunk's header on the wire: block number, light, paths, sample bytes, record bytes.
const CHUNK_HEADER_BYTES: usize = 8 + 4 + 8 + 8 + 8;

/// Encodes traced chunks with their block numbers. The samples go as their 32 bytes each, then
/// their MIS records as 16 bytes each (none when the chunk has none), as the dataset stores
/// them but without the file's padding and checksums (MPI's transport has its own).
pub fn encode_chunks(chunks: &[(u64, Chunk)]) -> Vec<u8> {
    let bytes: usize =
        chunks.iter().map(|(_, c)| CHUNK_HEADER_BYTES + c.samples.len() * 32 + c.records.len() * 16).sum();
    let mut w = Writer(Vec::with_capacity(bytes + 8));
    w.u64(chunks.len() as u64);
    for (seq, c) in chunks {
        w.u64(*seq).u32(c.light).u64(c.paths);
        w.bytes(bytemuck::cast_slice(&c.samples));
        w.bytes(bytemuck::cast_slice(&c.records));
    }
    w.0
}

/// Decodes a [`RESULT`] message.
pub fn decode_chunks(data: &[u8]) -> Result<Vec<(u64, Chunk)>, Malformed> {
    let mut r = Reader::new(data, "result");
    let n = r.len()?;
    if n > data.len() / CHUNK_HEADER_BYTES {
        return Err(r.bad());
    }
    let mut chunks = Vec::with_capacity(n);
    for _ in 0..n {
        let (seq, light, paths) = (r.u64()?, r.u32()?, r.u64()?);
        let raw = r.bytes()?;
        if raw.len() % 32 != 0 {
            return Err(r.bad());
        }
        // Copied, not cast in place: the message buffer need not be aligned for `Sample`.
        let samples: Vec<Sample> = raw.chunks_exact(32).map(bytemuck::pod_read_unaligned).collect();
        let raw = r.bytes()?;
        // Records: none, or one per sample, each valid (as a reader checks them).
        if !(raw.is_empty() || raw.len() == samples.len() * 16) {
            return Err(r.bad());
        }
        let records: Vec<MisRecord> = raw.chunks_exact(16).map(bytemuck::pod_read_unaligned).collect();
        if !records.iter().all(MisRecord::is_valid) {
            return Err(r.bad());
        }
        chunks.push((seq, Chunk { light, paths, samples, records }));
    }
    r.end()?;
    Ok(chunks)
}

/// Encodes a [`REQUEST`] for `want` blocks.
pub fn encode_request(want: usize) -> Vec<u8> {
    (want as u64).to_le_bytes().to_vec()
}

/// Decodes a [`REQUEST`].
pub fn decode_request(data: &[u8]) -> Result<usize, Malformed> {
    let mut r = Reader::new(data, "request");
    let want = r.len()?;
    r.end()?;
    Ok(want)
}

#[cfg(test)]
mod tests {
    use super::*;
    use opticks_core::math::{Rgb, Vec3};

    #[test]
    fn every_message_decodes_to_what_was_encoded() {
        let settings = TraceSettings {
            paths: 123_456,
            seed: 9,
            stream: 2,
            rr_depth: 3,
            roulette: Roulette::Fixed,
            directions: Directions::Uniform,
            selection: Selection::Priority,
            mis: Some(Heuristic::Power),
        };
        let job = TraceJob {
            scene: "/data/scène.xml".into(),
            defines: vec![("spp".into(), "4".into()), ("name".into(), "wall é".into())],
            gltf_scene: Some("Interior".into()),
            limits: crate::scene_formats::LoadLimits { max_texels: 5, max_mesh_expansion: 1000 },
            fingerprint: Fingerprint { geometry: [7; 16], lights: [3; 16] },
            settings,
        };
        assert_eq!(decode_job(&encode_job(&job)).unwrap(), job);
        let plain = TraceJob {
            defines: vec![],
            gltf_scene: None,
            limits: Default::default(),
            settings: TraceSettings { mis: None, ..settings },
            ..job
        };
        assert_eq!(decode_job(&encode_job(&plain)).unwrap(), plain);
        let light = LightPlan { scene_light: 4, table_index: 1, paths: 9000 };
        let blocks =
            vec![(5, Block { light, index: 2, paths: 808 }), (6, Block { light, index: 0, paths: 1 })];
        assert_eq!(decode_blocks(&encode_blocks(&blocks)).unwrap(), blocks);
        let many: Vec<Numbered> = (0..100).map(|i| (i, Block { light, index: i, paths: 4096 })).collect();
        assert_eq!(encode_blocks(&many).len(), 8 + 100 * BLOCK_BYTES);
        assert_eq!(decode_blocks(&encode_blocks(&many)).unwrap(), many);
        assert_eq!(decode_ready(&encode_ready("node-7", 16)).unwrap(), ("node-7".to_string(), 16));
        let s = Sample::scattered(Vec3::new(1.0, 2.0, 3.0), Vec3::Y, 11, Rgb::new(0.5, 0.25, 1.0));
        let samples = vec![s, Sample::emitted(Vec3::X, 2)];
        let chunks = vec![(3, Chunk { light: 1, paths: 4096, samples: samples.clone(), records: vec![] })];
        let bytes = encode_chunks(&chunks);
        assert_eq!(bytes.len(), 8 + CHUNK_HEADER_BYTES + 2 * 32, "32 bytes a sample on the wire");
        assert_eq!(decode_chunks(&bytes).unwrap(), chunks);
        let records: Vec<MisRecord> = vec![bytemuck::cast([0.5f32, 1.0, 2.0, 0.0]), MisRecord::default()];
        let with = vec![(4, Chunk { light: 0, paths: 7, samples, records })];
        let bytes = encode_chunks(&with);
        assert_eq!(bytes.len(), 8 + CHUNK_HEADER_BYTES + 2 * (32 + 16), "and 16 a record");
        assert_eq!(decode_chunks(&bytes).unwrap(), with);
        // Records for only some samples, or an invalid (negative) one, are malformed.
        let mut short = with.clone();
        short[0].1.records.pop();
        assert!(decode_chunks(&encode_chunks(&short)).is_err());
        let mut negative = with;
        negative[0].1.records[1] = bytemuck::cast([0.0f32, 0.0, -1.0, 0.0]);
        assert!(decode_chunks(&encode_chunks(&negative)).is_err());
        assert_eq!(decode_request(&encode_request(12)).unwrap(), 12);
    }

    #[test]
    fn a_truncated_or_padded_message_is_an_error_not_a_panic() {
        let light = LightPlan { scene_light: 0, table_index: 0, paths: 1 };
        let bytes = encode_blocks(&[(0, Block { light, index: 0, paths: 1 })]);
        for cut in 0..bytes.len() {
            assert!(decode_blocks(&bytes[..cut]).is_err(), "cut at {cut}");
        }
        let mut padded = bytes.clone();
        padded.push(0);
        assert!(decode_blocks(&padded).is_err());
        // A count no message could hold is refused before anything is allocated.
        let mut huge = Writer::default();
        huge.u64(u64::MAX);
        assert!(decode_blocks(&huge.0).is_err());
        assert!(decode_chunks(&huge.0).is_err());
        let e = decode_job(b"\x05").unwrap_err();
        assert_eq!(e.to_string(), "malformed job message at byte 0");
    }
}
