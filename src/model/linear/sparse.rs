//! The sparse Cholesky factorisation of the larger sheets (faer's, simplicial or supernodal),
//! with three right-hand sides solved together on a simplicial factor, in panels of a
//! supernode's columns.

use super::node::Node;
use super::pivot::*;
use super::symmetric::SymmetricMatrix;
use crate::error::{Error, Result};
use faer::dyn_stack::{MemBuffer, MemStack};
use faer::sparse::linalg::cholesky::{
    factorize_symbolic_cholesky, CholeskySymbolicParams, LltRef, SymbolicCholesky,
    SymbolicCholeskyRaw,
};
use faer::sparse::linalg::SupernodalThreshold;
use faer::sparse::{SparseColMatRef, SymbolicSparseColMatRef};
use faer::{Conj, MatMut, Par, Side};

/// faer's sparse $`LL^\top`$ with its fill-reducing ordering (approximate minimum degree),
/// simplicial or supernodal, through its low-level interface so that the factor's values are
/// ours to read.
///
/// Three right-hand sides (Liu's and ADMM's coordinates) on a simplicial factor are solved by
/// `SparseCholesky::solve_three`, not by faer: faer sweeps the three columns of the column-major
/// right-hand side, so every entry of $`L`$ touches three cache lines n values apart, and it
/// permutes through a fresh buffer each solve; interleaving the coordinates makes it one line
/// and a reused buffer: 1.6 ms to 0.65 ms on the 100 × 100 sheet (`make timing`). Each node's
/// coordinates are padded to four (x, y, z, 0), one 256-bit vector, and the substitutions run
/// in AVX2 registers where the CPU has them (`solve_three_dispatched`, the same bits): the
/// global step 0.89 ms to 0.71 ms of thread CPU on a loaded Xeon. The columns are taken in
/// panels of up to four columns of a supernode (`Panels`), each row below a panel loaded
/// once for all its columns (`docs/performance.md`, "The sheet").
#[derive(Debug, Clone)]
pub struct SparseCholesky {
    pub(super) n: usize,
    pub(super) col_ptr: Vec<usize>,
    pub(super) row_idx: Vec<usize>,
    pub(super) symbolic: std::sync::Arc<SymbolicCholesky<usize>>,
    /// The values of $`L`$, in the layout of `symbolic`.
    pub(super) values: Vec<f64>,
    /// The simplicial factor in panels, for [`Self::solve_three`]; `None` for a supernodal one.
    pub(super) panels: Option<Panels>,
}

/// A simplicial factor in the form [`SparseCholesky::solve_three`] reads: its columns in
/// panels of at most [`PANEL_WIDTH`] consecutive columns with the same rows below them (a
/// fundamental supernode: column j + 1 is the parent of column j and has the rows of j but
/// itself), so that a row below a panel is read and written once for all its columns.
#[derive(Debug, Clone)]
pub(super) struct Panels {
    pub(super) panels: Vec<Panel>,
    /// The rows below each panel, panel after panel.
    row: Vec<u32>,
    /// Per panel: the inverse of its triangle (its columns' rows within the panel, a lower
    /// triangle, row by row), then its rows below, row-major (one value per column); refreshed
    /// by every factorisation.
    values: Vec<f64>,
    /// Where each entry of `values` is in the factor's values: for a panel's triangle, its
    /// diagonal, then its strict lower part column by column, which [`Self::load`] inverts in
    /// place.
    source: Vec<u32>,
    /// Row i of the permuted system is row `permutation[i]` of the matrix.
    pub(super) permutation: Vec<u32>,
}

/// A panel of [`Panels`]: columns `first..first + width` of $`L`$.
#[derive(Debug, Clone, Copy)]
pub(super) struct Panel {
    first: usize,
    pub(super) width: usize,
    /// Its rows below, `row[rows.0..rows.1]`.
    rows: (usize, usize),
    /// Where its values start in `values`.
    values: usize,
}

/// The widest panel. A row below a panel costs a load and a store of its four lanes (forward)
/// or a load (backward) shared by the panel's columns: on the 100 × 100 sheet (10,000 columns,
/// 5,128 fundamental supernodes; 87 % of the entries in supernodes of three columns or more)
/// the two substitutions took 0.23 ms in panels of four against 0.40 ms column by column
/// (scratch program, thread CPU, least of eight rounds); six or eight were no faster, and
/// panels relaxed to take in neighbouring columns with explicit zeros were slower.
const PANEL_WIDTH: usize = 4;

impl Panels {
    /// The panels of `symbolic` if it is simplicial with each column's diagonal first, its
    /// rows ascending, and its rows and entries counted in 32 bits (`None` otherwise: faer's
    /// solve is used).
    fn new(symbolic: &SymbolicCholesky<usize>) -> Option<Self> {
        let SymbolicCholeskyRaw::Simplicial(simplicial) = symbolic.raw() else {
            return None;
        };
        let factor = simplicial.factor();
        let n = factor.ncols();
        let col_ptr = factor.col_ptr();
        let row: Vec<u32> = factor
            .row_idx()
            .iter()
            .map(|&i| u32::try_from(i).ok())
            .collect::<Option<_>>()?;
        // `source` holds an entry's index in 32 bits.
        u32::try_from(row.len()).ok()?;
        let column = |j: usize| &row[col_ptr[j]..col_ptr[j + 1]];
        if (0..n).any(|j| column(j).first() != Some(&(j as u32)) || !column(j).is_sorted()) {
            return None;
        }
        // Column j + 1 continues j's supernode when it is j's parent (the first row below j's
        // diagonal) and has one row fewer: then its rows are j's but itself.
        let continues = |j: usize| {
            column(j).get(1) == Some(&(j as u32 + 1)) && column(j).len() == column(j + 1).len() + 1
        };
        let mut panels = Self {
            panels: Vec::new(),
            row: Vec::new(),
            values: Vec::new(),
            source: Vec::new(),
            permutation: match symbolic.perm() {
                Some(perm) => perm.arrays().0.iter().map(|&i| i as u32).collect(),
                None => (0..n as u32).collect(),
            },
        };
        let mut first = 0;
        while first < n {
            let mut width = 1;
            while width < PANEL_WIDTH && first + width < n && continues(first + width - 1) {
                width += 1;
            }
            if !panels.push(first, width, &col_ptr[first..=first + width], &row) {
                return None;
            }
            first += width;
        }
        Some(panels)
    }

    /// Appends the panel of columns `first..first + width` of a supernode, whose entries
    /// start at `col_ptr[c]` (the diagonal) in the factor, at rows `row`; false if a column's
    /// rows are not the panel's (which a supernode's are).
    fn push(&mut self, first: usize, width: usize, col_ptr: &[usize], row: &[u32]) -> bool {
        // The rows below the panel: its last column's below its diagonal, which every column
        // of a supernode has after the panel's own rows.
        let below = &row[col_ptr[width - 1] + 1..col_ptr[width]];
        let panel_rows = |c: usize| (first + c..first + width).map(|i| i as u32);
        if (0..width).any(|c| {
            !row[col_ptr[c]..col_ptr[c + 1]]
                .iter()
                .copied()
                .eq(panel_rows(c).chain(below.iter().copied()))
        }) {
            return false;
        }
        let start = self.row.len();
        self.row.extend_from_slice(below);
        self.panels.push(Panel {
            first,
            width,
            rows: (start, self.row.len()),
            values: self.source.len(),
        });
        let entry = |c: usize, k: usize| (col_ptr[c] + k) as u32;
        self.source.extend((0..width).map(|c| entry(c, 0)));
        for c in 0..width {
            self.source.extend((1..width - c).map(|k| entry(c, k)));
        }
        for r in 0..below.len() {
            self.source
                .extend((0..width).map(|c| entry(c, width - c + r)));
        }
        self.values.resize(self.source.len(), 0.0);
        true
    }

    /// Takes the values of a new factorisation (in the layout of the structure these panels
    /// were made from), each panel's triangle inverted.
    fn load(&mut self, factor: &[f64]) {
        for (v, &k) in self.values.iter_mut().zip(&self.source) {
            *v = factor[k as usize];
        }
        for p in &self.panels {
            let w = p.width;
            invert_triangle(w, &mut self.values[p.values..p.values + w * (w + 1) / 2]);
        }
    }
}

/// The inverse of a lower triangle of `w` rows given as its diagonal, then its strict lower
/// part column by column, written over it row by row. A panel's substitution then multiplies
/// by it: each of its columns a sum of products that are independent of each other, where the
/// triangle's own substitution is a chain of `w` divisions and products. The chains through
/// consecutive panels (parent and child in 57 % of the 100 × 100 sheet's) bound the
/// substitutions: the two took 200-202 µs against 211 µs (a scratch program, least of 250, one
/// core), and 18 µs more with three dependent products added to each column's chain.
// The triangle's entries by their row and column, as the formula writes them.
#[allow(clippy::needless_range_loop)]
fn invert_triangle(w: usize, triangle: &mut [f64]) {
    let mut l = [[0.0; PANEL_WIDTH]; PANEL_WIDTH];
    let mut k = w;
    for c in 0..w {
        l[c][c] = triangle[c];
        for r in c + 1..w {
            l[r][c] = triangle[k];
            k += 1;
        }
    }
    let mut inverse = [[0.0; PANEL_WIDTH]; PANEL_WIDTH];
    for c in 0..w {
        for r in c..w {
            let mut s = if r == c { 1.0 } else { 0.0 };
            for j in c..r {
                s -= l[r][j] * inverse[j][c];
            }
            inverse[r][c] = s / l[r][r];
        }
    }
    let rows = inverse.iter().enumerate().take(w);
    for (v, &e) in triangle
        .iter_mut()
        .zip(rows.flat_map(|(r, row)| &row[..=r]))
    {
        *v = e;
    }
}

thread_local! {
    /// The interleaved right-hand sides of [`SparseCholesky::solve_three`], reused.
    static INTERLEAVED: std::cell::RefCell<Vec<Node>> = const { std::cell::RefCell::new(Vec::new()) };
}

impl SparseCholesky {
    /// Symbolic analysis (fill-reducing ordering) and a first numeric factorisation, simplicial
    /// or supernodal as faer's heuristic chooses (supernodal for large, dense-enough factors:
    /// its dense kernels factor them fastest).
    pub fn new(a: &SymmetricMatrix) -> Result<Self> {
        Self::with_threshold(a, SupernodalThreshold::default())
    }

    /// [`Self::new`] with the simplicial factor whatever the size: slower to factor than a
    /// supernodal one past some thousands of unknowns, but solved for three right-hand sides by
    /// `SparseCholesky::solve_three`, several times faster than faer's supernodal solve on the sheet
    /// (`make timing`), and by this crate's loops only, whose bits do not depend on the CPU.
    pub fn simplicial(a: &SymmetricMatrix) -> Result<Self> {
        Self::with_threshold(a, SupernodalThreshold::FORCE_SIMPLICIAL)
    }

    fn with_threshold(a: &SymmetricMatrix, threshold: SupernodalThreshold) -> Result<Self> {
        let col_ptr = a.row_ptr.clone();
        let row_idx = a.col_idx.clone();
        let pattern = SymbolicSparseColMatRef::new_checked(a.n, a.n, &col_ptr, None, &row_idx);
        let params = CholeskySymbolicParams {
            supernodal_flop_ratio_threshold: threshold,
            ..Default::default()
        };
        let symbolic =
            factorize_symbolic_cholesky(pattern, Side::Lower, Default::default(), params)
                .map_err(|e| Error::Input(format!("sparse Cholesky analysis failed: {e:?}")))?;
        let mut f = Self {
            n: a.n,
            values: vec![0.0; symbolic.len_val()],
            panels: Panels::new(&symbolic),
            col_ptr,
            row_idx,
            symbolic: std::sync::Arc::new(symbolic),
        };
        f.refactor(a)?;
        Ok(f)
    }

    /// Numeric refactorisation with the kept symbolic analysis.
    pub fn refactor(&mut self, a: &SymmetricMatrix) -> Result<()> {
        let pattern = SymbolicSparseColMatRef::new_checked(
            self.n,
            self.n,
            &self.col_ptr,
            None,
            &self.row_idx,
        );
        let mut scratch = MemBuffer::new(
            self.symbolic
                .factorize_numeric_llt_scratch::<f64>(Par::Seq, Default::default()),
        );
        self.symbolic
            .factorize_numeric_llt(
                &mut self.values,
                SparseColMatRef::new(pattern, &a.values),
                Side::Lower,
                Default::default(),
                Par::Seq,
                MemStack::new(&mut scratch),
                Default::default(),
            )
            // The pivot's index is in the fill-reducing order: meaningless to the caller.
            .map_err(|_| not_positive_definite(usize::MAX, f64::NAN))?;
        if let Some(panels) = &mut self.panels {
            panels.load(&self.values);
        }
        Ok(())
    }

    /// Solves all right-hand sides at once (the three coordinates of Liu and ADMM together).
    pub fn solve_in_place(&self, b: &mut [f64], ncols: usize) {
        if let (3, Some(panels)) = (ncols, &self.panels) {
            return self.solve_three(panels, &mut b[..3 * self.n]);
        }
        let rhs = MatMut::from_column_major_slice_mut(&mut b[..self.n * ncols], self.n, ncols);
        let mut scratch =
            MemBuffer::new(self.symbolic.solve_in_place_scratch::<f64>(ncols, Par::Seq));
        LltRef::new(&self.symbolic, &self.values).solve_in_place_with_conj(
            Conj::No,
            rhs,
            Par::Seq,
            MemStack::new(&mut scratch),
        );
    }

    /// The order in which [`Self::solve_nodes_in_order`] takes the nodes: row q of the
    /// permuted system is node `order[q]` (the fill-reducing ordering); None where the solve
    /// is faer's (a supernodal factor), which takes the nodes in their own order.
    pub fn node_order(&self) -> Option<&[u32]> {
        self.panels.as_ref().map(|panels| &panels.permutation[..])
    }

    /// $`A x = b`$ for the three coordinates of every node, held node by node in
    /// [`Self::node_order`] (`y`, overwritten by $`x`$): the two substitutions of
    /// [`Self::solve_three`] without its permutations. None (nothing done) without panels.
    pub fn solve_nodes_in_order(&self, y: &mut [Node]) -> Option<()> {
        let panels = self.panels.as_ref()?;
        solve_three_dispatched(panels, &mut y[..self.n]);
        Some(())
    }

    /// $`L y = P b`$ panel by panel (each panel's columns scatter into the rows below), then
    /// $`L^\top z = y`$ (each panel's columns gather), $`x = P^\top z`$, for the three columns
    /// of `b` interleaved: node i's three coordinates side by side, and a fourth lane of zeros.
    fn solve_three(&self, panels: &Panels, b: &mut [f64]) {
        let n = self.n;
        INTERLEAVED.with(|cell| {
            let mut y = cell.borrow_mut();
            y.resize(n, Node::default());
            for (y, &p) in y.iter_mut().zip(&panels.permutation) {
                let p = p as usize;
                y.0 = [b[p], b[n + p], b[2 * n + p], 0.0];
            }
            solve_three_dispatched(panels, &mut y);
            for (y, &p) in y.iter().zip(&panels.permutation) {
                let p = p as usize;
                [b[p], b[n + p], b[2 * n + p]] = [y.0[0], y.0[1], y.0[2]];
            }
        });
    }
}

/// [`substitute_three`] in AVX2 registers where the CPU has them (a node's four lanes, one
/// 256-bit vector; AVX-512 measured no faster), chosen at run time. The bits do not depend on
/// the choice: each lane adds and multiplies in the same order whatever the vector width, and
/// Rust never fuses a multiplication and an addition into one rounding.
pub(super) fn solve_three_dispatched(panels: &Panels, y: &mut [Node]) {
    #[cfg(target_arch = "x86_64")]
    if std::is_x86_feature_detected!("avx2") {
        #[target_feature(enable = "avx2")]
        unsafe fn avx2(panels: &Panels, y: &mut [Node]) {
            substitute_three(panels, y)
        }
        // SAFETY: the CPU has AVX2, detected above.
        return unsafe { avx2(panels, y) };
    }
    substitute_three(panels, y)
}

/// `kernel::<W>(args)` for a panel of `width` columns (1 to [`PANEL_WIDTH`]), so that each
/// width's loops are compiled with `W` a constant.
macro_rules! by_width {
    ($width:expr, $kernel:ident($($arg:expr),*)) => {
        match $width {
            1 => $kernel::<1>($($arg),*),
            2 => $kernel::<2>($($arg),*),
            3 => $kernel::<3>($($arg),*),
            _ => $kernel::<PANEL_WIDTH>($($arg),*),
        }
    };
}

/// The two substitutions of [`SparseCholesky::solve_three`] on the permuted, interleaved `y`,
/// each panel by the kernel of its width.
#[inline(always)]
pub(super) fn substitute_three(panels: &Panels, y: &mut [Node]) {
    let (row, values) = (&panels.row[..], &panels.values[..]);
    for p in &panels.panels {
        by_width!(p.width, forward_panel(p, row, values, y));
    }
    for p in panels.panels.iter().rev() {
        by_width!(p.width, backward_panel(p, row, values, y));
    }
}

/// A panel's values: the inverse of its triangle (row by row, lower) and its rows below
/// (row-major, `W` values a row).
#[inline(always)]
fn panel_values<'v, const W: usize>(p: &Panel, values: &'v [f64]) -> [&'v [f64]; 2] {
    let rows = p.rows.1 - p.rows.0;
    let v = &values[p.values..p.values + W * (W + 1) / 2 + W * rows];
    let (inverse, below) = v.split_at(W * (W + 1) / 2);
    [inverse, below]
}

/// The forward substitution of one panel of `W` columns: its columns times the inverse of its
/// triangle, then every row below loaded once, every column's term taken from it in column
/// order (the order of a column-by-column substitution), and stored once. A node's four lanes
/// are one vector operation ([`Node`]'s arithmetic).
#[inline(always)]
fn forward_panel<const W: usize>(p: &Panel, row: &[u32], values: &[f64], y: &mut [Node]) {
    let [inverse, below] = panel_values::<W>(p, values);
    let y_0: [Node; W] = std::array::from_fn(|c| y[p.first + c]);
    let mut first = 0;
    for r in 0..W {
        let mut sum = y_0[0] * inverse[first];
        for c in 1..=r {
            sum = sum + y_0[c] * inverse[first + c];
        }
        first += r + 1;
        // Not copy_from_slice: a call to memcpy per panel, 10 % of the substitutions.
        y[p.first + r] = sum;
    }
    let y_c: [Node; W] = std::array::from_fn(|c| y[p.first + c]);
    for (&i, l) in row[p.rows.0..p.rows.1].iter().zip(below.chunks_exact(W)) {
        let y_i = &mut y[i as usize];
        let mut sum = *y_i;
        for c in 0..W {
            sum = sum - y_c[c] * l[c];
        }
        *y_i = sum;
    }
}

/// The backward substitution of one panel of `W` columns: every row below loaded once and
/// its term added to each column's sum (the panel's columns are independent sums, whose
/// additions overlap), then the columns less their sums times the transposed inverse of the
/// triangle.
#[inline(always)]
fn backward_panel<const W: usize>(p: &Panel, row: &[u32], values: &[f64], y: &mut [Node]) {
    let [inverse, below] = panel_values::<W>(p, values);
    let mut sums = [Node::default(); W];
    for (&i, l) in row[p.rows.0..p.rows.1].iter().zip(below.chunks_exact(W)) {
        let y_i = y[i as usize];
        for c in 0..W {
            sums[c] = sums[c] + y_i * l[c];
        }
    }
    let y_0: [Node; W] = std::array::from_fn(|c| y[p.first + c] - sums[c]);
    for c in 0..W {
        let mut sum = y_0[c] * inverse[c * (c + 1) / 2 + c];
        for r in c + 1..W {
            sum = sum + y_0[r] * inverse[r * (r + 1) / 2 + c];
        }
        y[p.first + c] = sum;
    }
}
