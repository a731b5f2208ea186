//! Reading a dataset: memory-mapped, validated up front, payloads checked on access.

use super::format::{ChunkHeader, ChunkHeaderError, Trailer, decode_header, record_block_len};
use super::format::{validate_records, validate_samples};
use super::{CHUNK_HEADER_LEN, CHUNK_MAGIC, DatasetError, END_MAGIC, TRAILER_LEN};
use memmap2::Mmap;
use opticks_core::dataset::{Chunk, DatasetHeader, Sample};
use opticks_core::sensor::bidirectional::MisRecord;
use rayon::prelude::*;
use std::fs::File;
use std::path::{Path, PathBuf};

/// One chunk of a mapped dataset: `paths` light paths of light `light` produced `samples`,
/// borrowed straight from the mapped file (no copy).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ChunkView<'a> {
    /// Index of the light in the header's table.
    pub light: u32,
    /// Light paths this chunk accounts for.
    pub paths: u64,
    /// The stored samples.
    pub samples: &'a [Sample],
}

impl ChunkView<'_> {
    /// An owned copy of the samples, without MIS records ([`DatasetReader::owned_chunk`] copies
    /// them too).
    pub fn to_chunk(&self) -> Chunk {
        Chunk { light: self.light, paths: self.paths, samples: self.samples.to_vec(), records: Vec::new() }
    }
}

#[derive(Clone, Copy, Debug)]
struct Entry {
    /// Offset of the chunk header.
    offset: usize,
    light: u32,
    paths: u64,
    count: usize,
    crc: u32,
    /// Whether a record block follows the samples.
    records: bool,
}

impl Entry {
    /// Offset of the samples.
    fn samples_at(&self) -> usize {
        self.offset + CHUNK_HEADER_LEN
    }

    /// Offset of the record block.
    fn records_at(&self) -> usize {
        self.samples_at() + self.count * size_of::<Sample>()
    }
}

/// A validated, memory-mapped dataset file.
///
/// [`open`](Self::open) checks the header (magic, version, CRC, light table), every chunk header
/// (magic, CRC, light index, length) and the end record, and that each light's N_k equals the sum
/// of its chunks' paths. It does not read the payloads: [`chunk`](Self::chunk) verifies a chunk's
/// payload CRC and samples each time it is called (from any number of threads: the reader is
/// `Sync`), [`chunk_records`](Self::chunk_records) its MIS records (format 3), and
/// [`verify`](Self::verify) checks them all. `chunk` reads only the samples, so the light
/// estimator reads the same bytes from a format-3 file as from a format-2 one.
#[derive(Debug)]
pub struct DatasetReader {
    path: PathBuf,
    map: Option<Mmap>,
    header: DatasetHeader,
    index: Vec<Entry>,
    total_samples: u64,
}

impl DatasetReader {
    /// Opens and validates `path` (see the type's documentation).
    ///
    /// The file is memory-mapped: it must not be modified or truncated by another process while
    /// the reader lives (files written by [`DatasetWriter`](super::DatasetWriter) never are:
    /// they are replaced by rename, which leaves a mapped file intact).
    pub fn open(path: &Path) -> Result<Self, DatasetError> {
        let io = |op| move |source| DatasetError::Io { path: path.to_owned(), op, source };
        if cfg!(target_endian = "big") {
            return Err(DatasetError::InvalidInput {
                path: path.to_owned(),
                detail: "dataset files are little endian; big-endian hosts are not supported".into(),
            });
        }
        let file = File::open(path).map_err(io("open"))?;
        let len = file.metadata().map_err(io("read the size of"))?.len();
        let map = if len == 0 { None } else { Some(map_file(&file).map_err(io("memory-map"))?) };
        let bytes: &[u8] = map.as_deref().unwrap_or(&[]);
        let (header, index, total_samples) = scan(path, bytes)?;
        Ok(DatasetReader { path: path.to_owned(), map, header, index, total_samples })
    }

    /// The file's path.
    pub fn path(&self) -> &Path {
        &self.path
    }

    /// The header: fingerprint, label, trace settings and the light table.
    pub fn header(&self) -> &DatasetHeader {
        &self.header
    }

    /// Number of chunks.
    pub fn chunk_count(&self) -> usize {
        self.index.len()
    }

    /// Total number of stored samples.
    pub fn total_samples(&self) -> u64 {
        self.total_samples
    }

    /// File size in bytes.
    pub fn file_len(&self) -> u64 {
        self.bytes().len() as u64
    }

    /// Chunk `i`, borrowed from the mapped file after checking its payload CRC and that every
    /// sample has a finite position and a finite β ≥ 0.
    pub fn chunk(&self, i: usize) -> Result<ChunkView<'_>, DatasetError> {
        self.chunk_checked(i)
    }

    /// Light index, path count and sample count of chunk `i`, from the index built by
    /// [`open`](Self::open) (no payload is read).
    pub fn chunk_summary(&self, i: usize) -> Option<(u32, u64, usize)> {
        self.index.get(i).map(|e| (e.light, e.paths, e.count))
    }

    /// Whether chunk `i`'s samples carry MIS records (format 3; true for a chunk without
    /// samples, whose records are empty), from the index (no payload is read).
    pub fn has_records(&self, i: usize) -> Option<bool> {
        self.index.get(i).map(|e| e.records || e.count == 0)
    }

    /// The MIS records of chunk `i`'s samples (`records[j]` belongs to `chunk(i).samples[j]`),
    /// borrowed from the mapped file after checking the record block's CRC, its zero padding,
    /// that every record is possible ([`MisRecord::is_valid`]) and that the emitter-hit class
    /// marks exactly the emission samples. An error for a chunk with samples but no records
    /// ([`has_records`](Self::has_records)). The samples' own CRC is [`chunk`](Self::chunk)'s.
    pub fn chunk_records(&self, i: usize) -> Result<&[MisRecord], DatasetError> {
        let e = self.entry(i)?;
        if e.count == 0 {
            return Ok(&[]);
        }
        if !e.records {
            return Err(DatasetError::NoRecords {
                path: self.path.clone(),
                offset: e.offset as u64,
                chunk: i as u64,
            });
        }
        let start = e.records_at();
        let len = record_block_len(e.count as u64).expect("checked by open") as usize;
        let block = &self.bytes()[start..start + len];
        let stored = u32::from_le_bytes(block[len - 4..].try_into().unwrap());
        let computed = crc32fast::hash(&block[..len - 4]);
        if stored != computed {
            return Err(DatasetError::Checksum {
                path: self.path.clone(),
                offset: start as u64,
                what: format!("chunk {i} MIS records"),
                stored,
                computed,
            });
        }
        let records_len = e.count * size_of::<MisRecord>();
        if let Some(k) = block[records_len..len - 4].iter().position(|&x| x != 0) {
            return Err(DatasetError::Corrupt {
                path: self.path.clone(),
                offset: (start + records_len + k) as u64,
                detail: format!("chunk {i}: non-zero byte in the padding of the MIS records"),
            });
        }
        let records: &[MisRecord] = self.view(start, e.count, "MIS records")?;
        let samples: &[Sample] = self.view(e.samples_at(), e.count, "samples")?;
        if let Err((k, detail)) = validate_records(samples, records) {
            return Err(DatasetError::InvalidRecord {
                path: self.path.clone(),
                offset: (start + k * size_of::<MisRecord>()) as u64,
                chunk: i as u64,
                index: k,
                detail,
            });
        }
        Ok(records)
    }

    /// Chunk `i` as an owned [`Chunk`]: its samples and, if it has them, its MIS records (both
    /// checked as [`chunk`](Self::chunk) and [`chunk_records`](Self::chunk_records) check them).
    /// What copying a chunk into another dataset needs.
    pub fn owned_chunk(&self, i: usize) -> Result<Chunk, DatasetError> {
        let mut c = self.chunk(i)?.to_chunk();
        if self.index[i].records {
            c.records = self.chunk_records(i)?.to_vec();
        }
        Ok(c)
    }

    /// `count` records of type `T` at byte `at` of the mapped file, without a copy. Cannot fail
    /// for the payloads `open` indexed: the map is page aligned, payloads and record blocks sit
    /// at multiples of 32 bytes and inside the file.
    fn view<T: bytemuck::Pod>(&self, at: usize, count: usize, what: &str) -> Result<&[T], DatasetError> {
        bytemuck::try_cast_slice(&self.bytes()[at..at + count * size_of::<T>()]).map_err(|err| {
            DatasetError::Corrupt {
                path: self.path.clone(),
                offset: at as u64,
                detail: format!("payload cannot be viewed as {what}: {err}"),
            }
        })
    }

    fn entry(&self, i: usize) -> Result<Entry, DatasetError> {
        self.index.get(i).copied().ok_or_else(|| DatasetError::NoSuchChunk {
            path: self.path.clone(),
            index: i,
            count: self.index.len(),
        })
    }

    fn chunk_checked(&self, i: usize) -> Result<ChunkView<'_>, DatasetError> {
        let e = self.entry(i)?;
        let start = e.samples_at();
        let payload = &self.bytes()[start..start + e.count * size_of::<Sample>()];
        let computed = crc32fast::hash(payload);
        if computed != e.crc {
            return Err(DatasetError::Checksum {
                path: self.path.clone(),
                offset: start as u64,
                what: format!("chunk {i} payload"),
                stored: e.crc,
                computed,
            });
        }
        let samples: &[Sample] = self.view(start, e.count, "samples")?;
        if let Err((k, detail)) = validate_samples(samples) {
            return Err(DatasetError::InvalidSample {
                path: self.path.clone(),
                offset: (start + k * size_of::<Sample>()) as u64,
                chunk: i as u64,
                index: k,
                detail,
            });
        }
        Ok(ChunkView { light: e.light, paths: e.paths, samples })
    }

    /// Checks every chunk's payload and MIS records (in parallel); the error of the
    /// lowest-numbered bad chunk.
    pub fn verify(&self) -> Result<(), DatasetError> {
        match (0..self.index.len())
            .into_par_iter()
            .map(|i| {
                self.chunk(i)?;
                if self.index[i].records {
                    self.chunk_records(i)?;
                }
                Ok(())
            })
            .find_first(|r| r.is_err())
        {
            Some(r) => r,
            None => Ok(()),
        }
    }

    fn bytes(&self) -> &[u8] {
        self.map.as_deref().unwrap_or(&[])
    }
}

/// Reads a whole dataset into memory, verifying every chunk ([`DatasetReader::owned_chunk`]:
/// samples and MIS records).
pub fn read_all(path: &Path) -> Result<(DatasetHeader, Vec<Chunk>), DatasetError> {
    let r = DatasetReader::open(path)?;
    let chunks =
        (0..r.chunk_count()).into_par_iter().map(|i| r.owned_chunk(i)).collect::<Result<Vec<_>, _>>()?;
    Ok((r.header.clone(), chunks))
}

/// Maps `file` read-only. This is the only `unsafe` in the dataset code: mapping is unsafe
/// because another process could modify or truncate the file while it is mapped, changing bytes
/// behind our `&[u8]` (or raising SIGBUS on access past a truncation).
#[allow(unsafe_code)]
fn map_file(file: &File) -> std::io::Result<Mmap> {
    // SAFETY: the map is read-only and private to the reader, which never writes through it.
    // Opticks itself never modifies a finished dataset in place (writers create a new file and
    // rename it over the old one, which leaves existing maps of the old inode valid). Concurrent
    // modification by other programs is excluded by the documented contract of `open`.
    unsafe { Mmap::map(file) }
}

/// Validates the header, every chunk header and the end record; builds the chunk index.
fn scan(path: &Path, file: &[u8]) -> Result<(DatasetHeader, Vec<Entry>, u64), DatasetError> {
    let decoded = decode_header(path, file)?;
    let header = decoded.header;
    let lights = header.table.lights.len();
    let corrupt = |offset: usize, detail: String| DatasetError::Corrupt {
        path: path.to_owned(),
        offset: offset as u64,
        detail,
    };
    let mut index = Vec::new();
    let mut sums = vec![0u64; lights];
    let mut total_samples = 0u64;
    let mut pos = decoded.len;
    loop {
        let rest = file.len() - pos;
        if rest < CHUNK_HEADER_LEN {
            return Err(DatasetError::Truncated {
                path: path.to_owned(),
                offset: pos as u64,
                detail: format!(
                    "a chunk header or the end record ({CHUNK_HEADER_LEN} bytes) starts here, but the file \
                     ends {rest} bytes later (was the write interrupted?)"
                ),
            });
        }
        let rec: &[u8; 32] = file[pos..pos + 32].try_into().unwrap();
        let n = index.len() as u64;
        if rec[..4] == CHUNK_MAGIC {
            let h = ChunkHeader::decode(rec, decoded.version).map_err(|e| match e {
                ChunkHeaderError::Checksum(stored, computed) => DatasetError::Checksum {
                    path: path.to_owned(),
                    offset: pos as u64,
                    what: format!("chunk {n} header"),
                    stored,
                    computed,
                },
                ChunkHeaderError::Flags(flags) => {
                    corrupt(pos + 20, format!("chunk {n}: unknown chunk flags {flags:#x}"))
                }
            })?;
            if h.light as usize >= lights {
                return Err(DatasetError::LightOutOfRange {
                    path: path.to_owned(),
                    offset: pos as u64 + 4,
                    chunk: n,
                    light: h.light,
                    lights,
                });
            }
            let avail = rest - CHUNK_HEADER_LEN;
            let records = if h.records { record_block_len(h.count) } else { Some(0) };
            let payload = h
                .count
                .checked_mul(size_of::<Sample>() as u64)
                .zip(records)
                .and_then(|(s, r)| s.checked_add(r))
                .filter(|&b| b <= avail as u64);
            let Some(payload) = payload else {
                let with = if h.records { " and their MIS records" } else { "" };
                let bytes = h.count as u128
                    * (size_of::<Sample>() + if h.records { size_of::<MisRecord>() } else { 0 }) as u128;
                return Err(DatasetError::Truncated {
                    path: path.to_owned(),
                    offset: (pos + CHUNK_HEADER_LEN) as u64,
                    detail: format!(
                        "chunk {n} declares {} samples{with} (at least {bytes} bytes) but only {avail} bytes \
                         follow its header",
                        h.count,
                    ),
                });
            };
            let sum = &mut sums[h.light as usize];
            *sum = sum.checked_add(h.paths).ok_or_else(|| {
                corrupt(pos + 8, format!("chunk {n}: path count of light {} overflows 64 bits", h.light))
            })?;
            total_samples += h.count;
            index.push(Entry {
                offset: pos,
                light: h.light,
                paths: h.paths,
                count: h.count as usize,
                crc: h.payload_crc,
                records: h.records,
            });
            pos += CHUNK_HEADER_LEN + payload as usize;
        } else if rec[..4] == END_MAGIC {
            let t = Trailer::decode(rec).map_err(|(stored, computed)| DatasetError::Checksum {
                path: path.to_owned(),
                offset: pos as u64,
                what: "end record".into(),
                stored,
                computed,
            })?;
            if rest != TRAILER_LEN {
                return Err(corrupt(
                    pos + TRAILER_LEN,
                    format!("{} unexpected bytes after the end record", rest - TRAILER_LEN),
                ));
            }
            let scanned = Trailer { chunks: n, samples: total_samples, paths: sums.iter().sum() };
            if t != scanned {
                return Err(corrupt(
                    pos,
                    format!(
                        "the end record counts {} chunks, {} samples, {} paths; the file holds {} chunks, \
                         {} samples, {} paths",
                        t.chunks, t.samples, t.paths, scanned.chunks, scanned.samples, scanned.paths
                    ),
                ));
            }
            break;
        } else {
            return Err(corrupt(
                pos,
                format!(
                    "expected a chunk header (\"CHNK\") or the end record (\"END\\0\"), found bytes {:02x?}",
                    &rec[..4]
                ),
            ));
        }
    }
    for (k, (l, &sum)) in header.table.lights.iter().zip(&sums).enumerate() {
        if l.paths != sum {
            return Err(DatasetError::PathCountMismatch {
                path: path.to_owned(),
                offset: decoded.paths_offsets[k],
                light: k,
                name: l.name.clone(),
                header: l.paths,
                chunks: sum,
            });
        }
    }
    Ok((header, index, total_samples))
}
