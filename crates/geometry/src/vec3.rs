//! Small vector operations on 3-vectors of any scalar, for the wrap-surface geometry.

use crate::kinematics::Vec3;
use stride_ad::Scalar;

/// `a + b`.
pub(crate) fn add<T: Scalar>(a: &Vec3<T>, b: &Vec3<T>) -> Vec3<T> {
    [a[0] + b[0], a[1] + b[1], a[2] + b[2]]
}

/// `a − b`.
pub(crate) fn sub<T: Scalar>(a: &Vec3<T>, b: &Vec3<T>) -> Vec3<T> {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}

/// `a · s` for a scalar `s` of the same type.
pub(crate) fn scale<T: Scalar>(a: &Vec3<T>, s: T) -> Vec3<T> {
    [a[0] * s, a[1] * s, a[2] * s]
}

/// `a · s` for a constant `s`.
pub(crate) fn scale_c<T: Scalar>(a: &Vec3<T>, s: f64) -> Vec3<T> {
    [a[0] * s, a[1] * s, a[2] * s]
}

/// Dot product.
pub(crate) fn dot<T: Scalar>(a: &Vec3<T>, b: &Vec3<T>) -> T {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

/// Cross product `a × b`.
pub(crate) fn cross<T: Scalar>(a: &Vec3<T>, b: &Vec3<T>) -> Vec3<T> {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

/// Euclidean norm.
pub(crate) fn norm<T: Scalar>(a: &Vec3<T>) -> T {
    dot(a, a).sqrt()
}

/// `a / |a|` (a zero vector stays zero).
pub(crate) fn unit<T: Scalar>(a: &Vec3<T>) -> Vec3<T> {
    let n = norm(a);
    if n.value() > 0.0 {
        [a[0] / n, a[1] / n, a[2] / n]
    } else {
        *a
    }
}

/// Dot product of primal values.
pub(crate) fn dot_f(a: &[f64; 3], b: &[f64; 3]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}
