//! A pass traced out of order, by many hands: [`PassDispatch`] hands the plan's blocks out in
//! [`super::block_order`], takes their chunks back in any order, and gives them up strictly in
//! block order, counting the paths per plan entry — so whoever traced which block, the dataset
//! written is the one a single process writes. Blocks whose tracer is lost are handed out
//! again; a chunk that comes back twice (a late answer) is kept once. Stopping leaves a prefix
//! of whole blocks, which `resume_plan` completes.
//!
//! This is the law the cluster build's master (`opticks` with `--features mpi`) carries out
//! over MPI; it is plain data here, so it is tested without any transport.

use super::{Block, BlockOrder, Chunk, PassPlan, block_order};
use std::collections::{BTreeMap, HashMap, VecDeque};

/// A block handed out, numbered by its place in the pass's block order.
pub type NumberedBlock = (u64, Block);

/// The bookkeeping of one pass traced by several tracers; `T` is the caller's ticket for a
/// handed-out block (who has it, since when).
pub struct PassDispatch<'p, T> {
    pass: &'p PassPlan,
    /// The blocks not handed out yet, numbered (made lazily, as they are handed out).
    order: std::iter::Skip<std::iter::Enumerate<BlockOrder<'p>>>,
    /// Blocks to hand out again (their tracer was lost), before new ones.
    again: VecDeque<NumberedBlock>,
    /// Blocks handed out and not returned.
    out: HashMap<u64, (Block, T)>,
    /// Chunks returned ahead of the next one in order.
    done: BTreeMap<u64, Chunk>,
    /// The next block number to give up.
    next: u64,
    exhausted: bool,
    stopped: bool,
    traced: Vec<u64>,
}

impl<'p, T> PassDispatch<'p, T> {
    /// The dispatch of `pass`, from its first block not traced yet.
    pub fn new(pass: &'p PassPlan) -> Self {
        PassDispatch {
            pass,
            order: block_order(&pass.lights).enumerate().skip(pass.first_block),
            again: VecDeque::new(),
            out: HashMap::new(),
            done: BTreeMap::new(),
            next: pass.first_block as u64,
            exhausted: false,
            stopped: false,
            traced: vec![0; pass.lights.len()],
        }
    }

    /// Up to `n` blocks to trace (blocks to redo first), each recorded with `ticket`; none once
    /// stopped or when every block is out.
    pub fn hand_out(&mut self, n: usize, ticket: impl Fn() -> T) -> Vec<NumberedBlock> {
        let mut blocks = Vec::with_capacity(n.min(1024));
        while blocks.len() < n && !self.stopped {
            let next = match self.again.pop_front() {
                Some(b) => b,
                None => match self.order.next() {
                    Some((seq, b)) => (seq as u64, b),
                    None => {
                        self.exhausted = true;
                        break;
                    }
                },
            };
            self.out.insert(next.0, (next.1, ticket()));
            blocks.push(next);
        }
        blocks
    }

    /// Block `seq`'s chunk, from whoever traced it (a chunk already taken back is dropped).
    pub fn accept(&mut self, seq: u64, chunk: Chunk) {
        self.out.remove(&seq);
        if seq >= self.next {
            self.done.entry(seq).or_insert(chunk);
        }
    }

    /// The next chunk in block order, if it is back; its paths are counted as traced.
    pub fn next_in_order(&mut self) -> Option<Chunk> {
        let chunk = self.done.remove(&self.next)?;
        self.next += 1;
        if let Some(i) = self.pass.lights.iter().position(|p| p.table_index == chunk.light) {
            self.traced[i] += chunk.paths;
        }
        Some(chunk)
    }

    /// The tickets of the blocks out.
    pub fn tickets(&self) -> impl Iterator<Item = &T> {
        self.out.values().map(|(_, t)| t)
    }

    /// Takes back every block out whose ticket `lost` says its tracer is lost: they are handed
    /// out again (unless stopped). Returns how many.
    pub fn reclaim(&mut self, lost: impl Fn(&T) -> bool) -> usize {
        let seqs: Vec<u64> = self.out.iter().filter(|(_, (_, t))| lost(t)).map(|(&s, _)| s).collect();
        for &seq in &seqs {
            let (block, _) = self.out.remove(&seq).expect("listed");
            if !self.stopped {
                self.again.push_back((seq, block));
            }
        }
        self.again.make_contiguous().sort_by_key(|b| b.0);
        seqs.len()
    }

    /// Hands out nothing more: the pass ends with the blocks out when they are back.
    pub fn stop(&mut self) {
        self.stopped = true;
        self.again.clear();
    }

    /// Whether blocks are out.
    pub fn outstanding(&self) -> bool {
        !self.out.is_empty()
    }

    /// Whether nothing is left to hand out or wait for (every chunk back may still have to be
    /// taken with [`Self::next_in_order`]).
    pub fn is_over(&self) -> bool {
        (self.stopped || (self.exhausted && self.again.is_empty())) && self.out.is_empty()
    }

    /// Paths given up so far, per plan entry (what `DatasetHeader::record_traced` books).
    pub fn traced(&self) -> &[u64] {
        &self.traced
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::dataset::{BLOCK_PATHS, LightPlan, TraceSettings};

    fn pass(first_block: usize) -> PassPlan {
        PassPlan {
            settings: TraceSettings::default(),
            lights: vec![
                LightPlan { scene_light: 0, table_index: 0, paths: 5 * BLOCK_PATHS },
                LightPlan { scene_light: 1, table_index: 1, paths: 2 * BLOCK_PATHS + 9 },
            ],
            first_block,
        }
    }

    fn chunk(b: &Block) -> Chunk {
        Chunk { light: b.light.table_index, paths: b.paths, samples: vec![], records: vec![] }
    }

    #[test]
    fn chunks_returned_in_any_order_come_out_in_block_order_with_lost_blocks_redone() {
        let p = pass(0);
        let order: Vec<Block> = block_order(&p.lights).collect();
        let mut d = PassDispatch::new(&p);
        let a = d.hand_out(3, || "a");
        let b = d.hand_out(2, || "b");
        assert_eq!(a.iter().chain(&b).map(|x| x.0).collect::<Vec<_>>(), [0, 1, 2, 3, 4]);
        // b answers first and out of order; a is lost.
        d.accept(b[1].0, chunk(&b[1].1));
        d.accept(b[0].0, chunk(&b[0].1));
        assert!(d.next_in_order().is_none(), "block 0 is not back");
        assert_eq!(d.reclaim(|t| *t == "a"), 3);
        let redo = d.hand_out(10, || "b");
        assert_eq!(redo.iter().map(|x| x.0).take(4).collect::<Vec<_>>(), [0, 1, 2, 5], "lost blocks first");
        for (seq, block) in &redo {
            d.accept(*seq, chunk(block));
        }
        d.accept(a[0].0, chunk(&a[0].1)); // a late answer is dropped
        let mut out = Vec::new();
        while let Some(c) = d.next_in_order() {
            out.push(c);
        }
        assert!(d.is_over());
        assert_eq!(out, order.iter().map(chunk).collect::<Vec<_>>());
        assert_eq!(d.traced(), [5 * BLOCK_PATHS, 2 * BLOCK_PATHS + 9]);
    }

    #[test]
    fn a_stopped_pass_gives_up_a_prefix_and_a_resumed_one_starts_after_it() {
        let p = pass(0);
        let mut d = PassDispatch::new(&p);
        let blocks = d.hand_out(4, || ());
        d.stop();
        assert!(d.hand_out(4, || ()).is_empty() && !d.is_over());
        for (seq, b) in blocks.iter().rev() {
            d.accept(*seq, chunk(b));
        }
        assert!(d.is_over());
        assert_eq!(std::iter::from_fn(|| d.next_in_order()).count(), 4);
        let resumed = pass(4);
        let mut r = PassDispatch::<()>::new(&resumed);
        assert_eq!(
            r.hand_out(100, || ()).iter().map(|b| b.0).collect::<Vec<_>>(),
            [4, 5, 6, 7],
            "8 blocks: 5 + 3"
        );
    }
}
