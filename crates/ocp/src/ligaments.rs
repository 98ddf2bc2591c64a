//! Ligament moments of the torque balances (PREDSIM.md §3.7): each ligament's length from
//! its fitted polynomial over the coordinates it spans, its tension from PredSim's force
//! law, and the generalised forces `M = −J_lᵀ F = r F` (moment arm `r = −∂l/∂q`) on
//! every spanned coordinate. Not part of the cost.

use crate::problem::ProblemError;
use stride_ad::Scalar;
use stride_model::Model;
use stride_muscle::ligament::LigamentLaw;
use stride_muscle::{MusclePaths, PathPolynomialEval, PathWorkspace};

/// The ligaments of a model, ready for the node function.
#[derive(Clone, Debug)]
pub struct Ligaments {
    /// Length polynomials, indexed by ligament.
    paths: MusclePaths,
    /// Per ligament: force law, cross-section [mm²] and slack length [m].
    laws: Vec<(LigamentLaw, f64, f64)>,
    /// Per problem coordinate: (ligament, flat moment-arm index) of the ligaments spanning it.
    terms: Vec<Vec<(usize, usize)>>,
}

/// Per-thread scratch of [`Ligaments`] for scalar `T`.
#[derive(Clone, Debug)]
pub struct LigamentWorkspace<T: Scalar> {
    paths: PathWorkspace<T>,
    /// Lengths [m].
    pub length: Vec<T>,
    speed: Vec<T>,
    /// Moment arms `−∂l/∂q` [m], flat (ligament j's block in polynomial coordinate order).
    pub arms: Vec<T>,
    /// Tensions [N].
    pub force: Vec<T>,
}

impl Ligaments {
    /// The ligaments of `model` (each needs its `path_polynomial`, from the geometry
    /// file); `coord_model[i]` is the model coordinate of problem coordinate `i`.
    pub fn new(model: &Model, coord_model: &[usize]) -> Result<Self, ProblemError> {
        let mut polys = Vec::with_capacity(model.ligaments.len());
        for (j, l) in model.ligaments.iter().enumerate() {
            let p = l.path_polynomial.as_ref().ok_or_else(|| {
                ProblemError::Model(format!(
                    "ligament {} has no length polynomial: fit the model's geometry again \
                     (`stride model fit MODEL.osim --out FILE`) so that the geometry file \
                     carries its ligaments",
                    l.name
                ))
            })?;
            polys.push(
                PathPolynomialEval::new(j, p).map_err(|e| ProblemError::Model(e.to_string()))?,
            );
        }
        let paths = MusclePaths::new(polys, model.coordinates.len())
            .map_err(|e| ProblemError::Model(e.to_string()))?;
        let laws = model
            .ligaments
            .iter()
            .map(|l| {
                let law = LigamentLaw::for_name(&l.name);
                (law, l.pcsa_force, l.resting_length)
            })
            .collect();
        let terms = coord_model
            .iter()
            .map(|&c| {
                (0..paths.n_muscles())
                    .filter_map(|j| {
                        let k = paths
                            .polynomial(j)
                            .coordinates()
                            .iter()
                            .position(|&x| x == c)?;
                        Some((j, paths.moment_arm_range(j).start + k))
                    })
                    .collect()
            })
            .collect();
        Ok(Self { paths, laws, terms })
    }

    /// A workspace for scalar `T`.
    pub fn workspace<T: Scalar>(&self) -> LigamentWorkspace<T> {
        let n = self.laws.len();
        LigamentWorkspace {
            paths: PathWorkspace::for_paths(&self.paths),
            length: vec![T::zero(); n],
            speed: vec![T::zero(); n],
            arms: vec![T::zero(); self.paths.n_moment_arms()],
            force: vec![T::zero(); n],
        }
    }

    /// Lengths, moment arms and tensions of every ligament at coordinates `q` (model order).
    pub fn evaluate<T: Scalar>(&self, q: &[T], ws: &mut LigamentWorkspace<T>) {
        if self.laws.is_empty() {
            return;
        }
        let LigamentWorkspace {
            paths,
            length,
            speed,
            arms,
            force,
        } = ws;
        self.paths
            .evaluate(q, q, paths, length, speed, arms)
            .expect("ligament workspace sized at construction");
        for (j, &(law, area, slack)) in self.laws.iter().enumerate() {
            force[j] = law.force(area, slack, length[j]);
        }
    }

    /// Generalised force of the ligaments on problem coordinate `i` [N m or N] after
    /// [`Ligaments::evaluate`]; `None` when no ligament spans it.
    pub fn moment<T: Scalar>(&self, i: usize, ws: &LigamentWorkspace<T>) -> Option<T> {
        let terms = &self.terms[i];
        let (&(j0, k0), rest) = terms.split_first()?;
        Some(rest.iter().fold(ws.arms[k0] * ws.force[j0], |m, &(j, k)| {
            m + ws.arms[k] * ws.force[j]
        }))
    }
}
