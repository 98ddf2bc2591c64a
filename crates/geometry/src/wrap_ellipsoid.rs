//! Wrapping one straight path segment over an ellipsoid, in the frame of the wrap
//! object, as OpenSim 4.x `WrapEllipsoid::wrapLine` does.
//!
//! Only a segment that crosses the ellipsoid wraps. The path then lies in the plane
//! through both end points and a point `c1` of the surface near the segment (found by
//! the path wrap's method: `hybrid` blends the closest point to the segment where it
//! crosses the coordinate plane most normal to it with the average of the closest-point
//! directions along it, `midpoint` takes the closest point to the middle of the chord,
//! `axial` the first alone), flipped to the active half with a quadrant. In that plane
//! the tangent points from each end are found by OpenSim's damped search from `c1` (which
//! of the two tangent points it reaches depends on that search, so it is reproduced step
//! by step), and the surface path is OpenSim's polyline along the ellipse (rays from a
//! point of the plane on a coordinate axis, one chord per millimetre of the tangent
//! points' distance, at most 499).
//!
//! The path over an ellipsoid is not the shortest one, and OpenSim's moment arms are not
//! the derivatives of its length: they hold the tangent points fixed on the ellipsoid.
//! [`crate::wrap`] therefore evaluates this wrap on primal values and carries its tangent
//! points and surface length as constants in the wrap frame, which gives OpenSim's
//! moment arms. Decisions are taken on primal values.
//!
//! All computations run in coordinates scaled by `3 / (a + b + c)` as OpenSim's do.

use crate::ellipsoid_closest::closest_on_ellipsoid;
use crate::kinematics::Vec3;
use crate::vec3::{add, cross, dot, dot_f, norm, scale, scale_c, sub, unit};
use crate::wrap_shapes::{arc_angle, dsign, values, SurfacePath, WrapAction};
use stride_ad::Scalar;
use stride_model::WrapQuadrant;

/// Below this axis cosine of the segment the `hybrid` method uses the fan alone.
const MU_BLEND_MIN: f64 = 0.7073;
/// Above this axis cosine the `hybrid` method uses the axial point alone.
const MU_BLEND_MAX: f64 = 0.9;
/// Samples of the fan of closest-point directions along the chord.
const FAN_SAMPLES: usize = 300;
/// Fraction of the chord at each end over which the axial point fades out.
const SV_BOUNDARY_BLEND: f64 = 0.3;
/// Length of one chord of the surface polyline [m].
const SEGMENT_LENGTH: f64 = 0.001;
/// Largest number of chords of the surface polyline.
const MAX_SEGMENTS: usize = 499;

/// How the wrapping plane of an ellipsoid is chosen (OpenSim `PathWrap` method).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum WrapMethod {
    /// Axial point and fan blended by the segment's direction (OpenSim's default).
    Hybrid,
    /// Closest point to the middle of the chord.
    Midpoint,
    /// Closest point where the segment crosses the coordinate plane most normal to it.
    Axial,
}

impl WrapMethod {
    /// The method named `name` in an OpenSim file.
    pub(crate) fn parse(name: &str) -> Option<Self> {
        match name {
            "hybrid" | "" => Some(Self::Hybrid),
            "midpoint" => Some(Self::Midpoint),
            "axial" => Some(Self::Axial),
            _ => None,
        }
    }
}

/// Wraps the segment `p1`–`p2` (ellipsoid frame [m]) over the ellipsoid with semi-axes
/// `radii` [m] centred on the origin.
pub(crate) fn wrap_ellipsoid<T: Scalar>(
    p1: &Vec3<T>,
    p2: &Vec3<T>,
    radii: [f64; 3],
    quadrant: Option<WrapQuadrant>,
    method: WrapMethod,
) -> WrapAction<T> {
    let factor = 3.0 / (radii[0] + radii[1] + radii[2]);
    let a = radii.map(|r| r * factor);
    let (p1, p2) = (scale_c(p1, factor), scale_c(p2, factor));
    let (v1, v2) = (values(&p1), values(&p2));
    let excess = |v: [f64; 3]| (0..3).map(|k| (v[k] / a[k]).powi(2)).sum::<f64>() - 1.0;
    let (e1, e2) = (excess(v1), excess(v2));
    if e1 < -1e-4 || e2 < -1e-4 {
        return WrapAction::Inside;
    }
    if (dot_f(&unit(&v1), &unit(&v2)) - 1.0).abs() < 1e-4 {
        return WrapAction::NoWrap;
    }
    let Some((r1, r2)) = crossing(&p1, &p2, a) else {
        return WrapAction::NoWrap;
    };
    let plane = plane_point(&p1, &p2, &r1, &r2, a, quadrant, method);
    let c1 = plane.c1;
    let vs = unit(&cross(&sub(&p1, &p2), &sub(&p1, &c1)));
    let vs4 = -dot(&vs, &c1);
    let t1 = if e1.abs() < 1e-4 {
        p1
    } else {
        tangent_point(values(&p1), values(&vs), vs4.value(), a, plane.start[0]).map(T::cst)
    };
    let t2 = if e2.abs() < 1e-4 {
        p2
    } else {
        tangent_point(values(&p2), values(&vs), vs4.value(), a, plane.start[1]).map(T::cst)
    };
    let mut arc = ellipse_arc(&t1, &t2, &vs, vs4, a, factor, false);
    if quadrant.is_some() {
        if let Some([w1, w2]) = arc.inner {
            let (t1v, t2v) = (values(&t1), values(&t2));
            let back =
                |t: [f64; 3], p: [f64; 3], w: [f64; 3]| dot_f(&sub(&p, &t), &sub(&w, &t)) > 0.0;
            if back(t1v, v1, w1) || back(t2v, v2, w2) {
                arc = ellipse_arc(&t1, &t2, &vs, vs4, a, factor, true);
            }
        }
    }
    WrapAction::Mandatory(SurfacePath {
        r1: scale_c(&t1, 1.0 / factor),
        r2: scale_c(&t2, 1.0 / factor),
        length: arc.length / factor,
    })
}

/// The two points where the segment `p1`–`p2` crosses the ellipsoid (the first nearer
/// `p1`), or `None` when it does not cross it twice between its ends.
fn crossing<T: Scalar>(p1: &Vec3<T>, p2: &Vec3<T>, a: [f64; 3]) -> Option<(Vec3<T>, Vec3<T>)> {
    let d = sub(p1, p2);
    let f1: Vec3<T> = std::array::from_fn(|k| d[k] / a[k]);
    let f2: Vec3<T> = std::array::from_fn(|k| p2[k] / a[k]);
    let (aa, bb, cc) = (dot(&f1, &f1), dot(&f1, &f2) * 2.0, dot(&f2, &f2) - 1.0);
    let disc = bb * bb - aa * cc * 4.0;
    if disc.value() < 0.0 {
        return None;
    }
    let l1 = (-bb + disc.sqrt()) / (aa * 2.0);
    let l2 = (-bb - disc.sqrt()) / (aa * 2.0);
    let inside = |l: T| 0.0 < l.value() && l.value() < 1.0;
    if !(inside(l1) && inside(l2)) {
        return None;
    }
    Some((add(p2, &scale(&d, l1)), add(p2, &scale(&d, l2))))
}

/// The surface point that fixes the wrapping plane, and the starting points (primal) of
/// the two tangent-point searches.
struct PlanePoint<T> {
    c1: Vec3<T>,
    start: [[f64; 3]; 2],
}

/// `|x|` decided on the primal value.
fn abs<T: Scalar>(x: T) -> T {
    if x.value() < 0.0 {
        -x
    } else {
        x
    }
}

/// OpenSim's choice of `c1` between the crossing points `r1`, `r2` of the segment.
fn plane_point<T: Scalar>(
    p1: &Vec3<T>,
    p2: &Vec3<T>,
    r1: &Vec3<T>,
    r2: &Vec3<T>,
    a: [f64; 3],
    quadrant: Option<WrapQuadrant>,
    method: WrapMethod,
) -> PlanePoint<T> {
    let chord = sub(r2, r1);
    let mu = unit(&sub(p1, p2)).map(abs);
    let mut best = 0;
    for i in 1..3 {
        if mu[i].value() > mu[best].value() {
            best = i;
        }
    }
    // Where the line crosses the coordinate plane most normal to it, and the closest
    // surface point there.
    let t_axial = -r1[best] / chord[best];
    let axial = closest_on_ellipsoid(a, &add(r1, &scale(&chord, t_axial)), Some(best));
    let (c1, fan_weight, mu_best, start) = match method {
        WrapMethod::Midpoint => {
            let mid = add(r1, &scale_c(&chord, 0.5));
            (closest_on_ellipsoid(a, &mid, None), None, mu[best], None)
        }
        WrapMethod::Axial => {
            let t = t_axial.value();
            let start = if t > 0.0 && t < 1.0 {
                None
            } else {
                Some([values(r1), values(r2)])
            };
            (axial, None, mu[best], start)
        }
        WrapMethod::Hybrid => {
            let (c1, weight, m) = hybrid_point(r1, &chord, a, axial, mu[best], t_axial);
            (c1, weight, m, None)
        }
    };
    let start = start.unwrap_or([values(&c1); 2]);
    match quadrant {
        Some(q) if dsign(c1[q.axis].value()) != q.sign => {
            let blend = ((mu_best - MU_BLEND_MIN) / (MU_BLEND_MAX - MU_BLEND_MIN)).rsub(1.0);
            flip_to_quadrant(c1, q.axis, fan_weight.unwrap_or(blend), a)
        }
        _ => PlanePoint { c1, start },
    }
}

/// `c1` mirrored to the active half across the plane `x[axis] = 0`, then moved towards
/// that plane by `weight` (at most 1; none when not positive) and back onto the surface.
fn flip_to_quadrant<T: Scalar>(c1: Vec3<T>, axis: usize, weight: T, a: [f64; 3]) -> PlanePoint<T> {
    let mut c1 = c1;
    c1[axis] = -c1[axis];
    let start = [values(&c1); 2];
    let weight = if weight.value() > 1.0 {
        T::one()
    } else {
        weight
    };
    if weight.value() > 0.0 {
        c1[axis] *= weight.rsub(1.0);
        c1 = closest_on_ellipsoid(a, &c1, None);
    }
    PlanePoint { c1, start }
}

/// The hybrid method's `c1`: the axial point, the fan's point, or a blend of the two by
/// the axis cosine `mu` (faded when the axial crossing `t_axial` nears the chord's ends);
/// with the fan's weight when it was used, and the blended axis cosine.
fn hybrid_point<T: Scalar>(
    r1: &Vec3<T>,
    chord: &Vec3<T>,
    a: [f64; 3],
    axial: Vec3<T>,
    mu: T,
    t_axial: T,
) -> (Vec3<T>, Option<T>, T) {
    let mut mu = mu;
    if mu.value() > MU_BLEND_MIN {
        let t = t_axial.value();
        let s = if !(0.0..=1.0).contains(&t) {
            T::zero()
        } else if t < SV_BOUNDARY_BLEND {
            t_axial / SV_BOUNDARY_BLEND
        } else if t > 1.0 - SV_BOUNDARY_BLEND {
            t_axial.rsub(1.0) / SV_BOUNDARY_BLEND
        } else {
            T::one()
        };
        if s.value() < 1.0 {
            mu = (mu - MU_BLEND_MIN) * s + MU_BLEND_MIN;
        }
    }
    let c1 = axial;
    if mu.value() >= MU_BLEND_MAX {
        return (c1, None, mu);
    }
    let target = add(&add(r1, &scale_c(chord, 0.5)), &fan_direction(r1, chord, a));
    if mu.value() <= MU_BLEND_MIN {
        return (closest_on_ellipsoid(a, &target, None), Some(T::one()), mu);
    }
    let tt = (mu - MU_BLEND_MIN) / (MU_BLEND_MAX - MU_BLEND_MIN);
    let fan = closest_on_ellipsoid(a, &target, None);
    let blend: Vec3<T> = std::array::from_fn(|k| c1[k] * tt + fan[k] * tt.rsub(1.0));
    (
        closest_on_ellipsoid(a, &blend, None),
        Some(tt.rsub(1.0)),
        mu,
    )
}

/// Unit mean of the directions from points along the chord to their closest surface
/// points (OpenSim's "fan").
fn fan_direction<T: Scalar>(r1: &Vec3<T>, chord: &Vec3<T>, a: [f64; 3]) -> Vec3<T> {
    let mut sum = [T::zero(); 3];
    for i in 1..FAN_SAMPLES - 1 {
        let sv = add(r1, &scale_c(chord, i as f64 / FAN_SAMPLES as f64));
        let c = closest_on_ellipsoid(a, &sv, None);
        sum = add(&sum, &unit(&sub(&c, &sv)));
    }
    unit(&sum)
}

/// Convergence threshold of the tangent-point search on the squared residuals.
const TANGENT_TOLERANCE: f64 = 1e-8;

/// The tangent point from `p` to the ellipse cut by the plane `vs · x + vs4 = 0`, found
/// by OpenSim's damped Gauss–Newton search from `start` (`calcTangentPoint`): on the
/// surface, in the plane, with `p` in the tangent plane.
fn tangent_point(p: [f64; 3], vs: [f64; 3], vs4: f64, a: [f64; 3], start: [f64; 3]) -> [f64; 3] {
    let inv2 = a.map(|x| 1.0 / (x * x));
    let residuals = |r: &[f64; 3], d1: f64| {
        let nr: [f64; 3] = std::array::from_fn(|k| 2.0 * r[k] * inv2[k]);
        [
            dot_f(&vs, r) + vs4,
            (0..3).map(|k| r[k] * r[k] * inv2[k]).sum::<f64>() - 1.0,
            dot_f(&nr, r) + d1,
            dot_f(&nr, &p) + d1,
        ]
    };
    let ssq_of = |e: &[f64; 4]| e.iter().map(|x| x * x).sum::<f64>();
    let mut r = start;
    let mut d1 = -(0..3).map(|k| 2.0 * r[k] * inv2[k] * r[k]).sum::<f64>();
    let mut ssq = ssq_of(&residuals(&r, d1));
    let mut ssqo = ssq;
    let mut alpha = 0.01;
    let pm = unit(&p);
    for _ in 0..50 {
        if ssq <= TANGENT_TOLERANCE {
            break;
        }
        let e = residuals(&r, d1);
        // Rows: unknowns (r, d1); columns: residuals.
        let mut jt = [[0.0; 4]; 4];
        for i in 0..3 {
            jt[i] = [
                vs[i],
                2.0 * r[i] * inv2[i],
                4.0 * r[i] * inv2[i],
                2.0 * p[i] * inv2[i],
            ];
        }
        jt[3] = [0.0, 0.0, 1.0, 1.0];
        let pcos = dot_f(&unit(&sub(&p, &r)), &pm);
        let dd = if pcos > 0.1 {
            1.0 - pcos.powi(100)
        } else {
            1.0
        };
        let v: [f64; 4] = std::array::from_fn(|i| -(0..4).map(|j| jt[i][j] * e[j]).sum::<f64>());
        let mut h = [[0.0; 4]; 4];
        for i in 0..4 {
            for j in 0..4 {
                h[i][j] = (0..4).map(|k| jt[i][k] * jt[j][k]).sum();
            }
        }
        let diag: [f64; 4] = std::array::from_fn(|i| h[i][i]);
        let mut step = [0.0; 4];
        // Damped steps, accumulated, until the residual decreases.
        for _ in 0..1000 {
            if ssq < ssqo {
                break;
            }
            for i in 0..4 {
                h[i][i] = diag[i] * (1.0 + alpha);
            }
            step = solve4(h, v).map(|x| dd * x / 16.0);
            apply(&mut r, &mut d1, &step, 1.0);
            ssqo = ssq;
            ssq = ssq_of(&residuals(&r, d1));
            alpha *= 4.0;
        }
        alpha /= 8.0;
        // Then doubled steps while the residual keeps decreasing, less the last one.
        let mut fakt = 0.5;
        for _ in 0..1000 {
            if ssq > ssqo {
                break;
            }
            fakt *= 2.0;
            apply(&mut r, &mut d1, &step, fakt);
            ssqo = ssq;
            ssq = ssq_of(&residuals(&r, d1));
        }
        apply(&mut r, &mut d1, &step, -fakt);
        ssq = ssq_of(&residuals(&r, d1));
        ssqo = ssq;
    }
    r
}

/// Adds `f · step` to the unknowns `(r, d1)`.
fn apply(r: &mut [f64; 3], d1: &mut f64, step: &[f64; 4], f: f64) {
    for k in 0..3 {
        r[k] += step[k] * f;
    }
    *d1 += step[3] * f;
}

/// Solves the 4 × 4 system `h x = v` by Gaussian elimination with partial pivoting.
fn solve4(mut h: [[f64; 4]; 4], mut v: [f64; 4]) -> [f64; 4] {
    for c in 0..4 {
        let piv = (c..4)
            .max_by(|&i, &j| h[i][c].abs().total_cmp(&h[j][c].abs()))
            .unwrap_or(c);
        h.swap(c, piv);
        v.swap(c, piv);
        for i in c + 1..4 {
            let f = h[i][c] / h[c][c];
            let pivot_row = h[c];
            for (hij, hcj) in h[i].iter_mut().zip(pivot_row).skip(c) {
                *hij -= f * hcj;
            }
            v[i] -= f * v[c];
        }
    }
    let mut x = [0.0; 4];
    for c in (0..4).rev() {
        x[c] = (v[c] - (c + 1..4).map(|j| h[c][j] * x[j]).sum::<f64>()) / h[c][c];
    }
    x
}

/// OpenSim's surface polyline between two tangent points: its length (scaled units) and
/// its second and second-to-last points (primal) when it has interior points.
struct Arc<T> {
    length: T,
    inner: Option<[[f64; 3]; 2]>,
}

/// The polyline from `r1` to `r2` along the ellipse in the plane `vs · x + vs4 = 0`,
/// the short way round about its centre point on an axis, or the long way (`far`).
fn ellipse_arc<T: Scalar>(
    r1: &Vec3<T>,
    r2: &Vec3<T>,
    vs: &Vec3<T>,
    vs4: T,
    a: [f64; 3],
    factor: f64,
    far: bool,
) -> Arc<T> {
    let chord = norm(&sub(r1, r2));
    let len = chord.value() / factor;
    let n = (len / SEGMENT_LENGTH) as usize;
    if n <= 1 {
        return Arc {
            length: chord,
            inner: None,
        };
    }
    let n = n.min(MAX_SEGMENTS);
    let mut imax = 0;
    for i in 1..3 {
        if vs[i].value().abs() > vs[imax].value().abs() {
            imax = i;
        }
    }
    let mut a0 = [T::zero(); 3];
    a0[imax] = -vs4 / vs[imax];
    let ar1 = unit(&sub(r1, &a0));
    let ar2 = unit(&sub(r2, &a0));
    let phi0 = arc_angle(ar1, ar2);
    let dphi = if far {
        phi0.rsub(2.0 * std::f64::consts::PI) / -(n as f64)
    } else {
        phi0 / n as f64
    };
    let vsz = unit(&cross(&ar1, &ar2));
    let vsy = cross(&vsz, &ar1);
    let f2: Vec3<T> = std::array::from_fn(|k| a0[k] / a[k]);
    let cc = dot(&f2, &f2) - 1.0;
    let mut length = T::zero();
    let mut prev = *r1;
    let mut inner = [[0.0; 3]; 2];
    for i in 0..n - 1 {
        let phi = dphi * (i + 1) as f64;
        let dir = add(&scale(&ar1, phi.cos()), &scale(&vsy, phi.sin()));
        let f1: Vec3<T> = std::array::from_fn(|k| dir[k] / a[k]);
        let (aa, bb) = (dot(&f1, &f1), dot(&f1, &f2) * 2.0);
        let mu = (-bb + (bb * bb - aa * cc * 4.0).sqrt()) / (aa * 2.0);
        let s = add(&a0, &scale(&dir, mu));
        if i == 0 {
            inner[0] = values(&s);
        }
        if i == n - 2 {
            inner[1] = values(&s);
        }
        length += norm(&sub(&s, &prev));
        prev = s;
    }
    length += norm(&sub(r2, &prev));
    Arc {
        length,
        inner: Some(inner),
    }
}
