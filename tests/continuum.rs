//! The continuum (`src/model/continuum/`, `docs/fem-scenes.md`): the energies against finite
//! differences and closed forms, the Lamé conversion, the element kernels, the scenes' meshes,
//! and Newton's statics against the patch test, Cook's membrane and beam theory. One file a
//! concern in `tests/continuum/` (a folder without `main.rs`, so that `make test`'s wildcard
//! `tests/*.rs` runs this target).

#[path = "continuum/accuracy.rs"]
mod accuracy;
#[path = "continuum/energies.rs"]
mod energies;
#[path = "continuum/kernels.rs"]
mod kernels;
#[path = "continuum/polar.rs"]
mod polar;
#[path = "continuum/scene_file.rs"]
mod scene_file;
#[path = "continuum/scenes.rs"]
mod scenes;
#[path = "continuum/statics.rs"]
mod statics;

/// A small deterministic generator (xorshift64*): the tests' random F, the same every run.
pub struct Random(u64);

impl Random {
    pub fn new(seed: u64) -> Self {
        Self(seed.wrapping_mul(0x9E37_79B9_7F4A_7C15) | 1)
    }

    /// Uniform in [−1, 1).
    pub fn uniform(&mut self) -> f64 {
        self.0 ^= self.0 >> 12;
        self.0 ^= self.0 << 25;
        self.0 ^= self.0 >> 27;
        let bits = self.0.wrapping_mul(0x2545_F491_4F6C_DD1D) >> 11;
        bits as f64 / (1u64 << 52) as f64 - 1.0
    }
}
#[path = "continuum/dynamics.rs"]
mod dynamics;
