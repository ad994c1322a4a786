//! The lane type of batched runs (issue 26): several independent runs of one solver stepped
//! together, one run per lane of a SIMD vector, so that the CPU overlaps their dependency
//! chains instead of waiting on one.
//!
//! A solver's step is written once, generic over [`Lane`]: at `f64` it is the single run, at
//! [`Lanes4`] four runs. Each lane gives the bits of its run alone, because IEEE addition,
//! subtraction, multiplication, division and square root round the same in a vector lane as
//! in a scalar register. Fused multiply-add does not (one rounding instead of two), so a
//! generic step never calls `mul_add` (nor nalgebra's `axpy`, `gemv` and friends, which may):
//! only the element-wise operators, `norm` (whose sum of the three squares nalgebra adds in
//! index order for a 3-vector, as in a scalar run) and comparisons with `if_else`.

use crate::model::Vec3;
use nalgebra::Vector3;
use simba::simd::{SimdRealField, SimdValue, WideF64x4};

/// A value per run: `f64` for one run, [`Lanes4`] for four. Every [`SimdRealField`] whose lanes
/// are `f64` is one; a step generic over it must keep to the operations the module doc lists.
pub trait Lane: SimdRealField<Element = f64> + Copy {}

impl<T: SimdRealField<Element = f64> + Copy> Lane for T {}

/// Four runs: the `wide` crate's f64x4 (through simba), fast in the default x86-64 build
/// (two SSE2 registers) and one AVX register where the target has AVX.
pub type Lanes4 = WideF64x4;

/// Sets lane `lane` of every point of `into` to the matching point of `from`.
pub fn load_points<T: Lane>(into: &mut [Vector3<T>], lane: usize, from: &[Vec3]) {
    for (into, from) in into.iter_mut().zip(from) {
        for (into, &from) in into.iter_mut().zip(from.iter()) {
            into.replace(lane, from);
        }
    }
}

/// Lane `lane` of every point of `from`, into `into`.
pub fn read_points<T: Lane>(from: &[Vector3<T>], lane: usize, into: &mut [Vec3]) {
    for (from, into) in from.iter().zip(into) {
        for (from, into) in from.iter().zip(into.iter_mut()) {
            *into = from.extract(lane);
        }
    }
}

/// Sets lane `lane` of every value of `into` to the matching value of `from`.
pub fn load_values<T: Lane>(into: &mut [T], lane: usize, from: &[f64]) {
    for (into, &from) in into.iter_mut().zip(from) {
        into.replace(lane, from);
    }
}

/// Per lane, `a` where `cond` holds and `b` elsewhere (a branch at `f64`). Component by
/// component: nalgebra's `select` on a whole vector is a generic map the compiler does not
/// inline, four times the cost of the XPBD sweep it sat in; inlined always, for the same reason
/// (a call passes the vectors through memory).
#[inline(always)]
pub fn select<T: Lane>(cond: T::SimdBool, a: Vector3<T>, b: Vector3<T>) -> Vector3<T> {
    Vector3::new(
        a.x.select(cond, b.x),
        a.y.select(cond, b.y),
        a.z.select(cond, b.z),
    )
}

/// The points `points[i]` at four indices as one point of four lanes (lane `j` from `at[j]`).
/// Written out and inlined always: through `map` and `from_fn` the compiler made it a call
/// per lane, which cost more than the four springs' arithmetic it fed.
#[inline(always)]
pub fn gather_points(points: &[Vec3], at: [usize; 4]) -> Vector3<Lanes4> {
    let [p0, p1, p2, p3] = [
        &points[at[0]],
        &points[at[1]],
        &points[at[2]],
        &points[at[3]],
    ];
    Vector3::new(
        Lanes4::from([p0.x, p1.x, p2.x, p3.x]),
        Lanes4::from([p0.y, p1.y, p2.y, p3.y]),
        Lanes4::from([p0.z, p1.z, p2.z, p3.z]),
    )
}

/// Lane `lane` of a point of four lanes.
#[inline(always)]
pub fn lane_point(point: &Vector3<Lanes4>, lane: usize) -> Vec3 {
    Vec3::new(
        point.x.extract(lane),
        point.y.extract(lane),
        point.z.extract(lane),
    )
}
