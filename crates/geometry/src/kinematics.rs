//! Positions and orientations of all bodies in ground for given coordinates, generic over
//! the scalar.
//!
//! Local stand-in for the `stride_multibody` forward kinematics (not available when this
//! crate was written): OpenSim `CustomJoint` semantics of FORMULATION 1.2 — three
//! successive body-fixed rotations about axes given in the parent joint frame F, then
//! translations along axes fixed in F; joint frames placed by `Offset`s (body-fixed
//! X–Y–Z Euler angles).

use crate::error::GeometryError;
use crate::function::PreparedFunction;
use stride_ad::Scalar;
use stride_model::{CoordId, JointKind, Model, Offset};

/// A 3×3 rotation matrix, row-major (`m[row][col]`).
pub type Mat3<T> = [[T; 3]; 3];
/// A 3-vector.
pub type Vec3<T> = [T; 3];

/// One transform axis with its function precomputed.
#[derive(Clone, Debug)]
struct PreparedAxis {
    axis: [f64; 3],
    coordinate: Option<CoordId>,
    function: PreparedFunction,
}

/// One joint ready for evaluation.
#[derive(Clone, Debug)]
struct PreparedJoint {
    parent: usize,
    child: usize,
    frame_in_parent: (Mat3<f64>, [f64; 3]),
    frame_in_child: (Mat3<f64>, [f64; 3]),
    rotations: Vec<PreparedAxis>,
    translations: Vec<PreparedAxis>,
}

/// The joint tree of a model prepared for repeated forward kinematics.
#[derive(Clone, Debug)]
pub struct Kinematics {
    joints: Vec<PreparedJoint>,
    n_bodies: usize,
    n_coords: usize,
}

/// Pose of every body in ground: rotation body→ground and origin position [m].
#[derive(Clone, Debug)]
pub struct BodyPoses<T> {
    /// Rotation matrix of each body (maps body-frame vectors to ground).
    pub rotation: Vec<Mat3<T>>,
    /// Origin of each body in ground [m].
    pub origin: Vec<Vec3<T>>,
}

impl<T: Scalar> BodyPoses<T> {
    /// Workspace for `n_bodies` bodies (ground at identity).
    pub fn new(n_bodies: usize) -> Self {
        Self {
            rotation: vec![identity(); n_bodies],
            origin: vec![[T::zero(); 3]; n_bodies],
        }
    }

    /// Position in ground [m] of a point fixed at `local` [m] in body `body`.
    pub fn point_in_ground(&self, body: usize, local: &Vec3<T>) -> Vec3<T> {
        let r = &self.rotation[body];
        let o = &self.origin[body];
        let mut p = *o;
        for (i, pi) in p.iter_mut().enumerate() {
            *pi += r[i][0] * local[0] + r[i][1] * local[1] + r[i][2] * local[2];
        }
        p
    }
}

impl Kinematics {
    /// Prepares the joints of `model`; errors if a joint refers to a missing body or
    /// coordinate or the joints are not in topological order.
    pub fn new(model: &Model) -> Result<Self, GeometryError> {
        let n_bodies = model.bodies.len();
        let n_coords = model.coordinates.len();
        let mut placed = vec![false; n_bodies];
        if n_bodies > 0 {
            placed[0] = true;
        }
        let mut joints = Vec::with_capacity(model.joints.len());
        for j in &model.joints {
            if j.parent >= n_bodies || j.child >= n_bodies {
                return Err(GeometryError::Model {
                    what: format!("joint {} refers to a body index out of range", j.name),
                });
            }
            if !placed[j.parent] {
                return Err(GeometryError::Model {
                    what: format!(
                        "joint {}: parent body {} is not placed by an earlier joint",
                        j.name, model.bodies[j.parent].name
                    ),
                });
            }
            placed[j.child] = true;
            let prep = |ax: &stride_model::TransformAxis| -> Result<PreparedAxis, GeometryError> {
                if let Some(c) = ax.coordinate {
                    if c >= n_coords {
                        return Err(GeometryError::Model {
                            what: format!("joint {}: coordinate index {c} out of range", j.name),
                        });
                    }
                }
                Ok(PreparedAxis {
                    axis: normalize(ax.axis),
                    coordinate: ax.coordinate,
                    function: PreparedFunction::new(&ax.function),
                })
            };
            let (rotations, translations) = match &j.kind {
                JointKind::Weld => (Vec::new(), Vec::new()),
                JointKind::Custom {
                    rotations,
                    translations,
                } => (
                    rotations.iter().map(prep).collect::<Result<Vec<_>, _>>()?,
                    translations
                        .iter()
                        .map(prep)
                        .collect::<Result<Vec<_>, _>>()?,
                ),
            };
            joints.push(PreparedJoint {
                parent: j.parent,
                child: j.child,
                frame_in_parent: offset_transform(&j.frame_in_parent),
                frame_in_child: offset_transform(&j.frame_in_child),
                rotations,
                translations,
            });
        }
        Ok(Self {
            joints,
            n_bodies,
            n_coords,
        })
    }

    /// Number of bodies (including ground).
    pub fn n_bodies(&self) -> usize {
        self.n_bodies
    }

    /// Number of model coordinates expected in `q`.
    pub fn n_coords(&self) -> usize {
        self.n_coords
    }

    /// Which bodies move (relative to ground) when coordinate `c` changes, and the number
    /// of joints whose transform reads `c`. With one such joint, the moved bodies are
    /// that joint's subtree and move together as one rigid body.
    pub fn moved_by(&self, c: CoordId) -> (Vec<bool>, usize) {
        let mut moved = vec![false; self.n_bodies];
        let mut n_joints = 0;
        for j in &self.joints {
            let reads = j
                .rotations
                .iter()
                .chain(&j.translations)
                .any(|ax| ax.coordinate == Some(c));
            n_joints += usize::from(reads);
            moved[j.child] = reads || moved[j.parent];
        }
        (moved, n_joints)
    }

    /// Computes the pose of every body for coordinates `q` (model order, rad or m).
    pub fn forward<T: Scalar>(&self, q: &[T], poses: &mut BodyPoses<T>) {
        poses.rotation[0] = identity();
        poses.origin[0] = [T::zero(); 3];
        for j in &self.joints {
            let rp = poses.rotation[j.parent];
            let op = poses.origin[j.parent];
            // Joint frame F in ground.
            let rf = mul_mc(&rp, &j.frame_in_parent.0);
            let of = add(&op, &mul_mv_c(&rp, &j.frame_in_parent.1));
            // Rotation of M relative to F: successive body-fixed rotations.
            let mut rfm: Mat3<T> = identity();
            for ax in &j.rotations {
                let angle = ax.function.eval(coord_value(q, ax.coordinate));
                rfm = mul_mm(&rfm, &axis_angle(ax.axis, angle));
            }
            // Translation of M in F, along axes fixed in F.
            let mut t = [T::zero(); 3];
            for ax in &j.translations {
                let s = ax.function.eval(coord_value(q, ax.coordinate));
                for (tk, ak) in t.iter_mut().zip(ax.axis) {
                    *tk += s * ak;
                }
            }
            let rm = mul_mm(&rf, &rfm);
            let om = add(&of, &mul_mv(&rf, &t));
            // Child body: M = B · frame_in_child, so B = M · frame_in_child⁻¹.
            let (rc, lc) = &j.frame_in_child;
            let rb = mul_mct(&rm, rc);
            let ob = sub(&om, &mul_mv_c(&rb, lc));
            poses.rotation[j.child] = rb;
            poses.origin[j.child] = ob;
        }
    }
}

fn coord_value<T: Scalar>(q: &[T], c: Option<CoordId>) -> T {
    match c {
        Some(i) => q[i],
        None => T::zero(),
    }
}

fn normalize(a: [f64; 3]) -> [f64; 3] {
    let n = (a[0] * a[0] + a[1] * a[1] + a[2] * a[2]).sqrt();
    if n > 0.0 {
        [a[0] / n, a[1] / n, a[2] / n]
    } else {
        a
    }
}

/// Rotation and location of an `Offset` frame in its body.
pub(crate) fn offset_transform(o: &Offset) -> (Mat3<f64>, [f64; 3]) {
    let [a, b, c] = o.orientation;
    let rx = axis_angle([1.0, 0.0, 0.0], a);
    let ry = axis_angle([0.0, 1.0, 0.0], b);
    let rz = axis_angle([0.0, 0.0, 1.0], c);
    (mul_mm(&mul_mm(&rx, &ry), &rz), o.location)
}

fn identity<T: Scalar>() -> Mat3<T> {
    let (z, o) = (T::zero(), T::one());
    [[o, z, z], [z, o, z], [z, z, o]]
}

/// Rotation by `angle` [rad] about unit `axis` (Rodrigues).
fn axis_angle<T: Scalar>(a: [f64; 3], angle: T) -> Mat3<T> {
    let (s, c) = (angle.sin(), angle.cos());
    let v = c.rsub(1.0);
    let mut r = [[T::zero(); 3]; 3];
    for i in 0..3 {
        for k in 0..3 {
            r[i][k] = v * (a[i] * a[k]);
        }
        r[i][i] += c;
    }
    r[0][1] -= s * a[2];
    r[0][2] += s * a[1];
    r[1][0] += s * a[2];
    r[1][2] -= s * a[0];
    r[2][0] -= s * a[1];
    r[2][1] += s * a[0];
    r
}

fn mul_mm<T: Scalar>(a: &Mat3<T>, b: &Mat3<T>) -> Mat3<T> {
    let mut r = [[T::zero(); 3]; 3];
    for i in 0..3 {
        for k in 0..3 {
            r[i][k] = a[i][0] * b[0][k] + a[i][1] * b[1][k] + a[i][2] * b[2][k];
        }
    }
    r
}

fn mul_mc<T: Scalar>(a: &Mat3<T>, b: &Mat3<f64>) -> Mat3<T> {
    let mut r = [[T::zero(); 3]; 3];
    for i in 0..3 {
        for k in 0..3 {
            r[i][k] = a[i][0] * b[0][k] + a[i][1] * b[1][k] + a[i][2] * b[2][k];
        }
    }
    r
}

/// `a · bᵀ` for a constant `b`.
fn mul_mct<T: Scalar>(a: &Mat3<T>, b: &Mat3<f64>) -> Mat3<T> {
    let mut r = [[T::zero(); 3]; 3];
    for i in 0..3 {
        for k in 0..3 {
            r[i][k] = a[i][0] * b[k][0] + a[i][1] * b[k][1] + a[i][2] * b[k][2];
        }
    }
    r
}

fn mul_mv<T: Scalar>(a: &Mat3<T>, v: &Vec3<T>) -> Vec3<T> {
    let mut r = [T::zero(); 3];
    for (i, ri) in r.iter_mut().enumerate() {
        *ri = a[i][0] * v[0] + a[i][1] * v[1] + a[i][2] * v[2];
    }
    r
}

fn mul_mv_c<T: Scalar>(a: &Mat3<T>, v: &[f64; 3]) -> Vec3<T> {
    let mut r = [T::zero(); 3];
    for (i, ri) in r.iter_mut().enumerate() {
        *ri = a[i][0] * v[0] + a[i][1] * v[1] + a[i][2] * v[2];
    }
    r
}

fn add<T: Scalar>(a: &Vec3<T>, b: &Vec3<T>) -> Vec3<T> {
    [a[0] + b[0], a[1] + b[1], a[2] + b[2]]
}

fn sub<T: Scalar>(a: &Vec3<T>, b: &Vec3<T>) -> Vec3<T> {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}
