//! Outcome measures of a predicted gait cycle (FORMULATION 11.3): cost of transport,
//! stride length and frequency, step width, stance and double support, ground reaction
//! force peaks, and the condition measures of [`crate::measures`].

use crate::measures::ConditionMeasures;
use crate::node::NodeModel;
use crate::problem::{GaitProblem, ProblemError, GRAVITY};
use crate::trajectory::{
    prominent_peaks, MeshSolution, Trajectory, CONTACT_THRESHOLD, PEAK_MIN_HEIGHT,
    PEAK_MIN_PROMINENCE,
};
use serde::Serialize;

/// Outcome measures of a predicted gait (FORMULATION 11.3).
#[derive(Clone, Debug, Serialize)]
pub struct Outcomes {
    /// Metabolic cost of transport with Bhargava 2004, basal rate included [J kg⁻¹ m⁻¹].
    pub cost_of_transport: f64,
    /// Cost of transport with the cost function's metabolic model [J kg⁻¹ m⁻¹].
    pub cost_of_transport_cost_model: f64,
    /// Stride length [m].
    pub stride_length: f64,
    /// Step width [m]; NaN (written as null) for a planar model, which has none.
    pub step_width: f64,
    /// Stride frequency [strides s⁻¹].
    pub stride_frequency: f64,
    /// Average forward speed [m s⁻¹].
    pub speed: f64,
    /// Gait cycle duration [s].
    pub cycle_duration: f64,
    /// Fraction of the cycle with the right foot in contact.
    pub stance_fraction_right: f64,
    /// Fraction of the cycle with the left foot in contact.
    pub stance_fraction_left: f64,
    /// Fraction of the cycle with both feet in contact.
    pub double_support_fraction: f64,
    /// Number of separate stance phases of the right foot over the cycle.
    pub stance_phases_right: usize,
    /// Number of peaks of the right vertical ground reaction force over the cycle: local
    /// maxima above half body weight with a prominence of at least 5% body weight.
    pub vertical_grf_peaks_right: usize,
    /// Trunk sway and per-leg stance measures compared between conditions.
    #[serde(flatten)]
    pub conditions: ConditionMeasures,
}

impl GaitProblem {
    /// Outcome measures of a reconstructed gait cycle.
    pub fn outcomes(
        &self,
        node: &NodeModel,
        m: &MeshSolution,
        cycle: &Trajectory,
    ) -> Result<Outcomes, ProblemError> {
        let l = &self.layout;
        let ns = cycle.time.len();
        let mut e_bh = Vec::with_capacity(ns);
        let mut e_cost = Vec::with_capacity(ns);
        let basal = 1.2 * self.body_mass;
        for out in self.cycle_samples(node, cycle)? {
            e_bh.push(basal + out.metabolic_bhargava.iter().sum::<f64>());
            e_cost.push(basal + out.metabolic.iter().sum::<f64>());
        }
        let tx = self.gait.forward_translation;
        let d_gc = cycle.q[ns - 1][tx] - cycle.q[0][tx];
        let trapz = |e: &[f64]| -> f64 {
            (0..ns - 1)
                .map(|i| 0.5 * (e[i] + e[i + 1]) * (cycle.time[i + 1] - cycle.time[i]))
                .sum()
        };
        let cot = trapz(&e_bh) / (self.body_mass * d_gc);
        let cot_cost = trapz(&e_cost) / (self.body_mass * d_gc);
        let dist = |a: [f64; 3], b: [f64; 3]| {
            ((a[0] - b[0]).powi(2) + (a[1] - b[1]).powi(2) + (a[2] - b[2]).powi(2)).sqrt()
        };
        let n = l.n;
        let stride_length = if self.is_half_cycle() {
            dist(m.calcaneus[n][0], m.calcaneus[0][0]) + dist(m.calcaneus[n][1], m.calcaneus[0][1])
        } else {
            0.5 * (dist(m.calcaneus[n][0], m.calcaneus[0][0])
                + dist(m.calcaneus[n][1], m.calcaneus[0][1]))
        };
        let step_width = if self.gait.is_planar(&self.model) {
            f64::NAN
        } else {
            m.calcaneus
                .iter()
                .map(|c| (c[0][2] - c[1][2]).abs())
                .sum::<f64>()
                / m.calcaneus.len() as f64
        };
        let speed = m.distance / m.duration;
        let contact_r: Vec<bool> = cycle
            .grf_right
            .iter()
            .map(|f| f[1] > CONTACT_THRESHOLD)
            .collect();
        let contact_l: Vec<bool> = cycle
            .grf_left
            .iter()
            .map(|f| f[1] > CONTACT_THRESHOLD)
            .collect();
        let frac = |v: &[bool]| v.iter().filter(|&&b| b).count() as f64 / v.len() as f64;
        let both: Vec<bool> = contact_r
            .iter()
            .zip(&contact_l)
            .map(|(a, b)| *a && *b)
            .collect();
        let phases = (0..ns)
            .filter(|&i| contact_r[i] && !contact_r[(i + ns - 1) % ns])
            .count();
        let vy: Vec<f64> = cycle.grf_right.iter().map(|f| f[1]).collect();
        let weight = self.body_mass * GRAVITY;
        let peaks =
            prominent_peaks(&vy, PEAK_MIN_PROMINENCE * weight, PEAK_MIN_HEIGHT * weight).len();
        let cycle_duration = if self.is_half_cycle() {
            2.0 * m.duration
        } else {
            m.duration
        };
        Ok(Outcomes {
            cost_of_transport: cot,
            cost_of_transport_cost_model: cot_cost,
            stride_length,
            step_width,
            stride_frequency: speed / stride_length,
            speed,
            cycle_duration,
            stance_fraction_right: frac(&contact_r),
            stance_fraction_left: frac(&contact_l),
            double_support_fraction: frac(&both),
            stance_phases_right: phases,
            vertical_grf_peaks_right: peaks,
            conditions: self.condition_measures(cycle)?,
        })
    }
}
