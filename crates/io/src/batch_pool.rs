//! Batches read from a dataset file into recycled buffers.
//!
//! A render reads the dataset chunk by chunk (a few hundred per million paths, ~10⁴ samples
//! each). Read into a fresh `Vec<Sample>` each, every chunk's buffer was zero-filled before the
//! read overwrote it: `calloc` hands back freed heap memory, which it must clear — 6 % of the
//! instructions of a Cornell light-estimator frame (callgrind). A [`BatchPool`] keeps the
//! buffers of batches that are done and hands them to the next reads instead, so a buffer is
//! written only by the read (and, where a chunk is longer than the buffer was, its tail once).

use opticks_core::dataset::Sample;
use opticks_core::math::Rgb;
use opticks_core::sensor::{AsBatch, SampleBatch};
use std::sync::Mutex;

/// Buffers kept at most: more than the batches a render holds at once on any machine.
const KEPT: usize = 256;

/// Spare sample buffers, shared by the threads reading batches.
#[derive(Debug, Default)]
pub struct BatchPool {
    spare: Mutex<Vec<Vec<Sample>>>,
}

impl BatchPool {
    /// A buffer to read into: a spare one (its old samples still in it), or a new empty one.
    pub fn take(&self) -> Vec<Sample> {
        self.spare.lock().map(|mut s| s.pop()).ok().flatten().unwrap_or_default()
    }

    /// A batch of `samples` that gives its buffer back to this pool when dropped.
    pub fn batch(&self, flux_per_path: Rgb, samples: Vec<Sample>) -> PooledBatch<'_> {
        PooledBatch { flux_per_path, samples, pool: self }
    }

    fn give_back(&self, samples: Vec<Sample>) {
        if let Ok(mut spare) = self.spare.lock()
            && spare.len() < KEPT
        {
            spare.push(samples);
        }
    }
}

/// A batch whose samples were read into a [`BatchPool`]'s buffer.
#[derive(Debug)]
pub struct PooledBatch<'a> {
    flux_per_path: Rgb,
    samples: Vec<Sample>,
    pool: &'a BatchPool,
}

impl AsBatch for PooledBatch<'_> {
    #[inline]
    fn as_batch(&self) -> SampleBatch<'_> {
        SampleBatch { flux_per_path: self.flux_per_path, samples: &self.samples }
    }
}

impl Drop for PooledBatch<'_> {
    fn drop(&mut self) {
        self.pool.give_back(std::mem::take(&mut self.samples));
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A dropped batch's buffer is the next one taken, its memory reused; the pool keeps no
    /// more than [`KEPT`].
    #[test]
    fn a_dropped_batchs_buffer_is_reused() {
        let pool = BatchPool::default();
        let mut v = pool.take();
        v.resize(1000, Sample::default());
        let at = v.as_ptr();
        let b = pool.batch(Rgb::ONE, v);
        assert_eq!(b.as_batch().samples.len(), 1000);
        drop(b);
        let again = pool.take();
        assert_eq!((again.as_ptr(), again.capacity() >= 1000), (at, true));
        assert!(pool.take().is_empty());
        let live: Vec<PooledBatch> =
            (0..KEPT + 10).map(|_| pool.batch(Rgb::ONE, vec![Sample::default()])).collect();
        drop(live);
        assert_eq!(pool.spare.lock().unwrap().len(), KEPT);
    }
}
