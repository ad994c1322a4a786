//! The sparse symmetric matrix of a system (compressed rows), assembled once per pattern.

/// A symmetric matrix with both triangles stored in compressed rows (which, the matrix being
/// symmetric, is also its compressed-column form).
#[derive(Debug, Clone, PartialEq)]
pub struct SymmetricMatrix {
    pub(super) n: usize,
    pub(super) row_ptr: Vec<usize>,
    pub(super) col_idx: Vec<usize>,
    pub(super) values: Vec<f64>,
}

impl SymmetricMatrix {
    /// The pattern of a node graph with `block`×`block` blocks: one diagonal block per node
    /// and two off-diagonal blocks per edge. Values start at zero.
    pub fn from_node_graph(nodes: usize, block: usize, edges: &[(usize, usize)]) -> Self {
        let mut neighbours: Vec<Vec<usize>> = (0..nodes).map(|i| vec![i]).collect();
        for &(a, b) in edges {
            neighbours[a].push(b);
            neighbours[b].push(a);
        }
        let n = nodes * block;
        let mut row_ptr = Vec::with_capacity(n + 1);
        let mut col_idx = Vec::new();
        row_ptr.push(0);
        for list in &mut neighbours {
            list.sort_unstable();
            list.dedup();
        }
        for list in &neighbours {
            for _ in 0..block {
                for &j in list {
                    col_idx.extend((0..block).map(|c| j * block + c));
                }
                row_ptr.push(col_idx.len());
            }
        }
        let values = vec![0.0; col_idx.len()];
        Self {
            n,
            row_ptr,
            col_idx,
            values,
        }
    }

    /// Dimension.
    pub fn dim(&self) -> usize {
        self.n
    }

    /// Index into the value array of entry (i, j); `None` outside the pattern.
    pub fn slot(&self, i: usize, j: usize) -> Option<usize> {
        let row = &self.col_idx[self.row_ptr[i]..self.row_ptr[i + 1]];
        row.binary_search(&j).ok().map(|k| self.row_ptr[i] + k)
    }

    /// Entry (i, j), zero outside the pattern.
    pub fn get(&self, i: usize, j: usize) -> f64 {
        self.slot(i, j).map_or(0.0, |k| self.values[k])
    }

    /// Adds `value` to entry (i, j).
    ///
    /// # Panics
    /// If (i, j) is outside the pattern: a programming error in the assembly, not bad input.
    pub fn add(&mut self, i: usize, j: usize, value: f64) {
        let k = self
            .slot(i, j)
            .unwrap_or_else(|| panic!("entry ({i}, {j}) is outside the sparsity pattern"));
        self.values[k] += value;
    }

    /// The stored values, in pattern order (for assembly through precomputed slots).
    pub fn values_mut(&mut self) -> &mut [f64] {
        &mut self.values
    }

    /// Sets every stored value to zero, keeping the pattern.
    pub fn clear(&mut self) {
        self.values.fill(0.0);
    }

    /// Row `i` as (column, value) pairs.
    pub fn row(&self, i: usize) -> impl Iterator<Item = (usize, f64)> + '_ {
        let range = self.row_ptr[i]..self.row_ptr[i + 1];
        self.col_idx[range.clone()]
            .iter()
            .copied()
            .zip(self.values[range].iter().copied())
    }

    /// The stored values, in pattern order.
    pub fn values(&self) -> &[f64] {
        &self.values
    }

    /// Row `i` as (slot, column) pairs: where each stored entry's value sits in
    /// [`Self::values`].
    pub fn row_slots(&self, i: usize) -> impl Iterator<Item = (usize, usize)> + '_ {
        (self.row_ptr[i]..self.row_ptr[i + 1]).zip(
            self.col_idx[self.row_ptr[i]..self.row_ptr[i + 1]]
                .iter()
                .copied(),
        )
    }

    /// $`y = A x`$.
    pub fn mul_vec(&self, x: &[f64], y: &mut [f64]) {
        for (i, yi) in y.iter_mut().enumerate() {
            *yi = self.row(i).map(|(j, a)| a * x[j]).sum();
        }
    }

    /// Half-bandwidth: the largest |i - j| of a stored entry.
    pub fn bandwidth(&self) -> usize {
        (0..self.n)
            .flat_map(|i| {
                self.col_idx[self.row_ptr[i]..self.row_ptr[i + 1]]
                    .iter()
                    .map(move |&j| i.abs_diff(j))
            })
            .max()
            .unwrap_or(0)
    }
}
