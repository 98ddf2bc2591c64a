//! The point of an ellipsoid (or of an ellipse) closest to a given point, as OpenSim's
//! `WrapEllipsoid::findClosestPoint` computes it (Eberly's Newton iteration on the
//! Lagrange parameter, with its special cases for points on a coordinate plane).
//!
//! The iteration runs on primal values; one implicit-function step then carries the
//! derivatives, so the result is generic over the scalar with exact first derivatives.

use crate::kinematics::Vec3;
use stride_ad::Scalar;

/// OpenSim's `ROUNDOFF_ERROR`: a coordinate this close to 0 counts as on a plane.
const ROUNDOFF: f64 = 2e-13;

/// Largest number of Newton steps.
const MAX_STEPS: usize = 64;

/// Newton convergence threshold on the secular function.
const TOLERANCE: f64 = 1e-9;

/// Closest point of the ellipse `(x/a)² + (y/b)² = 1` to `(u, v)` (same units).
pub(crate) fn closest_on_ellipse<T: Scalar>(a: f64, b: f64, u: T, v: T) -> [T; 2] {
    let (uv, vv) = (u.value(), v.value());
    let (a2, b2) = (a * a, b * b);
    let (near_x, near_y) = (uv.abs() <= ROUNDOFF, vv.abs() <= ROUNDOFF);
    let signed = |s: f64, r: f64| T::cst(if s < 0.0 { -r } else { r });
    if near_x && near_y {
        return if a < b {
            [signed(uv, a), v]
        } else {
            [u, signed(vv, b)]
        };
    }
    if near_x {
        if a >= b || vv.abs() >= b - a2 / b {
            return [u, signed(vv, b)];
        }
        let y = v * (b2 / (b2 - a2));
        let ydb = y / b;
        return [ydb.sq().rsub(1.0).sqrt() * a, y];
    }
    if near_y {
        if b >= a || uv.abs() >= a - b2 / a {
            return [signed(uv, a), v];
        }
        let x = u * (a2 / (a2 - b2));
        let xda = x / a;
        return [x, xda.sq().rsub(1.0).sqrt() * b];
    }
    let secular = |t: f64, u2: T, v2: T| {
        let (p, q) = (t + a2, t + b2);
        (u2 * (-a2 * q * q) - v2 * (b2 * p * p)) + p * p * q * q
    };
    let slope = |t: f64| {
        let (p, q) = (t + a2, t + b2);
        2.0 * (p * q * (p + q) - a2 * uv * uv * q - b2 * vv * vv * p)
    };
    let mut t = if (uv / a).powi(2) + (vv / b).powi(2) < 1.0 {
        0.0
    } else {
        a.max(b) * uv.hypot(vv)
    };
    for _ in 0..MAX_STEPS {
        let f = secular(t, T::cst(uv * uv), T::cst(vv * vv)).value();
        if f.abs() < TOLERANCE {
            break;
        }
        t -= f / slope(t);
    }
    let f = secular(t, u.sq(), v.sq());
    let tt = T::cst(t) - (f - f.value()) / slope(t);
    [u * a2 / (tt + a2), v * b2 / (tt + b2)]
}

/// Closest point of the ellipsoid with semi-axes `a` to `p` (same units). `plane`: the
/// coordinate (0, 1, 2) taken to be zero, reducing the problem to the ellipse in the
/// other two; `None` picks one when `p` lies on coordinate planes, as OpenSim does.
pub(crate) fn closest_on_ellipsoid<T: Scalar>(
    a: [f64; 3],
    p: &Vec3<T>,
    plane: Option<usize>,
) -> Vec3<T> {
    let plane = plane.or_else(|| {
        (0..3)
            .filter(|&i| p[i].value().abs() <= ROUNDOFF)
            .min_by(|&i, &j| {
                let sum = |k: usize| a[(k + 1) % 3] + a[(k + 2) % 3];
                sum(i).total_cmp(&sum(j))
            })
    });
    if let Some(k) = plane {
        let (i, j) = ((k + 1) % 3, (k + 2) % 3);
        let [x, y] = closest_on_ellipse(a[i], a[j], p[i], p[j]);
        let mut out = *p;
        out[i] = x;
        out[j] = y;
        return out;
    }
    let pv = [p[0].value(), p[1].value(), p[2].value()];
    let a2 = [a[0] * a[0], a[1] * a[1], a[2] * a[2]];
    let w: [f64; 3] = std::array::from_fn(|k| a2[k] * pv[k] * pv[k]);
    let secular = |t: f64, w: [T; 3]| {
        let [pp, qq, rr] = [
            (t + a2[0]).powi(2),
            (t + a2[1]).powi(2),
            (t + a2[2]).powi(2),
        ];
        (w[0] * (-qq * rr) - w[1] * (pp * rr) - w[2] * (pp * qq)) + pp * qq * rr
    };
    let slope = |t: f64| {
        let [pp, qq, rr] = [t + a2[0], t + a2[1], t + a2[2]];
        let (pq, pr, qr) = (pp * qq, pp * rr, qq * rr);
        2.0 * (pq * rr * (qr + pr + pq)
            - w[0] * qr * (qq + rr)
            - w[1] * pr * (pp + rr)
            - w[2] * pq * (pp + qq))
    };
    let inside = (0..3).map(|k| (pv[k] / a[k]).powi(2)).sum::<f64>() < 1.0;
    let mut t = if inside {
        0.0
    } else {
        a[0].max(a[1]).max(a[2]) * (pv[0] * pv[0] + pv[1] * pv[1] + pv[2] * pv[2]).sqrt()
    };
    for _ in 0..MAX_STEPS {
        let f = secular(t, w.map(T::cst)).value();
        if f.abs() < TOLERANCE {
            break;
        }
        t -= f / slope(t);
    }
    let wt: [T; 3] = std::array::from_fn(|k| p[k].sq() * a2[k]);
    let f = secular(t, wt);
    let tt = T::cst(t) - (f - f.value()) / slope(t);
    std::array::from_fn(|k| p[k] * a2[k] / (tt + a2[k]))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The closest point lies on the surface and the offset is along the normal.
    #[test]
    fn closest_point_is_on_the_surface_along_the_normal() {
        let a = [1.2, 0.7, 0.9];
        for p in [[1.5, 0.4, -0.8], [0.3, 0.2, 0.1], [-2.0, 1.0, 0.5]] {
            let c = closest_on_ellipsoid(a, &p, None);
            let e: f64 = (0..3).map(|k| (c[k] / a[k]).powi(2)).sum();
            assert!((e - 1.0).abs() < 1e-7, "{p:?}: {e}");
            let n: [f64; 3] = std::array::from_fn(|k| c[k] / (a[k] * a[k]));
            let d: [f64; 3] = std::array::from_fn(|k| p[k] - c[k]);
            let cr = crate::vec3::cross(&n, &d);
            assert!(
                crate::vec3::norm(&cr) < 1e-7 * crate::vec3::norm(&n),
                "{p:?}"
            );
        }
    }
}
