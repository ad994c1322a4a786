//! What this machine does at best in the loops of the sheet's Liu iteration, for the bound of
//! `make timing` ("The bound of an iteration"): the read bandwidth of a buffer the size of the
//! factor, the local step's square root and division per spring, and the substitutions'
//! multiplication and addition of a node's four lanes per factor entry.
//!
//! The kernels live in the library, compiled with it (optimised and vectorised), whatever the
//! profile of the crate that calls them: the presentation crate is built unoptimised
//! (`Cargo.toml`), and these loops measured there would be the compiler's, not the machine's.
//! Each takes the clock it is measured by (the caller's thread CPU clock, as a function
//! pointer: a generic parameter would have the kernel compiled in the caller's crate) and the
//! number of timed batches, and returns the best batch.

use std::time::Instant;

/// Read bandwidth of a buffer of `bytes`, B/s: the best of `repeats` batches of sums over it
/// in eight independent lanes (vectorised), each batch at least `batch_seconds` long, timed by
/// `clock` (s).
pub fn read_bandwidth(bytes: usize, clock: fn() -> f64, repeats: usize, batch_seconds: f64) -> f64 {
    let buffer: Vec<f64> = (0..(bytes / 8).max(64)).map(|i| (i % 7) as f64).collect();
    let sum = |v: &[f64]| {
        let mut lanes = [0.0; 8];
        for chunk in v.chunks_exact(8) {
            for (l, x) in lanes.iter_mut().zip(chunk) {
                *l += x;
            }
        }
        lanes.iter().sum::<f64>()
    };
    let mut best = f64::INFINITY;
    let mut sink = 0.0;
    let once = {
        let t = Instant::now();
        sink += sum(&buffer);
        t.elapsed().as_secs_f64()
    };
    let batch = ((batch_seconds / once.max(1e-9)).ceil() as usize).clamp(1, 1 << 20);
    for _ in 0..repeats {
        let c = clock();
        for _ in 0..batch {
            sink += std::hint::black_box(sum(std::hint::black_box(&buffer)));
        }
        best = best.min((clock() - c) / batch as f64);
    }
    std::hint::black_box(sink);
    (buffer.len() * 8) as f64 / best
}

/// Throughput of the local step's arithmetic, s per spring: $`l_0/\sqrt{q}`$ over an in-cache
/// array, the square root and division that [`crate::solvers::projective::sphere_scales`]
/// does per spring; the best of `repeats` batches timed by `clock` (s).
pub fn sqrt_div_seconds(clock: fn() -> f64, repeats: usize) -> f64 {
    let q: Vec<f64> = (0..4096).map(|i| 1.0 + i as f64 * 1e-3).collect();
    let mut out = vec![0.0; q.len()];
    let batch = 2000;
    let mut best = f64::INFINITY;
    for _ in 0..repeats {
        let c = clock();
        for _ in 0..batch {
            for (o, q) in out.iter_mut().zip(std::hint::black_box(&q)) {
                *o = 1.5 / q.sqrt();
            }
            std::hint::black_box(&mut out);
        }
        best = best.min((clock() - c) / (batch * q.len()) as f64);
    }
    best
}

/// Throughput of the substitutions' arithmetic, s per entry of the factor: a multiplication
/// and an addition of four lanes (a node's x, y, z and padding, one AVX2 vector where the CPU
/// has it, 32-byte aligned, as in `SparseCholesky::solve_three`) into eight independent sums
/// over an in-cache array; the best of `repeats` batches timed by `clock` (s).
pub fn multiply_add_seconds(clock: fn() -> f64, repeats: usize) -> f64 {
    /// A node's four lanes, aligned as the solve's (an unaligned array measured 12 % slower).
    #[derive(Clone, Copy)]
    #[repr(align(32))]
    struct Node([f64; 4]);
    /// Eight sums of `l[k] * y[k]` over four lanes, the sums independent so that only the
    /// throughput counts.
    #[inline(always)]
    fn sums(l: &[f64], y: &[Node]) -> [[f64; 4]; 8] {
        let mut acc = [[0.0; 4]; 8];
        for (l, y) in l.chunks_exact(8).zip(y.chunks_exact(8)) {
            for k in 0..8 {
                for (acc, y) in acc[k].iter_mut().zip(y[k].0) {
                    *acc += l[k] * y;
                }
            }
        }
        acc
    }
    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx2")]
    unsafe fn sums_avx2(l: &[f64], y: &[Node]) -> [[f64; 4]; 8] {
        sums(l, y)
    }
    let run = |l: &[f64], y: &[Node]| {
        #[cfg(target_arch = "x86_64")]
        if std::is_x86_feature_detected!("avx2") {
            // SAFETY: the CPU has AVX2, detected above.
            return unsafe { sums_avx2(l, y) };
        }
        sums(l, y)
    };
    let l: Vec<f64> = (0..1024).map(|i| 1.0 + i as f64 * 1e-6).collect();
    let y: Vec<Node> = (0..1024).map(|i| Node([i as f64 * 1e-3; 4])).collect();
    let batch = 4000;
    let mut best = f64::INFINITY;
    for _ in 0..repeats {
        let c = clock();
        for _ in 0..batch {
            std::hint::black_box(run(std::hint::black_box(&l), std::hint::black_box(&y)));
        }
        best = best.min((clock() - c) / (batch * l.len()) as f64);
    }
    best
}
