//! Writing a dataset: sequential, buffered, atomic (temporary file + rename).

use super::DatasetError;
use super::format::{
    ChunkHeader, Invalid, Trailer, Unwritable, append_record_block, encode_header, validate_records,
    validate_samples,
};
use opticks_core::dataset::{Chunk, DatasetHeader, LightTable, MAX_PATHS, TraceInfo};
use std::fs::File;
use std::io::{Seek, SeekFrom, Write};
use std::path::{Path, PathBuf};

/// What [`DatasetWriter::finish`] wrote.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct DatasetSummary {
    /// The final file.
    pub path: PathBuf,
    /// File size in bytes.
    pub bytes: u64,
    /// Number of chunks.
    pub chunks: u64,
    /// Number of stored samples.
    pub samples: u64,
    /// Total light paths (the sum of N_k).
    pub paths: u64,
}

/// Writes a dataset file: [`create`](Self::create), any number of
/// [`write_chunk`](Self::write_chunk), then [`finish`](Self::finish).
///
/// Everything goes to a temporary file `.NAME.tmp-PID-N` in the target's directory (the same
/// file system, so the final rename is atomic). `finish` rewrites the header with the final light
/// table, appends the end record, syncs and renames over the target. Dropping the writer without
/// `finish` (an error, a panic) removes the temporary file; the previous file at the target is
/// never touched before the rename. (A process killed outright, e.g. by an unhandled Ctrl-C,
/// runs no destructor: its temporary file stays behind, but the target is still intact, and
/// the next writer of the same target removes it: `crate::dataset_lock`.)
///
/// Chunks are buffered whole and handed to the operating system at chunk boundaries, so the
/// writer always knows the last chunk known to be in the file. When a write fails (a full
/// disk), [`keep_written_prefix`](Self::keep_written_prefix) cuts the file back to it, and
/// `finish` then makes a valid dataset of the chunks written so far. Errors name the target,
/// not the hidden temporary file.
///
/// The header is written first with the light table given to `create` and rewritten in place by
/// `finish`, so the final table must have the same lights (same count and names, hence the same
/// encoded length) and the trace record the same passes with the same plans; only the powers
/// Φ_k, path counts N_k and the passes' figures (paths, seconds) may change.
#[derive(Debug)]
pub struct DatasetWriter {
    path: PathBuf,
    tmp: Option<PathBuf>,
    out: Option<File>,
    /// Whole chunks not yet handed to the operating system.
    buffer: Vec<u8>,
    header: DatasetHeader,
    header_len: usize,
    /// What has been written (buffered included)…
    written: Written,
    /// …and what is known to be in the file (everything before `buffer`).
    in_file: Written,
    failed: bool,
    /// Test hook (`$OPTICKS_FAIL_WRITES_AFTER_BYTES`): a disk that fills up after this many bytes.
    capacity: Option<u64>,
    /// Test hook (`$OPTICKS_ABORT_AFTER_CHUNKS`): the process is killed outright (aborted, no
    /// destructor runs) once this many chunks are in the file, as SIGKILL or a power cut would.
    abort_after: Option<u64>,
}

/// Counts of a prefix of the file: always whole chunks.
#[derive(Clone, Debug, Default)]
struct Written {
    bytes: u64,
    chunks: u64,
    samples: u64,
    light_paths: Vec<u64>,
}

/// Buffer size of the writer: large enough that the system call cost vanishes.
const BUFFER: usize = 1 << 20;

impl DatasetWriter {
    /// Starts a dataset at `path` (not created until [`finish`](Self::finish)). `header.table`
    /// fixes the lights; its path counts are placeholders until `finish`.
    pub fn create(path: &Path, header: &DatasetHeader) -> Result<Self, DatasetError> {
        let invalid = |detail: String| DatasetError::InvalidInput { path: path.to_owned(), detail };
        if cfg!(target_endian = "big") {
            return Err(invalid(
                "dataset files are little endian; big-endian hosts are not supported".into(),
            ));
        }
        check_table(&header.table).map_err(|e| invalid(e.to_string()))?;
        let bytes = encode_header(header).map_err(|e| invalid(e.to_string()))?;
        if path.file_name().is_none() {
            return Err(invalid("the path has no file name".into()));
        }
        let (tmp, file) = crate::output_paths::create_temporary(path).map_err(|source| DatasetError::Io {
            path: path.to_owned(),
            op: "create temporary file",
            source,
        })?;
        let empty = Written { light_paths: vec![0; header.table.lights.len()], ..Default::default() };
        let mut w = DatasetWriter {
            path: path.to_owned(),
            tmp: Some(tmp),
            out: Some(file),
            buffer: Vec::with_capacity(2 * BUFFER),
            header: header.clone(),
            header_len: bytes.len(),
            written: empty.clone(),
            in_file: empty,
            failed: false,
            capacity: std::env::var("OPTICKS_FAIL_WRITES_AFTER_BYTES").ok().and_then(|v| v.parse().ok()),
            abort_after: std::env::var("OPTICKS_ABORT_AFTER_CHUNKS").ok().and_then(|v| v.parse().ok()),
        };
        w.write(&bytes)?;
        w.flush_buffer()?;
        Ok(w)
    }

    /// Takes over the file `tmp` that a killed run left (`salvage.rs`): `header` as the run
    /// wrote it first, its whole chunks ending at byte `end` (the rest is cut off), holding
    /// `chunks` chunks, `samples` samples and `light_paths` paths per light. [`finish`](Self::finish)
    /// then makes it a dataset at `target`; dropped unfinished, the file is removed, as any
    /// writer's temporary file.
    pub(crate) fn adopt(
        tmp: &Path,
        target: &Path,
        header: &DatasetHeader,
        end: u64,
        (chunks, samples, light_paths): (u64, u64, Vec<u64>),
    ) -> Result<Self, DatasetError> {
        let io = |op| move |source| DatasetError::Io { path: tmp.to_owned(), op, source };
        let header_len = encode_header(header)
            .map_err(|e| DatasetError::InvalidInput { path: tmp.to_owned(), detail: e.to_string() })?
            .len();
        let mut file = std::fs::OpenOptions::new().read(true).write(true).open(tmp).map_err(io("open"))?;
        file.set_len(end).map_err(io("cut back the unfinished file"))?;
        file.seek(SeekFrom::Start(end)).map_err(io("seek"))?;
        let written = Written { bytes: end, chunks, samples, light_paths };
        Ok(DatasetWriter {
            path: target.to_owned(),
            tmp: Some(tmp.to_owned()),
            out: Some(file),
            buffer: Vec::new(),
            header: header.clone(),
            header_len,
            written: written.clone(),
            in_file: written,
            failed: false,
            capacity: None,
            abort_after: None,
        })
    }

    /// The target path.
    pub fn path(&self) -> &Path {
        &self.path
    }

    /// Appends one chunk, with its MIS records if it has them (a record block after the
    /// samples). Refuses (without writing anything) a chunk whose light is not in the table,
    /// whose samples are not finite with β ≥ 0, whose records are neither absent nor one per
    /// sample or fail the reader's checks, or with more than 2³² − 1 samples.
    pub fn write_chunk(&mut self, chunk: &Chunk) -> Result<(), DatasetError> {
        let invalid = |detail: String| DatasetError::InvalidInput { path: self.path.clone(), detail };
        let lights = self.written.light_paths.len();
        let Some(&sum) = self.written.light_paths.get(chunk.light as usize) else {
            return Err(invalid(format!(
                "chunk for light {}, but the table has {lights} lights",
                chunk.light
            )));
        };
        let total = self.written.light_paths.iter().fold(0u64, |a, &n| a.saturating_add(n));
        let Some(sum) =
            sum.checked_add(chunk.paths).filter(|_| total.saturating_add(chunk.paths) <= MAX_PATHS)
        else {
            return Err(invalid(format!(
                "a chunk of light {} takes the dataset beyond the maximum of {MAX_PATHS} paths (2^53)",
                chunk.light
            )));
        };
        if let Err(Invalid { index: i, fault: what }) = validate_samples(&chunk.samples, None) {
            return Err(invalid(format!("sample {i} of a chunk of light {}: {what}", chunk.light)));
        }
        if u32::try_from(chunk.samples.len()).is_err() {
            return Err(invalid(format!("a chunk of {} samples (at most 2^32 - 1)", chunk.samples.len())));
        }
        let records = !chunk.records.is_empty();
        if records && chunk.records.len() != chunk.samples.len() {
            return Err(invalid(format!(
                "a chunk of light {} with {} samples but {} MIS records",
                chunk.light,
                chunk.samples.len(),
                chunk.records.len()
            )));
        }
        if let Err(Invalid { index: i, fault: what }) = validate_records(&chunk.samples, &chunk.records) {
            return Err(invalid(format!("MIS record {i} of a chunk of light {}: {what}", chunk.light)));
        }
        let payload: &[u8] = bytemuck::cast_slice(&chunk.samples);
        let head = ChunkHeader {
            light: chunk.light,
            paths: chunk.paths,
            count: chunk.samples.len() as u64,
            records,
            payload_crc: crc32fast::hash(payload),
        };
        if self.failed {
            return Err(invalid("an earlier write failed".into()));
        }
        self.write(&head.encode())?;
        self.write(payload)?;
        if records {
            let start = self.buffer.len();
            append_record_block(&chunk.records, &mut self.buffer);
            self.written.bytes += (self.buffer.len() - start) as u64;
        }
        self.written.light_paths[chunk.light as usize] = sum;
        self.written.chunks += 1;
        self.written.samples += chunk.samples.len() as u64;
        if self.buffer.len() >= BUFFER {
            self.flush_buffer()?;
        }
        if self.abort_after == Some(self.written.chunks) {
            self.flush_buffer()?;
            std::process::abort();
        }
        Ok(())
    }

    /// Paths written so far per light (the N_k that `finish` expects).
    pub fn light_paths(&self) -> &[u64] {
        &self.written.light_paths
    }

    /// After a failed write: cuts the file back to the chunks known to be in it, so that
    /// [`finish`](Self::finish) (with N_k = [`light_paths`](Self::light_paths), now those of the
    /// kept chunks) makes a valid dataset of them. Cutting frees the space of the lost chunks,
    /// which is what the end record then needs on a full disk.
    pub fn keep_written_prefix(&mut self) -> Result<(), DatasetError> {
        let target = self.path.clone();
        let io = |op| move |source| DatasetError::Io { path: target, op, source };
        let out = self.out.as_mut().expect("writer present until finish");
        out.set_len(self.in_file.bytes).map_err(io("cut back the unfinished file"))?;
        out.seek(SeekFrom::Start(self.in_file.bytes)).map_err(|e| DatasetError::Io {
            path: self.path.clone(),
            op: "seek",
            source: e,
        })?;
        self.buffer.clear();
        self.written = self.in_file.clone();
        self.failed = false;
        Ok(())
    }

    /// Renames the file that [`finish`](Self::finish) will create (e.g. to save an interrupted
    /// run beside the dataset it would have replaced). Best kept in the same directory: the
    /// temporary file is there, and the final rename must not cross file systems.
    pub fn retarget(&mut self, path: &Path) {
        self.path = path.to_owned();
    }

    /// Completes the file: `table` must list the same lights as the header given to `create`
    /// and each N_k must equal the sum of that light's chunk paths; `trace` must have as many
    /// passes as the header given to `create` (their paths and times are final only now).
    /// Rewrites the header, writes the end record, syncs and atomically renames the file into
    /// place.
    pub fn finish(mut self, table: &LightTable, trace: &TraceInfo) -> Result<DatasetSummary, DatasetError> {
        let invalid = |detail: String| DatasetError::InvalidInput { path: self.path.clone(), detail };
        if self.failed {
            return Err(invalid("an earlier write failed; the dataset is incomplete".into()));
        }
        check_table(table).map_err(|e| invalid(e.to_string()))?;
        let old = &self.header.table.lights;
        if table.lights.len() != old.len() || table.lights.iter().zip(old).any(|(a, b)| a.name != b.name) {
            let names = |t: &LightTable| t.lights.iter().map(|l| l.name.clone()).collect::<Vec<_>>();
            return Err(invalid(format!(
                "the final light table {:?} does not list the lights the dataset was created with {:?}",
                names(table),
                names(&self.header.table)
            )));
        }
        for (k, (l, &sum)) in table.lights.iter().zip(&self.written.light_paths).enumerate() {
            if l.paths != sum {
                return Err(invalid(format!(
                    "light {k} ({:?}): the table says N_k = {} paths but the chunks written hold {sum}",
                    l.name, l.paths
                )));
            }
        }
        // Plans are fixed when a pass starts; the one change allowed is the last pass ending
        // where it stopped (`end_pass_here`): the same lights, none planned more paths.
        let ended_early = |new: &[(u32, u64)], old: &[(u32, u64)]| {
            new.len() == old.len() && new.iter().zip(old).all(|(n, o)| n.0 == o.0 && n.1 <= o.1)
        };
        let (new, old) = (&trace.passes, &self.header.trace.passes);
        let changed = new.len() == old.len()
            && new.iter().zip(old).enumerate().any(|(i, (n, o))| {
                n.planned != o.planned && (i + 1 != new.len() || !ended_early(&n.planned, &o.planned))
            });
        if changed {
            return Err(invalid("the final trace record changes a pass's plan".into()));
        }
        if trace.passes.len() != self.header.trace.passes.len() {
            return Err(invalid(format!(
                "the final trace record has {} passes, the dataset was created with {}",
                trace.passes.len(),
                self.header.trace.passes.len()
            )));
        }
        self.header.table = table.clone();
        self.header.trace = trace.clone();
        let head = encode_header(&self.header).map_err(|e| invalid(e.to_string()))?;
        if head.len() != self.header_len {
            return Err(invalid("the final header does not fit the space of the first".into()));
        }
        let trailer = Trailer {
            chunks: self.written.chunks,
            samples: self.written.samples,
            paths: table.total_paths(),
        };
        self.write(&trailer.encode())?;
        self.flush_buffer()?;

        let tmp = self.tmp.clone().expect("temporary path present until finish");
        let target = self.path.clone();
        let io = |op: &'static str| {
            let target = target.clone();
            move |source| DatasetError::Io { path: target, op, source }
        };
        let mut file = self.out.take().expect("writer present until finish");
        file.seek(SeekFrom::Start(0)).map_err(io("seek"))?;
        file.write_all(&head).map_err(io("write header"))?;
        file.sync_all().map_err(io("sync"))?;
        drop(file);
        std::fs::rename(&tmp, &self.path).map_err(|source| DatasetError::Io {
            path: self.path.clone(),
            op: "rename the finished temporary file into place",
            source,
        })?;
        self.tmp = None;
        // Make the rename itself durable. Not every platform can sync a directory; the data is
        // already safe, so a failure here is not worth failing the (completed) write for.
        if let Some(dir) = self.path.parent().filter(|d| !d.as_os_str().is_empty())
            && let Ok(d) = File::open(dir)
        {
            let _ = d.sync_all();
        }
        Ok(DatasetSummary {
            path: self.path.clone(),
            bytes: self.written.bytes,
            chunks: self.written.chunks,
            samples: self.written.samples,
            paths: table.total_paths(),
        })
    }

    /// Buffers `bytes` (the parts of one chunk, or the header, or the end record).
    fn write(&mut self, bytes: &[u8]) -> Result<(), DatasetError> {
        self.buffer.extend_from_slice(bytes);
        self.written.bytes += bytes.len() as u64;
        Ok(())
    }

    /// Hands the buffered whole chunks to the operating system.
    fn flush_buffer(&mut self) -> Result<(), DatasetError> {
        let out = self.out.as_mut().expect("writer present until finish");
        let result = match self.capacity {
            Some(cap) if self.in_file.bytes + self.buffer.len() as u64 > cap => {
                let fits = cap.saturating_sub(self.in_file.bytes) as usize;
                out.write_all(&self.buffer[..fits]).and(Err(std::io::Error::new(
                    std::io::ErrorKind::StorageFull,
                    "No space left on device (simulated: $OPTICKS_FAIL_WRITES_AFTER_BYTES)",
                )))
            }
            _ => out.write_all(&self.buffer),
        };
        if let Err(source) = result {
            self.failed = true;
            return Err(DatasetError::Io { path: self.path.clone(), op: "write", source });
        }
        self.buffer.clear();
        self.in_file = self.written.clone();
        Ok(())
    }
}

impl Drop for DatasetWriter {
    fn drop(&mut self) {
        if let Some(tmp) = self.tmp.take() {
            // Close before removing (required on Windows); buffered data is discarded anyway.
            drop(self.out.take());
            let _ = std::fs::remove_file(tmp);
        }
    }
}

/// Refuses a table with a light whose power is negative or not finite.
fn check_table(t: &LightTable) -> Result<(), Unwritable> {
    for (k, l) in t.lights.iter().enumerate() {
        let power = l.power.to_array();
        if !power.iter().all(|x| x.is_finite() && *x >= 0.0) {
            return Err(Unwritable::BadPower { light: k, name: l.name.clone(), power });
        }
    }
    Ok(())
}
