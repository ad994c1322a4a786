//! The scene file: the tutorial's "particle system file" as TOML.
//!
//! A scene file lists the nodes (the tutorial's particles), the springs between them, the
//! gravity and the extra forces of the tutorial's particle system. Units are SI throughout.
//!
//! ```toml
//! gravity = [0.0, -9.81, 0.0]           # m/s², required
//!
//! [[nodes]]
//! mass = 1.0                            # kg, > 0
//! position = [0.0, 0.0, 0.0]            # m
//! velocity = [0.0, 0.0, 0.0]            # m/s, optional (default 0)
//! fixed = true                          # optional (default false): an anchored node
//!
//! [[nodes]]
//! mass = 1.0
//! position = [1.0, 0.0, 0.0]
//!
//! [[springs]]
//! a = 0                                 # node indices, from 0, in file order
//! b = 1
//! rest_length = 1.0                     # m, > 0, optional (default: the initial distance)
//! stiffness = 1e6                       # N/m, > 0
//! damping = 0.0                         # N·s/m, >= 0, optional (default 0)
//!
//! [forces]                              # optional: the tutorial's extra forces
//! drag = 0.0                            # viscous drag k_f, N·s/m, >= 0: f_i = -k_f v_i
//! ground = { height = 0.0, restitution = 0.5 }   # plane y = height, restitution in [0, 1]
//! ```
//!
//! Beyond these signs, every value must be physically plausible ([`LIMITS`]: masses 1e-9 to
//! 1e9 kg, coordinates and rest lengths within 1e6 m, gravity within 1e4 m/s², stiffness 1e-9
//! to 1e12 N/m, ...), vectors have exactly three components, a file is at most
//! [`MAX_FILE_BYTES`] long, it has nodes, and no spring starts crushed to (nearly) nothing
//! ([`crate::model::scene::check_geometry`]). These are refused here, with the line, for every
//! solver; what only some solvers refuse (spring damping, drag, a ground) is theirs.
//!
//! Nodes and springs may equally be written as arrays of inline tables
//! (`nodes = [{ mass = 1.0, position = [0, 0, 0], fixed = true }, ...]`).
//!
//! Every error names where it is: a TOML syntax error, a missing or unknown field or a value of
//! the wrong type is reported by the `toml` crate with its line, column and the offending line;
//! a value out of range is rejected by [`MassSpringSystem::new`] (or by the checks of the extra
//! forces), which names the field (`springs[3].stiffness`), and this module adds the line and
//! column where the field is written.

use crate::error::{require_non_negative, require_within, Error, Result};
use crate::model::scene::check_geometry;
use crate::model::system::{MassSpringSystem, Node, Spring, Vec3};
use crate::particles::{Drag, Ground, ParticleSystem, Particles};
use crate::platform::paths::read_scene_text;
use serde::Deserialize;
use std::ops::Range;
use std::path::Path;
use toml::Spanned;

pub use crate::platform::paths::MAX_SCENE_FILE_BYTES as MAX_FILE_BYTES;

/// A plausible range: the least and greatest value, and the unit.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Plausible {
    pub min: f64,
    pub max: f64,
    pub unit: &'static str,
}

impl Plausible {
    /// Checks `value`, naming `field`.
    pub fn check(&self, field: impl Into<String>, value: f64) -> Result<f64> {
        require_within(field, value, self.min, self.max, self.unit)
    }
}

/// The plausible ranges of a scene's physical values; the command line's options share them.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Limits {
    pub mass: Plausible,
    /// Each coordinate of a position, and a ground height.
    pub coordinate: Plausible,
    pub velocity: Plausible,
    /// Each component of gravity.
    pub gravity: Plausible,
    pub rest_length: Plausible,
    pub stiffness: Plausible,
    /// Spring damping and drag.
    pub damping: Plausible,
}

/// See [`Limits`]: wide enough for any scene of the thesis or the tutorial by many orders of
/// magnitude, narrow enough that a value past them is a typo, not a scene.
pub const LIMITS: Limits = Limits {
    mass: Plausible {
        min: 1e-9,
        max: 1e9,
        unit: "kg",
    },
    coordinate: Plausible {
        min: -1e6,
        max: 1e6,
        unit: "m",
    },
    velocity: Plausible {
        min: -1e6,
        max: 1e6,
        unit: "m/s",
    },
    gravity: Plausible {
        min: -1e4,
        max: 1e4,
        unit: "m/s²",
    },
    rest_length: Plausible {
        min: 1e-9,
        max: 1e6,
        unit: "m",
    },
    // A spring of stiffness 0 is no spring: refused here, with its line, for every solver.
    stiffness: Plausible {
        min: 1e-9,
        max: 1e12,
        unit: "N/m",
    },
    damping: Plausible {
        min: 0.0,
        max: 1e9,
        unit: "N·s/m",
    },
};

/// Three numbers, exactly: `[x, y, z]`.
#[derive(Debug, Clone, Copy, PartialEq)]
struct Triple([f64; 3]);

impl<'de> Deserialize<'de> for Triple {
    fn deserialize<D: serde::Deserializer<'de>>(d: D) -> std::result::Result<Self, D::Error> {
        let values = Vec::<f64>::deserialize(d)?;
        let n = values.len();
        <[f64; 3]>::try_from(values)
            .map(Triple)
            .map_err(|_| serde::de::Error::invalid_length(n, &"an array of exactly 3 numbers"))
    }
}

/// Checks every component of a vector field (`nodes[2].position[1]`).
fn check_components(field: &str, v: [f64; 3], range: &Plausible) -> Result<()> {
    for (i, x) in v.into_iter().enumerate() {
        range.check(format!("{field}[{i}]"), x)?;
    }
    Ok(())
}

/// A scene read from a file: the mass-spring system and the tutorial's extra forces.
#[derive(Debug, Clone, PartialEq)]
pub struct SceneFile {
    pub system: MassSpringSystem,
    pub forces: Forces,
}

/// The tutorial's forces beyond springs and gravity.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Forces {
    /// Viscous drag coefficient $`k_f`$ in N·s/m, >= 0: $`f_i = -k_f\,v_i`$ on every node.
    pub drag: f64,
    /// A ground plane the nodes bounce on, if any.
    pub ground: Option<Ground>,
}

impl SceneFile {
    /// Checks that the scene needs nothing beyond springs (without damping) and gravity, the
    /// model of the thesis's solvers; otherwise names the first field they would ignore.
    pub fn require_springs_and_gravity_only(&self) -> Result<()> {
        const ALLOWED: &str = "0: the thesis's solvers model undamped springs and gravity only";
        if self.forces.drag != 0.0 {
            return Err(Error::invalid("forces.drag", self.forces.drag, ALLOWED));
        }
        if self.forces.ground.is_some() {
            return Err(Error::invalid(
                "forces.ground",
                "a ground plane",
                "none: the thesis's solvers model undamped springs and gravity only",
            ));
        }
        for (j, s) in self.system.springs().iter().enumerate() {
            if s.damping != 0.0 {
                return Err(Error::invalid(
                    format!("springs[{j}].damping"),
                    s.damping,
                    ALLOWED,
                ));
            }
        }
        Ok(())
    }

    /// The tutorial's particle system of the scene: gravity and the damped springs of the file,
    /// the drag on every node (if not 0) and the ground (if any).
    pub fn particle_system(&self) -> Result<ParticleSystem> {
        let mut particles = ParticleSystem::from_system(self.system.clone());
        if self.forces.drag != 0.0 {
            particles = particles.with_force(Box::new(Drag {
                k_f: self.forces.drag,
                particles: Particles::All,
            }))?;
        }
        Ok(match self.forces.ground {
            Some(ground) => particles.with_ground(ground),
            None => particles,
        })
    }
}

/// Reads and validates a scene file; every error starts with the file's path.
pub fn load(path: &Path) -> Result<SceneFile> {
    let text = read_scene_text(path)?;
    parse(&text).map_err(|e| Error::Input(format!("scene file {}: {e}", path.display())))
}

/// Parses and validates the text of a scene file.
pub fn parse(text: &str) -> Result<SceneFile> {
    let raw: RawScene = toml::from_str(text).map_err(|e| Error::Input(e.to_string()))?;
    build(&raw).map_err(|e| match &e {
        Error::InvalidParameter { field, .. } => match raw.span_of(field) {
            Some(span) => Error::Input(format!("{}: {e}", location(text, span.start))),
            None => e,
        },
        _ => e,
    })
}

/// "line L, column C" of a byte offset, both from 1.
fn location(text: &str, offset: usize) -> String {
    let before = &text[..offset.min(text.len())];
    let line = before.matches('\n').count() + 1;
    let column = before.rsplit('\n').next().map_or(0, |l| l.chars().count()) + 1;
    format!("line {line}, column {column}")
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct RawScene {
    gravity: Spanned<Triple>,
    #[serde(default)]
    nodes: Vec<Spanned<RawNode>>,
    #[serde(default)]
    springs: Vec<Spanned<RawSpring>>,
    forces: Option<Spanned<RawForces>>,
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct RawNode {
    mass: Spanned<f64>,
    position: Spanned<Triple>,
    velocity: Option<Spanned<Triple>>,
    #[serde(default)]
    fixed: bool,
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct RawSpring {
    a: Spanned<usize>,
    b: Spanned<usize>,
    rest_length: Option<Spanned<f64>>,
    stiffness: Spanned<f64>,
    damping: Option<Spanned<f64>>,
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct RawForces {
    drag: Option<Spanned<f64>>,
    ground: Option<Spanned<RawGround>>,
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct RawGround {
    height: Spanned<f64>,
    restitution: Spanned<f64>,
}

impl RawScene {
    /// Where a field named as in the crate's errors (`nodes[2].mass`, `springs[0].b`,
    /// `gravity[1]`, `forces.ground.restitution`) is written; the enclosing entry if the field
    /// was left to its default.
    fn span_of(&self, field: &str) -> Option<Range<usize>> {
        if field.starts_with("gravity") {
            return Some(self.gravity.span());
        }
        if let Some(rest) = field.strip_prefix("forces.") {
            let forces = self.forces.as_ref()?;
            let ground = forces.get_ref().ground.as_ref();
            return match rest {
                "drag" => forces.get_ref().drag.as_ref().map(Spanned::span),
                "ground.height" => ground.map(|g| g.get_ref().height.span()),
                "ground.restitution" => ground.map(|g| g.get_ref().restitution.span()),
                _ => None,
            }
            .or_else(|| Some(forces.span()));
        }
        let (list, rest) = field.split_once('[')?;
        let (index, member) = rest.split_once(']')?;
        let index: usize = index.parse().ok()?;
        let member = member.trim_start_matches('.');
        let member = member.split('[').next().unwrap_or(member);
        match list {
            "nodes" => {
                let node = self.nodes.get(index)?;
                let n = node.get_ref();
                match member {
                    "mass" => Some(n.mass.span()),
                    "position" => Some(n.position.span()),
                    "velocity" => n.velocity.as_ref().map(Spanned::span),
                    _ => None,
                }
                .or_else(|| Some(node.span()))
            }
            "springs" => {
                let spring = self.springs.get(index)?;
                let s = spring.get_ref();
                match member {
                    "a" => Some(s.a.span()),
                    "b" => Some(s.b.span()),
                    "rest_length" => s.rest_length.as_ref().map(Spanned::span),
                    "stiffness" => Some(s.stiffness.span()),
                    "damping" => s.damping.as_ref().map(Spanned::span),
                    _ => None,
                }
                .or_else(|| Some(spring.span()))
            }
            _ => None,
        }
    }
}

/// Checks the values of the file against [`LIMITS`], naming the first one out of range.
fn check_plausible(raw: &RawScene) -> Result<()> {
    if raw.nodes.is_empty() {
        return Err(Error::invalid(
            "nodes",
            "no nodes",
            "at least one [[nodes]] entry that is not fixed",
        ));
    }
    check_components("gravity", raw.gravity.get_ref().0, &LIMITS.gravity)?;
    for (i, n) in raw.nodes.iter().enumerate() {
        let n = n.get_ref();
        LIMITS
            .mass
            .check(format!("nodes[{i}].mass"), *n.mass.get_ref())?;
        let position = n.position.get_ref().0;
        check_components(
            &format!("nodes[{i}].position"),
            position,
            &LIMITS.coordinate,
        )?;
        if let Some(v) = &n.velocity {
            check_components(
                &format!("nodes[{i}].velocity"),
                v.get_ref().0,
                &LIMITS.velocity,
            )?;
        }
    }
    for (j, s) in raw.springs.iter().enumerate() {
        let s = s.get_ref();
        LIMITS
            .stiffness
            .check(format!("springs[{j}].stiffness"), *s.stiffness.get_ref())?;
        if let Some(l) = &s.rest_length {
            LIMITS
                .rest_length
                .check(format!("springs[{j}].rest_length"), *l.get_ref())?;
        }
        if let Some(d) = &s.damping {
            LIMITS
                .damping
                .check(format!("springs[{j}].damping"), *d.get_ref())?;
        }
    }
    if let Some(f) = &raw.forces {
        let f = f.get_ref();
        if let Some(d) = &f.drag {
            LIMITS.damping.check("forces.drag", *d.get_ref())?;
        }
        if let Some(g) = &f.ground {
            LIMITS
                .coordinate
                .check("forces.ground.height", *g.get_ref().height.get_ref())?;
        }
    }
    Ok(())
}

/// Builds the validated scene; range errors name the field as the file writes it.
fn build(raw: &RawScene) -> Result<SceneFile> {
    check_plausible(raw)?;
    let nodes: Vec<Node> = raw
        .nodes
        .iter()
        .map(|n| {
            let n = n.get_ref();
            Node {
                mass: *n.mass.get_ref(),
                position: Vec3::from(n.position.get_ref().0),
                velocity: n
                    .velocity
                    .as_ref()
                    .map_or(Vec3::zeros(), |v| Vec3::from(v.get_ref().0)),
                fixed: n.fixed,
            }
        })
        .collect();
    let springs = raw
        .springs
        .iter()
        .map(|s| {
            let s = s.get_ref();
            let (a, b) = (*s.a.get_ref(), *s.b.get_ref());
            // An index out of range leaves the distance undefined; `MassSpringSystem::new`
            // rejects that index before it looks at this spring's rest length.
            let distance = match (nodes.get(a), nodes.get(b)) {
                (Some(na), Some(nb)) => (na.position - nb.position).norm(),
                _ => f64::NAN,
            };
            Spring {
                a,
                b,
                rest_length: s.rest_length.as_ref().map_or(distance, |l| *l.get_ref()),
                stiffness: *s.stiffness.get_ref(),
                damping: s.damping.as_ref().map_or(0.0, |d| *d.get_ref()),
            }
        })
        .collect();
    let system = MassSpringSystem::new(nodes, springs, Vec3::from(raw.gravity.get_ref().0))?;
    check_geometry(&system)?;
    let forces = match &raw.forces {
        None => Forces::default(),
        Some(f) => {
            let f = f.get_ref();
            let drag = f.drag.as_ref().map_or(0.0, |d| *d.get_ref());
            require_non_negative("forces.drag", drag)?;
            let ground = f
                .ground
                .as_ref()
                .map(|g| {
                    let g = g.get_ref();
                    Ground::new(*g.height.get_ref(), *g.restitution.get_ref())
                        .map_err(within_forces)
                })
                .transpose()?;
            Forces { drag, ground }
        }
    };
    Ok(SceneFile { system, forces })
}

/// Names a field of [`Ground::new`]'s errors as the file writes it (`forces.ground.height`).
fn within_forces(e: Error) -> Error {
    match e {
        Error::InvalidParameter {
            field,
            value,
            allowed,
        } => Error::InvalidParameter {
            field: format!("forces.{field}"),
            value,
            allowed,
        },
        other => other,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const GOOD: &str = r#"
gravity = [0.0, -9.81, 0.0]

[[nodes]]
mass = 1.0
position = [0.0, 0.0, 0.0]
fixed = true

[[nodes]]
mass = 2
position = [3.0, 4.0, 0.0]
velocity = [0.0, 1.0, 0.0]

[[springs]]
a = 0
b = 1
stiffness = 1e3
damping = 0.5

[forces]
drag = 0.25
ground = { height = -2.0, restitution = 0.5 }
"#;

    fn error(text: &str) -> String {
        parse(text).expect_err("the file is bad").to_string()
    }

    #[test]
    fn reads_every_field_and_defaults() {
        let scene = parse(GOOD).unwrap();
        let s = &scene.system;
        assert_eq!(s.len(), 2);
        assert!(s.nodes()[0].fixed && !s.nodes()[1].fixed);
        assert_eq!(s.nodes()[1].mass, 2.0);
        assert_eq!(s.nodes()[1].velocity, Vec3::new(0.0, 1.0, 0.0));
        assert_eq!(s.nodes()[0].velocity, Vec3::zeros());
        assert_eq!(s.gravity(), Vec3::new(0.0, -9.81, 0.0));
        let spring = &s.springs()[0];
        // rest_length defaults to the initial distance |(3, 4, 0)| = 5 m.
        assert_eq!(
            (spring.rest_length, spring.stiffness, spring.damping),
            (5.0, 1e3, 0.5)
        );
        assert_eq!(
            scene.forces,
            Forces {
                drag: 0.25,
                ground: Some(Ground::new(-2.0, 0.5).unwrap())
            }
        );
        let particles = scene.particle_system().unwrap();
        assert_eq!(particles.forces().len(), 3, "gravity, damped springs, drag");
        assert_eq!(particles.ground(), Some(&Ground::new(-2.0, 0.5).unwrap()));
        let err = scene
            .require_springs_and_gravity_only()
            .unwrap_err()
            .to_string();
        assert!(err.contains("forces.drag"), "{err}");
    }

    #[test]
    fn inline_tables_and_no_forces() {
        let scene = parse(
            "gravity = [0, 0, 0]\n\
             nodes = [{ mass = 1, position = [0, 0, 0], fixed = true },\n\
                      { mass = 1, position = [0, -2, 0] }]\n\
             springs = [{ a = 0, b = 1, rest_length = 1.5, stiffness = 10 }]\n",
        )
        .unwrap();
        assert_eq!(scene.system.springs()[0].rest_length, 1.5);
        assert_eq!(scene.forces, Forces::default());
        scene.require_springs_and_gravity_only().unwrap();
    }

    #[test]
    fn spring_to_a_missing_node_names_field_and_line() {
        let text = GOOD.replace("a = 0\nb = 1", "a = 0\nb = 7");
        let err = error(&text);
        assert!(
            err.contains("springs[0].b") && err.contains("0..2"),
            "{err}"
        );
        assert!(err.contains("line 16, column 5"), "{err}");
    }

    #[test]
    fn negative_mass_names_field_and_line() {
        let err = error(&GOOD.replace("mass = 2", "mass = -2"));
        assert!(err.contains("nodes[1].mass") && err.contains("-2"), "{err}");
        assert!(err.contains("line 10, column 8"), "{err}");
    }

    #[test]
    fn negative_stiffness_names_field_and_line() {
        let err = error(&GOOD.replace("stiffness = 1e3", "stiffness = -1e3"));
        assert!(
            err.contains("springs[0].stiffness") && err.contains("line 17"),
            "{err}"
        );
    }

    #[test]
    fn defaulted_rest_length_of_coincident_nodes_points_at_the_spring() {
        let err = error(&GOOD.replace("[3.0, 4.0, 0.0]", "[0.0, 0.0, 0.0]"));
        assert!(err.contains("springs[0].rest_length"), "{err}");
        assert!(err.contains("line 14, column 1"), "{err}");
    }

    #[test]
    fn syntax_error_names_the_line() {
        let err = error(&GOOD.replace("mass = 2", "mass = = 2"));
        assert!(err.contains("line 10"), "{err}");
    }

    #[test]
    fn unknown_field_names_the_field_and_line() {
        let err = error(&GOOD.replace("damping = 0.5", "dampign = 0.5"));
        assert!(err.contains("dampign") && err.contains("line 18"), "{err}");
    }

    #[test]
    fn missing_field_and_wrong_type_are_named() {
        let err = error(&GOOD.replace("b = 1\n", ""));
        assert!(err.contains("missing field `b`"), "{err}");
        assert!(err.contains("line"), "{err}");
        let err = error(&GOOD.replace("a = 0", "a = -1"));
        assert!(err.contains("line 15"), "{err}");
        let err = error(&GOOD.replace("restitution = 0.5", "restitution = 1.5"));
        assert!(
            err.contains("forces.ground.restitution") && err.contains("line 22"),
            "{err}"
        );
    }
}
