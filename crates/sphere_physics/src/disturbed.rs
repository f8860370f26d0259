//! Where dynamic bodies were added, changed or removed through the world since the last step:
//! the awake bodies touching one of those places are calm from then on only (see
//! [`Sleeper::disturbed_at`](crate::sleep::Sleeper::disturbed_at)). The places are found
//! again through a hash grid over them, so that a step after many changes (a game setting
//! the velocities of thousands of bodies between two steps) costs each awake body a few cells'
//! look, not a look at every place.

use glam::DVec3;

/// Past this many places the grid is used; up to it each body looks at every place.
const FEW: usize = 16;

/// A body's reach spanning more cells than this looks at every place instead of the grid's.
const MAX_CELLS: i64 = 64;

/// The places, and a grid over them, laid out when a body first asks after
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
    /// Whether the grid below is laid out over the places.
    laid_out: bool,
    /// The grid's cell size (0 while the places are few and looked at one by one), and the
    /// largest radius of a place in it.
    cell: f64,
    widest: f64,
    /// Each place in the grid by the cell of its centre, `(cell key, place)`, sorted by key.
    cells: Vec<(u64, u32)>,
    /// Places more than twice the median's radius: looked at by every body.
    big: Vec<u32>,
    /// A box around every place grown by the margin and by its radius: a body whose reach
    /// misses it touches none.
    bounds: (DVec3, DVec3),
    /// Scratch: the places' radii, for their median.
    radii: Vec<f64>,
}

impl Disturbed {
    /// A dynamic sphere of `radius` at `centre` was added, changed or removed there, in a
    /// world of `bodies` bodies.
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
        self.cells.clear();
        self.big.clear();
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

    /// Lays out the grid over the places: each place by the cell of its centre, a body
    /// looking at the cells its reach grown by the largest radius in the grid meets (8 for a
    /// body of the places' size).
    fn lay_out(&mut self) {
        self.laid_out = true;
        self.cells.clear();
        self.big.clear();
        self.cell = 0.0;
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
        self.radii.clear();
        self.radii.extend(self.places.iter().map(|p| p.1));
        let middle = self.radii.len() / 2;
        let (_, &mut median, _) = self.radii.select_nth_unstable_by(middle, f64::total_cmp);
        self.widest = 0.0;
        for (k, &(_, radius)) in self.places.iter().enumerate() {
            if radius > 2.0 * median {
                self.big.push(k as u32);
            } else {
                self.widest = self.widest.max(radius);
            }
        }
        // Cells as wide as the reach of a body of the places' size, both ways: it looks at
        // 8 of them.
        self.cell =
            (2.0 * ((2.0 + self.contact) * self.widest + self.margin)).max(f64::MIN_POSITIVE);
        for (k, &(centre, radius)) in self.places.iter().enumerate() {
            if radius <= 2.0 * median {
                let (low, _) = self.span(centre, 0.0);
                self.cells.push((key(low[0], low[1], low[2]), k as u32));
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
        let reach = DVec3::splat(radius * (1.0 + self.contact));
        let (low, high) = self.bounds;
        if (centre + reach).cmplt(low).any() || (centre - reach).cmpgt(high).any() {
            return false;
        }
        let near = |&(place, place_radius): &(DVec3, f64)| {
            (centre - place).length() - radius - place_radius <= self.contact * radius + self.margin
        };
        if self.cell == 0.0 {
            return self.places.iter().any(near);
        }
        if self.big.iter().any(|&k| near(&self.places[k as usize])) {
            return true;
        }
        // Every place of the grid touching the body has its centre within this reach.
        let reach = radius * (1.0 + self.contact) + self.margin + self.widest;
        let (low, high) = self.span(centre, reach);
        if cell_count(low, high) > MAX_CELLS {
            return self.places.iter().any(near);
        }
        let mut found = false;
        for_each_cell(low, high, |key| {
            if found {
                return;
            }
            let from = self.cells.partition_point(|c| c.0 < key);
            found = self.cells[from..]
                .iter()
                .take_while(|c| c.0 == key)
                .any(|c| near(&self.places[c.1 as usize]));
        });
        found
    }

    /// The cells (lowest and highest, inclusive) of the box of half-size `reach` around
    /// `centre`, grown by a few units in the last place of its coordinates (so that rounding
    /// never leaves out a cell the box meets).
    fn span(&self, centre: DVec3, reach: f64) -> ([i64; 3], [i64; 3]) {
        let grown = reach + 4.0 * f64::EPSILON * centre.abs().max_element();
        let cell = |x: f64| (x / self.cell).floor() as i64;
        let (low, high) = (centre - DVec3::splat(grown), centre + DVec3::splat(grown));
        (
            [cell(low.x), cell(low.y), cell(low.z)],
            [cell(high.x), cell(high.y), cell(high.z)],
        )
    }
}

/// How many cells span `low..=high` (saturating).
fn cell_count(low: [i64; 3], high: [i64; 3]) -> i64 {
    (0..3).fold(1i64, |n, a| {
        n.saturating_mul(high[a].saturating_sub(low[a]).saturating_add(1))
    })
}

/// Calls `f` with the key of each cell of `low..=high` (at most [`MAX_CELLS`] of them).
fn for_each_cell(low: [i64; 3], high: [i64; 3], mut f: impl FnMut(u64)) {
    for x in low[0]..=high[0] {
        for y in low[1]..=high[1] {
            for z in low[2]..=high[2] {
                f(key(x, y, z));
            }
        }
    }
}

/// A cell's key: its coordinates mixed (two cells may share one, which costs a look only).
fn key(x: i64, y: i64, z: i64) -> u64 {
    let mix = |v: i64, m: u64| (v as u64).wrapping_mul(m);
    let h = mix(x, 0x9E37_79B9_7F4A_7C15)
        ^ mix(y, 0xC2B2_AE3D_27D4_EB4F)
        ^ mix(z, 0x1656_67B1_9E37_79F9);
    h ^ (h >> 29)
}
