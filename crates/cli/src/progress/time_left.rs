//! The estimate of the time left in the solve of one mesh, from the iterations seen so far
//! and, on the final mesh, from the coarse mesh solved before it.
//!
//! Time left = (expected iterations − iterations done) × seconds per iteration, where
//! - seconds per iteration: the rate observed on this mesh, weighted by the iterations it
//!   rests on against a prior of [`PRIOR_WEIGHT`] iterations at the coarse mesh's rate
//!   scaled by the mesh size ratio (the cost of an iteration grows about linearly with the
//!   number of intervals, the banded KKT system's size);
//! - expected iterations: on the final mesh, [`FINAL_PER_COARSE_ITERATION`] times as many as
//!   the coarse mesh took (the final solve starts from the coarse optimum: 71 iterations
//!   after 84 and after 103 on the coarse mesh in the nominal prediction); on the coarse mesh
//!   (no history), from how far the barrier parameter μ went from its first value towards
//!   its end in log scale;
//! - always at least [`LEAST_LEFT`] of the iterations done remain until the solve ends, so
//!   a solve running longer than expected shows a growing, not a negative, estimate.

/// Iterations of the final mesh per iteration of the coarse mesh solved before it.
const FINAL_PER_COARSE_ITERATION: f64 = 0.8;
/// Weight of the coarse-mesh rate against the observed rate, in iterations.
const PRIOR_WEIGHT: f64 = 3.0;
/// Least fraction of the iterations done that is expected to remain.
const LEAST_LEFT: f64 = 0.1;
/// Least progress of μ (fraction of the way, log scale) that gives an iteration estimate.
const LEAST_MU_PROGRESS: f64 = 0.05;

/// A finished solve of a coarser mesh: what the final mesh's estimate starts from.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SolvedMesh {
    /// Mesh intervals.
    pub intervals: usize,
    /// Iterations taken.
    pub iterations: usize,
    /// Time of those iterations [s] (from iteration 0 to the last).
    pub seconds: f64,
}

/// The solve of one mesh in progress.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MeshProgress {
    /// Mesh intervals.
    pub intervals: usize,
    /// Iterations done.
    pub iterations: usize,
    /// Time since iteration 0 of this mesh [s].
    pub seconds: f64,
    /// Barrier parameter μ at iteration 0.
    pub mu_start: f64,
    /// Barrier parameter μ now.
    pub mu: f64,
    /// Barrier parameter μ where a solve ends (the solver's floor).
    pub mu_end: f64,
}

/// Seconds left in the solve `now` (None when nothing can be said yet), given the coarse
/// mesh solved before it, if any.
pub fn seconds_left(now: &MeshProgress, before: Option<&SolvedMesh>) -> Option<f64> {
    let done = now.iterations as f64;
    let rate = seconds_per_iteration(now, before)?;
    let expected = match before {
        Some(b) => FINAL_PER_COARSE_ITERATION * b.iterations as f64,
        None => done / mu_progress(now)?,
    };
    let left = (expected - done).max(LEAST_LEFT * done);
    Some(left * rate)
}

/// Seconds per iteration on the mesh of `now`: observed, blended with the coarse mesh's
/// rate scaled by the size ratio.
fn seconds_per_iteration(now: &MeshProgress, before: Option<&SolvedMesh>) -> Option<f64> {
    let done = now.iterations as f64;
    let prior = before
        .filter(|b| b.iterations > 0 && b.intervals > 0)
        .map(|b| b.seconds / b.iterations as f64 * now.intervals as f64 / b.intervals as f64);
    match prior {
        Some(p) => Some((PRIOR_WEIGHT * p + now.seconds) / (PRIOR_WEIGHT + done)),
        None if now.iterations > 0 => Some(now.seconds / done),
        None => None,
    }
}

/// Fraction of the way μ went from its first value to its end, in log scale (None below
/// [`LEAST_MU_PROGRESS`] or when undefined); at most 1.
fn mu_progress(now: &MeshProgress) -> Option<f64> {
    let span = (now.mu_start / now.mu_end).ln();
    let done = (now.mu_start / now.mu).ln() / span;
    (span > 0.0 && done.is_finite() && done >= LEAST_MU_PROGRESS).then_some(done.min(1.0))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A synthetic solve: `total` iterations of `per_iter` seconds, μ falling
    /// geometrically from 0.1 to 1e-9 over the first `mu_iters` and staying there.
    fn record(k: usize, per_iter: f64, mu_iters: usize, intervals: usize) -> MeshProgress {
        let f = (k as f64 / mu_iters as f64).min(1.0);
        MeshProgress {
            intervals,
            iterations: k,
            seconds: k as f64 * per_iter,
            mu_start: 0.1,
            mu: 0.1 * 1e-8f64.powf(f),
            mu_end: 1e-9,
        }
    }

    #[test]
    fn the_coarse_mesh_estimate_follows_mu_in_log_scale() {
        // μ half way (log scale) after 20 iterations of 1 s: 20 s left
        let now = record(20, 1.0, 40, 10);
        assert!((seconds_left(&now, None).unwrap() - 20.0).abs() < 1e-9);
        // nothing at iteration 0, nor before μ moved
        assert_eq!(seconds_left(&record(0, 1.0, 40, 10), None), None);
        let mut still = record(5, 1.0, 40, 10);
        still.mu = still.mu_start;
        assert_eq!(seconds_left(&still, None), None);
    }

    #[test]
    fn the_final_mesh_estimate_starts_from_the_coarse_rate_and_learns_the_observed_one() {
        // coarse: 10 intervals, 90 iterations of 1 s; final: 50 intervals, 70 iterations of
        // 7 s (a little slower than the linear scaling's 5 s), μ nearly still (warm start)
        let coarse = SolvedMesh {
            intervals: 10,
            iterations: 90,
            seconds: 90.0,
        };
        let truth = |k: usize| (70 - k) as f64 * 7.0;
        let at = |k: usize| {
            let mut r = record(k, 7.0, 10_000, 50);
            r.mu = r.mu_start;
            seconds_left(&r, Some(&coarse)).unwrap()
        };
        // before any iteration: 0.8 × 90 = 72 iterations at the scaled 5 s
        assert!((at(0) - 360.0).abs() < 1e-9);
        // within 20 % of the time left over the first 30 % of the iterations; later the
        // error is at most that of 10 iterations at the true rate, plus 25 %
        for k in [1, 5, 10, 20] {
            let rel = (at(k) - truth(k)).abs() / truth(k);
            assert!(rel < 0.2, "iteration {k}: {} s for {} s", at(k), truth(k));
        }
        for k in 21..70 {
            let err = (at(k) - truth(k)).abs();
            assert!(
                err < 0.25 * truth(k) + 10.0 * 7.0,
                "iteration {k}: {} s for {} s",
                at(k),
                truth(k)
            );
        }
        // past the coarse mesh's count: a tenth of the iterations done at the observed rate
        let late = at(90);
        assert!((late - 9.0 * (3.0 * 5.0 + 90.0 * 7.0) / 93.0).abs() < 1e-9);
    }

    #[test]
    fn a_coarse_mesh_without_iterations_gives_no_prior() {
        let empty = SolvedMesh {
            intervals: 10,
            iterations: 0,
            seconds: 0.0,
        };
        // no prior rate: the observed one, still the coarse iteration count (0) → 10 %
        let r = record(10, 2.0, 10_000, 50);
        assert!((seconds_left(&r, Some(&empty)).unwrap() - 2.0).abs() < 1e-9);
        assert_eq!(
            seconds_left(&record(0, 2.0, 10_000, 50), Some(&empty)),
            None
        );
    }
}
