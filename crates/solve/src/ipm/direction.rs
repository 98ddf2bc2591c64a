//! Search directions: the primal-dual Newton step of the barrier problem from the condensed
//! KKT system, and the choice of μ by the free-mode oracles that need those steps.
//!
//! The Newton system (Wächter & Biegler 2006, section 2.2) with the bound multipliers eliminated
//! is [[W + Σ + δ_w I, Jᵀ], [J, −δ_c I]] (dw, dλ) = −(∇φ_μ + Jᵀλ, r) with Σ = Z_L/(w − L) +
//! Z_U/(U − w); slack rows are condensed into the constraint block (1/σ_s + δ_c). The
//! bound-multiplier steps follow from dw. The right-hand side is affine in μ, so
//! the steps for μ = 0 and μ = average complementarity give the step of any μ as their
//! affine combination: the oracles (Mehrotra probing, IPOPT's quality function) use this.
// Index loops over several parallel arrays are clearer than zipped iterators here.
#![allow(clippy::needless_range_loop)]

use std::time::Instant;

use crate::ipm::barrier::MU_MAX;
use crate::ipm::inertia::{KktStructure, KktSystem};
use crate::ipm::iterate::{dual_fraction_to_boundary, fraction_to_boundary, Iterate, NO_SLACK};
use crate::ipm::lbfgs::LowRankCorrection;
use crate::ipm::linsys::KktSolver;
use crate::ipm::mu_oracle::choose_sigma;
use crate::ipm::refine::{refine_solutions, RegularisedSystem};
use crate::ipm::workspace::{Ipm, Newton, Step};
use crate::observer::Emitter;
use crate::solver::{MuOracle, SolveError};

impl Step {
    /// A zero step over `big_n` variables and `m` constraints (`bound` multipliers if set).
    pub fn zeros(big_n: usize, m: usize, bound: bool) -> Self {
        let nb = if bound { big_n } else { 0 };
        Step {
            dw: vec![0.0; big_n],
            dlam: vec![0.0; m],
            dzl: vec![0.0; nb],
            dzu: vec![0.0; nb],
        }
    }
}

/// The data that defines one Newton right-hand side: the iterate, μ, the optional
/// complementarity targets (t_L, t_U) beyond μ (centrality correctors) and the residual r.
pub(super) struct NewtonRhs<'x> {
    pub st: &'x Iterate,
    pub mu: f64,
    pub targets: Option<(&'x [f64], &'x [f64])>,
    pub r: &'x [f64],
}

impl Newton {
    /// Buffers for `big_n` variables, `m` constraints and `ni` slacks.
    pub fn new(big_n: usize, m: usize, ni: usize) -> Self {
        Newton {
            main: Step::zeros(big_n, m, true),
            aff: Step::zeros(big_n, m, false),
            avg: Step::zeros(big_n, m, false),
            soc: Step::zeros(big_n, m, false),
            r_s: vec![0.0; ni],
            early_rhs: Vec::new(),
            early_rs: Vec::new(),
            early_block: Vec::new(),
            correction: LowRankCorrection::default(),
            correction_active: false,
            early_ready: false,
        }
    }
}

impl Newton {
    /// Frees the limited-memory correction's buffers (dim × 2k values) once the exact
    /// Hessian has taken over, so that they do not add to the exact tail's memory.
    pub fn drop_correction(&mut self) {
        self.correction = LowRankCorrection::default();
        self.correction_active = false;
    }

    /// The direction for μ = σ·avg from the block-solved steps for μ = 0 and μ = avg
    /// (their affine combination, see [`combine`]) into `main` (dw, dλ).
    fn combine_into_main(&mut self, sigma: f64) {
        let Newton { main, aff, avg, .. } = self;
        combine(&aff.dw, &avg.dw, sigma, &mut main.dw);
        combine(&aff.dlam, &avg.dlam, sigma, &mut main.dlam);
    }
}

/// Which buffer a direction is solved into.
#[derive(Clone, Copy, PartialEq, Eq)]
pub(super) enum Out {
    Main,
    Aff,
    Avg,
    Corrector,
    Soc,
}

/// Which complementarity targets a direction uses.
#[derive(Clone, Copy, PartialEq, Eq)]
pub(super) enum Targets {
    /// μ alone.
    None,
    /// The targets of the kept correctors.
    Kept,
    /// The targets of the corrector being tried.
    Trial,
}

/// Which residual a direction's right-hand side has.
#[derive(Clone, Copy, PartialEq, Eq)]
pub(super) enum Residual {
    /// r at the current iterate.
    Current,
    /// The accumulated residual of the second-order correction.
    Soc,
}

fn backend(e: impl std::fmt::Display) -> SolveError {
    SolveError::Backend(e.to_string())
}

/// Right-hand side of the condensed KKT system at barrier parameter μ: first block
/// −(∇f + Jᵀλ − μ/(x−L) + μ/(U−x)) (zero for fixed variables), then −r on rows without a
/// slack and −r − r_s/σ on slack rows; `r_s` receives the slack residuals −λ + barrier
/// terms. Affine in μ. With targets (t_L, t_U), bound j's complementarity target is
/// μ + t_L[j] (μ + t_U[j]) instead of μ (centrality correctors).
pub(super) fn newton_rhs(
    sys: &NewtonRhs,
    structure: &KktStructure,
    sigma: &[f64],
    rhs: &mut [f64],
    r_s: &mut [f64],
) {
    let (st, mu, targets) = (sys.st, sys.mu, sys.targets);
    let n = st.n;
    rhs[..n].copy_from_slice(&st.grad);
    for k in 0..st.jv.len() {
        rhs[structure.jac_cols[k]] += st.jv[k] * st.lam[structure.jac_rows[k]];
    }
    for j in 0..st.big_n {
        let (ml, mu_u) = match targets {
            Some((tl, tu)) => (mu + tl[j], mu + tu[j]),
            None => (mu, mu),
        };
        let mut b = 0.0;
        if st.has_l[j] {
            b -= ml / (st.w[j] - st.wl[j]);
        }
        if st.has_u[j] {
            b += mu_u / (st.wu[j] - st.w[j]);
        }
        if j < n {
            rhs[j] = if structure.fixed_x[j] {
                0.0
            } else {
                -(rhs[j] + b)
            };
        } else {
            r_s[j - n] = -st.lam[st.row_of_slack[j - n]] + b;
        }
    }
    for (i, &ri) in sys.r.iter().enumerate() {
        let k = st.slack_of_row[i];
        rhs[n + i] = if k == NO_SLACK {
            -ri
        } else {
            -ri - r_s[k] / sigma[n + k].max(1e-20)
        };
    }
}

/// The primal-dual step (dw with slack steps, dlam) from the solution `sol` of the condensed
/// KKT system and the slack residuals `r_s` of its right-hand side.
pub(super) fn step_from_solution(
    st: &Iterate,
    sol: &[f64],
    r_s: &[f64],
    kkt: (&KktStructure, &[f64]),
    dw: &mut [f64],
    dlam: &mut [f64],
) {
    let (structure, sigma) = kkt;
    let n = st.n;
    dw[..n].copy_from_slice(&sol[..n]);
    for j in 0..n {
        if structure.fixed_x[j] {
            dw[j] = 0.0;
        }
    }
    dlam.copy_from_slice(&sol[n..]);
    for (k, &i) in st.row_of_slack.iter().enumerate() {
        dw[n + k] = (dlam[i] - r_s[k]) / sigma[n + k].max(1e-20);
    }
}

/// out = a + σ (b − a): the step for μ = σ·avg from the steps `a` (μ = 0) and `b` (μ = avg),
/// the KKT right-hand side being affine in μ.
pub(super) fn combine(a: &[f64], b: &[f64], sigma: f64, out: &mut [f64]) {
    for ((o, &x), &y) in out.iter_mut().zip(a).zip(b) {
        *o = x + sigma * (y - x);
    }
}

/// Primal-dual steps of the bound multipliers for the primal step `dw` (Wächter & Biegler
/// 2006, section 2.2); with `targets` (t_L, t_U) the complementarity targets are μ + t_L[j],
/// μ + t_U[j] (centrality correctors), as in [`newton_rhs`].
pub(super) fn bound_multiplier_steps(
    st: &Iterate,
    mu: f64,
    targets: Option<(&[f64], &[f64])>,
    dw: &[f64],
    dzl: &mut [f64],
    dzu: &mut [f64],
) {
    for j in 0..st.big_n {
        dzl[j] = if st.has_l[j] {
            let sl = st.w[j] - st.wl[j];
            let d = mu / sl - st.zl[j] - st.zl[j] / sl * dw[j];
            targets.map_or(d, |(tl, _)| d + tl[j] / sl)
        } else {
            0.0
        };
        dzu[j] = if st.has_u[j] {
            let su = st.wu[j] - st.w[j];
            let d = mu / su - st.zu[j] + st.zu[j] / su * dw[j];
            targets.map_or(d, |(_, tu)| d + tu[j] / su)
        } else {
            0.0
        };
    }
}

/// Smallest curvature dxᵀ(W + Σ + δ_w I)dx per squared length ‖dx‖² of the primal step for
/// a factor of the wrong inertia to be kept (scaled problem; Chiang & Zavala's α_n).
const CURVATURE_MIN: f64 = 1e-8;
/// Smallest fraction-to-boundary step size (τ = 0.99) of a step kept with a wrong inertia.
const STEP_MIN: f64 = 0.5;

/// Whether the Newton step of barrier parameter `mu` and constraint residual `r`, solved
/// with the current factor, is usable although the factor's inertia is not (n, m, 0): its
/// primal part dx has curvature dxᵀ(W + Σ + δ_w I)dx ≥ κ‖dx‖² (the inertia-free test of
/// Chiang & Zavala 2016), and the fraction-to-boundary rule lets at least [`STEP_MIN`] of it
/// be taken (a factor with a nearly singular direction gives a step that runs into the
/// bounds at once). The step is left, unrefined, in `kkt.rhs`; `newton.main` and
/// `newton.r_s` serve as scratch (the iteration's direction is computed after).
pub(super) fn usable_step(
    kkt: &mut KktSystem,
    st: &Iterate,
    mu: f64,
    r: &[f64],
    newton: &mut Newton,
) -> Result<bool, SolveError> {
    let sys = NewtonRhs {
        st,
        mu,
        targets: None,
        r,
    };
    let Newton { main, r_s, .. } = newton;
    newton_rhs(&sys, &kkt.structure, &kkt.sigma, &mut kkt.rhs, r_s);
    kkt.linear.solve(&mut kkt.rhs).map_err(backend)?;
    let (curv, norm2) = kkt.curvature(&kkt.rhs[..st.n]);
    if !(curv.is_finite() && curv >= CURVATURE_MIN * norm2) {
        return Ok(false);
    }
    let parts = (&kkt.structure, &kkt.sigma[..]);
    step_from_solution(st, &kkt.rhs, r_s, parts, &mut main.dw, &mut main.dlam);
    Ok(fraction_to_boundary(st, &st.w, &main.dw, 0.99) >= STEP_MIN)
}

/// Solves for the step of right-hand side `sys` with the iteration's factorisation: with
/// the limited-memory correction applied, else refined against the unregularised matrix.
fn solve_newton(
    kkt: &mut KktSystem,
    correction: Option<&mut LowRankCorrection>,
    sys: NewtonRhs,
    r_s: &mut [f64],
    dw: &mut [f64],
    dlam: &mut [f64],
    emitter: &mut Emitter,
) -> Result<(), SolveError> {
    newton_rhs(&sys, &kkt.structure, &kkt.sigma, &mut kkt.rhs, r_s);
    let t = Instant::now();
    kkt.b_save.copy_from_slice(&kkt.rhs);
    kkt.linear.solve(&mut kkt.rhs).map_err(backend)?;
    if let Some(c) = correction {
        c.apply(&mut kkt.rhs);
    } else {
        // iterative refinement against the unregularised constraint block
        let reg = RegularisedSystem {
            linear: &mut kkt.linear,
            pattern: &kkt.pattern,
            vals: &kkt.vals,
            d_c_reg: &kkt.d_c_reg,
        };
        refine_solutions(reg, &kkt.b_save, &mut kkt.rhs, 1, &mut kkt.refine, emitter)
            .map_err(backend)?;
    }
    kkt.time += t.elapsed();
    let parts = (&kkt.structure, &kkt.sigma[..]);
    step_from_solution(sys.st, &kkt.rhs, r_s, parts, dw, dlam);
    Ok(())
}

impl Ipm<'_> {
    /// Solves for the Newton step at `mu` with `targets` and right-hand-side residual
    /// `residual` into the buffer `out` (its dw and dλ).
    pub(super) fn direction(
        &mut self,
        mu: f64,
        targets: Targets,
        residual: Residual,
        out: Out,
    ) -> Result<(), SolveError> {
        let Ipm {
            st,
            kkt,
            newton,
            corr,
            opt,
            ls,
            emitter,
            ..
        } = self;
        let targets = match targets {
            Targets::None => None,
            Targets::Kept => Some((&corr.tl[..], &corr.tu[..])),
            Targets::Trial => Some((&corr.tl_c[..], &corr.tu_c[..])),
        };
        let r = match residual {
            Residual::Current => &opt.r[..],
            Residual::Soc => &ls.soc_rhs_r[..],
        };
        let step = match out {
            Out::Main => &mut newton.main,
            Out::Aff => &mut newton.aff,
            Out::Avg => &mut newton.avg,
            Out::Soc => &mut newton.soc,
            Out::Corrector => &mut corr.trial,
        };
        let sys = NewtonRhs { st, mu, targets, r };
        let correction = newton.correction_active.then_some(&mut newton.correction);
        let r_s = &mut newton.r_s;
        solve_newton(
            kkt,
            correction,
            sys,
            r_s,
            &mut step.dw,
            &mut step.dlam,
            emitter,
        )
    }

    /// The Newton steps this iteration needs, solved together in one block solve (one pass
    /// over the factor instead of one per step): in free mode the steps for μ = 0 and μ =
    /// average complementarity (the step of any μ is their affine combination), in fixed
    /// mode the step for μ. With the limited-memory correction the block also holds the
    /// correction's columns; with the exact Hessian the steps are refined together. They
    /// are left in `newton.aff` and `newton.avg`.
    pub(super) fn early_steps(&mut self, avg: f64) -> Result<(), SolveError> {
        let mus = [self.barrier.mu, 0.0, avg];
        let early_mus: &[f64] = if !self.barrier.adaptive {
            &mus[..1]
        } else if avg > 0.0 {
            &mus[1..]
        } else {
            &[]
        };
        let k0 = early_mus.len();
        let Ipm {
            st,
            kkt,
            newton,
            opt,
            lbfgs,
            emitter,
            ..
        } = self;
        let (dim, ni) = (kkt.pattern.dim, st.row_of_slack.len());
        newton.early_rhs.resize(k0 * dim, 0.0);
        newton.early_rs.resize(k0 * ni, 0.0);
        for (c, &mu_c) in early_mus.iter().enumerate() {
            let sys = NewtonRhs {
                st,
                mu: mu_c,
                targets: None,
                r: &opt.r,
            };
            let rhs = &mut newton.early_rhs[c * dim..(c + 1) * dim];
            let r_s = &mut newton.early_rs[c * ni..(c + 1) * ni];
            newton_rhs(&sys, &kkt.structure, &kkt.sigma, rhs, r_s);
        }
        let t_early = Instant::now();
        let lb = lbfgs.as_ref().map(|q| &q.lbfgs).filter(|lb| !lb.is_empty());
        // the step check solves the fixed-mode step (the one step of k0 = 1) for μ itself
        let solved = k0 == 1 && std::mem::take(&mut kkt.step_solved);
        let early_ok = match lb {
            Some(lb) => correct_block(kkt, newton, lb, st.n, k0),
            None => {
                newton.correction_active = false;
                k0 > 0 && refined_block(kkt, newton, k0, solved, emitter)
            }
        };
        kkt.time += t_early.elapsed();
        newton.early_ready = false;
        if early_ok && k0 > 0 {
            let outputs = [&mut newton.aff, &mut newton.avg];
            for (col, step) in outputs.into_iter().take(k0).enumerate() {
                step_from_solution(
                    st,
                    &newton.early_rhs[col * dim..(col + 1) * dim],
                    &newton.early_rs[col * ni..(col + 1) * ni],
                    (&kkt.structure, &kkt.sigma),
                    &mut step.dw,
                    &mut step.dlam,
                );
            }
            newton.early_ready = true;
        }
        Ok(())
    }
}

/// The limited-memory correction of the iteration: its columns K₀⁻¹Ŵ solved in one block
/// with the `k0` Newton right-hand sides, which are then corrected. Whether all worked.
fn correct_block(
    kkt: &mut KktSystem,
    newton: &mut Newton,
    lb: &crate::ipm::lbfgs::Lbfgs,
    n: usize,
    k0: usize,
) -> bool {
    let dim = kkt.pattern.dim;
    let mut early_ok = false;
    let Newton {
        early_rhs,
        early_block,
        correction,
        correction_active,
        ..
    } = newton;
    let linear = &mut kkt.linear;
    *correction_active = correction.prepare(lb, n, dim, |v, k| {
        early_block.clear();
        early_block.extend_from_slice(v);
        early_block.extend_from_slice(early_rhs);
        let ok = linear.solve_many(early_block, k + k0).is_ok();
        v.copy_from_slice(&early_block[..k * dim]);
        early_rhs.copy_from_slice(&early_block[k * dim..]);
        early_ok = ok;
        ok
    });
    if *correction_active {
        for sol in early_rhs.chunks_mut(dim) {
            correction.apply(sol);
        }
    } else {
        early_ok = false;
    }
    early_ok
}

/// The `k0` Newton right-hand sides solved in one block and refined together; with
/// `solved`, the one right-hand side's solution is taken from `kkt.rhs` (the step check's
/// solve of the same system, see [`usable_step`]). Whether it worked.
fn refined_block(
    kkt: &mut KktSystem,
    newton: &mut Newton,
    k0: usize,
    solved: bool,
    emitter: &mut Emitter,
) -> bool {
    newton.early_block.clear();
    newton.early_block.extend_from_slice(&newton.early_rhs);
    if solved {
        newton.early_rhs.copy_from_slice(&kkt.rhs);
    } else if kkt.linear.solve_many(&mut newton.early_rhs, k0).is_err() {
        return false;
    }
    let reg = RegularisedSystem {
        linear: &mut kkt.linear,
        pattern: &kkt.pattern,
        vals: &kkt.vals,
        d_c_reg: &kkt.d_c_reg,
    };
    let (b, x) = (&newton.early_block, &mut newton.early_rhs);
    refine_solutions(reg, b, x, k0, &mut kkt.refine, emitter).is_ok()
}

impl Ipm<'_> {
    /// The search direction of the iteration and, in free mode, μ: fixed mode takes the
    /// block-solved step for μ; IPOPT's quality function picks σ (μ = σ·avg) minimising the
    /// linearised optimality error of the combined step; Mehrotra probing sets σ = (affine
    /// complementarity / avg)³, kept above a fraction of the infeasibility (safeguard). The
    /// direction is left in `newton.main` and τ set from the final μ.
    pub(super) fn search_direction(&mut self, floor: f64, avg: f64) -> Result<(), SolveError> {
        let mut direction_ready = false;
        let (adaptive, early_ready) = (self.barrier.adaptive, self.newton.early_ready);
        if !adaptive && early_ready {
            // fixed mode: the step for μ came with the block solve
            let n = &mut self.newton;
            n.main.dw.copy_from_slice(&n.aff.dw);
            n.main.dlam.copy_from_slice(&n.aff.dlam);
            direction_ready = true;
        }
        if adaptive && self.barrier.oracle == MuOracle::QualityFunction && avg > 0.0 {
            self.quality_function_mu(floor, avg)?;
            direction_ready = true;
        } else if adaptive {
            direction_ready = self.probing_mu(floor, avg)?;
        }
        let mu = self.barrier.mu;
        self.barrier.tau = (1.0 - mu).max(0.99);
        if !direction_ready {
            self.direction(mu, Targets::None, Residual::Current, Out::Main)?;
        }
        Ok(())
    }

    /// IPOPT's quality-function oracle: μ from the σ that minimises the linearised
    /// optimality error after the step; the final direction is the combination of the
    /// steps for μ = 0 and μ = avg, without a third solve.
    fn quality_function_mu(&mut self, floor: f64, avg: f64) -> Result<(), SolveError> {
        if !self.newton.early_ready {
            self.direction(0.0, Targets::None, Residual::Current, Out::Aff)?;
            self.direction(avg, Targets::None, Residual::Current, Out::Avg)?;
        }
        let tau_q = (1.0 - self.opt.err0).max(0.99);
        let (primal2, dual2) = self
            .st
            .mean_squared_infeasibilities(&self.opt.gl, &self.opt.r);
        let Ipm { st, newton, .. } = self;
        let Newton {
            main,
            aff,
            avg: at_avg,
            ..
        } = newton;
        let quality = |sigma: f64| -> f64 {
            combine(&aff.dw, &at_avg.dw, sigma, &mut main.dw);
            bound_multiplier_steps(
                st,
                sigma * avg,
                None,
                &main.dw,
                &mut main.dzl,
                &mut main.dzu,
            );
            let ap = fraction_to_boundary(st, &st.w, &main.dw, tau_q);
            let ad = dual_fraction_to_boundary(st, &main.dzl, &main.dzu, tau_q);
            let c2 = st
                .complementarity_after_step(&main.dw, &main.dzl, &main.dzu, ap, ad)
                .1;
            (1.0 - ad).powi(2) * dual2 + (1.0 - ap).powi(2) * primal2 + c2
        };
        let sigma = choose_sigma(quality, floor / avg, MU_MAX / avg);
        let mu = (sigma * avg).clamp(floor, MU_MAX);
        self.barrier.mu = mu;
        self.newton.combine_into_main(mu / avg);
        Ok(())
    }

    /// Mehrotra probing with the affine-scaling direction (μ = 0): σ = (complementarity
    /// after the affine step / avg)³. Far from feasibility a small μ lets iterates hug their
    /// bounds and the multipliers run away (quasi-random gait guess), so μ stays at least
    /// the safeguard factor × the scaled infeasibility, never above avg. Returns whether the
    /// final direction is ready (combined from the block-solved steps).
    fn probing_mu(&mut self, floor: f64, avg: f64) -> Result<bool, SolveError> {
        if self.newton.early_ready {
            let n = &mut self.newton;
            n.main.dw.copy_from_slice(&n.aff.dw);
            n.main.dlam.copy_from_slice(&n.aff.dlam);
        } else {
            self.direction(0.0, Targets::None, Residual::Current, Out::Main)?;
        }
        let (st, main) = (&self.st, &mut self.newton.main);
        bound_multiplier_steps(st, 0.0, None, &main.dw, &mut main.dzl, &mut main.dzu);
        let ap = fraction_to_boundary(st, &st.w, &main.dw, 1.0);
        let ad = dual_fraction_to_boundary(st, &main.dzl, &main.dzu, 1.0);
        if avg <= 0.0 {
            self.barrier.mu = floor;
            return Ok(false);
        }
        let aff = st
            .complementarity_after_step(&main.dw, &main.dzl, &main.dzu, ap, ad)
            .0
            .max(0.0);
        let sig = (aff / avg).powi(3).min(1.0);
        let e = &self.opt;
        let lower = (self.o.mu_safeguard_factor() * (e.inf_du / e.s_d).max(e.inf_pr)).min(avg);
        let mu = (sig * avg).max(lower).clamp(floor, MU_MAX);
        self.barrier.mu = mu;
        if self.newton.early_ready {
            // the step of the final μ, without another solve
            self.newton.combine_into_main(mu / avg);
            return Ok(true);
        }
        Ok(false)
    }
}
