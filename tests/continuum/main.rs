//! The continuum (`src/model/continuum/`, `docs/fem-scenes.md`): the energies against finite
//! differences and closed forms, the Lamé conversion, the element kernels, the scenes' meshes,
//! and Newton's statics against the patch test, Cook's membrane and beam theory.

mod energies;
mod kernels;
mod polar;
mod scenes;
mod statics;

/// A small deterministic generator (xorshift64*): the tests' random F, the same every run.
pub struct Random(u64);

impl Random {
    pub fn new(seed: u64) -> Self {
        Self(seed.wrapping_mul(0x9E37_79B9_7F4A_7C15) | 1)
    }

    /// Uniform in [−1, 1).
    pub fn next(&mut self) -> f64 {
        self.0 ^= self.0 >> 12;
        self.0 ^= self.0 << 25;
        self.0 ^= self.0 >> 27;
        let bits = self.0.wrapping_mul(0x2545_F491_4F6C_DD1D) >> 11;
        bits as f64 / (1u64 << 52) as f64 - 1.0
    }
}
