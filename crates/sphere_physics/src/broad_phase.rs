//! Broad phase: which bodies' boxes may overlap, in O(1) per body.
//!
//! A hierarchical hash grid. Level `L` has cells of side `base · 2^L`; each body lives at the
//! lowest level whose cells are at least as large as its box, in the one cell that holds its
//! box's lower corner. A body whose box overlaps a query box therefore has its lower corner in
//! `[query.lo − cell, query.hi]` at its level: at most 3 cells per axis to visit. The base cell
//! is the median box size, so a shower of small spheres sits on level 0 and a huge fixed sphere
//! (a dome, a wall) sits alone on a high level, where small bodies find it in a few cells.
//!
//! Cells are hashed into buckets holding intrusive doubly linked lists, so moving one body after a
//! collision is O(1), and nothing allocates once the buffers have grown to the scene. Scenes of
//! a few bodies skip the grid: all pairs are cheaper.

use glam::DVec3;

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

    pub fn overlaps(&self, other: &Aabb) -> bool {
        self.lo.cmple(other.hi).all() && other.lo.cmple(self.hi).all()
    }

    fn extent(&self) -> f64 {
        (self.hi - self.lo).max_element()
    }
}

const NONE: u32 = u32::MAX;

/// A cell itself, then the 13 neighbours that follow it in (x, y, z) order: each unordered pair
/// of neighbouring cells appears once among "cell and its forward neighbours".
const FORWARD: [(i64, i64, i64); 14] = [
    (0, 0, 0),
    (0, 0, 1),
    (0, 1, -1),
    (0, 1, 0),
    (0, 1, 1),
    (1, -1, -1),
    (1, -1, 0),
    (1, -1, 1),
    (1, 0, -1),
    (1, 0, 0),
    (1, 0, 1),
    (1, 1, -1),
    (1, 1, 0),
    (1, 1, 1),
];

/// Below this many bodies, all pairs are tested directly.
const SMALL_SCENE: usize = 24;

/// Levels above the base: cells up to `base · 2^40`.
const MAX_LEVEL: u32 = 40;

/// Where a body sits in the grid.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
struct CellKey {
    level: u32,
    x: i64,
    y: i64,
    z: i64,
}

impl CellKey {
    fn bucket(&self, mask: usize) -> usize {
        let mut h = (self.x as u64).wrapping_mul(0x9E37_79B9_7F4A_7C15);
        h ^= (self.y as u64).wrapping_mul(0xC2B2_AE3D_27D4_EB4F);
        h ^= (self.z as u64).wrapping_mul(0x1656_67B1_9E37_79F9);
        h ^= u64::from(self.level).wrapping_mul(0x27D4_EB2F_1656_67C5);
        h ^= h >> 29;
        (h as usize) & mask
    }
}

/// The hierarchical hash grid (see the module docs). Keeps its buffers between steps.
#[derive(Debug, Default)]
pub(crate) struct BroadPhase {
    /// All pairs directly (small scenes).
    brute: bool,
    base: f64,
    inverse_cells: Vec<f64>,
    cells: Vec<f64>,
    mask: usize,
    heads: Vec<u32>,
    next: Vec<u32>,
    prev: Vec<u32>,
    keys: Vec<CellKey>,
    /// Bodies per level, to know which levels to visit.
    level_counts: Vec<u32>,
    scratch: Vec<f64>,
}

impl BroadPhase {
    /// Rebuilds the grid for `boxes`.
    pub fn rebuild(&mut self, boxes: &[Aabb]) {
        let n = boxes.len();
        self.brute = n <= SMALL_SCENE;
        if self.brute {
            return;
        }
        self.scratch.clear();
        self.scratch
            .extend(boxes.iter().map(Aabb::extent).filter(|e| e.is_finite()));
        let middle = self.scratch.len() / 2;
        let median = if self.scratch.is_empty() {
            1.0
        } else {
            *self
                .scratch
                .select_nth_unstable_by(middle, f64::total_cmp)
                .1
        };
        // The base cell holds every typical body (up to twice the median size) on level 0.
        let typical = self
            .scratch
            .iter()
            .copied()
            .filter(|&e| e <= 2.0 * median)
            .fold(0.0f64, f64::max);
        self.base = if typical > 0.0 { typical } else { 1.0 };
        self.cells.clear();
        self.inverse_cells.clear();
        for level in 0..=MAX_LEVEL {
            let cell = self.base * 2f64.powi(level as i32);
            self.cells.push(cell);
            self.inverse_cells.push(1.0 / cell);
        }
        let buckets = (2 * n).next_power_of_two();
        self.mask = buckets - 1;
        self.heads.clear();
        self.heads.resize(buckets, NONE);
        self.next.clear();
        self.next.resize(n, NONE);
        self.prev.clear();
        self.prev.resize(n, NONE);
        self.keys.clear();
        self.keys.resize(n, CellKey::default());
        self.level_counts.clear();
        self.level_counts.resize(MAX_LEVEL as usize + 1, 0);
        for (i, b) in boxes.iter().enumerate() {
            self.insert(i as u32, b);
        }
    }

    fn level_for(&self, b: &Aabb) -> u32 {
        let extent = b.extent();
        if extent.is_nan() || extent > self.cells[MAX_LEVEL as usize] {
            return MAX_LEVEL;
        }
        let mut level = 0;
        while self.cells[level as usize] < extent {
            level += 1;
        }
        level
    }

    fn key(&self, level: u32, point: DVec3) -> CellKey {
        let inverse = self.inverse_cells[level as usize];
        let c = |v: f64| (v * inverse).floor().clamp(-1e15, 1e15) as i64;
        CellKey {
            level,
            x: c(point.x),
            y: c(point.y),
            z: c(point.z),
        }
    }

    fn insert(&mut self, i: u32, b: &Aabb) {
        let level = self.level_for(b);
        let key = self.key(level, b.lo);
        let bucket = key.bucket(self.mask);
        let head = self.heads[bucket];
        self.keys[i as usize] = key;
        self.prev[i as usize] = NONE;
        self.next[i as usize] = head;
        if head != NONE {
            self.prev[head as usize] = i;
        }
        self.heads[bucket] = i;
        self.level_counts[level as usize] += 1;
    }

    fn remove(&mut self, i: u32) {
        let key = self.keys[i as usize];
        let (p, n) = (self.prev[i as usize], self.next[i as usize]);
        if p == NONE {
            self.heads[key.bucket(self.mask)] = n;
        } else {
            self.next[p as usize] = n;
        }
        if n != NONE {
            self.prev[n as usize] = p;
        }
        self.level_counts[key.level as usize] -= 1;
    }

    /// Body `i`'s box is now `b`.
    pub fn update(&mut self, i: usize, b: &Aabb) {
        if self.brute {
            return;
        }
        let level = self.level_for(b);
        if self.keys[i] == self.key(level, b.lo) {
            return;
        }
        self.remove(i as u32);
        self.insert(i as u32, b);
    }

    /// Calls `f(j)` for every body `j` at a level in `levels` whose box may overlap `q`
    /// (each once; the caller tests the boxes).
    fn visit(&self, q: &Aabb, levels: std::ops::RangeInclusive<u32>, f: &mut impl FnMut(usize)) {
        for level in levels {
            if self.level_counts[level as usize] == 0 {
                continue;
            }
            let cell = self.cells[level as usize];
            let lo = self.key(level, q.lo - DVec3::splat(cell));
            let hi = self.key(level, q.hi);
            let count =
                (hi.x - lo.x + 1) as f64 * (hi.y - lo.y + 1) as f64 * (hi.z - lo.z + 1) as f64;
            if count > self.level_counts[level as usize] as f64 + 27.0 {
                // A big box over a fine level: scanning the level's bodies is cheaper.
                for (j, key) in self.keys.iter().enumerate() {
                    if key.level == level {
                        f(j);
                    }
                }
                continue;
            }
            for x in lo.x..=hi.x {
                for y in lo.y..=hi.y {
                    for z in lo.z..=hi.z {
                        self.walk(CellKey { level, x, y, z }, f);
                    }
                }
            }
        }
    }

    /// Calls `f(i, j)` with `i < j` for every pair of overlapping boxes, each pair once.
    pub fn pairs(&self, boxes: &[Aabb], mut f: impl FnMut(usize, usize)) {
        if self.brute {
            for i in 0..boxes.len() {
                for j in i + 1..boxes.len() {
                    if boxes[i].overlaps(&boxes[j]) {
                        f(i, j);
                    }
                }
            }
            return;
        }
        // A pair on one level is reported once, from the cell pair's "forward" side: the body
        // visits its own cell (partners of higher index) and the 13 cells after it. A pair
        // across levels is reported by the body on the lower level.
        for (i, bi) in boxes.iter().enumerate() {
            let key = self.keys[i];
            for (n, (dx, dy, dz)) in FORWARD.iter().enumerate() {
                let cell = CellKey {
                    level: key.level,
                    x: key.x + dx,
                    y: key.y + dy,
                    z: key.z + dz,
                };
                self.walk(cell, &mut |j| {
                    if (n > 0 || j > i) && bi.overlaps(&boxes[j]) {
                        f(i.min(j), i.max(j));
                    }
                });
            }
            if key.level < MAX_LEVEL {
                self.visit(bi, key.level + 1..=MAX_LEVEL, &mut |j| {
                    if bi.overlaps(&boxes[j]) {
                        f(i.min(j), i.max(j));
                    }
                });
            }
        }
    }

    /// Calls `f(j)` for every body in `cell`.
    fn walk(&self, cell: CellKey, f: &mut impl FnMut(usize)) {
        let mut j = self.heads[cell.bucket(self.mask)];
        while j != NONE {
            if self.keys[j as usize] == cell {
                f(j as usize);
            }
            j = self.next[j as usize];
        }
    }

    /// Calls `f(j)` for every body `j != i` whose box overlaps body `i`'s.
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
        self.visit(bi, 0..=MAX_LEVEL, &mut |j| {
            if j != i && bi.overlaps(&boxes[j]) {
                f(j);
            }
        });
    }
}
