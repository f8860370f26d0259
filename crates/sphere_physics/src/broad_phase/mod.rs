//! Broad phase: which bodies' boxes may overlap, in O(1) per body.
//!
//! Two tiers. Bodies of the scene's typical size (per axis, up to twice the median side:
//! falling spheres sweep tall boxes) go to a dense uniform [`Grid`] with cells the size of the
//! largest of them, sorted by cell, so a query reads nine short ranges of consecutive bodies.
//! Its block of cells spans the bodies' cells, with long runs of empty cells along an axis
//! squeezed out (groups far apart, see [`squeeze`]) when the whole would be too large, and
//! cells up to [`MAX_COARSE`] times larger on each side when even the middle 99% of its bodies
//! spans too many (bodies scattered evenly, far apart), unless the larger cells would crowd a
//! dense group among them.
//! Everything else (a dome, walls, big balls, a body that strays far from the others where
//! even the squeezed block would be too large, a body whose box outgrows its cell after a
//! collision) goes to a [`Hierarchy`] of grids whose cells double from level to level. The
//! step works in the grid's order ([`BroadPhase::sort`]): neighbours in space are neighbours
//! in memory.
//! Scenes of a few bodies skip both: all pairs are cheaper. Nothing allocates once the buffers
//! have grown to the scene.

mod grid;
mod hierarchy;
mod packed;
mod squeeze;

use glam::DVec3;

use grid::{Cell, Grid};
use hierarchy::Hierarchy;
use squeeze::Squeeze;

/// Axis-aligned box.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub(crate) struct Aabb {
    pub lo: DVec3,
    pub hi: DVec3,
}

impl Aabb {
    /// The box around a sphere of `radius` swept from `from` to `to`, grown by `margin`.
    pub fn swept(from: DVec3, to: DVec3, radius: f64, margin: f64) -> Self {
        let r = DVec3::splat(radius + margin);
        Aabb {
            lo: from.min(to) - r,
            hi: from.max(to) + r,
        }
    }

    /// Whether the boxes meet (touching counts). Branch-free (min and max, then one test): in
    /// the broad phase's scans most candidates miss on some axis, unpredictably.
    #[inline]
    pub fn overlaps(&self, other: &Aabb) -> bool {
        (self.hi.min(other.hi) - self.lo.max(other.lo)).min_element() >= 0.0
    }

    fn extent(&self) -> f64 {
        (self.hi - self.lo).max_element()
    }
}

/// `floor(v)` as an integer, saturating far outside any scene (and 0 for a NaN).
#[inline]
fn floor_i32(v: f64) -> i32 {
    // Truncate, then step down for negatives: `f64::floor` is a library call on baseline x86-64.
    let v = v.clamp(-1.0e9, 1.0e9);
    let t = if v.is_nan() {
        0
    } else {
        // SAFETY: `v` is a number within ±1e9, well inside `i32`'s range. (`as` would check
        // the range again, and saturate: a handful of instructions per coordinate.)
        unsafe { v.to_int_unchecked::<i32>() }
    };
    t - i32::from(v < f64::from(t))
}

/// How many cells of side `base` from the origin a scene may lie before cells are counted
/// from among its bodies instead ([`far_origin`]): well inside [`floor_i32`]'s range.
const FAR_CELLS: f64 = 1e7;

/// Where the grid and the hierarchy count their cells from: the origin, unless the middle
/// body (in the last step's grid order) lies more than [`FAR_CELLS`] cells of side `base`
/// from it, and then that body's box's centre. Counted from the origin, a scene 2e8 m out in
/// cells of 0.1 m had every cell clamped to the same one by [`floor_i32`]: the grid held no
/// body, the hierarchy's one cell held all, and each step compared every two (2000 spheres
/// stepped 28 times slower than at the origin).
fn far_origin(boxes: &[Aabb], base: f64) -> DVec3 {
    let b = &boxes[boxes.len() / 2];
    let centre = (b.lo + b.hi) * 0.5;
    if centre.is_finite() && centre.abs().max_element() > FAR_CELLS * base {
        centre
    } else {
        DVec3::ZERO
    }
}

/// Pairs of bodies' indices, found in batches ([`BroadPhase::pairs_batched`]).
pub(crate) type Pairs = Vec<(u32, u32)>;

/// Up to this many bodies, all pairs are tested directly: below about 64 the grid's setup
/// costs more than it saves (a 30-sphere shower stepped 3x faster with all pairs, a 30-sphere
/// gas 1.4x; past about 80 bodies a gas is faster with the grid, a shower past about 130).
const SMALL_SCENE: usize = 64;

/// The most cells the grid's block may span for `n` bodies: 64 per body. A shower falls as a
/// lattice with one site in eight filled: about ten cells per sphere; once a small one has slid
/// off its dome its spheres spread over far more, and groups of spheres far apart (the bench's
/// `showers`: a hundred showers side by side, over 73 m by 73 m at 100k) span mostly empty
/// cells. A cell costs a few instructions a step (its count and start), a body in the
/// hierarchy's lowest level hundreds: with 16 cells per body the 100- and 300-sphere showers
/// ended with most of their spheres in the hierarchy, 1.1x and 1.2x slower than with 64 (32 and
/// 128 no better there). Until 2026-12-05 the limit was 16 per body beyond 2^20 cells: the 100k
/// `showers` took 1.3x as long (398 to 421 ns per sphere per step against 289 to 321; 128 per
/// body, 278 to 282, for twice the memory: the counts take 4 bytes a cell).
fn block_limit(n: usize) -> usize {
    64 * n + 64
}

/// The most times the typical box a grid cell may be on each side: when even the middle 99%
/// of the grid's bodies spans more cells than [`block_limit`] allows (spheres scattered
/// evenly, far apart), cells two, four or eight times larger each way, the least that fits,
/// rather than most of the bodies sent to the hierarchy. A sparse gas of spheres 0.1 m across,
/// a metre apart (the bench's `sparse`), took 177 / 192 / 250 ns per sphere per step at 1k /
/// 10k / 100k with most of its spheres in the hierarchy, and 80 / 75 / 106 in cells four times
/// larger.
const MAX_COARSE: u32 = 8;

/// Larger cells are given up if their bodies share a cell with more than twice this many
/// others on average (pairs in one cell, over bodies).
const CROWDED: u64 = 2;

/// The cells of the block from cell `lo` to `hi` with its empty border.
fn volume(lo: &[i32; 3], hi: &[i32; 3]) -> u64 {
    (0..3)
        .map(|a| (i64::from(hi[a]) - i64::from(lo[a]) + 3) as u64)
        .fold(1u64, u64::saturating_mul)
}

/// The cells of the block from cell `lo` to `hi` (with its empty border) once cells are
/// `factor` times larger on each side.
fn coarse_volume(lo: &[i32; 3], hi: &[i32; 3], factor: u32) -> u64 {
    (0..3)
        .map(|a| {
            let span = (i64::from(hi[a]) - i64::from(lo[a]) + 1) as u64;
            span.div_ceil(u64::from(factor)) + 3
        })
        .fold(1u64, u64::saturating_mul)
}

/// The broad phase (see the module docs). Keeps its buffers between steps.
#[derive(Debug, Default)]
pub(crate) struct BroadPhase {
    /// All pairs directly (small scenes).
    brute: bool,
    grid: Grid,
    hierarchy: Hierarchy,
    /// The typical box size: the grid's cell and the hierarchy's finest.
    base: f64,
    /// Where both count their cells from (see [`far_origin`]).
    origin: DVec3,
    /// How each axis of the block places a cell (see [`squeeze`]).
    axes: [Squeeze; 3],
    /// New index `p` is old index `permutation[p]`.
    permutation: Vec<u32>,
    /// Each body's grid cell (in the order given to `sort`), if it goes to the grid.
    cells: Vec<Option<Cell>>,
    /// The grid bodies' cells in the new order.
    sorted_cells: Vec<Cell>,
    counts: Vec<u32>,
    /// The sampled boxes' sides per axis (`typical_box`).
    sides: [Vec<f64>; 3],
    coordinates: Vec<i32>,
    /// Each body's cell of the typical size while the grid tries larger ones, and the bounds
    /// of the block they would be trimmed to (see [`BroadPhase::choose_block`]).
    fine_cells: Vec<Option<Cell>>,
    fine_bounds: ([i32; 3], [i32; 3]),
}

impl BroadPhase {
    /// Chooses the order to step `boxes` in and returns it (new index `p` is old index
    /// `permutation[p]`), or `None` to keep the given order (small scenes). Then call
    /// [`BroadPhase::build`] with the boxes in that order.
    pub fn sort(&mut self, boxes: &[Aabb]) -> Option<&[u32]> {
        let n = boxes.len();
        self.brute = n <= SMALL_SCENE;
        if self.brute {
            return None;
        }
        let typical = self.typical_box(boxes);
        self.base = typical.max_element();
        self.origin = far_origin(boxes, self.base);
        self.grid.set_origin(self.origin);
        let limit = block_limit(n);
        self.grid.set_cell(typical);
        self.cells.clear();
        self.cells
            .extend(boxes.iter().map(|b| self.grid.cell_of(b)));
        let coarse = self.choose_block(limit);
        if coarse > 1 {
            self.grid.set_cell(typical * f64::from(coarse));
            if !self.sort_in_block(n, limit, CROWDED) {
                // The larger cells crowd a dense group among the scattered bodies: the typical
                // cells after all, with the stragglers in the hierarchy.
                self.grid.set_cell(typical);
                std::mem::swap(&mut self.cells, &mut self.fine_cells);
                let (lo, hi) = self.fine_bounds;
                self.trim(lo, hi, limit as u64);
                self.sort_in_block(n, limit, u64::MAX);
            }
        } else {
            self.sort_in_block(n, limit, u64::MAX);
        }
        self.grid.swap_start(&mut self.counts);
        Some(&self.permutation)
    }

    /// Counting-sorts the grid's bodies by cell over the block the axes place them in (see
    /// [`BroadPhase::sort_by_cell`], which may give up if `crowded`).
    fn sort_in_block(&mut self, n: usize, limit: usize, crowded: u64) -> bool {
        // The axes out of `self` while the sort reads them (no copy: their buffers move).
        let axes = std::mem::take(&mut self.axes);
        let dims = axes.each_ref().map(Squeeze::len);
        let sorted = if axes.iter().any(Squeeze::squeezed) {
            self.sort_by_cell(n, limit, dims, crowded, |k| {
                (
                    axes[0].place(k[0]),
                    axes[1].place(k[1]),
                    axes[2].place(k[2]),
                )
            })
        } else {
            // Nearly every scene: a cell's place is its offset from the block's first cell,
            // worked out without the axes' lookups (with them the sort took a fifth longer).
            let first = axes.each_ref().map(|a| a.ends().0);
            self.sort_by_cell(n, limit, dims, crowded, |k| {
                (
                    (k[0] - first[0]) as usize,
                    (k[1] - first[1]) as usize,
                    (k[2] - first[2]) as usize,
                )
            })
        };
        self.axes = axes;
        sorted
    }

    /// Counting-sorts the grid's bodies by cell, each cell's place in the block `dims` (per
    /// axis) as `place` says, into [`BroadPhase::permutation`] (the bodies the hierarchy takes
    /// after them, in their order), their cells into `sorted_cells`, and each cell's start
    /// into `counts`, for a block of at most `limit` cells. Gives up (returns false) if the
    /// pairs of bodies sharing a cell are more than `crowded` times the bodies.
    fn sort_by_cell(
        &mut self,
        n: usize,
        limit: usize,
        dims: [usize; 3],
        crowded: u64,
        place: impl Fn(Cell) -> (usize, usize, usize),
    ) -> bool {
        let index = |k: Cell| {
            let (x, y, z) = place(k);
            x + dims[0] * (y + dims[1] * z)
        };
        // Counting sort by cell; the rest after, in their order.
        let total = dims[0] * dims[1] * dims[2];
        // Room for the largest block the scene may need, so that a scene spreading out over
        // its steps allocates nothing.
        self.counts.clear();
        self.counts.reserve(limit + 1);
        self.counts.resize(total + 1, 0);
        let (mut in_grid, mut shared) = (0usize, 0u64);
        for k in self.cells.iter().flatten() {
            let count = &mut self.counts[index(*k)];
            shared += u64::from(*count);
            *count += 1;
            in_grid += 1;
        }
        if shared > crowded.saturating_mul(in_grid as u64) {
            return false;
        }
        // Running sums (a loop over the slice: indexing `self.counts` reloaded and
        // bounds-checked it for each of the several cells per body): each cell's end.
        let mut sum = 0;
        for count in &mut self.counts {
            sum += *count;
            *count = sum;
        }
        // Bodies placed from the last, each cell's end stepping back: every cell's bodies in
        // their order, and the counts end as the cells' starts (the last entry the grid
        // bodies' end), handed to the grid without a copy.
        self.permutation.clear();
        self.permutation.resize(n, 0);
        self.sorted_cells.clear();
        // Room for every body, not the grid's share: that may grow from step to step.
        self.sorted_cells.reserve(n);
        self.sorted_cells.resize(in_grid, [0; 3]);
        let mut rest = n;
        for (i, cell) in self.cells.iter().enumerate().rev() {
            match cell {
                Some(k) => {
                    let slot = &mut self.counts[index(*k)];
                    *slot -= 1;
                    self.permutation[*slot as usize] = i as u32;
                    self.sorted_cells[*slot as usize] = *k;
                }
                None => {
                    rest -= 1;
                    self.permutation[rest] = i as u32;
                }
            }
        }
        true
    }

    /// The typical box, per axis: the longest side up to twice the median side (the median
    /// taken over at most 256 boxes spread through the scene: a median of 1024 cost a 1k
    /// scene a tenth of its step).
    fn typical_box(&mut self, boxes: &[Aabb]) -> DVec3 {
        let stride = boxes.len().div_ceil(256).max(1);
        // The sampled boxes' sides, all three axes in one pass (finite ones only).
        for sides in &mut self.sides {
            sides.clear();
        }
        let mut k = 0;
        while let Some(b) = boxes.get(k) {
            let side = b.hi - b.lo;
            for (sides, v) in self.sides.iter_mut().zip(side.to_array()) {
                if v.is_finite() {
                    sides.push(v);
                }
            }
            k += stride;
        }
        let mut limit = DVec3::ZERO;
        for (a, sides) in self.sides.iter_mut().enumerate() {
            if sides.is_empty() {
                continue;
            }
            let middle = sides.len() / 2;
            let median = *sides.select_nth_unstable_by(middle, f64::total_cmp).1;
            limit[a] = 2.0 * median;
        }
        // The longest sides within the limits, all three axes in one pass over the boxes.
        let largest = boxes.iter().fold(DVec3::ZERO, |largest, b| {
            let side = b.hi - b.lo;
            // A side over its limit (or NaN) counts as zero.
            largest.max(DVec3::select(side.cmple(limit), side, DVec3::ZERO))
        });
        DVec3::select(largest.cmpgt(DVec3::ZERO), largest, DVec3::ONE)
    }

    /// The block of cells the grid spans: all the grid bodies' cells and an empty border, cut
    /// down to at most `limit` cells ([`block_limit`]; stragglers go to the hierarchy
    /// instead). Returns how many times larger than the typical box the cells are on each
    /// side: 1, unless even the middle 99% of the bodies spans more than `limit` cells (spread
    /// evenly, far apart), when the bodies' cells are made [`MAX_COARSE`] times larger at most,
    /// the cells of the typical size kept in `fine_cells` and their trimmed block's bounds in
    /// `fine_bounds`.
    fn choose_block(&mut self, limit: usize) -> u32 {
        // Room for the trimming below, whether or not this step trims: a scene that spreads
        // out first needs it well after its first steps, and must not allocate then.
        self.coordinates.clear();
        self.coordinates.reserve(self.cells.len());
        self.fine_cells.clear();
        self.fine_cells.reserve(self.cells.len());
        for axis in &mut self.axes {
            axis.reserve(self.cells.len());
        }
        let limit = limit as u64;
        let mut lo = [i32::MAX; 3];
        let mut hi = [i32::MIN; 3];
        for k in self.cells.iter().flatten() {
            for a in 0..3 {
                lo[a] = lo[a].min(k[a]);
                hi[a] = hi[a].max(k[a]);
            }
        }
        if lo[0] > hi[0] {
            for axis in &mut self.axes {
                axis.plain(0, 0);
            }
            return 1;
        }
        if volume(&lo, &hi) <= limit {
            self.plain(lo, hi);
            return 1;
        }
        self.choose_spread_block(lo, hi, limit)
    }

    /// [`BroadPhase::choose_block`] for bodies whose cells from `lo` to `hi` span more than
    /// `limit` (rare: kept out of the common path).
    #[cold]
    #[inline(never)]
    fn choose_spread_block(&mut self, mut lo: [i32; 3], mut hi: [i32; 3], limit: u64) -> u32 {
        // Groups far apart along an axis: squeeze out the empty cells between them.
        let mut cells = 1u64;
        for a in 0..3 {
            let occupied = self.cells.iter().flatten().map(|k| k[a]);
            let len = self.axes[a].squeeze(lo[a] - 1, hi[a] + 1, occupied, self.cells.len());
            cells = cells.saturating_mul(len as u64);
        }
        if cells <= limit {
            return 1;
        }
        // The middle 99% on each axis.
        let all = (lo, hi);
        for a in 0..3 {
            self.coordinates.clear();
            self.coordinates
                .extend(self.cells.iter().flatten().map(|k| k[a]));
            let m = self.coordinates.len();
            let low = *self.coordinates.select_nth_unstable(m / 200).1;
            let high = *self.coordinates.select_nth_unstable(m - 1 - m / 200).1;
            (lo[a], hi[a]) = (low, high);
        }
        if volume(&lo, &hi) <= limit {
            // A group with stragglers around it.
            self.trim(lo, hi, limit);
            return 1;
        }
        // Spread evenly: cells `2^bits` times larger on each side, each the union of that many
        // cubed (flooring never decreases, so the bounds stay the bounds, and a box within a
        // cell's envelope is within the larger cell's).
        let mut bits = 1;
        while (1 << bits) < MAX_COARSE && coarse_volume(&lo, &hi, 1 << bits) > limit {
            bits += 1;
        }
        self.fine_cells.clone_from(&self.cells);
        self.fine_bounds = (lo, hi);
        for k in self.cells.iter_mut().flatten() {
            *k = k.map(|c| c >> bits);
        }
        let (all_lo, all_hi) = (all.0.map(|c| c >> bits), all.1.map(|c| c >> bits));
        if volume(&all_lo, &all_hi) <= limit {
            self.plain(all_lo, all_hi);
        } else {
            self.trim(lo.map(|c| c >> bits), hi.map(|c| c >> bits), limit);
        }
        1 << bits
    }

    /// The block from cell `lo` to `hi` cut down (its longest axis first) to at most `limit`
    /// cells, the bodies outside it sent to the hierarchy.
    fn trim(&mut self, mut lo: [i32; 3], mut hi: [i32; 3], limit: u64) {
        while volume(&lo, &hi) > limit {
            let a = (0..3)
                .max_by_key(|&a| i64::from(hi[a]) - i64::from(lo[a]))
                .unwrap_or(0);
            let cut = ((i64::from(hi[a]) - i64::from(lo[a])) / 16).max(1) as i32;
            lo[a] += cut;
            hi[a] = (hi[a] - cut).max(lo[a]);
        }
        for cell in &mut self.cells {
            if let Some(k) = cell
                && (0..3).any(|a| k[a] < lo[a] || k[a] > hi[a])
            {
                *cell = None;
            }
        }
        self.plain(lo, hi);
    }

    /// The block from cell `lo` to `hi` with an empty cell on every side, so that every grid
    /// body's 26 neighbour cells are in the block (the grid's pair scan needs no bounds
    /// checks), nothing squeezed.
    fn plain(&mut self, lo: [i32; 3], hi: [i32; 3]) {
        for (a, axis) in self.axes.iter_mut().enumerate() {
            axis.plain(lo[a] - 1, hi[a] + 1);
        }
    }

    /// Builds both tiers for `boxes`, in the order [`BroadPhase::sort`] chose.
    pub fn build(&mut self, boxes: &[Aabb]) {
        if self.brute {
            return;
        }
        self.grid
            .layout(&mut self.axes, &mut self.sorted_cells, boxes);
        self.hierarchy
            .rebuild(boxes, self.grid.len(), self.base, self.origin);
    }

    /// Body `i`'s box is now `b`.
    pub fn update(&mut self, i: usize, b: &Aabb) {
        self.update_kept(i, b);
    }

    /// [`BroadPhase::update`], and whether [`BroadPhase::pairs_batched`] still finds every
    /// pair of body `i` as its box now is: the body stays in the grid, within its cell's
    /// envelope (as every grid body's box was at [`BroadPhase::build`], so the grid's scan of
    /// neighbouring cells still meets all its pairs), or the scene is small enough that every
    /// pair is compared. A body that leaves the grid, or is in the hierarchy, returns false:
    /// the hierarchy's pairs are those it was built with.
    pub fn update_kept(&mut self, i: usize, b: &Aabb) -> bool {
        if self.brute {
            return true;
        }
        if self.grid.holds(i) && self.grid.keep(i, b) {
            return true;
        }
        self.hierarchy.update(i, b);
        false
    }

    /// The room a buffer of pairs handed to [`BroadPhase::pairs_batched`] (and each one
    /// `flush` leaves in its place) needs so that the scan never grows it, whatever the
    /// crowding, for `n` boxes: the scan reserves room for every candidate near a body at a
    /// time, at most all the boxes, beyond less than a batch.
    pub fn pairs_room(n: usize, batch: usize) -> usize {
        n + batch + grid::SCAN_PADDING
    }

    /// Appends to `out` every pair `(i, j)` with `i < j` of overlapping boxes, each pair once,
    /// handing `out` to `flush` whenever it holds at least `batch` pairs (`flush` empties it;
    /// the pairs come in batches of about that size). The last pairs are left in `out`.
    /// Call right after [`BroadPhase::build`] with the same boxes, or after updates every one
    /// of which [`BroadPhase::update_kept`] said true for (a body it said false for is left
    /// out: its grid box is emptied, and the hierarchy's pairs are those it was built with).
    pub fn pairs_batched(
        &self,
        boxes: &[Aabb],
        out: &mut Pairs,
        batch: usize,
        mut flush: impl FnMut(&mut Pairs),
    ) {
        let push = |out: &mut Pairs, flush: &mut dyn FnMut(&mut Pairs), i, j| {
            out.push((i as u32, j as u32));
            if out.len() >= batch {
                flush(out);
            }
        };
        if self.brute {
            for i in 0..boxes.len() {
                for j in i + 1..boxes.len() {
                    if boxes[i].overlaps(&boxes[j]) {
                        push(out, &mut flush, i, j);
                    }
                }
            }
            return;
        }
        self.grid.pairs(out, batch, &mut flush);
        self.hierarchy
            .pairs(boxes, |i, j| push(out, &mut flush, i, j));
        for (j, bj) in boxes.iter().enumerate().skip(self.grid.len()) {
            self.grid.visit(bj, &mut |i| push(out, &mut flush, i, j));
        }
    }

    /// Calls `f(i, j)` with `i < j` for every pair of overlapping boxes, each pair once, with
    /// `scratch` for their batches ([`BroadPhase::pairs_batched`]).
    pub fn pairs(&self, boxes: &[Aabb], scratch: &mut Pairs, mut f: impl FnMut(usize, usize)) {
        let mut each = |pairs: &mut Pairs| {
            for &(i, j) in pairs.iter() {
                f(i as usize, j as usize);
            }
            pairs.clear();
        };
        scratch.clear();
        self.pairs_batched(boxes, scratch, 64, &mut each);
        each(scratch);
    }

    /// Hints that body `i` will be updated and queried soon.
    #[inline]
    pub fn prefetch(&self, i: usize) {
        if !self.brute {
            self.grid.prefetch(i);
        }
    }

    /// Appends to `out` every body whose box may overlap body `i`'s (`boxes` current): a
    /// superset of what [`BroadPhase::overlapping`] finds, and it may hold `i` itself (its own
    /// box overlaps it: a caller skips it for less than removing it would cost).
    pub fn collect_overlapping(&mut self, i: usize, boxes: &[Aabb], out: &mut Vec<u32>) {
        if self.brute {
            self.overlapping(i, boxes, |j| out.push(j as u32));
            return;
        }
        self.grid.collect(&boxes[i], out);
        self.hierarchy
            .overlapping(i, &boxes[i], boxes, |j| out.push(j as u32));
    }

    /// [`BroadPhase::collect_overlapping`] for two bodies at once, `i`'s candidates into
    /// `out_i` and `j`'s into `out_j` (the same sets), scanning the grid once for both: for
    /// bodies side by side, whose queries read nearly the same rows.
    pub fn collect_overlapping_both(
        &mut self,
        (i, j): (usize, usize),
        boxes: &[Aabb],
        out_i: &mut Vec<u32>,
        out_j: &mut Vec<u32>,
    ) {
        if self.brute {
            self.overlapping(i, boxes, |m| out_i.push(m as u32));
            self.overlapping(j, boxes, |m| out_j.push(m as u32));
            return;
        }
        self.grid.collect_both(&boxes[i], &boxes[j], out_i, out_j);
        self.hierarchy.overlapping_both(
            (i, &boxes[i]),
            (j, &boxes[j]),
            boxes,
            |m| out_i.push(m as u32),
            |m| out_j.push(m as u32),
        );
    }

    /// Calls `f(j)` for every body `j != i` whose box overlaps body `i`'s (`boxes` current).
    pub fn overlapping(&self, i: usize, boxes: &[Aabb], mut f: impl FnMut(usize)) {
        let bi = &boxes[i];
        if self.brute {
            for (j, bj) in boxes.iter().enumerate() {
                if j != i && bi.overlaps(bj) {
                    f(j);
                }
            }
            return;
        }
        self.grid.visit(bi, &mut |j| {
            if j != i {
                f(j);
            }
        });
        self.hierarchy.overlapping(i, bi, boxes, f);
    }
}
