//! Limited-memory BFGS approximation of the Lagrangian Hessian in compact form
//! (Byrd, Nocedal & Schnabel 1994):
//!
//! ```text
//!     B = σ I − W M⁻¹ Wᵀ,   W = [σS  Y],   M = [[σ SᵀS, L], [Lᵀ, −D]]
//! ```
//!
//! with S, Y the stored steps and gradient differences, L the strictly lower part of SᵀY and
//! D its diagonal. The sparse KKT matrix is factorised with B replaced by σI; the low-rank
//! term is handled with the Sherman–Morrison–Woodbury formula ([`LowRankCorrection`]).

use std::collections::VecDeque;

/// Stored correction pairs and the scaling σ of the initial matrix.
#[derive(Debug, Clone)]
pub struct Lbfgs {
    capacity: usize,
    s: VecDeque<Vec<f64>>,
    y: VecDeque<Vec<f64>>,
    /// Diagonal of the initial approximation B₀ = σI.
    pub sigma: f64,
}

impl Lbfgs {
    /// An empty approximation keeping at most `capacity` pairs.
    pub fn new(capacity: usize) -> Self {
        Lbfgs {
            capacity: capacity.max(1),
            s: VecDeque::new(),
            y: VecDeque::new(),
            sigma: 1.0,
        }
    }

    /// Number of stored pairs.
    pub fn len(&self) -> usize {
        self.s.len()
    }

    /// Whether no pair is stored (B = σI).
    pub fn is_empty(&self) -> bool {
        self.s.is_empty()
    }

    /// Adds the pair (s, y) if it has enough positive curvature (sᵀy > 1e-8 ‖s‖‖y‖);
    /// returns whether it was kept.
    pub fn update(&mut self, s: &[f64], y: &[f64]) -> bool {
        let sy = dot(s, y);
        let ss = dot(s, s);
        let yy = dot(y, y);
        if !sy.is_finite() || sy <= 1e-8 * (ss * yy).sqrt() {
            return false;
        }
        // the oldest pair's storage is reused once the history is full
        let (mut s_new, mut y_new) = if self.s.len() == self.capacity {
            (
                self.s.pop_front().unwrap_or_default(),
                self.y.pop_front().unwrap_or_default(),
            )
        } else {
            (Vec::new(), Vec::new())
        };
        s_new.clear();
        s_new.extend_from_slice(s);
        y_new.clear();
        y_new.extend_from_slice(y);
        self.s.push_back(s_new);
        self.y.push_back(y_new);
        // B₀ = σI with σ = sᵀy / sᵀs (IPOPT's `scalar1`, the mean curvature along s). The
        // alternative yᵀy / sᵀy (`scalar2`) is dominated by the stiffest directions: on the
        // gait problem it gave δ-free but tiny steps and inf_du 1e9 (decision 0002).
        self.sigma = (sy / ss).clamp(1e-8, 1e8);
        true
    }

    /// Column `j` (0..2k) of W = [σS Y].
    fn w_col(&self, j: usize, out: &mut [f64]) {
        let k = self.len();
        if j < k {
            for (o, v) in out.iter_mut().zip(&self.s[j]) {
                *o = self.sigma * v;
            }
        } else {
            out.copy_from_slice(&self.y[j - k]);
        }
    }

    /// The 2k × 2k middle matrix M (row-major).
    fn middle(&self) -> Vec<f64> {
        let mut m = Vec::new();
        self.middle_into(&mut m);
        m
    }

    /// The 2k × 2k middle matrix M (row-major) written into `m`.
    fn middle_into(&self, m: &mut Vec<f64>) {
        let k = self.len();
        let d = 2 * k;
        m.clear();
        m.resize(d * d, 0.0);
        for i in 0..k {
            for j in 0..k {
                m[i * d + j] = self.sigma * dot(&self.s[i], &self.s[j]);
                let l = if i > j {
                    dot(&self.s[i], &self.y[j])
                } else {
                    0.0
                };
                m[i * d + k + j] = l;
                m[(k + j) * d + i] = l;
            }
            m[(k + i) * d + k + i] = -dot(&self.s[i], &self.y[i]);
        }
    }

    /// Product B v.
    pub fn multiply(&self, v: &[f64], out: &mut [f64]) {
        for (o, x) in out.iter_mut().zip(v) {
            *o = self.sigma * x;
        }
        let d = 2 * self.len();
        if d == 0 {
            return;
        }
        let n = v.len();
        let mut col = vec![0.0; n];
        let mut t = vec![0.0; d];
        for (j, tj) in t.iter_mut().enumerate() {
            self.w_col(j, &mut col);
            *tj = dot(&col, v);
        }
        let mut m = self.middle();
        if !lu_solve(&mut m, d, &mut t) {
            return;
        }
        for (j, &tj) in t.iter().enumerate() {
            self.w_col(j, &mut col);
            for (o, c) in out.iter_mut().zip(&col) {
                *o -= c * tj;
            }
        }
    }
}

/// Sherman–Morrison–Woodbury data for solving with K = K₀ − Ŵ M⁻¹ Ŵᵀ, where K₀ is the
/// factorised sparse KKT matrix with B replaced by σI and Ŵ = [W; 0]. Its buffers are reused
/// from one preparation to the next.
#[derive(Debug, Clone, Default)]
pub struct LowRankCorrection {
    d: usize,
    n: usize,
    /// K₀⁻¹ Ŵ, column-major (dim × 2k).
    z: Vec<f64>,
    /// W, column-major (n × 2k).
    w: Vec<f64>,
    /// Capacitance C = M − Ŵᵀ K₀⁻¹ Ŵ (row-major 2k × 2k).
    cap: Vec<f64>,
    /// Scratch of `apply`: Ŵᵀ x and the factorised copy of C.
    t: Vec<f64>,
    c: Vec<f64>,
}

impl LowRankCorrection {
    /// Prepares the correction: `solve0(cols, ncols)` solves with K₀ in place for `ncols`
    /// column-major right-hand sides of dimension `dim`.
    pub fn new(
        lb: &Lbfgs,
        n: usize,
        dim: usize,
        solve0: impl FnOnce(&mut [f64], usize) -> bool,
    ) -> Option<Self> {
        let mut c = LowRankCorrection::default();
        c.prepare(lb, n, dim, solve0).then_some(c)
    }

    /// Prepares the correction in place (as [`LowRankCorrection::new`]); returns false,
    /// leaving it unusable, when `solve0` fails.
    pub fn prepare(
        &mut self,
        lb: &Lbfgs,
        n: usize,
        dim: usize,
        solve0: impl FnOnce(&mut [f64], usize) -> bool,
    ) -> bool {
        let d = 2 * lb.len();
        (self.d, self.n) = (d, n);
        let (w, z) = (&mut self.w, &mut self.z);
        w.clear();
        w.resize(n * d, 0.0);
        z.clear();
        z.resize(dim * d, 0.0);
        for j in 0..d {
            lb.w_col(j, &mut w[j * n..(j + 1) * n]);
            z[j * dim..j * dim + n].copy_from_slice(&w[j * n..(j + 1) * n]);
        }
        if !solve0(z, d) {
            return false;
        }
        let cap = &mut self.cap;
        lb.middle_into(cap);
        for i in 0..d {
            for j in 0..d {
                cap[i * d + j] -= dot(&w[i * n..(i + 1) * n], &z[j * dim..j * dim + n]);
            }
        }
        true
    }

    /// Turns x₀ = K₀⁻¹ b into x = K⁻¹ b in place.
    pub fn apply(&mut self, x: &mut [f64]) {
        if self.d == 0 {
            return;
        }
        let (d, n, dim) = (self.d, self.n, x.len());
        let (t, c) = (&mut self.t, &mut self.c);
        t.clear();
        t.extend((0..d).map(|j| dot(&self.w[j * n..(j + 1) * n], &x[..n])));
        c.clear();
        c.extend_from_slice(&self.cap);
        if !lu_solve(c, d, t) {
            return;
        }
        for (j, &tj) in t.iter().enumerate() {
            for (xi, zi) in x.iter_mut().zip(&self.z[j * dim..(j + 1) * dim]) {
                *xi += zi * tj;
            }
        }
    }
}

/// Dot product.
pub fn dot(a: &[f64], b: &[f64]) -> f64 {
    a.iter().zip(b).map(|(x, y)| x * y).sum()
}

/// Solves the dense row-major `d × d` system in place by LU with partial pivoting (the
/// matrix is overwritten); returns false if it is singular.
pub fn lu_solve(a: &mut [f64], d: usize, b: &mut [f64]) -> bool {
    for k in 0..d {
        let p = (k..d)
            .max_by(|&i, &j| a[i * d + k].abs().total_cmp(&a[j * d + k].abs()))
            .unwrap_or(k);
        if a[p * d + k] == 0.0 || !a[p * d + k].is_finite() {
            return false;
        }
        if p != k {
            for j in 0..d {
                a.swap(k * d + j, p * d + j);
            }
            b.swap(k, p);
        }
        for i in k + 1..d {
            let f = a[i * d + k] / a[k * d + k];
            if f != 0.0 {
                for j in k..d {
                    a[i * d + j] -= f * a[k * d + j];
                }
                b[i] -= f * b[k];
            }
        }
    }
    for k in (0..d).rev() {
        let mut s = b[k];
        for j in k + 1..d {
            s -= a[k * d + j] * b[j];
        }
        b[k] = s / a[k * d + k];
    }
    true
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn compact_bfgs_satisfies_secant_equation() {
        // The latest pair always satisfies B s = y.
        let mut lb = Lbfgs::new(3);
        let pairs = [
            ([1.0, 0.0, 0.5], [2.0, 0.1, 1.0]),
            ([0.0, 1.0, -0.2], [0.3, 3.0, -0.5]),
            ([0.4, -0.3, 1.0], [1.0, -0.6, 4.0]),
        ];
        for (s, y) in &pairs {
            assert!(lb.update(s, y));
            let mut bs = [0.0; 3];
            lb.multiply(s, &mut bs);
            for (a, b) in bs.iter().zip(y) {
                assert!((a - b).abs() < 1e-10, "{bs:?} vs {y:?}");
            }
        }
    }

    #[test]
    fn lu_solves_pivoting_system() {
        let mut a = vec![0.0, 2.0, 1.0, 1.0];
        let mut b = vec![4.0, 3.0];
        assert!(lu_solve(&mut a, 2, &mut b));
        assert!((b[0] - 1.0).abs() < 1e-14 && (b[1] - 2.0).abs() < 1e-14);
    }
}
