//! Coupled coordinates (OpenSim `CoordinateCouplerConstraint`), eliminated by
//! substitution: a dependent coordinate's value, speed and acceleration follow from its
//! independent coordinate, `q_d = f(q_i)`, `q̇_d = f'(q_i) q̇_i`,
//! `q̈_d = f'(q_i) q̈_i + f''(q_i) q̇_i²`, and its generalised force is carried by the
//! independent coordinate, `τ_i += f'(q_i) τ_d`, `τ_d = 0` (virtual work). This is exact
//! and adds no constraint forces or states; the values a caller passes for a dependent
//! coordinate are ignored.

use stride_ad::Scalar;
use stride_model::function::CompiledFunction;
use stride_model::Model;

use crate::error::MultibodyError;

/// A coupler prepared for evaluation.
#[derive(Clone, Debug)]
pub struct CompiledCoupler {
    /// Dependent coordinate index.
    pub dependent: usize,
    /// Independent coordinate index.
    pub independent: usize,
    /// `q_d = f(q_i)`.
    pub function: CompiledFunction,
}

/// Compile the couplers of `model`; an independent coordinate may not itself be dependent.
pub fn compile_couplers(model: &Model) -> Result<Vec<CompiledCoupler>, MultibodyError> {
    let nc = model.coordinates.len();
    let mut out = Vec::with_capacity(model.couplers.len());
    for c in &model.couplers {
        let bad = |reason: String| MultibodyError::Coupler {
            name: c.name.clone(),
            reason,
        };
        if c.dependent >= nc || c.independent >= nc || c.dependent == c.independent {
            return Err(bad(format!(
                "coordinates {} and {} are not two of the {nc} coordinates",
                c.dependent, c.independent
            )));
        }
        if model.couplers.iter().any(|o| o.dependent == c.independent) {
            return Err(bad(
                "its independent coordinate is itself coupled (chains are not supported)".into(),
            ));
        }
        let function = c
            .function
            .compile()
            .map_err(|e| bad(format!("function: {e}")))?;
        out.push(CompiledCoupler {
            dependent: c.dependent,
            independent: c.independent,
            function,
        });
    }
    Ok(out)
}

/// Overwrite the dependent coordinates of `q`, `v` and (when given) `a` from their
/// independent coordinates.
pub fn couple<T: Scalar>(
    couplers: &[CompiledCoupler],
    q: &mut [T],
    v: &mut [T],
    a: Option<&mut [T]>,
) {
    let mut a = a;
    for c in couplers {
        let (i, d) = (c.independent, c.dependent);
        let [f, d1, d2] = c.function.eval(q[i]);
        q[d] = f;
        v[d] = d1 * v[i];
        if let Some(a) = a.as_deref_mut() {
            a[d] = d1 * a[i] + d2 * v[i] * v[i];
        }
    }
}

/// Move each dependent coordinate's generalised force onto its independent coordinate
/// (`q`: the coupled coordinates the forces were computed at).
pub fn reduce<T: Scalar>(couplers: &[CompiledCoupler], q: &[T], tau: &mut [T]) {
    for c in couplers {
        let [_, d1, _] = c.function.eval(q[c.independent]);
        let t = tau[c.dependent];
        tau[c.independent] += d1 * t;
        tau[c.dependent] = T::zero();
    }
}
