//! Static parameters: decision variables that are constant over time (FORMULATION 12.6),
//! appended to the NLP vector after the layout's variables, each with bounds and a linear
//! scaling to [−0.5, 0.5], and read by the node function as extra inputs placed after its
//! variable inputs. What a parameter sets in the model is a list of [`ParameterTarget`]s.

use serde::Serialize;
use stride_ad::Scalar;
use stride_model::Model;
use stride_multibody::SphereGeometry;

/// A model quantity that a static parameter sets.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum ParameterTarget {
    /// Component `axis` (0 = x, 1 = y, 2 = z) of the centre of contact sphere `sphere`
    /// (model index) in its body frame [m], set to `sign` × the parameter.
    SphereCenter {
        /// Model index of the sphere.
        sphere: usize,
        /// Body-frame axis (0, 1 or 2).
        axis: usize,
        /// +1 or −1 (−1 mirrors a right-foot z onto the left foot).
        sign: f64,
    },
    /// Radius of contact sphere `sphere` (model index) [m].
    SphereRadius {
        /// Model index of the sphere.
        sphere: usize,
    },
}

/// One static parameter: its name, bounds and initial value in physical units, and the
/// model quantities it sets.
#[derive(Clone, Debug, PartialEq)]
pub struct StaticParameter {
    /// Name (e.g. `sphere_1_x`), used in outputs.
    pub name: String,
    /// Lower bound (physical units).
    pub lower: f64,
    /// Upper bound (physical units).
    pub upper: f64,
    /// Initial guess (physical units).
    pub initial: f64,
    /// What the parameter sets in the model.
    pub targets: Vec<ParameterTarget>,
}

impl StaticParameter {
    /// The NLP variable of the physical value `p`: p̃ = p v + r with v = 1/(ub − lb) and
    /// r = 0.5 − ub/(ub − lb), so that [lb, ub] maps to [−0.5, 0.5].
    pub fn scale(&self, p: f64) -> f64 {
        let range = self.upper - self.lower;
        p / range + 0.5 - self.upper / range
    }

    /// The physical value of the NLP variable `scaled` (inverse of [`Self::scale`]).
    pub fn unscale<T: Scalar>(&self, scaled: T) -> T {
        let range = self.upper - self.lower;
        (scaled - (0.5 - self.upper / range)) * range
    }
}

/// A value closer to a bound than this fraction of the bounds' range is reported at that
/// bound (an interior-point solution stops just inside an active bound).
pub const AT_BOUND_FRACTION: f64 = 0.01;

/// A solved static parameter as the result files report it (physical units).
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct ParameterValue {
    /// Parameter name.
    pub name: String,
    /// Value at the solution.
    pub value: f64,
    /// Lower bound.
    pub lower: f64,
    /// Upper bound.
    pub upper: f64,
    /// Initial value (the generic one).
    pub initial: f64,
    /// `"lower"` or `"upper"` when the value is within [`AT_BOUND_FRACTION`] of the range
    /// of that bound, else none.
    pub at_bound: Option<&'static str>,
}

impl StaticParameter {
    /// The report of the physical value `value` of this parameter.
    pub fn report(&self, value: f64) -> ParameterValue {
        let tol = AT_BOUND_FRACTION * (self.upper - self.lower);
        let at_bound = if value - self.lower <= tol {
            Some("lower")
        } else if self.upper - value <= tol {
            Some("upper")
        } else {
            None
        };
        ParameterValue {
            name: self.name.clone(),
            value,
            lower: self.lower,
            upper: self.upper,
            initial: self.initial,
            at_bound,
        }
    }
}

/// Why a list of static parameters does not fit a model.
#[derive(Debug, thiserror::Error)]
pub enum StaticError {
    /// Bounds empty, or the initial value outside them.
    #[error("static parameter `{name}`: bounds [{lower}, {upper}] with initial value {initial}: need lower < upper and the initial value inside")]
    Bounds {
        /// Parameter name.
        name: String,
        /// Lower bound.
        lower: f64,
        /// Upper bound.
        upper: f64,
        /// Initial value.
        initial: f64,
    },
    /// A target naming a sphere or axis the model does not have.
    #[error("static parameter `{name}`: targets sphere {sphere} (axis {axis}) but the model has {count} contact spheres")]
    Target {
        /// Parameter name.
        name: String,
        /// Sphere index.
        sphere: usize,
        /// Axis.
        axis: usize,
        /// Spheres in the model.
        count: usize,
    },
}

/// The static parameters of a problem (empty for the usual prediction).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct StaticParameters {
    /// The parameters, in NLP order.
    pub list: Vec<StaticParameter>,
}

impl StaticParameters {
    /// Number of parameters.
    pub fn len(&self) -> usize {
        self.list.len()
    }

    /// Whether there are none.
    pub fn is_empty(&self) -> bool {
        self.list.is_empty()
    }

    /// Checks bounds, initial values and targets against `model`.
    pub fn check(&self, model: &Model) -> Result<(), StaticError> {
        let count = model.contacts.len();
        for p in &self.list {
            if !(p.lower < p.upper && (p.lower..=p.upper).contains(&p.initial)) {
                return Err(StaticError::Bounds {
                    name: p.name.clone(),
                    lower: p.lower,
                    upper: p.upper,
                    initial: p.initial,
                });
            }
            for t in &p.targets {
                let (sphere, axis) = match *t {
                    ParameterTarget::SphereCenter { sphere, axis, .. } => (sphere, axis),
                    ParameterTarget::SphereRadius { sphere } => (sphere, 0),
                };
                if sphere >= count || axis > 2 {
                    return Err(StaticError::Target {
                        name: p.name.clone(),
                        sphere,
                        axis,
                        count,
                    });
                }
            }
        }
        Ok(())
    }

    /// The scaled initial values (NLP variables).
    pub fn scaled_initial(&self) -> Vec<f64> {
        self.list.iter().map(|p| p.scale(p.initial)).collect()
    }

    /// The physical values of the NLP variables `scaled`.
    pub fn values(&self, scaled: &[f64]) -> Vec<f64> {
        self.list
            .iter()
            .zip(scaled)
            .map(|(p, &s)| p.unscale(s))
            .collect()
    }

    /// The reports of the parameters whose NLP variables are `scaled`.
    pub fn reports(&self, scaled: &[f64]) -> Vec<ParameterValue> {
        let values = self.values(scaled);
        self.list
            .iter()
            .zip(values)
            .map(|(p, v)| p.report(v))
            .collect()
    }

    /// Whether any parameter sets contact-sphere geometry.
    pub fn sets_contact(&self) -> bool {
        !self.list.iter().all(|p| p.targets.is_empty())
    }

    /// The contact-sphere geometry of `model` with the quantities set by the parameters
    /// whose NLP variables are `scaled` (one per parameter).
    pub fn sphere_geometry<T: Scalar>(
        &self,
        model: &Model,
        scaled: &[T],
    ) -> Vec<SphereGeometry<T>> {
        let mut g = SphereGeometry::of_model(model);
        for (p, &s) in self.list.iter().zip(scaled) {
            let value = p.unscale(s);
            for t in &p.targets {
                match *t {
                    ParameterTarget::SphereCenter { sphere, axis, sign } => {
                        g[sphere].location[axis] = value * sign
                    }
                    ParameterTarget::SphereRadius { sphere } => g[sphere].radius = value,
                }
            }
        }
        g
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A radius of 32 mm ± 50 % (the contact calibration's).
    fn radius() -> StaticParameter {
        StaticParameter {
            name: "r".into(),
            lower: 0.016,
            upper: 0.048,
            initial: 0.032,
            targets: vec![],
        }
    }

    #[test]
    fn scaling_maps_the_bounds_to_plus_minus_one_half_and_back() {
        let p = radius();
        assert!((p.scale(0.016) + 0.5).abs() < 1e-14);
        assert!((p.scale(0.048) - 0.5).abs() < 1e-14);
        assert!(p.scale(0.032).abs() < 1e-14);
        for v in [0.02, 0.031, 0.047] {
            assert!((p.unscale(p.scale(v)) - v).abs() < 1e-15);
        }
    }

    #[test]
    fn a_value_within_one_percent_of_the_range_of_a_bound_is_reported_at_it() {
        let p = radius();
        // range 0.032 m: 1 % is 0.32 mm
        assert_eq!(p.report(0.0163).at_bound, Some("lower"));
        assert_eq!(p.report(0.0164).at_bound, None);
        assert_eq!(p.report(0.0477).at_bound, Some("upper"));
        assert_eq!(p.report(0.0476).at_bound, None);
        assert_eq!(p.report(0.03).initial, 0.032);
    }
}
