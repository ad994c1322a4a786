//! Axes: the data's extent, the range and scale of an axis, and its ticks (decades in
//! superscript on a log axis, one number of decimals on a linear one).

use super::*;
use mass_spring_solvers::error::Error;

pub(super) fn plot_error(message: String) -> Error {
    Error::Input(format!("drawing a figure: {message}"))
}

/// A range with a coordinate transform: linear or log10.
#[derive(Debug, Clone, Copy)]
pub(super) struct Scale {
    pub(super) log: bool,
    pub(super) lo: f64,
    pub(super) hi: f64,
    /// Screen interval, pt; `a` maps `lo`.
    pub(super) a: f64,
    pub(super) b: f64,
}

impl Scale {
    /// The x axis of `frame` over `range`, left to right.
    pub(super) fn along_x(log: bool, range: (f64, f64), frame: &Rect) -> Self {
        Self {
            log,
            lo: range.0,
            hi: range.1,
            a: frame.x0,
            b: frame.x1,
        }
    }

    pub(super) fn t(&self, v: f64) -> f64 {
        if self.log {
            v.log10()
        } else {
            v
        }
    }

    pub(super) fn map(&self, v: f64) -> f64 {
        let (lo, hi) = (self.t(self.lo), self.t(self.hi));
        self.a + (self.t(v) - lo) / (hi - lo) * (self.b - self.a)
    }

    pub(super) fn valid(&self, v: f64) -> bool {
        v.is_finite() && (!self.log || v > 0.0)
    }
}

/// Data extent of an axis over a panel's series, labels, arrows and bands.
pub(super) fn extent(
    panel: &Panel,
    pick: impl Fn((f64, f64)) -> f64,
    log: bool,
) -> Option<(f64, f64)> {
    let points = panel
        .series
        .iter()
        .flat_map(|s| s.points.iter().copied())
        .chain(panel.labels.iter().map(|l| l.at))
        .chain(panel.arrows.iter().flat_map(|a| [a.from, a.to]))
        .chain(
            panel
                .bands
                .iter()
                .flat_map(|b| b.lower.iter().chain(&b.upper).copied()),
        );
    let (lo, hi) = points
        .map(pick)
        .filter(|v| v.is_finite() && (!log || *v > 0.0))
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), v| {
            (lo.min(v), hi.max(v))
        });
    lo.is_finite().then_some((lo, hi))
}

/// An axis range: fixed, or the data's extent padded by 5 % of it and at least `pad_pt` of
/// the `length_pt` the axis is drawn on, so no marker touches the frame.
pub(super) fn axis_range(axis: &Axis, data: Option<(f64, f64)>, length_pt: f64) -> (f64, f64) {
    if let Some(r) = axis.range {
        return r;
    }
    let Some((lo, hi)) = data else {
        return if axis.log { (0.1, 10.0) } else { (0.0, 1.0) };
    };
    let (tlo, thi) = if axis.log {
        (lo.log10(), hi.log10())
    } else {
        (lo, hi)
    };
    // A single value gets a decade (log), ±10 % of itself, or ±0.5 around zero.
    let span = if thi > tlo {
        thi - tlo
    } else if axis.log || tlo == 0.0 {
        1.0
    } else {
        0.2 * tlo.abs()
    };
    let fraction = (EDGE_PAD_PT / length_pt.max(1.0)).max(0.05);
    // pad = fraction of the padded span: span + 2 pad = span / (1 - 2 fraction).
    let pad = if thi > tlo {
        span * fraction / (1.0 - 2.0 * fraction).max(0.2)
    } else {
        span / 2.0
    };
    let (a, b) = (tlo - pad, thi + pad);
    if axis.log {
        (10f64.powf(a), 10f64.powf(b))
    } else {
        (a, b)
    }
}

pub(super) const SUPERSCRIPTS: [char; 10] = ['⁰', '¹', '²', '³', '⁴', '⁵', '⁶', '⁷', '⁸', '⁹'];

/// `10⁻³`: a power of ten with a superscript exponent.
pub fn power_of_ten(exponent: i32) -> String {
    let mut s = String::from("10");
    if exponent < 0 {
        s.push('⁻');
    }
    for d in exponent.unsigned_abs().to_string().bytes() {
        s.push(SUPERSCRIPTS[(d - b'0') as usize]);
    }
    s
}

/// Ticks of a range: (value, label, major). Linear: multiples of 1, 2 or 5 × 10ᵏ, at most six.
/// Log: decades (every second or third when there are many), with 2 and 5 labelled when the
/// range spans less than two decades, and unlabelled minor ticks at 2-9 × 10ᵏ.
pub(super) fn ticks(lo: f64, hi: f64, log: bool) -> Vec<(f64, String, bool)> {
    if !log {
        let span = hi - lo;
        let raw = span / 6.0;
        let k = raw.log10().floor();
        let base = 10f64.powf(k);
        let step = [1.0, 2.0, 5.0, 10.0]
            .into_iter()
            .map(|m| m * base)
            .find(|s| *s >= raw * 0.999)
            .unwrap_or(10.0 * base);
        let decimals = (-(step.log10().floor())).max(0.0) as usize;
        let first = (lo / step - 1e-9).ceil() as i64;
        let last = (hi / step + 1e-9).floor() as i64;
        return (first..=last)
            .map(|i| {
                let v = i as f64 * step;
                let mut s = format!("{v:.decimals$}");
                if s.starts_with('-') && s.trim_start_matches(['-', '0', '.']).is_empty() {
                    s.remove(0);
                }
                (v, s.replace('-', "−"), true)
            })
            .collect();
    }
    let (a, b) = (lo.log10(), hi.log10());
    let first = (a - 1e-9).ceil() as i32;
    let last = (b + 1e-9).floor() as i32;
    let decades = (last - first + 1).max(0);
    let mut out = Vec::new();
    if decades < 2 {
        // Digits where they stay short; `2×10⁶` from 10⁴ up or below 10⁻⁴, never `2000000`.
        let digits = |v: f64| {
            let e = v.log10().floor();
            if !(-4.0..4.0).contains(&e) {
                let m = (v / 10f64.powf(e)).round();
                let power = power_of_ten(e as i32);
                return if m == 1.0 {
                    power
                } else {
                    format!("{m}×{power}")
                };
            }
            let decimals = (-e).max(0.0) as usize;
            format!("{v:.decimals$}")
        };
        for e in (a.floor() as i32)..=(b.ceil() as i32) {
            for m in [1.0, 2.0, 5.0] {
                let v = m * 10f64.powi(e);
                if v >= lo * (1.0 - 1e-9) && v <= hi * (1.0 + 1e-9) {
                    out.push((v, digits(v), true));
                }
            }
        }
        return out;
    }
    let every = match decades {
        0..=7 => 1,
        8..=13 => 2,
        _ => 3,
    };
    for e in (a.floor() as i32)..=(b.ceil() as i32) {
        let v = 10f64.powi(e);
        if e >= first && e <= last && (e - first) % every == 0 {
            out.push((v, power_of_ten(e), true));
        }
        if every == 1 && decades <= 5 {
            for m in 2..10 {
                let v = m as f64 * 10f64.powi(e);
                if v > lo && v < hi {
                    out.push((v, String::new(), false));
                }
            }
        }
    }
    out
}

/// Width of the widest tick label of an axis range, pt.
pub(super) fn tick_width(lo: f64, hi: f64, log: bool) -> f64 {
    ticks(lo, hi, log)
        .iter()
        .map(|t| text_width(&t.1, TEXT_PT))
        .fold(0.0, f64::max)
}

/// The ranges of a panel drawn on an axes box of `w` × `h` pt.
pub(super) fn ranges(panel: &Panel, w: f64, h: f64) -> ((f64, f64), (f64, f64)) {
    let xr = axis_range(&panel.x, extent(panel, |p| p.0, panel.x.log), w);
    let yr = axis_range(&panel.y, extent(panel, |p| p.1, panel.y.log), h);
    if !panel.equal_aspect || panel.x.log || panel.y.log {
        return (xr, yr);
    }
    let (sx, sy) = (w / (xr.1 - xr.0), h / (yr.1 - yr.0));
    if sx > sy {
        let half = w / sy / 2.0;
        let c = (xr.0 + xr.1) / 2.0;
        ((c - half, c + half), yr)
    } else {
        let half = h / sx / 2.0;
        let c = (yr.0 + yr.1) / 2.0;
        (xr, (c - half, c + half))
    }
}
