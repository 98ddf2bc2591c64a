//! Sparsity patterns, bit sets for index-set propagation, and greedy graph colouring.

/// A sparsity pattern in coordinate form, sorted row-major (by row, then column).
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct Pattern {
    /// Number of rows.
    pub n_rows: usize,
    /// Number of columns.
    pub n_cols: usize,
    /// Row index of each structural nonzero.
    pub rows: Vec<u32>,
    /// Column index of each structural nonzero.
    pub cols: Vec<u32>,
}

impl Pattern {
    /// Number of structural nonzeros.
    pub fn nnz(&self) -> usize {
        self.rows.len()
    }
    /// Iterator over `(row, col)` of the structural nonzeros, in storage order.
    pub fn iter(&self) -> impl Iterator<Item = (usize, usize)> + '_ {
        self.rows
            .iter()
            .zip(&self.cols)
            .map(|(&r, &c)| (r as usize, c as usize))
    }
    /// Position of entry `(row, col)` in storage order, if structurally nonzero.
    pub fn find(&self, row: usize, col: usize) -> Option<usize> {
        let start = self.rows.partition_point(|&r| (r as usize) < row);
        let end = self.rows.partition_point(|&r| (r as usize) <= row);
        self.cols[start..end]
            .binary_search(&(col as u32))
            .ok()
            .map(|k| start + k)
    }
}

/// A fixed-width family of bit sets stored contiguously (one set per row).
#[derive(Clone, Debug)]
pub(crate) struct BitSets {
    words: usize,
    data: Vec<u64>,
}

impl BitSets {
    /// `n` empty sets over the universe `0..universe`.
    pub fn new(n: usize, universe: usize) -> Self {
        let words = universe.div_ceil(64).max(1);
        Self {
            words,
            data: vec![0; n * words],
        }
    }
    /// Number of 64-bit words per set.
    pub fn words(&self) -> usize {
        self.words
    }
    #[inline]
    pub fn row(&self, i: usize) -> &[u64] {
        &self.data[i * self.words..(i + 1) * self.words]
    }
    #[inline]
    pub fn insert(&mut self, i: usize, bit: usize) {
        self.data[i * self.words + bit / 64] |= 1 << (bit % 64);
    }
    /// Set `dst ∪= src` where both are rows of this family.
    #[inline]
    pub fn union_rows(&mut self, dst: usize, src: usize) {
        if dst == src {
            return;
        }
        let w = self.words;
        let (d, s) = if dst < src {
            let (lo, hi) = self.data.split_at_mut(src * w);
            (&mut lo[dst * w..dst * w + w], &hi[..w])
        } else {
            let (lo, hi) = self.data.split_at_mut(dst * w);
            (&mut hi[..w], &lo[src * w..src * w + w])
        };
        for (a, b) in d.iter_mut().zip(s) {
            *a |= *b;
        }
    }
    /// Set row `dst ∪= other` for an external set.
    #[inline]
    pub fn union_with(&mut self, dst: usize, other: &[u64]) {
        let w = self.words;
        for (a, b) in self.data[dst * w..dst * w + w].iter_mut().zip(other) {
            *a |= *b;
        }
    }
    #[inline]
    pub fn is_empty_row(&self, i: usize) -> bool {
        self.row(i).iter().all(|&w| w == 0)
    }
}

/// The elements of a bit set, ascending.
pub(crate) fn bits(set: &[u64]) -> impl Iterator<Item = usize> + '_ {
    set.iter().enumerate().flat_map(|(w, &word)| {
        let mut x = word;
        std::iter::from_fn(move || {
            if x == 0 {
                None
            } else {
                let t = x.trailing_zeros() as usize;
                x &= x - 1;
                Some(w * 64 + t)
            }
        })
    })
}

/// Greedy colouring of `n` vertices given each vertex's neighbour list; returns the
/// colour of each vertex and the number of colours.
pub(crate) fn greedy_colouring(neighbours: &[Vec<u32>]) -> (Vec<u32>, usize) {
    let n = neighbours.len();
    let mut colour = vec![u32::MAX; n];
    let mut forbidden: Vec<usize> = Vec::new();
    let mut n_colours = 0usize;
    for v in 0..n {
        for &u in &neighbours[v] {
            let c = colour[u as usize];
            if c != u32::MAX {
                let c = c as usize;
                if forbidden.len() <= c {
                    forbidden.resize(c + 1, usize::MAX);
                }
                forbidden[c] = v;
            }
        }
        let c = (0..)
            .find(|&c| forbidden.get(c).is_none_or(|&f| f != v))
            .unwrap_or(0);
        colour[v] = c as u32;
        n_colours = n_colours.max(c + 1);
    }
    (colour, n_colours)
}
