//! Path wrapping: OpenSim's procedure (`GeometryPath::applyWrapObjects`) over the active
//! path points of one muscle.
//!
//! Each wrap of the muscle, in order, removes its previous tangent points, then tries
//! every segment of the path between the first and last active points of its range
//! (1-based indices into all path points; tangent points of other wraps count as path
//! points, a segment between the two tangent points of one object is skipped): the first
//! segment that crosses the object wraps, else the wrapped segment that lengthens the
//! path least. The two tangent points are inserted in the path. With two or more wraps
//! the sweep repeats (at most 8 times) until the length changes by less than 0.5 mm, the
//! first two wraps swapped after the first sweep when the first did not wrap and the
//! second had a point inside its object. The length is the sum of the straight segments
//! and of the surface paths between the two tangent points of each wrap.

use crate::error::GeometryError;
use crate::kinematics::{offset_transform, BodyPoses, Mat3, Vec3};
use crate::path::distance;
use crate::wrap_ellipsoid::{wrap_ellipsoid, WrapMethod};
use crate::wrap_shapes::{values, wrap_cylinder, wrap_sphere, SurfacePath, WrapAction};
use stride_ad::Scalar;
use stride_model::{Offset, WrapObject, WrapQuadrant, WrapShape};

/// A wrap object ready for evaluation.
#[derive(Clone, Debug)]
pub(crate) struct PreparedWrapObject {
    body: usize,
    rotation: Mat3<f64>,
    translation: [f64; 3],
    quadrant: Option<WrapQuadrant>,
    active: bool,
    shape: WrapShape,
}

impl PreparedWrapObject {
    /// Prepares `o`; errors when its body does not exist.
    pub(crate) fn new(o: &WrapObject, n_bodies: usize) -> Result<Self, GeometryError> {
        if o.body >= n_bodies {
            return Err(GeometryError::Model {
                what: format!("wrap object {}: body index out of range", o.name),
            });
        }
        let (rotation, translation) = offset_transform(&Offset {
            location: o.translation,
            orientation: o.rotation,
        });
        Ok(Self {
            body: o.body,
            rotation,
            translation,
            quadrant: o.quadrant,
            active: o.active,
            shape: o.shape.clone(),
        })
    }

    /// Index of the body carrying the wrap object.
    pub(crate) fn body(&self) -> usize {
        self.body
    }

    /// OpenSim class of a shape this module cannot wrap over, if it is one.
    pub(crate) fn unsupported(&self) -> Option<&'static str> {
        match self.shape {
            WrapShape::Cylinder { .. } | WrapShape::Sphere { .. } | WrapShape::Ellipsoid { .. } => {
                None
            }
            _ => Some(self.shape.class_name()),
        }
    }

    /// Rotation (wrap frame → ground) and origin in ground [m] of the wrap frame.
    fn frame<T: Scalar>(&self, poses: &BodyPoses<T>) -> (Mat3<T>, Vec3<T>) {
        let rb = &poses.rotation[self.body];
        let mut r = [[T::zero(); 3]; 3];
        for (i, row) in r.iter_mut().enumerate() {
            for (k, v) in row.iter_mut().enumerate() {
                *v = rb[i][0] * self.rotation[0][k]
                    + rb[i][1] * self.rotation[1][k]
                    + rb[i][2] * self.rotation[2][k];
            }
        }
        let o = poses.point_in_ground(self.body, &self.translation.map(T::cst));
        (r, o)
    }

    /// Wraps the segment `a`–`b` (wrap frame [m]); `method` chooses an ellipsoid's plane,
    /// `single` tells that the path has no other wrap (cylinders).
    fn wrap<T: Scalar>(
        &self,
        a: &Vec3<T>,
        b: &Vec3<T>,
        method: WrapMethod,
        single: bool,
    ) -> WrapAction<T> {
        match self.shape {
            WrapShape::Cylinder { radius, length } => {
                wrap_cylinder(a, b, radius, length, self.quadrant, single)
            }
            WrapShape::Sphere { radius } => wrap_sphere(a, b, radius, self.quadrant),
            WrapShape::Ellipsoid { radii } => {
                // Tangent points fixed on the ellipsoid: OpenSim's moment arms.
                let (a, b) = (values(a), values(b));
                wrap_ellipsoid(&a, &b, radii, self.quadrant, method).to_constant()
            }
            // Rejected when the paths are prepared.
            _ => WrapAction::NoWrap,
        }
    }
}

/// One wrap of a muscle path: the object, the 1-based range of path points and the
/// method (ellipsoids).
#[derive(Clone, Debug)]
pub(crate) struct PreparedPathWrap {
    /// Index of the wrap object.
    pub object: usize,
    /// First and last path point considered (below 1: the first / last point).
    pub range: [i32; 2],
    /// How an ellipsoid's wrapping plane is chosen.
    pub method: WrapMethod,
}

/// Where a node of the current path comes from.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) enum Origin {
    /// Path point with this index in the muscle's full list.
    Point(usize),
    /// First (`false`) or second (`true`) tangent point of the muscle's wrap `wrap`.
    Tangent { wrap: usize, second: bool },
}

/// A node of the current path: position in ground [m] and origin.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Node<T> {
    /// Position in ground [m].
    pub at: Vec3<T>,
    /// Path point or tangent point.
    pub origin: Origin,
}

/// Outcome code of the last segment tried by a wrap (for the order swap rule).
#[derive(Clone, Copy, Debug, PartialEq)]
enum Code {
    NoWrap,
    Inside,
    Wrapped,
}

/// Length [m] of a path with wraps. `active[i]` tells whether path point `i` is active;
/// `path` holds the active points in order.
pub(crate) fn wrapped_length<T: Scalar>(
    objects: &[PreparedWrapObject],
    wraps: &[PreparedPathWrap],
    active: &[bool],
    mut path: Vec<Node<T>>,
    poses: &BodyPoses<T>,
) -> T {
    let nw = wraps.len();
    let mut surface = vec![T::zero(); nw];
    let mut order: Vec<usize> = (0..nw).collect();
    let mut result = vec![Code::NoWrap; nw];
    let sweeps = if nw < 2 { 1 } else { 8 };
    let mut last = f64::INFINITY;
    for sweep in 0..sweeps {
        for i in 0..nw {
            let w = order[i];
            result[i] = Code::NoWrap;
            remove_tangents(&mut path, w);
            let object = &objects[wraps[w].object];
            if !object.active {
                continue;
            }
            let Some((start, end)) = range_in_path(&path, active, wraps[w].range) else {
                return total_length(&path, &surface);
            };
            let (code, best) = best_wrap(objects, wraps, w, &path, start, end, poses);
            result[i] = code;
            if let Some((at, sp, frame)) = best {
                let to_ground = |r: &Vec3<T>| {
                    let (rot, o) = &frame;
                    std::array::from_fn(|k| {
                        o[k] + rot[k][0] * r[0] + rot[k][1] * r[1] + rot[k][2] * r[2]
                    })
                };
                let first = Node {
                    at: to_ground(&sp.r1),
                    origin: Origin::Tangent {
                        wrap: w,
                        second: false,
                    },
                };
                let second = Node {
                    at: to_ground(&sp.r2),
                    origin: Origin::Tangent {
                        wrap: w,
                        second: true,
                    },
                };
                path.insert(at + 1, first);
                path.insert(at + 2, second);
                surface[w] = sp.length;
            }
        }
        let length = total_length(&path, &surface).value();
        if (length - last).abs() < 0.0005 {
            break;
        }
        last = length;
        if sweep == 0 && nw > 1 && result[0] == Code::NoWrap && result[1] == Code::Inside {
            order.swap(0, 1);
            remove_tangents(&mut path, 0);
        }
    }
    total_length(&path, &surface)
}

/// A wrapped segment: index of its first node, surface path and wrap frame.
type Best<T> = (usize, SurfacePath<T>, (Mat3<T>, Vec3<T>));

/// Tries wrap `w` on the segments `start..end` of `path`: the outcome code of the last
/// segment tried and the chosen wrap, if any.
fn best_wrap<T: Scalar>(
    objects: &[PreparedWrapObject],
    wraps: &[PreparedPathWrap],
    w: usize,
    path: &[Node<T>],
    start: usize,
    end: usize,
    poses: &BodyPoses<T>,
) -> (Code, Option<Best<T>>) {
    let object = &objects[wraps[w].object];
    let (rot, o) = object.frame(poses);
    let to_local = |g: &Vec3<T>| -> Vec3<T> {
        let d = [g[0] - o[0], g[1] - o[1], g[2] - o[2]];
        std::array::from_fn(|k| rot[0][k] * d[0] + rot[1][k] * d[1] + rot[2][k] * d[2])
    };
    let object_of = |n: &Node<T>| match n.origin {
        Origin::Tangent { wrap, .. } => Some(wraps[wrap].object),
        Origin::Point(_) => None,
    };
    let mut code = Code::NoWrap;
    let mut best: Option<(usize, SurfacePath<T>)> = None;
    let mut least = f64::INFINITY;
    for pt1 in start..end {
        let (n1, n2) = (&path[pt1], &path[pt1 + 1]);
        if object_of(n1).is_some() && object_of(n1) == object_of(n2) {
            continue;
        }
        let (a, b) = (to_local(&n1.at), to_local(&n2.at));
        match object.wrap(&a, &b, wraps[w].method, wraps.len() == 1) {
            WrapAction::Mandatory(sp) => {
                code = Code::Wrapped;
                best = Some((pt1, sp));
                break;
            }
            WrapAction::Wrapped(sp) => {
                code = Code::Wrapped;
                let change =
                    distance(&a, &sp.r1).value() + sp.length.value() + distance(&sp.r2, &b).value()
                        - distance(&a, &b).value();
                if change < least {
                    least = change;
                    best = Some((pt1, sp));
                }
            }
            WrapAction::Inside => code = Code::Inside,
            WrapAction::NoWrap => code = Code::NoWrap,
        }
    }
    (code, best.map(|(at, sp)| (at, sp, (rot, o))))
}

/// Removes the two tangent points of wrap `w` from the path, if present.
fn remove_tangents<T>(path: &mut Vec<Node<T>>, w: usize) {
    path.retain(|n| !matches!(n.origin, Origin::Tangent { wrap, .. } if wrap == w));
}

/// Indices in `path` of the first and last active path points of the 1-based `range`.
fn range_in_path<T>(path: &[Node<T>], active: &[bool], range: [i32; 2]) -> Option<(usize, usize)> {
    let n = active.len();
    let first = if range[0] < 1 {
        0
    } else {
        range[0] as usize - 1
    };
    let last = if range[1] < 1 {
        n - 1
    } else {
        range[1] as usize - 1
    };
    let lo = (first..=last.min(n - 1)).find(|&j| active[j])?;
    let hi = (first..=last.min(n - 1)).rev().find(|&j| active[j])?;
    let pos = |j: usize| path.iter().position(|p| p.origin == Origin::Point(j));
    Some((pos(lo)?, pos(hi)?))
}

/// Sum of the straight segments and of the surface paths between tangent-point pairs [m].
fn total_length<T: Scalar>(path: &[Node<T>], surface: &[T]) -> T {
    let mut total = T::zero();
    for pair in path.windows(2) {
        match (pair[0].origin, pair[1].origin) {
            (
                Origin::Tangent {
                    wrap: a,
                    second: false,
                },
                Origin::Tangent {
                    wrap: b,
                    second: true,
                },
            ) if a == b => total += surface[a],
            _ => total += distance(&pair[0].at, &pair[1].at),
        }
    }
    total
}
