//! The dataset file, continued (`dataset_file.rs` holds round trips, atomic writes and damage):
//! what the chunks say (light indices, path counts, finite weights), throughput, the tiny
//! example, older format versions, and MIS records.

use super::dataset_file::{
    POWER, Rng, expect_err, first_chunk, fix_header_crc, fix_record_crc, header, table, tiny, write,
};
use opticks_core::dataset::{
    Chunk, DatasetHeader, Emitter, Heuristic, LightRecord, LightTable, LightVertexMis, PassMis, Sample,
    TraceInfo, TracePass,
};
use opticks_core::math::{Rgb, Vec3};
use opticks_core::scene::{Fingerprint, ObjectHash, ObjectKind};
use opticks_io::dataset_file::*;
use rayon::prelude::*;
use std::path::Path;
use std::time::Instant;

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
