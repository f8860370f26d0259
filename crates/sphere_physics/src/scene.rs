//! Scene description: a whole scene as plain data, read from and written to RON.
//!
//! ```
//! use sphere_physics::SceneDesc;
//!
//! let scene = SceneDesc::from_ron(r#"(
//!     name: "Two spheres",
//!     gravity: (0.0, 0.0, 0.0),
//!     restitution: 1.0,
//!     spheres: [
//!         (name: "a", position: (0.0, 0.0, 0.0), velocity: (1.0, 0.0, 0.0), radius: 0.5),
//!         (name: "b", position: (2.0, 0.0, 0.0), radius: 0.5, density: 2.0),
//!     ],
//! )"#)?;
//! let world = scene.build()?;
//! assert_eq!(world.len(), 2);
//! # Ok::<(), sphere_physics::SceneError>(())
//! ```

use std::fmt;
use std::path::{Path, PathBuf};

use glam::DVec3;
use ron::extensions::Extensions;
use serde::{Deserialize, Serialize};

use crate::generate::{GenerateError, Generator};
use crate::{
    BodyError, IntegratorKind, Settings, Sleep, SphereDesc, Tether, ToiMethod, World, WorldError,
};

fn one() -> f64 {
    1.0
}

/// A whole scene: world settings and spheres. Fields with defaults may be left out of a file.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SceneDesc {
    /// Scene name.
    pub name: String,
    /// What the scene shows and what it models (default empty).
    #[serde(default)]
    pub description: String,
    /// Gravity (default none).
    #[serde(default)]
    pub gravity: [f64; 3],
    /// Restitution of spheres that do not give their own (default 1).
    #[serde(default = "one")]
    pub restitution: f64,
    /// Time-of-impact method (default [`ToiMethod::Exact`]).
    #[serde(default)]
    pub method: Option<ToiMethod>,
    /// Integrator (default [`IntegratorKind::SemiImplicitEuler`]).
    #[serde(default)]
    pub integrator: Option<IntegratorKind>,
    /// The scene's preferred time step in seconds (a runner's default; none means 1/60).
    #[serde(default)]
    pub dt: Option<f64>,
    /// Substeps per step (default 1; see [`Settings::substeps`]).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub substeps: Option<u32>,
    /// Sleeping (default off; `sleep: ()` for [`Sleep`]'s defaults, or
    /// `sleep: (speed: 0.1, time: 2.0)`; see [`Settings::sleep`]).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub sleep: Option<Sleep>,
    /// The spheres; their order is their body ids' order. At most [`MAX_LISTED`] in a file.
    #[serde(default, deserialize_with = "listed_spheres")]
    pub spheres: Vec<SphereSpec>,
    /// Generators of many spheres, added after `spheres` in this order (default none).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub generate: Vec<Generator>,
    /// A box a viewer keeps in view besides the spheres, `(low corner, high corner)` (default
    /// none): for motion that leaves where the spheres start, such as a ball thrown high. The
    /// lab frames it with the spheres; runners do not use it, but check it (a bad one fails
    /// [`SceneDesc::build`]). See [`SceneDesc::view`].
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub view: Option<[[f64; 3]; 2]>,
}

/// The largest scene file [`SceneDesc::load`] reads, 4 GiB (a generator makes up to ten
/// million spheres from a line; a file may list up to [`MAX_LISTED`] one by one).
pub const MAX_SCENE_BYTES: u64 = 1 << 32;

/// The most spheres a scene file may list one by one, as many as its generators may make
/// ([`MAX_GENERATED`](crate::generate::MAX_GENERATED)): ten million take some 7 GB to step.
/// Until the sixty-fourth session only the file's size bounded them: a file of 4 GiB may list
/// 150 million spheres of 28 bytes each, some 27 GB once read.
pub const MAX_LISTED: u32 = crate::generate::MAX_GENERATED;

/// Reads a scene's list of spheres, refusing it (where it passes the limit, so a file says
/// where) past [`MAX_LISTED`].
fn listed_spheres<'de, D>(deserializer: D) -> Result<Vec<SphereSpec>, D::Error>
where
    D: serde::Deserializer<'de>,
{
    struct Listed;
    impl<'de> serde::de::Visitor<'de> for Listed {
        type Value = Vec<SphereSpec>;
        fn expecting(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
            f.write_str("a list of spheres")
        }
        fn visit_seq<A: serde::de::SeqAccess<'de>>(
            self,
            mut seq: A,
        ) -> Result<Self::Value, A::Error> {
            let mut spheres = Vec::new();
            while let Some(sphere) = seq.next_element::<SphereSpec>()? {
                if spheres.len() >= MAX_LISTED as usize {
                    return Err(serde::de::Error::custom(format!(
                        "more than {MAX_LISTED} spheres listed (a generator makes many from \
                         one line)"
                    )));
                }
                spheres.push(sphere);
            }
            Ok(spheres)
        }
    }
    deserializer.deserialize_seq(Listed)
}

/// One sphere in a scene file.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SphereSpec {
    /// Name (default: none; runners call it by its index).
    #[serde(default)]
    pub name: Option<String>,
    /// Centre position.
    pub position: [f64; 3],
    /// Velocity (default 0).
    #[serde(default)]
    pub velocity: [f64; 3],
    /// Radius.
    pub radius: f64,
    /// Density (default 1).
    #[serde(default = "one")]
    pub density: f64,
    /// Restitution (default: the scene's).
    #[serde(default)]
    pub restitution: Option<f64>,
    /// Constant applied force (default 0).
    #[serde(default)]
    pub force: [f64; 3],
    /// Fixed: infinite mass (default false).
    #[serde(default)]
    pub fixed: bool,
    /// A string to a fixed anchor: `tether: (anchor: (x, y, z), length: L)` (default none).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub tether: Option<Tether>,
    /// Never falls asleep, nor lets the spheres it touches fall asleep (default false; see
    /// [`SphereDesc::never_sleeps`]).
    #[serde(default, skip_serializing_if = "std::ops::Not::not")]
    pub never_sleeps: bool,
}

/// What can go wrong loading or building a scene.
#[derive(Debug, thiserror::Error)]
pub enum SceneError {
    /// The file could not be read.
    #[error("{}: {source}", path.display())]
    Io {
        /// The file.
        path: PathBuf,
        /// Why.
        source: std::io::Error,
    },
    /// The text is not a valid scene.
    #[error("{}{line}:{column}: {message}", path.as_ref().map(|p| format!("{}:", p.display())).unwrap_or_default())]
    Parse {
        /// The file, if the text came from one.
        path: Option<PathBuf>,
        /// 1-based line.
        line: usize,
        /// 1-based column.
        column: usize,
        /// What is wrong.
        message: String,
    },
    /// A sphere is invalid.
    #[error("{0}")]
    Sphere(#[from] BodyError),
    /// A generator cannot make its spheres.
    #[error("{0}")]
    Generate(#[from] GenerateError),
    /// The world settings the scene makes are invalid (see [`Settings::validate`]).
    #[error("scene {0}")]
    Settings(WorldError),
    /// A scene-wide setting is invalid.
    #[error("scene {field} {reason}, got {}", crate::Readable(*.value))]
    Setting {
        /// The field.
        field: &'static str,
        /// The value.
        value: f64,
        /// What it must be.
        reason: &'static str,
    },
}

impl SceneDesc {
    fn ron_options() -> ron::Options {
        ron::Options::default().with_default_extension(Extensions::IMPLICIT_SOME)
    }

    /// Parses a scene from RON text. `name: "a"` is accepted for optional fields (no `Some(..)`).
    /// A byte-order mark at the start (which some editors write) is skipped, and lines and
    /// columns counted after it, as the editor shows them.
    pub fn from_ron(text: &str) -> Result<Self, SceneError> {
        let text = text.strip_prefix('\u{feff}').unwrap_or(text);
        Self::ron_options()
            .from_str(text)
            .map_err(|e: ron::error::SpannedError| SceneError::Parse {
                path: None,
                line: e.span.start.line,
                column: e.span.start.col,
                message: e.code.to_string(),
            })
    }

    /// Reads and parses a scene file. A regular file or a pipe (`<(make_scene)`, `/dev/stdin`)
    /// is read, up to [`MAX_SCENE_BYTES`]; a folder or a device is refused (`/dev/zero` was
    /// read until memory ran out, before the fifty-seventh session).
    pub fn load(path: impl AsRef<Path>) -> Result<Self, SceneError> {
        use std::io::Read;
        let path = path.as_ref();
        let io = |source| SceneError::Io {
            path: path.to_owned(),
            source,
        };
        let refused = |what: &str| {
            io(std::io::Error::new(
                std::io::ErrorKind::InvalidInput,
                format!("{what}, not a scene file"),
            ))
        };
        let kind = std::fs::metadata(path).map_err(io)?.file_type();
        if kind.is_dir() {
            return Err(refused("a folder"));
        }
        #[cfg(unix)]
        {
            use std::os::unix::fs::FileTypeExt;
            if kind.is_char_device() || kind.is_block_device() || kind.is_socket() {
                return Err(refused("a device"));
            }
        }
        let mut bytes = Vec::new();
        std::fs::File::open(path)
            .and_then(|file| file.take(MAX_SCENE_BYTES + 1).read_to_end(&mut bytes))
            .map_err(io)?;
        if bytes.len() as u64 > MAX_SCENE_BYTES {
            return Err(refused("more than 4 GiB"));
        }
        // Text that is not UTF-8 is placed too: the line and column of its first bad byte.
        let text = std::str::from_utf8(&bytes).map_err(|error| {
            let good = &bytes[..error.valid_up_to()];
            // After a byte-order mark, as `from_ron` counts (until the sixty-first session the
            // mark was counted here, a column too many on the first line).
            let good = good.strip_prefix("\u{feff}".as_bytes()).unwrap_or(good);
            let line_start = good.iter().rposition(|&b| b == b'\n').map_or(0, |n| n + 1);
            let column = String::from_utf8_lossy(&good[line_start..]).chars().count() + 1;
            SceneError::Parse {
                path: Some(path.to_owned()),
                line: 1 + good.iter().filter(|&&b| b == b'\n').count(),
                column,
                message: "not valid UTF-8 text here".to_string(),
            }
        })?;
        Self::from_ron(text).map_err(|e| match e {
            SceneError::Parse {
                line,
                column,
                message,
                ..
            } => SceneError::Parse {
                path: Some(path.to_owned()),
                line,
                column,
                message,
            },
            other => other,
        })
    }

    /// The scene as pretty RON text, which [`SceneDesc::from_ron`] reads back unchanged.
    pub fn to_ron(&self) -> String {
        let pretty = ron::ser::PrettyConfig::default().extensions(Extensions::IMPLICIT_SOME);
        Self::ron_options()
            .to_string_pretty(self, pretty)
            .expect("a scene always serialises")
    }

    /// The world settings the scene asks for.
    pub fn settings(&self) -> Result<Settings, SceneError> {
        let gravity = DVec3::from(self.gravity);
        if let Some(bad) = self.gravity.into_iter().find(|g| !g.is_finite()) {
            return Err(SceneError::Setting {
                field: "gravity",
                value: bad,
                reason: "must be finite",
            });
        }
        if !(0.0..=1.0).contains(&self.restitution) {
            return Err(SceneError::Setting {
                field: "restitution",
                value: self.restitution,
                reason: "must be in [0, 1]",
            });
        }
        if let Some(dt) = self.dt.filter(|dt| !(dt.is_normal() && *dt > 0.0)) {
            return Err(SceneError::Setting {
                field: "dt",
                value: dt,
                reason: "must be finite, normal and > 0",
            });
        }
        if self.substeps == Some(0) {
            return Err(SceneError::Setting {
                field: "substeps",
                value: 0.0,
                reason: "must be at least 1",
            });
        }
        let settings = Settings {
            gravity,
            method: self.method.unwrap_or_default(),
            integrator: self.integrator.unwrap_or_default(),
            substeps: self.substeps.unwrap_or(1),
            sleep: self.sleep,
            ..Settings::default()
        };
        // The limits every world checks (substeps, bisection iterations), said at load time.
        settings.validate().map_err(SceneError::Settings)?;
        Ok(settings)
    }

    /// The box to keep in view (see the `view` field), checked: its corners finite and the
    /// low one nowhere above the high one.
    pub fn view(&self) -> Result<Option<(DVec3, DVec3)>, SceneError> {
        let Some([low, high]) = self.view else {
            return Ok(None);
        };
        if let Some(bad) = low.into_iter().chain(high).find(|x| !x.is_finite()) {
            return Err(SceneError::Setting {
                field: "view",
                value: bad,
                reason: "must be finite",
            });
        }
        if let Some(axis) = (0..3).find(|&k| low[k] > high[k]) {
            return Err(SceneError::Setting {
                field: "view",
                value: low[axis],
                reason: "low corner must not exceed the high corner on any axis",
            });
        }
        Ok(Some((DVec3::from(low), DVec3::from(high))))
    }

    /// Every sphere of the scene: the listed ones, then each generator's, in order. The
    /// generators may make at most [`MAX_GENERATED`](crate::generate::MAX_GENERATED) spheres
    /// in all (the first to pass it is the error), checked before any is made.
    pub fn all_spheres(&self) -> Result<Vec<SphereSpec>, SceneError> {
        let mut generated = 0;
        for (index, generator) in self.generate.iter().enumerate() {
            if let Some(error) = generator.over_limit(index, generated) {
                return Err(error.into());
            }
            generated += generator.len();
        }
        let mut all = self.spheres.clone();
        for (index, generator) in self.generate.iter().enumerate() {
            all.extend(generator.spheres_at(index)?);
        }
        Ok(all)
    }

    /// How many spheres the scene asks for: those listed and those its generators would make.
    pub fn len(&self) -> u64 {
        self.spheres.len() as u64 + self.generate.iter().map(Generator::len).sum::<u64>()
    }

    /// Whether the scene asks for no sphere at all.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// The description of every sphere (see [`SceneDesc::all_spheres`]), with the scene's
    /// defaults filled in.
    pub fn sphere_descs(&self) -> Result<Vec<SphereDesc>, SceneError> {
        Ok(self
            .all_spheres()?
            .into_iter()
            .map(|s| SphereDesc {
                name: s.name,
                position: s.position.into(),
                velocity: s.velocity.into(),
                radius: s.radius,
                density: s.density,
                restitution: s.restitution.unwrap_or(self.restitution),
                force: s.force.into(),
                fixed: s.fixed,
                tether: s.tether,
                never_sleeps: s.never_sleeps,
            })
            .collect())
    }

    /// Builds the world: the first invalid sphere, if any, is reported by name or index. A
    /// bad `view` box fails it too (see [`SceneDesc::view`]), though the world does not use
    /// it, so a file a viewer refuses is refused everywhere.
    pub fn build(&self) -> Result<World, SceneError> {
        let settings = self.settings()?;
        self.view()?;
        let mut world = World::new(settings);
        for desc in self.sphere_descs()? {
            world.add_sphere(desc)?;
        }
        Ok(world)
    }
}

impl fmt::Display for SceneDesc {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{} ({} spheres)", self.name, self.len())
    }
}
