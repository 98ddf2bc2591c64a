//! Dense ordinary least squares by column-pivoted Householder QR (faer).

use faer::prelude::*;
use faer::Mat;

/// Solves `min ‖A c − b‖₂` for a dense `A` (rows × cols, column-major `a`) and returns `c`.
///
/// Columns are scaled to unit Euclidean norm before a column-pivoted QR factorisation
/// (faer `ColPivQr`), which keeps high-order monomial bases well conditioned and handles
/// rank-deficient systems; the scaling is undone in the returned coefficients.
pub fn solve_least_squares(a: &mut Mat<f64>, b: &[f64]) -> Vec<f64> {
    let cols = a.ncols();
    let rows = a.nrows();
    let mut scale = vec![1.0; cols];
    for (j, s) in scale.iter_mut().enumerate() {
        let norm = (0..rows).map(|i| a[(i, j)] * a[(i, j)]).sum::<f64>().sqrt();
        if norm > 0.0 {
            *s = 1.0 / norm;
            for i in 0..rows {
                a[(i, j)] *= *s;
            }
        }
    }
    let rhs = Mat::<f64>::from_fn(rows, 1, |i, _| b[i]);
    let qr = a.col_piv_qr();
    let sol = qr.solve_lstsq(&rhs);
    (0..cols).map(|j| sol[(j, 0)] * scale[j]).collect()
}
