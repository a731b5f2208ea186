//! The light vertex cache: the dataset as the light half of the bidirectional estimator
//! (`docs/bidirectional.md` §1). It holds borrowed views of the rendered chunks — their samples
//! and the samples' [`MisRecord`]s, from memory ([`LightCache::from_chunks`], the core's tests)
//! or from a dataset file read into memory (`opticks_io::light_cache`, which verifies each chunk once and hands
//! its views here) — so its own memory is a few words per chunk, whatever the dataset's size.
//!
//! What the renderer asks of it: |Y|, the stored non-emission vertices of the lights that are
//! on; a vertex drawn uniformly from them ([`LightCache::draw`]: a chunk by prefix sums of its
//! non-emission count, then a sample of it by rejection of its emission vertices, which is
//! exactly uniform — in two halves, so that a camera path can begin the draw one vertex ahead
//! and its random read of memory overlaps that vertex's work: [`LightCache::begin_draw`]
//! prefetches, [`LightCache::finish_draw`] reads); every chunk in turn for the light-tracing splat; and per table light its
//! paths N_k in the rendered chunks. Emission vertices are counted per chunk when a view is
//! made ([`CacheChunk::new`]), so nothing is assumed about where a chunk keeps them.

use crate::dataset::{Chunk, MisRecord, Sample};
use crate::math::prefetch;
use crate::sampling::RandomStream;

/// One chunk of the cache: `paths` light paths of table light `light`, their `samples` and the
/// samples' MIS records (parallel to `samples`; empty for a dataset without records).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CacheChunk<'a> {
    /// Index of the light in the dataset's table.
    pub light: u32,
    /// Light paths the chunk accounts for.
    pub paths: u64,
    /// The stored vertices.
    pub samples: &'a [Sample],
    /// Their records (`records[i]` belongs to `samples[i]`), or empty.
    pub records: &'a [MisRecord],
    /// How many of `samples` are not emission vertices.
    non_emission: u64,
}

/// Records do not match the samples one to one.
#[derive(Clone, Copy, Debug, PartialEq, Eq, thiserror::Error)]
#[error("a chunk of {samples} samples has {records} MIS records")]
pub struct RecordMismatch {
    /// Samples in the chunk.
    pub samples: usize,
    /// Records given for them.
    pub records: usize,
}

impl<'a> CacheChunk<'a> {
    /// A view of a chunk (counts its emission vertices: one pass over the samples).
    pub fn new(
        light: u32,
        paths: u64,
        samples: &'a [Sample],
        records: &'a [MisRecord],
    ) -> Result<Self, RecordMismatch> {
        if !records.is_empty() && records.len() != samples.len() {
            return Err(RecordMismatch { samples: samples.len(), records: records.len() });
        }
        let non_emission = samples.iter().filter(|s| !s.is_emission()).count() as u64;
        Ok(CacheChunk { light, paths, samples, records, non_emission })
    }

    /// The chunk's non-emission samples.
    pub fn non_emission(&self) -> u64 {
        self.non_emission
    }
}

/// A vertex drawn from the cache.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CachedVertex<'a> {
    /// Index of its light in the dataset's table.
    pub light: u32,
    /// The stored sample.
    pub sample: &'a Sample,
    /// Its MIS record.
    pub record: MisRecord,
}

/// The light vertex cache (module docs).
#[derive(Clone, Debug, PartialEq)]
pub struct LightCache<'a> {
    chunks: Vec<CacheChunk<'a>>,
    /// Per chunk, the drawable vertices of the chunks before it (0 for lights that are off).
    prefix: Vec<u64>,
    /// |Y|.
    vertices: u64,
    /// Per table light, its paths in the cache's chunks.
    paths: Vec<u64>,
    /// Whether every chunk has records.
    records: bool,
}

impl<'a> LightCache<'a> {
    /// The cache of `chunks` for a table of `lights` lights, of which those with `on[k]` are
    /// drawn from (a light switched off keeps its N_k in [`LightCache::paths`] but gives no
    /// vertices).
    pub fn new(chunks: Vec<CacheChunk<'a>>, lights: usize, on: &[bool]) -> Self {
        let mut prefix = Vec::with_capacity(chunks.len());
        let (mut vertices, mut paths) = (0u64, vec![0u64; lights]);
        for c in &chunks {
            prefix.push(vertices);
            let k = c.light as usize;
            if k < lights {
                paths[k] += c.paths;
            }
            if on.get(k).copied().unwrap_or(false) {
                vertices += c.non_emission;
            }
        }
        let records = chunks.iter().all(|c| c.records.len() == c.samples.len());
        LightCache { chunks, prefix, vertices, paths, records }
    }

    /// The in-memory cache of `chunks` (a dataset held in memory, with the records they carry).
    pub fn from_chunks(chunks: &'a [Chunk], lights: usize, on: &[bool]) -> Result<Self, RecordMismatch> {
        let views = chunks
            .iter()
            .map(|c| CacheChunk::new(c.light, c.paths, &c.samples, &c.records))
            .collect::<Result<Vec<_>, _>>()?;
        Ok(LightCache::new(views, lights, on))
    }

    /// The chunks, in dataset order.
    pub fn chunks(&self) -> &[CacheChunk<'a>] {
        &self.chunks
    }

    /// |Y|: the stored non-emission vertices of the lights that are on.
    pub fn vertices(&self) -> u64 {
        self.vertices
    }

    /// Per table light, its paths N_k in the cache's chunks.
    pub fn paths(&self) -> &[u64] {
        &self.paths
    }

    /// Whether every sample has its MIS record.
    pub fn has_records(&self) -> bool {
        self.records
    }

    /// Draws a vertex uniformly from the |Y| drawable ones; `None` if there are none or the
    /// cache has no records. The same as [`LightCache::begin_draw`] then
    /// [`LightCache::finish_draw`] at once.
    #[inline]
    pub fn draw(&self, rng: &mut RandomStream) -> Option<CachedVertex<'a>> {
        let p = self.begin_draw(rng)?;
        Some(self.finish_draw(p, rng))
    }

    /// The first half of a draw, which can be made well before the vertex is needed: the chunk
    /// (by prefix sums of the non-emission counts, so with probability ∝ its drawable vertices)
    /// and [`CANDIDATES`] sample indices drawn uniformly in it, whose sample and record are
    /// prefetched into the CPU cache; `None` if there is nothing to draw. A connection's vertex
    /// lies anywhere in a cache of hundreds of MB, so reading it is a miss all the way to
    /// memory; started one camera vertex ahead, the read overlaps that vertex's rays instead of
    /// stalling the connection (`docs/performance.md`).
    #[inline]
    pub fn begin_draw(&self, rng: &mut RandomStream) -> Option<PendingDraw> {
        if self.vertices == 0 || !self.records {
            return None;
        }
        let g = below(rng, self.vertices);
        let c = self.prefix.partition_point(|&p| p <= g) - 1;
        // `prefix` is non-decreasing; the last chunk starting at or before g with vertices.
        let chunk = &self.chunks[c];
        debug_assert!(chunk.non_emission > 0);
        let n = chunk.samples.len() as u64;
        let candidates = [(); CANDIDATES].map(|_| below(rng, n) as usize);
        for &i in &candidates {
            prefetch(&chunk.samples[i]);
            prefetch(&chunk.records[i]);
        }
        Some(PendingDraw { chunk: c, candidates })
    }

    /// The vertex of a draw begun by [`LightCache::begin_draw`] on this cache: the first of its
    /// candidates that is not an emission vertex, or else further uniform candidates in the same
    /// chunk until one is not (rejection sampling, whose candidates are independent and uniform
    /// however many of them were drawn ahead: the vertex is uniform over the chunk's drawable
    /// ones, and so over all |Y|).
    #[inline]
    pub fn finish_draw(&self, p: PendingDraw, rng: &mut RandomStream) -> CachedVertex<'a> {
        let chunk = &self.chunks[p.chunk];
        let vertex = |i: usize| CachedVertex {
            light: chunk.light,
            sample: &chunk.samples[i],
            record: chunk.records[i],
        };
        if let Some(&i) = p.candidates.iter().find(|&&i| !chunk.samples[i].is_emission()) {
            return vertex(i);
        }
        let n = chunk.samples.len() as u64;
        loop {
            let i = below(rng, n) as usize;
            if !chunk.samples[i].is_emission() {
                return vertex(i);
            }
        }
    }
}

/// A connection set: vertices drawn uniformly from the cache, copied into one compact array
/// small enough to stay in the CPU's L2 cache ([`LightCache::fill_set`]); a band of camera
/// paths then connects to vertices drawn uniformly from the set instead of the whole cache
/// (`docs/bidirectional.md` §11).
///
/// Why it is unbiased: the set's entries are independent uniform draws from the |Y| drawable
/// vertices, and a draw from the set picks one of them uniformly, so each connection's vertex
/// is, marginally, uniform over |Y| — the same distribution as a draw from the cache, so the
/// |Y|/n_c weight and the MIS weights are unchanged. What it changes is the correlation between
/// the connections of one band (they share the set's vertices), traded for reading memory once
/// per entry, in a pipelined loop, instead of once per connection at the far end of a random
/// DRAM access.
#[derive(Clone, Debug, Default)]
pub struct ConnectionSet {
    entries: Vec<SetEntry>,
}

/// One vertex of a [`ConnectionSet`]: its sample, record and light, held by value.
#[derive(Clone, Copy, Debug)]
struct SetEntry {
    sample: Sample,
    record: MisRecord,
    light: u32,
}

impl ConnectionSet {
    /// An empty set with room for `n` vertices.
    pub fn with_capacity(n: usize) -> Self {
        ConnectionSet { entries: Vec::with_capacity(n) }
    }

    /// Vertices in the set.
    pub fn len(&self) -> usize {
        self.entries.len()
    }

    /// Whether the set has no vertex (the cache had none to give).
    pub fn is_empty(&self) -> bool {
        self.entries.is_empty()
    }

    /// A vertex drawn uniformly from the set; `None` if it is empty.
    #[inline]
    pub fn draw(&self, rng: &mut RandomStream) -> Option<CachedVertex<'_>> {
        if self.entries.is_empty() {
            return None;
        }
        let e = &self.entries[below(rng, self.entries.len() as u64) as usize];
        Some(CachedVertex { light: e.light, sample: &e.sample, record: e.record })
    }
}

/// Draws a [`LightCache::fill_set`] keeps in flight: each is begun (its memory read started)
/// this many draws before it is read.
const SET_AHEAD: usize = 8;

impl LightCache<'_> {
    /// Replaces the contents of `set` by `n` vertices drawn independently and uniformly from
    /// the cache (none if the cache has nothing to draw). The draws are pipelined: each read
    /// is started eight draws before it is used, so that the memory reads overlap.
    pub fn fill_set(&self, set: &mut ConnectionSet, n: usize, rng: &mut RandomStream) {
        set.entries.clear();
        let mut ring = [None; SET_AHEAD];
        for slot in ring.iter_mut().take(n) {
            *slot = self.begin_draw(rng);
        }
        for k in 0..n {
            let Some(pending) = ring[k % SET_AHEAD].take() else { return };
            if k + SET_AHEAD < n {
                ring[k % SET_AHEAD] = self.begin_draw(rng);
            }
            let v = self.finish_draw(pending, rng);
            set.entries.push(SetEntry { sample: *v.sample, record: v.record, light: v.light });
        }
    }
}

/// Candidate indices a [`PendingDraw`] draws ahead: with a fraction e of emission vertices in a
/// chunk (a quarter in a closed room), a draw must still read memory synchronously with
/// probability e^CANDIDATES.
pub const CANDIDATES: usize = 2;

/// A draw from the cache begun ahead of its use ([`LightCache::begin_draw`]): its chunk and
/// candidate samples, already on their way into the CPU cache.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct PendingDraw {
    chunk: usize,
    candidates: [usize; CANDIDATES],
}

/// A uniform integer in [0, n) (n > 0), by the multiply-high map of 64 random bits (its bias,
/// below n/2⁶⁴, is far beneath any other rounding).
#[inline]
fn below(rng: &mut RandomStream, n: u64) -> u64 {
    ((rng.next_u64() as u128 * n as u128) >> 64) as u64
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::{Rgb, Vec3};

    fn chunk(light: u32, emission: &[bool]) -> Chunk {
        let samples = emission
            .iter()
            .enumerate()
            .map(|(i, &e)| {
                let p = Vec3::new(light as f32, i as f32, 0.0);
                if e { Sample::emitted(p, 0) } else { Sample::scattered(p, Vec3::Y, 0, Rgb::ONE) }
            })
            .collect();
        let records = vec![MisRecord::default(); emission.len()];
        Chunk { light, paths: emission.iter().filter(|e| **e).count() as u64, samples, records }
    }

    /// Every drawable vertex is drawn with probability 1/|Y|, none of a light that is off, no
    /// emission vertex, chunks without drawable vertices never.
    #[test]
    fn draws_are_uniform_over_the_non_emission_vertices_of_lights_on() {
        let chunks = vec![
            chunk(0, &[true, false, false, true, false]),
            chunk(1, &[true, false, true, false, false, false]),
            chunk(0, &[true, true]),
            chunk(2, &[false, false, false]),
            chunk(0, &[false]),
        ];
        let cache = LightCache::from_chunks(&chunks, 3, &[true, false, true]).unwrap();
        assert_eq!(cache.vertices(), 3 + 3 + 1);
        assert_eq!(cache.paths(), &[2 + 2, 2, 0]);
        let mut rng = RandomStream::new(1, &[]);
        let mut counts = std::collections::HashMap::new();
        let n = 140_000;
        for _ in 0..n {
            let v = cache.draw(&mut rng).unwrap();
            assert!(!v.sample.is_emission() && v.light != 1);
            *counts.entry(v.sample.position.map(f32::to_bits)).or_insert(0u32) += 1;
        }
        assert_eq!(counts.len(), 7);
        for c in counts.values() {
            let expected = n as f64 / 7.0;
            assert!((*c as f64 - expected).abs() < 5.0 * expected.sqrt(), "{c} vs {expected}");
        }
        let mut bare = chunks.clone();
        bare.iter_mut().for_each(|c| c.records.clear());
        let bare = LightCache::from_chunks(&bare, 3, &[true, true, true]).unwrap();
        assert!(!bare.has_records() && bare.draw(&mut rng).is_none());
        let mut short = chunks[..1].to_vec();
        short[0].records.truncate(2);
        assert!(LightCache::from_chunks(&short, 3, &[true; 3]).is_err());
    }

    /// A vertex drawn through connection sets (each filled afresh, as a band does) is drawn with
    /// the cache's own probability 1/|Y|: the set keeps every vertex's marginal probability.
    #[test]
    fn draws_through_a_connection_set_keep_the_marginal_probability() {
        let chunks = vec![
            chunk(0, &[true, false, false, true, false]),
            chunk(1, &[true, false, true, false, false, false]),
            chunk(0, &[false]),
        ];
        let cache = LightCache::from_chunks(&chunks, 2, &[true, true]).unwrap();
        let drawable = cache.vertices() as f64;
        let mut rng = RandomStream::new(3, &[]);
        let mut set = ConnectionSet::with_capacity(4);
        let mut counts = std::collections::HashMap::new();
        let (sets, per_set) = (20_000, 8);
        for _ in 0..sets {
            cache.fill_set(&mut set, 4, &mut rng);
            assert_eq!(set.len(), 4);
            for _ in 0..per_set {
                let v = set.draw(&mut rng).unwrap();
                assert!(!v.sample.is_emission());
                *counts.entry((v.light, v.sample.position.map(f32::to_bits))).or_insert(0u32) += 1;
            }
        }
        assert_eq!(counts.len() as f64, drawable);
        // The draws of one set are correlated: the bound is on the sets' independent means.
        let n = (sets * per_set) as f64;
        for c in counts.values() {
            let expected = n / drawable;
            let sd = (expected * per_set as f64).sqrt();
            assert!((*c as f64 - expected).abs() < 5.0 * sd, "{c} vs {expected}");
        }
        let empty = LightCache::from_chunks(&chunks, 2, &[false, false]).unwrap();
        empty.fill_set(&mut set, 4, &mut rng);
        assert!(set.is_empty() && set.draw(&mut rng).is_none());
    }
}
