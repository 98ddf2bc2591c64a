//! An [`Nlp`] wrapper that times and counts every problem evaluation made by a backend.
//!
//! Backends call the problem through [`TimedNlp`] so the time spent in the problem's own
//! functions (seconds of wall-clock) is measured on stride's side, independently of what the
//! backend library reports. Counters use `Cell`, so a `TimedNlp` belongs to one solve on one
//! thread.

use std::cell::{Cell, RefCell};
use std::time::{Duration, Instant};

use crate::nlp::{EvalError, Nlp};

/// Evaluation counts and accumulated wall-clock time of one solve.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct EvalCounts {
    /// Objective evaluations f(x).
    pub objective: usize,
    /// Gradient evaluations ∇f(x).
    pub gradient: usize,
    /// Constraint evaluations c(x).
    pub constraints: usize,
    /// Jacobian value evaluations.
    pub jacobian: usize,
    /// Hessian value evaluations.
    pub hessian: usize,
    /// Total wall-clock time spent inside the problem functions.
    pub time: Duration,
}

/// A problem whose evaluations are timed and counted; the first evaluation error is kept.
pub struct TimedNlp<'a> {
    nlp: &'a dyn Nlp,
    counts: Cell<EvalCounts>,
    first_error: RefCell<Option<EvalError>>,
}

impl<'a> TimedNlp<'a> {
    /// Wraps `nlp` with zeroed counters.
    pub fn new(nlp: &'a dyn Nlp) -> Self {
        TimedNlp {
            nlp,
            counts: Cell::new(EvalCounts::default()),
            first_error: RefCell::new(None),
        }
    }

    /// The wrapped problem.
    pub fn inner(&self) -> &'a dyn Nlp {
        self.nlp
    }

    /// Counts and time accumulated so far.
    pub fn counts(&self) -> EvalCounts {
        self.counts.get()
    }

    /// The first evaluation error seen (backends treat errors as rejected trial points).
    pub fn first_error(&self) -> Option<EvalError> {
        self.first_error.borrow().clone()
    }

    fn timed<R>(
        &self,
        bump: fn(&mut EvalCounts),
        f: impl FnOnce() -> Result<R, EvalError>,
    ) -> Result<R, EvalError> {
        let t0 = Instant::now();
        let r = f();
        let mut c = self.counts.get();
        c.time += t0.elapsed();
        bump(&mut c);
        self.counts.set(c);
        if let Err(e) = &r {
            let mut slot = self.first_error.borrow_mut();
            if slot.is_none() {
                *slot = Some(e.clone());
            }
        }
        r
    }

    /// Timed [`Nlp::objective`].
    pub fn objective(&self, x: &[f64]) -> Result<f64, EvalError> {
        self.timed(|c| c.objective += 1, || self.nlp.objective(x))
    }

    /// Timed [`Nlp::gradient`].
    pub fn gradient(&self, x: &[f64], grad: &mut [f64]) -> Result<(), EvalError> {
        self.timed(|c| c.gradient += 1, || self.nlp.gradient(x, grad))
    }

    /// Timed [`Nlp::constraints`].
    pub fn constraints(&self, x: &[f64], c: &mut [f64]) -> Result<(), EvalError> {
        self.timed(|k| k.constraints += 1, || self.nlp.constraints(x, c))
    }

    /// Timed [`Nlp::jacobian_values`].
    pub fn jacobian_values(&self, x: &[f64], vals: &mut [f64]) -> Result<(), EvalError> {
        self.timed(|c| c.jacobian += 1, || self.nlp.jacobian_values(x, vals))
    }

    /// Timed [`Nlp::hessian_values`].
    pub fn hessian_values(
        &self,
        x: &[f64],
        obj_factor: f64,
        lambda: &[f64],
        vals: &mut [f64],
    ) -> Result<(), EvalError> {
        self.timed(
            |c| c.hessian += 1,
            || self.nlp.hessian_values(x, obj_factor, lambda, vals),
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::nlp::{NlpFunction, Sparsity};

    /// f(x) = x², one variable, no constraints; fails for x < 0.
    struct Square;
    impl Nlp for Square {
        fn n(&self) -> usize {
            1
        }
        fn m(&self) -> usize {
            0
        }
        fn bounds(&self, _: &mut [f64], _: &mut [f64], _: &mut [f64], _: &mut [f64]) {}
        fn initial_point(&self, x: &mut [f64]) {
            x[0] = 1.0;
        }
        fn objective(&self, x: &[f64]) -> Result<f64, EvalError> {
            if x[0] < 0.0 {
                return Err(EvalError::Failed {
                    function: NlpFunction::Objective,
                    reason: "negative".into(),
                });
            }
            Ok(x[0] * x[0])
        }
        fn gradient(&self, x: &[f64], g: &mut [f64]) -> Result<(), EvalError> {
            g[0] = 2.0 * x[0];
            Ok(())
        }
        fn constraints(&self, _: &[f64], _: &mut [f64]) -> Result<(), EvalError> {
            Ok(())
        }
        fn jacobian_structure(&self) -> Sparsity {
            Sparsity::default()
        }
        fn jacobian_values(&self, _: &[f64], _: &mut [f64]) -> Result<(), EvalError> {
            Ok(())
        }
        fn hessian_structure(&self) -> Sparsity {
            Sparsity::new(vec![0], vec![0])
        }
        fn hessian_values(
            &self,
            _: &[f64],
            s: f64,
            _: &[f64],
            v: &mut [f64],
        ) -> Result<(), EvalError> {
            v[0] = 2.0 * s;
            Ok(())
        }
    }

    #[test]
    fn counts_calls_and_keeps_first_error() {
        let p = Square;
        let t = TimedNlp::new(&p);
        assert_eq!(t.objective(&[3.0]).unwrap(), 9.0);
        let mut g = [0.0];
        t.gradient(&[3.0], &mut g).unwrap();
        assert_eq!(g[0], 6.0);
        assert!(t.objective(&[-1.0]).is_err());
        let c = t.counts();
        assert_eq!((c.objective, c.gradient, c.hessian), (2, 1, 0));
        assert!(matches!(
            t.first_error(),
            Some(EvalError::Failed {
                function: NlpFunction::Objective,
                ..
            })
        ));
    }
}
