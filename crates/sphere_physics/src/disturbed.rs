//! Where bodies were added, changed or removed through the world since the last step: the
//! awake bodies touching one of those places are calm from then on only (see
//! [`Sleeper::disturbed_at`](crate::sleep::Sleeper::disturbed_at)). The places are found
//! again through hash grids over them, one for each size of place within a factor of two, so
//! that a step after many changes (a game setting the velocities of thousands of bodies
//! between two steps) costs each awake body a look at a few cells of each size, not at every
//! place, whatever the sizes.

use glam::DVec3;

/// Past this many places the grids are used; up to it each body looks at every place.
const FEW: usize = 16;

/// A body's reach spanning more cells than this in one size's grid looks at every place of
/// that size instead (a body far larger than those places).
const MAX_CELLS: i64 = 343;

/// The places of one size (radii within a factor of two) and their grid.
#[derive(Clone, Copy, Debug)]
struct Size {
    /// The places' `log2(radius)`, rounded down.
    exponent: i32,
    /// The largest radius among them.
    widest: f64,
    /// The grid's cell size: as wide as the reach of a body of that radius, both ways.
    cell: f64,
    /// The places, as a range of `Disturbed::by_size`.
    from: usize,
    to: usize,
}

/// The places, and the grids over them, laid out when a body first asks after
/// [`Disturbed::prepare`].
#[derive(Debug, Default)]
pub(crate) struct Disturbed {
    /// Centre and radius of each place.
    places: Vec<(DVec3, f64)>,
    /// More places than a few per body were given since the last step: every awake body is
    /// disturbed.
    everywhere: bool,
    /// How far beyond a place a body's surface may be and still touch it, as a fraction of
    /// the body's radius, and in the world's units (set by [`Disturbed::prepare`]).
    contact: f64,
    margin: f64,
    /// Whether the grids below are laid out over the places.
    laid_out: bool,
    /// The sizes of the places, smallest first (none while the places are few and looked at
    /// one by one).
    sizes: Vec<Size>,
    /// The places by size: `(exponent, place)`, sorted.
    by_size: Vec<(i32, u32)>,
    /// Each place by its size and the cell of its centre, `(key, place)`, sorted by key.
    cells: Vec<(u64, u32)>,
    /// A box around every place grown by the margin and by its radius: a body whose reach
    /// misses it touches none.
    bounds: (DVec3, DVec3),
}

impl Disturbed {
    /// A sphere of `radius` at `centre` was added, changed or removed there, in a world of
    /// `bodies` bodies.
    pub fn add(&mut self, bodies: usize, centre: DVec3, radius: f64) {
        if self.everywhere {
            return;
        }
        if self.places.len() >= bodies.saturating_mul(4).saturating_add(64) {
            // Each body changed several times over since the last step.
            self.clear();
            self.everywhere = true;
            return;
        }
        self.places.push((centre, radius));
    }

    /// Whether nothing was disturbed since the last step.
    pub fn is_empty(&self) -> bool {
        !self.everywhere && self.places.is_empty()
    }

    /// Forgets every place.
    pub fn clear(&mut self) {
        self.places.clear();
        self.sizes.clear();
        self.by_size.clear();
        self.cells.clear();
        self.everywhere = false;
        self.laid_out = false;
    }

    /// Sets what [`Disturbed::touches`] counts as touching: a body within `contact` of its
    /// radius plus `margin` of a place (how far a calm body may have moved since the places
    /// were given).
    pub fn prepare(&mut self, contact: f64, margin: f64) {
        (self.contact, self.margin) = (contact, margin);
        self.laid_out = false;
    }

    /// Lays out a grid over the places of each size: each place in the cell of its centre, a
    /// body looking at the cells its reach grown by the size's largest radius meets (8 for a
    /// body of that size, more for a larger one).
    fn lay_out(&mut self) {
        self.laid_out = true;
        self.sizes.clear();
        self.by_size.clear();
        self.cells.clear();
        let grown = |&(centre, radius): &(DVec3, f64)| {
            let reach = DVec3::splat(radius + self.margin);
            (centre - reach, centre + reach)
        };
        self.bounds = self
            .places
            .iter()
            .map(grown)
            .reduce(|a, b| (a.0.min(b.0), a.1.max(b.1)))
            .unwrap_or((DVec3::INFINITY, DVec3::NEG_INFINITY));
        if self.everywhere || self.places.len() <= FEW {
            return;
        }
        self.by_size.extend(
            (0..self.places.len() as u32).map(|k| (exponent(self.places[k as usize].1), k)),
        );
        self.by_size.sort_unstable();
        let mut from = 0;
        while from < self.by_size.len() {
            let exponent = self.by_size[from].0;
            let to = from + self.by_size[from..].partition_point(|p| p.0 == exponent);
            let widest = self.by_size[from..to]
                .iter()
                .fold(0.0f64, |w, p| w.max(self.places[p.1 as usize].1));
            let cell = (2.0 * ((2.0 + self.contact) * widest + self.margin)).max(f64::MIN_POSITIVE);
            self.sizes.push(Size {
                exponent,
                widest,
                cell,
                from,
                to,
            });
            from = to;
        }
        for size in &self.sizes {
            for &(_, k) in &self.by_size[size.from..size.to] {
                let c = cell_of(self.places[k as usize].0, size.cell);
                self.cells.push((key(size.exponent, c), k));
            }
        }
        self.cells.sort_unstable();
    }

    /// Whether a body of `radius` at `centre` touches a place (within the contact and margin
    /// given to [`Disturbed::prepare`]), or every body is disturbed.
    pub fn touches(&mut self, centre: DVec3, radius: f64) -> bool {
        if self.everywhere {
            return true;
        }
        if !self.laid_out {
            self.lay_out();
        }
        let own = radius * (1.0 + self.contact);
        // Grown by the rounding allowance, as the grids' look is (an ulp at the threshold).
        let bound = own + 4.0 * f64::EPSILON * (centre.abs().max_element() + own);
        let (low, high) = self.bounds;
        if (centre + DVec3::splat(bound)).cmplt(low).any()
            || (centre - DVec3::splat(bound)).cmpgt(high).any()
        {
            return false;
        }
        let near = |k: u32| {
            let (place, place_radius) = self.places[k as usize];
            (centre - place).length() - radius - place_radius <= self.contact * radius + self.margin
        };
        if self.sizes.is_empty() {
            return (0..self.places.len() as u32).any(near);
        }
        self.sizes.iter().any(|size| {
            // Every place of this size touching the body has its centre within this reach.
            let reach = own + self.margin + size.widest;
            let grown = reach + 4.0 * f64::EPSILON * (centre.abs().max_element() + reach);
            let low = cell_of(centre - DVec3::splat(grown), size.cell);
            let high = cell_of(centre + DVec3::splat(grown), size.cell);
            if cell_count(low, high) > MAX_CELLS {
                return self.by_size[size.from..size.to]
                    .iter()
                    .any(|&(_, k)| near(k));
            }
            let mut found = false;
            for_each_cell(low, high, |c| {
                if found {
                    return;
                }
                let key = key(size.exponent, c);
                let from = self.cells.partition_point(|e| e.0 < key);
                found = self.cells[from..]
                    .iter()
                    .take_while(|e| e.0 == key)
                    .any(|e| near(e.1));
            });
            found
        })
    }
}

/// `log2(radius)` rounded down (radii are positive and finite).
fn exponent(radius: f64) -> i32 {
    radius.log2().floor().clamp(-2000.0, 2000.0) as i32
}

/// The cell of a point in a grid of cells `cell` wide (saturating far out).
fn cell_of(point: DVec3, cell: f64) -> [i64; 3] {
    let at = |x: f64| (x / cell).floor() as i64;
    [at(point.x), at(point.y), at(point.z)]
}

/// How many cells span `low..=high` (saturating).
fn cell_count(low: [i64; 3], high: [i64; 3]) -> i64 {
    (0..3).fold(1i64, |n, a| {
        n.saturating_mul(high[a].saturating_sub(low[a]).saturating_add(1))
    })
}

/// Calls `f` with each cell of `low..=high` (at most [`MAX_CELLS`] of them).
fn for_each_cell(low: [i64; 3], high: [i64; 3], mut f: impl FnMut([i64; 3])) {
    for x in low[0]..=high[0] {
        for y in low[1]..=high[1] {
            for z in low[2]..=high[2] {
                f([x, y, z]);
            }
        }
    }
}

/// A cell's key in the grid of one size: the size and coordinates mixed (two cells may share
/// one, which costs a look only).
fn key(exponent: i32, [x, y, z]: [i64; 3]) -> u64 {
    let mix = |v: i64, m: u64| (v as u64).wrapping_mul(m);
    let h = mix(x, 0x9E37_79B9_7F4A_7C15)
        ^ mix(y, 0xC2B2_AE3D_27D4_EB4F)
        ^ mix(z, 0x1656_67B1_9E37_79F9)
        ^ mix(i64::from(exponent), 0xFF51_AFD7_ED55_8CCD);
    h ^ (h >> 29)
}
