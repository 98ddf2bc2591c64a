//! Muscle–tendon length, moment arms and lengthening speed from OpenSim path points.
//!
//! The length is the sum of the straight segments between consecutive *active* path
//! points, with the segments that meet a wrap object replaced by the path over its
//! surface ([`crate::wrap`]). Whether a `Conditional` point is active is a discrete choice made from the
//! primal value of its coordinate, spline intervals of `Moving` points and whether and
//! where a segment wraps likewise: the
//! geometric length is generic over the scalar (so it can run on dual numbers) but is
//! **not meant for recorded tapes**; the optimal control problem uses the fitted
//! polynomials instead.

use crate::couplers::Couplers;
use crate::error::GeometryError;
use crate::function::PreparedFunction;
use crate::kinematics::{BodyPoses, Kinematics, Vec3};
use crate::wrap::{wrapped_length, Node, PreparedPathWrap, PreparedWrapObject};
use crate::wrap_ellipsoid::WrapMethod;
use stride_ad::{Dual, Scalar};
use stride_model::{CoordId, Model, PathPoint, PathPointKind, PathWrap};

/// Central finite-difference step of the checking moment arms [rad or m]: the truncation error
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

/// The path points and wraps of every muscle (or every ligament) of a model, with spline
/// coefficients and wrap frames precomputed.
#[derive(Clone, Debug)]
pub struct MusclePaths {
    paths: Vec<Vec<PreparedPoint>>,
    wraps: Vec<Vec<PreparedPathWrap>>,
    objects: Vec<PreparedWrapObject>,
}

impl MusclePaths {
    /// Prepares the paths of all muscles of `model`; errors on a point attached to a
    /// missing body or driven by a missing coordinate, and on a wrap over a missing wrap
    /// object.
    pub fn new(model: &Model) -> Result<Self, GeometryError> {
        let items = model
            .muscles
            .iter()
            .map(|m| (format!("muscle {}", m.name), &m.path[..], &m.wraps[..]));
        Self::prepare(model, items)
    }

    /// Prepares the paths of all ligaments of `model` (index = ligament index), with the
    /// same checks as [`MusclePaths::new`]: a ligament's length is evaluated exactly as a
    /// muscle's.
    pub fn ligaments(model: &Model) -> Result<Self, GeometryError> {
        let items = model
            .ligaments
            .iter()
            .map(|l| (format!("ligament {}", l.name), &l.path[..], &l.wraps[..]));
        Self::prepare(model, items)
    }

    /// Prepares the named paths `items` (points, wraps) of `model`.
    fn prepare<'a>(
        model: &Model,
        items: impl Iterator<Item = (String, &'a [PathPoint], &'a [PathWrap])>,
    ) -> Result<Self, GeometryError> {
        let objects = model
            .wrap_objects
            .iter()
            .map(|o| PreparedWrapObject::new(o, model.bodies.len()))
            .collect::<Result<Vec<_>, _>>()?;
        let (mut paths, mut wraps) = (Vec::new(), Vec::new());
        for (name, points, path_wraps) in items {
            let pts = points
                .iter()
                .map(|p| prepare_point(model, &name, p))
                .collect::<Result<Vec<_>, _>>()?;
            paths.push(pts);
            let ws = path_wraps
                .iter()
                .map(|w| prepare_wrap(model, &name, w))
                .collect::<Result<Vec<_>, _>>()?;
            wraps.push(ws);
        }
        Ok(Self {
            paths,
            wraps,
            objects,
        })
    }

    /// Whether the length of path `m` can change with coordinate `c`, from the structure
    /// alone (`moved`, `n_joints`: [`Kinematics::moved_by`] of `c`): false when no body
    /// carrying a point or a wrap object of the path moves, or all of them move as one
    /// rigid body, and no moving point reads `c`. A `false` means the moment arm is
    /// exactly zero.
    pub fn depends_on(&self, m: usize, c: CoordId, moved: &[bool], n_joints: usize) -> bool {
        let points = &self.paths[m];
        let reads = points.iter().any(|p| match &p.kind {
            PointLocation::Moving(components) => {
                components.iter().flatten().any(|(ci, _)| *ci == c)
            }
            _ => false,
        });
        let bodies = points
            .iter()
            .map(|p| p.body)
            .chain(self.wraps[m].iter().map(|w| self.objects[w.object].body()));
        let (mut any, mut all) = (false, true);
        for b in bodies {
            any |= moved[b];
            all &= moved[b];
        }
        reads || (any && !(all && n_joints == 1))
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
    /// by [`Kinematics::forward`] for the same `q`). Wrapping points are not visited.
    pub fn for_each_active_point<T: Scalar>(
        &self,
        m: usize,
        q: &[T],
        poses: &BodyPoses<T>,
        mut visit: impl FnMut(Vec3<T>),
    ) {
        for p in &self.paths[m] {
            if let Some(g) = point_in_ground(p, q, poses) {
                visit(g);
            }
        }
    }

    /// Muscle–tendon length [m] of muscle `m` at coordinates `q` whose body poses are
    /// `poses` (computed by [`Kinematics::forward`] for the same `q`): straight segments
    /// between the active path points, wrapped over the muscle's wrap objects as OpenSim
    /// does.
    pub fn length<T: Scalar>(&self, m: usize, q: &[T], poses: &BodyPoses<T>) -> T {
        if !self.wraps[m].is_empty() {
            let mut points = Vec::with_capacity(self.paths[m].len());
            let mut active = Vec::with_capacity(self.paths[m].len());
            for (i, p) in self.paths[m].iter().enumerate() {
                let g = point_in_ground(p, q, poses);
                active.push(g.is_some());
                if let Some(g) = g {
                    points.push(Node {
                        at: g,
                        body: p.body,
                        index: i,
                    });
                }
            }
            return wrapped_length(&self.objects, &self.wraps[m], &active, &points, poses);
        }
        let mut total = T::zero();
        let mut prev: Option<Vec3<T>> = None;
        for p in &self.paths[m] {
            let Some(g) = point_in_ground(p, q, poses) else {
                continue;
            };
            if let Some(a) = prev {
                total += distance(&a, &g);
            }
            prev = Some(g);
        }
        total
    }
}

/// Checks and prepares one wrap of the path `owner` ("muscle NAME", "ligament NAME").
fn prepare_wrap(
    model: &Model,
    owner: &str,
    w: &PathWrap,
) -> Result<PreparedPathWrap, GeometryError> {
    let o = model
        .wrap_objects
        .get(w.object)
        .ok_or_else(|| GeometryError::Model {
            what: format!("{owner}: wrap object index {} out of range", w.object),
        })?;
    let method = WrapMethod::parse(&w.method).ok_or_else(|| GeometryError::Model {
        what: format!(
            "{owner} wrap over `{}`: method `{}` is not one of hybrid, midpoint, axial",
            o.name, w.method
        ),
    })?;
    Ok(PreparedPathWrap {
        object: w.object,
        range: w.range,
        method,
    })
}

/// Checks and prepares one path point of the path `owner` ("muscle NAME", …).
fn prepare_point(
    model: &Model,
    owner: &str,
    p: &PathPoint,
) -> Result<PreparedPoint, GeometryError> {
    let nc = model.coordinates.len();
    let bad = |what: &str| GeometryError::Model {
        what: format!("{owner} path point {}: {what}", p.name),
    };
    if p.body >= model.bodies.len() {
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
    Ok(PreparedPoint {
        body: p.body,
        location: p.location,
        kind,
    })
}

/// Position in ground [m] of a path point, or `None` when it is inactive (a conditional
/// point outside its range; decided on the primal value, see the module doc).
fn point_in_ground<T: Scalar>(p: &PreparedPoint, q: &[T], poses: &BodyPoses<T>) -> Option<Vec3<T>> {
    let local: Vec3<T> = match &p.kind {
        PointLocation::Fixed => p.location.map(T::cst),
        PointLocation::Conditional { coordinate, range } => {
            let v = q[*coordinate].value();
            if v < range[0] || v > range[1] {
                return None;
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
    Some(poses.point_in_ground(p.body, &local))
}

/// Euclidean distance [m] between two points.
pub(crate) fn distance<T: Scalar>(a: &Vec3<T>, b: &Vec3<T>) -> T {
    let d = [b[0] - a[0], b[1] - a[1], b[2] - a[2]];
    (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt()
}

/// Path geometry of a whole model on `f64`, with preallocated workspaces.
#[derive(Clone, Debug)]
pub struct PathGeometry {
    /// Forward kinematics of the skeleton.
    pub kinematics: Kinematics,
    /// Prepared muscle paths.
    pub paths: MusclePaths,
    /// Finite-difference step of [`PathGeometry::moment_arms_fd`] [rad or m].
    pub fd_step: f64,
    poses: BodyPoses<f64>,
    dual_poses: BodyPoses<Dual>,
    /// Coupled coordinates, computed from their independent coordinates at every pose.
    pub couplers: Couplers,
    /// `depends[c][m]`: [`MusclePaths::depends_on`] of every coordinate and muscle (an
    /// independent coordinate also through its coupled ones; a coupled one never).
    depends: Vec<Vec<bool>>,
    q_work: Vec<f64>,
    q_dual: Vec<Dual>,
    plus: Vec<f64>,
    minus: Vec<f64>,
}

impl PathGeometry {
    /// Prepares the muscle geometry of `model` with the default finite-difference step.
    pub fn new(model: &Model) -> Result<Self, GeometryError> {
        Self::with_paths(model, MusclePaths::new(model)?)
    }

    /// Prepares the ligament geometry of `model` (path index = ligament index), as
    /// [`PathGeometry::new`] does for the muscles.
    pub fn ligaments(model: &Model) -> Result<Self, GeometryError> {
        Self::with_paths(model, MusclePaths::ligaments(model)?)
    }

    /// The geometry of the prepared `paths` of `model`.
    fn with_paths(model: &Model, paths: MusclePaths) -> Result<Self, GeometryError> {
        let kinematics = Kinematics::new(model)?;
        let couplers = Couplers::new(model)?;
        let n = paths.len();
        let mut depends: Vec<Vec<bool>> = (0..kinematics.n_coords())
            .map(|c| {
                let (moved, n_joints) = kinematics.moved_by(c);
                (0..n)
                    .map(|m| paths.depends_on(m, c, &moved, n_joints))
                    .collect()
            })
            .collect();
        for (d, i) in couplers.pairs() {
            let through = std::mem::replace(&mut depends[d], vec![false; n]);
            for (a, b) in depends[i].iter_mut().zip(through) {
                *a |= b;
            }
        }
        Ok(Self {
            couplers,
            depends,
            poses: BodyPoses::new(kinematics.n_bodies()),
            dual_poses: BodyPoses::new(kinematics.n_bodies()),
            q_work: vec![0.0; kinematics.n_coords()],
            q_dual: vec![Dual::constant(0.0); kinematics.n_coords()],
            kinematics,
            paths,
            fd_step: DEFAULT_FD_STEP,
            plus: vec![0.0; n],
            minus: vec![0.0; n],
        })
    }

    /// Whether the length of muscle `m` can depend on coordinate `c` (see
    /// [`MusclePaths::depends_on`]; `false`: its moment arm about `c` is exactly zero).
    pub fn depends(&self, m: usize, c: CoordId) -> bool {
        self.depends
            .get(c)
            .and_then(|d| d.get(m))
            .copied()
            .unwrap_or(false)
    }

    /// Lengths [m] of all muscles at `q` (model coordinate order; the values of coupled
    /// coordinates are ignored and computed from their independent ones) into `out`.
    pub fn lengths(&mut self, q: &[f64], out: &mut [f64]) {
        self.q_work.copy_from_slice(q);
        self.couplers.apply(&mut self.q_work);
        self.kinematics.forward(&self.q_work, &mut self.poses);
        for (m, o) in out.iter_mut().enumerate() {
            *o = self.paths.length(m, &self.q_work, &self.poses);
        }
    }

    /// Moment arms `r = −∂l/∂q_c` [m] of all muscles about coordinate `c` at `q`, exact
    /// (forward-mode dual numbers along `q_c`), into `out`. Muscles whose length cannot
    /// depend on `q_c` ([`MusclePaths::depends_on`]) get an exact 0 without evaluation.
    /// On wrapped paths the tangent points are held fixed on their wrap objects, as in
    /// OpenSim's moment arms; where OpenSim's wrapped length is not the shortest path
    /// (ellipsoids, cylinders, paths with several wraps) these differ from the derivative
    /// of the length. About an independent coordinate the coupled coordinates move with
    /// it (chain rule, as OpenSim's moment arms); about a coupled coordinate all are 0.
    pub fn moment_arms(&mut self, q: &[f64], c: CoordId, out: &mut [f64]) {
        let depends = &self.depends[c];
        if !depends.iter().any(|d| *d) {
            out.fill(0.0);
            return;
        }
        for (i, (d, v)) in self.q_dual.iter_mut().zip(q).enumerate() {
            *d = Dual::new(*v, if i == c { 1.0 } else { 0.0 });
        }
        self.couplers.apply(&mut self.q_dual);
        self.kinematics.forward(&self.q_dual, &mut self.dual_poses);
        for (m, o) in out.iter_mut().enumerate() {
            *o = if depends[m] {
                -self.paths.length(m, &self.q_dual, &self.dual_poses).eps
            } else {
                0.0
            };
        }
    }

    /// `−∂l/∂q_c` by central finite differences with step [`PathGeometry::fd_step`]: an
    /// independent check of [`PathGeometry::moment_arms`] on paths without wrapping (see
    /// there for wrapped paths).
    pub fn moment_arms_fd(&mut self, q: &[f64], c: CoordId, out: &mut [f64]) {
        let h = self.fd_step;
        self.q_work.copy_from_slice(q);
        self.q_work[c] = q[c] + h;
        self.couplers.apply(&mut self.q_work);
        self.kinematics.forward(&self.q_work, &mut self.poses);
        for m in 0..self.plus.len() {
            self.plus[m] = self.paths.length(m, &self.q_work, &self.poses);
        }
        self.q_work[c] = q[c] - h;
        self.couplers.apply(&mut self.q_work);
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
