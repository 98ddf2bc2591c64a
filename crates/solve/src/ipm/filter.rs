//! The filter of the line search (Wächter & Biegler 2006, section 2.3).
//!
//! A trial point with constraint violation θ and barrier objective φ is acceptable if it is
//! not dominated by a filter entry and, against the point the step starts from (θ_k, φ_k),
//! either
//! - the switching condition ∇φᵀd < 0 and α (−∇φᵀd)^s_φ > δ θ_k^s_θ holds with θ_k ≤ θ_min
//!   and the Armijo condition φ ≤ φ_k + η_φ α ∇φᵀd, or
//! - θ ≤ (1 − γ_θ) θ_k or φ ≤ φ_k − γ_φ θ_k.
//!
//! A step accepted without the Armijo test of the switching condition augments the filter by
//! ((1 − γ_θ) θ_k, φ_k − γ_φ θ_k). The smallest step size tried is α_min.

/// Armijo constant η_φ of the filter line search.
const ETA_PHI: f64 = 1e-8;
/// Filter margin on the constraint violation γ_θ.
pub(super) const GAMMA_THETA: f64 = 1e-5;
/// Filter margin on the barrier function γ_φ.
pub(super) const GAMMA_PHI: f64 = 1e-8;
/// Switching-condition constants δ, s_θ, s_φ.
const SWITCH_DELTA: f64 = 1.0;
const S_THETA: f64 = 1.1;
const S_PHI: f64 = 2.3;
/// Safety factor γ_α for the minimum step size.
const GAMMA_ALPHA: f64 = 0.05;

/// Reference values of the filter line search at the point a step starts from: constraint
/// violation θ (1-norm, scaled), barrier objective φ and its directional derivative ∇φᵀd;
/// with the solve's bounds θ_min (switching condition) and θ_max (largest θ accepted).
#[derive(Clone, Copy, Debug)]
pub(super) struct LsReference {
    /// θ_k.
    pub theta: f64,
    /// φ_k.
    pub phi: f64,
    /// ∇φ_kᵀ d_k.
    pub gphi_d: f64,
    /// θ_min of the switching condition.
    pub theta_min: f64,
    /// θ_max, the largest θ accepted.
    pub theta_max: f64,
}

impl LsReference {
    /// Filter acceptance of a trial point (θ, φ) at step size α (Wächter & Biegler 2006):
    /// None if rejected, else Some(whether the step passed the Armijo test of the
    /// switching condition, in which case the filter is not augmented).
    pub fn accepts(&self, alpha: f64, theta: f64, phi: f64, filter: &Filter) -> Option<bool> {
        if !phi.is_finite() || theta > self.theta_max {
            return None;
        }
        if filter.dominates(theta, phi) {
            return None;
        }
        let switching = self.gphi_d < 0.0
            && alpha * (-self.gphi_d).powf(S_PHI) > SWITCH_DELTA * self.theta.powf(S_THETA);
        let armijo = phi <= self.phi + ETA_PHI * alpha * self.gphi_d;
        if switching && self.theta <= self.theta_min {
            return armijo.then_some(true);
        }
        if theta <= (1.0 - GAMMA_THETA) * self.theta || phi <= self.phi - GAMMA_PHI * self.theta {
            Some(switching && armijo)
        } else {
            None
        }
    }

    /// The smallest step size α_min of the backtracking from this reference.
    pub fn alpha_min(&self) -> f64 {
        let (theta0, gphi_d) = (self.theta, self.gphi_d);
        if gphi_d < 0.0 {
            GAMMA_ALPHA
                * GAMMA_THETA
                    .min(GAMMA_PHI * theta0 / -gphi_d)
                    .min(SWITCH_DELTA * theta0.powf(S_THETA) / (-gphi_d).powf(S_PHI))
        } else {
            GAMMA_ALPHA * GAMMA_THETA
        }
    }
}

/// The filter: pairs (θ, φ) that trial points must not be dominated by, for one barrier
/// parameter μ (the filter is emptied when μ changes).
#[derive(Default)]
pub(super) struct Filter {
    entries: Vec<(f64, f64)>,
    /// μ the entries belong to.
    mu: Option<f64>,
}

impl Filter {
    /// An empty filter with room for `capacity` entries.
    pub fn with_capacity(capacity: usize) -> Self {
        Filter {
            entries: Vec::with_capacity(capacity),
            mu: None,
        }
    }

    /// Whether an entry dominates (θ, φ): θ ≥ θ_f and φ ≥ φ_f.
    pub fn dominates(&self, theta: f64, phi: f64) -> bool {
        self.entries
            .iter()
            .any(|&(ft, fp)| theta >= ft && phi >= fp)
    }

    /// Adds the entry of a step from `reference` accepted without the Armijo test.
    pub fn augment(&mut self, reference: &LsReference) {
        self.entries.push((
            (1.0 - GAMMA_THETA) * reference.theta,
            reference.phi - GAMMA_PHI * reference.theta,
        ));
    }

    /// Empties the filter.
    pub fn clear(&mut self) {
        self.entries.clear();
    }

    /// Empties the filter if the barrier parameter is no longer `mu`.
    pub fn set_mu(&mut self, mu: f64) {
        if self.mu != Some(mu) {
            self.entries.clear();
            self.mu = Some(mu);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn reference(theta: f64, phi: f64, gphi_d: f64) -> LsReference {
        LsReference {
            theta,
            phi,
            gphi_d,
            theta_min: 1e-4,
            theta_max: 1e4,
        }
    }

    #[test]
    fn sufficient_decrease_of_theta_or_phi_is_accepted_and_augments_the_filter() {
        let filter = Filter::default();
        // θ_k = 1 above θ_min: the switching condition does not apply
        let r = reference(1.0, 0.0, -1.0);
        // θ reduced by more than γ_θ: accepted, not an Armijo (f-type) step
        assert_eq!(r.accepts(1.0, 0.5, 10.0, &filter), Some(false));
        // neither θ nor φ reduced enough: rejected
        let theta = 1.0 - 0.5 * GAMMA_THETA;
        assert_eq!(r.accepts(1.0, theta, 0.0, &filter), None);
        // φ reduced by more than γ_φ θ_k: accepted
        assert_eq!(
            r.accepts(1.0, theta, -2.0 * GAMMA_PHI, &filter),
            Some(false)
        );
        // above θ_max, or φ not finite: rejected
        assert_eq!(r.accepts(1.0, 2e4, -1.0, &filter), None);
        assert_eq!(r.accepts(1.0, 0.5, f64::NAN, &filter), None);
    }

    #[test]
    fn switching_condition_needs_armijo_below_theta_min() {
        let filter = Filter::default();
        // θ_k = 1e-6 ≤ θ_min, descent direction ∇φᵀd = −1: α (1)^2.3 > (1e-6)^1.1 holds
        let r = reference(1e-6, 1.0, -1.0);
        // Armijo: φ ≤ 1 − 1e-8 α
        assert_eq!(r.accepts(1.0, 1e-6, 1.0 - 2e-8, &filter), Some(true));
        // φ not decreased enough, although θ decreased a lot: rejected
        assert_eq!(r.accepts(1.0, 0.0, 1.0, &filter), None);
    }

    #[test]
    fn the_filter_rejects_dominated_points_and_forgets_them_when_mu_changes() {
        let mut filter = Filter::default();
        filter.set_mu(0.1);
        let r = reference(1.0, 5.0, 1.0);
        filter.augment(&r);
        let (ft, fp) = (1.0 - GAMMA_THETA, 5.0 - GAMMA_PHI);
        assert!(filter.dominates(ft, fp));
        assert!(filter.dominates(2.0, 6.0));
        assert!(!filter.dominates(0.5, 6.0));
        assert!(!filter.dominates(2.0, 4.0));
        // a point dominated by the filter is rejected even if it decreases θ against r
        let r2 = reference(10.0, 0.0, 1.0);
        assert_eq!(r2.accepts(1.0, 2.0, 6.0, &filter), None);
        filter.set_mu(0.1);
        assert!(filter.dominates(2.0, 6.0));
        filter.set_mu(0.02);
        assert!(!filter.dominates(2.0, 6.0));
    }

    #[test]
    fn alpha_min_follows_the_minimum_of_the_three_bounds() {
        // no descent: γ_α γ_θ
        assert_eq!(
            reference(1.0, 0.0, 1.0).alpha_min(),
            GAMMA_ALPHA * GAMMA_THETA
        );
        // descent with θ_k = 1, ∇φᵀd = −1: min(γ_θ, γ_φ, δ) = γ_φ
        let a = reference(1.0, 0.0, -1.0).alpha_min();
        assert!((a - GAMMA_ALPHA * GAMMA_PHI).abs() < 1e-24);
    }
}
