//! Classic small NLPs with published optima (Hock & Schittkowski 1981 numbering) and one
//! infeasible problem, with hand-coded exact derivatives.

use crate::nlp::{EvalError, Nlp, Sparsity};

const INF: f64 = f64::INFINITY;

/// HS071: min x₁x₄(x₁+x₂+x₃) + x₃ s.t. x₁x₂x₃x₄ >= 25, Σxᵢ² = 40, 1 <= x <= 5;
/// optimum f* = 17.0140173 at (1, 4.7429994, 3.8211503, 1.3794082).
#[derive(Debug, Clone, Default)]
pub struct Hs071;

impl Hs071 {
    /// Published optimal objective value.
    pub const F_OPT: f64 = 17.014017145179164;
    /// Published optimal point.
    pub const X_OPT: [f64; 4] = [1.0, 4.742999643, 3.821149978, 1.379408293];
}

impl Nlp for Hs071 {
    fn n(&self) -> usize {
        4
    }
    fn m(&self) -> usize {
        2
    }
    fn bounds(&self, x_l: &mut [f64], x_u: &mut [f64], g_l: &mut [f64], g_u: &mut [f64]) {
        x_l.fill(1.0);
        x_u.fill(5.0);
        g_l.copy_from_slice(&[25.0, 40.0]);
        g_u.copy_from_slice(&[INF, 40.0]);
    }
    fn initial_point(&self, x: &mut [f64]) {
        x.copy_from_slice(&[1.0, 5.0, 5.0, 1.0]);
    }
    fn objective(&self, x: &[f64]) -> Result<f64, EvalError> {
        Ok(x[0] * x[3] * (x[0] + x[1] + x[2]) + x[2])
    }
    fn gradient(&self, x: &[f64], g: &mut [f64]) -> Result<(), EvalError> {
        g[0] = x[3] * (2.0 * x[0] + x[1] + x[2]);
        g[1] = x[0] * x[3];
        g[2] = x[0] * x[3] + 1.0;
        g[3] = x[0] * (x[0] + x[1] + x[2]);
        Ok(())
    }
    fn constraints(&self, x: &[f64], c: &mut [f64]) -> Result<(), EvalError> {
        c[0] = x[0] * x[1] * x[2] * x[3];
        c[1] = x.iter().map(|v| v * v).sum();
        Ok(())
    }
    fn jacobian_structure(&self) -> Sparsity {
        Sparsity::new(vec![0, 0, 0, 0, 1, 1, 1, 1], vec![0, 1, 2, 3, 0, 1, 2, 3])
    }
    fn jacobian_values(&self, x: &[f64], v: &mut [f64]) -> Result<(), EvalError> {
        v[0] = x[1] * x[2] * x[3];
        v[1] = x[0] * x[2] * x[3];
        v[2] = x[0] * x[1] * x[3];
        v[3] = x[0] * x[1] * x[2];
        for i in 0..4 {
            v[4 + i] = 2.0 * x[i];
        }
        Ok(())
    }
    fn hessian_structure(&self) -> Sparsity {
        let mut s = Sparsity::default();
        for r in 0..4 {
            for c in 0..=r {
                s.push(r, c);
            }
        }
        s
    }
    fn hessian_values(
        &self,
        x: &[f64],
        of: f64,
        l: &[f64],
        v: &mut [f64],
    ) -> Result<(), EvalError> {
        // order: (0,0) (1,0) (1,1) (2,0) (2,1) (2,2) (3,0) (3,1) (3,2) (3,3)
        v[0] = of * 2.0 * x[3] + l[1] * 2.0;
        v[1] = of * x[3] + l[0] * x[2] * x[3];
        v[2] = l[1] * 2.0;
        v[3] = of * x[3] + l[0] * x[1] * x[3];
        v[4] = l[0] * x[0] * x[3];
        v[5] = l[1] * 2.0;
        v[6] = of * (2.0 * x[0] + x[1] + x[2]) + l[0] * x[1] * x[2];
        v[7] = of * x[0] + l[0] * x[0] * x[2];
        v[8] = of * x[0] + l[0] * x[0] * x[1];
        v[9] = l[1] * 2.0;
        Ok(())
    }
}

/// Rosenbrock's function on the unit disk: min (1−x)² + 100(y−x²)² s.t. x² + y² <= 1;
/// optimum f* ≈ 0.0456748 at (0.786415, 0.617698) (the constraint is active).
#[derive(Debug, Clone, Default)]
pub struct RosenbrockDisk;

impl RosenbrockDisk {
    /// Optimal objective value (from the KKT conditions on the unit circle).
    pub const F_OPT: f64 = 0.045674808;
    /// Optimal point.
    pub const X_OPT: [f64; 2] = [0.7864151, 0.6176983];
}

impl Nlp for RosenbrockDisk {
    fn n(&self) -> usize {
        2
    }
    fn m(&self) -> usize {
        1
    }
    fn bounds(&self, x_l: &mut [f64], x_u: &mut [f64], g_l: &mut [f64], g_u: &mut [f64]) {
        x_l.fill(-INF);
        x_u.fill(INF);
        g_l[0] = -INF;
        g_u[0] = 1.0;
    }
    fn initial_point(&self, x: &mut [f64]) {
        x.copy_from_slice(&[-1.2, 1.0]);
    }
    fn objective(&self, x: &[f64]) -> Result<f64, EvalError> {
        Ok((1.0 - x[0]).powi(2) + 100.0 * (x[1] - x[0] * x[0]).powi(2))
    }
    fn gradient(&self, x: &[f64], g: &mut [f64]) -> Result<(), EvalError> {
        let t = x[1] - x[0] * x[0];
        g[0] = -2.0 * (1.0 - x[0]) - 400.0 * x[0] * t;
        g[1] = 200.0 * t;
        Ok(())
    }
    fn constraints(&self, x: &[f64], c: &mut [f64]) -> Result<(), EvalError> {
        c[0] = x[0] * x[0] + x[1] * x[1];
        Ok(())
    }
    fn jacobian_structure(&self) -> Sparsity {
        Sparsity::new(vec![0, 0], vec![0, 1])
    }
    fn jacobian_values(&self, x: &[f64], v: &mut [f64]) -> Result<(), EvalError> {
        v[0] = 2.0 * x[0];
        v[1] = 2.0 * x[1];
        Ok(())
    }
    fn hessian_structure(&self) -> Sparsity {
        Sparsity::new(vec![0, 1, 1], vec![0, 0, 1])
    }
    fn hessian_values(
        &self,
        x: &[f64],
        of: f64,
        l: &[f64],
        v: &mut [f64],
    ) -> Result<(), EvalError> {
        v[0] = of * (2.0 - 400.0 * x[1] + 1200.0 * x[0] * x[0]) + 2.0 * l[0];
        v[1] = of * (-400.0 * x[0]);
        v[2] = of * 200.0 + 2.0 * l[0];
        Ok(())
    }
}

/// HS035 (Beale): min 9 − 8x₁ − 6x₂ − 4x₃ + 2x₁² + 2x₂² + x₃² + 2x₁x₂ + 2x₁x₃
/// s.t. x₁ + x₂ + 2x₃ <= 3, x >= 0; optimum f* = 1/9 at (4/3, 7/9, 4/9).
#[derive(Debug, Clone, Default)]
pub struct Hs035;

impl Hs035 {
    /// Published optimal objective value.
    pub const F_OPT: f64 = 1.0 / 9.0;
    /// Published optimal point.
    pub const X_OPT: [f64; 3] = [4.0 / 3.0, 7.0 / 9.0, 4.0 / 9.0];
}

impl Nlp for Hs035 {
    fn n(&self) -> usize {
        3
    }
    fn m(&self) -> usize {
        1
    }
    fn bounds(&self, x_l: &mut [f64], x_u: &mut [f64], g_l: &mut [f64], g_u: &mut [f64]) {
        x_l.fill(0.0);
        x_u.fill(INF);
        g_l[0] = -INF;
        g_u[0] = 3.0;
    }
    fn initial_point(&self, x: &mut [f64]) {
        x.fill(0.5);
    }
    fn objective(&self, x: &[f64]) -> Result<f64, EvalError> {
        Ok(9.0 - 8.0 * x[0] - 6.0 * x[1] - 4.0 * x[2]
            + 2.0 * x[0] * x[0]
            + 2.0 * x[1] * x[1]
            + x[2] * x[2]
            + 2.0 * x[0] * x[1]
            + 2.0 * x[0] * x[2])
    }
    fn gradient(&self, x: &[f64], g: &mut [f64]) -> Result<(), EvalError> {
        g[0] = -8.0 + 4.0 * x[0] + 2.0 * x[1] + 2.0 * x[2];
        g[1] = -6.0 + 4.0 * x[1] + 2.0 * x[0];
        g[2] = -4.0 + 2.0 * x[2] + 2.0 * x[0];
        Ok(())
    }
    fn constraints(&self, x: &[f64], c: &mut [f64]) -> Result<(), EvalError> {
        c[0] = x[0] + x[1] + 2.0 * x[2];
        Ok(())
    }
    fn jacobian_structure(&self) -> Sparsity {
        Sparsity::new(vec![0, 0, 0], vec![0, 1, 2])
    }
    fn jacobian_values(&self, _x: &[f64], v: &mut [f64]) -> Result<(), EvalError> {
        v.copy_from_slice(&[1.0, 1.0, 2.0]);
        Ok(())
    }
    fn hessian_structure(&self) -> Sparsity {
        Sparsity::new(vec![0, 1, 1, 2, 2], vec![0, 0, 1, 0, 2])
    }
    fn hessian_values(
        &self,
        _x: &[f64],
        of: f64,
        _l: &[f64],
        v: &mut [f64],
    ) -> Result<(), EvalError> {
        v.copy_from_slice(&[4.0 * of, 2.0 * of, 4.0 * of, 2.0 * of, 2.0 * of]);
        Ok(())
    }
}

/// HS021: min 0.01x₁² + x₂² − 100 s.t. 10x₁ − x₂ >= 10, 2 <= x₁ <= 50, −50 <= x₂ <= 50;
/// optimum f* = −99.96 at (2, 0) (a bound is active).
#[derive(Debug, Clone, Default)]
pub struct Hs021;

impl Hs021 {
    /// Published optimal objective value.
    pub const F_OPT: f64 = -99.96;
    /// Published optimal point.
    pub const X_OPT: [f64; 2] = [2.0, 0.0];
}

impl Nlp for Hs021 {
    fn n(&self) -> usize {
        2
    }
    fn m(&self) -> usize {
        1
    }
    fn bounds(&self, x_l: &mut [f64], x_u: &mut [f64], g_l: &mut [f64], g_u: &mut [f64]) {
        x_l.copy_from_slice(&[2.0, -50.0]);
        x_u.copy_from_slice(&[50.0, 50.0]);
        g_l[0] = 10.0;
        g_u[0] = INF;
    }
    fn initial_point(&self, x: &mut [f64]) {
        x.copy_from_slice(&[-1.0, -1.0]);
    }
    fn objective(&self, x: &[f64]) -> Result<f64, EvalError> {
        Ok(0.01 * x[0] * x[0] + x[1] * x[1] - 100.0)
    }
    fn gradient(&self, x: &[f64], g: &mut [f64]) -> Result<(), EvalError> {
        g[0] = 0.02 * x[0];
        g[1] = 2.0 * x[1];
        Ok(())
    }
    fn constraints(&self, x: &[f64], c: &mut [f64]) -> Result<(), EvalError> {
        c[0] = 10.0 * x[0] - x[1];
        Ok(())
    }
    fn jacobian_structure(&self) -> Sparsity {
        Sparsity::new(vec![0, 0], vec![0, 1])
    }
    fn jacobian_values(&self, _x: &[f64], v: &mut [f64]) -> Result<(), EvalError> {
        v.copy_from_slice(&[10.0, -1.0]);
        Ok(())
    }
    fn hessian_structure(&self) -> Sparsity {
        Sparsity::new(vec![0, 1], vec![0, 1])
    }
    fn hessian_values(
        &self,
        _x: &[f64],
        of: f64,
        _l: &[f64],
        v: &mut [f64],
    ) -> Result<(), EvalError> {
        v.copy_from_slice(&[0.02 * of, 2.0 * of]);
        Ok(())
    }
}

/// HS006: min (1 − x₁)² s.t. 10(x₂ − x₁²) = 0; optimum f* = 0 at (1, 1).
#[derive(Debug, Clone, Default)]
pub struct Hs006;

impl Hs006 {
    /// Published optimal objective value.
    pub const F_OPT: f64 = 0.0;
    /// Published optimal point.
    pub const X_OPT: [f64; 2] = [1.0, 1.0];
}

impl Nlp for Hs006 {
    fn n(&self) -> usize {
        2
    }
    fn m(&self) -> usize {
        1
    }
    fn bounds(&self, x_l: &mut [f64], x_u: &mut [f64], g_l: &mut [f64], g_u: &mut [f64]) {
        x_l.fill(-INF);
        x_u.fill(INF);
        g_l[0] = 0.0;
        g_u[0] = 0.0;
    }
    fn initial_point(&self, x: &mut [f64]) {
        x.copy_from_slice(&[-1.2, 1.0]);
    }
    fn objective(&self, x: &[f64]) -> Result<f64, EvalError> {
        Ok((1.0 - x[0]).powi(2))
    }
    fn gradient(&self, x: &[f64], g: &mut [f64]) -> Result<(), EvalError> {
        g[0] = -2.0 * (1.0 - x[0]);
        g[1] = 0.0;
        Ok(())
    }
    fn constraints(&self, x: &[f64], c: &mut [f64]) -> Result<(), EvalError> {
        c[0] = 10.0 * (x[1] - x[0] * x[0]);
        Ok(())
    }
    fn jacobian_structure(&self) -> Sparsity {
        Sparsity::new(vec![0, 0], vec![0, 1])
    }
    fn jacobian_values(&self, x: &[f64], v: &mut [f64]) -> Result<(), EvalError> {
        v[0] = -20.0 * x[0];
        v[1] = 10.0;
        Ok(())
    }
    fn hessian_structure(&self) -> Sparsity {
        Sparsity::new(vec![0], vec![0])
    }
    fn hessian_values(
        &self,
        _x: &[f64],
        of: f64,
        l: &[f64],
        v: &mut [f64],
    ) -> Result<(), EvalError> {
        v[0] = 2.0 * of - 20.0 * l[0];
        Ok(())
    }
}

/// An infeasible problem: min x + y s.t. x² + y² <= 1 and x + y >= 3 (the disk and the
/// half-plane do not intersect; least violation at x = y = 1/√2).
#[derive(Debug, Clone, Default)]
pub struct InfeasibleDisk;

impl Nlp for InfeasibleDisk {
    fn n(&self) -> usize {
        2
    }
    fn m(&self) -> usize {
        2
    }
    fn bounds(&self, x_l: &mut [f64], x_u: &mut [f64], g_l: &mut [f64], g_u: &mut [f64]) {
        x_l.fill(-INF);
        x_u.fill(INF);
        g_l.copy_from_slice(&[-INF, 3.0]);
        g_u.copy_from_slice(&[1.0, INF]);
    }
    fn initial_point(&self, x: &mut [f64]) {
        x.copy_from_slice(&[0.5, 0.0]);
    }
    fn objective(&self, x: &[f64]) -> Result<f64, EvalError> {
        Ok(x[0] + x[1])
    }
    fn gradient(&self, _x: &[f64], g: &mut [f64]) -> Result<(), EvalError> {
        g.fill(1.0);
        Ok(())
    }
    fn constraints(&self, x: &[f64], c: &mut [f64]) -> Result<(), EvalError> {
        c[0] = x[0] * x[0] + x[1] * x[1];
        c[1] = x[0] + x[1];
        Ok(())
    }
    fn jacobian_structure(&self) -> Sparsity {
        Sparsity::new(vec![0, 0, 1, 1], vec![0, 1, 0, 1])
    }
    fn jacobian_values(&self, x: &[f64], v: &mut [f64]) -> Result<(), EvalError> {
        v.copy_from_slice(&[2.0 * x[0], 2.0 * x[1], 1.0, 1.0]);
        Ok(())
    }
    fn hessian_structure(&self) -> Sparsity {
        Sparsity::new(vec![0, 1], vec![0, 1])
    }
    fn hessian_values(
        &self,
        _x: &[f64],
        _of: f64,
        l: &[f64],
        v: &mut [f64],
    ) -> Result<(), EvalError> {
        v.copy_from_slice(&[2.0 * l[0], 2.0 * l[0]]);
        Ok(())
    }
}

/// Wächter & Biegler (2000) counterexample: min x₁ s.t. x₁² − x₂ − 1 = 0, x₁ − x₃ − 0.5 = 0,
/// x₂, x₃ ≥ 0, from x₀ = (−2, 3, 1): the linearised constraints and the bounds become
/// inconsistent on the way, so a line-search IPM needs a feasibility restoration. The
/// optimum is x* = (1, 0, 0.5), f* = 1.
pub struct WaechterBiegler;

impl Nlp for WaechterBiegler {
    fn n(&self) -> usize {
        3
    }
    fn m(&self) -> usize {
        2
    }
    fn bounds(&self, x_l: &mut [f64], x_u: &mut [f64], g_l: &mut [f64], g_u: &mut [f64]) {
        x_l.copy_from_slice(&[-INF, 0.0, 0.0]);
        x_u.fill(INF);
        g_l.fill(0.0);
        g_u.fill(0.0);
    }
    fn initial_point(&self, x: &mut [f64]) {
        x.copy_from_slice(&[-2.0, 3.0, 1.0]);
    }
    fn objective(&self, x: &[f64]) -> Result<f64, EvalError> {
        Ok(x[0])
    }
    fn gradient(&self, _x: &[f64], g: &mut [f64]) -> Result<(), EvalError> {
        g.copy_from_slice(&[1.0, 0.0, 0.0]);
        Ok(())
    }
    fn constraints(&self, x: &[f64], c: &mut [f64]) -> Result<(), EvalError> {
        c[0] = x[0] * x[0] - x[1] - 1.0;
        c[1] = x[0] - x[2] - 0.5;
        Ok(())
    }
    fn jacobian_structure(&self) -> Sparsity {
        Sparsity::new(vec![0, 0, 1, 1], vec![0, 1, 0, 2])
    }
    fn jacobian_values(&self, x: &[f64], v: &mut [f64]) -> Result<(), EvalError> {
        v.copy_from_slice(&[2.0 * x[0], -1.0, 1.0, -1.0]);
        Ok(())
    }
    fn hessian_structure(&self) -> Sparsity {
        Sparsity::new(vec![0], vec![0])
    }
    fn hessian_values(
        &self,
        _x: &[f64],
        _of: f64,
        l: &[f64],
        v: &mut [f64],
    ) -> Result<(), EvalError> {
        v[0] = 2.0 * l[0];
        Ok(())
    }
}
