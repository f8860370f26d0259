//! The step's event queue: a calendar of time buckets over `[0, dt]`, each bucket a small
//! binary heap once it is reached. Pops come in exactly the order a single binary heap would
//! give (the items' own order; bucket boundaries follow time, which leads that order), but each
//! pop works on a heap of the few events near the current time instead of all of them.

use std::cmp::Reverse;
use std::collections::BinaryHeap;

/// An item with a time in `[0, span]`, first in its order.
pub(crate) trait Timed: Ord + Copy {
    fn time(&self) -> f64;
}

/// No item (end of a bucket's list).
const NONE: u32 = u32::MAX;

#[derive(Debug)]
pub(crate) struct EventQueue<T: Timed> {
    /// Items pushed beyond the current bucket, in push order; each bucket's items form a list
    /// through `next`, starting at `heads[bucket]`. One array for all buckets, so its capacity
    /// settles after a few steps and pushing allocates nothing.
    items: Vec<T>,
    next: Vec<u32>,
    heads: Vec<u32>,
    /// The current bucket's items (and any pushed into it), ordered.
    current: BinaryHeap<Reverse<T>>,
    /// The current bucket.
    at: usize,
    /// Buckets in use.
    count: usize,
    /// Buckets per unit of time.
    scale: f64,
    /// Items waiting in later buckets.
    waiting: usize,
}

impl<T: Timed> Default for EventQueue<T> {
    fn default() -> Self {
        Self {
            items: Vec::new(),
            next: Vec::new(),
            heads: Vec::new(),
            current: BinaryHeap::new(),
            at: 0,
            count: 0,
            scale: 0.0,
            waiting: 0,
        }
    }
}

impl<T: Timed> EventQueue<T> {
    /// Empties the queue for items in `[0, span]`, with about one bucket per `per_bucket`
    /// expected items (`expected` in all). Keeps its buffers.
    pub fn reset(&mut self, span: f64, expected: usize, per_bucket: usize) {
        let count = (expected / per_bucket.max(1)).clamp(1, 1 << 16);
        self.items.clear();
        self.next.clear();
        self.heads.clear();
        self.heads.resize(count, NONE);
        self.count = count;
        self.current.clear();
        self.at = 0;
        self.scale = if span > 0.0 { count as f64 / span } else { 0.0 };
        self.waiting = 0;
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
        let b = self.bucket(item.time());
        if b <= self.at {
            self.current.push(Reverse(item));
        } else {
            self.next.push(self.heads[b]);
            self.heads[b] = self.items.len() as u32;
            self.items.push(item);
            self.waiting += 1;
        }
    }

    /// Makes `current` hold the earliest items, moving on to later buckets as needed.
    fn fill(&mut self) {
        while self.current.is_empty() && self.waiting > 0 {
            self.at += 1;
            let mut i = self.heads[self.at];
            while i != NONE {
                self.current.push(Reverse(self.items[i as usize]));
                self.waiting -= 1;
                i = self.next[i as usize];
            }
        }
    }

    pub fn peek(&mut self) -> Option<T> {
        self.fill();
        self.current.peek().map(|r| r.0)
    }

    pub fn pop(&mut self) -> Option<T> {
        self.fill();
        self.current.pop().map(|r| r.0)
    }
}
