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
//!
//! The same lanes hold four springs of one run where their forces are independent
//! ([`each_spring_force`]): the forces four at a time, their sums one spring at a time.

use crate::model::Vec3;
use nalgebra::Vector3;
use simba::simd::{SimdPartialOrd, SimdRealField, SimdValue, WideF64x4};

/// A value per run: `f64` for one run, [`Lanes4`] for four. Every [`SimdRealField`] whose lanes
/// are `f64` is one; a step generic over it must keep to the operations the module doc lists.
pub trait Lane: SimdRealField<Element = f64> + Copy {}

impl<T: SimdRealField<Element = f64> + Copy> Lane for T {}

/// Four runs: the `wide` crate's f64x4 (through simba), fast in the default x86-64 build
/// (two SSE2 registers) and one AVX register where the target has AVX.
pub type Lanes4 = WideF64x4;

/// Runs in a [`Lanes4`]: the lanes of a batch (`crate::solvers::batch`).
pub const WIDTH: usize = <Lanes4 as SimdValue>::LANES;

/// Sets lane `lane` of every point of `into` to the matching point of `from`.
///
/// Each value is blended in (a broadcast, then a select by the lane's mask) rather than
/// replaced through memory: a replacement stores the vector, writes one lane and loads it
/// back, and the load waits for the narrower store to retire (a batch of damped runs loads
/// every lane's velocities after every step).
pub fn load_points(into: &mut [Vector3<Lanes4>], lane: usize, from: &[Vec3]) {
    let mask = lane_mask(|l| l == lane);
    for (into, from) in into.iter_mut().zip(from) {
        for (into, &from) in into.iter_mut().zip(from.iter()) {
            *into = Lanes4::splat(from).select(mask, *into);
        }
    }
}

/// A mask of lanes.
pub type LaneMask = <Lanes4 as SimdValue>::SimdBool;

/// Per lane, whether `lane_holds` holds of its index.
pub fn lane_mask(lane_holds: impl Fn(usize) -> bool) -> LaneMask {
    let ones = std::array::from_fn(|lane| if lane_holds(lane) { 1.0 } else { 0.0 });
    Lanes4::from(ones).simd_gt(Lanes4::splat(0.0))
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

/// An element between two points, by their indices: a spring ([`crate::model::system::Spring`]
/// implements it, so that this module need not import the model it serves).
pub trait TwoEnds {
    /// The indices of its two ends, a then b.
    fn ends(&self) -> (usize, usize);
}

/// A spring's inputs to a force: one spring's at `f64`, four springs' side by side at
/// [`Lanes4`] (lane `j` the `j`-th spring's).
pub trait SpringInputs<S, T: Lane> {
    /// The points of `points` at each spring's two ends, a then b.
    fn ends(&self, points: &[Vec3]) -> (Vector3<T>, Vector3<T>);
    /// Each spring's value `of`.
    fn value(&self, of: fn(&S) -> f64) -> T;
}

impl<S: TwoEnds> SpringInputs<S, f64> for &S {
    fn ends(&self, points: &[Vec3]) -> (Vec3, Vec3) {
        let (a, b) = TwoEnds::ends(*self);
        (points[a], points[b])
    }

    fn value(&self, of: fn(&S) -> f64) -> f64 {
        of(self)
    }
}

/// Inlined always, the points gathered written out (`gather_points`): through `map` and
/// `from_fn` over the points the compiler made each lane a call, which cost more than the four
/// springs' arithmetic they fed (the `map` over the four index pairs below did not).
impl<S: TwoEnds> SpringInputs<S, Lanes4> for [&S; 4] {
    #[inline(always)]
    fn ends(&self, points: &[Vec3]) -> (Vector3<Lanes4>, Vector3<Lanes4>) {
        let [e0, e1, e2, e3] = self.map(TwoEnds::ends);
        (
            gather_points(points, [e0.0, e1.0, e2.0, e3.0]),
            gather_points(points, [e0.1, e1.1, e2.1, e3.1]),
        )
    }

    #[inline(always)]
    fn value(&self, of: fn(&S) -> f64) -> Lanes4 {
        let [s0, s1, s2, s3] = self;
        Lanes4::from([of(s0), of(s1), of(s2), of(s3)])
    }
}

/// A force on a spring's first end (its second end takes the negative), written once for
/// every lane type.
pub trait SpringForce<S> {
    /// Implementations are inlined always (`#[inline(always)]`): a call returns the four
    /// lanes' force through memory, which cost a quarter more than the arithmetic.
    fn on_first_end<T: Lane>(&self, spring: &impl SpringInputs<S, T>) -> Vector3<T>;
}

/// Every spring's `force` on its first end, `sink(spring, force)` in spring order: computed
/// four springs at a time as the lanes of one vector (the square roots and divisions of four
/// springs in one instruction each), the springs left over one by one. Each lane's force has
/// the bits of its spring's own (IEEE arithmetic, the module doc), so whatever `sink` sums in
/// spring order has the bits of one spring at a time.
pub fn each_spring_force<S: TwoEnds>(
    springs: &[S],
    force: &impl SpringForce<S>,
    mut sink: impl FnMut(&S, Vec3),
) {
    let mut fours = springs.chunks_exact(4);
    for four in &mut fours {
        let four = [&four[0], &four[1], &four[2], &four[3]];
        let f = force.on_first_end(&four);
        for (lane, s) in four.into_iter().enumerate() {
            sink(s, lane_point(&f, lane));
        }
    }
    for s in fours.remainder() {
        sink(s, force.on_first_end(&s));
    }
}

/// The points `points[i]` at four indices as one point of four lanes (lane `j` from `at[j]`).
#[inline(always)]
fn gather_points(points: &[Vec3], at: [usize; 4]) -> Vector3<Lanes4> {
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
fn lane_point(point: &Vector3<Lanes4>, lane: usize) -> Vec3 {
    Vec3::new(
        point.x.extract(lane),
        point.y.extract(lane),
        point.z.extract(lane),
    )
}
