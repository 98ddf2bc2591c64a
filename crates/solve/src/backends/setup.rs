//! Checks shared by the backends before a solve: bounds, derivative patterns and the problem
//! functions at the initial point, turned into [`SolveError`]s that say what is wrong.

use crate::nlp::{validate_bounds, validate_structures, Bounds, Nlp, Structures};
use crate::solver::{HessianMode, SolveError, SolverOptions};

/// A validated problem: bounds, derivative patterns and the initial point.
#[derive(Debug, Clone)]
pub struct Prepared {
    /// Variable and constraint bounds.
    pub bounds: Bounds,
    /// Jacobian and Hessian patterns.
    pub structures: Structures,
    /// The problem's initial guess.
    pub x0: Vec<f64>,
}

/// Validates `nlp` and evaluates f, ∇f, c and the Jacobian at its initial point.
pub fn prepare(nlp: &dyn Nlp) -> Result<Prepared, SolveError> {
    let bounds = validate_bounds(nlp)?;
    let structures = validate_structures(nlp)?;
    let (n, m) = (nlp.n(), nlp.m());
    let mut x0 = vec![0.0; n];
    nlp.initial_point(&mut x0);
    let init = |r: Result<(), crate::nlp::EvalError>| r.map_err(SolveError::InitialEvaluation);
    init(nlp.objective(&x0).map(|_| ()))?;
    init(nlp.gradient(&x0, &mut vec![0.0; n]))?;
    init(nlp.constraints(&x0, &mut vec![0.0; m]))?;
    init(nlp.jacobian_values(&x0, &mut vec![0.0; structures.jacobian.nnz()]))?;
    Ok(Prepared {
        bounds,
        structures,
        x0,
    })
}

/// Rejects the stride-ipm features a backend (`name`) does not have:
/// [`HessianMode::Hybrid`] (switching from the limited-memory to the exact Hessian during a
/// solve) and `SolverOptions::centrality_correctors`.
pub fn reject_ipm_only(o: &SolverOptions, name: &str) -> Result<(), SolveError> {
    if matches!(o.hessian, HessianMode::Hybrid { .. }) {
        return Err(SolveError::InvalidOption {
            name: "hessian",
            reason: format!(
                "{name} cannot switch from the limited-memory to the exact Hessian during a \
                 solve (a stride-ipm feature); choose the exact or the limited-memory Hessian"
            ),
        });
    }
    if o.centrality_correctors > 0 {
        return Err(SolveError::InvalidOption {
            name: "centrality_correctors",
            reason: format!(
                "{name} has no centrality correctors (a stride-ipm feature); set them to 0"
            ),
        });
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ipm_only_options_are_named_in_the_error() {
        assert!(reject_ipm_only(&SolverOptions::default(), "IPOPT").is_ok());
        let tail = SolverOptions {
            hessian: HessianMode::Hybrid { history: 6 },
            ..SolverOptions::default()
        };
        let correctors = SolverOptions {
            centrality_correctors: 2,
            ..SolverOptions::default()
        };
        for (o, field) in [(tail, "hessian"), (correctors, "centrality_correctors")] {
            match reject_ipm_only(&o, "IPOPT") {
                Err(SolveError::InvalidOption { name, reason }) => {
                    assert_eq!(name, field);
                    assert!(reason.contains("IPOPT"), "{reason}");
                }
                other => panic!("{field}: {other:?}"),
            }
        }
    }
}
