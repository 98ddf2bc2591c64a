//! Centrality correctors (Gondzio 1996).
//!
//! The step is cut by the fraction-to-boundary rule when some complementarity products
//! would leave the neighbourhood of μ; each corrector moves the targets of those products
//! back into [β_min μ, β_max μ] at an enlarged step size and solves again with the same
//! factorisation, and is kept only if the step size grows by a factor
//! [`CORRECTOR_GAIN`].
// Index loops over several parallel arrays are clearer than zipped iterators here.
#![allow(clippy::needless_range_loop)]

use crate::ipm::direction::{bound_multiplier_steps, Out, Residual, Targets};
use crate::ipm::iterate::{dual_fraction_to_boundary, fraction_to_boundary, Iterate};
use crate::ipm::workspace::{Correctors, Ipm, Step};
use crate::observer::Diagnostic;
use crate::solver::SolveError;

/// Products outside [β_min μ, β_max μ] are corrected.
const CORRECTOR_BETA_MIN: f64 = 0.1;
const CORRECTOR_BETA_MAX: f64 = 10.0;
/// A corrector aims at the step size min(1, CORRECTOR_AIM_FACTOR α + CORRECTOR_AIM_ADD).
const CORRECTOR_AIM_FACTOR: f64 = 2.0;
const CORRECTOR_AIM_ADD: f64 = 0.1;
/// A corrected direction is kept if its step size is at least this factor times the
/// previous one's.
const CORRECTOR_GAIN: f64 = 1.1;

impl Correctors {
    /// Buffers for `big_n` variables and `m` constraints, empty when `enabled` is false.
    pub fn new(enabled: bool, big_n: usize, m: usize) -> Self {
        let len = if enabled { big_n } else { 0 };
        Correctors {
            tl: vec![0.0; len],
            tu: vec![0.0; len],
            tl_c: vec![0.0; len],
            tu_c: vec![0.0; len],
            trial: Step::zeros(len, if enabled { m } else { 0 }, true),
            targets_on: false,
            kept: 0,
        }
    }

    /// The kept targets if the direction carries them.
    pub fn kept_targets(&self) -> Option<(&[f64], &[f64])> {
        self.targets_on.then_some((&self.tl[..], &self.tu[..]))
    }
}

/// Complementarity targets of Gondzio's centrality correction for `step` taken with the
/// enlarged step sizes (ap, ad): each trial product (w + ap dw − L)(z_L + ad dz_L) is moved
/// into [β_min μ, β_max μ] by adding the difference to that bound's target (a decrease by at
/// most β_max μ). Returns the number of products outside the box.
pub(super) fn centrality_targets(
    st: &Iterate,
    mu: f64,
    step: &Step,
    (ap, ad): (f64, f64),
    tl: &mut [f64],
    tu: &mut [f64],
) -> usize {
    let (dw, dzl, dzu) = (&step.dw, &step.dzl, &step.dzu);
    let (lo, hi) = (CORRECTOR_BETA_MIN * mu, CORRECTOR_BETA_MAX * mu);
    let shift = |v: f64| -> f64 {
        if v < lo {
            lo - v
        } else if v > hi {
            (hi - v).max(-hi)
        } else {
            0.0
        }
    };
    let mut outside = 0usize;
    for j in 0..st.big_n {
        if st.has_l[j] {
            let v = (st.w[j] + ap * dw[j] - st.wl[j]) * (st.zl[j] + ad * dzl[j]);
            let d = shift(v);
            if d != 0.0 {
                outside += 1;
                tl[j] += d;
            }
        }
        if st.has_u[j] {
            let v = (st.wu[j] - st.w[j] - ap * dw[j]) * (st.zu[j] + ad * dzu[j]);
            let d = shift(v);
            if d != 0.0 {
                outside += 1;
                tu[j] += d;
            }
        }
    }
    outside
}

impl Ipm<'_> {
    /// Up to `centrality_correctors` correctors on the iteration's direction; a kept one
    /// replaces the direction and its targets.
    pub(super) fn centrality_correctors(&mut self) -> Result<(), SolveError> {
        let (mu, tau) = (self.barrier.mu, self.barrier.tau);
        self.corr.targets_on = false;
        if self.o.centrality_correctors == 0 || mu <= 0.0 {
            return Ok(());
        }
        self.corr.tl.fill(0.0);
        self.corr.tu.fill(0.0);
        let (st, main) = (&self.st, &mut self.newton.main);
        bound_multiplier_steps(st, mu, None, &main.dw, &mut main.dzl, &mut main.dzu);
        let mut ap = fraction_to_boundary(st, &st.w, &main.dw, tau);
        let mut ad = dual_fraction_to_boundary(st, &main.dzl, &main.dzu, tau);
        for _ in 0..self.o.centrality_correctors {
            let a = ap.min(ad);
            if a >= 1.0 {
                break;
            }
            let aim_p = (CORRECTOR_AIM_FACTOR * ap + CORRECTOR_AIM_ADD).min(1.0);
            let aim_d = (CORRECTOR_AIM_FACTOR * ad + CORRECTOR_AIM_ADD).min(1.0);
            let c = &mut self.corr;
            c.tl_c.copy_from_slice(&c.tl);
            c.tu_c.copy_from_slice(&c.tu);
            let outside = centrality_targets(
                &self.st,
                mu,
                &self.newton.main,
                (aim_p, aim_d),
                &mut c.tl_c,
                &mut c.tu_c,
            );
            if outside == 0 {
                break;
            }
            self.direction(mu, Targets::Trial, Residual::Current, Out::Corrector)?;
            let (st, c) = (&self.st, &mut self.corr);
            let targets_c = Some((&c.tl_c[..], &c.tu_c[..]));
            let t = &mut c.trial;
            bound_multiplier_steps(st, mu, targets_c, &t.dw, &mut t.dzl, &mut t.dzu);
            let ap_c = fraction_to_boundary(st, &st.w, &t.dw, tau);
            let ad_c = dual_fraction_to_boundary(st, &t.dzl, &t.dzu, tau);
            if self.emitter.wants(3) {
                self.emitter.emit(Diagnostic::Corrector {
                    outside,
                    before: (ap, ad),
                    after: (ap_c, ad_c),
                });
            }
            if ap_c.min(ad_c) < CORRECTOR_GAIN * a {
                break;
            }
            let c = &mut self.corr;
            std::mem::swap(&mut self.newton.main, &mut c.trial);
            std::mem::swap(&mut c.tl, &mut c.tl_c);
            std::mem::swap(&mut c.tu, &mut c.tu_c);
            (ap, ad) = (ap_c, ad_c);
            c.targets_on = true;
            c.kept += 1;
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// One variable with bounds 0 ≤ w ≤ 10 at w = 1 with z_L = 1, z_U = 0.1.
    fn one_variable() -> Iterate {
        Iterate {
            n: 1,
            m: 0,
            big_n: 1,
            slack_of_row: vec![],
            row_of_slack: vec![],
            g_eq: vec![],
            wl: vec![0.0],
            wu: vec![10.0],
            has_l: vec![true],
            has_u: vec![true],
            w: vec![1.0],
            lam: vec![],
            zl: vec![1.0],
            zu: vec![0.1],
            f: 0.0,
            grad: vec![0.0],
            c: vec![],
            jv: vec![],
            hv: vec![],
        }
    }

    #[test]
    fn targets_move_products_into_the_neighbourhood_of_mu() {
        let st = one_variable();
        let mu = 1.0;
        // step w → 1 − 0.99 = 0.01, z_L → 1, z_U unchanged: products 0.01 (below 0.1 μ)
        // and 9.99 × 0.1 ≈ 1 (inside)
        let step = Step {
            dw: vec![-0.99],
            dlam: vec![],
            dzl: vec![0.0],
            dzu: vec![0.0],
        };
        let (mut tl, mut tu) = (vec![0.0], vec![0.0]);
        let outside = centrality_targets(&st, mu, &step, (1.0, 1.0), &mut tl, &mut tu);
        assert_eq!(outside, 1);
        assert!((tl[0] - (0.1 - 0.01)).abs() < 1e-15, "{}", tl[0]);
        assert_eq!(tu[0], 0.0);
        // a product far above β_max μ is lowered by at most β_max μ
        let step = Step {
            dw: vec![0.0],
            dlam: vec![],
            dzl: vec![100.0],
            dzu: vec![0.0],
        };
        let (mut tl, mut tu) = (vec![0.0], vec![0.0]);
        centrality_targets(&st, mu, &step, (1.0, 1.0), &mut tl, &mut tu);
        assert_eq!(tl[0], -10.0);
    }
}
