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
use std::time::Instant;

/// A tiny deterministic generator (SplitMix64), so the test needs no extra dependency.
struct Rng(u64);
impl Rng {
    fn next(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9e37_79b9_7f4a_7c15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
        z ^ (z >> 31)
    }
    fn f(&mut self) -> f32 {
        (self.next() >> 40) as f32 / (1u64 << 24) as f32
    }
    fn sample(&mut self) -> Sample {
        let p = Vec3::new(self.f() * 4.0 - 2.0, self.f() * 3.0, self.f() - 5.0);
        let d = Vec3::new(self.f() - 0.5, self.f() - 0.5, self.f() - 0.5).normalize_or(Vec3::Y);
        if self.next().is_multiple_of(5) {
            Sample::emitted(p, (self.next() % 1000) as u32)
        } else {
            Sample::scattered(p, d, (self.next() % 1000) as u32, Rgb::new(self.f(), self.f() * 2.0, self.f()))
        }
    }
    /// A valid MIS record for `s` (an emission record for an emission sample).
    fn record(&mut self, s: &Sample) -> MisRecord {
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
    fn chunk(&mut self, light: u32, paths: u64, n: usize) -> Chunk {
        let samples: Vec<Sample> = (0..n).map(|_| self.sample()).collect();
        let records = samples.iter().map(|s| self.record(s)).collect();
        Chunk { light, paths, samples, records }
    }
}

/// The MIS header fields of a pass with power-heuristic records of signature 1.
const POWER: Option<PassMis> = Some(PassMis { heuristic: Heuristic::Power, signature: 1 });

fn table(paths: &[u64]) -> LightTable {
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

fn header(paths: &[u64]) -> DatasetHeader {
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

fn write(path: &Path, h: &DatasetHeader, chunks: &[Chunk]) -> DatasetSummary {
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
fn tiny(path: &Path) -> (DatasetHeader, Vec<Chunk>) {
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
fn load(path: &Path) -> Result<(), DatasetError> {
    let r = DatasetReader::open(path)?;
    r.verify()?;
    Ok(())
}

fn u32_at(b: &[u8], at: usize) -> u32 {
    u32::from_le_bytes(b[at..at + 4].try_into().unwrap())
}

fn fix_header_crc(b: &mut [u8]) {
    let len = u32_at(b, 12) as usize;
    let crc = crc32fast::hash(&b[..len - 4]);
    b[len - 4..len].copy_from_slice(&crc.to_le_bytes());
}

fn fix_record_crc(b: &mut [u8], at: usize) {
    let crc = crc32fast::hash(&b[at..at + 28]);
    b[at + 28..at + 32].copy_from_slice(&crc.to_le_bytes());
}

fn first_chunk(b: &[u8]) -> usize {
    u32_at(b, 12) as usize
}

#[track_caller]
fn expect_err(path: &Path, bytes: &[u8], needle: &str) -> DatasetError {
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

#[test]
fn light_index_out_of_range_is_detected() {
    let dir = tempfile::tempdir().unwrap();
    let good = dir.path().join("good.opds");
    tiny(&good);
    let mut b = std::fs::read(&good).unwrap();
    let c0 = first_chunk(&b);
    b[c0 + 4..c0 + 8].copy_from_slice(&7u32.to_le_bytes());
    fix_record_crc(&mut b, c0);
    let e = expect_err(
        &dir.path().join("l.opds"),
        &b,
        &format!("chunk 0 at byte {} names light 7, but the light table has 2 lights", c0 + 4),
    );
    assert!(matches!(e, DatasetError::LightOutOfRange { light: 7, .. }));
}

#[test]
fn path_count_mismatch_is_detected() {
    let dir = tempfile::tempdir().unwrap();
    let good = dir.path().join("good.opds");
    tiny(&good);
    let bytes = std::fs::read(&good).unwrap();
    // N_k of light 1 ("lamp"): after the label, the count, light 0 (4+3+16+12+8), light 1's name,
    // shape and power.
    let at = 100 + 4 + 4 + (4 + 3 + 16 + 12 + 8) + (4 + 4 + 16 + 12);
    assert_eq!(u64::from_le_bytes(bytes[at..at + 8].try_into().unwrap()), 3);
    let mut b = bytes.clone();
    b[at..at + 8].copy_from_slice(&4u64.to_le_bytes());
    fix_header_crc(&mut b);
    let e = expect_err(
        &dir.path().join("n.opds"),
        &b,
        &format!("light 1 (\"lamp\"): the header (N_k at byte {at}) says 4 paths, the chunks sum to 3"),
    );
    assert!(matches!(e, DatasetError::PathCountMismatch { .. }));
    // Changing a chunk's paths instead (with a valid chunk CRC) is caught the same way.
    let mut b = bytes.clone();
    let c0 = first_chunk(&b);
    b[c0 + 8] = 9;
    fix_record_crc(&mut b, c0);
    // (the end record's path total disagrees first).
    expect_err(&dir.path().join("n.opds"), &b, "the file holds 3 chunks, 3 samples, 13 paths");
}

/// Issue 10: lights of 2^63+18 and 2^63+32 paths, with every checksum and count consistent in
/// wrapping arithmetic, made `info` say "paths 50". Sums of path counts are checked.
#[test]
fn path_counts_whose_sum_wraps_are_refused() {
    let dir = tempfile::tempdir().unwrap();
    let good = dir.path().join("good.opds");
    tiny(&good);
    let mut b = std::fs::read(&good).unwrap();
    let n_k0 = 96 + 4 + 4 + (4 + 3 + 16 + 12);
    let n_k1 = n_k0 + 8 + (4 + 4 + 16 + 12);
    let (l0, l1) = ((1u64 << 63) + 18, (1u64 << 63) + 32);
    b[n_k0..n_k0 + 8].copy_from_slice(&l0.to_le_bytes());
    b[n_k1..n_k1 + 8].copy_from_slice(&l1.to_le_bytes());
    fix_header_crc(&mut b);
    // Chunks: light 0 (2 paths), light 1 (3), light 0 (1), each header + its samples.
    let c0 = first_chunk(&b);
    let c1 = c0 + 32 + 2 * 32;
    let c2 = c1 + 32;
    b[c0 + 8..c0 + 16].copy_from_slice(&(l0 - 1).to_le_bytes());
    b[c1 + 8..c1 + 16].copy_from_slice(&l1.to_le_bytes());
    fix_record_crc(&mut b, c0);
    fix_record_crc(&mut b, c1);
    let end = c2 + 32 + 32;
    b[end + 20..end + 28].copy_from_slice(&l0.wrapping_add(l1).to_le_bytes());
    fix_record_crc(&mut b, end);
    assert_eq!(l0.wrapping_add(l1), 50);
    let e = expect_err(&dir.path().join("wrap.opds"), &b, "exceeds the maximum of 9007199254740992");
    assert_eq!(e.offset(), Some(c0 as u64 + 8), "the first chunk already exceeds 2^53");
}

#[test]
fn non_finite_beta_is_detected_even_with_a_valid_checksum() {
    let dir = tempfile::tempdir().unwrap();
    let good = dir.path().join("good.opds");
    tiny(&good);
    let mut b = std::fs::read(&good).unwrap();
    let c0 = first_chunk(&b);
    let s1 = c0 + 32 + 32; // second sample of chunk 0
    b[s1 + 24..s1 + 28].copy_from_slice(&f32::NAN.to_le_bytes()); // β.g
    let crc = crc32fast::hash(&b[c0 + 32..c0 + 32 + 64]);
    b[c0 + 24..c0 + 28].copy_from_slice(&crc.to_le_bytes());
    fix_record_crc(&mut b, c0);
    let path = dir.path().join("nan.opds");
    let e =
        expect_err(&path, &b, &format!("invalid sample 1 of chunk 0 at byte {s1}: non-finite or negative β"));
    assert!(matches!(e, DatasetError::InvalidSample { index: 1, detail: SampleFault::NonFinite { .. }, .. }));
    // The header and index are fine: other chunks still read.
    let r = DatasetReader::open(&path).unwrap();
    assert!(r.chunk(0).is_err());
    assert!(r.chunk(1).is_ok() && r.chunk(2).is_ok());
}

/// Prints write and read throughput; set OPTICKS_DATASET_BENCH_SAMPLES to change the size.
#[test]
fn throughput() {
    let n: usize = std::env::var("OPTICKS_DATASET_BENCH_SAMPLES")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(16_000_000);
    let per_chunk = 1 << 16;
    let mut rng = Rng(9);
    let pool: Vec<Sample> = (0..per_chunk).map(|_| rng.sample()).collect();
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("big.opds");
    let t = Instant::now();
    let mut w = DatasetWriter::create(&path, &header(&[0, 0])).unwrap();
    let mut chunk = Chunk { light: 0, paths: 1000, samples: pool, records: vec![] };
    let mut left = n;
    while left > 0 {
        chunk.samples.truncate(left.min(per_chunk));
        chunk.light ^= 1;
        w.write_chunk(&chunk).unwrap();
        left -= chunk.samples.len();
    }
    let paths = w.light_paths().to_vec();
    let s = w.finish(&table(&paths), &header(&[0]).trace).unwrap();
    let tw = t.elapsed().as_secs_f64();
    let t = Instant::now();
    let r = DatasetReader::open(&path).unwrap();
    let topen = t.elapsed().as_secs_f64();
    let t = Instant::now();
    let beta: f64 = (0..r.chunk_count())
        .into_par_iter()
        .map(|i| r.chunk(i).unwrap().samples.iter().map(|s| s.beta[1] as f64).sum::<f64>())
        .sum();
    let tr = t.elapsed().as_secs_f64();
    assert_eq!(r.total_samples(), n as u64);
    let mb = s.bytes as f64 / 1e6;
    println!(
        "dataset throughput: {n} samples, {mb:.0} MB, {} chunks: write+fsync {:.0} MB/s ({tw:.2} s), \
         open {:.1} ms, read (CRC + checks + sum, {} threads) {:.0} MB/s ({tr:.2} s) [Σβ {beta:.3e}]",
        s.chunks,
        mb / tw,
        topen * 1e3,
        rayon::current_num_threads(),
        mb / tr,
    );
}

/// Writes the tiny file shown in docs/dataset-format.md to $OPTICKS_TINY_DATASET.
#[test]
#[ignore]
fn write_tiny_example() {
    let path = std::env::var("OPTICKS_TINY_DATASET").expect("set OPTICKS_TINY_DATASET");
    let chunks = vec![
        Chunk {
            light: 0,
            paths: 4,
            samples: vec![Sample::emitted(Vec3::new(0.0, 1.98, 0.0), 7)],
            // An emission vertex of a light of area 1/4: vcm = A (its root), the hit class.
            records: vec![
                LightVertexMis::emission_vertex(Emitter::area(4.0, 0.25), Heuristic::Power).record(),
            ],
        },
        Chunk { light: 0, paths: 0, samples: vec![], records: vec![] },
    ];
    let h = DatasetHeader {
        fingerprint: Fingerprint { geometry: [0xaa; 16], lights: [0xbb; 16] },
        objects: vec![ObjectHash { kind: ObjectKind::Material, name: "white".into(), hash: [0x0c; 16] }],
        label: "box.xml".into(),
        trace: TraceInfo {
            passes: vec![TracePass {
                seed: 1,
                stream: 0,
                paths: 4,
                rr_depth: 5,
                seconds: 0.5,
                planned: vec![(0, 4)],
                mis: POWER,
                ..Default::default()
            }],
        },
        table: LightTable {
            lights: vec![LightRecord {
                shape: [7; 16],
                name: "ceiling".into(),
                power: Rgb::new(1.0, 1.0, 1.0),
                paths: 0,
            }],
        },
    };
    let mut w = DatasetWriter::create(Path::new(&path), &h).unwrap();
    for c in &chunks {
        w.write_chunk(c).unwrap();
    }
    w.finish(
        &LightTable {
            lights: vec![LightRecord {
                shape: [7; 16],
                name: "ceiling".into(),
                power: Rgb::new(1.0, 1.0, 1.0),
                paths: 4,
            }],
        },
        &h.trace,
    )
    .unwrap();
}

/// A version-1 file (pass records without strategy and plan) still reads: the default strategy
/// and an unknown plan, i.e. a complete pass.
#[test]
fn version_1_files_are_still_read() {
    let dir = tempfile::tempdir().unwrap();
    let good = dir.path().join("good.opds");
    let (h, chunks) = tiny(&good);
    let v3 = std::fs::read(&good).unwrap();
    let header_len = u32::from_le_bytes(v3[12..16].try_into().unwrap()) as usize;
    // The tiny header's contents end after the label and both lights (see its builder).
    let end = 96 + (4 + 4) + 4 + (4 + 3 + 36) + (4 + 4 + 36);
    // Drop the pass's strategy bytes, signature and plan length (the 12 bytes after its 32
    // version-1 bytes).
    let mut b = [&v3[..84], &v3[96..end]].concat();
    let len = (b.len() + 4).div_ceil(32) * 32;
    b.resize(len - 4, 0);
    b[8..12].copy_from_slice(&1u32.to_le_bytes());
    b[12..16].copy_from_slice(&(len as u32).to_le_bytes());
    b.extend_from_slice(&crc32fast::hash(&b).to_le_bytes());
    // Version-1 chunks have no records: keep the samples only.
    let c0 = header_len;
    let mut c0_header: [u8; 32] = v3[c0..c0 + 32].try_into().unwrap();
    c0_header[20..24].copy_from_slice(&0u32.to_le_bytes());
    fix_record_crc(&mut c0_header, 0);
    b.extend_from_slice(&c0_header);
    b.extend_from_slice(&v3[c0 + 32..c0 + 96]);
    b.extend_from_slice(&v3[c0 + 160..]);
    let old = dir.path().join("v1.opds");
    std::fs::write(&old, &b).unwrap();
    let (read, read_chunks) = read_all(&old).unwrap();
    let mut want = DatasetHeader { table: read.table.clone(), objects: Vec::new(), ..h };
    want.trace.passes[0].mis = None;
    assert_eq!(read, want);
    let mut want = chunks.clone();
    want[0].records.clear();
    assert_eq!(read_chunks, want);
    assert!(read.trace.passes[0].is_complete() && read.trace.passes[0].planned.is_empty());
}

/// The file format encodes the core's dataset and depends on nothing else of it: not on the
/// tracer (ARCHITECTURE.md, "every dataset law and operation is a core function").
#[test]
fn the_file_format_imports_nothing_from_the_tracer() {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("src/dataset_file");
    let mut files = 0;
    for entry in std::fs::read_dir(&dir).unwrap() {
        let path = entry.unwrap().path();
        let text = std::fs::read_to_string(&path).unwrap();
        for import in ["opticks_core::trace", "opticks_core::{"] {
            assert!(!text.contains(import), "{} imports `{import}`", path.display());
        }
        files += 1;
    }
    assert!(files >= 4, "{files} files in {}", dir.display());
}

/// Format 3: chunks with MIS records round trip next to chunks without; `chunk` hands out the
/// same samples either way (the light estimator's bytes), `chunk_records` the records.
#[test]
fn mis_records_round_trip_beside_chunks_without_them() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("mis.opds");
    let mut rng = Rng(3);
    let mut chunks: Vec<Chunk> =
        (0..8u32).map(|i| rng.chunk(i % 2, 7, [0, 1, 2, 17, 4096][i as usize % 5])).collect();
    chunks.push(Chunk { records: vec![], ..rng.chunk(1, 3, 5) });
    let mut h = header(&[0, 0]);
    h.trace.passes[0].mis = Some(PassMis { heuristic: Heuristic::Balance, signature: 7 });
    h.trace.passes.push(TracePass { seed: 1, ..Default::default() });
    let summary = write(&path, &h, &chunks);
    let (h2, c2) = read_all(&path).unwrap();
    assert_eq!((h2.trace, c2), (h.trace.clone(), chunks.clone()));
    let r = DatasetReader::open(&path).unwrap();
    r.verify().unwrap();
    let record_bytes: u64 = chunks
        .iter()
        .filter(|c| !c.records.is_empty())
        .map(|c| (16 * c.records.len() as u64 + 4).div_ceil(32) * 32)
        .sum();
    let sample_bytes: u64 = chunks.iter().map(|c| 32 * c.samples.len() as u64 + 32).sum();
    assert_eq!(
        summary.bytes,
        first_chunk(&std::fs::read(&path).unwrap()) as u64 + sample_bytes + record_bytes + 32
    );
    for (i, c) in chunks.iter().enumerate() {
        let v = r.chunk(i).unwrap();
        assert_eq!(v.samples, &c.samples[..]);
        assert_eq!(r.has_records(i), Some(!c.records.is_empty() || c.samples.is_empty()));
        match r.chunk_records(i) {
            Ok(records) => assert_eq!(records, &c.records[..]),
            Err(e) => {
                assert!(c.records.is_empty() && !c.samples.is_empty(), "{e}");
                assert!(matches!(e, DatasetError::NoRecords { chunk: 8, .. }), "{e}");
                assert!(
                    e.to_string().contains("chunk 8 (header at byte")
                        && e.to_string().contains("no MIS records"),
                    "{e}"
                );
            }
        }
    }
}

/// The writer refuses records that are not one per sample or fail the reader's checks, and the
/// reader catches such records even under a valid checksum.
#[test]
fn invalid_mis_records_are_refused_and_detected() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("bad.opds");
    let mut rng = Rng(4);
    let mut w = DatasetWriter::create(&path, &header(&[0])).unwrap();
    let good = rng.chunk(0, 1, 6);
    let short = Chunk { records: good.records[..5].to_vec(), ..good.clone() };
    assert!(w.write_chunk(&short).unwrap_err().to_string().contains("6 samples but 5 MIS records"));
    let emission = good.samples.iter().position(|s| s.is_emission()).unwrap();
    let scattered = good.samples.iter().position(|s| !s.is_emission()).unwrap();
    let mut swapped = good.clone();
    swapped.records.swap(emission, scattered);
    let e = w.write_chunk(&swapped).unwrap_err().to_string();
    assert!(e.contains("MIS record") && e.contains("emission"), "{e}");
    let mut negative = good.clone();
    let mut v: [f32; 4] = bytemuck::cast(negative.records[scattered]);
    v[2] = -1.0;
    negative.records[scattered] = bytemuck::cast(v);
    assert!(w.write_chunk(&negative).unwrap_err().to_string().contains("negative or NaN MIS quantity"));
    drop(w);

    // On disk: a NaN and a misplaced emission class under valid checksums.
    tiny(&path);
    let bytes = std::fs::read(&path).unwrap();
    let c0 = first_chunk(&bytes);
    let block = c0 + 32 + 64;
    let refresh = |b: &mut Vec<u8>| {
        let crc = crc32fast::hash(&b[block..block + 60]);
        b[block + 60..block + 64].copy_from_slice(&crc.to_le_bytes());
    };
    let mut b = bytes.clone();
    b[block + 16 + 8..block + 16 + 12].copy_from_slice(&f32::NAN.to_le_bytes());
    refresh(&mut b);
    let e = expect_err(&path, &b, &format!("invalid MIS record 1 of chunk 0 at byte {}", block + 16));
    assert!(matches!(e, DatasetError::InvalidRecord { index: 1, detail: RecordFault::Quantity(_), .. }));
    let mut b = bytes.clone();
    b[block + 32] = 1;
    refresh(&mut b);
    expect_err(&path, &b, &format!("corrupt at byte {}: chunk 0: non-zero byte in the padding", block + 32));
    let mut b = bytes.clone();
    b[block + 7] ^= 0x80; // the class bit of record 0's vc_hit
    refresh(&mut b);
    expect_err(&path, &b, "invalid MIS record 0 of chunk 0");
    let mut b = bytes.clone();
    b[block + 3] ^= 1;
    expect_err(&path, &b, &format!("corrupt chunk 0 MIS records at byte {block}: CRC-32 stored"));
    // The samples are still readable: a damaged record block costs only the records.
    std::fs::write(&path, &b).unwrap();
    let r = DatasetReader::open(&path).unwrap();
    assert!(r.chunk(0).is_ok() && r.chunk_records(0).is_err());
}

/// The committed format-2 datasets read as datasets without MIS records.
#[test]
fn format_2_datasets_read_without_records() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../testdata/datasets");
    for name in ["cornell-v2.opds", "rough-v2.opds"] {
        let r = DatasetReader::open(&root.join(name)).unwrap();
        r.verify().unwrap();
        assert!(r.header().trace.passes.iter().all(|p| p.mis.is_none()), "{name}");
        let i = (0..r.chunk_count()).find(|&i| r.chunk_summary(i).unwrap().2 > 0).unwrap();
        assert_eq!(r.has_records(i), Some(false));
        let e = r.chunk_records(i).unwrap_err();
        assert!(matches!(e, DatasetError::NoRecords { .. }), "{e}");
        assert!(r.owned_chunk(i).unwrap().records.is_empty());
    }
}
