//! Small fixed-size 3-D algebra generic over the scalar (no allocation).

use stride_ad::Scalar;

/// A 3-vector (position [m], velocity [m s⁻¹], force [N], ...), components x, y, z.
pub type Vec3<T> = [T; 3];
/// A 3×3 matrix stored by rows (rotation matrices map body to ground coordinates).
pub type Mat3<T> = [[T; 3]; 3];

/// Zero vector.
#[inline]
pub fn zero3<T: Scalar>() -> Vec3<T> {
    [T::zero(); 3]
}

/// Constant vector from plain numbers.
#[inline]
pub fn cst3<T: Scalar>(v: [f64; 3]) -> Vec3<T> {
    [T::cst(v[0]), T::cst(v[1]), T::cst(v[2])]
}

/// Sum `a + b`.
#[inline]
pub fn add<T: Scalar>(a: Vec3<T>, b: Vec3<T>) -> Vec3<T> {
    [a[0] + b[0], a[1] + b[1], a[2] + b[2]]
}

/// Difference `a − b`.
#[inline]
pub fn sub<T: Scalar>(a: Vec3<T>, b: Vec3<T>) -> Vec3<T> {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}

/// Scaled vector `s a`.
#[inline]
pub fn scale<T: Scalar>(a: Vec3<T>, s: T) -> Vec3<T> {
    [a[0] * s, a[1] * s, a[2] * s]
}

/// Vector scaled by a constant `c a`.
#[inline]
pub fn scale_f<T: Scalar>(a: Vec3<T>, c: f64) -> Vec3<T> {
    [a[0] * c, a[1] * c, a[2] * c]
}

/// Dot product.
#[inline]
pub fn dot<T: Scalar>(a: Vec3<T>, b: Vec3<T>) -> T {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

/// Dot product with a constant vector.
#[inline]
pub fn dot_f<T: Scalar>(a: Vec3<T>, b: [f64; 3]) -> T {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

/// Cross product `a × b`.
#[inline]
pub fn cross<T: Scalar>(a: Vec3<T>, b: Vec3<T>) -> Vec3<T> {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

/// Identity matrix.
#[inline]
pub fn identity<T: Scalar>() -> Mat3<T> {
    let (o, z) = (T::one(), T::zero());
    [[o, z, z], [z, o, z], [z, z, o]]
}

/// Constant matrix from plain numbers.
#[inline]
pub fn cst33<T: Scalar>(m: [[f64; 3]; 3]) -> Mat3<T> {
    [cst3(m[0]), cst3(m[1]), cst3(m[2])]
}

/// Matrix–vector product `m v`.
#[inline]
pub fn mat_vec<T: Scalar>(m: &Mat3<T>, v: Vec3<T>) -> Vec3<T> {
    [dot(m[0], v), dot(m[1], v), dot(m[2], v)]
}

/// Matrix times a constant vector `m v`.
#[inline]
pub fn mat_vec_f<T: Scalar>(m: &Mat3<T>, v: [f64; 3]) -> Vec3<T> {
    [dot_f(m[0], v), dot_f(m[1], v), dot_f(m[2], v)]
}

/// Transposed matrix–vector product `mᵀ v`.
#[inline]
pub fn mat_t_vec<T: Scalar>(m: &Mat3<T>, v: Vec3<T>) -> Vec3<T> {
    [
        m[0][0] * v[0] + m[1][0] * v[1] + m[2][0] * v[2],
        m[0][1] * v[0] + m[1][1] * v[1] + m[2][1] * v[2],
        m[0][2] * v[0] + m[1][2] * v[1] + m[2][2] * v[2],
    ]
}

/// Matrix product `a b`.
#[inline]
pub fn mat_mul<T: Scalar>(a: &Mat3<T>, b: &Mat3<T>) -> Mat3<T> {
    let mut out = [[T::zero(); 3]; 3];
    for (i, row) in out.iter_mut().enumerate() {
        for (j, v) in row.iter_mut().enumerate() {
            *v = a[i][0] * b[0][j] + a[i][1] * b[1][j] + a[i][2] * b[2][j];
        }
    }
    out
}

/// Matrix product with a constant right factor `a b`.
#[inline]
pub fn mat_mul_f<T: Scalar>(a: &Mat3<T>, b: &[[f64; 3]; 3]) -> Mat3<T> {
    let mut out = [[T::zero(); 3]; 3];
    for (i, row) in out.iter_mut().enumerate() {
        for (j, v) in row.iter_mut().enumerate() {
            *v = a[i][0] * b[0][j] + a[i][1] * b[1][j] + a[i][2] * b[2][j];
        }
    }
    out
}

/// Rotation about the constant unit axis `a` by the angle whose cosine is `c` and sine
/// is `s` (Rodrigues).
#[inline]
pub fn axis_angle<T: Scalar>(a: [f64; 3], c: T, s: T) -> Mat3<T> {
    let v = c.rsub(1.0);
    let mut m = [[T::zero(); 3]; 3];
    for (i, row) in m.iter_mut().enumerate() {
        for (j, e) in row.iter_mut().enumerate() {
            *e = v * (a[i] * a[j]);
            if i == j {
                *e += c;
            }
        }
    }
    m[0][1] -= s * a[2];
    m[0][2] += s * a[1];
    m[1][0] += s * a[2];
    m[1][2] -= s * a[0];
    m[2][0] -= s * a[1];
    m[2][1] += s * a[0];
    m
}

/// `m R(a, θ)` for a constant unit axis `a`, given `c = cos θ` and `s = sin θ`; a fast
/// path for coordinate axes (±x, ±y, ±z) touches only the two affected columns.
#[inline]
pub fn rotate_columns<T: Scalar>(m: &Mat3<T>, a: [f64; 3], c: T, s: T) -> Mat3<T> {
    // Coordinate axis k with sign σ: columns i, j (cyclic after k) rotate in their plane.
    let nz: Vec3<bool> = [a[0] != 0.0, a[1] != 0.0, a[2] != 0.0];
    let count = nz.iter().filter(|b| **b).count();
    if count == 1 {
        let k = nz.iter().position(|b| *b).unwrap_or(0);
        let sign = a[k].signum();
        let (i, j) = ((k + 1) % 3, (k + 2) % 3);
        let s = if sign > 0.0 { s } else { -s };
        let mut out = *m;
        for row in out.iter_mut() {
            let (mi, mj) = (row[i], row[j]);
            row[i] = mi * c + mj * s;
            row[j] = mj * c - mi * s;
        }
        return out;
    }
    mat_mul(m, &axis_angle(a, c, s))
}

/// Constant rotation matrix of body-fixed X–Y–Z Euler angles [rad] (OpenSim orientation).
pub fn body_fixed_xyz(angles: [f64; 3]) -> [[f64; 3]; 3] {
    let rot = |a: [f64; 3], t: f64| axis_angle::<f64>(a, t.cos(), t.sin());
    let rx = rot([1.0, 0.0, 0.0], angles[0]);
    let ry = rot([0.0, 1.0, 0.0], angles[1]);
    let rz = rot([0.0, 0.0, 1.0], angles[2]);
    mat_mul(&mat_mul(&rx, &ry), &rz)
}

/// Transpose of a constant matrix.
pub fn transpose_f(m: &[[f64; 3]; 3]) -> [[f64; 3]; 3] {
    let mut t = [[0.0; 3]; 3];
    for i in 0..3 {
        for j in 0..3 {
            t[i][j] = m[j][i];
        }
    }
    t
}

/// Constant matrix times constant vector.
pub fn mat_vec_ff(m: &[[f64; 3]; 3], v: [f64; 3]) -> [f64; 3] {
    mat_vec_f::<f64>(m, v)
}
