//! The last resting solve's loads, by the pair's body ids, for the next solve's warm start: a
//! table of open addressing, filled once a step and asked for each resting contact (and
//! whether a touching pair took a load in the last step).
//! (It was a list sorted by the ids and searched by halves: on a table of 10 000 spheres
//! resting on a floor, the sort and the searches took a tenth of the step.)

use crate::BodyId;

/// Loads by body-id pair (smaller id first). Its answers depend only on what was put in, never
/// on where in the table it went.
#[derive(Debug, Default)]
pub(super) struct WarmLoads {
    /// Each slot's pair and load, valid where its stamp is the table's (so emptying the table
    /// writes nothing but the stamp).
    slots: Vec<Slot>,
    /// The number of slots less one (a power of two less one).
    mask: usize,
    stamp: u32,
    len: usize,
}

#[derive(Clone, Copy, Debug, Default)]
struct Slot {
    key: (u64, u64),
    load: f64,
    stamp: u32,
}

impl WarmLoads {
    /// Empties the table and readies it for up to `count` loads, keeping its memory.
    pub(super) fn start(&mut self, count: usize) {
        self.len = 0;
        // At most half full, so a search ends within a few slots; kept as large unless it
        // is more than four times what is needed (a count about a power of two would
        // otherwise refill the table step after step).
        let slots = (2 * count).next_power_of_two().max(8);
        self.stamp = self.stamp.wrapping_add(1);
        if self.stamp == 0 || slots > self.slots.len() || 4 * slots < self.slots.len() {
            self.slots.clear();
            self.slots.resize(slots, Slot::default());
            self.stamp = 1;
        }
        self.mask = self.slots.len() - 1;
    }

    /// Whether no load is kept.
    pub(super) fn is_empty(&self) -> bool {
        self.len == 0
    }

    /// Forgets every load, keeping the table's size.
    pub(super) fn clear(&mut self) {
        self.len = 0;
        self.stamp = self.stamp.wrapping_add(1);
        if self.stamp == 0 {
            self.slots.fill(Slot::default());
            self.stamp = 1;
        }
    }

    /// Keeps `load` for the pair `(a, b)` (`a < b`), which has none yet (a resting contact is
    /// listed once). The table must have been started for at least this many loads.
    pub(super) fn insert(&mut self, a: BodyId, b: BodyId, load: f64) {
        debug_assert!(a < b, "warm pair ({a:?}, {b:?}) not in order");
        debug_assert!(
            2 * (self.len + 1) <= self.slots.len(),
            "warm table too full"
        );
        let key = (a.0, b.0);
        let mut at = self.slot_of(key);
        while self.slots[at].stamp == self.stamp {
            debug_assert!(
                self.slots[at].key != key,
                "warm pair ({a:?}, {b:?}) kept twice"
            );
            at = (at + 1) & self.mask;
        }
        self.slots[at] = Slot {
            key,
            load,
            stamp: self.stamp,
        };
        self.len += 1;
    }

    /// The load kept for the pair `(a, b)` (`a < b`), if any.
    #[inline]
    pub(super) fn get(&self, a: BodyId, b: BodyId) -> Option<f64> {
        if self.len == 0 {
            return None;
        }
        let key = (a.0, b.0);
        let mut at = self.slot_of(key);
        loop {
            let slot = &self.slots[at];
            if slot.stamp != self.stamp {
                return None;
            }
            if slot.key == key {
                return Some(slot.load);
            }
            at = (at + 1) & self.mask;
        }
    }

    /// Asks for the slot where the pair `(a, b)` (`a < b`) is first looked for.
    #[inline]
    pub(super) fn prefetch(&self, a: BodyId, b: BodyId) {
        if let Some(slot) = self.slots.get(self.slot_of((a.0, b.0))) {
            super::prefetch(slot);
        }
    }

    /// The first slot to look in for `key`: the ids mixed (a multiply and a shift, as Fx-style
    /// hashes do), so that neighbouring ids spread over the table.
    #[inline]
    fn slot_of(&self, (a, b): (u64, u64)) -> usize {
        let mixed = (a.wrapping_mul(0x9e37_79b9_7f4a_7c15) ^ b).wrapping_mul(0xff51_afd7_ed55_8ccd);
        (mixed >> 32) as usize & self.mask
    }
}
