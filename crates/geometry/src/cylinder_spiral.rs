//! OpenSim's tangent-height adjustment of a cylinder wrap on a path with more than one
//! wrap (`WrapCylinder::_make_spiral_path`), on primal values.
//!
//! The helix between the two tangent points is cut into chords of 2 mm. While the
//! straight line from an end point to its tangent point and the first chord of the helix
//! make angles with the cylinder axis that differ by more than 0.1°, the tangent point
//! slides along the cylinder: to 1.5 times the way to where the line from the end point
//! to the chord's far point crosses the tangent point's generator. Both tangent points
//! are adjusted from the same helix, then the helix is rebuilt, at most 100 times. A
//! helix shorter than two chords is not adjusted. The adjustment does not always
//! converge: then OpenSim keeps the tangent points of its 100th step, however far along
//! the cylinder they have slid, and so does this module.

use crate::vec3::{dot_f, sub};

/// Length of one chord of the helix [m].
const CHORD: f64 = 0.002;
/// Largest number of adjustments.
const MAX_ADJUSTMENTS: usize = 100;
/// Largest difference of the two angles with the axis left alone [rad] (0.1°).
const TANGENCY: f64 = 0.1 * std::f64::consts::PI / 180.0;

/// Angle [rad] of the helix from the tangent point `t[0]` to `t[1]` (x, y on the
/// cylinder), the long way round with `long`: OpenSim's `acos` of the radial directions.
pub(crate) fn helix_angle(t: [[f64; 2]; 2], long: bool) -> f64 {
    let cross = t[0][0] * t[1][1] - t[0][1] * t[1][0];
    let dot = t[0][0] * t[1][0] + t[0][1] * t[1][1];
    let theta = cross.atan2(dot).abs();
    if long {
        2.0 * std::f64::consts::PI - theta
    } else {
        theta
    }
}

/// Heights `z` [m] of the tangent points `t` (x, y on the cylinder of `radius`) after
/// OpenSim's adjustment towards tangency with the lines to the end points `p` (cylinder
/// frame [m]); `long`: the helix goes the long way round.
pub(crate) fn adjust_heights(
    p: [[f64; 3]; 2],
    t: [[f64; 2]; 2],
    mut z: [f64; 2],
    radius: f64,
    long: bool,
) -> [f64; 2] {
    for _ in 0..MAX_ADJUSTMENTS {
        let theta = helix_angle(t, long);
        let length = (radius * theta).hypot(z[1] - z[0]);
        let chords = ((length / CHORD) as usize).max(1);
        if chords < 2 {
            break;
        }
        let s = 1.0 / chords as f64;
        let near = helix_point(t, z, radius, long, theta, s);
        let far = helix_point(t, z, radius, long, theta, 1.0 - s);
        let r1 = [t[0][0], t[0][1], z[0]];
        let r2 = [t[1][0], t[1][1], z[1]];
        let z1 = slide(p[0], r1, near);
        let z2 = slide(p[1], r2, far);
        if z1.is_none() && z2.is_none() {
            break;
        }
        z = [z1.unwrap_or(z[0]), z2.unwrap_or(z[1])];
    }
    z
}

/// The point at fraction `s` of the helix from the first tangent point to the second
/// (OpenSim's `_calc_spiral_wrap_point`): the radial direction rotated by `s·theta`
/// about the axis (the other way round with `long`), the height linear in `s`.
fn helix_point(
    t: [[f64; 2]; 2],
    z: [f64; 2],
    radius: f64,
    long: bool,
    theta: f64,
    s: f64,
) -> [f64; 3] {
    let u = [t[0][0] / radius, t[0][1] / radius];
    let cross = t[0][0] * t[1][1] - t[0][1] * t[1][0];
    // Rotation axis ±z (the normal of the two radial directions); none when parallel.
    let axis = if cross > 0.0 {
        1.0
    } else if cross < 0.0 {
        -1.0
    } else {
        0.0
    };
    let sense = if long { -1.0 } else { 1.0 };
    let angle = sense * s * theta;
    let (sin, cos) = if axis == 0.0 {
        (0.0, 1.0)
    } else {
        (axis * angle).sin_cos()
    };
    [
        radius * (u[0] * cos - u[1] * sin),
        radius * (u[0] * sin + u[1] * cos),
        z[0] + s * (z[1] - z[0]),
    ]
}

/// OpenSim's `_adjust_tangent_point`: the new height of the tangent point `r` when the
/// line from the end point `p` to `r` and the chord from `r` to `w` make angles with the
/// axis that differ by more than [`TANGENCY`], else `None`.
fn slide(p: [f64; 3], r: [f64; 3], w: [f64; 3]) -> Option<f64> {
    let angle_with_axis = |d: [f64; 3]| {
        let n = dot_f(&d, &d).sqrt();
        if n > 0.0 {
            (d[2] / n).clamp(-1.0, 1.0).acos()
        } else {
            std::f64::consts::FRAC_PI_2
        }
    };
    let alpha = angle_with_axis(sub(&r, &p));
    let omega = angle_with_axis(sub(&w, &r));
    if (alpha - omega).abs() <= TANGENCY {
        return None;
    }
    // Where the line p → w passes closest to the generator of r (a vertical line): the
    // parameter minimising the horizontal distance to r.
    let d = [w[0] - p[0], w[1] - p[1]];
    let dd = d[0] * d[0] + d[1] * d[1];
    if dd == 0.0 {
        return None;
    }
    let s = ((r[0] - p[0]) * d[0] + (r[1] - p[1]) * d[1]) / dd;
    let crossing = p[2] + s * (w[2] - p[2]);
    Some(r[2] + 1.5 * (crossing - r[2]))
}
