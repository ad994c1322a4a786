//! Number and table formatting shared by the report, its CSV files and its snapshots.
//!
//! Every number the report prints goes through one of these functions, so that the same
//! inputs give byte-identical output: [`sig`] rounds to a stated number of significant
//! digits (tables and snapshots), [`full`] prints the shortest decimal that round-trips an
//! `f64` (machine-readable CSV files).

/// Significant digits of every number in the report's tables and snapshots.
pub const SIGNIFICANT_DIGITS: usize = 4;

/// `x` rounded to `digits` significant digits: fixed notation for magnitudes from 1e-3 to
/// below 1e5, scientific (`3.560e-4`) otherwise; `0` for zero, `NaN`/`inf` as such.
pub fn sig(x: f64, digits: usize) -> String {
    let digits = digits.max(1);
    if !x.is_finite() {
        return format!("{x}");
    }
    if x == 0.0 {
        return "0".to_string();
    }
    // The exponent after rounding, so 9.9996 → 1.000e1 is placed correctly.
    let scientific = format!("{:.*e}", digits - 1, x);
    let exponent: i32 = scientific
        .rsplit('e')
        .next()
        .and_then(|e| e.parse().ok())
        .expect("Rust's {:e} always writes an integer exponent");
    if (-3..5).contains(&exponent) {
        let decimals = (digits as i32 - 1 - exponent).max(0) as usize;
        format!("{x:.decimals$}")
    } else {
        let (mantissa, _) = scientific.split_once('e').expect("scientific notation");
        format!("{mantissa}e{exponent}")
    }
}

/// [`sig`] with [`SIGNIFICANT_DIGITS`].
pub fn sig4(x: f64) -> String {
    sig(x, SIGNIFICANT_DIGITS)
}

/// An optional number with [`sig4`], or `–` when absent.
pub fn opt4(x: Option<f64>) -> String {
    x.map_or_else(|| "–".to_string(), sig4)
}

/// A signed relative deviation in percent with two significant digits (at least one
/// decimal), e.g. `+0.15 %`, `-12 %`.
pub fn percent(relative: f64) -> String {
    let p = 100.0 * relative;
    if p == 0.0 {
        return "0 %".to_string();
    }
    let text = sig(p.abs(), 2);
    let sign = if p > 0.0 { "+" } else { "-" };
    format!("{sign}{text} %")
}

/// A signed integer difference, `+2`, `0`, `-5`.
pub fn signed(diff: i64) -> String {
    if diff > 0 {
        format!("+{diff}")
    } else {
        diff.to_string()
    }
}

/// A count with its noun, singular for one: `1 iteration`, `30 iterations`.
pub fn counted(n: usize, noun: &str) -> String {
    if n == 1 {
        format!("1 {noun}")
    } else {
        format!("{n} {noun}s")
    }
}

/// The shortest decimal text that parses back to exactly `x` (Rust's `{:?}` for `f64`:
/// `0.001`, `1000000.0`, `3.7e-24`), for machine-readable files.
pub fn full(x: f64) -> String {
    format!("{x:?}")
}

/// A number for prose: the shortest decimal without exponent (`1`, `0.001`, `9.81`, `3000`).
pub fn short(x: f64) -> String {
    format!("{x}")
}

/// An optional [`full`] number, empty when absent (a CSV empty field).
pub fn full_opt(x: Option<f64>) -> String {
    x.map(full).unwrap_or_default()
}

/// A Markdown table with a header row; cells are written as given (a `|` inside a cell is
/// escaped).
#[derive(Debug, Clone, Default, PartialEq)]
pub struct MarkdownTable {
    header: Vec<String>,
    /// `true` for right-aligned (numeric) columns.
    right: Vec<bool>,
    rows: Vec<Vec<String>>,
}

impl MarkdownTable {
    /// A table with these column titles; titles starting with `>` are right-aligned (the `>`
    /// is dropped).
    pub fn new<S: AsRef<str>>(header: &[S]) -> Self {
        let (header, right) = header
            .iter()
            .map(|h| {
                let h = h.as_ref();
                match h.strip_prefix('>') {
                    Some(rest) => (rest.to_string(), true),
                    None => (h.to_string(), false),
                }
            })
            .unzip();
        Self {
            header,
            right,
            rows: Vec::new(),
        }
    }

    /// Appends a row; it must have as many cells as the header.
    pub fn row(&mut self, cells: Vec<String>) {
        assert_eq!(
            cells.len(),
            self.header.len(),
            "row width differs from the header's"
        );
        self.rows.push(cells);
    }

    /// Number of rows.
    pub fn len(&self) -> usize {
        self.rows.len()
    }

    /// Whether the table has no rows.
    pub fn is_empty(&self) -> bool {
        self.rows.is_empty()
    }

    /// The table as Markdown, ending with a newline.
    pub fn render(&self) -> String {
        let escape = |s: &str| s.replace('|', "\\|");
        let mut out = String::new();
        let line = |cells: &mut dyn Iterator<Item = String>| {
            let mut s = String::from("|");
            for c in cells {
                s.push(' ');
                s.push_str(&c);
                s.push_str(" |");
            }
            s.push('\n');
            s
        };
        out += &line(&mut self.header.iter().map(|h| escape(h)));
        out += &line(
            &mut self
                .right
                .iter()
                .map(|&r| if r { "---:" } else { "---" }.to_string()),
        );
        for row in &self.rows {
            out += &line(&mut row.iter().map(|c| escape(c)));
        }
        out
    }
}

/// `x` in scientific notation with 3 significant digits, `1.22e1`, `3.58e-3`: one format for a
/// column whose values span many orders of magnitude.
pub fn sci3(x: f64) -> String {
    if x == 0.0 {
        "0".into()
    } else {
        format!("{x:.2e}")
    }
}

/// A rest-state error below this is the round-off of a converged solve, not physics, m: the
/// report and the snapshots print it as the bound.
pub const ROUND_OFF_REST_ERROR_M: f64 = 1e-6;

/// A kinetic energy, J: [`sig4`], or `< 1e-15` below [`mass_spring_solvers::studies::forensics::NOISE_PEAK_J`], where
/// its digits are floating-point noise.
pub fn energy(e: f64) -> String {
    if e.abs() < mass_spring_solvers::studies::forensics::NOISE_PEAK_J {
        format!(
            "< {:e}",
            mass_spring_solvers::studies::forensics::NOISE_PEAK_J
        )
    } else {
        sig4(e)
    }
}

/// A rest-state error, m: [`sig4`], or `< 1e-6` below [`ROUND_OFF_REST_ERROR_M`].
pub fn rest_error(e: f64) -> String {
    if e.abs() < ROUND_OFF_REST_ERROR_M {
        format!("< {ROUND_OFF_REST_ERROR_M:e}")
    } else {
        sig4(e)
    }
}

/// [`rest_error`] of an optional error, `–` when absent.
pub fn opt_rest_error(e: Option<f64>) -> String {
    e.map_or_else(|| "–".to_string(), rest_error)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_count_of_one_is_singular() {
        assert_eq!(counted(1, "iteration"), "1 iteration");
        assert_eq!(counted(0, "iteration"), "0 iterations");
        assert_eq!(counted(30, "solver"), "30 solvers");
    }

    #[test]
    fn significant_digits() {
        assert_eq!(sig4(0.6773), "0.6773");
        assert_eq!(sig4(0.206), "0.2060");
        assert_eq!(sig4(12.2), "12.20");
        assert_eq!(sig4(1108.6999), "1109");
        assert_eq!(sig4(9.99996), "10.00");
        assert_eq!(sig4(3.56e-4), "3.560e-4");
        assert_eq!(sig4(0.001), "0.001000");
        assert_eq!(sig4(5381.81), "5382");
        assert_eq!(sig4(123456.0), "1.235e5");
        assert_eq!(sig4(-0.5), "-0.5000");
        assert_eq!(sig4(0.0), "0");
        assert_eq!(percent(0.0015), "+0.15 %");
        assert_eq!(percent(-0.123), "-12 %");
        assert_eq!(full(1e-3), "0.001");
        assert_eq!(full(1e6), "1000000.0");
        assert_eq!(signed(-3), "-3");
    }

    #[test]
    fn markdown() {
        let mut t = MarkdownTable::new(&["a", ">b"]);
        t.row(vec!["x|y".into(), "1".into()]);
        assert_eq!(t.render(), "| a | b |\n| --- | ---: |\n| x\\|y | 1 |\n");
    }
}
