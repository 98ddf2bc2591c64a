//! De Groote et al. (2016) Hill-type contraction dynamics in implicit form (FORMULATION 3):
//! normalised tendon force is the state, the equilibrium residual (ESM eq. 13) is a
//! constraint, and every force/length/velocity used downstream (joint torques, metabolics)
//! is returned from this one evaluation.

use stride_ad::Scalar;
use stride_model::Muscle;

use crate::curves::{
    active_force_length, force_velocity, passive_force_length_shifted, tendon_length, tendon_shift,
    tendon_stiffness, TENDON_STIFFNESS_DEFAULT,
};
use crate::MuscleError;

/// Fibre damping coefficient `d` of the contractile element (normalised force per ṽ_M).
pub const FIBER_DAMPING: f64 = 0.01;
/// Muscle tissue density ρ [kg m⁻³] used for the muscle mass.
pub const MUSCLE_DENSITY: f64 = 1059.7;

/// Parameters of one muscle–tendon unit, with derived constants precomputed.
#[derive(Clone, Debug, PartialEq)]
pub struct HillParams {
    name: String,
    f_max: f64,
    l_opt: f64,
    l_ts: f64,
    alpha_opt: f64,
    v_max_norm: f64,
    k_t: f64,
    shift: f64,
    sigma: f64,
    f_st: f64,
    /// Passive fibre curve shift λ and exponent scale κ.
    passive_shift: f64,
    passive_scale: f64,
    /// Width scale of the active force–length curve (≥ 1).
    active_width: f64,
    /// Whether the passive fibre force is zero.
    no_passive: bool,
    /// Steepness of the Bhargava metabolic smooth conditionals.
    metabolic_smoothing: f64,
    // derived
    height: f64,
    v_max: f64,
    mass: f64,
}

impl HillParams {
    /// Builds parameters from raw values: `F_max` [N], `l_opt` [m], `l_ts` [m], `α_opt` [rad],
    /// `v̄_max` [l_opt s⁻¹], specific tension σ [Pa], slow-twitch fraction (0–1); `k_T = 35`.
    #[allow(clippy::too_many_arguments)]
    pub fn new(
        name: &str,
        max_isometric_force: f64,
        optimal_fiber_length: f64,
        tendon_slack_length: f64,
        pennation_angle_at_optimal: f64,
        max_contraction_velocity: f64,
        specific_tension: f64,
        slow_twitch_fraction: f64,
    ) -> Result<Self, MuscleError> {
        let bad = |parameter: &'static str, value: f64, reason: &'static str| {
            Err(MuscleError::InvalidParameter {
                muscle: name.to_string(),
                parameter,
                value,
                reason,
            })
        };
        let positive = "must be finite and > 0";
        if !(max_isometric_force.is_finite() && max_isometric_force > 0.0) {
            return bad("max_isometric_force", max_isometric_force, positive);
        }
        if !(optimal_fiber_length.is_finite() && optimal_fiber_length > 0.0) {
            return bad("optimal_fiber_length", optimal_fiber_length, positive);
        }
        if !(tendon_slack_length.is_finite() && tendon_slack_length > 0.0) {
            return bad("tendon_slack_length", tendon_slack_length, positive);
        }
        if !(pennation_angle_at_optimal.is_finite()
            && (0.0..std::f64::consts::FRAC_PI_2).contains(&pennation_angle_at_optimal))
        {
            return bad(
                "pennation_angle_at_optimal",
                pennation_angle_at_optimal,
                "must lie in [0, π/2) rad",
            );
        }
        if !(max_contraction_velocity.is_finite() && max_contraction_velocity > 0.0) {
            return bad(
                "max_contraction_velocity",
                max_contraction_velocity,
                positive,
            );
        }
        if !(specific_tension.is_finite() && specific_tension > 0.0) {
            return bad("specific_tension", specific_tension, positive);
        }
        if !(slow_twitch_fraction.is_finite() && (0.0..=1.0).contains(&slow_twitch_fraction)) {
            return bad(
                "slow_twitch_fraction",
                slow_twitch_fraction,
                "must lie in [0, 1]",
            );
        }
        let mut p = Self {
            name: name.to_string(),
            f_max: max_isometric_force,
            l_opt: optimal_fiber_length,
            l_ts: tendon_slack_length,
            alpha_opt: pennation_angle_at_optimal,
            v_max_norm: max_contraction_velocity,
            k_t: TENDON_STIFFNESS_DEFAULT,
            shift: 0.0,
            sigma: specific_tension,
            f_st: slow_twitch_fraction,
            passive_shift: 1.0,
            passive_scale: 1.0,
            active_width: 1.0,
            no_passive: false,
            metabolic_smoothing: crate::metabolic::SMOOTHING,
            height: 0.0,
            v_max: 0.0,
            mass: 0.0,
        };
        p.update();
        Ok(p)
    }

    /// Parameters of a model muscle (its `max_contraction_velocity` is in l_opt s⁻¹), with
    /// tendon stiffness 35 × its `tendon_stiffness_scale`, its passive fibre curve shift
    /// and scale and its metabolic smoothing.
    pub fn from_muscle(m: &Muscle) -> Result<Self, MuscleError> {
        let mut p = Self::new(
            &m.name,
            m.max_isometric_force,
            m.optimal_fiber_length,
            m.tendon_slack_length,
            m.pennation_angle_at_optimal,
            m.max_contraction_velocity,
            m.specific_tension,
            m.slow_twitch_fraction,
        )?
        .with_tendon_stiffness(TENDON_STIFFNESS_DEFAULT * m.tendon_stiffness_scale)?
        .with_passive_fibre(m.passive_fibre_shift, m.passive_fibre_scale)?
        .with_active_width(m.active_force_width_scale)?;
        p.no_passive = m.ignore_passive_fiber_force;
        if !(m.metabolic_smoothing.is_finite() && m.metabolic_smoothing > 0.0) {
            return Err(MuscleError::InvalidParameter {
                muscle: m.name.clone(),
                parameter: "metabolic_smoothing",
                value: m.metabolic_smoothing,
                reason: "must be finite and > 0",
            });
        }
        p.metabolic_smoothing = m.metabolic_smoothing;
        Ok(p)
    }

    /// Same muscle with the passive fibre force–length curve shifted to `λ = shift` and its
    /// exponent scaled by `κ = scale`: `f_PE = (exp(4κ(l̃_M − λ)/0.6) − 1 − p1)/p2`
    /// (PREDSIM.md §3.4; 1 and 1 give FORMULATION 3.5's curve).
    pub fn with_passive_fibre(mut self, shift: f64, scale: f64) -> Result<Self, MuscleError> {
        for (parameter, value) in [
            ("passive_fibre_shift", shift),
            ("passive_fibre_scale", scale),
        ] {
            if !(value.is_finite() && value > 0.0) {
                return Err(MuscleError::InvalidParameter {
                    muscle: self.name,
                    parameter,
                    value,
                    reason: "must be finite and > 0",
                });
            }
        }
        self.passive_shift = shift;
        self.passive_scale = scale;
        Ok(self)
    }

    /// Same muscle with the active force–length curve widened by `width` ≥ 1 about its
    /// peak: `f_L` evaluated at `(l̃_M − 1)/width + 1` (OpenSim's
    /// `active_force_width_scale`; 1 gives FORMULATION 3's curve).
    pub fn with_active_width(mut self, width: f64) -> Result<Self, MuscleError> {
        if !(width.is_finite() && width >= 1.0) {
            return Err(MuscleError::InvalidParameter {
                muscle: self.name,
                parameter: "active_force_width_scale",
                value: width,
                reason: "must be finite and ≥ 1",
            });
        }
        self.active_width = width;
        Ok(self)
    }

    fn update(&mut self) {
        self.height = self.l_opt * self.alpha_opt.sin();
        self.v_max = self.v_max_norm * self.l_opt;
        self.mass = self.f_max * self.l_opt * MUSCLE_DENSITY / self.sigma;
        self.shift = tendon_shift(self.k_t);
    }

    /// Same muscle with tendon stiffness `k_T` (curve shifted by `s_T(k_T)`, FORMULATION 3.2).
    pub fn with_tendon_stiffness(mut self, k_t: f64) -> Result<Self, MuscleError> {
        if !(k_t.is_finite() && k_t > 0.0) {
            return Err(MuscleError::InvalidParameter {
                muscle: self.name,
                parameter: "tendon_stiffness",
                value: k_t,
                reason: "must be finite and > 0",
            });
        }
        self.k_t = k_t;
        self.update();
        Ok(self)
    }

    /// Same muscle with maximal contraction velocity `v̄_max` [l_opt s⁻¹] (20 = "doubled").
    pub fn with_max_contraction_velocity(mut self, v_max_norm: f64) -> Result<Self, MuscleError> {
        if !(v_max_norm.is_finite() && v_max_norm > 0.0) {
            return Err(MuscleError::InvalidParameter {
                muscle: self.name,
                parameter: "max_contraction_velocity",
                value: v_max_norm,
                reason: "must be finite and > 0",
            });
        }
        self.v_max_norm = v_max_norm;
        self.update();
        Ok(self)
    }

    /// Same muscle with `F_max` scaled by `factor` (weakness; the mass scales too, as in the code).
    pub fn with_force_scale(mut self, factor: f64) -> Result<Self, MuscleError> {
        if !(factor.is_finite() && factor > 0.0) {
            return Err(MuscleError::InvalidParameter {
                muscle: self.name,
                parameter: "force scale factor",
                value: factor,
                reason: "must be finite and > 0",
            });
        }
        self.f_max *= factor;
        self.update();
        Ok(self)
    }

    /// Muscle name.
    pub fn name(&self) -> &str {
        &self.name
    }
    /// Maximal isometric force `F_max` [N].
    pub fn max_isometric_force(&self) -> f64 {
        self.f_max
    }
    /// Optimal fibre length `l_opt` [m].
    pub fn optimal_fiber_length(&self) -> f64 {
        self.l_opt
    }
    /// Tendon slack length `l_ts` [m].
    pub fn tendon_slack_length(&self) -> f64 {
        self.l_ts
    }
    /// Pennation angle at optimal fibre length [rad].
    pub fn pennation_angle_at_optimal(&self) -> f64 {
        self.alpha_opt
    }
    /// Normalised maximal contraction velocity `v̄_max` [l_opt s⁻¹].
    pub fn max_contraction_velocity_norm(&self) -> f64 {
        self.v_max_norm
    }
    /// Maximal contraction velocity `v_max = v̄_max l_opt` [m s⁻¹].
    pub fn max_contraction_velocity(&self) -> f64 {
        self.v_max
    }
    /// Tendon stiffness `k_T` (dimensionless).
    pub fn tendon_stiffness(&self) -> f64 {
        self.k_t
    }
    /// Tendon curve shift `s_T(k_T)` (normalised force).
    pub fn tendon_shift(&self) -> f64 {
        self.shift
    }
    /// Specific tension σ [Pa].
    pub fn specific_tension(&self) -> f64 {
        self.sigma
    }
    /// Slow-twitch fibre fraction (0–1).
    pub fn slow_twitch_fraction(&self) -> f64 {
        self.f_st
    }
    /// Steepness b of the smooth conditionals of the Bhargava metabolic rate.
    pub fn metabolic_smoothing(&self) -> f64 {
        self.metabolic_smoothing
    }
    /// Muscle mass `F_max l_opt ρ / σ` [kg].
    pub fn mass(&self) -> f64 {
        self.mass
    }
    /// Constant fibre height `l_opt sin α_opt` [m].
    pub fn fiber_height(&self) -> f64 {
        self.height
    }
}

/// Everything one Hill evaluation produces (FORMULATION 3.3–3.7).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct HillOutput<T> {
    /// Equilibrium residual `f_c = (F̃_CE + f_PE) cos α − F̃_T` (dimensionless, unscaled).
    pub residual: T,
    /// Tendon force `F_T = F̃_T F_max` [N].
    pub tendon_force: T,
    /// Contractile-element force `F_CE = F_max (a f_L f_V + d ṽ_M)` [N] (incl. damping).
    pub active_fiber_force: T,
    /// Passive fibre force `F_PE = F_max f_PE` [N].
    pub passive_fiber_force: T,
    /// Active force–length multiplier `f_L` (dimensionless).
    pub force_length: T,
    /// Force–velocity multiplier `f_V` (dimensionless).
    pub force_velocity: T,
    /// Tendon length `l_T` [m].
    pub tendon_length: T,
    /// Fibre length `l_M` [m].
    pub fiber_length: T,
    /// Normalised fibre length `l̃_M = l_M / l_opt`.
    pub fiber_length_norm: T,
    /// Fibre velocity `v_M` [m s⁻¹] (positive = lengthening).
    pub fiber_velocity: T,
    /// Normalised fibre velocity `ṽ_M = v_M / v_max`.
    pub fiber_velocity_norm: T,
    /// Cosine of the pennation angle.
    pub cos_pennation: T,
    /// Muscle mass [kg].
    pub mass: f64,
}

/// Evaluates the implicit Hill model for activation `a`, normalised tendon force `F̃_T`, its
/// time derivative `dF̃_T/dt` [s⁻¹], muscle–tendon length `l_MT` [m] and lengthening
/// velocity `v_MT` [m s⁻¹].
#[inline]
pub fn hill_equilibrium<T: Scalar>(
    p: &HillParams,
    activation: T,
    tendon_force_norm: T,
    tendon_force_norm_rate: T,
    mt_length: T,
    mt_velocity: T,
) -> HillOutput<T> {
    let lt_norm = tendon_length(tendon_force_norm, p.k_t, p.shift);
    let lt = lt_norm * p.l_ts;
    let along = mt_length - lt;
    let lm = (along.sq() + p.height * p.height).sqrt();
    let lm_norm = lm / p.l_opt;
    let cos_a = along / lm;
    let vt = tendon_force_norm_rate * p.l_ts / tendon_stiffness(lt_norm, p.k_t);
    let vm = (mt_velocity - vt) * cos_a;
    let vm_norm = vm / p.v_max;
    let fl = if p.active_width == 1.0 {
        active_force_length(lm_norm)
    } else {
        active_force_length((lm_norm - 1.0) * (1.0 / p.active_width) + 1.0)
    };
    let fv = force_velocity(vm_norm);
    let fpe = if p.no_passive {
        T::zero()
    } else {
        passive_force_length_shifted(lm_norm, p.passive_shift, p.passive_scale)
    };
    let fce_norm = activation * fl * fv + vm_norm * FIBER_DAMPING;
    let residual = (fce_norm + fpe) * cos_a - tendon_force_norm;
    HillOutput {
        residual,
        tendon_force: tendon_force_norm * p.f_max,
        active_fiber_force: fce_norm * p.f_max,
        passive_fiber_force: fpe * p.f_max,
        force_length: fl,
        force_velocity: fv,
        tendon_length: lt,
        fiber_length: lm,
        fiber_length_norm: lm_norm,
        fiber_velocity: vm,
        fiber_velocity_norm: vm_norm,
        cos_pennation: cos_a,
        mass: p.mass,
    }
}

/// Hill parameters of every muscle of a model, in model order (errors name the muscle).
pub fn hill_params_from_model(model: &stride_model::Model) -> Result<Vec<HillParams>, MuscleError> {
    model.muscles.iter().map(HillParams::from_muscle).collect()
}
