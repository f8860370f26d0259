//! Scene generators: many spheres from a few numbers and a seed.
//!
//! A generator places spheres on a jittered lattice inside a box, so no two of them overlap
//! whatever the seed, and draws their jitter (and, for a gas, their directions) from a small
//! seeded generator of its own. The same seed gives the same spheres, bit for bit, on every
//! machine and with every version of the crate's dependencies.
//!
//! ```
//! use sphere_physics::generate::Generator;
//!
//! let shower = Generator::Shower {
//!     count: 100,
//!     seed: 1,
//!     min: [-1.0, 2.0, -1.0],
//!     max: [1.0, 4.0, 1.0],
//!     radius: 0.05,
//!     velocity: [0.0, 0.0, 0.0],
//!     density: 1.0,
//!     restitution: None,
//! };
//! let spheres = shower.spheres()?;
//! assert_eq!(spheres.len(), 100);
//! assert_eq!(spheres, shower.spheres()?);
//! # Ok::<(), sphere_physics::generate::GenerateError>(())
//! ```

use serde::{Deserialize, Serialize};

use crate::SphereSpec;

/// The most spheres a scene's generators may make, each and all together: ten million spheres
/// take some 7 GB to step (the description, the world's bodies and the solver's records), and
/// a larger count is far more likely a typo than a scene.
pub const MAX_GENERATED: u32 = 10_000_000;

fn one() -> f64 {
    1.0
}

fn wall_radius() -> f64 {
    1.0e4
}

fn yes() -> bool {
    true
}

/// A recipe for many spheres.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub enum Generator {
    /// `count` spheres of one radius, at rest or with one common velocity, in the box
    /// `min..max` (typically above a large fixed sphere, to fall onto it).
    Shower {
        /// How many spheres.
        count: u32,
        /// Seed of the jitter.
        seed: u64,
        /// Lower corner of the box the sphere centres and surfaces stay inside.
        min: [f64; 3],
        /// Upper corner of the box.
        max: [f64; 3],
        /// Radius of every sphere.
        radius: f64,
        /// Common initial velocity (default 0).
        #[serde(default)]
        velocity: [f64; 3],
        /// Density (default 1).
        #[serde(default = "one")]
        density: f64,
        /// Restitution (default: the scene's).
        #[serde(default)]
        restitution: Option<f64>,
    },
    /// `count` spheres of one radius moving at `speed` in random directions inside the box
    /// `min..max`, closed (by default) by six fixed walls: spheres of radius `wall_radius`
    /// whose surfaces touch the box's faces' middles, flat to within `(a² + b²) / (8 ·
    /// wall_radius)` over a face of sides `a` and `b` (at its corners). Walls too small to
    /// close the box's corners (about 4.45 times its largest half-size, less for larger
    /// spheres) are refused.
    Gas {
        /// How many spheres.
        count: u32,
        /// Seed of the jitter and the directions.
        seed: u64,
        /// Lower corner of the box.
        min: [f64; 3],
        /// Upper corner of the box.
        max: [f64; 3],
        /// Radius of every sphere.
        radius: f64,
        /// Speed of every sphere.
        speed: f64,
        /// Density (default 1).
        #[serde(default = "one")]
        density: f64,
        /// Restitution (default: the scene's).
        #[serde(default)]
        restitution: Option<f64>,
        /// Close the box with six fixed wall spheres (default true).
        #[serde(default = "yes")]
        walls: bool,
        /// Radius of the wall spheres (default 1e4).
        #[serde(default = "wall_radius")]
        wall_radius: f64,
    },
}

/// Why a generator cannot make its spheres.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
#[error("generator {index} ({kind}): {field} {reason}")]
pub struct GenerateError {
    /// The generator's index in the scene's list.
    pub index: usize,
    /// `"Shower"` or `"Gas"`.
    pub kind: &'static str,
    /// The field that is wrong.
    pub field: &'static str,
    /// What is wrong with it.
    pub reason: String,
}

/// SplitMix64: tiny, fast, and fully specified, so generated scenes never change.
struct SplitMix64(u64);

impl SplitMix64 {
    fn next_u64(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }

    /// Uniform in [0, 1).
    fn unit(&mut self) -> f64 {
        (self.next_u64() >> 11) as f64 * (1.0 / (1u64 << 53) as f64)
    }

    /// Uniform in 0..n.
    fn below(&mut self, n: u64) -> u64 {
        ((self.next_u64() as u128 * n as u128) >> 64) as u64
    }

    /// Uniform on the unit sphere, by arithmetic and one square root only, which IEEE 754
    /// rounds the same everywhere (`sin` and `cos` come from the platform's maths library, whose
    /// last bits differ between systems): a point uniform in the cube, kept if it lies inside
    /// the ball and not within 0.01 of its centre, scaled out to the sphere.
    fn direction(&mut self) -> [f64; 3] {
        loop {
            let x = 2.0 * self.unit() - 1.0;
            let y = 2.0 * self.unit() - 1.0;
            let z = 2.0 * self.unit() - 1.0;
            let p = [x, y, z];
            let s = p[0] * p[0] + p[1] * p[1] + p[2] * p[2];
            if (1e-4..=1.0).contains(&s) {
                let length = s.sqrt();
                return p.map(|c| c / length);
            }
        }
    }
}

struct Lattice {
    min: [f64; 3],
    /// The cells' side along each axis (see [`Lattice::new`]).
    step: [f64; 3],
    counts: [u64; 3],
}

impl Lattice {
    /// Cells of side `2 · radius · 1.1`, as many as fit in `min..max`, up to 2²¹ per axis (so
    /// that their number fits in a `u64`: a box that holds more uses only its lower corner).
    /// A box a whole number of cells wide to within the rounding of its corners (four units in
    /// the last place of their sizes) holds that number: 0.88 / 0.11000000000000001, the width
    /// of eight cells of spheres of radius 0.05, is 7.999999999999999, and until the
    /// sixty-fourth session such a box held seven, its spheres packed towards its lower corner.
    /// Along such an axis the cells are made that much narrower, to fill the box exactly.
    fn new(min: [f64; 3], max: [f64; 3], radius: f64) -> Self {
        let cell = 2.0 * radius * 1.1;
        let mut step = [cell; 3];
        let counts = std::array::from_fn(|k| {
            let width = max[k] - min[k];
            let mut cells = (width / cell).floor();
            let rounding = 4.0 * f64::EPSILON * (min[k].abs() + max[k].abs());
            if (cells + 1.0) * cell - width <= rounding {
                cells += 1.0;
                step[k] = width / cells;
            }
            cells.clamp(0.0, f64::from(1u32 << 21)) as u64
        });
        Self { min, step, counts }
    }

    fn capacity(&self) -> u64 {
        self.counts.iter().product()
    }

    /// The centre of cell `i`, moved by up to the cell's slack in each axis.
    fn place(&self, i: u64, radius: f64, rng: &mut SplitMix64) -> [f64; 3] {
        let [nx, ny, _] = self.counts;
        let idx = [i % nx, (i / nx) % ny, i / (nx * ny)];
        std::array::from_fn(|k| {
            let slack = self.step[k] / 2.0 - radius;
            let centre = self.min[k] + (idx[k] as f64 + 0.5) * self.step[k];
            centre + slack * (2.0 * rng.unit() - 1.0)
        })
    }
}

struct Checked {
    index: usize,
    kind: &'static str,
}

impl Checked {
    fn err(&self, field: &'static str, reason: impl Into<String>) -> GenerateError {
        GenerateError {
            index: self.index,
            kind: self.kind,
            field,
            reason: reason.into(),
        }
    }

    fn positive(&self, field: &'static str, value: f64) -> Result<(), GenerateError> {
        if value.is_finite() && value > 0.0 {
            Ok(())
        } else {
            Err(self.err(
                field,
                format!("must be finite and > 0, got {}", crate::Readable(value)),
            ))
        }
    }

    fn finite(&self, field: &'static str, value: &[f64]) -> Result<(), GenerateError> {
        match value.iter().find(|v| !v.is_finite()) {
            None => Ok(()),
            Some(v) => Err(self.err(
                field,
                format!("must be finite, got {}", crate::Readable(*v)),
            )),
        }
    }

    /// The spheres' shared density and restitution, checked as a world checks each sphere, so
    /// that a bad one names this generator and the field rather than a sphere's index.
    fn material(
        &self,
        radius: f64,
        density: f64,
        restitution: Option<f64>,
    ) -> Result<(), GenerateError> {
        let mut probe = crate::SphereDesc::new(radius).with_density(density);
        if let Some(restitution) = restitution {
            probe = probe.with_restitution(restitution);
        }
        probe.validate(String::new).map_err(|e| {
            self.err(
                e.field.name(),
                format!("{}, got {}", e.reason, crate::Readable(e.value)),
            )
        })
    }

    fn lattice(
        &self,
        count: u32,
        min: [f64; 3],
        max: [f64; 3],
        radius: f64,
    ) -> Result<Lattice, GenerateError> {
        self.positive("radius", radius)?;
        self.finite("min", &min)?;
        self.finite("max", &max)?;
        if let Some(k) = (0..3).find(|&k| max[k] <= min[k]) {
            return Err(self.err(
                "max",
                format!(
                    "must exceed min in every axis (axis {k}: {} <= {})",
                    crate::Readable(max[k]),
                    crate::Readable(min[k])
                ),
            ));
        }
        let lattice = Lattice::new(min, max, radius);
        // Far from the origin an f64 resolves positions only coarsely: neighbouring spheres
        // would round onto each other. Ask for positions resolved to a millionth of the radius.
        for ((&start, &cells), &step) in min.iter().zip(&lattice.counts).zip(&lattice.step) {
            let end = start + cells as f64 * step;
            let (field, far) = if start.abs() >= end.abs() {
                ("min", start.abs())
            } else {
                ("max", end.abs())
            };
            if far * f64::EPSILON > 1e-6 * radius {
                return Err(self.err(
                    field,
                    format!(
                        "is too far from the origin for spheres of radius {}: positions \
                         {far:e} from it are resolved only to {:e}",
                        crate::Readable(radius),
                        far * f64::EPSILON
                    ),
                ));
            }
        }
        if u64::from(count) > lattice.capacity() {
            return Err(self.err(
                "count",
                format!(
                    "{count} spheres of radius {} do not fit in the box (at most {})",
                    crate::Readable(radius),
                    lattice.capacity()
                ),
            ));
        }
        Ok(lattice)
    }
}

/// Picks `count` distinct cells of `capacity` in a seeded order (a partial Fisher–Yates
/// shuffle when the box is much larger than needed, every cell in turn otherwise).
fn cells(count: u32, capacity: u64, rng: &mut SplitMix64) -> Vec<u64> {
    let count = u64::from(count);
    if capacity <= 4 * count.max(1) {
        let mut all: Vec<u64> = (0..capacity).collect();
        for i in 0..count.min(capacity) {
            let j = i + rng.below(capacity - i);
            all.swap(i as usize, j as usize);
        }
        all.truncate(count as usize);
        all.sort_unstable();
        all
    } else {
        // Sparse: rejection sampling into a sorted, deduplicated set.
        let mut chosen = std::collections::BTreeSet::new();
        while (chosen.len() as u64) < count {
            chosen.insert(rng.below(capacity));
        }
        chosen.into_iter().collect()
    }
}

impl Generator {
    fn kind(&self) -> &'static str {
        match self {
            Generator::Shower { .. } => "Shower",
            Generator::Gas { .. } => "Gas",
        }
    }

    /// How many spheres the generator asks for: its `count`, and a gas's six walls.
    pub fn len(&self) -> u64 {
        match *self {
            Generator::Shower { count, .. } => u64::from(count),
            Generator::Gas { count, walls, .. } => u64::from(count) + if walls { 6 } else { 0 },
        }
    }

    /// Whether the generator asks for no sphere at all.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// The error for generator `index` when the scene's generators before it (`before`
    /// spheres) and it would make more than [`MAX_GENERATED`] spheres in all.
    pub(crate) fn over_limit(&self, index: usize, before: u64) -> Option<GenerateError> {
        let total = before + self.len();
        (total > u64::from(MAX_GENERATED)).then(|| {
            Checked {
                index,
                kind: self.kind(),
            }
            .err(
                "count",
                format!(
                    "brings the scene's generated spheres to {total}, more than {MAX_GENERATED}"
                ),
            )
        })
    }

    /// The spheres this generator makes (the generator being the first in its scene).
    pub fn spheres(&self) -> Result<Vec<SphereSpec>, GenerateError> {
        self.spheres_at(0)
    }

    /// The spheres this generator makes, with errors naming it as generator `index`.
    pub fn spheres_at(&self, index: usize) -> Result<Vec<SphereSpec>, GenerateError> {
        let check = Checked {
            index,
            kind: self.kind(),
        };
        // A gas's walls count too (its count alone was checked until the fifty-seventh
        // session: ten million and six spheres were made).
        if self.len() > u64::from(MAX_GENERATED) {
            return Err(check.err(
                "count",
                format!(
                    "makes {} spheres (a gas's walls counted), more than {MAX_GENERATED}",
                    self.len()
                ),
            ));
        }
        match *self {
            Generator::Shower {
                count,
                seed,
                min,
                max,
                radius,
                velocity,
                density,
                restitution,
            } => {
                let lattice = check.lattice(count, min, max, radius)?;
                check.material(radius, density, restitution)?;
                check.finite("velocity", &velocity)?;
                let mut rng = SplitMix64(seed);
                let picked = cells(count, lattice.capacity(), &mut rng);
                Ok(picked
                    .into_iter()
                    .map(|cell| SphereSpec {
                        name: None,
                        position: lattice.place(cell, radius, &mut rng),
                        velocity,
                        radius,
                        density,
                        restitution,
                        force: [0.0; 3],
                        fixed: false,
                        tether: None,
                        never_sleeps: false,
                    })
                    .collect())
            }
            Generator::Gas {
                count,
                seed,
                min,
                max,
                radius,
                speed,
                density,
                restitution,
                walls,
                wall_radius,
            } => {
                let lattice = check.lattice(count, min, max, radius)?;
                check.material(radius, density, restitution)?;
                if !(speed.is_finite() && speed >= 0.0) {
                    return Err(check.err(
                        "speed",
                        format!("must be finite and >= 0, got {}", crate::Readable(speed)),
                    ));
                }
                let mut rng = SplitMix64(seed);
                let picked = cells(count, lattice.capacity(), &mut rng);
                let mut spheres: Vec<SphereSpec> = picked
                    .into_iter()
                    .map(|cell| {
                        let position = lattice.place(cell, radius, &mut rng);
                        let velocity = rng.direction().map(|c| c * speed);
                        SphereSpec {
                            name: None,
                            position,
                            velocity,
                            radius,
                            density,
                            restitution,
                            force: [0.0; 3],
                            fixed: false,
                            tether: None,
                            never_sleeps: false,
                        }
                    })
                    .collect();
                if walls {
                    check.positive("wall_radius", wall_radius)?;
                    // A wall is checked as a world checks each sphere (a radius past
                    // `MAX_RADIUS` was taken here, and then refused naming the wall's sphere,
                    // not this generator's field).
                    if let Err(e) = crate::SphereDesc::new(wall_radius)
                        .fixed()
                        .validate(String::new)
                    {
                        return Err(check.err(
                            "wall_radius",
                            format!("{}, got {}", e.reason, crate::Readable(e.value)),
                        ));
                    }
                    // Walls too small leave a gap at each corner of the box: three walls of
                    // radius R whose surfaces touch a cube's faces, `h` from its centre, leave
                    // a sphere of radius r a way out along the corner's diagonal unless
                    // R + r >= (h + R)·√(2/3) (the three, grown by r, then meet on it). Checked
                    // with the box's largest half-size (exact for a cube; a bound, not a proof,
                    // for other boxes: 1 m boxes of gas escaped at R = 1.5 m and stayed in at
                    // the bound's 2 m, see `regression_gas_walls_too_small.rs`).
                    let h = (0..3).fold(0.0f64, |m, k| m.max(0.5 * (max[k] - min[k])));
                    let k = (2.0f64 / 3.0).sqrt();
                    let least = (k * h - radius) / (1.0 - k);
                    if wall_radius < least {
                        return Err(check.err(
                            "wall_radius",
                            format!(
                                "is too small to close the box: walls of radius {} leave a gap \
                                 at each corner for spheres of radius {} (at least {} needed)",
                                crate::Readable(wall_radius),
                                crate::Readable(radius),
                                crate::Readable(least)
                            ),
                        ));
                    }
                    // The walls' centres lie `wall_radius` beyond the box: there too an f64
                    // must resolve a millionth of the gas's radius.
                    let far =
                        min.iter().chain(&max).fold(0.0f64, |m, v| m.max(v.abs())) + wall_radius;
                    if far * f64::EPSILON > 1e-6 * radius {
                        return Err(check.err(
                            "wall_radius",
                            format!(
                                "is too large for spheres of radius {}: the walls' centres, \
                                 {far:e} from the origin, are resolved only to {:e}",
                                crate::Readable(radius),
                                far * f64::EPSILON
                            ),
                        ));
                    }
                    let centre: [f64; 3] = std::array::from_fn(|k| 0.5 * (min[k] + max[k]));
                    for axis in 0..3 {
                        for (side, face) in [("min", min[axis]), ("max", max[axis])] {
                            let mut position = centre;
                            let outward = if side == "min" { -1.0 } else { 1.0 };
                            position[axis] = face + outward * wall_radius;
                            spheres.push(SphereSpec {
                                name: Some(format!("wall {}{}", ["x", "y", "z"][axis], side)),
                                position,
                                velocity: [0.0; 3],
                                radius: wall_radius,
                                density: 1.0,
                                restitution,
                                force: [0.0; 3],
                                fixed: true,
                                tether: None,
                                never_sleeps: false,
                            });
                        }
                    }
                }
                Ok(spheres)
            }
        }
    }
}
