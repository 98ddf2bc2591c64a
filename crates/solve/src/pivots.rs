//! The inertia of a factorised symmetric matrix: how many pivots are positive, negative
//! and zero (what the interior-point method checks of its KKT matrix).

/// Number of positive, negative and zero pivots of a factorised symmetric matrix.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct Inertia {
    /// Positive pivots.
    pub positive: usize,
    /// Negative pivots.
    pub negative: usize,
    /// Zero (or failed) pivots.
    pub zero: usize,
}

impl Inertia {
    /// The inertia reported for a failed factorisation of a `dim`-row matrix: every pivot
    /// zero (singular).
    pub fn singular(dim: usize) -> Self {
        Inertia {
            positive: 0,
            negative: 0,
            zero: dim,
        }
    }
}
