//! The broad phase's general tier: a hierarchical grid for bodies of any size.
//!
//! Level `L` has cells of side `base · 2^L`; each body lives at the lowest level whose cells are
//! at least as large as its box, in the one cell that holds its box's lower corner. A body whose
//! box overlaps a query box therefore has its lower corner in `[query.lo − cell, query.hi]` at
//! its level: at most 3 cells per axis to visit. (The top level also holds anything larger
//! than its cells, absurd as that is: there a query reaches as far as its largest box, and
//! its pairs are tested directly.) A huge fixed sphere (a dome, a wall) sits alone
//! on a high level, where small bodies find it through the level's short member list.
//!
//! At the start of a step the bodies it holds are counting-sorted by cell into flat arrays
//! (cells map to buckets by a hash). A body that joins during the step, or whose box leaves its
//! cell, moves to an overlay of linked lists, where moving again is O(1). Nothing allocates once
//! the buffers have grown to the scene.

use glam::DVec3;

use super::{Aabb, floor_i32};

const NONE: u32 = u32::MAX;

/// A level no body is on: marks sorted entries of bodies that moved to the overlay.
const GONE: u32 = u32::MAX;

/// Levels: cells from `base` to `base · 2^40`.
const LEVELS: usize = 41;

/// A cell itself, then the 13 neighbours that follow it in (z, y, x) order: each unordered pair
/// of neighbouring cells appears once among "a cell and its forward neighbours".
const FORWARD: [(i32, i32, i32); 14] = [
    (0, 0, 0),
    (1, 0, 0),
    (-1, 1, 0),
    (0, 1, 0),
    (1, 1, 0),
    (-1, -1, 1),
    (0, -1, 1),
    (1, -1, 1),
    (-1, 0, 1),
    (0, 0, 1),
    (1, 0, 1),
    (-1, 1, 1),
    (0, 1, 1),
    (1, 1, 1),
];

/// Where a body sits in the grid.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
struct CellKey {
    level: u32,
    x: i32,
    y: i32,
    z: i32,
}

/// The hierarchical grid (see the module docs). Keeps its buffers between steps.
#[derive(Debug, Default)]
pub(crate) struct Hierarchy {
    /// Where every level's cell (0, 0, 0) has its low corner (the grid's origin).
    origin: DVec3,
    cells: Vec<f64>,
    inverse_cells: Vec<f64>,
    /// Level-0 buckets are `2^bits` per axis.
    bits: u32,
    mask: usize,
    /// Every body's current cell.
    keys: Vec<CellKey>,
    /// Bodies per level (sorted and overlay).
    level_counts: Vec<u32>,
    /// Bit `L` set when level `L` holds a body: a query visits only those levels.
    occupied: u64,
    /// The largest box on each level (at most its cell): a body overlapping a query box has its
    /// lower corner at most this far below the query's.
    level_extents: Vec<f64>,
    /// The sorted arrays: bucket `b` holds sorted positions `start[b]..start[b + 1]`.
    start: Vec<u32>,
    order: Vec<u32>,
    sorted_keys: Vec<CellKey>,
    sorted_boxes: Vec<Aabb>,
    sorted_position: Vec<u32>,
    /// The overlay: bodies that left their sorted cell, in bucket lists.
    in_overlay: Vec<bool>,
    overlay_heads: Vec<u32>,
    next: Vec<u32>,
    prev: Vec<u32>,
    /// Body `i`'s entries in the arrays above are this step's when `stamp[i] == epoch`;
    /// otherwise the hierarchy does not hold it. (The arrays are never cleared: a step costs
    /// the bodies held, not all bodies.)
    stamp: Vec<u32>,
    epoch: u32,
    overlay_level_counts: Vec<u32>,
    /// The highest level any body has been on this step.
    highest: usize,
    /// Bodies on each level, while there are few of them (big spheres: a dome, walls):
    /// testing them directly beats visiting cells. May hold bodies that have since left the
    /// level; each body at most once.
    members: Vec<Vec<u32>>,
    /// Every body held this step, while there are at most [`HELD_FEW`] (a dome, a box's walls
    /// and the bodies that left the grid): a query tests them directly, whatever their levels.
    few: Vec<u32>,
    /// How many bodies the hierarchy holds this step.
    held: usize,
}

/// Levels with at most this many bodies are scanned through their member lists.
const FEW: usize = 16;

/// While the hierarchy holds at most this many bodies, a query tests each directly (their
/// boxes stay in the cache between queries): cheaper than visiting the cells of the levels
/// they are on, which for the bodies that left the grid (the lowest level) means hashing and
/// walking some 8 to 27 cells. The 100k shower's grid loses up to 40 bodies in a step.
const HELD_FEW: usize = 64;

impl Hierarchy {
    /// Rebuilds the grid with level-0 cells of side `base` counted from `origin`, holding the
    /// bodies `held..` of `boxes`; bodies `..held` may join later through
    /// [`Hierarchy::update`].
    pub fn rebuild(&mut self, boxes: &[Aabb], held: usize, base: f64, origin: DVec3) {
        let n = boxes.len();
        self.origin = origin;
        self.cells.clear();
        self.inverse_cells.clear();
        for level in 0..LEVELS {
            let cell = base * 2f64.powi(level as i32);
            self.cells.push(cell);
            self.inverse_cells.push(1.0 / cell);
        }
        // Buckets: a power of two per axis, at least twice the bodies held and an eighth of
        // those that may join.
        self.bits = 1;
        while (1usize << (3 * self.bits)) < (2 * (n - held)).max(n / 8) {
            self.bits += 1;
        }
        let buckets = 1usize << (3 * self.bits);
        self.mask = buckets - 1;

        self.epoch = self.epoch.wrapping_add(1);
        if self.epoch == 0 {
            self.stamp.iter_mut().for_each(|s| *s = 0);
            self.epoch = 1;
        }
        if self.stamp.len() < n {
            self.stamp.resize(n, 0);
            self.keys.resize(n, CellKey::default());
            self.sorted_position.resize(n, 0);
            self.in_overlay.resize(n, false);
            self.next.resize(n, NONE);
            self.prev.resize(n, NONE);
        }
        self.level_counts.clear();
        self.level_counts.resize(LEVELS, 0);
        self.occupied = 0;
        self.level_extents.clear();
        self.level_extents.resize(LEVELS, 0.0);
        self.overlay_level_counts.clear();
        self.overlay_level_counts.resize(LEVELS, 0);
        // Room for the most buckets any number held could ask for (twice all bodies), so a
        // step with more stragglers than the last allocates nothing.
        let mut most = 8usize;
        while most < 2 * n {
            most *= 8;
        }
        let most = most.max(buckets);
        self.start.clear();
        self.start.reserve(most + 1);
        self.start.resize(buckets + 1, 0);
        // The short lists at their longest from the start: a step that first fills one must
        // not allocate.
        self.members
            .resize_with(LEVELS, || Vec::with_capacity(FEW + 1));
        self.members.iter_mut().for_each(Vec::clear);
        self.few.clear();
        self.few.reserve(HELD_FEW);
        self.held = n - held;
        self.highest = 0;
        for (i, b) in boxes.iter().enumerate().skip(held) {
            let key = self.key_of(b);
            self.highest = self.highest.max(key.level as usize);
            if self.members[key.level as usize].len() <= FEW {
                self.members[key.level as usize].push(i as u32);
            }
            if self.held <= HELD_FEW {
                self.few.push(i as u32);
            }
            self.count_in(key.level);
            let extent = &mut self.level_extents[key.level as usize];
            *extent = extent.max(b.extent());
            let bucket = self.bucket(&key);
            self.start[bucket + 1] += 1;
            self.keys[i] = key;
            self.stamp[i] = self.epoch;
            self.in_overlay[i] = false;
        }
        for b in 0..buckets {
            self.start[b + 1] += self.start[b];
        }
        // Sized for every body, so a step with more stragglers than the last allocates nothing.
        let m = n - held;
        self.order.clear();
        self.order.reserve(n);
        self.order.resize(m, 0);
        self.sorted_keys.clear();
        self.sorted_keys.reserve(n);
        self.sorted_keys.resize(m, CellKey::default());
        self.sorted_boxes.clear();
        self.sorted_boxes.reserve(n);
        self.sorted_boxes.resize(m, Aabb::default());
        // Place bodies; `start[b]` ends as the end of bucket b - 1's range, so shift back after.
        for (i, placed) in boxes.iter().enumerate().skip(held) {
            let key = &self.keys[i];
            let b = self.bucket(key);
            let p = self.start[b] as usize;
            self.start[b] += 1;
            self.order[p] = i as u32;
            self.sorted_keys[p] = *key;
            self.sorted_boxes[p] = *placed;
            self.sorted_position[i] = p as u32;
        }
        for b in (1..=buckets).rev() {
            self.start[b] = self.start[b - 1];
        }
        self.start[0] = 0;

        self.overlay_heads.clear();
        self.overlay_heads.reserve(most);
        self.overlay_heads.resize(buckets, NONE);
    }

    #[inline]
    fn bucket(&self, key: &CellKey) -> usize {
        if key.level == 0 {
            let m = (1usize << self.bits) - 1;
            (key.x as usize & m)
                | ((key.y as usize & m) << self.bits)
                | ((key.z as usize & m) << (2 * self.bits))
        } else {
            let mut h = (key.x as u32 as u64).wrapping_mul(0x9E37_79B9_7F4A_7C15);
            h ^= (key.y as u32 as u64).wrapping_mul(0xC2B2_AE3D_27D4_EB4F);
            h ^= (key.z as u32 as u64).wrapping_mul(0x1656_67B1_9E37_79F9);
            h ^= u64::from(key.level).wrapping_mul(0x27D4_EB2F_1656_67C5);
            h ^= h >> 29;
            (h as usize) & self.mask
        }
    }

    fn level_for(&self, b: &Aabb) -> u32 {
        let extent = b.extent();
        if extent.is_nan() || extent > self.cells[LEVELS - 1] {
            return (LEVELS - 1) as u32;
        }
        let mut level = 0;
        while self.cells[level] < extent {
            level += 1;
        }
        level as u32
    }

    #[inline]
    fn key_at(&self, level: u32, point: DVec3) -> CellKey {
        let inverse = self.inverse_cells[level as usize];
        let point = point - self.origin;
        CellKey {
            level,
            x: floor_i32(point.x * inverse),
            y: floor_i32(point.y * inverse),
            z: floor_i32(point.z * inverse),
        }
    }

    fn key_of(&self, b: &Aabb) -> CellKey {
        self.key_at(self.level_for(b), b.lo)
    }

    /// Body `i`'s box is now `b` (joining the hierarchy if it was not in it).
    pub fn update(&mut self, i: usize, b: &Aabb) {
        let key = self.key_of(b);
        let extent = &mut self.level_extents[key.level as usize];
        *extent = extent.max(b.extent());
        self.highest = self.highest.max(key.level as usize);
        if self.stamp[i] != self.epoch {
            self.stamp[i] = self.epoch;
            self.in_overlay[i] = true;
            self.keys[i] = key;
            self.count_in(key.level);
            self.add_member(i, key.level);
            self.overlay_insert(i as u32);
            self.held += 1;
            if self.held <= HELD_FEW {
                self.few.push(i as u32);
            }
            return;
        }
        if !self.in_overlay[i] {
            let p = self.sorted_position[i] as usize;
            if key == self.keys[i] {
                self.sorted_boxes[p] = *b;
                return;
            }
            // Leave the sorted arrays for the overlay.
            self.sorted_keys[p].level = GONE;
            self.in_overlay[i] = true;
        } else {
            if key == self.keys[i] {
                return;
            }
            self.overlay_remove(i as u32);
        }
        self.count_out(self.keys[i].level);
        self.keys[i] = key;
        self.count_in(key.level);
        self.add_member(i, key.level);
        self.overlay_insert(i as u32);
    }

    /// One more body on `level`.
    fn count_in(&mut self, level: u32) {
        self.level_counts[level as usize] += 1;
        self.occupied |= 1 << level;
    }

    /// One body fewer on `level`.
    fn count_out(&mut self, level: u32) {
        self.level_counts[level as usize] -= 1;
        if self.level_counts[level as usize] == 0 {
            self.occupied &= !(1 << level);
        }
    }

    fn add_member(&mut self, i: usize, level: u32) {
        let members = &mut self.members[level as usize];
        if members.len() <= FEW && !members.contains(&(i as u32)) {
            members.push(i as u32);
        }
    }

    fn overlay_insert(&mut self, i: u32) {
        let key = self.keys[i as usize];
        let bucket = self.bucket(&key);
        let head = self.overlay_heads[bucket];
        self.prev[i as usize] = NONE;
        self.next[i as usize] = head;
        if head != NONE {
            self.prev[head as usize] = i;
        }
        self.overlay_heads[bucket] = i;
        self.overlay_level_counts[key.level as usize] += 1;
    }

    fn overlay_remove(&mut self, i: u32) {
        let key = self.keys[i as usize];
        let (p, n) = (self.prev[i as usize], self.next[i as usize]);
        if p == NONE {
            let bucket = self.bucket(&key);
            self.overlay_heads[bucket] = n;
        } else {
            self.next[p as usize] = n;
        }
        if n != NONE {
            self.prev[n as usize] = p;
        }
        self.overlay_level_counts[key.level as usize] -= 1;
    }

    /// Calls `f(j)` for every body in `cell` (sorted and overlay), each once.
    #[inline]
    fn walk(&self, cell: CellKey, f: &mut impl FnMut(usize)) {
        let b = self.bucket(&cell);
        for p in self.start[b] as usize..self.start[b + 1] as usize {
            if self.sorted_keys[p] == cell {
                f(self.order[p] as usize);
            }
        }
        self.walk_overlay(cell, f);
    }

    /// Calls `f(j)` for every overlay body in `cell`.
    #[inline]
    fn walk_overlay(&self, cell: CellKey, f: &mut impl FnMut(usize)) {
        if self.overlay_level_counts[cell.level as usize] > 0 {
            let mut j = self.overlay_heads[self.bucket(&cell)];
            while j != NONE {
                if self.keys[j as usize] == cell {
                    f(j as usize);
                }
                j = self.next[j as usize];
            }
        }
    }

    /// Whether the level-0 cells `xlo..=xhi` of one row sit in consecutive buckets.
    #[inline]
    fn contiguous(&self, xlo: i32, xhi: i32) -> bool {
        let m = (1usize << self.bits) - 1;
        (xlo as usize & m) + (xhi - xlo) as usize <= m
    }

    /// Calls `f(q)` for each sorted position `q` in `from..to` on `level`, in row `(y, z)`,
    /// with `x` in `xlo..=xhi`.
    #[inline]
    #[allow(clippy::too_many_arguments)]
    fn scan(
        &self,
        from: usize,
        to: usize,
        level: u32,
        y: i32,
        z: i32,
        xlo: i32,
        xhi: i32,
        f: &mut impl FnMut(usize),
    ) {
        for q in from..to {
            let k = &self.sorted_keys[q];
            if k.y == y && k.z == z && k.level == level && k.x >= xlo && k.x <= xhi {
                f(q);
            }
        }
    }

    /// Calls `f(q)` for each sorted position `q` (from `from` on, in the first cell) in the
    /// level-0 cells `xlo..=xhi` of row `(y, z)`.
    #[inline]
    fn scan_row(
        &self,
        from: Option<usize>,
        y: i32,
        z: i32,
        xlo: i32,
        xhi: i32,
        f: &mut impl FnMut(usize),
    ) {
        let cell = |x| CellKey { level: 0, x, y, z };
        if self.contiguous(xlo, xhi) {
            let first = self.bucket(&cell(xlo));
            let last = self.bucket(&cell(xhi));
            let from = from.unwrap_or(self.start[first] as usize);
            self.scan(from, self.start[last + 1] as usize, 0, y, z, xlo, xhi, f);
        } else {
            for x in xlo..=xhi {
                let b = self.bucket(&cell(x));
                let from = match from {
                    Some(from) if x == xlo => from,
                    _ => self.start[b] as usize,
                };
                self.scan(from, self.start[b + 1] as usize, 0, y, z, x, x, f);
            }
        }
    }

    /// Calls `f(j)` for every body `j` at a level in `levels` whose box may overlap `q`.
    fn visit(&self, q: &Aabb, levels: std::ops::Range<usize>, f: &mut impl FnMut(usize)) {
        // The occupied levels within `levels`, lowest first.
        let below = |end: usize| {
            if end >= 64 {
                u64::MAX
            } else {
                (1u64 << end) - 1
            }
        };
        let mut left = self.occupied & below(levels.end) & !below(levels.start);
        while left != 0 {
            let level = left.trailing_zeros() as usize;
            left &= left - 1;
            let count = self.level_counts[level];
            let members = &self.members[level];
            if members.len() <= FEW && count as usize <= members.len() {
                // Every body on this level is in the list: test them directly.
                for &j in members {
                    if self.keys[j as usize].level as usize == level {
                        f(j as usize);
                    }
                }
                continue;
            }
            // At most the cell, except on the top level, which also holds anything larger.
            let reach = self.level_extents[level];
            let lo = self.key_at(level as u32, q.lo - DVec3::splat(reach));
            let hi = self.key_at(level as u32, q.hi);
            let cells = (f64::from(hi.x) - f64::from(lo.x) + 1.0)
                * (f64::from(hi.y) - f64::from(lo.y) + 1.0)
                * (f64::from(hi.z) - f64::from(lo.z) + 1.0);
            if cells > f64::from(count) + 27.0 {
                // A big box over a fine level: scanning the level's bodies is cheaper.
                for (j, key) in self.keys.iter().enumerate() {
                    if key.level as usize == level && self.stamp[j] == self.epoch {
                        f(j);
                    }
                }
                continue;
            }
            for z in lo.z..=hi.z {
                for y in lo.y..=hi.y {
                    if level == 0 {
                        self.scan_row(None, y, z, lo.x, hi.x, &mut |q| f(self.order[q] as usize));
                        if self.overlay_level_counts[0] > 0 {
                            for x in lo.x..=hi.x {
                                self.walk_overlay(CellKey { level: 0, x, y, z }, f);
                            }
                        }
                    } else {
                        for x in lo.x..=hi.x {
                            let level = level as u32;
                            self.walk(CellKey { level, x, y, z }, f);
                        }
                    }
                }
            }
        }
    }

    /// Calls `f(i, j)` with `i < j` for every pair of overlapping boxes, each pair once.
    /// Call right after [`Hierarchy::rebuild`] with the same boxes.
    pub fn pairs(&self, boxes: &[Aabb], mut f: impl FnMut(usize, usize)) {
        // In sorted order, so memory is read nearly in order. A pair on one level is reported
        // from the forward side of its pair of cells (in one cell: from the earlier entry); a
        // pair across levels by the body on the lower level.
        let highest = self.highest;
        for (p, (key, bp)) in self.sorted_keys.iter().zip(&self.sorted_boxes).enumerate() {
            let i = self.order[p] as usize;
            if key.level == 0 {
                // Rows of cells along x sit in consecutive buckets: the own cell (after p) and
                // the next one, then three cells in each of the four forward rows.
                let mut report = |q: usize| {
                    if bp.overlaps(&self.sorted_boxes[q]) {
                        let j = self.order[q] as usize;
                        f(i.min(j), i.max(j));
                    }
                };
                let (x, y, z) = (key.x, key.y, key.z);
                self.scan_row(Some(p + 1), y, z, x, x.wrapping_add(1), &mut report);
                for (dy, dz) in [(1, 0), (-1, 1), (0, 1), (1, 1)] {
                    let (y, z) = (y.wrapping_add(dy), z.wrapping_add(dz));
                    self.scan_row(
                        None,
                        y,
                        z,
                        x.wrapping_sub(1),
                        x.wrapping_add(1),
                        &mut report,
                    );
                }
            } else if key.level as usize == LEVELS - 1
                && self.level_extents[LEVELS - 1] > self.cells[LEVELS - 1]
            {
                // Bodies larger than the top level's cells (absurdly large: 2^40 typical
                // boxes): their cells do not tell who they meet, so test every later one.
                for q in p + 1..self.sorted_keys.len() {
                    if self.sorted_keys[q].level == key.level && bp.overlaps(&self.sorted_boxes[q])
                    {
                        let j = self.order[q] as usize;
                        f(i.min(j), i.max(j));
                    }
                }
            } else {
                self.pairs_in_cells(p, key, bp, &mut f);
            }
            let level = key.level as usize;
            if level < highest {
                self.visit(bp, level + 1..highest + 1, &mut |j| {
                    if bp.overlaps(&boxes[j]) {
                        f(i.min(j), i.max(j));
                    }
                });
            }
        }
    }

    /// Pairs of the body at sorted position `p` with the bodies of its own cell (after it) and
    /// the 13 forward neighbour cells, on its (hashed) level.
    fn pairs_in_cells(&self, p: usize, key: &CellKey, bp: &Aabb, f: &mut impl FnMut(usize, usize)) {
        let i = self.order[p] as usize;
        {
            for (n, &(dx, dy, dz)) in FORWARD.iter().enumerate() {
                let cell = CellKey {
                    level: key.level,
                    x: key.x.wrapping_add(dx),
                    y: key.y.wrapping_add(dy),
                    z: key.z.wrapping_add(dz),
                };
                let b = self.bucket(&cell);
                let from = if n == 0 {
                    p + 1
                } else {
                    self.start[b] as usize
                };
                for q in from..self.start[b + 1] as usize {
                    if self.sorted_keys[q] == cell && bp.overlaps(&self.sorted_boxes[q]) {
                        let j = self.order[q] as usize;
                        f(i.min(j), i.max(j));
                    }
                }
            }
        }
    }

    /// [`Hierarchy::overlapping`] for two bodies at once (`fa` for `a`'s, `fb` for `b`'s),
    /// reading the bodies it holds once for both while it holds few.
    pub fn overlapping_both(
        &self,
        (a, qa): (usize, &Aabb),
        (b, qb): (usize, &Aabb),
        boxes: &[Aabb],
        mut fa: impl FnMut(usize),
        mut fb: impl FnMut(usize),
    ) {
        if self.held <= HELD_FEW {
            for &j in &self.few {
                let j = j as usize;
                let bj = &boxes[j];
                if j != a && qa.overlaps(bj) {
                    fa(j);
                }
                if j != b && qb.overlaps(bj) {
                    fb(j);
                }
            }
            return;
        }
        self.overlapping(a, qa, boxes, fa);
        self.overlapping(b, qb, boxes, fb);
    }

    /// Calls `f(j)` for every body `j != i` it holds whose box overlaps `q` (`boxes` current).
    pub fn overlapping(&self, i: usize, q: &Aabb, boxes: &[Aabb], mut f: impl FnMut(usize)) {
        if self.held <= HELD_FEW {
            for &j in &self.few {
                let j = j as usize;
                if j != i && q.overlaps(&boxes[j]) {
                    f(j);
                }
            }
            return;
        }
        self.visit(q, 0..self.highest + 1, &mut |j| {
            if j != i && q.overlaps(&boxes[j]) {
                f(j);
            }
        });
    }
}
