//! The sheet's scene file loads the system the constructor builds (`docs/sheet-scene.md`).

use mass_spring_solvers::model::scene::SheetParams;
use mass_spring_solvers::particles::scene_file;
use std::path::Path;

#[test]
fn the_sheet_scene_file_is_the_constructed_sheet() {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/sheet.toml");
    let file = scene_file::load(&path).unwrap();
    file.require_springs_and_gravity_only().unwrap();
    let built = SheetParams::spec(10, 1e6).build().unwrap();
    assert_eq!(file.system.springs().len(), 342);
    // Node for node and spring for spring, in the same order, bit for bit.
    assert_eq!(file.system, built);
}
