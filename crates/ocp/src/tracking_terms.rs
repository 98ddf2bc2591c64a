//! The tracking cost of one collocation point (FORMULATION 12.6, ESM eq. 34): squared
//! differences between model and measured joint angles, ground reaction forces and torques
//! and joint torques, each normalised by its scale and averaged over its elements, plus the
//! activation effort and the slack-control penalty.

use serde::{Deserialize, Serialize};
use stride_ad::Scalar;

/// Scale of the joint-torque differences [N m] (the paper divides them by 150).
pub const TORQUE_SCALE: f64 = 150.0;

/// Weights of the tracking cost (dimensionless). Defaults: the paper's (ESM eq. 34) except
/// kinematics 300 (paper 10) and GRF and GRT 10 (paper 1): with the paper's weights on this
/// transcription the joint angles of gait_1 are tracked to 4–8° at 50 intervals.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct TrackingWeights {
    /// Joint angles (scaled coordinates).
    pub kinematics: f64,
    /// Ground reaction forces.
    pub grf: f64,
    /// Ground reaction torques about the ground origin.
    pub grt: f64,
    /// Net joint torques.
    pub torques: f64,
    /// Muscle activations squared.
    pub activations: f64,
    /// Slack controls (scaled accelerations, activation and tendon-force derivatives).
    pub slack_controls: f64,
}

impl Default for TrackingWeights {
    fn default() -> Self {
        Self {
            kinematics: 300.0,
            grf: 10.0,
            grt: 10.0,
            torques: 10.0,
            activations: 1.0,
            slack_controls: 0.001,
        }
    }
}

/// What the node function of a tracking problem tracks and how; the measured values are
/// constant node inputs in the order of [`TrackingTerms::n_data`]: scaled coordinates,
/// GRF (right x y z, left x y z) [N], GRT about the ground origin (same order) [N m], joint
/// torques [N m or N], root generalised forces [N m or N].
#[derive(Clone, Debug)]
pub struct TrackingTerms {
    /// Problem indices of the tracked coordinates.
    pub coordinates: Vec<usize>,
    /// Problem indices of the coordinates whose generalised force is tracked.
    pub torques: Vec<usize>,
    /// Number of root coordinates (their residuals equal measured values).
    pub n_root: usize,
    /// Scale of each GRF component [N].
    pub grf_scale: [f64; 6],
    /// Scale of each GRT component [N m].
    pub grt_scale: [f64; 6],
    /// Weights.
    pub weights: TrackingWeights,
}

/// The model quantities at one collocation point that the tracking cost compares with data.
pub struct TrackedModel<'a, T: Scalar> {
    /// Node inputs (scaled variables).
    pub x: &'a [T],
    /// Constant inputs (measured values).
    pub data: &'a [T],
    /// Offset of the scaled coordinates in `x`.
    pub q_offset: usize,
    /// Offset of the scaled accelerations in `x`.
    pub qdd_offset: usize,
    /// Number of problem coordinates.
    pub nq: usize,
    /// Generalised forces of the problem coordinates [N m or N].
    pub tau: &'a [T],
    /// Contact force per foot (right, left) [N].
    pub force: &'a [[T; 3]],
    /// Contact moment per foot about the ground origin [N m].
    pub moment: &'a [[T; 3]],
}

impl TrackingTerms {
    /// Offset of the GRF in the constants.
    pub fn grf_offset(&self) -> usize {
        self.coordinates.len()
    }
    /// Offset of the GRT.
    pub fn grt_offset(&self) -> usize {
        self.grf_offset() + 6
    }
    /// Offset of the joint torques.
    pub fn torque_offset(&self) -> usize {
        self.grt_offset() + 6
    }
    /// Offset of the root generalised forces.
    pub fn root_offset(&self) -> usize {
        self.torque_offset() + self.torques.len()
    }
    /// Number of constant inputs per collocation point.
    pub fn n_data(&self) -> usize {
        self.root_offset() + self.n_root
    }

    /// The cost integrand given the model quantities and the mean squared activation.
    pub fn cost<T: Scalar>(&self, m: &TrackedModel<T>, mean_a2: T) -> T {
        let w = &self.weights;
        let mut sq = T::zero();
        for (k, &i) in self.coordinates.iter().enumerate() {
            sq += (m.x[m.q_offset + i] - m.data[k]).sq();
        }
        let mut l = sq * (w.kinematics / self.coordinates.len().max(1) as f64);
        let (mut f2, mut t2) = (T::zero(), T::zero());
        for c in 0..6 {
            let (g, d) = (c / 3, c % 3);
            f2 += ((m.force[g][d] - m.data[self.grf_offset() + c]) / self.grf_scale[c]).sq();
            t2 += ((m.moment[g][d] - m.data[self.grt_offset() + c]) / self.grt_scale[c]).sq();
        }
        l += f2 * (w.grf / 6.0) + t2 * (w.grt / 6.0);
        let mut tq = T::zero();
        for (k, &i) in self.torques.iter().enumerate() {
            tq += ((m.tau[i] - m.data[self.torque_offset() + k]) / TORQUE_SCALE).sq();
        }
        l += tq * (w.torques / self.torques.len().max(1) as f64);
        let mut acc = T::zero();
        for i in 0..m.nq {
            acc += m.x[m.qdd_offset + i].sq();
        }
        l + mean_a2 * w.activations + acc * (w.slack_controls / m.nq.max(1) as f64)
    }
}
