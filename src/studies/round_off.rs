//! Starts nudged by a few units in the last place: how much of a measured count, ratio or
//! pass/fail outcome is round-off. A quantity that differs between the start and its nudges
//! is decided by the last bits of the arithmetic, and is stated (and asserted) as its range
//! over them, never as one value.

use crate::model::system::State;

/// The nudges, in units in the last place: ±1 to ±4.
pub const NUDGES_ULP: [i64; 8] = [-4, -3, -2, -1, 1, 2, 3, 4];

/// `x` moved by `ulps` units in the last place, toward +∞ for a positive `ulps`, through its
/// bits (`f64::next_up` is newer than the crate's MSRV). `x` is finite and nonzero, and far
/// from zero in units of its last place, so that the bits never cross zero's.
pub fn nudge(x: f64, ulps: i64) -> f64 {
    assert!(
        x.is_finite() && x != 0.0,
        "only a finite nonzero value has neighbours of its own scale"
    );
    let bits = x.to_bits() as i64;
    // The bits of a negative value grow toward −∞.
    f64::from_bits((if x > 0.0 { bits + ulps } else { bits - ulps }) as u64)
}

/// `state` with node 1's horizontal position moved by `ulps` units in the last place, every
/// other bit kept. Its horizontal position, not its height: at rest the height is 0, whose
/// neighbours are subnormal and vanish in the first step's additions.
pub fn nudged(state: &State, ulps: i64) -> State {
    let mut s = state.clone();
    s.x[1].x = nudge(s.x[1].x, ulps);
    s
}

/// `state` nudged by each of [`NUDGES_ULP`], in that order.
pub fn nudged_starts(state: &State) -> [State; NUDGES_ULP.len()] {
    NUDGES_ULP.map(|u| nudged(state, u))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A nudge is a neighbour by bits, in the direction of its sign, for either sign.
    #[test]
    fn a_nudge_moves_by_that_many_neighbours() {
        for x in [1.0, -0.25, 3.7e-3, -9.0] {
            for &u in &NUDGES_ULP {
                let y = nudge(x, u);
                assert_eq!(y > x, u > 0, "{x} {u}");
                assert_eq!(x.to_bits().abs_diff(y.to_bits()), u.unsigned_abs());
            }
        }
        assert_eq!(nudge(1.0, 1), 1.0 + f64::EPSILON);
        assert_eq!(nudge(1.0, -2), 1.0 - f64::EPSILON);
    }
}
