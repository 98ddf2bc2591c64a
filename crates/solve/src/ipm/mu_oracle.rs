//! Centring parameter σ of IPOPT's quality-function μ oracle: the σ (μ = σ × average
//! complementarity) whose step d(σ) = d_aff + σ (d_avg − d_aff) minimises a quality
//! function of the linearised optimality error, by golden-section search either above 1 or
//! below 1, whichever side the quality function falls towards (Nocedal, Wächter & Waltz
//! 2009; IPOPT `mu_oracle = quality-function`).

/// Smallest centring parameter searched (IPOPT `sigma_min`).
const SIGMA_MIN: f64 = 1e-6;
/// Largest centring parameter searched (IPOPT `sigma_max`).
const SIGMA_MAX: f64 = 100.0;
/// Relative width of the σ bracket at which the search stops
/// (IPOPT `quality_function_section_sigma_tol`).
const SIGMA_TOL: f64 = 1e-2;
/// Bracket reductions at most (IPOPT `quality_function_max_section_steps`).
const MAX_SECTIONS: usize = 8;

/// Choose σ for the quality function `q`, with σ·avg kept within [σ_lo_bound, σ_hi_bound]
/// (the barrier parameter's own bounds divided by the average complementarity).
pub(super) fn choose_sigma(
    mut q: impl FnMut(f64) -> f64,
    sigma_lo_bound: f64,
    sigma_hi_bound: f64,
) -> f64 {
    let q_one = q(1.0);
    let below_one = 1.0 - SIGMA_TOL.max(1e-4);
    let q_below = q(below_one);
    if q_below > q_one {
        // the quality function still falls at σ = 1: search above
        let up = SIGMA_MAX.min(sigma_hi_bound);
        if up <= 1.0 {
            return up;
        }
        golden_section(&mut q, (1.0, Some(q_one)), (up, None))
    } else {
        let lo = SIGMA_MIN.max(sigma_lo_bound);
        let up = lo.max(below_one).min(sigma_hi_bound);
        if lo >= up {
            return lo;
        }
        golden_section(&mut q, (lo, None), (up, Some(q_below)))
    }
}

/// Golden-section search for the minimiser of `q` in [lo, up], given the values at the
/// ends where known; the ends themselves are candidates when the bracket never left them.
fn golden_section(
    q: &mut impl FnMut(f64) -> f64,
    (lo0, q_lo0): (f64, Option<f64>),
    (up0, q_up0): (f64, Option<f64>),
) -> f64 {
    let g = (3.0 - 5f64.sqrt()) / 2.0;
    let (mut lo, mut up) = (lo0, up0);
    let (mut q_lo, mut q_up) = (q_lo0, q_up0);
    let mut m1 = lo + g * (up - lo);
    let mut m2 = lo + (1.0 - g) * (up - lo);
    let (mut q1, mut q2) = (q(m1), q(m2));
    let mut sections = 0;
    while up - lo >= SIGMA_TOL * up && sections < MAX_SECTIONS {
        sections += 1;
        if q1 > q2 {
            (lo, q_lo) = (m1, Some(q1));
            (m1, q1) = (m2, q2);
            m2 = lo + (1.0 - g) * (up - lo);
            q2 = q(m2);
        } else {
            (up, q_up) = (m2, Some(q2));
            (m2, q2) = (m1, q1);
            m1 = lo + g * (up - lo);
            q1 = q(m1);
        }
    }
    let (mut sigma, q_best) = if q1 < q2 { (m1, q1) } else { (m2, q2) };
    if up == up0 {
        if q_up.unwrap_or_else(|| q(up)) < q_best {
            sigma = up;
        }
    } else if lo == lo0 && q_lo.unwrap_or_else(|| q(lo)) < q_best {
        sigma = lo;
    }
    sigma
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn finds_an_interior_minimum_below_one() {
        let s = choose_sigma(|s| (s - 0.3).powi(2), 0.0, 1e5);
        // eight golden sections of [1e-6, 0.99] leave a bracket of 0.99 × 0.618⁸ ≈ 0.021
        assert!((s - 0.3).abs() < 0.025, "{s}");
    }

    #[test]
    fn finds_a_minimum_above_one() {
        let s = choose_sigma(|s| (s - 5.0).powi(2), 0.0, 1e5);
        assert!((s - 5.0).abs() < 99.0 * 0.618f64.powi(8), "{s}");
        assert!(s > 1.0);
    }

    #[test]
    fn monotone_quality_functions_end_at_the_bounds() {
        // decreasing in σ: the largest σ allowed
        assert_eq!(choose_sigma(|s| -s, 0.0, 1e5), SIGMA_MAX);
        assert_eq!(choose_sigma(|s| -s, 0.0, 20.0), 20.0);
        // increasing in σ: the smallest σ allowed
        assert_eq!(choose_sigma(|s| s, 0.0, 1e5), SIGMA_MIN);
        assert_eq!(choose_sigma(|s| s, 1e-3, 1e5), 1e-3);
    }

    #[test]
    fn counts_evaluations() {
        // two probes at 1 and 0.99, two interior points, one per section, at most one end
        let mut n = 0;
        choose_sigma(
            |s| {
                n += 1;
                (s - 0.5).powi(2)
            },
            0.0,
            1e5,
        );
        assert!(n <= 2 + 2 + MAX_SECTIONS + 1, "{n}");
    }
}
