//! Dimensionless characteristic curves of the De Groote et al. (2016) Hill-type muscle
//! (FORMULATION 3.2 and 3.5): active and passive fibre force–length, force–velocity, and the
//! tendon force–length relation with its inverse and stiffness shift.

use stride_ad::Scalar;

/// Gaussian coefficients `[b1, b2, b3, b4]` of the three terms of the active force–length curve.
pub const FL_PARAMS: [[f64; 4]; 3] = [
    [
        0.814_483_478_343_008_4,
        1.055_033_428_970_574_5,
        0.162_384_573_599_573_73,
        0.063_303_448_465_464_64,
    ],
    [
        0.433_004_984_392_647_34,
        0.716_775_413_397_760_3,
        -0.029_947_116_970_695_593,
        0.200_356_847_296_187_83,
    ],
    [0.1, 1.0, 0.353_553_390_593_273_8, 0.0],
];

/// Force–velocity coefficients `[e1, e2, e3, e4]` (dimensionless).
pub const FV_PARAMS: [f64; 4] = [
    -0.318_323_436_899_127_45,
    -8.149_156_043_475_25,
    -0.374_121_508_647_863_1,
    0.885_644_059_915_003_8,
];

/// Passive force–length exponent shape `k_PE` (dimensionless).
pub const FPE_KPE: f64 = 4.0;
/// Passive force–length strain at which `f_PE` reaches its scale `e0` (dimensionless).
pub const FPE_E0: f64 = 0.6;
/// Passive force–length offset `p1` (makes `f_PE(0.2) = 0`).
pub const FPE_P1: f64 = -0.995_172_050_006_168_6;
/// Passive force–length scale `p2 = e^4 − 1`.
pub const FPE_P2: f64 = 53.598_150_033_144_236;

/// Standard tendon stiffness `k_T` of the paper (dimensionless).
pub const TENDON_STIFFNESS_DEFAULT: f64 = 35.0;
/// Tendon curve scale `c1 = 0.2`.
const TENDON_C1: f64 = 0.2;
/// Tendon curve length offset `c2 = 0.995` (normalised length).
const TENDON_C2: f64 = 0.995;
/// Tendon curve force offset `c3 = 0.25` (normalised force).
const TENDON_C3: f64 = 0.25;

/// Active force–length multiplier `f_L(l̃_M)` (sum of three Gaussians), `l̃_M = l_M/l_opt`.
#[inline]
pub fn active_force_length<T: Scalar>(lm_norm: T) -> T {
    let mut sum = T::zero();
    for [b1, b2, b3, b4] in FL_PARAMS {
        let num = lm_norm - b2;
        let den = lm_norm * b4 + b3;
        sum += ((num / den).sq() * -0.5).exp() * b1;
    }
    sum
}

/// Force–velocity multiplier `f_V(ṽ_M)`, `ṽ_M = v_M / v_max` (positive = lengthening).
#[inline]
pub fn force_velocity<T: Scalar>(vm_norm: T) -> T {
    let [e1, e2, e3, e4] = FV_PARAMS;
    let x = vm_norm * e2 + e3;
    (x + (x.sq() + 1.0).sqrt()).ln() * e1 + e4
}

/// Passive fibre force–length `f_PE(l̃_M)` (normalised by `F_max`).
#[inline]
pub fn passive_force_length<T: Scalar>(lm_norm: T) -> T {
    passive_force_length_shifted(lm_norm, 1.0, 1.0)
}

/// Passive fibre force–length with PredSim's shift λ and exponent scale κ (PREDSIM.md
/// §3.4): `f_PE = (exp(κ k_PE (l̃_M − λ)/e0) − 1 − p1)/p2` with the unchanged p1, p2;
/// λ = κ = 1 is [`passive_force_length`].
#[inline]
pub fn passive_force_length_shifted<T: Scalar>(lm_norm: T, shift: f64, scale: f64) -> T {
    (((lm_norm - shift) * (FPE_KPE / FPE_E0 * scale)).exp() - 1.0 - FPE_P1) / FPE_P2
}

/// Tendon curve shift `s_T(k_T)` making the force at `l̃_T = 1` equal to the `k_T = 35` curve.
#[inline]
pub fn tendon_shift(k_t: f64) -> f64 {
    0.2 * ((TENDON_STIFFNESS_DEFAULT * 0.005).exp() - (k_t * 0.005).exp())
}

/// Normalised tendon force `F̃_T(l̃_T) = 0.2 e^{k_T(l̃_T − 0.995)} − 0.25 + s_T`.
#[inline]
pub fn tendon_force<T: Scalar>(lt_norm: T, k_t: f64, shift: f64) -> T {
    ((lt_norm - TENDON_C2) * k_t).exp() * TENDON_C1 - TENDON_C3 + shift
}

/// Normalised tendon length `l̃_T(F̃_T) = ln(5(F̃_T + 0.25 − s_T))/k_T + 0.995` (inverse curve).
#[inline]
pub fn tendon_length<T: Scalar>(ft_norm: T, k_t: f64, shift: f64) -> T {
    ((ft_norm + (TENDON_C3 - shift)) * (1.0 / TENDON_C1)).ln() / k_t + TENDON_C2
}

/// Tendon stiffness `dF̃_T/dl̃_T = 0.2 k_T e^{k_T(l̃_T − 0.995)}` (dimensionless).
#[inline]
pub fn tendon_stiffness<T: Scalar>(lt_norm: T, k_t: f64) -> T {
    ((lt_norm - TENDON_C2) * k_t).exp() * (TENDON_C1 * k_t)
}
