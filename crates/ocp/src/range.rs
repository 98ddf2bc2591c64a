//! The lower and upper bound of one quantity and its scale factor.

/// Lower and upper bound of one quantity (physical units).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Range {
    /// Lower bound.
    pub lo: f64,
    /// Upper bound.
    pub hi: f64,
}

impl Range {
    /// Scale factor max(|lo|, |hi|) (1 when both are 0).
    pub fn scale(&self) -> f64 {
        let s = self.lo.abs().max(self.hi.abs());
        if s > 0.0 {
            s
        } else {
            1.0
        }
    }
}
