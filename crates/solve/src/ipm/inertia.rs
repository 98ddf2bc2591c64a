//! The KKT matrix of the interior point, its factorisation and the inertia correction.
//!
//! The condensed matrix K = [[W + Σ + δ_w I, Jᵀ], [J, −D_c]] must have n positive and m
//! negative eigenvalues for the step to be a descent direction of the barrier problem
//! (Wächter & Biegler 2006, section 3.1). When the factorisation reports another inertia,
//! δ_w grows: the first nonzero trial is δ̄_w⁰ = [`REG_FIRST`] in a solve's first
//! regularised iteration and δ_w_last·κ_w⁻ later, then ×κ̄_w⁺ = [`REG_INCREASE_FIRST`]
//! before any iteration was regularised and ×κ_w⁺ = [`REG_INCREASE`] after (IPOPT's rule,
//! Algorithm IC). The constraint block always carries δ_c = [`DELTA_C`] (removed again by
//! iterative refinement, [`super::refine`]).
// Index loops over several parallel arrays are clearer than zipped iterators here.
#![allow(clippy::needless_range_loop)]

use std::time::{Duration, Instant};

use crate::ipm::iterate::{Iterate, NO_SLACK};
use crate::ipm::kkt::KktPattern;
use crate::ipm::linsys::{Counted, KktSolver};
use crate::ipm::ordering::kkt_ordering;
use crate::ipm::refine::RefineScratch;
use crate::ipm::scaled::ScaledNlp;
use crate::nlp::{BlockStructure, Sparsity};
use crate::observer::{Diagnostic, Emitter};
use crate::pivots::Inertia;
use crate::solver::SolveError;

/// KKT diagonal of a fixed variable (x_l = x_u), which keeps its step at zero.
pub(super) const FIXED_DIAG: f64 = 1e20;
/// Constant regularisation of the constraint block (quasi-definiteness).
pub(super) const DELTA_C: f64 = 1e-9;
/// First nonzero Hessian regularisation δ_w of a solve (IPOPT's δ̄_w⁰).
const REG_FIRST: f64 = 1e-4;
/// Divisor of the last δ_w for the first nonzero trial of a later iteration (κ_w⁻ = 1/3).
const REG_DECREASE: f64 = 3.0;
/// Factor of δ_w after a failed trial before any iteration was regularised (κ̄_w⁺).
const REG_INCREASE_FIRST: f64 = 100.0;
/// Factor of δ_w after a failed trial once an iteration was regularised (κ_w⁺).
const REG_INCREASE: f64 = 8.0;
/// Largest δ_w tried before the matrix counts as impossible to regularise.
const REG_MAX: f64 = 1e40;
/// Factorisations of one inertia correction at most.
const MAX_INERTIA_TRIALS: usize = 60;
/// After a regularised iteration a later one may start from δ_w_last/`REG_DECREASE` instead
/// of 0 (see [`KktSystem::first_delta_w`]) while that is at least this large.
const REG_SKIP_ZERO_MIN: f64 = 1e-8;

/// The check of a factor with the wrong inertia (its Newton step usable or not, see
/// `direction::usable_step`); a kept factor leaves that step, unrefined, in `rhs`.
pub(super) type StepCheck<'c, 'l> =
    &'c mut dyn FnMut(&mut KktSystem<'l>, &Iterate) -> Result<bool, SolveError>;

/// Which variables are fixed or appear nonlinearly, and the Jacobian's triplet indices.
pub(super) struct KktStructure {
    /// Variables with x_l = x_u, kept at their value.
    pub fixed_x: Vec<bool>,
    /// Variables with a nonzero Hessian row or column (the L-BFGS space).
    pub nonlinear: Vec<bool>,
    /// Jacobian row of each stored entry.
    pub jac_rows: Vec<usize>,
    /// Jacobian column of each stored entry.
    pub jac_cols: Vec<usize>,
}

/// The KKT matrix, its factorisation and the linear-algebra accounting of a solve.
pub(super) struct KktSystem<'l> {
    /// The factorisation, counting its solves.
    pub linear: Counted<'l>,
    /// Fixed and nonlinear variables, Jacobian indices.
    pub structure: KktStructure,
    /// Pattern of the lower triangle.
    pub pattern: KktPattern,
    /// Values of the lower triangle.
    pub vals: Vec<f64>,
    /// Diagonal of the (1,1) block.
    pub diag_x: Vec<f64>,
    /// Diagonal D_c of the constraint block.
    pub d_c: Vec<f64>,
    /// Σ over w.
    pub sigma: Vec<f64>,
    /// δ_c on each constraint row (what refinement removes).
    pub d_c_reg: Vec<f64>,
    /// Zero Hessian values (limited-memory mode, restoration, multiplier initialisation).
    pub zero_h: Vec<f64>,
    /// Right-hand side and solution of single solves.
    pub rhs: Vec<f64>,
    /// Copy of the right-hand side for refinement.
    pub b_save: Vec<f64>,
    /// Scratch of iterative refinement.
    pub refine: RefineScratch,
    /// Chain structure for the ordering.
    blocks: Option<BlockStructure>,
    /// δ_w of the last regularised iteration (0 before any).
    pub delta_w_last: f64,
    /// Whether the previous iteration needed δ_w > 0.
    pub regularised_last: bool,
    /// Time in the KKT linear solver (symbolic, numeric, solves).
    pub time: Duration,
    /// Time in the symbolic analyses.
    pub time_symbolic: Duration,
    /// Time in the numeric factorisations of the main iterations.
    pub factor_time: Duration,
    /// Numeric factorisations (restoration and initialisation included).
    pub factorizations: usize,
    /// Whether the factor was kept by the step check, whose Newton step `rhs` then still
    /// holds (unrefined), so that the step need not be solved again.
    pub step_solved: bool,
}

impl<'l> KktSystem<'l> {
    /// The KKT system of `prob` with its symbolic analysis. Without the exact Hessian the
    /// Hessian entries stay zero; without a chain ordering they are kept in the pattern
    /// anyway (minimum degree orders the gait KKT better with them), while the chain
    /// dissection does best without them (decision 0002).
    pub fn new(
        linear: Counted<'l>,
        structure: KktStructure,
        prob: &ScaledNlp,
        blocks: Option<BlockStructure>,
        exact: bool,
    ) -> Result<Self, SolveError> {
        let (n, m) = (prob.nlp.n(), prob.nlp.m());
        let t = Instant::now();
        let pattern = if !exact && blocks.is_some() {
            KktPattern::new(n, m, &prob.jac, &Sparsity::default())
        } else {
            KktPattern::new(n, m, &prob.jac, &prob.hess)
        };
        // the buffers are allocated after the symbolic analysis, whose own peak memory is
        // then not added to theirs
        let mut kkt = KktSystem {
            linear,
            structure,
            vals: Vec::new(),
            diag_x: Vec::new(),
            d_c: Vec::new(),
            sigma: Vec::new(),
            d_c_reg: Vec::new(),
            zero_h: Vec::new(),
            rhs: Vec::new(),
            b_save: Vec::new(),
            refine: RefineScratch::default(),
            pattern,
            blocks,
            delta_w_last: 0.0,
            regularised_last: false,
            time: Duration::ZERO,
            time_symbolic: Duration::ZERO,
            factor_time: Duration::ZERO,
            factorizations: 0,
            step_solved: false,
        };
        kkt.analyse(&prob.hess)?;
        kkt.time_symbolic = t.elapsed();
        kkt.time += kkt.time_symbolic;
        let dim = kkt.pattern.dim;
        kkt.vals = vec![0.0; kkt.pattern.nnz()];
        kkt.diag_x = vec![0.0; n];
        kkt.d_c = vec![0.0; m];
        kkt.d_c_reg = vec![DELTA_C; m];
        kkt.zero_h = vec![0.0; prob.hess.nnz()];
        kkt.rhs = vec![0.0; dim];
        kkt.b_save = vec![0.0; dim];
        Ok(kkt)
    }

    /// Symbolic analysis of the pattern (Lagrangian Hessian pattern `hess`), ordered by
    /// chain dissection along the blocks when given.
    fn analyse(&mut self, hess: &Sparsity) -> Result<(), SolveError> {
        let p = &self.pattern;
        let ordering = kkt_ordering(self.blocks.as_ref(), hess, p);
        self.linear
            .analyse(p.dim, &p.col_ptr, &p.row_idx, ordering.as_deref())
            .map_err(|e| SolveError::Backend(e.to_string()))
    }

    /// Moves to the exact Hessian: the pattern gets the Hessian's entries and a new
    /// symbolic analysis.
    pub fn switch_to_exact(&mut self, prob: &ScaledNlp) -> Result<(), SolveError> {
        let t = Instant::now();
        self.pattern = KktPattern::new(prob.nlp.n(), prob.nlp.m(), &prob.jac, &prob.hess);
        self.analyse(&prob.hess)?;
        self.vals = vec![0.0; self.pattern.nnz()];
        self.time += t.elapsed();
        Ok(())
    }

    /// Σ = z_L/(w − L) + z_U/(U − w) at `st`, and the constraint diagonal D_c: δ_c on
    /// equality rows, 1/σ_s + δ_c on slack rows.
    pub fn set_barrier_terms(&mut self, st: &Iterate) {
        self.sigma.resize(st.big_n, 0.0);
        for j in 0..st.big_n {
            let mut s = 0.0;
            if st.has_l[j] {
                s += st.zl[j] / (st.w[j] - st.wl[j]);
            }
            if st.has_u[j] {
                s += st.zu[j] / (st.wu[j] - st.w[j]);
            }
            self.sigma[j] = s;
        }
        for i in 0..st.m {
            let k = st.slack_of_row[i];
            self.d_c[i] = if k == NO_SLACK {
                DELTA_C
            } else {
                1.0 / self.sigma[st.n + k].max(1e-20) + DELTA_C
            };
        }
    }

    /// First δ_w trial of an iteration: 0, as IPOPT, or δ_w_last/3 directly after a
    /// regularised iteration when `skip_zero` says the trial with 0 is likely to fail again
    /// (and δ_w_last/3 is at least 1e-8).
    pub fn first_delta_w(&self, skip_zero: bool) -> f64 {
        let reduced = self.delta_w_last / REG_DECREASE;
        if skip_zero && self.regularised_last && reduced >= REG_SKIP_ZERO_MIN {
            reduced
        } else {
            0.0f64
        }
    }

    /// The next δ_w after a trial with `delta_w` failed (IPOPT's rule).
    fn next_delta_w(&self, delta_w: f64) -> f64 {
        if delta_w == 0.0 {
            if self.delta_w_last == 0.0 {
                REG_FIRST
            } else {
                (self.delta_w_last / REG_DECREASE).max(1e-20)
            }
        } else if self.delta_w_last == 0.0 {
            delta_w * REG_INCREASE_FIRST
        } else {
            delta_w * REG_INCREASE
        }
    }

    /// Assembles and factorises K with Hessian values `hv` (L-BFGS initial scaling `b0` on
    /// the nonlinear variables), increasing δ_w from `delta_w` until the inertia is (n, m,
    /// 0), or, with `check`, until that inertia or a factor whose Newton step the check
    /// accepts. Returns the δ_w used, or None when no δ_w ≤ 1e40 gives either.
    pub fn factor_with_inertia_correction(
        &mut self,
        st: &Iterate,
        b0: f64,
        mut delta_w: f64,
        mut check: Option<StepCheck<'_, 'l>>,
        emitter: &mut Emitter,
    ) -> Result<Option<f64>, SolveError> {
        let (n, m) = (st.n, st.m);
        let want = Inertia {
            positive: n,
            negative: m,
            zero: 0,
        };
        let t_lin = Instant::now();
        let mut ok = false;
        self.step_solved = false;
        for _ in 0..MAX_INERTIA_TRIALS {
            let inertia = self.factor_regularised(st, b0, delta_w)?;
            let tested = match check.as_mut() {
                Some(check) if inertia != want && inertia.zero == 0 => Some(check(self, st)?),
                _ => None,
            };
            if emitter.wants(3) {
                emitter.emit(Diagnostic::InertiaTrial {
                    delta_w,
                    inertia,
                    positive: n,
                    negative: m,
                    step_check: tested,
                });
            }
            if inertia == want || tested == Some(true) {
                self.step_solved = tested == Some(true);
                ok = true;
                break;
            }
            delta_w = self.next_delta_w(delta_w);
            if delta_w > REG_MAX {
                break;
            }
        }
        self.time += t_lin.elapsed();
        if !ok {
            return Ok(None);
        }
        if delta_w > 0.0 {
            self.delta_w_last = delta_w;
        }
        self.regularised_last = delta_w > 0.0;
        Ok(Some(delta_w))
    }

    /// The curvature dxᵀ(W + Σ + δ_w I)dx of the primal step `dx` from the assembled (1,1)
    /// block, and ‖dx‖², both over the variables that are not fixed.
    pub fn curvature(&self, dx: &[f64]) -> (f64, f64) {
        let (p, fixed) = (&self.pattern, &self.structure.fixed_x);
        let (mut curv, mut norm2) = (0.0, 0.0);
        for j in (0..dx.len()).filter(|&j| !fixed[j]) {
            norm2 += dx[j] * dx[j];
            for k in p.col_ptr[j]..p.col_ptr[j + 1] {
                let i = p.row_idx[k];
                if i < dx.len() && !fixed[i] {
                    let v = self.vals[k] * dx[i] * dx[j];
                    curv += if i == j { v } else { 2.0 * v };
                }
            }
        }
        (curv, norm2)
    }

    /// One numeric factorisation of K with Hessian regularisation `delta_w`.
    fn factor_regularised(
        &mut self,
        st: &Iterate,
        b0: f64,
        delta_w: f64,
    ) -> Result<Inertia, SolveError> {
        let s = &self.structure;
        for j in 0..st.n {
            self.diag_x[j] = if s.fixed_x[j] {
                FIXED_DIAG
            } else if s.nonlinear[j] {
                self.sigma[j] + delta_w + b0
            } else {
                self.sigma[j] + delta_w
            };
        }
        self.pattern
            .assemble(&mut self.vals, &st.hv, &st.jv, &self.diag_x, &self.d_c);
        let t_factor = Instant::now();
        let inertia = self
            .linear
            .factor(&self.vals)
            .map_err(|e| SolveError::Backend(e.to_string()))?;
        self.factor_time += t_factor.elapsed();
        self.factorizations += 1;
        Ok(inertia)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::ipm::direction::usable_step;
    use crate::ipm::linsys::FaerLdlt;
    use crate::ipm::workspace::Newton;
    use crate::nlp::{EvalError, Nlp};
    use crate::observer::Observer;
    use crate::solver::{ControlFlow, IterationRecord};

    /// min −x₀² + x₁²/2 subject to x₀ + x₁ = 0: the Hessian diag(−2, 1) is indefinite and
    /// its reduction to the null space of J = [1 1], (−2 + 1)/2, is negative, so the KKT
    /// matrix has inertia (2, 1) only for δ_w > 1/2.
    struct Indefinite;

    impl Nlp for Indefinite {
        fn n(&self) -> usize {
            2
        }
        fn m(&self) -> usize {
            1
        }
        fn bounds(&self, xl: &mut [f64], xu: &mut [f64], gl: &mut [f64], gu: &mut [f64]) {
            xl.fill(f64::NEG_INFINITY);
            xu.fill(f64::INFINITY);
            (gl[0], gu[0]) = (0.0, 0.0);
        }
        fn initial_point(&self, x: &mut [f64]) {
            x.fill(0.0);
        }
        fn objective(&self, x: &[f64]) -> Result<f64, EvalError> {
            Ok(-x[0] * x[0] + 0.5 * x[1] * x[1])
        }
        fn gradient(&self, x: &[f64], g: &mut [f64]) -> Result<(), EvalError> {
            (g[0], g[1]) = (-2.0 * x[0], x[1]);
            Ok(())
        }
        fn constraints(&self, x: &[f64], c: &mut [f64]) -> Result<(), EvalError> {
            c[0] = x[0] + x[1];
            Ok(())
        }
        fn jacobian_structure(&self) -> Sparsity {
            Sparsity::new(vec![0, 0], vec![0, 1])
        }
        fn jacobian_values(&self, _: &[f64], v: &mut [f64]) -> Result<(), EvalError> {
            v.fill(1.0);
            Ok(())
        }
        fn hessian_structure(&self) -> Sparsity {
            Sparsity::new(vec![0, 1], vec![0, 1])
        }
        fn hessian_values(
            &self,
            _: &[f64],
            sigma: f64,
            _: &[f64],
            v: &mut [f64],
        ) -> Result<(), EvalError> {
            (v[0], v[1]) = (-2.0 * sigma, sigma);
            Ok(())
        }
    }

    /// Collects the δ_w, inertia and step-check outcome of the inertia trials.
    struct Trials(Vec<(f64, Inertia, Option<bool>)>);

    impl Observer for Trials {
        fn iteration(&mut self, _: &IterationRecord) -> ControlFlow {
            ControlFlow::Continue(())
        }
        fn diagnostic(&mut self, event: &Diagnostic) {
            if let Diagnostic::InertiaTrial {
                delta_w,
                inertia,
                step_check,
                ..
            } = event
            {
                self.0.push((*delta_w, *inertia, *step_check));
            }
        }
    }

    /// The KKT system of [`Indefinite`] (exact Hessian, natural order).
    fn indefinite_kkt<'l>(ldlt: &'l mut FaerLdlt) -> KktSystem<'l> {
        let nlp = Indefinite;
        let prob = ScaledNlp::new(&nlp, nlp.jacobian_structure(), nlp.hessian_structure());
        let structure = KktStructure {
            fixed_x: vec![false; 2],
            nonlinear: vec![true; 2],
            jac_rows: vec![0, 0],
            jac_cols: vec![0, 1],
        };
        KktSystem::new(Counted::new(ldlt), structure, &prob, None, true).unwrap()
    }

    /// An iterate of [`Indefinite`] without bounds, multipliers zero, with objective
    /// gradient `grad` and constraint value `c`.
    fn indefinite_iterate(grad: [f64; 2], c: f64) -> Iterate {
        Iterate {
            n: 2,
            m: 1,
            big_n: 2,
            slack_of_row: vec![NO_SLACK],
            row_of_slack: vec![],
            g_eq: vec![0.0],
            wl: vec![f64::NEG_INFINITY; 2],
            wu: vec![f64::INFINITY; 2],
            has_l: vec![false; 2],
            has_u: vec![false; 2],
            w: vec![0.0; 2],
            lam: vec![0.0],
            zl: vec![0.0; 2],
            zu: vec![0.0; 2],
            f: 0.0,
            grad: grad.to_vec(),
            c: vec![c],
            jv: vec![1.0, 1.0],
            hv: vec![-2.0, 1.0],
        }
    }

    #[test]
    fn inertia_correction_reaches_the_wanted_inertia_by_ipopt_s_rule() {
        let mut ldlt = FaerLdlt::new();
        let mut kkt = indefinite_kkt(&mut ldlt);
        let st = indefinite_iterate([0.0, 0.0], 0.0);
        let mut trials = Trials(Vec::new());
        let mut emitter = Emitter::new(&mut trials, 3);
        kkt.set_barrier_terms(&st);
        let d = kkt.first_delta_w(true);
        assert_eq!(d, 0.0, "nothing regularised yet");
        let delta = kkt
            .factor_with_inertia_correction(&st, 0.0, d, None, &mut emitter)
            .unwrap()
            .expect("regularised");
        // 0, then δ̄⁰ = 1e-4 growing by κ̄⁺ = 100 until δ > 1/2: 1e-4, 1e-2, 1
        let tried: Vec<f64> = trials.0.iter().map(|t| t.0).collect();
        assert_eq!(tried.len(), 4, "{tried:?}");
        assert_eq!(tried[0], 0.0);
        for (got, want) in tried[1..].iter().zip([1e-4, 1e-2, 1.0]) {
            assert!((got - want).abs() <= 1e-12 * want, "{tried:?}");
        }
        assert_eq!(delta, tried[3]);
        // the rejected trials have one negative eigenvalue too many, the accepted one (2, 1)
        for (_, inertia, _) in &trials.0[..3] {
            assert_eq!((inertia.positive, inertia.negative), (1, 2), "{inertia:?}");
        }
        let last = trials.0[3].1;
        assert_eq!((last.positive, last.negative, last.zero), (2, 1, 0));
        // the next iteration may start from δ_last/3, and a failed trial then grows by κ⁺ = 8
        assert!(kkt.regularised_last);
        assert_eq!(kkt.first_delta_w(true), delta / 3.0);
        assert_eq!(kkt.first_delta_w(false), 0.0);
        assert_eq!(kkt.next_delta_w(0.1), 0.1 * 8.0);
        assert_eq!(kkt.next_delta_w(0.0), delta / 3.0);
    }

    /// δ_w of the trials and whether each passed the step check (None: not checked).
    fn curvature_trials(grad: [f64; 2], r: f64, x1_upper: f64) -> (f64, Vec<(f64, Option<bool>)>) {
        let mut ldlt = FaerLdlt::new();
        let mut kkt = indefinite_kkt(&mut ldlt);
        let mut st = indefinite_iterate(grad, r);
        if x1_upper.is_finite() {
            (st.has_u[1], st.wu[1]) = (true, x1_upper);
        }
        let mut trials = Trials(Vec::new());
        let mut emitter = Emitter::new(&mut trials, 3);
        kkt.set_barrier_terms(&st);
        let mut newton = Newton::new(2, 1, 0);
        let mut check =
            |kkt: &mut KktSystem, st: &Iterate| usable_step(kkt, st, 0.0, &[r], &mut newton);
        let delta = kkt
            .factor_with_inertia_correction(&st, 0.0, 0.0, Some(&mut check), &mut emitter)
            .unwrap()
            .expect("a usable factor");
        (delta, trials.0.iter().map(|t| (t.0, t.2)).collect())
    }

    #[test]
    fn a_wrong_inertia_is_kept_only_for_a_long_step_of_positive_curvature() {
        // With δ_w = 0 the KKT matrix of min −x₀² + x₁²/2, x₀ + x₁ = 0 has one negative
        // eigenvalue too many (the reduced Hessian along (1, −1) is −1/2).
        // Gradient (0, −1), residual r = −1: the Newton step is dx = (0, 1) (dλ = 0), whose
        // curvature dxᵀ H dx = 1 is positive, so the unregularised factor is kept.
        let (delta, trials) = curvature_trials([0.0, -1.0], -1.0, f64::INFINITY);
        assert_eq!(delta, 0.0);
        assert_eq!(trials, vec![(0.0, Some(true))]);
        // The same step towards an upper bound x₁ ≤ 0.1 could only be taken to 0.099 of
        // its length: rejected as well, until δ_w = 1 gives the right inertia.
        let (delta, trials) = curvature_trials([0.0, -1.0], -1.0, 0.1);
        assert!((delta - 1.0).abs() < 1e-12, "δ_w = {delta}");
        let tested: Vec<Option<bool>> = trials.iter().map(|t| t.1).collect();
        assert_eq!(tested, vec![Some(false), Some(false), Some(false), None]);
        // Gradient (1, 0), r = 0: the step lies along the null space (1, −1) of J, where the
        // curvature (−2 + 1 + 2δ_w)t² is negative until δ_w > 1/2; IPOPT's sequence 0, 1e-4,
        // 1e-2 is rejected by the test, and δ_w = 1 has the right inertia (not tested).
        let (delta, trials) = curvature_trials([1.0, 0.0], 0.0, f64::INFINITY);
        assert!((delta - 1.0).abs() < 1e-12, "δ_w = {delta}");
        let tested: Vec<Option<bool>> = trials.iter().map(|t| t.1).collect();
        assert_eq!(tested, vec![Some(false), Some(false), Some(false), None]);
    }
}
