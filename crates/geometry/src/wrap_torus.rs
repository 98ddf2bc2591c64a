//! Wrapping one straight path segment over a torus, in the frame of the wrap object, as
//! OpenSim 4.x `WrapTorus::wrapLine` does.
//!
//! OpenSim does not wrap over the torus itself: it finds the point `c` of the torus's
//! centre circle (radius `outer_radius`, about the z axis) nearest to the segment
//! ([`crate::ring_closest`]), places there a cylinder of radius `inner_radius`, 10 km
//! long, tangent to the circle (x axis towards the torus's axis, y along −z), and wraps
//! the segment over that cylinder with the quadrant `+x`: the path bends around the side
//! of the tube that faces the hole. A path passing outside the ring is therefore wrapped
//! around the hole's side of the tube too, a long detour — OpenSim's result, reproduced.
//! The torus's own quadrant only chooses between the two candidates for `c`.
//!
//! The outcome is always "wrapped, may not be the best" (never mandatory). When the
//! cylinder does not wrap, OpenSim still reports a wrap, without tangent points: the path
//! stays straight ([`WrapAction::Degenerate`]).

use crate::ring_closest::closest_on_ring;
use crate::wrap_shapes::{wrap_cylinder, SurfacePath, WrapAction};
use stride_model::WrapQuadrant;

/// Length of the cylinder OpenSim wraps over [m].
const CYLINDER_LENGTH: f64 = 10_000.0;

/// Wraps the segment `a`–`b` (torus frame [m]) over the torus with tube radius `inner`
/// and centre-circle radius `outer` [m]; `single`: the path has no other wrap.
pub(crate) fn wrap_torus(
    a: &[f64; 3],
    b: &[f64; 3],
    inner: f64,
    outer: f64,
    quadrant: Option<WrapQuadrant>,
    single: bool,
) -> WrapAction<f64> {
    let Some(c) = closest_on_ring(*a, *b, outer, quadrant) else {
        return WrapAction::NoWrap;
    };
    let frame = TubeFrame::at(c);
    let inward = WrapQuadrant { axis: 0, sign: 1 };
    let (pa, pb) = (frame.to_local(a), frame.to_local(b));
    match wrap_cylinder(&pa, &pb, inner, CYLINDER_LENGTH, Some(inward), single) {
        WrapAction::Wrapped(sp) | WrapAction::Mandatory(sp) => WrapAction::Wrapped(SurfacePath {
            r1: frame.to_torus(&sp.r1),
            r2: frame.to_torus(&sp.r2),
            length: sp.length,
        }),
        _ => WrapAction::Degenerate,
    }
}

/// The frame of OpenSim's cylinder on the centre circle: origin `c`, axes in the torus
/// frame.
struct TubeFrame {
    origin: [f64; 3],
    axes: [[f64; 3]; 3],
}

impl TubeFrame {
    /// The frame at the circle point `c` (z = 0): x towards the torus's axis, y = −z,
    /// z = x × y along the circle.
    fn at(c: [f64; 3]) -> Self {
        let n = (c[0] * c[0] + c[1] * c[1]).sqrt();
        let x = if n > 0.0 {
            [-c[0] / n, -c[1] / n, 0.0]
        } else {
            [0.0; 3]
        };
        let y = [0.0, 0.0, -1.0];
        let z = crate::vec3::cross(&x, &y);
        Self {
            origin: c,
            axes: [x, y, z],
        }
    }

    /// Torus-frame point → cylinder frame.
    fn to_local(&self, p: &[f64; 3]) -> [f64; 3] {
        let d = crate::vec3::sub(p, &self.origin);
        self.axes.map(|e| crate::vec3::dot_f(&e, &d))
    }

    /// Cylinder-frame point → torus frame.
    fn to_torus(&self, p: &[f64; 3]) -> [f64; 3] {
        std::array::from_fn(|k| {
            self.origin[k]
                + self.axes[0][k] * p[0]
                + self.axes[1][k] * p[1]
                + self.axes[2][k] * p[2]
        })
    }
}
