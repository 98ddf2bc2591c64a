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
//! and of the surface paths between the two tangent points of each wrap; with several
//! wraps the straight segments run to the tangent points where OpenSim first located
//! them in ground (see `Tangents`).

use crate::error::GeometryError;
use crate::kinematics::{offset_transform, BodyPoses, Mat3, Vec3};
use crate::wrap_ellipsoid::{wrap_ellipsoid, WrapMethod};
use crate::wrap_shapes::{values, wrap_cylinder, wrap_sphere, SurfacePath, WrapAction};
use crate::wrap_torus::wrap_torus;
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

    /// Wraps the segment `a`–`b` (wrap frame [m], primal values); `method` chooses an
    /// ellipsoid's plane, `single` tells that the path has no other wrap (cylinders,
    /// tori).
    fn wrap(
        &self,
        a: &[f64; 3],
        b: &[f64; 3],
        method: WrapMethod,
        single: bool,
    ) -> WrapAction<f64> {
        match self.shape {
            WrapShape::Cylinder { radius, length } => {
                wrap_cylinder(a, b, radius, length, self.quadrant, single)
            }
            WrapShape::Sphere { radius } => wrap_sphere(a, b, radius, self.quadrant),
            WrapShape::Ellipsoid { radii } => wrap_ellipsoid(a, b, radii, self.quadrant, method),
            WrapShape::Torus {
                inner_radius,
                outer_radius,
            } => wrap_torus(a, b, inner_radius, outer_radius, self.quadrant, single),
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

/// An active path point: position in ground [m], body and index in the muscle's list.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Node<T> {
    /// Position in ground [m].
    pub at: Vec3<T>,
    /// Body carrying the point.
    pub body: usize,
    /// Index in the muscle's full list of path points.
    pub index: usize,
}

/// Outcome code of the last segment tried by a wrap (for the order swap rule).
#[derive(Clone, Copy, Debug, PartialEq)]
enum Code {
    NoWrap,
    Inside,
    Wrapped,
}

/// The tangent points of one wrap: in the wrap frame and in ground [m] as last computed,
/// the ground positions OpenSim's straight segments use, and the surface length [m].
///
/// OpenSim caches a point's ground position the first time it is asked for while the
/// pose stays the same; moving a tangent point later does not update that cache. With
/// two or more wraps, the sweeps after the first move tangent points whose ground
/// positions were cached by the first: the straight segments then run to the tangent
/// points of the first sweep while the surface lengths are the latest ones. OpenSim's
/// lengths and moment arms are those of that mixed path, so stride's are too.
#[derive(Clone, Copy, Debug, Default)]
struct Tangents {
    local: [[f64; 3]; 2],
    ground: [[f64; 3]; 2],
    cached: [Option<[f64; 3]>; 2],
    surface: f64,
}

/// The state of one path evaluation: active points, tangent points of every wrap, the
/// current node order and the wrap frames (primal values).
struct Sweep<'a, T> {
    points: &'a [Node<T>],
    values: Vec<[f64; 3]>,
    slot: Vec<usize>,
    tangents: Vec<Tangents>,
    path: Vec<Origin>,
    frames: Vec<(Mat3<f64>, [f64; 3])>,
}

impl<T: Scalar> Sweep<'_, T> {
    /// Latest ground position [m] of a node (what a wrap computation sees).
    fn fresh(&self, o: Origin) -> [f64; 3] {
        match o {
            Origin::Point(i) => self.values[self.slot[i]],
            Origin::Tangent { wrap, second } => self.tangents[wrap].ground[usize::from(second)],
        }
    }

    /// Ground position [m] of a node as OpenSim's straight segments see it: cached on the
    /// first request.
    fn ground(&mut self, o: Origin) -> [f64; 3] {
        match o {
            Origin::Point(_) => self.fresh(o),
            Origin::Tangent { wrap, second } => {
                let t = &mut self.tangents[wrap];
                let k = usize::from(second);
                *t.cached[k].get_or_insert(t.ground[k])
            }
        }
    }

    /// Primal length [m] of the current path: straight segments between cached ground
    /// positions, surface lengths between the two tangent points of a wrap.
    fn length(&mut self) -> f64 {
        let mut total = 0.0;
        for k in 1..self.path.len() {
            let (a, b) = (self.path[k - 1], self.path[k]);
            if let Some(w) = surface_of(a, b) {
                total += self.tangents[w].surface;
            } else {
                let (ga, gb) = (self.ground(a), self.ground(b));
                total += dist(&ga, &gb);
            }
        }
        total
    }
}

/// The wrap whose surface path joins nodes `a` and `b`, if they are its two tangent points.
fn surface_of(a: Origin, b: Origin) -> Option<usize> {
    match (a, b) {
        (
            Origin::Tangent {
                wrap: x,
                second: false,
            },
            Origin::Tangent {
                wrap: y,
                second: true,
            },
        ) if x == y => Some(x),
        _ => None,
    }
}

fn dist(a: &[f64; 3], b: &[f64; 3]) -> f64 {
    ((a[0] - b[0]).powi(2) + (a[1] - b[1]).powi(2) + (a[2] - b[2]).powi(2)).sqrt()
}

/// Length [m] of a path with wraps. `active[i]` tells whether path point `i` is active;
/// `points` holds the active points in order.
///
/// Decisions and tangent points are computed on primal values. The length on `T` is the
/// primal one plus, for every straight segment between points on different bodies, the
/// change of that segment's end points (tangent points fixed on their wrap objects) along
/// the segment's direction: its derivatives are OpenSim's moment arms, which hold the
/// tangent points fixed and take the directions of the segments as it draws them.
pub(crate) fn wrapped_length<T: Scalar>(
    objects: &[PreparedWrapObject],
    wraps: &[PreparedPathWrap],
    active: &[bool],
    points: &[Node<T>],
    poses: &BodyPoses<T>,
) -> T {
    let frames_t: Vec<(Mat3<T>, Vec3<T>)> = wraps
        .iter()
        .map(|w| objects[w.object].frame(poses))
        .collect();
    let mut slot = vec![usize::MAX; active.len()];
    for (k, n) in points.iter().enumerate() {
        slot[n.index] = k;
    }
    let mut sweep = Sweep {
        points,
        values: points.iter().map(|n| values(&n.at)).collect(),
        slot,
        tangents: vec![Tangents::default(); wraps.len()],
        path: points.iter().map(|n| Origin::Point(n.index)).collect(),
        frames: frames_t
            .iter()
            .map(|(r, o)| (r.map(|row| row.map(|v| v.value())), values(o)))
            .collect(),
    };
    run_sweeps(objects, wraps, active, &mut sweep);
    linearised_length(objects, wraps, &mut sweep, &frames_t)
}

/// OpenSim's sweeps over the wraps (`GeometryPath::applyWrapObjects`).
fn run_sweeps<T: Scalar>(
    objects: &[PreparedWrapObject],
    wraps: &[PreparedPathWrap],
    active: &[bool],
    sweep: &mut Sweep<'_, T>,
) {
    let nw = wraps.len();
    let mut order: Vec<usize> = (0..nw).collect();
    let mut result = vec![Code::NoWrap; nw];
    let sweeps = if nw < 2 { 1 } else { 8 };
    let mut last = f64::INFINITY;
    for round in 0..sweeps {
        for i in 0..nw {
            let w = order[i];
            result[i] = Code::NoWrap;
            remove_tangents(&mut sweep.path, w);
            if !objects[wraps[w].object].active {
                continue;
            }
            let Some((start, end)) = range_in_path(&sweep.path, active, wraps[w].range) else {
                return;
            };
            let (code, best) = best_wrap(objects, wraps, w, sweep, start, end);
            result[i] = code;
            if let Some((at, sp)) = best {
                let frame = &sweep.frames[w];
                let t = &mut sweep.tangents[w];
                t.local = [sp.r1, sp.r2];
                t.ground = [to_ground(frame, &sp.r1), to_ground(frame, &sp.r2)];
                t.surface = sp.length;
                let first = Origin::Tangent {
                    wrap: w,
                    second: false,
                };
                let second = Origin::Tangent {
                    wrap: w,
                    second: true,
                };
                sweep.path.insert(at + 1, first);
                sweep.path.insert(at + 2, second);
            }
        }
        let length = sweep.length();
        if (length - last).abs() < 0.0005 {
            break;
        }
        last = length;
        if round == 0 && nw > 1 && result[0] == Code::NoWrap && result[1] == Code::Inside {
            order.swap(0, 1);
            remove_tangents(&mut sweep.path, 0);
        }
    }
}

/// Wrap-frame point → ground (primal).
fn to_ground(frame: &(Mat3<f64>, [f64; 3]), r: &[f64; 3]) -> [f64; 3] {
    let (rot, o) = frame;
    std::array::from_fn(|k| o[k] + rot[k][0] * r[0] + rot[k][1] * r[1] + rot[k][2] * r[2])
}

/// Tries wrap `w` on the segments `start..end` of the current path: the outcome code of
/// the last segment tried and the chosen wrap (index of its first node, surface path in
/// the wrap frame), if any.
fn best_wrap<T: Scalar>(
    objects: &[PreparedWrapObject],
    wraps: &[PreparedPathWrap],
    w: usize,
    sweep: &mut Sweep<'_, T>,
    start: usize,
    end: usize,
) -> (Code, Option<(usize, SurfacePath<f64>)>) {
    let object = &objects[wraps[w].object];
    let frame = sweep.frames[w];
    let (rot, o) = &frame;
    let to_local = |g: &[f64; 3]| -> [f64; 3] {
        let d = [g[0] - o[0], g[1] - o[1], g[2] - o[2]];
        std::array::from_fn(|k| rot[0][k] * d[0] + rot[1][k] * d[1] + rot[2][k] * d[2])
    };
    let object_of = |n: Origin| match n {
        Origin::Tangent { wrap, .. } => Some(wraps[wrap].object),
        Origin::Point(_) => None,
    };
    let mut code = Code::NoWrap;
    let mut best: Option<(usize, SurfacePath<f64>)> = None;
    let mut least = f64::INFINITY;
    for pt1 in start..end {
        let (n1, n2) = (sweep.path[pt1], sweep.path[pt1 + 1]);
        if object_of(n1).is_some() && object_of(n1) == object_of(n2) {
            continue;
        }
        let (a, b) = (to_local(&sweep.fresh(n1)), to_local(&sweep.fresh(n2)));
        match object.wrap(&a, &b, wraps[w].method, wraps.len() == 1) {
            WrapAction::Mandatory(sp) => {
                code = Code::Wrapped;
                best = Some((pt1, sp));
                break;
            }
            WrapAction::Wrapped(sp) => {
                code = Code::Wrapped;
                // OpenSim measures the change from the cached ground positions.
                let (g1, g2) = (sweep.ground(n1), sweep.ground(n2));
                let change = dist(&g1, &to_ground(&frame, &sp.r1))
                    + sp.length
                    + dist(&to_ground(&frame, &sp.r2), &g2)
                    - dist(&g1, &g2);
                if change < least {
                    least = change;
                    best = Some((pt1, sp));
                }
            }
            WrapAction::Degenerate => code = Code::Wrapped,
            WrapAction::Inside => code = Code::Inside,
            WrapAction::NoWrap => code = Code::NoWrap,
        }
    }
    (code, best)
}

/// The length on `T` of the final path (see [`wrapped_length`]).
fn linearised_length<T: Scalar>(
    objects: &[PreparedWrapObject],
    wraps: &[PreparedPathWrap],
    sweep: &mut Sweep<'_, T>,
    frames_t: &[(Mat3<T>, Vec3<T>)],
) -> T {
    let at_t = |sweep: &Sweep<'_, T>, o: Origin| -> (Vec3<T>, usize) {
        match o {
            Origin::Point(i) => {
                let n = &sweep.points[sweep.slot[i]];
                (n.at, n.body)
            }
            Origin::Tangent { wrap, second } => {
                let r = sweep.tangents[wrap].local[usize::from(second)].map(T::cst);
                let (rot, o) = &frames_t[wrap];
                let g = std::array::from_fn(|k| {
                    o[k] + rot[k][0] * r[0] + rot[k][1] * r[1] + rot[k][2] * r[2]
                });
                (g, objects[wraps[wrap].object].body())
            }
        }
    };
    let mut total = T::zero();
    for k in 1..sweep.path.len() {
        let (a, b) = (sweep.path[k - 1], sweep.path[k]);
        if let Some(w) = surface_of(a, b) {
            total += T::cst(sweep.tangents[w].surface);
            continue;
        }
        let (ga, gb) = (sweep.ground(a), sweep.ground(b));
        let d = dist(&ga, &gb);
        let ((pa, body_a), (pb, body_b)) = (at_t(sweep, a), at_t(sweep, b));
        if body_a == body_b || d == 0.0 {
            total += T::cst(d);
            continue;
        }
        let (fa, fb) = (sweep.fresh(a), sweep.fresh(b));
        let mut seg = T::cst(d);
        for j in 0..3 {
            let dir = (gb[j] - ga[j]) / d;
            seg += ((pb[j] - pa[j]) - (fb[j] - fa[j])) * dir;
        }
        total += seg;
    }
    total
}

/// Removes the two tangent points of wrap `w` from the path, if present.
fn remove_tangents(path: &mut Vec<Origin>, w: usize) {
    path.retain(|n| !matches!(n, Origin::Tangent { wrap, .. } if *wrap == w));
}

/// Indices in `path` of the first and last active path points of the 1-based `range`.
fn range_in_path(path: &[Origin], active: &[bool], range: [i32; 2]) -> Option<(usize, usize)> {
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
    let pos = |j: usize| path.iter().position(|p| *p == Origin::Point(j));
    Some((pos(lo)?, pos(hi)?))
}
