//! Long runs of empty cells squeezed out of the grid's block, one axis at a time: groups of
//! spheres far apart along an axis share one block without the empty space between them.
//!
//! An axis of the block is cut into chunks of `2^k` cells (one cell each where that makes no
//! more chunks than about twice the bodies). A chunk is kept if a grid body's
//! cell is in it or in a chunk next to it; the others are squeezed out, and every cell of a run
//! of them takes the place of the first cell of the next kept chunk. The map never decreases,
//! so the cells of a range keep every occupied cell between its ends; an occupied cell's
//! neighbours (in its chunk or the kept ones beside it) stay its neighbours; and the cell a
//! squeezed run lands on is empty (the chunk before it was squeezed out, so no chunk beside it
//! is occupied). The grid's rows of three cells and its empty border hold as before.

/// The top bit of a chunk's place: the chunk is squeezed out.
const OUT: u32 = 1 << 31;

/// How one axis of the grid's block places a cell (see the module docs).
#[derive(Clone, Debug, Default)]
pub(crate) struct Squeeze {
    /// The absolute coordinates of the block's first and last cells on this axis.
    first: i32,
    last: i32,
    /// Whether chunks are squeezed out (else a cell's place is its offset from `first`).
    squeezed: bool,
    /// The chunks' size, `2^bits` cells.
    bits: u32,
    /// Each chunk's first cell's place, [`OUT`] set for a chunk squeezed out.
    places: Vec<u32>,
    /// The block's cells along this axis.
    len: usize,
}

impl Squeeze {
    /// The block's cells `first..=last`, each in its own place.
    pub fn plain(&mut self, first: i32, last: i32) {
        self.first = first;
        self.last = last;
        self.squeezed = false;
        self.len = (i64::from(last) - i64::from(first) + 1) as usize;
    }

    /// The block's cells `first..=last`, with the chunks no cell of `occupied` is in or beside
    /// squeezed out (`occupied` within `first + 1 ..= last - 1`); chunks of one cell, or as
    /// many as keep them to about `2 · bodies`. Returns the cells left (`usize::MAX`, and no
    /// squeeze, past two billion).
    pub fn squeeze(
        &mut self,
        first: i32,
        last: i32,
        occupied: impl Iterator<Item = i32>,
        bodies: usize,
    ) -> usize {
        let span = (i64::from(last) - i64::from(first) + 1) as u64;
        let mut bits = 0;
        while span >> bits > 2 * bodies as u64 + 2 {
            bits += 1;
        }
        let chunks = (span >> bits) as usize + 1;
        self.places.clear();
        self.places.resize(chunks, 0);
        // Marks: 1 for an occupied chunk.
        for v in occupied {
            // (The offset in `u32`: a squeezed axis may span more than `i32` holds.)
            self.places[(v.wrapping_sub(first) as u32 >> bits) as usize] = 1;
        }
        // Kept: occupied or beside one (marked 2), then each chunk's place.
        for c in 0..chunks {
            if self.places[c] == 1 {
                if c > 0 && self.places[c - 1] == 0 {
                    self.places[c - 1] = 2;
                }
                if c + 1 < chunks && self.places[c + 1] == 0 {
                    self.places[c + 1] = 2;
                }
            }
        }
        let mut place = 0u64;
        for c in 0..chunks {
            if place >= u64::from(OUT) {
                // More places than the table can mark (billions of cells kept): no squeeze
                // helps a block that large.
                self.squeezed = false;
                return usize::MAX;
            }
            let at = place as u32;
            if self.places[c] == 0 {
                self.places[c] = OUT | at;
            } else {
                self.places[c] = at;
                place += 1 << bits;
            }
        }
        self.first = first;
        self.last = last;
        self.squeezed = place < u64::from(OUT);
        self.bits = bits;
        self.len = if self.squeezed {
            place as usize
        } else {
            usize::MAX
        };
        self.len
    }

    /// Room for the most chunks a squeeze of `bodies` bodies' cells may need (called every
    /// step before the block is chosen, so that a scene that spreads out allocates nothing
    /// after its first steps). Forgets the chunks' places.
    pub fn reserve(&mut self, bodies: usize) {
        self.places.clear();
        self.places.reserve(2 * bodies + 4);
    }

    /// The absolute coordinates of the block's first and last cells on this axis.
    pub fn ends(&self) -> (i32, i32) {
        (self.first, self.last)
    }

    /// Whether chunks of this axis are squeezed out.
    pub fn squeezed(&self) -> bool {
        self.squeezed
    }

    /// The block's cells along this axis.
    pub fn len(&self) -> usize {
        self.len
    }

    /// Cell `v`'s place along this axis (`v` within the block's ends).
    #[inline]
    pub fn place(&self, v: i32) -> usize {
        let offset = v.wrapping_sub(self.first) as u32;
        if !self.squeezed {
            return offset as usize;
        }
        let place = self.places[(offset >> self.bits) as usize];
        if place & OUT != 0 {
            (place & !OUT) as usize
        } else {
            (place + (offset & ((1 << self.bits) - 1))) as usize
        }
    }
}
