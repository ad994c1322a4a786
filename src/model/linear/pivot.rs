//! What the factorisations share: a pivot's reciprocal (or the error naming the row whose
//! pivot is not positive) and the columns of a right-hand side.

use crate::error::{Error, Result};
use crate::model::lanes::Lane;

/// Splits `b` into `C` right-hand sides of length `n`, stored one after another.
#[inline]
pub(super) fn columns<T, const C: usize>(b: &mut [T], n: usize) -> [&mut [T]; C] {
    let mut columns = b.chunks_exact_mut(n);
    std::array::from_fn(|_| columns.next().expect("C columns of length n"))
}

/// Per lane, whether a pivot is positive and finite. Two comparisons (both false for a
/// NaN): fewer instructions in every row of a factorisation than testing the float's bits
/// for NaN and infinity.
#[inline(always)]
pub(super) fn is_pivot<T: Lane>(d: T) -> T::SimdBool {
    d.simd_gt(T::splat(0.0)) & d.simd_lt(T::splat(f64::INFINITY))
}

/// Rejects a pivot that is not positive and finite, and returns its inverse.
#[inline]
pub(super) fn inverse_pivot(row: usize, d: f64) -> Result<f64> {
    if is_pivot(d) {
        Ok(1.0 / d)
    } else {
        Err(not_positive_definite(row, d))
    }
}

pub(super) fn not_positive_definite(row: usize, pivot: f64) -> Error {
    let at = if row == usize::MAX {
        String::from("a pivot")
    } else {
        format!("row {row} (pivot {pivot:e})")
    };
    Error::NotConverged {
        what: "Cholesky factorisation".into(),
        detail: format!("the matrix is not positive definite at {at}"),
    }
}
