//! The dataset file: round trips, atomic writes, and that every kind of damage is an error
//! (never a panic, never a huge allocation) naming the file and the offset.

use opticks_core::dataset::{
    Chunk, DatasetHeader, Emitter, Heuristic, LightRecord, LightTable, LightVertexMis, MisRecord, PassMis,
    Sample, TraceInfo, TracePass,
};
use opticks_core::math::{Rgb, Vec3};
use opticks_core::scene::{Fingerprint, ObjectHash, ObjectKind};
use opticks_io::dataset_file::*;
use rayon::prelude::*;
use std::path::Path;

/// A tiny deterministic generator (SplitMix64), so the test needs no extra dependency.
pub(crate) struct Rng(pub(crate) u64);
impl Rng {
    pub(crate) fn next(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9e37_79b9_7f4a_7c15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
        z ^ (z >> 31)
    }
    pub(crate) fn f(&mut self) -> f32 {
        (self.next() >> 40) as f32 / (1u64 << 24) as f32
    }
    pub(crate) fn sample(&mut self) -> Sample {
        let p = Vec3::new(self.f() * 4.0 - 2.0, self.f() * 3.0, self.f() - 5.0);
        let d = Vec3::new(self.f() - 0.5, self.f() - 0.5, self.f() - 0.5).normalize_or(Vec3::Y);
        if self.next().is_multiple_of(5) {
            Sample::emitted(p, (self.next() % 1000) as u32)
        } else {
            Sample::scattered(p, d, (self.next() % 1000) as u32, Rgb::new(self.f(), self.f() * 2.0, self.f()))
        }
    }
    /// A valid MIS record for `s` (an emission record for an emission sample).
    pub(crate) fn record(&mut self, s: &Sample) -> MisRecord {
        let emitter = Emitter::area(0.1 + self.f(), 0.1 + self.f());
        if s.is_emission() {
            return LightVertexMis::emission_vertex(emitter, Heuristic::Power).record();
        }
        let at = LightVertexMis::at_emission(emitter, self.f(), Heuristic::Power);
        let mut m = at.after_hit(0.5 + self.f(), 0.1 + self.f());
        for _ in 0..self.next() % 3 {
            m = m.after_scatter(self.f(), 0.1 + self.f(), self.f(), false).after_hit(1.0 + self.f(), 0.2);
        }
        m.record()
    }
    /// `n` samples and their records.
    pub(crate) fn chunk(&mut self, light: u32, paths: u64, n: usize) -> Chunk {
        let samples: Vec<Sample> = (0..n).map(|_| self.sample()).collect();
        let records = samples.iter().map(|s| self.record(s)).collect();
        Chunk { light, paths, samples, records }
    }
}

/// The MIS header fields of a pass with power-heuristic records of signature 1.
pub(crate) const POWER: Option<PassMis> = Some(PassMis { heuristic: Heuristic::Power, signature: 1 });

pub(crate) fn table(paths: &[u64]) -> LightTable {
    LightTable {
        lights: paths
            .iter()
            .enumerate()
            .map(|(k, &p)| LightRecord {
                name: format!("light-{k}"),
                shape: [k as u8; 16],
                power: Rgb::new(10.0 + k as f32, 5.0, 1.5),
                paths: p,
            })
            .collect(),
    }
}

pub(crate) fn header(paths: &[u64]) -> DatasetHeader {
    DatasetHeader {
        fingerprint: Fingerprint { geometry: [0xa5; 16], lights: std::array::from_fn(|i| i as u8) },
        objects: vec![
            ObjectHash { kind: ObjectKind::Mesh, name: "flöor".into(), hash: [3; 16] },
            ObjectHash { kind: ObjectKind::Mesh, name: String::new(), hash: [4; 16] },
            ObjectHash {
                kind: ObjectKind::Material,
                name: "white".into(),
                hash: std::array::from_fn(|i| i as u8),
            },
        ],
        label: "scenes/cornell/scene.xml — ünïcode".into(),
        trace: TraceInfo {
            passes: vec![TracePass {
                seed: 0x0123_4567_89ab_cdef,
                stream: 0,
                paths: 0,
                rr_depth: 5,
                seconds: 0.0,
                ..Default::default()
            }],
        },
        table: table(paths),
    }
}

pub(crate) fn write(path: &Path, h: &DatasetHeader, chunks: &[Chunk]) -> DatasetSummary {
    let mut w = DatasetWriter::create(path, h).unwrap();
    for c in chunks {
        w.write_chunk(c).unwrap();
    }
    let mut t = h.table.clone();
    for (k, l) in t.lights.iter_mut().enumerate() {
        l.paths = chunks.iter().filter(|c| c.light as usize == k).map(|c| c.paths).sum();
    }
    w.finish(&t, &h.trace).unwrap()
}

/// Small file used by the damage tests: two lights, three chunks (one empty with paths > 0),
/// the first with MIS records, the last without.
pub(crate) fn tiny(path: &Path) -> (DatasetHeader, Vec<Chunk>) {
    let mut rng = Rng(7);
    let chunks = vec![
        rng.chunk(0, 2, 2),
        Chunk { light: 1, paths: 3, samples: vec![], records: vec![] },
        Chunk { light: 0, paths: 1, samples: vec![rng.sample()], records: vec![] },
    ];
    let h = DatasetHeader {
        fingerprint: Fingerprint { geometry: [0x11; 16], lights: [0x22; 16] },
        objects: vec![ObjectHash { kind: ObjectKind::Material, name: "m".into(), hash: [5; 16] }],
        label: "tiny".into(),
        trace: TraceInfo {
            passes: vec![TracePass {
                seed: 42,
                stream: 0,
                paths: 0,
                rr_depth: 3,
                mis: POWER,
                ..Default::default()
            }],
        },
        table: LightTable {
            lights: vec![
                LightRecord { shape: [7; 16], name: "sun".into(), power: Rgb::new(1.0, 2.0, 3.0), paths: 3 },
                LightRecord { shape: [7; 16], name: "lamp".into(), power: Rgb::splat(0.5), paths: 3 },
            ],
        },
    };
    write(path, &h, &chunks);
    (h, chunks)
}

/// Opens and reads every chunk: the full check a renderer would make.
pub(crate) fn load(path: &Path) -> Result<(), DatasetError> {
    let r = DatasetReader::open(path)?;
    r.verify()?;
    Ok(())
}

pub(crate) fn u32_at(b: &[u8], at: usize) -> u32 {
    u32::from_le_bytes(b[at..at + 4].try_into().unwrap())
}

pub(crate) fn fix_header_crc(b: &mut [u8]) {
    let len = u32_at(b, 12) as usize;
    let crc = crc32fast::hash(&b[..len - 4]);
    b[len - 4..len].copy_from_slice(&crc.to_le_bytes());
}

pub(crate) fn fix_record_crc(b: &mut [u8], at: usize) {
    let crc = crc32fast::hash(&b[at..at + 28]);
    b[at + 28..at + 32].copy_from_slice(&crc.to_le_bytes());
}

pub(crate) fn first_chunk(b: &[u8]) -> usize {
    u32_at(b, 12) as usize
}

#[track_caller]
pub(crate) fn expect_err(path: &Path, bytes: &[u8], needle: &str) -> DatasetError {
    std::fs::write(path, bytes).unwrap();
    let e = load(path).expect_err("damaged file accepted");
    let msg = e.to_string();
    assert!(msg.contains(&path.display().to_string()), "message does not name the file: {msg}");
    assert!(msg.contains(needle), "expected {needle:?} in: {msg}");
    e
}

#[test]
fn round_trip_several_lights_and_chunks() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("scene.opds");
    let mut rng = Rng(1);
    let mut chunks = Vec::new();
    for i in 0..9u32 {
        let n = [0, 1, 17, 1000, 4096][i as usize % 5];
        chunks.push(Chunk {
            light: i % 3,
            paths: 100 + i as u64,
            samples: (0..n).map(|_| rng.sample()).collect(),
            records: vec![],
        });
    }
    // An empty chunk whose paths still count (every path was absorbed or hit a delta surface).
    chunks.push(Chunk { light: 2, paths: 50, samples: vec![], records: vec![] });
    let h = header(&[0, 0, 0]);
    let summary = write(&path, &h, &chunks);
    let total: u64 = chunks.iter().map(|c| c.samples.len() as u64).sum();
    assert_eq!(summary.chunks, 10);
    assert_eq!(summary.samples, total);
    assert_eq!(summary.paths, chunks.iter().map(|c| c.paths).sum::<u64>());
    assert_eq!(summary.bytes, std::fs::metadata(&path).unwrap().len());

    let (h2, c2) = read_all(&path).unwrap();
    assert_eq!(c2, chunks);
    assert_eq!(h2.fingerprint, h.fingerprint);
    assert_eq!(h2.label, h.label);
    assert_eq!(h2.trace, h.trace);
    let want: Vec<u64> =
        (0..3).map(|k| chunks.iter().filter(|c| c.light == k).map(|c| c.paths).sum()).collect();
    assert_eq!(h2.table.lights.iter().map(|l| l.paths).collect::<Vec<_>>(), want);
    assert_eq!(h2.table.lights[1].name, "light-1");
    assert_eq!(h2.table.lights[1].power, Rgb::new(11.0, 5.0, 1.5));

    let r = DatasetReader::open(&path).unwrap();
    assert_eq!(r.chunk_count(), 10);
    assert_eq!(r.total_samples(), total);
    assert_eq!(r.file_len(), summary.bytes);
    assert_eq!(r.header(), &h2);
    assert!(matches!(r.chunk(10), Err(DatasetError::NoSuchChunk { index: 10, count: 10, .. })));
}

#[test]
fn empty_dataset_round_trips() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("empty.opds");
    let h = DatasetHeader::default();
    let s = DatasetWriter::create(&path, &h).unwrap().finish(&LightTable::default(), &h.trace).unwrap();
    assert_eq!((s.chunks, s.samples, s.paths), (0, 0, 0));
    let (h2, c) = read_all(&path).unwrap();
    assert_eq!(h2, h);
    assert!(c.is_empty());
}

#[test]
fn chunks_are_aligned_and_readable_from_many_threads() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("par.opds");
    let mut rng = Rng(2);
    let chunks: Vec<Chunk> = (0..64u32)
        .map(|i| Chunk {
            light: i % 2,
            paths: 10,
            samples: (0..(i * 37) % 301).map(|_| rng.sample()).collect(),
            records: vec![],
        })
        .collect();
    write(&path, &header(&[0, 0]), &chunks);
    let r = DatasetReader::open(&path).unwrap();
    fn is_sync<T: Sync + Send>(_: &T) {}
    is_sync(&r);
    let sums: Vec<f64> = (0..r.chunk_count())
        .into_par_iter()
        .map(|i| {
            let v = r.chunk(i).unwrap();
            v.samples.iter().map(|s| s.beta[0] as f64).sum()
        })
        .collect();
    for (c, s) in chunks.iter().zip(sums) {
        assert_eq!(s, c.samples.iter().map(|s| s.beta[0] as f64).sum::<f64>());
    }
}

/// Issue 10, item 13: truncating a dataset while it was read killed the process with SIGBUS
/// (the reader touched a memory map whose pages had vanished). Chunks are now read with explicit
/// reads: the chunks past the cut are an error naming the file and the offset, those before it
/// still read, and a chunk rewritten in place fails its checksum.
#[test]
fn a_file_truncated_or_rewritten_while_open_is_an_error_not_a_signal() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("cut.opds");
    let mut rng = Rng(5);
    let chunks: Vec<Chunk> = (0..8u32)
        .map(|_| Chunk {
            light: 0,
            paths: 4,
            samples: (0..500).map(|_| rng.sample()).collect(),
            records: Vec::new(),
        })
        .collect();
    write(&path, &header(&[0]), &chunks);
    let r = DatasetReader::open(&path).unwrap();
    let len = std::fs::metadata(&path).unwrap().len();
    let cut = len / 2;
    std::fs::OpenOptions::new().write(true).open(&path).unwrap().set_len(cut).unwrap();
    assert_eq!(r.chunk(0).unwrap().samples, chunks[0].samples, "data before the cut still reads");
    let e = r.chunk(7).unwrap_err();
    let msg = e.to_string();
    assert!(matches!(e, DatasetError::Truncated { .. }), "{msg}");
    assert!(msg.contains(&path.display().to_string()) && msg.contains("truncated or rewrote"), "{msg}");
    assert!(e.offset().is_some_and(|o| o > cut), "{msg}");
    assert!(r.verify().is_err());
    // Rewritten in place (same length, other bytes): the payload checksum catches it.
    std::fs::OpenOptions::new().write(true).open(&path).unwrap().set_len(len).unwrap();
    let e = r.chunk(7).unwrap_err();
    assert!(matches!(e, DatasetError::Checksum { .. }), "{e}");
}

/// Issue 10, item 15: a sample naming a triangle the scene does not have panicked `render`
/// (an index out of bounds), with valid checksums. Once the reader knows the scene's triangle
/// count, such a sample is an error naming the file and the sample's byte offset.
#[test]
fn a_sample_naming_a_missing_triangle_is_an_error_once_the_scene_is_known() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("prim.opds");
    let mut rng = Rng(6);
    let mut samples: Vec<Sample> = (0..10).map(|_| rng.sample()).collect();
    samples.iter_mut().for_each(|s| s.prim = 35 | (s.prim & opticks_core::dataset::EMISSION_FLAG));
    samples[3].prim = 2_147_483_647;
    write(&path, &header(&[0]), &[Chunk { light: 0, paths: 1, samples, records: Vec::new() }]);
    let mut r = DatasetReader::open(&path).unwrap();
    r.verify().unwrap();
    r.check_triangles(36);
    let e = r.verify().unwrap_err();
    let msg = e.to_string();
    assert!(msg.contains("triangle 2147483647 does not exist: the scene has 36 triangles"), "{msg}");
    let first = u32_at(&std::fs::read(&path).unwrap(), 12) as u64;
    assert_eq!(e.offset(), Some(first + 32 + 3 * 32), "{msg}");
    r.check_triangles(1 << 31);
    r.verify().unwrap();
}

fn dir_names(dir: &Path) -> Vec<String> {
    let mut v: Vec<String> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    v.sort();
    v
}

#[test]
fn dropped_writer_leaves_the_old_file_and_no_temporary() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("keep.opds");
    tiny(&path);
    let before = std::fs::read(&path).unwrap();
    {
        let mut w = DatasetWriter::create(&path, &header(&[0])).unwrap();
        let mut rng = Rng(3);
        w.write_chunk(&Chunk {
            light: 0,
            paths: 5,
            samples: (0..100_000).map(|_| rng.sample()).collect(),
            records: vec![],
        })
        .unwrap();
        assert_eq!(dir_names(dir.path()).len(), 2, "temporary file next to the target");
        // Dropped here: an error or Ctrl-C handled by unwinding.
    }
    assert_eq!(std::fs::read(&path).unwrap(), before);
    assert_eq!(dir_names(dir.path()), vec!["keep.opds".to_string()]);
    load(&path).unwrap();
}

#[test]
fn failed_finish_leaves_the_old_file_and_no_temporary() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("keep.opds");
    tiny(&path);
    let before = std::fs::read(&path).unwrap();
    let mut w = DatasetWriter::create(&path, &header(&[0, 0])).unwrap();
    w.write_chunk(&Chunk { light: 1, paths: 5, samples: vec![], records: vec![] }).unwrap();
    assert_eq!(w.light_paths(), &[0, 5]);
    // N_k that does not match the chunks written: refused.
    let e = w.finish(&table(&[0, 4]), &header(&[0]).trace).unwrap_err();
    assert!(e.to_string().contains("N_k = 4 paths but the chunks written hold 5"), "{e}");
    assert_eq!(std::fs::read(&path).unwrap(), before);
    assert_eq!(dir_names(dir.path()), vec!["keep.opds".to_string()]);
}

#[test]
fn writer_refuses_invalid_chunks_and_tables() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("bad.opds");
    let mut w = DatasetWriter::create(&path, &header(&[0, 0])).unwrap();
    let e = w.write_chunk(&Chunk { light: 2, paths: 1, samples: vec![], records: vec![] }).unwrap_err();
    assert!(e.to_string().contains("chunk for light 2, but the table has 2 lights"), "{e}");
    let mut s = Rng(4).sample();
    for bad in [f32::NAN, f32::INFINITY, -1.0] {
        s.beta[1] = bad;
        let e = w
            .write_chunk(&Chunk { light: 0, paths: 1, samples: vec![Sample::default(), s], records: vec![] })
            .unwrap_err();
        assert!(e.to_string().contains("sample 1 of a chunk of light 0"), "{e}");
    }
    // The refused chunks wrote nothing: the writer is still usable.
    w.write_chunk(&Chunk { light: 0, paths: 1, samples: vec![Sample::default()], records: vec![] }).unwrap();
    let mut renamed = table(&[1, 0]);
    renamed.lights[1].name = "other".into();
    assert!(
        w.finish(&renamed, &header(&[0]).trace).unwrap_err().to_string().contains("does not list the lights")
    );
    assert_eq!(dir_names(dir.path()), Vec::<String>::new());

    let mut h = header(&[0]);
    h.table.lights[0].power = Rgb::new(1.0, f32::NAN, 1.0);
    assert!(DatasetWriter::create(&path, &h).unwrap_err().to_string().contains("invalid power"));
}

#[test]
fn truncation_at_every_byte_is_an_error() {
    let dir = tempfile::tempdir().unwrap();
    let good = dir.path().join("good.opds");
    tiny(&good);
    let bytes = std::fs::read(&good).unwrap();
    let path = dir.path().join("cut.opds");
    for len in 0..bytes.len() {
        std::fs::write(&path, &bytes[..len]).unwrap();
        let e = load(&path).expect_err(&format!("file cut to {len} bytes accepted"));
        let msg = e.to_string();
        assert!(msg.contains("cut.opds"), "{msg}");
        if len == 0 {
            assert!(matches!(e, DatasetError::NotADataset { .. }), "{msg}");
        } else {
            assert!(matches!(e, DatasetError::Truncated { .. }), "cut to {len}: {msg}");
            assert!(e.offset().unwrap() <= len as u64, "cut to {len}: {msg}");
        }
    }
    load(&good).unwrap();
}

#[test]
fn flipping_any_byte_is_an_error() {
    let dir = tempfile::tempdir().unwrap();
    let good = dir.path().join("good.opds");
    tiny(&good);
    let bytes = std::fs::read(&good).unwrap();
    let path = dir.path().join("flip.opds");
    for at in 0..bytes.len() {
        for mask in [0x01u8, 0x80, 0xff] {
            let mut b = bytes.clone();
            b[at] ^= mask;
            std::fs::write(&path, &b).unwrap();
            let e = load(&path).expect_err(&format!("byte {at} ^ {mask:#x} accepted"));
            assert!(e.to_string().contains("flip.opds"), "{e}");
            assert!(e.offset().is_some(), "{e}");
        }
    }
}

#[test]
fn damage_messages_name_the_place() {
    let dir = tempfile::tempdir().unwrap();
    let good = dir.path().join("good.opds");
    tiny(&good);
    let bytes = std::fs::read(&good).unwrap();
    let path = dir.path().join("d.opds");
    let c0 = first_chunk(&bytes);
    let mut b = bytes.clone();
    b[20] ^= 1;
    expect_err(&path, &b, "corrupt header at byte 0: CRC-32 stored");
    let mut b = bytes.clone();
    b[c0 + 9] ^= 1;
    expect_err(&path, &b, &format!("corrupt chunk 0 header at byte {c0}"));
    let mut b = bytes.clone();
    b[c0 + 40] ^= 1;
    expect_err(&path, &b, &format!("corrupt chunk 0 payload at byte {}", c0 + 32));
    let n = bytes.len();
    let mut b = bytes.clone();
    b[n - 10] ^= 1;
    expect_err(&path, &b, &format!("corrupt end record at byte {}", n - 32));
    expect_err(&path, &bytes[..n - 32], &format!("truncated at byte {}", n - 32));
    let mut b = bytes.clone();
    b.extend_from_slice(&[0; 32]);
    expect_err(&path, &b, &format!("corrupt at byte {n}: 32 unexpected bytes after the end record"));
}

#[test]
fn foreign_files_are_refused() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("foreign.opds");
    for bytes in [
        &b""[..],
        b"\x89PNG\r\n\x1a\n\0\0\0\rIHDR",
        b"#VRML V2.0 utf8\nShape {}\n",
        b"OPTICKS",
        // The signature after a text-mode transfer turned CR LF into LF.
        b"\x89OPK\n\x1a\n\x01\0\0\0",
    ] {
        let e = expect_err(&path, bytes, "not an Opticks dataset");
        assert!(matches!(e, DatasetError::NotADataset { .. }));
    }
    let e = expect_err(&path, b"\x89PNG\r\n\x1a\n", "found 89 50 4e 47 0d 0a 1a 0a");
    assert_eq!(e.offset(), Some(0));
    // A directory is an IO error, not a panic.
    assert!(matches!(DatasetReader::open(dir.path()), Err(DatasetError::Io { .. })));
    assert!(matches!(DatasetReader::open(&dir.path().join("missing")), Err(DatasetError::Io { .. })));
}

#[test]
fn newer_version_is_refused() {
    let dir = tempfile::tempdir().unwrap();
    let good = dir.path().join("good.opds");
    tiny(&good);
    let mut b = std::fs::read(&good).unwrap();
    b[8..12].copy_from_slice(&(FORMAT_VERSION + 1).to_le_bytes());
    fix_header_crc(&mut b);
    let path = dir.path().join("new.opds");
    let e = expect_err(
        &path,
        &b,
        &format!(
            "written by a newer Opticks: format version {}, this build reads {FORMAT_VERSION}",
            FORMAT_VERSION + 1
        ),
    );
    assert!(matches!(e, DatasetError::NewerVersion { .. }));
    b[8..12].copy_from_slice(&0u32.to_le_bytes());
    fix_header_crc(&mut b);
    expect_err(&path, &b, "corrupt at byte 8: format version 0 does not exist");
}

#[test]
fn huge_length_fields_are_errors_not_allocations() {
    let dir = tempfile::tempdir().unwrap();
    let good = dir.path().join("good.opds");
    tiny(&good);
    let bytes = std::fs::read(&good).unwrap();
    let path = dir.path().join("huge.opds");
    let label_len_at = 96; // 48 fixed bytes, the pass count, one 44-byte pass (with an empty plan)
    let light_count_at = 100 + "tiny".len();
    let c0 = first_chunk(&bytes);

    // Header length beyond the file, and not a multiple of 32.
    for (v, needle) in [(u32::MAX - 31, "the header is"), (u32::MAX, "impossible header length")] {
        let mut b = bytes.clone();
        b[12..16].copy_from_slice(&v.to_le_bytes());
        expect_err(&path, &b, needle);
    }
    // Label and light count: checksummed correctly, so only the bounds checks stand in the way.
    let mut b = bytes.clone();
    b[label_len_at..label_len_at + 4].copy_from_slice(&u32::MAX.to_le_bytes());
    fix_header_crc(&mut b);
    expect_err(&path, &b, "scene label (4294967295 bytes) runs past the end");
    let mut b = bytes.clone();
    b[light_count_at..light_count_at + 4].copy_from_slice(&u32::MAX.to_le_bytes());
    fix_header_crc(&mut b);
    expect_err(&path, &b, &format!("corrupt at byte {light_count_at}: light count 4294967295 cannot fit"));
    let mut b = bytes.clone();
    let name_len_at = light_count_at + 4;
    b[name_len_at..name_len_at + 4].copy_from_slice(&0x7fff_ffffu32.to_le_bytes());
    fix_header_crc(&mut b);
    expect_err(&path, &b, "name of light 0 (2147483647 bytes) runs past the end");
    // The object table (format 4): its count, a record's kind.
    let mut record = vec![1u8, 1, 0, 0, 0, b'm'];
    record.extend([5u8; 16]);
    let kind_at = bytes.windows(record.len()).position(|w| w == record).expect("tiny's object record");
    let object_count_at = kind_at - 4;
    let mut b = bytes.clone();
    b[object_count_at..kind_at].copy_from_slice(&u32::MAX.to_le_bytes());
    fix_header_crc(&mut b);
    expect_err(&path, &b, &format!("corrupt at byte {object_count_at}: object count 4294967295 cannot fit"));
    let mut b = bytes.clone();
    b[kind_at] = 7;
    fix_header_crc(&mut b);
    expect_err(&path, &b, &format!("corrupt at byte {kind_at}: object 0: unknown kind code 7"));
    // Sample counts that exceed the file (a u32 since format 3), with and without records.
    for (count, records) in [(u32::MAX, 1u32), (u32::MAX, 0), (1 << 27, 1), (1 << 27, 0)] {
        let mut b = bytes.clone();
        b[c0 + 16..c0 + 20].copy_from_slice(&count.to_le_bytes());
        b[c0 + 20..c0 + 24].copy_from_slice(&records.to_le_bytes());
        fix_record_crc(&mut b, c0);
        let with = if records == 1 { " and their MIS records" } else { "" };
        let e = expect_err(&path, &b, &format!("chunk 0 declares {count} samples{with}"));
        assert_eq!(e.offset(), Some(c0 as u64 + 32));
    }
    // Unknown flags.
    let mut b = bytes.clone();
    b[c0 + 20..c0 + 24].copy_from_slice(&3u32.to_le_bytes());
    fix_record_crc(&mut b, c0);
    let e = expect_err(&path, &b, &format!("corrupt at byte {}: chunk 0: unknown chunk flags 0x3", c0 + 20));
    assert_eq!(e.offset(), Some(c0 as u64 + 20));
}
