//! Wrapping one straight path segment over a cylinder or a sphere, in the frame of the
//! wrap object, with OpenSim's rules for when a segment wraps and on which side.
//!
//! Decisions (inside the surface, wrap or not, which tangent points, the long way round)
//! follow OpenSim 4.x `WrapCylinder::wrapLine` and `WrapSphere::wrapLine`, on primal
//! values. The sphere's path is the great-circle arc between the tangent points. The
//! cylinder's is the helix between tangent points whose heights come from OpenSim's
//! apex-plane construction, which is not the shortest path; on a path with other wraps
//! OpenSim then slides them towards tangency ([`crate::cylinder_spiral`]).
//! [`crate::wrap`] holds the tangent points fixed on the surface for the moment arms, as
//! OpenSim's do.

use crate::cylinder_spiral::{adjust_heights, helix_angle};
use crate::kinematics::Vec3;
use stride_ad::Scalar;
use stride_model::WrapQuadrant;

/// Result of wrapping one segment (OpenSim's `WrapAction`).
#[derive(Clone, Copy, Debug)]
pub(crate) enum WrapAction<T> {
    /// The segment stays straight.
    NoWrap,
    /// An end point lies inside the surface: the segment stays straight.
    Inside,
    /// The segment wraps (it may not intersect the surface: quadrant rule).
    Wrapped(SurfacePath<T>),
    /// The segment intersects the surface and must wrap.
    Mandatory(SurfacePath<T>),
    /// Reported as wrapped but without a surface path (a torus whose cylinder does not
    /// wrap): the segment stays straight. OpenSim weighs it against the other segments
    /// with the tangent points of its previous evaluation, which stride does not keep;
    /// here it is no candidate.
    Degenerate,
}

/// A wrapped segment: tangent points (wrap frame [m]) and the length on the surface [m].
#[derive(Clone, Copy, Debug)]
pub(crate) struct SurfacePath<T> {
    /// Tangent point on the side of the segment's first point.
    pub r1: Vec3<T>,
    /// Tangent point on the side of the segment's second point.
    pub r2: Vec3<T>,
    /// Length of the path on the surface between `r1` and `r2` [m].
    pub length: T,
}

/// OpenSim's `DSIGN`: +1 for x ≥ 0, else −1.
pub(crate) fn dsign(x: f64) -> i8 {
    if x >= 0.0 {
        1
    } else {
        -1
    }
}

/// Primal values of a point.
pub(crate) fn values<T: Scalar>(p: &Vec3<T>) -> [f64; 3] {
    [p[0].value(), p[1].value(), p[2].value()]
}

fn dot2(a: [f64; 2], b: [f64; 2]) -> f64 {
    a[0] * b[0] + a[1] * b[1]
}

fn unit2(a: [f64; 2]) -> [f64; 2] {
    let n = a[0].hypot(a[1]);
    if n > 0.0 {
        [a[0] / n, a[1] / n]
    } else {
        a
    }
}

fn angle2(a: [f64; 2], b: [f64; 2]) -> f64 {
    dot2(unit2(a), unit2(b)).clamp(-1.0, 1.0).acos()
}

/// The two tangent points `[a, b]` on the circle of radius `r` about the origin seen from
/// the 2-D point `p` (outside the circle); `a` is `b` mirrored across the line to `p`,
/// rotated counter-clockwise from it.
fn circle_tangents<T: Scalar>(p: [T; 2], r: f64) -> [[T; 2]; 2] {
    let rho2 = p[0] * p[0] + p[1] * p[1];
    // Foot of the tangent chord on the line to p (at R²/ρ from the centre) and the half
    // chord R √(ρ² − R²) / ρ along z × p / ρ.
    let k = rho2.rdiv(r * r);
    let hn = (rho2 - r * r).sqrt() * r / rho2;
    let foot = [p[0] * k, p[1] * k];
    let u = [-p[1] * hn, p[0] * hn];
    [
        [foot[0] + u[0], foot[1] + u[1]],
        [foot[0] - u[0], foot[1] - u[1]],
    ]
}

/// Angle [rad] in [0, π] between two vectors of equal length, by `atan` only.
pub(crate) fn arc_angle<T: Scalar, const N: usize>(a: [T; N], b: [T; N]) -> T {
    let (mut d, mut s) = (T::zero(), T::zero());
    for k in 0..N {
        d += (a[k] - b[k]).sq();
        s += (a[k] + b[k]).sq();
    }
    let (d, s) = (d.sqrt(), s.sqrt());
    if d.value() <= s.value() {
        (d / s).apply(crate::atan::atan()) * 2.0
    } else {
        ((s / d).apply(crate::atan::atan()) * 2.0).rsub(std::f64::consts::PI)
    }
}

fn v2<T: Scalar>(a: [T; 2]) -> [f64; 2] {
    [a[0].value(), a[1].value()]
}

/// Which tangent candidates a cylinder wrap uses (`true` = candidate `a`), whether it
/// goes the long way round, and OpenSim's `far_side_wrap` (which side the apex of its
/// tangent-height construction lies on), by OpenSim's rules.
fn cylinder_choice(
    p: [[f64; 3]; 2],
    c1: [[f64; 2]; 2],
    c2: [[f64; 2]; 2],
    quadrant: Option<WrapQuadrant>,
) -> (bool, bool, bool, bool) {
    let Some(q) = quadrant else {
        // The pair with the smallest angle between the radial directions.
        let d = [
            dot2(unit2(c1[0]), unit2(c2[0])),
            dot2(unit2(c1[0]), unit2(c2[1])),
            dot2(unit2(c1[1]), unit2(c2[0])),
            dot2(unit2(c1[1]), unit2(c2[1])),
        ];
        let pick = if d[0] > d[1] && d[0] > d[2] && d[0] > d[3] {
            (true, true)
        } else if d[1] > d[2] && d[1] > d[3] {
            (true, false)
        } else if d[2] > d[3] {
            (false, true)
        } else {
            (false, false)
        };
        return (pick.0, pick.1, false, false);
    };
    // Candidate coordinate along the quadrant axis (z candidates keep the point's z).
    let comp = |c: [f64; 2], z: f64| if q.axis == 2 { z } else { c[q.axis] };
    let on = |x: f64| dsign(x) == q.sign;
    let (z1, z2) = (p[0][2], p[1][2]);
    let alpha = angle2(c1[0], c2[1]);
    let beta = angle2(c1[1], c2[0]);
    let ab = (true, false); // r1a, r2b
    let ba = (false, true); // r1b, r2a
    let (r1a_on, r1b_on) = (on(comp(c1[0], z1)), on(comp(c1[1], z1)));
    let (pick1, pick2) = if r1a_on == r1b_on {
        if on(comp(c2[0], z2)) {
            ba
        } else if r1a_on || on(comp(c2[1], z2)) || alpha > beta {
            ab
        } else {
            ba
        }
    } else if r1a_on {
        ab
    } else {
        ba
    };
    // Long wrap: the radial directions of the tangent points point against the muscle.
    let r1 = if pick1 { c1[0] } else { c1[1] };
    let r2 = if pick2 { c2[0] } else { c2[1] };
    let musc = [
        r1[0] - p[0][0] + r2[0] - p[1][0],
        r1[1] - p[0][1] + r2[1] - p[1][1],
    ];
    let radial = [r1[0] + r2[0], r1[1] + r2[1]];
    let none_on = !r1a_on && !r1b_on && !on(comp(c2[0], z2)) && !on(comp(c2[1], z2));
    let far = none_on || (pick1 == (alpha > beta));
    (pick1, pick2, dot2(radial, musc) < 0.0, far)
}

/// Wraps the segment `a`–`b` (cylinder frame [m]) over the cylinder of `radius` and
/// `length` along z centred on the origin, on primal values. The tangent heights come
/// from OpenSim's apex-plane construction ([`cylinder_path`]); `single` tells that the
/// path has no other wrap, else OpenSim adjusts them towards tangency
/// ([`crate::cylinder_spiral`]).
pub(crate) fn wrap_cylinder(
    a: &[f64; 3],
    b: &[f64; 3],
    radius: f64,
    length: f64,
    quadrant: Option<WrapQuadrant>,
    single: bool,
) -> WrapAction<f64> {
    let (a, b) = (*a, *b);
    let r2 = radius * radius;
    if a[0] * a[0] + a[1] * a[1] < r2 || b[0] * b[0] + b[1] * b[1] < r2 {
        return WrapAction::Inside;
    }
    let (near12, t12, dist2) = closest_to_z_axis(a, b);
    let hits = dist2 < r2 && t12 > 0.0 && t12 < 1.0;
    // A crossing segment must wrap, except that with both points off the active side
    // OpenSim wraps every segment without giving it precedence.
    let mandatory = match quadrant {
        None if !hits => return WrapAction::NoWrap,
        None => true,
        Some(q) if dsign(a[q.axis]) == q.sign || dsign(b[q.axis]) == q.sign => {
            let crosses = dsign(a[q.axis]) != dsign(b[q.axis]);
            let wraps_across = crosses && dsign(near12[q.axis]) != q.sign;
            if !(hits || wraps_across) {
                return WrapAction::NoWrap;
            }
            hits
        }
        Some(_) => false,
    };
    let c1 = circle_tangents([a[0], a[1]], radius);
    let c2 = circle_tangents([b[0], b[1]], radius);
    let (pick1, pick2, long, far) = cylinder_choice([a, b], c1, c2, quadrant);
    let t1 = if pick1 { c1[0] } else { c1[1] };
    let t2 = if pick2 { c2[0] } else { c2[1] };
    let turn = CylinderTurn { long, far };
    let Some(path) = cylinder_path([a, b], [t1, t2], radius, length, turn, !single) else {
        return WrapAction::NoWrap;
    };
    if mandatory {
        WrapAction::Mandatory(path)
    } else {
        WrapAction::Wrapped(path)
    }
}

/// How a cylinder wrap turns: the long way round (`long`), and on which side the apex of
/// OpenSim's tangent-height construction lies (`far`).
#[derive(Clone, Copy, Debug)]
struct CylinderTurn {
    long: bool,
    far: bool,
}

/// OpenSim's surface path over a cylinder, on primal values: the tangent points `t`
/// (x, y) take their heights from the plane through both end points `p` and an apex on
/// the cylinder's surface (on the far side with `turn.far`); with `adjust` (a path with
/// other wraps) OpenSim then slides them towards tangency. The path is the helix between
/// them, `turn.long` the long way round. `None` when both tangent points lie beyond the
/// cylinder's ends before the adjustment.
fn cylinder_path(
    p: [[f64; 3]; 2],
    t: [[f64; 2]; 2],
    radius: f64,
    length: f64,
    turn: CylinderTurn,
    adjust: bool,
) -> Option<SurfacePath<f64>> {
    use crate::vec3::{cross, dot, sub, unit};
    let [a, b] = p;
    let (n1, n2) = (a[0].hypot(a[1]), b[0].hypot(b[1]));
    let s = n1 / (n1 + n2);
    let mpt: [f64; 3] = std::array::from_fn(|k| a[k] + s * (b[k] - a[k]));
    let axis_pt = [0.0, 0.0, mpt[2]];
    let normal = unit(&cross(&unit(&sub(&a, &axis_pt)), &unit(&sub(&b, &axis_pt))));
    let vert = unit(&cross(&[0.0, 0.0, 1.0], &normal));
    let apex1: [f64; 3] = std::array::from_fn(|k| axis_pt[k] + radius * vert[k]);
    let apex2: [f64; 3] = std::array::from_fn(|k| axis_pt[k] - radius * vert[k]);
    let d2 = |x: &[f64; 3], y: &[f64; 3]| dot(&sub(x, y), &sub(x, y));
    let nearer_first = d2(&mpt, &apex1) < d2(&mpt, &apex2);
    let apex = if nearer_first != turn.far {
        apex1
    } else {
        apex2
    };
    let plane = unit(&cross(&unit(&sub(&a, &apex)), &unit(&sub(&b, &apex))));
    let offset = -dot(&a, &plane);
    // Slide each tangent point along the cylinder onto that plane, unless that moves it
    // beyond the other end point's height.
    let height = |t: [f64; 2], own: f64, other: f64| {
        if plane[2] == 0.0 {
            return own;
        }
        let z = -(dot(&plane, &[t[0], t[1], 0.0]) + offset) / plane[2];
        if (z - own).abs() <= 10.0 && (z - other).abs() < (own - other).abs() {
            z
        } else {
            own
        }
    };
    let z1 = height(t[0], a[2], b[2]);
    let z2 = height(t[1], b[2], a[2]);
    let half = 0.5 * length;
    if z1.abs() > half && z2.abs() > half {
        return None;
    }
    let (z1, z2, theta) = if adjust {
        let [z1, z2] = adjust_heights(p, t, [z1, z2], radius, turn.long);
        (z1, z2, helix_angle(t, turn.long))
    } else {
        let mut theta = (t[0][0] * t[1][1] - t[0][1] * t[1][0]).atan2(dot2(t[0], t[1]));
        if turn.long {
            theta = 2.0 * std::f64::consts::PI - theta;
        }
        (z1, z2, theta)
    };
    Some(SurfacePath {
        r1: [t[0][0], t[0][1], z1],
        r2: [t[1][0], t[1][1], z2],
        length: (radius * theta).hypot(z2 - z1),
    })
}

/// Closest point of the line through `a`, `b` to the z axis: the point, its parameter
/// along `a`→`b` and its squared distance to the axis.
fn closest_to_z_axis(a: [f64; 3], b: [f64; 3]) -> ([f64; 3], f64, f64) {
    let d = [b[0] - a[0], b[1] - a[1]];
    let dd = d[0] * d[0] + d[1] * d[1];
    // Parallel to the axis: any point; use a.
    let t = if dd > 0.0 {
        -(a[0] * d[0] + a[1] * d[1]) / dd
    } else {
        0.0
    };
    let p = [
        a[0] + t * (b[0] - a[0]),
        a[1] + t * (b[1] - a[1]),
        a[2] + t * (b[2] - a[2]),
    ];
    (p, t, p[0] * p[0] + p[1] * p[1])
}

/// Wraps the segment `p1`–`p2` (sphere frame [m]) over the sphere of `radius` centred on
/// the origin. As in OpenSim, only a segment that crosses the sphere wraps.
pub(crate) fn wrap_sphere<T: Scalar>(
    p1: &Vec3<T>,
    p2: &Vec3<T>,
    radius: f64,
    quadrant: Option<WrapQuadrant>,
) -> WrapAction<T> {
    let (a, b) = (values(p1), values(p2));
    let n2 = |v: [f64; 3]| v[0] * v[0] + v[1] * v[1] + v[2] * v[2];
    if n2(a) < radius * radius || n2(b) < radius * radius {
        return WrapAction::Inside;
    }
    // Both intersections of the line with the sphere strictly between p1 and p2.
    let d = [b[0] - a[0], b[1] - a[1], b[2] - a[2]];
    let qa = n2(d);
    let qb = 2.0 * (a[0] * d[0] + a[1] * d[1] + a[2] * d[2]);
    let qc = n2(a) - radius * radius;
    let disc = qb * qb - 4.0 * qa * qc;
    if disc < 0.0 || qa == 0.0 {
        return WrapAction::NoWrap;
    }
    let l = [
        (-qb - disc.sqrt()) / (2.0 * qa),
        (-qb + disc.sqrt()) / (2.0 * qa),
    ];
    if !l.iter().all(|t| *t > 0.0 && *t < 1.0) {
        return WrapAction::NoWrap;
    }
    // The great circle through p1 and p2: orthonormal in-plane basis (e1, e2).
    let n1 = (p1[0] * p1[0] + p1[1] * p1[1] + p1[2] * p1[2]).sqrt();
    let e1 = [p1[0] / n1, p1[1] / n1, p1[2] / n1];
    let x2 = p2[0] * e1[0] + p2[1] * e1[1] + p2[2] * e1[2];
    let w = [p2[0] - e1[0] * x2, p2[1] - e1[1] * x2, p2[2] - e1[2] * x2];
    let y2 = (w[0] * w[0] + w[1] * w[1] + w[2] * w[2]).sqrt();
    if y2.value() < 1e-5 * n1.value() {
        // The segment passes through the centre: no plane (OpenSim keeps the last wrap).
        return WrapAction::NoWrap;
    }
    let e2 = [w[0] / y2, w[1] / y2, w[2] / y2];
    let q1 = [n1, T::zero()];
    let q2 = [x2, y2];
    let c1 = circle_tangents(q1, radius);
    let c2 = circle_tangents(q2, radius);
    let (pick1, pick2, long) = sphere_choice([a, b], &c1, &c2, &e1, &e2, radius, quadrant);
    let t1 = if pick1 { c1[0] } else { c1[1] };
    let t2 = if pick2 { c2[0] } else { c2[1] };
    let mut theta = arc_angle(t1, t2);
    if long {
        theta = theta.rsub(2.0 * std::f64::consts::PI);
    }
    let to3 = |t: [T; 2]| {
        [
            e1[0] * t[0] + e2[0] * t[1],
            e1[1] * t[0] + e2[1] * t[1],
            e1[2] * t[0] + e2[2] * t[1],
        ]
    };
    let path = SurfacePath {
        r1: to3(t1),
        r2: to3(t2),
        length: theta * radius,
    };
    match quadrant {
        Some(q) if !(dsign(a[q.axis]) == q.sign || dsign(b[q.axis]) == q.sign) => {
            WrapAction::Wrapped(path)
        }
        _ => WrapAction::Mandatory(path),
    }
}

/// Tangent candidates of a sphere wrap (`true` = candidate `a`) and the long way round,
/// by OpenSim's rules.
#[allow(clippy::too_many_arguments)]
fn sphere_choice<T: Scalar>(
    p: [[f64; 3]; 2],
    c1: &[[T; 2]; 2],
    c2: &[[T; 2]; 2],
    e1: &Vec3<T>,
    e2: &Vec3<T>,
    radius: f64,
    quadrant: Option<WrapQuadrant>,
) -> (bool, bool, bool) {
    let (e1, e2) = (values(e1), values(e2));
    let to3 = |t: [T; 2]| {
        let t = v2(t);
        [
            (e1[0] * t[0] + e2[0] * t[1]) / radius,
            (e1[1] * t[0] + e2[1] * t[1]) / radius,
            (e1[2] * t[0] + e2[2] * t[1]) / radius,
        ]
    };
    let (r1a, r1b, r2a, r2b) = (to3(c1[0]), to3(c1[1]), to3(c2[0]), to3(c2[1]));
    let dot = |u: [f64; 3], v: [f64; 3]| u[0] * v[0] + u[1] * v[1] + u[2] * v[2];
    let j = [dot(r1a, r2a), dot(r1a, r2b), dot(r1b, r2a), dot(r1b, r2b)];
    let (mut pick1, mut pick2) = if j[0] > j[1] && j[0] > j[2] && j[0] > j[3] {
        (true, true)
    } else if j[1] > j[2] && j[1] > j[3] {
        (true, false)
    } else if j[2] > j[3] {
        (false, true)
    } else {
        (false, false)
    };
    let Some(q) = quadrant else {
        return (pick1, pick2, false);
    };
    let on = |x: f64| dsign(x) == q.sign;
    if on(p[0][q.axis]) && on(p[1][q.axis]) {
        return (pick1, pick2, false);
    }
    // Both tangent points towards the centre side seen from the muscle, then flipped to
    // the active side.
    let mut musc = [0.0; 3];
    for (k, m) in musc.iter_mut().enumerate() {
        *m = -p[0][k] - p[1][k];
    }
    pick1 = dot(r1a, musc) > dot(r1b, musc);
    pick2 = dot(r2a, musc) > dot(r2b, musc);
    let pt = |pick: bool, a: [f64; 3], b: [f64; 3]| {
        let u = if pick { a } else { b };
        [u[0] * radius, u[1] * radius, u[2] * radius]
    };
    let side = |p1: bool, p2: bool| {
        let (t1, t2) = (pt(p1, r1a, r1b), pt(p2, r2a, r2b));
        let m: [f64; 3] = std::array::from_fn(|k| t1[k] - p[0][k] + t2[k] - p[1][k]);
        let r: [f64; 3] = std::array::from_fn(|k| t1[k] + t2[k]);
        (m, r)
    };
    let (m, _) = side(pick1, pick2);
    if m[q.axis] * f64::from(q.sign) < 0.0 {
        pick1 = !pick1;
        pick2 = !pick2;
    }
    let (m, r) = side(pick1, pick2);
    (pick1, pick2, dot(m, r) < 0.0)
}
