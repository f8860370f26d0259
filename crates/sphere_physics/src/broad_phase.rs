//! Broad phase: which pairs of axis-aligned boxes overlap, by sort and sweep along x.

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
}

/// Sort-and-sweep over x. Keeps its scratch between calls: no allocation once warmed up.
#[derive(Debug, Default)]
pub(crate) struct SweepAndPrune {
    order: Vec<u32>,
}

impl SweepAndPrune {
    /// Calls `f(i, j)` with `i < j` for every pair of overlapping boxes.
    pub fn pairs(&mut self, boxes: &[Aabb], mut f: impl FnMut(usize, usize)) {
        self.order.clear();
        self.order.extend(0..boxes.len() as u32);
        self.order.sort_unstable_by(|&i, &j| {
            boxes[i as usize]
                .lo
                .x
                .total_cmp(&boxes[j as usize].lo.x)
                .then(i.cmp(&j))
        });
        for (k, &i) in self.order.iter().enumerate() {
            let bi = &boxes[i as usize];
            for &j in &self.order[k + 1..] {
                let bj = &boxes[j as usize];
                if bj.lo.x > bi.hi.x {
                    break;
                }
                if bi.overlaps(bj) {
                    f(i.min(j) as usize, i.max(j) as usize);
                }
            }
        }
    }
}
