//! A scalable direct-collocation problem with the block structure of the gait NLP:
//! minimum-effort swing-up of a chain of K torque-driven pendulums coupled by torsional
//! springs, transcribed with 3rd-order Radau collocation (FORMULATION 8.2) on N intervals.
//!
//! Dynamics (unit mass, length, gravity; spring stiffness κ between neighbours):
//! θᵢ' = ωᵢ, ωᵢ' = −sin θᵢ + κ Σ_{neighbours n} (θₙ − θᵢ) + uᵢ.
//! Cost: Σ_k h Σ_j B_j Σᵢ u²_{k,j,i}. Constraints per interval: 3 × 2K collocation equations,
//! 2K continuity equations, 3 × (K−1) path inequalities |θᵢ − θᵢ₊₁| <= 1.5 rad; globally:
//! θ(0) = ω(0) = 0 and θ(T) = π, ω(T) = 0. Bounds: |u| <= 10 N·m, −2π <= θ <= 3π.
//!
//! Variables per interval: mesh state (2K) then for each collocation point j = 1..3 the
//! states (2K) and controls (K): 11K; plus the final mesh state (2K).

use crate::nlp::{BlockStructure, EvalError, Nlp, Sparsity};

/// Radau collocation coefficients C[r][j−1] = ℓ_r'(τ_j) (FORMULATION 8.2).
pub const RADAU_C: [[f64; 3]; 4] = [
    [-4.139387691339811, 1.739387691339813, -3.000000000000000],
    [3.224744871391587, -3.567840084690404, 5.531972647421812],
    [1.167840084690406, 0.775255128608411, -7.531972647421811],
    [-0.253197264742181, 1.053197264742181, 5.000000000000000],
];
/// Radau quadrature weights B_j, j = 1..3 (FORMULATION 8.2).
pub const RADAU_B: [f64; 3] = [0.376403062700467, 0.512485826188421, 0.111111111111111];

/// Pendulum-chain swing-up on `intervals` Radau intervals with `links` pendulums.
#[derive(Debug, Clone)]
pub struct PendulumChain {
    /// Number of pendulums K.
    pub links: usize,
    /// Number of mesh intervals N.
    pub intervals: usize,
    /// Final time T (s).
    pub final_time: f64,
    /// Spring stiffness κ between neighbouring pendulums (N·m/rad).
    pub stiffness: f64,
}

impl PendulumChain {
    /// A chain of `links` pendulums on `intervals` intervals with T = 3 s, κ = 0.5.
    pub fn new(links: usize, intervals: usize) -> Self {
        PendulumChain {
            links: links.max(1),
            intervals: intervals.max(1),
            final_time: 3.0,
            stiffness: 0.5,
        }
    }

    /// Number of variables for a chain size, for choosing sizes: N·11K + 2K.
    pub fn variables_for(links: usize, intervals: usize) -> usize {
        intervals * 11 * links + 2 * links
    }

    fn h(&self) -> f64 {
        self.final_time / self.intervals as f64
    }
    fn vars_per_interval(&self) -> usize {
        11 * self.links
    }
    fn cons_per_interval(&self) -> usize {
        8 * self.links + 3 * (self.links - 1)
    }
    /// Index of state component `comp` (θᵢ = i, ωᵢ = K + i) at point j (0 = mesh point) of
    /// interval k; k = N, j = 0 is the final mesh state.
    pub fn state(&self, k: usize, j: usize, comp: usize) -> usize {
        let base = k * self.vars_per_interval();
        if j == 0 {
            base + comp
        } else {
            base + 2 * self.links + (j - 1) * 3 * self.links + comp
        }
    }
    /// Index of control uᵢ at collocation point j (1..3) of interval k.
    pub fn control(&self, k: usize, j: usize, i: usize) -> usize {
        self.state(k, j, 2 * self.links + i)
    }
    fn neighbours(&self, i: usize) -> impl Iterator<Item = usize> {
        let k = self.links;
        let left = if i > 0 { Some(i - 1) } else { None };
        let right = if i + 1 < k { Some(i + 1) } else { None };
        left.into_iter().chain(right)
    }
    fn row_coll(&self, k: usize, j: usize, comp: usize) -> usize {
        k * self.cons_per_interval() + (j - 1) * 2 * self.links + comp
    }
    fn row_cont(&self, k: usize, comp: usize) -> usize {
        k * self.cons_per_interval() + 6 * self.links + comp
    }
    fn row_path(&self, k: usize, j: usize, i: usize) -> usize {
        k * self.cons_per_interval() + 8 * self.links + (j - 1) * (self.links - 1) + i
    }
    fn row_global(&self, which: usize) -> usize {
        self.intervals * self.cons_per_interval() + which
    }
}

impl Nlp for PendulumChain {
    fn n(&self) -> usize {
        Self::variables_for(self.links, self.intervals)
    }
    fn m(&self) -> usize {
        self.intervals * self.cons_per_interval() + 4 * self.links
    }
    fn bounds(&self, x_l: &mut [f64], x_u: &mut [f64], g_l: &mut [f64], g_u: &mut [f64]) {
        let kk = self.links;
        let pi = std::f64::consts::PI;
        for k in 0..=self.intervals {
            let points = if k == self.intervals { 0..1 } else { 0..4 };
            for j in points {
                for i in 0..kk {
                    let t = self.state(k, j, i);
                    x_l[t] = -2.0 * pi;
                    x_u[t] = 3.0 * pi;
                    let w = self.state(k, j, kk + i);
                    x_l[w] = f64::NEG_INFINITY;
                    x_u[w] = f64::INFINITY;
                    if j > 0 {
                        let u = self.control(k, j, i);
                        x_l[u] = -10.0;
                        x_u[u] = 10.0;
                    }
                }
            }
        }
        g_l.fill(0.0);
        g_u.fill(0.0);
        for k in 0..self.intervals {
            for j in 1..=3 {
                for i in 0..kk.saturating_sub(1) {
                    let r = self.row_path(k, j, i);
                    g_l[r] = -1.5;
                    g_u[r] = 1.5;
                }
            }
        }
        for i in 0..kk {
            let r = self.row_global(2 * kk + i);
            g_l[r] = pi;
            g_u[r] = pi;
        }
    }
    fn initial_point(&self, x: &mut [f64]) {
        let kk = self.links;
        let pi = std::f64::consts::PI;
        let tau = [0.0, 0.155051025721682, 0.644948974278318, 1.0];
        for k in 0..=self.intervals {
            let points = if k == self.intervals { 0..1 } else { 0..4 };
            for j in points {
                let s = (k as f64 + tau[j]) / self.intervals as f64;
                for i in 0..kk {
                    x[self.state(k, j, i)] = pi * s;
                    x[self.state(k, j, kk + i)] = pi / self.final_time;
                    if j > 0 {
                        x[self.control(k, j, i)] = 0.0;
                    }
                }
            }
        }
    }
    fn objective(&self, x: &[f64]) -> Result<f64, EvalError> {
        let h = self.h();
        let mut f = 0.0;
        for k in 0..self.intervals {
            for j in 1..=3 {
                for i in 0..self.links {
                    let u = x[self.control(k, j, i)];
                    f += h * RADAU_B[j - 1] * u * u;
                }
            }
        }
        Ok(f)
    }
    fn gradient(&self, x: &[f64], g: &mut [f64]) -> Result<(), EvalError> {
        g.fill(0.0);
        let h = self.h();
        for k in 0..self.intervals {
            for j in 1..=3 {
                for i in 0..self.links {
                    let u = self.control(k, j, i);
                    g[u] = 2.0 * h * RADAU_B[j - 1] * x[u];
                }
            }
        }
        Ok(())
    }
    fn constraints(&self, x: &[f64], c: &mut [f64]) -> Result<(), EvalError> {
        let (kk, h, kap) = (self.links, self.h(), self.stiffness);
        for k in 0..self.intervals {
            for j in 1..=3 {
                for comp in 0..2 * kk {
                    let mut s = 0.0;
                    for (r, cr) in RADAU_C.iter().enumerate() {
                        s += cr[j - 1] * x[self.point_state(k, r, comp)];
                    }
                    let f = if comp < kk {
                        x[self.state(k, j, kk + comp)]
                    } else {
                        let i = comp - kk;
                        let th = x[self.state(k, j, i)];
                        let mut acc = -th.sin() + x[self.control(k, j, i)];
                        for nb in self.neighbours(i) {
                            acc += kap * (x[self.state(k, j, nb)] - th);
                        }
                        acc
                    };
                    c[self.row_coll(k, j, comp)] = h * f - s;
                }
                for i in 0..kk.saturating_sub(1) {
                    c[self.row_path(k, j, i)] = x[self.state(k, j, i)] - x[self.state(k, j, i + 1)];
                }
            }
            for comp in 0..2 * kk {
                c[self.row_cont(k, comp)] =
                    x[self.state(k + 1, 0, comp)] - x[self.state(k, 3, comp)];
            }
        }
        for comp in 0..2 * kk {
            c[self.row_global(comp)] = x[self.state(0, 0, comp)];
            c[self.row_global(2 * kk + comp)] = x[self.state(self.intervals, 0, comp)];
        }
        Ok(())
    }
    fn jacobian_structure(&self) -> Sparsity {
        let mut s = Sparsity::default();
        self.jacobian_walk(None, &mut |r, c, _| {
            s.push(r, c);
        });
        s
    }
    fn jacobian_values(&self, x: &[f64], vals: &mut [f64]) -> Result<(), EvalError> {
        let mut p = 0;
        self.jacobian_walk(Some(x), &mut |_, _, v| {
            vals[p] = v;
            p += 1;
        });
        Ok(())
    }
    fn hessian_structure(&self) -> Sparsity {
        let mut s = Sparsity::default();
        for k in 0..self.intervals {
            for j in 1..=3 {
                for i in 0..self.links {
                    let t = self.state(k, j, i);
                    s.push(t, t);
                    let u = self.control(k, j, i);
                    s.push(u, u);
                }
            }
        }
        s
    }
    fn hessian_values(
        &self,
        x: &[f64],
        of: f64,
        lambda: &[f64],
        vals: &mut [f64],
    ) -> Result<(), EvalError> {
        let (kk, h) = (self.links, self.h());
        let mut p = 0;
        for k in 0..self.intervals {
            for j in 1..=3 {
                for i in 0..kk {
                    let th = x[self.state(k, j, i)];
                    // ∂²(h(−sin θ))/∂θ² = h sin θ, on the ω-collocation row.
                    vals[p] = lambda[self.row_coll(k, j, kk + i)] * h * th.sin();
                    vals[p + 1] = of * 2.0 * h * RADAU_B[j - 1];
                    p += 2;
                }
            }
        }
        Ok(())
    }
    fn blocks(&self) -> Option<BlockStructure> {
        let nv = self.vars_per_interval();
        Some(BlockStructure {
            blocks: (0..self.intervals)
                .map(|k| (k * nv..(k + 1) * nv).collect())
                .collect(),
            global_variables: (0..2 * self.links)
                .map(|c| self.state(self.intervals, 0, c))
                .collect(),
        })
    }
}

impl PendulumChain {
    /// State component `comp` at point r (0..3) of interval k.
    fn point_state(&self, k: usize, r: usize, comp: usize) -> usize {
        self.state(k, r, comp)
    }

    /// Visits every Jacobian nonzero (row, col, value) in a fixed order; values are only
    /// meaningful when `x` is given.
    fn jacobian_walk(&self, x: Option<&[f64]>, emit: &mut dyn FnMut(usize, usize, f64)) {
        let (kk, h, kap) = (self.links, self.h(), self.stiffness);
        for k in 0..self.intervals {
            for j in 1..=3 {
                for comp in 0..2 * kk {
                    let row = self.row_coll(k, j, comp);
                    // −Σ_r C_rj x_r
                    for (r, cr) in RADAU_C.iter().enumerate() {
                        emit(row, self.point_state(k, r, comp), -cr[j - 1]);
                    }
                    if comp < kk {
                        // h ωᵢ (ω is a different component: no duplicate)
                        emit(row, self.state(k, j, kk + comp), h);
                    } else {
                        let i = comp - kk;
                        let nn = self.neighbours(i).count() as f64;
                        let th = x.map_or(0.0, |x| x[self.state(k, j, i)]);
                        emit(row, self.state(k, j, i), h * (-th.cos() - kap * nn));
                        for nb in self.neighbours(i) {
                            emit(row, self.state(k, j, nb), h * kap);
                        }
                        emit(row, self.control(k, j, i), h);
                    }
                }
                for i in 0..kk.saturating_sub(1) {
                    let row = self.row_path(k, j, i);
                    emit(row, self.state(k, j, i), 1.0);
                    emit(row, self.state(k, j, i + 1), -1.0);
                }
            }
            for comp in 0..2 * kk {
                let row = self.row_cont(k, comp);
                emit(row, self.state(k + 1, 0, comp), 1.0);
                emit(row, self.state(k, 3, comp), -1.0);
            }
        }
        for comp in 0..2 * kk {
            emit(self.row_global(comp), self.state(0, 0, comp), 1.0);
            emit(
                self.row_global(2 * kk + comp),
                self.state(self.intervals, 0, comp),
                1.0,
            );
        }
    }
}
