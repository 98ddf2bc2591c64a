//! Muscle–tendon length, moment arms and lengthening speed from OpenSim path points.
//!
//! The length is the sum of the straight segments between consecutive *active* path
//! points. Whether a `Conditional` point is active is a discrete choice made from the
//! primal value of its coordinate, and spline intervals of `Moving` points likewise: the
//! geometric length is generic over the scalar (so it can run on dual numbers) but is
//! **not meant for recorded tapes**; the optimal control problem uses the fitted
//! polynomials instead.

use crate::error::GeometryError;
use crate::function::PreparedFunction;
use crate::kinematics::{BodyPoses, Kinematics, Vec3};
use stride_ad::Scalar;
use stride_model::{CoordId, Model, PathPointKind};

/// Central finite-difference step used for moment arms [rad or m]: the truncation error
/// (≈ h² l‴/6 ≈ 1e-13 m) and the round-off (≈ 1e-16 · l / h ≈ 1e-10 m) are both far
/// below the 3 mm accuracy target.
pub const DEFAULT_FD_STEP: f64 = 1e-6;

/// How the location of a prepared path point is obtained.
#[derive(Clone, Debug)]
enum PointLocation {
    Fixed,
    Conditional {
        coordinate: CoordId,
        range: [f64; 2],
    },
    Moving(Box<[Option<(CoordId, PreparedFunction)>; 3]>),
}

/// A path point ready for evaluation.
#[derive(Clone, Debug)]
struct PreparedPoint {
    body: usize,
    location: [f64; 3],
    kind: PointLocation,
}

/// The path points of every muscle of a model, with spline coefficients precomputed.
#[derive(Clone, Debug)]
pub struct MusclePaths {
    paths: Vec<Vec<PreparedPoint>>,
}

impl MusclePaths {
    /// Prepares the paths of all muscles of `model`; errors on a point attached to a
    /// missing body or driven by a missing coordinate.
    pub fn new(model: &Model) -> Result<Self, GeometryError> {
        let nb = model.bodies.len();
        let nc = model.coordinates.len();
        let mut paths = Vec::with_capacity(model.muscles.len());
        for m in &model.muscles {
            let mut pts = Vec::with_capacity(m.path.len());
            for p in &m.path {
                let bad = |what: &str| GeometryError::Model {
                    what: format!("muscle {} path point {}: {what}", m.name, p.name),
                };
                if p.body >= nb {
                    return Err(bad("body index out of range"));
                }
                let kind = match &p.kind {
                    PathPointKind::Fixed => PointLocation::Fixed,
                    PathPointKind::Conditional { coordinate, range } => {
                        if *coordinate >= nc {
                            return Err(bad("coordinate index out of range"));
                        }
                        PointLocation::Conditional {
                            coordinate: *coordinate,
                            range: *range,
                        }
                    }
                    PathPointKind::Moving { components } => {
                        let mut out: [Option<(CoordId, PreparedFunction)>; 3] = [None, None, None];
                        for (o, c) in out.iter_mut().zip(components) {
                            if let Some((ci, f)) = c {
                                if *ci >= nc {
                                    return Err(bad("coordinate index out of range"));
                                }
                                *o = Some((*ci, PreparedFunction::new(f)));
                            }
                        }
                        PointLocation::Moving(Box::new(out))
                    }
                };
                pts.push(PreparedPoint {
                    body: p.body,
                    location: p.location,
                    kind,
                });
            }
            paths.push(pts);
        }
        Ok(Self { paths })
    }

    /// Number of muscles.
    pub fn len(&self) -> usize {
        self.paths.len()
    }

    /// True when the model has no muscle.
    pub fn is_empty(&self) -> bool {
        self.paths.is_empty()
    }

    /// Number of path points of muscle `m` (active or not).
    pub fn n_points(&self, m: usize) -> usize {
        self.paths[m].len()
    }

    /// Calls `visit` with the position in ground [m] of each *active* path point of muscle
    /// `m`, origin to insertion, at coordinates `q` whose body poses are `poses` (computed
    /// by [`Kinematics::forward`] for the same `q`).
    pub fn for_each_active_point<T: Scalar>(
        &self,
        m: usize,
        q: &[T],
        poses: &BodyPoses<T>,
        mut visit: impl FnMut(Vec3<T>),
    ) {
        for p in &self.paths[m] {
            let local: Vec3<T> = match &p.kind {
                PointLocation::Fixed => p.location.map(T::cst),
                PointLocation::Conditional { coordinate, range } => {
                    // Discrete activity decision from the primal value (see module doc).
                    let v = q[*coordinate].value();
                    if v < range[0] || v > range[1] {
                        continue;
                    }
                    p.location.map(T::cst)
                }
                PointLocation::Moving(components) => {
                    let mut l = p.location.map(T::cst);
                    for (li, c) in l.iter_mut().zip(components.iter()) {
                        if let Some((ci, f)) = c {
                            *li = f.eval(q[*ci]);
                        }
                    }
                    l
                }
            };
            visit(poses.point_in_ground(p.body, &local));
        }
    }

    /// Muscle–tendon length [m] of muscle `m` at coordinates `q` whose body poses are
    /// `poses` (computed by [`Kinematics::forward`] for the same `q`): the sum of the
    /// straight segments between consecutive active path points.
    pub fn length<T: Scalar>(&self, m: usize, q: &[T], poses: &BodyPoses<T>) -> T {
        let mut total = T::zero();
        let mut prev: Option<Vec3<T>> = None;
        self.for_each_active_point(m, q, poses, |g| {
            if let Some(a) = prev {
                let d = [g[0] - a[0], g[1] - a[1], g[2] - a[2]];
                total += (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt();
            }
            prev = Some(g);
        });
        total
    }
}

/// Path-point geometry of a whole model on `f64`, with preallocated workspaces.
#[derive(Clone, Debug)]
pub struct PathGeometry {
    /// Forward kinematics of the skeleton.
    pub kinematics: Kinematics,
    /// Prepared muscle paths.
    pub paths: MusclePaths,
    /// Finite-difference step for moment arms [rad or m].
    pub fd_step: f64,
    poses: BodyPoses<f64>,
    q_work: Vec<f64>,
    plus: Vec<f64>,
    minus: Vec<f64>,
}

impl PathGeometry {
    /// Prepares the geometry of `model` with the default finite-difference step.
    pub fn new(model: &Model) -> Result<Self, GeometryError> {
        let kinematics = Kinematics::new(model)?;
        let paths = MusclePaths::new(model)?;
        let n = model.muscles.len();
        Ok(Self {
            poses: BodyPoses::new(kinematics.n_bodies()),
            q_work: vec![0.0; kinematics.n_coords()],
            kinematics,
            paths,
            fd_step: DEFAULT_FD_STEP,
            plus: vec![0.0; n],
            minus: vec![0.0; n],
        })
    }

    /// Lengths [m] of all muscles at `q` (model coordinate order) into `out`.
    pub fn lengths(&mut self, q: &[f64], out: &mut [f64]) {
        self.kinematics.forward(q, &mut self.poses);
        for (m, o) in out.iter_mut().enumerate() {
            *o = self.paths.length(m, q, &self.poses);
        }
    }

    /// Moment arms `r = −∂l/∂q_c` [m] of all muscles about coordinate `c` at `q`, by
    /// central finite differences with step [`PathGeometry::fd_step`], into `out`.
    pub fn moment_arms(&mut self, q: &[f64], c: CoordId, out: &mut [f64]) {
        let h = self.fd_step;
        self.q_work.copy_from_slice(q);
        self.q_work[c] = q[c] + h;
        self.kinematics.forward(&self.q_work, &mut self.poses);
        for m in 0..self.plus.len() {
            self.plus[m] = self.paths.length(m, &self.q_work, &self.poses);
        }
        self.q_work[c] = q[c] - h;
        self.kinematics.forward(&self.q_work, &mut self.poses);
        for m in 0..self.minus.len() {
            self.minus[m] = self.paths.length(m, &self.q_work, &self.poses);
        }
        for (m, o) in out.iter_mut().enumerate() {
            *o = -(self.plus[m] - self.minus[m]) / (2.0 * h);
        }
    }
}

/// Lengthening speed `v = Σ_i (∂l/∂q_i) q̇_i = −Σ_i r_i q̇_i` [m s⁻¹] from moment arms
/// `r` [m] and coordinate speeds `qdot` [rad s⁻¹ or m s⁻¹] of the same coordinates.
pub fn lengthening_speed(moment_arms: &[f64], qdot: &[f64]) -> f64 {
    -moment_arms
        .iter()
        .zip(qdot)
        .map(|(r, v)| r * v)
        .sum::<f64>()
}
