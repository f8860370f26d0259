//! The step's event queue: a calendar of time buckets over `[0, dt]`, each bucket sorted once
//! it is reached. Pops come in exactly the order a single priority queue would give (the
//! items' own order; bucket boundaries follow time, which leads that order), but each pop
//! works on the few events near the current time instead of all of them.

use std::cmp::Reverse;
use std::collections::BinaryHeap;

/// An item with a time in `[0, span]`, first in its order.
pub(crate) trait Timed: Ord + Copy {
    fn time(&self) -> f64;
}

/// No chunk (end of a bucket's list).
const NONE: u32 = u32::MAX;

/// How many items the current bucket holds before further pushes into it go to a heap.
const CROWD: usize = 32;

/// At most this many buckets, however many items are expected: a push writes into its
/// bucket's newest chunk, and with a bucket per four of the 100k shower's spheres (25 000
/// buckets, their newest chunks 3 MB) nearly every push missed the core's caches. With 2048
/// (their heads 16 KB, their newest chunks 256 KB) a bucket holds more items to sort once it
/// is reached, and the 100k shower and gas stepped 0.88x to 0.95x the time (1024 and 4096
/// buckets: no better); 1k and 10k, with fewer buckets than this anyway, within 1%.
const MOST_BUCKETS: usize = 1 << 11;

/// Items per chunk: a chunk of the solver's 24-byte events fills two cache lines.
const CHUNK: usize = 5;

/// A few items of one bucket, stored together so that emptying a bucket reads a line or two
/// per chunk instead of one scattered item at a time.
#[derive(Clone, Copy, Debug)]
#[repr(align(64))]
struct Chunk<T> {
    items: [T; CHUNK],
    /// The bucket's previous (older, full) chunk.
    next: u32,
}

#[derive(Debug)]
pub(crate) struct EventQueue<T: Timed> {
    /// Items pushed beyond the current bucket, in chunks; each bucket's chunks form a list
    /// through `next`, newest first, starting at `heads[bucket]`. One array for all buckets,
    /// so its capacity settles after a few steps and pushing allocates nothing.
    chunks: Vec<Chunk<T>>,
    /// Each bucket's newest chunk and how many items it holds (older chunks are full).
    heads: Vec<(u32, u32)>,
    /// The current bucket's items (and any pushed into it while it holds few), latest first:
    /// a pop takes the last. A bucket holds a few items (four expected), so sorting them and
    /// inserting in place beats a heap.
    current: Vec<T>,
    /// Items pushed into the current bucket while it holds many (a crowd of events within a
    /// bucket's width of time): a heap, so that such a crowd costs O(log n) a push, not the
    /// O(n) of an insertion. Pops take the earlier of its first and `current`'s last.
    spill: BinaryHeap<Reverse<T>>,
    /// The current bucket.
    at: usize,
    /// Buckets in use.
    count: usize,
    /// Buckets per unit of time.
    scale: f64,
    /// Items waiting in later buckets.
    waiting: usize,
    /// Items pushed since the last reset.
    pushed: usize,
}

impl<T: Timed> Default for EventQueue<T> {
    fn default() -> Self {
        Self {
            chunks: Vec::new(),
            heads: Vec::new(),
            current: Vec::new(),
            spill: BinaryHeap::new(),
            at: 0,
            count: 0,
            scale: 0.0,
            waiting: 0,
            pushed: 0,
        }
    }
}

impl<T: Timed> EventQueue<T> {
    /// Empties the queue for items in `[0, span]`, with about one bucket per `per_bucket`
    /// expected items (`expected` in all). Keeps its buffers.
    pub fn reset(&mut self, span: f64, expected: usize, per_bucket: usize) {
        let count = (expected / per_bucket.max(1)).clamp(1, MOST_BUCKETS);
        self.chunks.clear();
        self.heads.clear();
        // Room for the most buckets' heads once, so that a step expecting more events than
        // the last does not grow them (its chunks grow with its pushes, as they always did).
        self.heads.reserve(MOST_BUCKETS);
        self.heads.resize(count, (NONE, 0));
        self.count = count;
        self.current.clear();
        self.spill.clear();
        self.at = 0;
        self.scale = if span > 0.0 { count as f64 / span } else { 0.0 };
        self.waiting = 0;
        self.pushed = 0;
    }

    /// How many items were pushed since the last reset.
    pub fn pushed(&self) -> usize {
        self.pushed
    }

    fn bucket(&self, time: f64) -> usize {
        let b = time * self.scale;
        if b >= 0.0 {
            (b as usize).min(self.count - 1)
        } else {
            0
        }
    }

    pub fn push(&mut self, item: T) {
        if self.count == 0 {
            self.reset(0.0, 1, 1);
        }
        self.pushed += 1;
        let b = self.bucket(item.time());
        if b <= self.at {
            if self.current.len() >= CROWD {
                self.spill.push(Reverse(item));
            } else {
                // After every later item, before every earlier one.
                let at = self.current.partition_point(|queued| *queued > item);
                self.current.insert(at, item);
            }
            return;
        }
        let (head, len) = self.heads[b];
        if head != NONE && (len as usize) < CHUNK {
            self.chunks[head as usize].items[len as usize] = item;
            self.heads[b].1 += 1;
        } else {
            self.heads[b] = (self.chunks.len() as u32, 1);
            self.chunks.push(Chunk {
                items: [item; CHUNK],
                next: head,
            });
        }
        self.waiting += 1;
    }

    /// Makes `current` hold the earliest items, moving on to later buckets as needed: a check
    /// inlined into every pop and peek, and the work, when there is some, out of line.
    #[inline(always)]
    fn fill(&mut self) {
        if self.current.is_empty() && self.spill.is_empty() && self.waiting > 0 {
            self.refill();
        }
    }

    #[inline(never)]
    fn refill(&mut self) {
        while self.current.is_empty() && self.spill.is_empty() && self.waiting > 0 {
            self.at += 1;
            // The next bucket's newest chunk will be read soon: ask for it now.
            if let Some(&(ahead, _)) = self.heads.get(self.at + 1)
                && ahead != NONE
            {
                crate::solver::prefetch(&self.chunks[ahead as usize]);
            }
            let (mut c, mut len) = self.heads[self.at];
            while c != NONE {
                let chunk = &self.chunks[c as usize];
                self.current.extend_from_slice(&chunk.items[..len as usize]);
                self.waiting -= len as usize;
                (c, len) = (chunk.next, CHUNK as u32);
            }
            // Latest first (items equal in order are the same event twice: either may go
            // first).
            self.current.sort_unstable_by(|x, y| y.cmp(x));
        }
    }

    #[inline]
    pub fn peek(&mut self) -> Option<T> {
        self.fill();
        if self.spill.is_empty() {
            return self.current.last().copied();
        }
        self.peek_crowded()
    }

    #[inline]
    pub fn pop(&mut self) -> Option<T> {
        self.fill();
        if self.spill.is_empty() {
            return self.current.pop();
        }
        self.pop_crowded()
    }

    /// [`EventQueue::peek`] with items in the heap: kept out of line, so that the usual path
    /// stays small enough to inline into the event loop.
    #[cold]
    #[inline(never)]
    fn peek_crowded(&self) -> Option<T> {
        match (self.current.last(), self.spill.peek()) {
            (Some(&last), Some(Reverse(first))) => Some(last.min(*first)),
            (last, first) => last.copied().or(first.map(|r| r.0)),
        }
    }

    /// [`EventQueue::pop`] with items in the heap (see [`EventQueue::peek_crowded`]).
    #[cold]
    #[inline(never)]
    fn pop_crowded(&mut self) -> Option<T> {
        match (self.current.last(), self.spill.peek()) {
            (Some(last), Some(Reverse(first))) if first < last => self.spill.pop().map(|r| r.0),
            (Some(_), _) => self.current.pop(),
            (None, _) => self.spill.pop().map(|r| r.0),
        }
    }
}
