//! Coupled coordinates in the path geometry (OpenSim `CoordinateCouplerConstraint`): a
//! dependent coordinate is computed from its independent coordinate, `q_d = f(q_i)`,
//! before the skeleton is posed, as OpenSim's assembly does. On dual numbers the chain
//! rule follows: a moment arm about `q_i` includes `f'(q_i)` times the path's
//! derivative along `q_d`, as OpenSim's `computeMomentArm` does; a dependent coordinate
//! is not a free variable and has no moment arm of its own.

use crate::error::GeometryError;
use stride_ad::Scalar;
use stride_model::function::CompiledFunction;
use stride_model::{CoordId, Model};

/// One coupler prepared for evaluation.
#[derive(Clone, Debug)]
struct Coupler {
    dependent: CoordId,
    independent: CoordId,
    function: CompiledFunction,
}

/// The couplers of a model, prepared for evaluation.
#[derive(Clone, Debug, Default)]
pub struct Couplers {
    list: Vec<Coupler>,
}

impl Couplers {
    /// Prepares the couplers of `model`; an error names a coupler whose coordinates are
    /// missing or whose independent coordinate is itself coupled.
    pub fn new(model: &Model) -> Result<Self, GeometryError> {
        let nc = model.coordinates.len();
        let mut list = Vec::with_capacity(model.couplers.len());
        for c in &model.couplers {
            let bad = |why: &str| GeometryError::Model {
                what: format!("coordinate coupler `{}`: {why}", c.name),
            };
            if c.dependent >= nc || c.independent >= nc || c.dependent == c.independent {
                return Err(bad("its coordinates are not two of the model's"));
            }
            if model.couplers.iter().any(|o| o.dependent == c.independent) {
                return Err(bad("its independent coordinate is itself coupled"));
            }
            let function = c
                .function
                .compile()
                .map_err(|e| bad(&format!("function: {e}")))?;
            list.push(Coupler {
                dependent: c.dependent,
                independent: c.independent,
                function,
            });
        }
        Ok(Self { list })
    }

    /// True when the model has no coupled coordinate.
    pub fn is_empty(&self) -> bool {
        self.list.is_empty()
    }

    /// The independent coordinate that coordinate `c` follows, if `c` is coupled.
    pub fn independent_of(&self, c: CoordId) -> Option<CoordId> {
        self.list
            .iter()
            .find(|k| k.dependent == c)
            .map(|k| k.independent)
    }

    /// `(dependent, independent)` of every coupler.
    pub fn pairs(&self) -> impl Iterator<Item = (CoordId, CoordId)> + '_ {
        self.list.iter().map(|k| (k.dependent, k.independent))
    }

    /// Overwrites every dependent coordinate of `q` [rad or m] with its value from the
    /// independent one.
    pub fn apply<T: Scalar>(&self, q: &mut [T]) {
        for k in &self.list {
            q[k.dependent] = k.function.eval(q[k.independent])[0];
        }
    }
}
