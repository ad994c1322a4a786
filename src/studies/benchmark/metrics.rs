//! The benchmark's errors ([`super`], item 3 of its specification): per node, in metres and
//! relative to the exact motion's amplitude, and the lowest mode's phase and amplitude.

use crate::model::system::{MassSpringSystem, Vec3};
use crate::studies::work_precision::SAMPLE_INTERVAL_S;

/// What a run records over the window: the positions at every sample time and the lowest
/// mode's coordinate and energy after every step.
#[derive(Debug, Clone, PartialEq)]
pub struct Trajectory {
    /// Time step, s.
    pub dt: f64,
    /// Positions at $`t_j = j\cdot`$ [`SAMPLE_INTERVAL_S`], $`j = 1 \dots J`$.
    pub samples: Vec<Vec<Vec3>>,
    /// The lowest mode's coordinate after each step $`n = 1 \dots`$ (time $`n\,dt`$).
    pub modal: Vec<f64>,
    /// The lowest mode's energy after each step.
    pub modal_energy: Vec<f64>,
}

impl Trajectory {
    /// The trajectory cut at `window` seconds.
    pub fn truncate(&mut self, window: f64) {
        self.samples
            .truncate((window / SAMPLE_INTERVAL_S).round() as usize);
        let steps = (window / self.dt).round() as usize;
        self.modal.truncate(steps);
        self.modal_energy.truncate(steps);
    }
}

/// The free nodes of a system (the errors are over them: fixed nodes never err).
fn free_nodes(system: &MassSpringSystem) -> Vec<usize> {
    (0..system.len())
        .filter(|&i| !system.nodes()[i].fixed)
        .collect()
}

/// The RMS over samples and free nodes of the distance between two sampled motions, m:
/// $`\sqrt{\frac{1}{J N_f}\sum_j \sum_{i\ free} |a_i(t_j) - b_i(t_j)|^2}`$.
pub fn rms_distance(system: &MassSpringSystem, a: &[Vec<Vec3>], b: &[Vec<Vec3>]) -> f64 {
    let free = free_nodes(system);
    let (sum, count) = a.iter().zip(b).fold((0.0, 0usize), |(s, n), (a, b)| {
        (
            s + free
                .iter()
                .map(|&i| (a[i] - b[i]).norm_squared())
                .sum::<f64>(),
            n + free.len(),
        )
    });
    (sum / count.max(1) as f64).sqrt()
}

/// The RMS over samples and free nodes of the distance of a sampled motion to one state, m.
pub fn rms_distance_to(system: &MassSpringSystem, a: &[Vec<Vec3>], x: &[Vec3]) -> f64 {
    let held: Vec<Vec<Vec3>> = vec![x.to_vec(); a.len()];
    rms_distance(system, a, &held)
}

/// The largest node distance between two sampled motions over all samples, m.
pub fn largest_distance(a: &[Vec<Vec3>], b: &[Vec<Vec3>]) -> f64 {
    a.iter()
        .zip(b)
        .flat_map(|(a, b)| a.iter().zip(b).map(|(p, q)| (p - q).norm()))
        .fold(0.0, f64::max)
}

/// The period of the lowest mode in a run, s: the mean interval between the upward crossings
/// of its coordinate through its mean over the window (times interpolated linearly between
/// steps); None with fewer than two crossings (a run that does not oscillate).
pub fn modal_period(t: &Trajectory) -> Option<f64> {
    let q = &t.modal;
    if q.len() < 2 {
        return None;
    }
    let mean = q.iter().sum::<f64>() / q.len() as f64;
    let crossings: Vec<f64> = q
        .windows(2)
        .enumerate()
        .filter(|(_, w)| w[0] - mean < 0.0 && w[1] - mean >= 0.0)
        .map(|(n, w)| {
            let fraction = (mean - w[0]) / (w[1] - w[0]);
            (n as f64 + 1.0 + fraction) * t.dt
        })
        .collect();
    match crossings.as_slice() {
        [first, .., last] => Some((last - first) / (crossings.len() - 1) as f64),
        _ => None,
    }
}

/// The fraction of the lowest mode's energy lost per `period` seconds: the least-squares rate
/// $`\kappa`$ of $`\ln E(t) \approx a - \kappa t`$ over the window's steps, then
/// $`1 - e^{-\kappa T}`$. Energies below [`ENERGY_FLOOR`] of the first are taken at it (a run
/// that parks the rope at rest loses it all).
pub fn energy_decay_per_period(t: &Trajectory, period: f64) -> Option<f64> {
    let e = &t.modal_energy;
    let first = *e.first()?;
    if first <= 0.0 || e.len() < 2 {
        return None;
    }
    let floor = ENERGY_FLOOR * first;
    let n = e.len() as f64;
    let (mut st, mut sy, mut stt, mut sty) = (0.0, 0.0, 0.0, 0.0);
    for (k, &energy) in e.iter().enumerate() {
        let time = (k + 1) as f64 * t.dt;
        let y = energy.max(floor).ln();
        st += time;
        sy += y;
        stt += time * time;
        sty += time * y;
    }
    let slope = (n * sty - st * sy) / (n * stt - st * st);
    Some(1.0 - (slope * period).exp())
}

/// Energies below this fraction of the first count as this fraction.
pub const ENERGY_FLOOR: f64 = 1e-12;
