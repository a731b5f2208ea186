//! Reading a dataset: validated up front, payloads read and checked on access.
//!
//! Chunks are read with explicit positioned reads into buffers the caller owns, not through a
//! memory map: a file that another program truncates or rewrites while it is being rendered
//! then gives an error naming the file and the byte offset (a mapping would raise SIGBUS on the
//! vanished pages and kill the process). Reads go through the page cache as a mapping's faults
//! did, and only one chunk per thread is in memory at a time, so render memory stays
//! independent of the dataset's size.

use super::format::{ChunkHeader, ChunkHeaderError, Trailer, decode_header, record_block_len};
use super::format::{Invalid, validate_records, validate_samples};
use super::{CHUNK_HEADER_LEN, CHUNK_MAGIC, DatasetError, END_MAGIC, TRAILER_LEN};
use opticks_core::dataset::{Chunk, DatasetHeader, MAX_PATHS, MisRecord, Sample};
use rayon::prelude::*;
use std::fs::File;
use std::path::{Path, PathBuf};

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

    /// Offset just after the chunk (its record block included).
    fn end(&self) -> usize {
        let records =
            if self.records { record_block_len(self.count as u64).unwrap_or(0) as usize } else { 0 };
        self.records_at() + records
    }
}

/// A validated dataset file, open for reading.
///
/// [`open`](Self::open) checks the header (magic, version, CRC, light table), every chunk header
/// (magic, CRC, light index, length) and the end record, and that each light's N_k equals the sum
/// of its chunks' paths. It does not read the payloads: [`chunk`](Self::chunk) reads a chunk's
/// samples and verifies their CRC and values each time it is called (from any number of
/// threads: the reader is `Sync`), [`read_chunk_records`](Self::read_chunk_records) also its MIS
/// records (format 3), and [`verify`](Self::verify) checks them all. `chunk` reads only the
/// samples, so the light estimator reads the same bytes from a format-3 file as from a format-2
/// one. Once [`check_triangles`](Self::check_triangles) has given the scene's triangle count,
/// every sample read must also name an existing triangle.
#[derive(Debug)]
pub struct DatasetReader {
    path: PathBuf,
    file: File,
    len: u64,
    header: DatasetHeader,
    index: Vec<Entry>,
    total_samples: u64,
    triangles: Option<u32>,
}

impl DatasetReader {
    /// Opens and validates `path` (see the type's documentation). Only regular files are read:
    /// a FIFO, a device (`/dev/zero`) or a directory is refused before it is opened.
    pub fn open(path: &Path) -> Result<Self, DatasetError> {
        Self::open_with(path, false)
    }

    /// Opens the file of a run that was killed before it finished (`salvage.rs`): the header
    /// and the whole chunks before the first one cut short or damaged, whose headers passed
    /// their checks; the header's N_k are those the run started with, not the chunks'.
    pub(crate) fn open_unfinished(path: &Path) -> Result<Self, DatasetError> {
        Self::open_with(path, true)
    }

    /// [`open`](Self::open), or with `tolerant` [`open_unfinished`](Self::open_unfinished).
    fn open_with(path: &Path, tolerant: bool) -> Result<Self, DatasetError> {
        let io = |op| move |source| DatasetError::Io { path: path.to_owned(), op, source };
        if cfg!(target_endian = "big") {
            return Err(DatasetError::InvalidInput {
                path: path.to_owned(),
                detail: "dataset files are little endian; big-endian hosts are not supported".into(),
            });
        }
        crate::input_file::check_regular(path).map_err(io("read"))?;
        let (file, len) = crate::input_file::open(path).map_err(io("open"))?;
        let mut r = DatasetReader {
            path: path.to_owned(),
            file,
            len,
            header: DatasetHeader::default(),
            index: Vec::new(),
            total_samples: 0,
            triangles: None,
        };
        (r.header, r.index, r.total_samples) = scan(path, &r, tolerant)?;
        Ok(r)
    }

    /// Keeps only the first `n` chunks.
    pub(crate) fn keep_chunks(&mut self, n: usize) {
        self.index.truncate(n);
        self.total_samples = self.index.iter().map(|e| e.count as u64).sum();
    }

    /// The offset just after the last chunk, if there is one.
    pub(crate) fn chunks_end(&self) -> Option<u64> {
        self.index.last().map(|e| e.end() as u64)
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

    /// File size in bytes (when it was opened).
    pub fn file_len(&self) -> u64 {
        self.len
    }

    /// From now on, every sample read must name one of the scene's `triangles` triangles (a
    /// sample's triangle gives the normal and material its renderer looks up): the check a
    /// checksum cannot make, for a file written with valid checksums from a bad triangle index.
    pub fn check_triangles(&mut self, triangles: usize) {
        self.triangles = Some(u32::try_from(triangles).unwrap_or(u32::MAX));
    }

    /// Chunk `i`, read from the file after checking its payload CRC and that every sample has a
    /// finite position and a finite β ≥ 0 (and names an existing triangle, see
    /// [`check_triangles`](Self::check_triangles)).
    pub fn chunk(&self, i: usize) -> Result<Chunk, DatasetError> {
        let mut samples = Vec::new();
        let (light, paths) = self.read_chunk(i, &mut samples)?;
        Ok(Chunk { light, paths, samples, records: Vec::new() })
    }

    /// [`chunk`](Self::chunk) into `samples` (replacing its contents, reusing its memory):
    /// returns the chunk's light index and path count. After an error `samples` holds
    /// unspecified (but initialised) samples.
    pub fn read_chunk(&self, i: usize, samples: &mut Vec<Sample>) -> Result<(u32, u64), DatasetError> {
        let e = self.entry(i)?;
        let start = e.samples_at();
        fit(samples, e.count);
        self.read_exact_at(start as u64, bytemuck::cast_slice_mut(samples))?;
        let computed = crc32fast::hash(bytemuck::cast_slice(samples));
        if computed != e.crc {
            return Err(DatasetError::Checksum {
                path: self.path.clone(),
                offset: start as u64,
                what: format!("chunk {i} payload"),
                stored: e.crc,
                computed,
            });
        }
        if let Err(Invalid { index: k, fault: detail }) = validate_samples(samples, self.triangles) {
            return Err(DatasetError::InvalidSample {
                path: self.path.clone(),
                offset: (start + k * size_of::<Sample>()) as u64,
                chunk: i as u64,
                index: k,
                detail,
            });
        }
        Ok((e.light, e.paths))
    }

    /// Whether chunk `i`'s samples carry MIS records (format 3; true for a chunk without
    /// samples, whose records are empty), from the index (no payload is read).
    pub fn has_records(&self, i: usize) -> Option<bool> {
        self.index.get(i).map(|e| e.records || e.count == 0)
    }

    /// [`read_chunk`](Self::read_chunk) plus the MIS records of the chunk's samples into
    /// `records` (`records[j]` belongs to `samples[j]`; both replaced, their memory reused),
    /// after checking the record block's CRC, its zero padding, that every record is possible
    /// ([`MisRecord::is_valid`]) and that the emitter-hit class marks exactly the emission
    /// samples. An error for a chunk with samples but no records ([`has_records`](Self::has_records)).
    /// After an error both hold unspecified (but initialised) values.
    pub fn read_chunk_records(
        &self,
        i: usize,
        samples: &mut Vec<Sample>,
        records: &mut Vec<MisRecord>,
    ) -> Result<(u32, u64), DatasetError> {
        let (light, paths) = self.read_chunk(i, samples)?;
        let e = self.entry(i)?;
        if e.count == 0 {
            records.clear();
            return Ok((light, paths));
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
        let records_len = e.count * size_of::<MisRecord>();
        // The records straight into `records` (no zero fill, no intermediate copy), then the
        // block's few bytes of padding and CRC.
        fit(records, e.count);
        self.read_exact_at(start as u64, bytemuck::cast_slice_mut(records))?;
        let tail = self.bytes_at(start + records_len, len - records_len)?;
        let stored = u32::from_le_bytes(tail[tail.len() - 4..].try_into().unwrap());
        let mut crc = crc32fast::Hasher::new();
        crc.update(bytemuck::cast_slice(records));
        crc.update(&tail[..tail.len() - 4]);
        let computed = crc.finalize();
        if stored != computed {
            return Err(DatasetError::Checksum {
                path: self.path.clone(),
                offset: start as u64,
                what: format!("chunk {i} MIS records"),
                stored,
                computed,
            });
        }
        if let Some(k) = tail[..tail.len() - 4].iter().position(|&x| x != 0) {
            return Err(DatasetError::Corrupt {
                path: self.path.clone(),
                offset: (start + records_len + k) as u64,
                detail: format!("chunk {i}: non-zero byte in the padding of the MIS records"),
            });
        }
        if let Err(Invalid { index: k, fault: detail }) = validate_records(samples, records) {
            return Err(DatasetError::InvalidRecord {
                path: self.path.clone(),
                offset: (start + k * size_of::<MisRecord>()) as u64,
                chunk: i as u64,
                index: k,
                detail,
            });
        }
        Ok((light, paths))
    }

    /// The MIS records of chunk `i`, checked as [`read_chunk_records`](Self::read_chunk_records)
    /// checks them (its samples are read for that too).
    pub fn chunk_records(&self, i: usize) -> Result<Vec<MisRecord>, DatasetError> {
        let (mut samples, mut records) = (Vec::new(), Vec::new());
        self.read_chunk_records(i, &mut samples, &mut records)?;
        Ok(records)
    }

    /// Chunk `i` as an owned [`Chunk`]: its samples and, if it has them, its MIS records (both
    /// checked). What copying a chunk into another dataset needs.
    pub fn owned_chunk(&self, i: usize) -> Result<Chunk, DatasetError> {
        let (mut samples, mut records) = (Vec::new(), Vec::new());
        let (light, paths) = if self.entry(i)?.records {
            self.read_chunk_records(i, &mut samples, &mut records)?
        } else {
            self.read_chunk(i, &mut samples)?
        };
        Ok(Chunk { light, paths, samples, records })
    }

    fn entry(&self, i: usize) -> Result<Entry, DatasetError> {
        self.index.get(i).copied().ok_or_else(|| DatasetError::NoSuchChunk {
            path: self.path.clone(),
            index: i,
            count: self.index.len(),
        })
    }

    /// Light index, path count and sample count of chunk `i`, from the index built by
    /// [`open`](Self::open) (no payload is read).
    pub fn chunk_summary(&self, i: usize) -> Option<(u32, u64, usize)> {
        self.index.get(i).map(|e| (e.light, e.paths, e.count))
    }

    /// Checks every chunk's payload and MIS records (in parallel); the error of the
    /// lowest-numbered bad chunk.
    pub fn verify(&self) -> Result<(), DatasetError> {
        match (0..self.index.len())
            .into_par_iter()
            .map_init(
                || (Vec::new(), Vec::new()),
                |(samples, records), i| match self.index[i].records {
                    true => self.read_chunk_records(i, samples, records).map(|_| ()),
                    false => self.read_chunk(i, samples).map(|_| ()),
                },
            )
            .find_first(|r| r.is_err())
        {
            Some(r) => r,
            None => Ok(()),
        }
    }

    /// Fills `buf` from byte `offset`. A file that ends early — it was truncated or replaced in
    /// place after it was opened — is an error naming the offset, not a signal.
    fn read_exact_at(&self, offset: u64, buf: &mut [u8]) -> Result<(), DatasetError> {
        crate::input_file::read_exact_at(&self.file, offset, buf).map_err(|source| {
            if source.kind() == std::io::ErrorKind::UnexpectedEof {
                DatasetError::Truncated {
                    path: self.path.clone(),
                    offset: offset + buf.len() as u64,
                    detail: format!(
                        "the file ends before byte {}, but it was {} bytes long when it was opened: \
                         another program truncated or rewrote it while it was being read",
                        offset + buf.len() as u64,
                        self.len
                    ),
                }
            } else {
                DatasetError::Io { path: self.path.clone(), op: "read", source }
            }
        })
    }

    /// `n` bytes from `offset` (within the length the file had when opened).
    fn bytes_at(&self, offset: usize, n: usize) -> Result<Vec<u8>, DatasetError> {
        let mut b = vec![0u8; n];
        self.read_exact_at(offset as u64, &mut b)?;
        Ok(b)
    }
}

/// `v` resized to `n` values that a read will overwrite, without zero-filling them first (that
/// `memset` was ~5 % of a Cornell light-estimator frame): a buffer too small is replaced by a
/// zeroed allocation (`calloc`: large ones are fresh pages the system has zeroed), a large
/// enough one is resized in place, its old values kept.
fn fit<T: bytemuck::Pod>(v: &mut Vec<T>, n: usize) {
    if v.capacity() < n {
        *v = bytemuck::zeroed_vec(n);
    } else {
        v.resize(n, T::zeroed());
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

/// Validates the header, every chunk header and the end record; builds the chunk index.
/// With `tolerant` (the file of a run that was killed, `salvage.rs`), the scan stops at the
/// first chunk that is cut short or damaged, or at the end record, and keeps the whole chunks
/// before it; the header's N_k are not checked against them.
fn scan(
    path: &Path,
    r: &DatasetReader,
    tolerant: bool,
) -> Result<(DatasetHeader, Vec<Entry>, u64), DatasetError> {
    // A fault in the chunks: an error, or where a tolerant scan stops.
    macro_rules! fault {
        ($e:expr) => {{
            if tolerant {
                break;
            }
            return Err($e);
        }};
    }
    let file_len = usize::try_from(r.len).unwrap_or(usize::MAX);
    // The header's first 16 bytes give its length; then the whole header (no longer than the file).
    let head = r.bytes_at(0, file_len.min(16))?;
    let header_len = head.get(12..16).map_or(0, |b| u32::from_le_bytes(b.try_into().unwrap()) as usize);
    let head =
        if header_len > head.len() && header_len <= file_len { r.bytes_at(0, header_len)? } else { head };
    let decoded = decode_header(path, &head, file_len)?;
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
    let mut total_paths = 0u64;
    let mut pos = decoded.len;
    loop {
        let rest = file_len - pos;
        if rest < CHUNK_HEADER_LEN {
            fault!(DatasetError::Truncated {
                path: path.to_owned(),
                offset: pos as u64,
                detail: format!(
                    "a chunk header or the end record ({CHUNK_HEADER_LEN} bytes) starts here, but the file \
                     ends {rest} bytes later (was the write interrupted?)"
                ),
            })
        }
        let rec = r.bytes_at(pos, CHUNK_HEADER_LEN)?;
        let rec: &[u8; 32] = rec[..].try_into().unwrap();
        let n = index.len() as u64;
        if rec[..4] == CHUNK_MAGIC {
            let h = match ChunkHeader::decode(rec, decoded.version).map_err(|e| match e {
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
            }) {
                Ok(h) => h,
                Err(e) => fault!(e),
            };
            if h.light as usize >= lights {
                fault!(DatasetError::LightOutOfRange {
                    path: path.to_owned(),
                    offset: pos as u64 + 4,
                    chunk: n,
                    light: h.light,
                    lights,
                })
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
                fault!(DatasetError::Truncated {
                    path: path.to_owned(),
                    offset: (pos + CHUNK_HEADER_LEN) as u64,
                    detail: format!(
                        "chunk {n} declares {} samples{with} (at least {bytes} bytes) but only {avail} bytes \
                         follow its header",
                        h.count,
                    ),
                })
            };
            // Every sum of path counts is checked: a dataset holds at most MAX_PATHS in all.
            let Some(sum) = total_paths.checked_add(h.paths).filter(|&t| t <= MAX_PATHS) else {
                fault!(corrupt(
                    pos + 8,
                    format!("chunk {n}: the dataset's path count exceeds the maximum of {MAX_PATHS} (2^53)"),
                ))
            };
            total_paths = sum;
            sums[h.light as usize] += h.paths;
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
            if tolerant {
                break;
            }
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
            let scanned = Trailer { chunks: n, samples: total_samples, paths: total_paths };
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
            fault!(corrupt(
                pos,
                format!(
                    "expected a chunk header (\"CHNK\") or the end record (\"END\\0\"), found bytes {:02x?}",
                    &rec[..4]
                ),
            ))
        }
    }
    if tolerant {
        return Ok((header, index, total_samples));
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
