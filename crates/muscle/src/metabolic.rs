//! Metabolic energy models (FORMULATION 7), smooth versions, evaluated per muscle from the
//! outputs of [`crate::hill_equilibrium`] with activation used as excitation. The Umberger
//! family uses the July-2020 fixed normalised maximal velocity `v̄_max = v_max / l_opt`.

use serde::{Deserialize, Serialize};
use stride_ad::{smooth_step, Scalar};

use crate::{HillOutput, HillParams};

/// Steepness `b` of the smooth conditionals `σ_b(x) = ½ + ½ tanh(b x)`.
pub const SMOOTHING: f64 = 10.0;
/// Basal metabolic rate coefficient [W kg⁻¹] (exponent 1 on body mass).
pub const BASAL_RATE_PER_KG: f64 = 1.2;
/// Lower bound of the heat rate per unit muscle mass [W kg⁻¹].
pub const MIN_HEAT_RATE_PER_KG: f64 = 1.0;
/// Aerobic scaling factor S of the Umberger-family models.
const UMBERGER_S: f64 = 1.5;

/// Which metabolic energy model to evaluate (ESM Table S2).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash, Serialize, Deserialize)]
pub enum MetabolicModel {
    /// Bhargava et al. (2004), the paper's nominal model.
    #[default]
    #[serde(rename = "bhargava2004")]
    Bhargava2004,
    /// Umberger et al. (2003): negative work and full lengthening heat included.
    #[serde(rename = "umberger2003")]
    Umberger2003,
    /// Umberger (2010): negative work excluded, lengthening heat scaled by 0.3.
    #[serde(rename = "umberger2010")]
    Umberger2010,
    /// Uchida et al. (2016): Umberger 2003 with orderly recruitment and non-negative total.
    #[serde(rename = "uchida2016")]
    Uchida2016,
    /// Umberger (2010) with the lengthening heat of 2003 (α_L = 4 α_ST).
    #[serde(rename = "umberger2010_hl")]
    Umberger2010LengtheningHeat2003,
    /// Umberger (2010) with the negative work of 2003.
    #[serde(rename = "umberger2010_neg")]
    Umberger2010NegativeWork2003,
}

/// Per-muscle metabolic rate and its parts [W]; `total = activation_heat + maintenance_heat
/// + shortening_heat + heat_floor + work_rate`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MetabolicRate<T> {
    /// Activation heat rate [W] (Umberger family: activation + maintenance heat together).
    pub activation_heat: T,
    /// Maintenance heat rate [W] (zero for the Umberger family, see `activation_heat`).
    pub maintenance_heat: T,
    /// Shortening/lengthening heat rate [W], after the non-negative-total correction.
    pub shortening_heat: T,
    /// Heat added [W] so that the heat rate is at least 1 W per kg of muscle.
    pub heat_floor: T,
    /// Mechanical work rate of the contractile element [W].
    pub work_rate: T,
    /// Total rate `Ė_m` [W] (heat + work, no basal rate).
    pub total: T,
}

/// Basal metabolic rate `1.2 W/kg × body mass` [W].
pub fn basal_metabolic_rate(body_mass: f64) -> f64 {
    BASAL_RATE_PER_KG * body_mass
}

impl MetabolicModel {
    /// All six models, in the order of ESM Table S2.
    pub const ALL: [MetabolicModel; 6] = [
        MetabolicModel::Bhargava2004,
        MetabolicModel::Umberger2003,
        MetabolicModel::Umberger2010,
        MetabolicModel::Uchida2016,
        MetabolicModel::Umberger2010LengtheningHeat2003,
        MetabolicModel::Umberger2010NegativeWork2003,
    ];

    /// Metabolic rate of one muscle [W] at activation `a` from its Hill outputs.
    #[inline]
    pub fn rate<T: Scalar>(
        self,
        p: &HillParams,
        activation: T,
        hill: &HillOutput<T>,
    ) -> MetabolicRate<T> {
        match self {
            MetabolicModel::Bhargava2004 => bhargava2004(p, activation, hill),
            MetabolicModel::Umberger2003 => umberger(p, activation, hill, UmbergerVariant::U2003),
            MetabolicModel::Umberger2010 => umberger(p, activation, hill, UmbergerVariant::U2010),
            MetabolicModel::Uchida2016 => umberger(p, activation, hill, UmbergerVariant::U2016),
            MetabolicModel::Umberger2010LengtheningHeat2003 => {
                umberger(p, activation, hill, UmbergerVariant::U2010Hl)
            }
            MetabolicModel::Umberger2010NegativeWork2003 => {
                umberger(p, activation, hill, UmbergerVariant::U2010Neg)
            }
        }
    }
}

/// Smoothly raises `x` to at least `floor`: `x + (floor − x) σ_b(floor − x)`; returns the
/// increment.
#[inline]
fn floor_increment<T: Scalar>(x: T, floor: f64, b: f64) -> T {
    let gap = x.rsub(floor);
    gap * smooth_step(gap, b)
}

/// Bhargava et al. (2004), smooth version (FORMULATION 7.1).
fn bhargava2004<T: Scalar>(p: &HillParams, a: T, h: &HillOutput<T>) -> MetabolicRate<T> {
    use std::f64::consts::FRAC_PI_2;
    let mass = p.mass();
    let f_st = p.slow_twitch_fraction();
    let u_st = (a * FRAC_PI_2).sin() * f_st;
    let u_ft = (a * FRAC_PI_2).cos().rsub(1.0) * (1.0 - f_st);
    let activation_heat = (u_st * 40.0 + u_ft * 133.0) * mass;
    let maintenance_heat = h.fiber_length_norm * (u_st * 74.0 + u_ft * 111.0) * mass;
    let vm = h.fiber_velocity;
    let f_iso = a * h.force_length * p.max_isometric_force();
    let f_fib = h.active_fiber_force + h.passive_fiber_force;
    let b = p.metabolic_smoothing();
    let lengthening = smooth_step(vm, b);
    let shortening = lengthening.rsub(1.0);
    let alpha = (f_iso * 0.16 + f_fib * 0.18) * shortening + f_fib * 0.157 * lengthening;
    let mut shortening_heat = -alpha * vm;
    let work_rate = -h.active_fiber_force * vm * shortening;
    let e0 = activation_heat + maintenance_heat + shortening_heat + work_rate;
    shortening_heat -= e0 * smooth_step(-e0, b);
    let heat_per_kg = (activation_heat + maintenance_heat + shortening_heat) / mass;
    let heat_floor = floor_increment(heat_per_kg, MIN_HEAT_RATE_PER_KG, b) * mass;
    let total = activation_heat + maintenance_heat + shortening_heat + heat_floor + work_rate;
    MetabolicRate {
        activation_heat,
        maintenance_heat,
        shortening_heat,
        heat_floor,
        work_rate,
        total,
    }
}

/// Which member of the Umberger family (FORMULATION 7.2–7.5).
#[derive(Clone, Copy, PartialEq, Eq)]
enum UmbergerVariant {
    U2003,
    U2010,
    U2016,
    U2010Hl,
    U2010Neg,
}

impl UmbergerVariant {
    /// Lengthening heat coefficient relative to α_ST.
    fn lengthening_factor(self) -> f64 {
        match self {
            UmbergerVariant::U2003 | UmbergerVariant::U2016 | UmbergerVariant::U2010Hl => 4.0,
            UmbergerVariant::U2010 | UmbergerVariant::U2010Neg => 0.3,
        }
    }
    /// Whether negative mechanical work is counted.
    fn negative_work(self) -> bool {
        matches!(
            self,
            UmbergerVariant::U2003 | UmbergerVariant::U2016 | UmbergerVariant::U2010Neg
        )
    }
}

/// Umberger et al. (2003) family, per-kg formulation scaled by the muscle mass.
fn umberger<T: Scalar>(
    p: &HillParams,
    a: T,
    h: &HillOutput<T>,
    variant: UmbergerVariant,
) -> MetabolicRate<T> {
    use std::f64::consts::FRAC_PI_2;
    let mass = p.mass();
    let f_st_param = p.slow_twitch_fraction();
    // Fibre-type fractions: fixed, or orderly recruitment (Uchida 2016) with u = a.
    let (f_st, f_ft) = if variant == UmbergerVariant::U2016 {
        let slow = (a * FRAC_PI_2).sin() * f_st_param;
        let fast = (a * FRAC_PI_2).cos().rsub(1.0) * (1.0 - f_st_param);
        let ratio = slow / (slow + fast);
        let f_st = (ratio - 1.0) * smooth_step(a, SMOOTHING) + 1.0;
        (f_st, f_st.rsub(1.0))
    } else {
        (T::cst(f_st_param), T::cst(1.0 - f_st_param))
    };
    let act = a; // effective activation A = a (excitation = activation)
    let v_bar_max = p.max_contraction_velocity_norm();
    let alpha_ft = 153.0 / v_bar_max;
    let alpha_st = 100.0 / (v_bar_max / 2.5);
    let alpha_l = variant.lengthening_factor() * alpha_st;

    let desc = smooth_step(h.fiber_length_norm - 1.0, SMOOTHING);
    let fl = h.force_length;
    let h_am = (f_ft * 128.0 + 25.0) * ((fl * 0.6 - 0.6) * desc + 1.0);
    let e_am = h_am * act.powf(0.6) * UMBERGER_S;

    let v_bar = h.fiber_velocity / p.optimal_fiber_length();
    let lengthening = smooth_step(v_bar, SMOOTHING);
    let shortening = lengthening.rsub(1.0);
    let h_sl =
        v_bar * lengthening * alpha_l - (f_st * alpha_st + f_ft * alpha_ft) * v_bar * shortening;
    let act_scale = act * lengthening + act.sq() * shortening;
    let length_scale = desc.rsub(1.0) + fl * desc;
    let mut e_sl = h_sl * UMBERGER_S * act_scale * length_scale;

    let mut w = -h.active_fiber_force * h.fiber_velocity / mass;
    if !variant.negative_work() {
        w *= shortening;
    }
    if variant == UmbergerVariant::U2016 {
        let e0 = e_am + e_sl + w;
        e_sl -= e0 * smooth_step(-e0, SMOOTHING);
    }
    let heat = e_am + e_sl;
    let floor = floor_increment(heat, MIN_HEAT_RATE_PER_KG, SMOOTHING);

    let activation_heat = e_am * mass;
    let shortening_heat = e_sl * mass;
    let heat_floor = floor * mass;
    let work_rate = w * mass;
    MetabolicRate {
        activation_heat,
        maintenance_heat: T::zero(),
        shortening_heat,
        heat_floor,
        work_rate,
        total: activation_heat + shortening_heat + heat_floor + work_rate,
    }
}
