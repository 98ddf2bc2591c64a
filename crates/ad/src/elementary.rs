//! Value, first and second derivative of the elementary functions of [`crate::Scalar`].
//!
//! Shared by the dual numbers and the tape so every derivative type uses the same formulas.

/// `[sin x, cos x, -sin x]` (x in rad).
#[inline]
pub fn sin3(x: f64) -> [f64; 3] {
    let (s, c) = x.sin_cos();
    [s, c, -s]
}

/// `[cos x, -sin x, -cos x]` (x in rad).
#[inline]
pub fn cos3(x: f64) -> [f64; 3] {
    let (s, c) = x.sin_cos();
    [c, -s, -c]
}

/// `[e^x, e^x, e^x]`.
#[inline]
pub fn exp3(x: f64) -> [f64; 3] {
    let e = x.exp();
    [e, e, e]
}

/// `[ln x, 1/x, -1/x²]`.
#[inline]
pub fn ln3(x: f64) -> [f64; 3] {
    let r = 1.0 / x;
    [x.ln(), r, -r * r]
}

/// `[√x, 1/(2√x), -1/(4 x √x)]`.
#[inline]
pub fn sqrt3(x: f64) -> [f64; 3] {
    let s = x.sqrt();
    let d = 0.5 / s;
    [s, d, -0.5 * d / x]
}

/// `[tanh x, 1 - tanh² x, -2 tanh x (1 - tanh² x)]`.
#[inline]
pub fn tanh3(x: f64) -> [f64; 3] {
    let t = x.tanh();
    let d = 1.0 - t * t;
    [t, d, -2.0 * t * d]
}

/// `[xᵖ, p xᵖ⁻¹, p (p-1) xᵖ⁻²]` for a constant exponent `p` (value exactly `f64::powf`).
#[inline]
pub fn powf3(x: f64, p: f64) -> [f64; 3] {
    if p == 0.0 {
        return [1.0, 0.0, 0.0];
    }
    if p == 1.0 {
        return [x, 1.0, 0.0];
    }
    [
        x.powf(p),
        p * x.powf(p - 1.0),
        p * (p - 1.0) * x.powf(p - 2.0),
    ]
}

/// `[1/x, -1/x², 2/x³]`.
#[inline]
pub fn recip3(x: f64) -> [f64; 3] {
    let r = 1.0 / x;
    let r2 = r * r;
    [r, -r2, 2.0 * r2 * r]
}
