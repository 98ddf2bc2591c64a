//! Muscle activation dynamics (Raasch model, implicit formulation, FORMULATION 2) and the
//! first-order arm actuator dynamics (FORMULATION 6.2).

use stride_ad::Scalar;

/// Activation time constant τ_a [s].
pub const TAU_ACTIVATION: f64 = 0.015;
/// Deactivation time constant τ_d [s].
pub const TAU_DEACTIVATION: f64 = 0.060;
/// Lower bound of muscle activation (baseline activation, dimensionless).
pub const MIN_ACTIVATION: f64 = 0.05;
/// Upper bound of muscle activation (dimensionless).
pub const MAX_ACTIVATION: f64 = 1.0;
/// Arm actuator excitation-to-activation time constant τ [s].
pub const ARM_TAU: f64 = 0.035;
/// Arm actuator torque per unit activation [N m].
pub const ARM_TORQUE_SCALE: f64 = 150.0;
/// Arm joint damping B [N m s rad⁻¹].
pub const ARM_DAMPING: f64 = 0.1;

/// Raasch activation dynamics with time constants τ_a, τ_d [s].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ActivationDynamics {
    /// Activation time constant τ_a [s].
    pub tau_activation: f64,
    /// Deactivation time constant τ_d [s].
    pub tau_deactivation: f64,
}

impl Default for ActivationDynamics {
    /// τ_a = 0.015 s, τ_d = 0.06 s (the paper).
    fn default() -> Self {
        Self {
            tau_activation: TAU_ACTIVATION,
            tau_deactivation: TAU_DEACTIVATION,
        }
    }
}

impl ActivationDynamics {
    /// Explicit rate `ȧ = (e − a)(c1 e + c2)` [s⁻¹] for excitation `e` and activation `a`.
    #[inline]
    pub fn rate<T: Scalar>(&self, excitation: T, activation: T) -> T {
        let (c1, c2) = self.coefficients();
        (excitation - activation) * (excitation * c1 + c2)
    }

    /// `(c1, c2) = (1/τ_a − 1/τ_d, 1/τ_d)` [s⁻¹].
    #[inline]
    pub fn coefficients(&self) -> (f64, f64) {
        (
            1.0 / self.tau_activation - 1.0 / self.tau_deactivation,
            1.0 / self.tau_deactivation,
        )
    }

    /// The two linear path-constraint values `[ȧ + a/τ_d, ȧ + a/τ_a]` [s⁻¹] standing for
    /// `e ≥ 0` and `e ≤ 1`; see [`Self::constraint_bounds`].
    #[inline]
    pub fn constraints<T: Scalar>(&self, activation: T, activation_rate: T) -> [T; 2] {
        [
            activation_rate + activation / self.tau_deactivation,
            activation_rate + activation / self.tau_activation,
        ]
    }

    /// Bounds `[lower, upper]` [s⁻¹] of the two constraint values of [`Self::constraints`]:
    /// `[0, +∞)` and `(−∞, 1/τ_a]`.
    pub fn constraint_bounds(&self) -> [[f64; 2]; 2] {
        [
            [0.0, f64::INFINITY],
            [f64::NEG_INFINITY, 1.0 / self.tau_activation],
        ]
    }

    /// Range `[ȧ_min, ȧ_max]` [s⁻¹] allowed by the constraints at activation `a`.
    pub fn rate_range(&self, activation: f64) -> [f64; 2] {
        [
            -activation / self.tau_deactivation,
            (1.0 - activation) / self.tau_activation,
        ]
    }

    /// Simple bounds of `ȧ` [s⁻¹]: `[−1/τ_d, 1/τ_a]` (control bounds times s_da = 100).
    pub fn rate_bounds(&self) -> [f64; 2] {
        [-1.0 / self.tau_deactivation, 1.0 / self.tau_activation]
    }

    /// Simple bounds of the activation: `[0.05, 1]`.
    pub fn activation_bounds(&self) -> [f64; 2] {
        [MIN_ACTIVATION, MAX_ACTIVATION]
    }

    /// Excitation recovered from `a` and `ȧ` [s⁻¹] in post-processing (FORMULATION 2):
    /// `a + τ_d ȧ` when `ȧ ≤ 0`, else the positive root of the Raasch quadratic.
    #[inline]
    pub fn excitation<T: Scalar>(&self, activation: T, activation_rate: T) -> T {
        let (c1, c2) = self.coefficients();
        let down = activation + activation_rate * self.tau_deactivation;
        let disc = (activation * c1 + c2).sq() + activation_rate * (4.0 * c1);
        // Guard the square root on the branch that is not selected (ȧ ≤ 0 may make it negative).
        let disc = disc.fmax(T::zero());
        let up = (activation * c1 - c2 + disc.sqrt()) / (2.0 * c1);
        T::select_pos(activation_rate, up, down)
    }
}

/// Arm activation rate `da/dt = (e − a)/τ` [s⁻¹] with τ = 0.035 s.
#[inline]
pub fn arm_activation_rate<T: Scalar>(excitation: T, activation: T) -> T {
    (excitation - activation) / ARM_TAU
}

/// Arm actuator torque `150 a` [N m] (without damping; see [`crate::passive::arm_damping_torque`]).
#[inline]
pub fn arm_torque<T: Scalar>(activation: T) -> T {
    activation * ARM_TORQUE_SCALE
}
