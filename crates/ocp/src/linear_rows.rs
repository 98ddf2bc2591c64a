//! The linear constraint rows of the transcription (collocation, continuity, symmetry):
//! sums of variable terms, some times the interval length h = t_f / N.

/// One entry of a linear or bilinear constraint: `coef · x[var]`, optionally times t_f/N.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Term {
    pub(crate) var: usize,
    pub(crate) coef: f64,
    pub(crate) times_h: bool,
}

/// A constraint row that is a sum of terms (collocation, continuity, symmetry).
#[derive(Clone, Debug)]
pub(crate) struct LinearRow {
    pub(crate) row: usize,
    pub(crate) terms: Vec<Term>,
}
