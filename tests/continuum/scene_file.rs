//! The continuum's scene file (`src/model/continuum/scene_file.rs`): the committed files
//! (`scenes/continuum-*.toml`) build the scenes' systems, and every field is checked, naming
//! it, before any work.

use mass_spring_solvers::error::Error;
use mass_spring_solvers::model::continuum::energy::EnergyKind;
use mass_spring_solvers::model::continuum::scene_file::{load, parse};
use mass_spring_solvers::model::continuum::scenes::{beam, cook, membrane, patch};
use std::path::Path;

/// Each committed scene file builds the very system of its builder (positions, elements,
/// masses, clamps, held displacements, loads and material, compared exactly). Wrong
/// implementations it catches: a plane-stress file read as a solid (another λ), a density
/// ignored for per-node masses, a held displacement dropped (the patch's).
#[test]
fn the_committed_scene_files_are_the_scenes() {
    let scenes = [
        ("continuum-beam", beam(2, EnergyKind::StableNeoHookean, 1e9)),
        ("continuum-cook", cook(4, EnergyKind::Linear, 1.0)),
        (
            "continuum-membrane",
            membrane(10, EnergyKind::StableNeoHookean, 1e3),
        ),
        ("continuum-patch", patch(EnergyKind::StableNeoHookean)),
    ];
    for (name, built) in scenes {
        let path = Path::new(env!("CARGO_MANIFEST_DIR")).join(format!("scenes/{name}.toml"));
        let read = load(&path).unwrap_or_else(|e| panic!("{name}: {e}"));
        assert!(read == built.unwrap(), "{name} differs from its builder");
    }
}

/// A tet with three held nodes and one free, every field written.
const VALID: &str = r#"
element = "tetrahedron"
energy = "corotated"
youngs_modulus = 1e6
poisson_ratio = 0.3
density = 1000.0
gravity = [0.0, -9.81, 0.0]
nodes = [
  { position = [0.0, 0.0, 0.0], fixed = true, displacement = [0.0, 0.0, 0.0] },
  { position = [1.0, 0.0, 0.0], fixed = true },
  { position = [0.0, 1.0, 0.0], fixed = true },
  { position = [0.0, 0.0, 1.0], load = [0.0, 1.0, 0.0] },
]
elements = [[0, 1, 2, 3]]
"#;

/// The field an edit of [`VALID`] is refused for.
fn refused_field(from: &str, to: &str) -> String {
    assert!(VALID.contains(from), "{from}");
    match parse(&VALID.replacen(from, to, 1)) {
        Err(Error::InvalidParameter { field, .. }) => field,
        other => panic!("{from} -> {to}: {other:?}"),
    }
}

/// Every field, one bad value each, refused with an error naming it: a degenerate and an
/// inverted element, ν at 0.5 and beyond −1, non-finite numbers (TOML's `nan` and `inf`),
/// vectors of the wrong length, a mass beside a density or none, a displacement on a free node,
/// nodes out of range or repeated, an element of the wrong size, no free node. The valid file
/// builds. Wrong implementations it catches (tried): the displacement on a free node silently
/// zeroed (accepted), the non-finite load left to the solver (accepted: NaN forces).
#[test]
fn every_field_of_the_scene_file_is_checked() {
    assert!(parse(VALID).is_ok());
    let cases = [
        (r#""tetrahedron""#, r#""hexahedron""#, "element"),
        (r#""corotated""#, r#""rubber""#, "energy"),
        (
            "youngs_modulus = 1e6",
            "youngs_modulus = 0.0",
            "youngs_modulus",
        ),
        (
            "youngs_modulus = 1e6",
            "youngs_modulus = inf",
            "youngs_modulus",
        ),
        (
            "poisson_ratio = 0.3",
            "poisson_ratio = 0.5",
            "poisson_ratio",
        ),
        (
            "poisson_ratio = 0.3",
            "poisson_ratio = -1.0",
            "poisson_ratio",
        ),
        (
            "poisson_ratio = 0.3",
            "poisson_ratio = nan",
            "poisson_ratio",
        ),
        ("density = 1000.0", "density = -1.0", "density"),
        ("density = 1000.0", "density = nan", "density"),
        ("[0.0, -9.81, 0.0]", "[0.0, -9.81]", "gravity"),
        ("[0.0, -9.81, 0.0]", "[0.0, nan, 0.0]", "gravity[1]"),
        ("[1.0, 0.0, 0.0]", "[1.0, 0.0, inf]", "nodes[1].position[2]"),
        (
            "[0.0, 1.0, 0.0], fixed",
            "[0.0, 1.0], fixed",
            "nodes[2].position",
        ),
        (
            "load = [0.0, 1.0, 0.0]",
            "load = [0.0, nan, 0.0]",
            "nodes[3].load[1]",
        ),
        (
            "displacement = [0.0, 0.0, 0.0]",
            "displacement = [0.0, 0.0, -inf]",
            "nodes[0].displacement[2]",
        ),
        (
            "load = [0.0, 1.0, 0.0]",
            "displacement = [0.0, 1.0, 0.0]",
            "nodes[3].displacement",
        ),
        (
            "fixed = true }",
            "fixed = true, mass = 1.0 }",
            "nodes[1].mass",
        ),
        ("density = 1000.0", "", "nodes[0].mass"),
        // Degenerate (the fourth node in the others' plane) and inverted (two nodes swapped).
        (
            "[0.0, 0.0, 1.0], load",
            "[0.5, 0.5, 0.0], load",
            "elements[0]",
        ),
        ("[[0, 1, 2, 3]]", "[[0, 2, 1, 3]]", "elements[0]"),
        ("[[0, 1, 2, 3]]", "[[0, 1, 2]]", "elements[0]"),
        ("[[0, 1, 2, 3]]", "[[0, 1, 2, 4]]", "elements[0][3]"),
        ("[[0, 1, 2, 3]]", "[[0, 1, 1, 3]]", "elements[0][2]"),
        (
            "{ position = [0.0, 0.0, 1.0], load",
            "{ position = [0.0, 0.0, 1.0], fixed = true, load",
            "fixed",
        ),
    ];
    for (from, to, field) in cases {
        assert_eq!(refused_field(from, to), field, "{from} -> {to}");
    }
    // The mass of a per-node file is checked too.
    let per_node = VALID
        .replacen("density = 1000.0", "", 1)
        .replace("fixed = true", "fixed = true, mass = 1.0")
        .replace("load = [0.0, 1.0, 0.0]", "mass = -1.0");
    assert!(
        matches!(parse(&per_node), Err(Error::InvalidParameter { field, .. }) if field == "nodes[3].mass")
    );
    // A syntax error and an unknown field carry the toml crate's line.
    for text in [VALID.replacen("density", "densty", 1), "element = ".into()] {
        assert!(
            matches!(parse(&text), Err(Error::Input(m)) if m.contains("line")),
            "{text}"
        );
    }
}
