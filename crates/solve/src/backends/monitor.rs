//! Per-iteration bookkeeping shared by the C-style backends: builds the iteration log from
//! IPOPT-style intermediate callbacks, forwards each record to the caller's observer and
//! enforces the wall-clock limit.

use std::ffi::{c_int, c_void};
use std::panic::{catch_unwind, AssertUnwindSafe};
use std::time::{Duration, Instant};

use crate::observer::Observer;
use crate::solver::{ControlFlow, IterationRecord};

/// Why the monitor asked the backend to stop early.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum StopReason {
    /// The observer returned `Break`.
    Observer,
    /// The wall-clock limit passed.
    TimeLimit,
    /// The observer panicked (the panic is not propagated through C frames).
    ObserverPanic,
}

/// Iteration log, observer and time limit of one solve.
pub struct Monitor<'o> {
    observer: &'o mut dyn Observer,
    /// The iteration log collected so far (one record per callback).
    pub log: Vec<IterationRecord>,
    /// When the solve started.
    pub start: Instant,
    time_limit: Option<Duration>,
    /// Set when the monitor has asked the backend to stop.
    pub stop: Option<StopReason>,
}

impl<'o> Monitor<'o> {
    /// A monitor starting its clock now.
    pub fn new(observer: &'o mut dyn Observer, time_limit: Option<Duration>) -> Self {
        Monitor {
            observer,
            log: Vec::new(),
            start: Instant::now(),
            time_limit,
            stop: None,
        }
    }

    /// Records one iteration (its number is the log position) and says whether to go on.
    pub fn record(&mut self, mut rec: IterationRecord) -> bool {
        rec.iter = self.log.len();
        rec.elapsed = self.start.elapsed();
        let flow = catch_unwind(AssertUnwindSafe(|| self.observer.iteration(&rec)));
        self.log.push(rec);
        match flow {
            Err(_) => self.stop = Some(StopReason::ObserverPanic),
            Ok(ControlFlow::Break(())) => self.stop = Some(StopReason::Observer),
            Ok(ControlFlow::Continue(())) => {}
        }
        if self.stop.is_none() {
            if let Some(limit) = self.time_limit {
                if self.start.elapsed() >= limit {
                    self.stop = Some(StopReason::TimeLimit);
                }
            }
        }
        self.stop.is_none()
    }
}

/// IPOPT's `Intermediate_CB` (also ripopt's `IntermediateCb`): `user_data` is a `*mut Monitor`.
///
/// # Safety
/// `user_data` must point to a live [`Monitor`] not otherwise borrowed during the call.
#[allow(clippy::too_many_arguments)]
pub unsafe extern "C" fn intermediate_callback(
    _alg_mod: c_int,
    _iter_count: c_int,
    obj_value: f64,
    inf_pr: f64,
    inf_du: f64,
    mu: f64,
    d_norm: f64,
    regularization_size: f64,
    alpha_du: f64,
    alpha_pr: f64,
    ls_trials: c_int,
    user_data: *mut c_void,
) -> c_int {
    // SAFETY: guaranteed by the caller (the backend passes its own live Monitor).
    let monitor = unsafe { &mut *(user_data as *mut Monitor) };
    let rec = IterationRecord {
        objective: obj_value,
        inf_pr,
        inf_du,
        mu,
        step_norm: d_norm,
        alpha_pr,
        alpha_du,
        regularisation: regularization_size,
        ls_trials: ls_trials.max(0) as usize,
        ..IterationRecord::default()
    };
    c_int::from(monitor.record(rec))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn numbers_iterations_and_stops_on_break() {
        let mut seen = Vec::new();
        let mut obs = |r: &IterationRecord| {
            seen.push(r.iter);
            if r.iter == 2 {
                ControlFlow::Break(())
            } else {
                ControlFlow::Continue(())
            }
        };
        let mut m = Monitor::new(&mut obs, None);
        let p = &mut m as *mut Monitor as *mut c_void;
        let call = |obj: f64| unsafe {
            intermediate_callback(0, 7, obj, 0.0, 0.0, 0.1, 0.0, 0.0, 1.0, 1.0, 0, p)
        };
        assert_eq!(call(3.0), 1);
        assert_eq!(call(2.0), 1);
        assert_eq!(call(1.0), 0);
        assert_eq!(m.stop, Some(StopReason::Observer));
        assert_eq!(m.log.len(), 3);
        assert_eq!(m.log[2].objective, 1.0);
        drop(m);
        assert_eq!(seen, vec![0, 1, 2]);
    }

    #[test]
    fn time_limit_zero_stops_at_first_iteration() {
        let mut obs = |_: &IterationRecord| ControlFlow::Continue(());
        let mut m = Monitor::new(&mut obs, Some(Duration::ZERO));
        assert!(!m.record(IterationRecord::default()));
        assert_eq!(m.stop, Some(StopReason::TimeLimit));
    }

    #[test]
    fn observer_panic_is_contained() {
        let mut obs = |_: &IterationRecord| -> ControlFlow { panic!("observer bug") };
        let mut m = Monitor::new(&mut obs, None);
        assert!(!m.record(IterationRecord::default()));
        assert_eq!(m.stop, Some(StopReason::ObserverPanic));
    }
}
