//! Static parameters: decision variables that are constant over time (FORMULATION 12.6),
//! appended to the NLP vector after the layout's variables, each with bounds and a linear
//! scaling to [−0.5, 0.5], and read by the node function as extra inputs placed after its
//! variable inputs. What a parameter sets in the model is a list of [`ParameterTarget`]s.

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

    #[test]
    fn scaling_maps_the_bounds_to_plus_minus_one_half_and_back() {
        let p = StaticParameter {
            name: "r".into(),
            lower: 0.016,
            upper: 0.048,
            initial: 0.032,
            targets: vec![],
        };
        assert!((p.scale(0.016) + 0.5).abs() < 1e-14);
        assert!((p.scale(0.048) - 0.5).abs() < 1e-14);
        assert!(p.scale(0.032).abs() < 1e-14);
        for v in [0.02, 0.031, 0.047] {
            assert!((p.unscale(p.scale(v)) - v).abs() < 1e-15);
        }
    }
}
