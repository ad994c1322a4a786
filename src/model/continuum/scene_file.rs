//! The continuum's scene file (`docs/fem-scenes.md`; the spring scenes' is
//! [`crate::particles::scene_file`]): a mesh of linear elements, one material, gravity and
//! nodal loads, as TOML. Units are SI throughout.
//!
//! ```toml
//! element = "tetrahedron"        # or "plane-triangle" (d = 2) or "membrane" (triangles in 3D)
//! energy = "stable-neo-hookean"  # linear, arap, corotated, stvk, stable-neo-hookean
//! youngs_modulus = 1e9           # Pa; for triangles Y = E·t, N/m (per unit rest area)
//! poisson_ratio = 0.3            # in (-1, 0.5); plane stress for triangles
//! density = 1000.0               # kg/m³ (kg/m² for triangles): lumped masses; or every node a mass
//! gravity = [0.0, -9.81, 0.0]    # m/s², d components
//!
//! nodes = [
//!   { position = [0.0, 0.0, 0.0], fixed = true },     # m, d components
//!   { position = [1.0, 0.0, 0.0], load = [0.0, -1.0, 0.0] },  # N, optional
//!   # mass = 1.0 (kg, >= 0) on every node instead of `density`;
//!   # displacement = [...] (m) on a fixed node: where it is held (the patch test)
//! ]
//! elements = [[0, 1, 2, 3]]      # node indices from 0; tets ordered so that det D_m > 0
//! ```
//!
//! Every value is checked before any work, and an error names the field as the file writes it
//! (`nodes[3].position[1]`, `elements[7]`, `poisson_ratio`): a non-finite number, a vector of
//! the wrong length, ν ≥ 0.5 or ≤ −1, E ≤ 0, a density and masses both or neither, a
//! displacement on a free node, an element with the wrong number of nodes, a node out of range
//! or repeated, and a degenerate or inverted rest element ([`ContinuumSystem::new`]). A TOML
//! syntax error, a missing or unknown field and a value of the wrong type are reported by the
//! `toml` crate with their line.

use super::energy::EnergyKind;
use super::lame::{Lame, Loading};
use super::system::{ContinuumSystem, ElementKind, Masses, Material, Mesh};
use crate::error::{require_finite, require_non_negative, require_positive, Error, Result};
use crate::platform::paths::read_scene_text;
use serde::Deserialize;
use std::path::Path;

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct RawScene {
    element: String,
    energy: String,
    youngs_modulus: f64,
    poisson_ratio: f64,
    density: Option<f64>,
    gravity: Vec<f64>,
    nodes: Vec<RawNode>,
    elements: Vec<Vec<usize>>,
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct RawNode {
    position: Vec<f64>,
    #[serde(default)]
    fixed: bool,
    mass: Option<f64>,
    load: Option<Vec<f64>>,
    displacement: Option<Vec<f64>>,
}

/// Reads and builds a continuum scene file; every error starts with the file's path.
pub fn load(path: &Path) -> Result<ContinuumSystem> {
    let text = read_scene_text(path)?;
    parse(&text).map_err(|e| Error::Input(format!("scene file {}: {e}", path.display())))
}

/// Parses, checks and builds the text of a continuum scene file.
pub fn parse(text: &str) -> Result<ContinuumSystem> {
    let raw: RawScene = toml::from_str(text).map_err(|e| Error::Input(e.to_string()))?;
    build(raw)
}

/// The element kind a file names.
fn element_kind(name: &str) -> Result<ElementKind> {
    match name {
        "tetrahedron" => Ok(ElementKind::Tetrahedron),
        "plane-triangle" => Ok(ElementKind::PlaneTriangle),
        "membrane" => Ok(ElementKind::Membrane),
        _ => Err(Error::invalid(
            "element",
            name,
            "one of tetrahedron, plane-triangle, membrane",
        )),
    }
}

/// A vector field of d finite numbers (`nodes[2].load`), appended to `out`.
fn push_vector(field: &str, values: &[f64], d: usize, out: &mut Vec<f64>) -> Result<()> {
    if values.len() != d {
        return Err(Error::invalid(
            field,
            format!("{} numbers", values.len()),
            &format!("{d} numbers (the element's space has d = {d})"),
        ));
    }
    for (k, &v) in values.iter().enumerate() {
        out.push(require_finite(format!("{field}[{k}]"), v)?);
    }
    Ok(())
}

/// Checks every field in the order of the file and builds the system.
fn build(raw: RawScene) -> Result<ContinuumSystem> {
    let kind = element_kind(&raw.element)?;
    let energy = EnergyKind::parse("energy", &raw.energy)?;
    let loading = match kind {
        ElementKind::Tetrahedron => Loading::Solid,
        _ => Loading::PlaneStress,
    };
    let lame = Lame::from_youngs_poisson(raw.youngs_modulus, raw.poisson_ratio, loading)?;
    let d = kind.space_dimension();
    let mut gravity = Vec::with_capacity(d);
    push_vector("gravity", &raw.gravity, d, &mut gravity)?;
    if raw.nodes.is_empty() {
        return Err(Error::invalid("nodes", "none", "at least one node"));
    }
    let n = raw.nodes.len();
    let (mut positions, mut loads, mut displacement) = (
        Vec::with_capacity(n * d),
        Vec::with_capacity(n * d),
        Vec::with_capacity(n * d),
    );
    let mut masses = Vec::with_capacity(n);
    for (i, node) in raw.nodes.iter().enumerate() {
        push_vector(
            &format!("nodes[{i}].position"),
            &node.position,
            d,
            &mut positions,
        )?;
        let zero = vec![0.0; d];
        push_vector(
            &format!("nodes[{i}].load"),
            node.load.as_ref().unwrap_or(&zero),
            d,
            &mut loads,
        )?;
        if node.displacement.is_some() && !node.fixed {
            return Err(Error::invalid(
                format!("nodes[{i}].displacement"),
                "a displacement on a free node",
                "none: only a fixed node is held displaced (Newton finds the free ones')",
            ));
        }
        push_vector(
            &format!("nodes[{i}].displacement"),
            node.displacement.as_ref().unwrap_or(&zero),
            d,
            &mut displacement,
        )?;
        match (node.mass, raw.density) {
            (Some(m), None) => masses.push(require_non_negative(format!("nodes[{i}].mass"), m)?),
            (None, Some(_)) => {}
            (Some(_), Some(_)) => {
                return Err(Error::invalid(
                    format!("nodes[{i}].mass"),
                    "a mass beside a density",
                    "either a density (lumped masses) or a mass on every node, not both",
                ))
            }
            (None, None) => {
                return Err(Error::invalid(
                    format!("nodes[{i}].mass"),
                    "missing, and no density",
                    "either a density (lumped masses) or a mass on every node",
                ))
            }
        }
    }
    let masses = match raw.density {
        Some(density) => Masses::Lumped(require_positive("density", density)?),
        None => Masses::PerNode(masses),
    };
    let mesh = Mesh {
        kind,
        positions,
        elements: raw.elements,
        masses,
        fixed: raw.nodes.iter().map(|node| node.fixed).collect(),
        displacement,
        loads,
        gravity,
    };
    ContinuumSystem::new(mesh, Material { energy, lame })
}
