//! The broad phase's fast tier: bodies of about one size in a dense grid of cells as large as
//! the largest of them, sorted by cell, so that a row of three cells is one range of bodies.
//!
//! A body belongs to the cell holding its box's centre at the start of the step, and its box
//! lies within that cell's *envelope*: the cell grown by just under half a cell on each side.
//! Boxes within the envelopes of two cells two apart along an axis cannot overlap, so a body's
//! partners are in the 27 cells around it. After a collision a body stays where it is while its
//! new box is still within the envelope (most do: the new box is the rest of the old drift,
//! turned); otherwise it leaves the grid for the broad phase's general tier.
//!
//! The grid's scans compare boxes [packed](super::packed) into 16-bit integers (boxes that
//! meet still meet when packed): 16 bytes and one comparison per box.

use glam::DVec3;

use super::packed::{Frame, Packed, Query};
use super::squeeze::Squeeze;
use super::{Aabb, Pairs, floor_i32};

/// How many rows a query finds before scanning them: a grid body's box meets two or three
/// cells per axis, so nine rows of three at most, unless the box is almost a cell wide (then
/// up to sixteen, found and scanned nine at a time).
const PREFETCHED_ROWS: usize = 9;

/// Boxes compared at a time by [`Grid::pairs`]: a row of three cells holds about one in the
/// gas benchmark, so most rows take one pass. Four compared twice as many boxes as needed; one
/// left a mispredicted branch at the end of most rows (both slower, measured).
const BLOCK: usize = 2;

/// The offers a scan for one body's pairs may write beyond its candidates: a block for each
/// of its five ranges.
pub(crate) const SCAN_PADDING: usize = 5 * BLOCK;

/// Rows a query reads in one pass ([`Grid::one_pass_rows`]): three by three (y, z).
const ONE_PASS_ROWS: usize = 9;

/// The most bodies a row may hold for the one pass (a longer one, rare, sends the query to
/// the row-by-row scan).
const ONE_PASS_ROW: usize = 32;

/// A cell's coordinates, absolute (cell `k` spans `[k·cell, (k+1)·cell)` on its axis).
pub(crate) type Cell = [i32; 3];

/// The dense grid (see the module docs). Keeps its buffers between steps.
#[derive(Debug, Default)]
pub(crate) struct Grid {
    /// Where cell (0, 0, 0)'s low corner is (see [`BroadPhase::sort`](super::BroadPhase)).
    origin: DVec3,
    /// The cell's sides: the typical box per axis (falling spheres sweep tall boxes).
    cell: DVec3,
    inverse: DVec3,
    /// How far a box may reach beyond its cell on each side: just under half a cell.
    slack: DVec3,
    /// How each axis of the dense block places a cell, and the block's size in cells per axis.
    axes: [Squeeze; 3],
    dims: [usize; 3],
    /// Bodies `0..len` are the grid's, sorted by cell: cell `c` (dense index) holds bodies
    /// `start[c]..start[c + 1]`.
    len: usize,
    start: Vec<u32>,
    /// Each grid body's cell.
    cells: Vec<Cell>,
    /// Each grid body's box, packed ([`Packed::empty`] once it has left).
    boxes: Vec<Packed>,
    /// The frame the boxes are packed in: the block and two cells around it.
    frame: Frame,
    /// Whether grid body `i` is still in the grid (it leaves when its box leaves its envelope).
    present: Vec<bool>,
    /// Scratch for a query's bodies, row after row ([`Grid::one_pass_rows`]).
    flat: Vec<u32>,
}

/// Indices appended to a list without filling its new slots first: each offered index is
/// written past the list's end and kept by advancing past it only if wanted, with no branch on
/// that (whether a box overlaps is a coin toss the branch predictor loses).
struct Kept<'a, T> {
    out: &'a mut Vec<T>,
    /// The first new slot.
    slots: *mut T,
    kept: usize,
    /// How many offers there is room for.
    room: usize,
}

impl<'a, T> Kept<'a, T> {
    /// Room for `room` offers at the end of `out`.
    #[inline(always)]
    fn new(out: &'a mut Vec<T>, room: usize) -> Self {
        out.reserve(room);
        // SAFETY: `out.len()` is within its allocation (one past its end at most).
        let slots = unsafe { out.as_mut_ptr().add(out.len()) };
        Kept {
            out,
            slots,
            kept: 0,
            room,
        }
    }

    /// Writes `j` into the next slot, and keeps it if `keep`.
    ///
    /// # Safety
    /// At most `room` offers in all (as given to [`Kept::new`]).
    #[inline(always)]
    unsafe fn offer(&mut self, j: T, keep: bool) {
        debug_assert!(self.kept < self.room);
        // SAFETY: `kept` is at most the offers before this one, fewer than `room` (the
        // caller's promise): the slot lies within the capacity reserved.
        unsafe { self.slots.add(self.kept).write(j) };
        self.kept += usize::from(keep);
    }

    /// Adds the kept indices to the list.
    #[inline(always)]
    fn finish(self) {
        let len = self.out.len() + self.kept;
        // SAFETY: the slots up to `kept` were all written (each offer writes the slot at
        // `kept` before it may advance), within the capacity reserved.
        unsafe { self.out.set_len(len) };
    }
}

/// Cell `k`'s coordinates as a vector (its low corner, in cells).
#[inline]
fn corner_of(k: Cell) -> DVec3 {
    DVec3::new(f64::from(k[0]), f64::from(k[1]), f64::from(k[2]))
}

impl Grid {
    /// Counts cells from `origin` (cell (0, 0, 0)'s low corner).
    pub fn set_origin(&mut self, origin: DVec3) {
        self.origin = origin;
    }

    /// Sets the cell's sides: boxes up to `largest` (per axis) fit their cell's envelope.
    pub fn set_cell(&mut self, largest: DVec3) {
        self.cell = largest * (1.0 + 1e-5);
        self.inverse = self.cell.recip();
        self.slack = self.cell * (0.5 * (1.0 - 1e-6));
    }

    /// The cell whose envelope holds `b`, if the box is no larger than the cell allows.
    #[inline]
    pub fn cell_of(&self, b: &Aabb) -> Option<Cell> {
        let centre = (b.lo + b.hi) * 0.5 - self.origin;
        let k = [
            floor_i32(centre.x * self.inverse.x),
            floor_i32(centre.y * self.inverse.y),
            floor_i32(centre.z * self.inverse.z),
        ];
        self.within(b, k).then_some(k)
    }

    /// Whether `b` lies within the envelope of cell `k` (branch-free: it runs for every body
    /// every step).
    #[inline]
    fn within(&self, b: &Aabb, k: Cell) -> bool {
        let k = corner_of(k);
        let lo = k * self.cell - self.slack + self.origin;
        let hi = (k + 1.0) * self.cell + self.slack + self.origin;
        (b.lo.cmpge(lo) & b.hi.cmple(hi)).all()
    }

    /// Takes `start` as where each cell's bodies start (dense index over the block; one more
    /// for the end), leaving the grid's previous buffer in its place (to be refilled next
    /// step) rather than copying.
    pub fn swap_start(&mut self, start: &mut Vec<u32>) {
        std::mem::swap(&mut self.start, start);
    }

    /// Lays the grid out over the block whose axes place cells as `axes` say, for bodies
    /// `0..cells.len()`, already sorted by the dense index of their cells (`cells` are theirs,
    /// in that order) as [`Grid::swap_start`] says, with `boxes` (at least as many). Takes the
    /// cells' and the axes' buffers (leaving the grid's old ones, to be refilled next step)
    /// rather than copying them.
    pub fn layout(&mut self, axes: &mut [Squeeze; 3], cells: &mut Vec<Cell>, boxes: &[Aabb]) {
        std::mem::swap(&mut self.axes, axes);
        self.dims = self.axes.each_ref().map(Squeeze::len);
        self.len = cells.len();
        std::mem::swap(&mut self.cells, cells);
        // Room for every body (`boxes` has one each), not the grid's share: that may grow
        // from step to step.
        self.present.clear();
        self.present.reserve(boxes.len());
        self.present.resize(self.len, true);
        // The frame spans the block's cells before any squeeze: every box of the grid is
        // packed by the same map, whatever lies between.
        let ends = self.axes.each_ref().map(Squeeze::ends);
        let first = ends.map(|(first, _)| first);
        let span = ends.map(|(first, last)| (i64::from(last) - i64::from(first) + 1) as usize);
        self.frame = Frame::new(corner_of(first) * self.cell + self.origin, self.cell, span);
        let frame = &self.frame;
        self.boxes.clear();
        self.boxes.reserve(boxes.len() + BLOCK);
        self.boxes
            .extend(boxes[..self.len].iter().map(|b| Packed::new(frame, b)));
        // Padding, so that a scan may read a whole block past any range's start.
        self.boxes
            .extend(std::iter::repeat_n(Packed::empty(), BLOCK));
    }

    /// Bodies `0..len()` are (or were, at the start of the step) the grid's.
    pub fn len(&self) -> usize {
        self.len
    }

    /// Whether body `i` is in the grid.
    #[inline]
    pub fn holds(&self, i: usize) -> bool {
        i < self.len && self.present[i]
    }

    /// Hints that body `i`'s cell will be read soon.
    #[inline]
    pub fn prefetch(&self, i: usize) {
        if let Some(k) = self.cells.get(i) {
            crate::solver::prefetch(k);
        }
    }

    /// Body `i`'s box is now `b`: it stays if the box is within its cell's envelope, and
    /// otherwise leaves the grid (returns false).
    pub fn keep(&mut self, i: usize, b: &Aabb) -> bool {
        if self.within(b, self.cells[i]) {
            self.boxes[i] = Packed::new(&self.frame, b);
            return true;
        }
        self.present[i] = false;
        self.boxes[i] = Packed::empty();
        false
    }

    /// Appends to `out` every pair `(i, j)` with `i < j` of grid bodies whose boxes overlap,
    /// each pair once: a cell with itself and its 13 neighbours that follow it, body by body
    /// (empty cells cost nothing). Before each body, hands `out` to `flush` if it holds at least
    /// `batch` pairs (`flush` empties it). Call right after [`Grid::layout`], with a block that
    /// has an empty cell on every side of the bodies' cells.
    pub fn pairs(&self, out: &mut Pairs, batch: usize, flush: &mut impl FnMut(&mut Pairs)) {
        if self.len == 0 {
            // No body fits the grid: its block is a bare cell, with no rows around it.
            return;
        }
        let boxes = &self.boxes[..];
        let [nx, ny, _] = self.dims;
        let start = &self.start[..];
        // The forward rows of three cells (x − 1 ..= x + 1) at (y + 1, z), (y − 1, z + 1),
        // (y, z + 1) and (y + 1, z + 1), as offsets from the body's cell.
        let rows = [nx - 1, nx * ny - nx - 1, nx * ny - 1, nx * ny + nx - 1];
        for i in 0..self.len {
            if out.len() >= batch {
                flush(out);
            }
            let k = self.cells[i];
            let axes = &self.axes;
            let c = axes[0].place(k[0]) + nx * (axes[1].place(k[1]) + ny * axes[2].place(k[2]));
            let bi = &boxes[i].as_query();
            // Own cell (after i) and the next along x: one range. Then four rows of three.
            debug_assert!(c + rows[3] + 3 < start.len());
            // SAFETY: the body's cell lies inside the block's empty border, so the cells read
            // (up to x + 1, y + 1, z + 1, and the start of the cell after it) are in the block,
            // whose starts `start` holds, with one more for the end.
            let at = |offset: usize| unsafe { *start.get_unchecked(c + offset) } as usize;
            let ranges = [
                (i + 1, at(2)),
                (at(rows[0]), at(rows[0] + 3)),
                (at(rows[1]), at(rows[1] + 3)),
                (at(rows[2]), at(rows[2] + 3)),
                (at(rows[3]), at(rows[3] + 3)),
            ];
            // Every candidate is written, and kept only if its box overlaps, so no branch
            // depends on an overlap (a coin toss the branch predictor loses). A range takes
            // whole blocks, at least one: fewer than its length plus a block in all.
            let room = ranges.iter().map(|&(from, to)| to - from).sum::<usize>() + SCAN_PADDING;
            let mut kept = Kept::new(out, room);
            for (from, to) in ranges {
                // A row of up to a block's bodies (the usual) takes one pass, with no branch on
                // its length.
                let mut j = from;
                loop {
                    for b in 0..BLOCK {
                        let m = j + b;
                        debug_assert!(m < boxes.len());
                        // SAFETY: `m < to + BLOCK <= len + BLOCK`, the boxes' length with their
                        // padding; and the offers, a block at a time while `j < to`, number
                        // fewer than `room`.
                        unsafe {
                            kept.offer(
                                (i as u32, m as u32),
                                (m < to) & boxes.get_unchecked(m).meets(bi),
                            );
                        }
                    }
                    j += BLOCK;
                    if j >= to {
                        break;
                    }
                }
            }
            kept.finish();
        }
    }

    /// Calls `f(j)` for every body `j` in `from..to` still in the grid whose box overlaps `q`
    /// (bodies that left have empty boxes).
    #[inline]
    fn visit_in(&self, q: &Query, from: usize, to: usize, f: &mut impl FnMut(usize)) {
        for (offset, bj) in self.boxes[from..to].iter().enumerate() {
            if bj.meets(q) {
                f(from + offset);
            }
        }
    }

    /// Appends to `out` every body in the given rows (ranges of bodies) still in the grid
    /// whose box overlaps `q`, without a branch per box (whether a box overlaps is a coin toss
    /// the branch predictor loses): each index is written, and kept by advancing past it only
    /// if it overlaps. `out` grows once for all the rows.
    #[inline]
    fn collect_in(&self, q: &Query, rows: &[(u32, u32)], out: &mut Vec<u32>) {
        let total: u32 = rows.iter().map(|&(from, to)| to - from).sum();
        let mut kept = Kept::new(out, total as usize);
        for &(from, to) in rows {
            for (j, bj) in (from..to).zip(&self.boxes[from as usize..to as usize]) {
                // SAFETY: one offer per box of the rows, `total` in all.
                unsafe { kept.offer(j, bj.meets(q)) };
            }
        }
        kept.finish();
    }

    /// Calls `scan` with `q` packed and the ranges of grid bodies whose cells'
    /// envelopes may meet `q`: found first and handed over nine at a time, each row's first
    /// boxes asked for as it is found, since the rows lie far apart in memory and their loads
    /// then overlap instead of each waiting in turn. (A large box meets more rows than nine:
    /// they come a batch at a time, in order.)
    #[inline]
    fn scan_rows(&self, q: &Aabb, scan: &mut impl FnMut(&Query, &[(u32, u32)])) {
        let mut rows = [(0u32, 0u32); PREFETCHED_ROWS];
        let mut count = 0;
        let mut query = Packed::empty().as_query();
        self.visit_rows(q, &mut |c, from, to| {
            if count == PREFETCHED_ROWS {
                scan(c, &rows);
                count = 0;
            }
            if let Some(first) = self.boxes.get(from) {
                crate::solver::prefetch(first);
            }
            rows[count] = (from as u32, to as u32);
            count += 1;
            query = *c;
        });
        scan(&query, &rows[..count]);
    }

    /// Appends to `out` every body in the grid whose box may overlap `q` (a superset: the
    /// grid compares boxes packed into integers, see `packed`).
    pub fn collect(&mut self, q: &Aabb, out: &mut Vec<u32>) {
        if self.len == 0 {
            return;
        }
        if let Some(total) = self.one_pass_rows(q) {
            let query = Query::new(&self.frame, q);
            let mut kept = Kept::new(out, total);
            for &j in &self.flat[..total] {
                debug_assert!((j as usize) < self.boxes.len());
                // SAFETY: `j` is a grid body, one of `boxes`; one offer per body, `total` in
                // all.
                unsafe { kept.offer(j, self.boxes.get_unchecked(j as usize).meets(&query)) };
            }
            kept.finish();
            return;
        }
        self.scan_rows(q, &mut |query, rows| self.collect_in(query, rows, out));
    }

    /// [`Grid::collect_in`] for two query boxes at once: each box of the rows is compared
    /// with both, and kept in each list it overlaps.
    #[inline]
    fn collect_both_in(
        &self,
        (qa, qb): (&Query, &Query),
        rows: &[(u32, u32)],
        (out_a, out_b): (&mut Vec<u32>, &mut Vec<u32>),
    ) {
        let total: u32 = rows.iter().map(|&(from, to)| to - from).sum();
        let (mut kept_a, mut kept_b) = (
            Kept::new(out_a, total as usize),
            Kept::new(out_b, total as usize),
        );
        for &(from, to) in rows {
            for (j, bj) in (from..to).zip(&self.boxes[from as usize..to as usize]) {
                // SAFETY: one offer to each per box of the rows, `total` in all.
                unsafe {
                    kept_a.offer(j, bj.meets(qa));
                    kept_b.offer(j, bj.meets(qb));
                }
            }
        }
        kept_a.finish();
        kept_b.finish();
    }

    /// [`Grid::collect`] for two boxes at once (`a`'s candidates into `out_a`, `b`'s into
    /// `out_b`), scanning the rows around both once.
    pub fn collect_both(&mut self, a: &Aabb, b: &Aabb, out_a: &mut Vec<u32>, out_b: &mut Vec<u32>) {
        if self.len == 0 {
            return;
        }
        let both = Aabb {
            lo: a.lo.min(b.lo),
            hi: a.hi.max(b.hi),
        };
        let (qa, qb) = (Query::new(&self.frame, a), Query::new(&self.frame, b));
        if let Some(total) = self.one_pass_rows(&both) {
            let (mut kept_a, mut kept_b) = (Kept::new(out_a, total), Kept::new(out_b, total));
            for &j in &self.flat[..total] {
                debug_assert!((j as usize) < self.boxes.len());
                // SAFETY: `j` is a grid body, one of `boxes`; one offer to each per body,
                // `total` in all.
                unsafe {
                    let bj = self.boxes.get_unchecked(j as usize);
                    kept_a.offer(j, bj.meets(&qa));
                    kept_b.offer(j, bj.meets(&qb));
                }
            }
            kept_a.finish();
            kept_b.finish();
            return;
        }
        self.scan_rows(&both, &mut |_, rows| {
            self.collect_both_in((&qa, &qb), rows, (&mut *out_a, &mut *out_b))
        });
    }

    /// Calls `f(j)` for every body `j` in the grid whose box may overlap `q` (a superset: the
    /// grid compares boxes packed into integers, see `packed`).
    pub fn visit(&self, q: &Aabb, f: &mut impl FnMut(usize)) {
        self.visit_rows(q, &mut |query, from, to| self.visit_in(query, from, to, f));
    }

    /// The cells whose envelopes may meet `q`, per axis (inclusive, as offsets into the block),
    /// and how many they are; `None` if none are in the block.
    #[inline]
    fn cell_range(&self, q: &Aabb) -> Option<([(usize, usize); 3], usize)> {
        let mut range = [(0usize, 0usize); 3];
        let mut cells = 1usize;
        for (a, r) in range.iter_mut().enumerate() {
            // Cell k's envelope [k·cell − slack, (k+1)·cell + slack] overlaps [lo, hi] when
            // (lo − slack)/cell − 1 <= k <= (hi + slack)/cell; padded against rounding.
            // ceil(v) = -floor(-v)
            let (qlo, qhi) = (q.lo[a] - self.origin[a], q.hi[a] - self.origin[a]);
            let lo = -floor_i32(-((qlo - self.slack[a]) * self.inverse[a] - 1.0 - 1e-7));
            let hi = floor_i32((qhi + self.slack[a]) * self.inverse[a] + 1e-7);
            let (first, last) = self.axes[a].ends();
            let (lo, hi) = (lo.max(first), hi.min(last));
            if lo > hi {
                return None;
            }
            *r = (self.axes[a].place(lo), self.axes[a].place(hi));
            cells = cells.saturating_mul(r.1 - r.0 + 1);
        }
        Some((range, cells))
    }

    /// Calls `scan(q packed, from, to)` for each range of grid bodies whose cells'
    /// envelopes may meet `q`.
    #[inline]
    fn visit_rows(&self, q: &Aabb, scan: &mut impl FnMut(&Query, usize, usize)) {
        if self.len == 0 {
            return;
        }
        let query = Query::new(&self.frame, q);
        let Some((range, cells)) = self.cell_range(q) else {
            return;
        };
        if cells > self.len {
            // A box over much of the grid: every body is cheaper than every cell.
            scan(&query, 0, self.len);
            return;
        }
        let [nx, ny, _] = self.dims;
        let ([xl, xh], [yl, yh], [zl, zh]) = (
            [range[0].0, range[0].1],
            [range[1].0, range[1].1],
            [range[2].0, range[2].1],
        );
        for z in zl..=zh {
            for y in yl..=yh {
                let row = xl + nx * (y + ny * z);
                let (s, e) = (
                    self.start[row] as usize,
                    self.start[row + (xh - xl) + 1] as usize,
                );
                scan(&query, s, e);
            }
        }
    }

    /// Writes into `flat` the grid bodies whose cells' envelopes may meet `q`, row after row,
    /// and returns how many, when they lie in at most three by three rows (y, z) of at most
    /// [`ONE_PASS_ROW`] bodies each (nearly every query after an impact); `None` otherwise.
    ///
    /// Every row is read, and every row's slots written, whatever its length: a scan row by
    /// row mispredicts the end of nearly every row (their lengths are coin tosses), and a
    /// query reads nine. The bodies then take one pass, one loop.
    #[inline]
    fn one_pass_rows(&mut self, q: &Aabb) -> Option<usize> {
        let (range, cells) = self.cell_range(q)?;
        let ([xl, xh], [yl, yh], [zl, zh]) = (
            [range[0].0, range[0].1],
            [range[1].0, range[1].1],
            [range[2].0, range[2].1],
        );
        if cells > self.len || yh - yl > 2 || zh - zl > 2 {
            return None;
        }
        let [nx, ny, _] = self.dims;
        let width = xh - xl + 1;
        // Rows beyond the range read the last one in range, and count as empty.
        let mut rows = [(0u32, 0u32); ONE_PASS_ROWS];
        let mut longest = 0;
        for (r, row) in rows.iter_mut().enumerate() {
            let (dy, dz) = (r % 3, r / 3);
            let (y, z) = ((yl + dy).min(yh), (zl + dz).min(zh));
            let cell = xl + nx * (y + ny * z);
            let (from, to) = (self.start[cell], self.start[cell + width]);
            let len = if (yl + dy <= yh) & (zl + dz <= zh) {
                to - from
            } else {
                0
            };
            longest = longest.max(len);
            *row = (from, len);
        }
        if longest as usize > ONE_PASS_ROW {
            return None;
        }
        let flat = &mut self.flat;
        flat.resize(ONE_PASS_ROWS * ONE_PASS_ROW, 0);
        let mut total = 0;
        for (from, len) in rows {
            // The rows lie far apart in memory: ask for each now, so that their loads overlap.
            if let Some(first) = self.boxes.get(from as usize) {
                crate::solver::prefetch(first);
            }
            let slots = &mut flat[total..total + ONE_PASS_ROW];
            for (offset, slot) in slots.iter_mut().enumerate() {
                *slot = from + offset as u32;
            }
            total += len as usize;
        }
        Some(total)
    }
}
