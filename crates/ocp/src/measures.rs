//! Outcome measures the paper compares between conditions (FORMULATION 11.3, 13.2): trunk
//! sway, and per leg the stance-phase knee flexion, ankle dorsiflexion, hip abduction torque
//! and ankle plantarflexion torques (weakness, co-contraction and prosthesis studies).
//!
//! Stance is the longest run of samples with that foot's vertical ground reaction force
//! above [`CONTACT_THRESHOLD`](crate::trajectory::CONTACT_THRESHOLD), taken periodically over
//! the reconstructed cycle. Angle signs follow the model: ankle dorsiflexion and hip
//! adduction are positive (OpenSim convention), knee flexion is the direction of the larger
//! end of the knee coordinate's range (negative in gait2392, positive in Rajagopal).

use crate::problem::{GaitProblem, ProblemError};
use crate::trajectory::{Trajectory, CONTACT_THRESHOLD};
use serde::{Deserialize, Serialize};
use stride_multibody::spatial::Mat3;

/// Body whose frontal-plane rotation is the trunk sway.
pub const TRUNK_BODY: &str = "torso";

/// Stance-phase measures of one leg; `None` when the model lacks the coordinate or the foot
/// never touches the ground.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct LegMeasures {
    /// Fraction of the cycle in stance (longest contact phase).
    pub stance_fraction: Option<f64>,
    /// Largest knee flexion over the first half of stance (loading response and mid
    /// stance, before the knee flexes for push-off) [deg].
    pub peak_knee_flexion: Option<f64>,
    /// Largest ankle dorsiflexion during stance [deg].
    pub peak_ankle_dorsiflexion: Option<f64>,
    /// Largest hip abduction torque (net joint torque) during stance [N m kg⁻¹].
    pub peak_hip_abduction_torque: Option<f64>,
    /// Largest ankle plantarflexion torque during stance [N m kg⁻¹].
    pub peak_ankle_plantarflexion_torque: Option<f64>,
    /// Mean ankle plantarflexion torque over the first half of stance (early and mid
    /// stance) [N m kg⁻¹].
    pub early_stance_ankle_plantarflexion_torque: Option<f64>,
}

/// Condition measures of a reconstructed gait cycle.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct ConditionMeasures {
    /// Range over the cycle of the torso's rotation about the ground forward axis (first
    /// angle of its body-fixed X–Y–Z orientation) [deg]; `None` without a `torso` body or
    /// for a planar model.
    pub trunk_sway: Option<f64>,
    /// Right leg.
    pub right: LegMeasures,
    /// Left leg.
    pub left: LegMeasures,
}

/// Rotation about the ground x axis [rad] of an orientation (body → ground) written as
/// body-fixed X–Y–Z angles: R = Rx(a)·Ry(b)·Rz(c), whose third column is
/// (sin b, −sin a cos b, cos a cos b).
pub fn frontal_rotation(r: &Mat3<f64>) -> f64 {
    (-r[1][2]).atan2(r[2][2])
}

/// Sample indices of the longest contact phase of a periodic contact series, in time order
/// from its first sample (wrapping past the end); empty without contact.
pub fn stance_phase(contact: &[bool]) -> Vec<usize> {
    let n = contact.len();
    if n == 0 || !contact.iter().any(|&c| c) {
        return Vec::new();
    }
    if contact.iter().all(|&c| c) {
        return (0..n).collect();
    }
    let mut best: (usize, usize) = (0, 0); // (start, length)
    for start in (0..n).filter(|&i| contact[i] && !contact[(i + n - 1) % n]) {
        let len = (0..n).take_while(|&k| contact[(start + k) % n]).count();
        if len > best.1 {
            best = (start, len);
        }
    }
    (0..best.1).map(|k| (best.0 + k) % n).collect()
}

/// Largest value of `f` over `idx` (`None` for no samples).
fn peak(idx: &[usize], f: impl Fn(usize) -> f64) -> Option<f64> {
    idx.iter().map(|&i| f(i)).reduce(f64::max)
}

impl GaitProblem {
    /// Model speed vector (every model coordinate, locked ones at rest) from a vector in
    /// problem order [rad s⁻¹ or m s⁻¹].
    pub fn model_speeds(&self, v: &[f64]) -> Vec<f64> {
        let mut vm = vec![0.0; self.model.coordinates.len()];
        for (i, c) in self.gait.coordinates.iter().enumerate() {
            vm[c.model_index] = v[i];
        }
        vm
    }

    /// Model coordinate vector (every model coordinate, locked ones at their value) from a
    /// vector in problem order [rad or m].
    pub fn model_coordinates(&self, q: &[f64]) -> Vec<f64> {
        let mut qm = self.model_speeds(q);
        for &(c, val) in &self.gait.locked {
            qm[c] = val;
        }
        qm
    }

    /// Problem index of a free coordinate by name.
    fn free_coordinate(&self, name: &str) -> Option<usize> {
        self.gait.coordinates.iter().position(|c| c.name == name)
    }

    /// Stance measures of the leg with suffix `side` (`r` or `l`).
    fn leg_measures(&self, cycle: &Trajectory, side: &str) -> LegMeasures {
        let grf = if side == "r" {
            &cycle.grf_right
        } else {
            &cycle.grf_left
        };
        let contact: Vec<bool> = grf.iter().map(|f| f[1] > CONTACT_THRESHOLD).collect();
        let stance = stance_phase(&contact);
        if stance.is_empty() {
            return LegMeasures::default();
        }
        let deg = 180.0 / std::f64::consts::PI;
        let mass = self.body_mass;
        let coord = |base: &str| self.free_coordinate(&format!("{base}_{side}"));
        let knee = coord("knee_angle").map(|i| {
            let r = self.model.coordinates[self.gait.coordinates[i].model_index].range;
            let sign = if r[1].abs() > r[0].abs() { 1.0 } else { -1.0 };
            (i, sign)
        });
        let ankle = coord("ankle_angle");
        let hip_add = coord("hip_adduction");
        let first_half = &stance[..stance.len().div_ceil(2)];
        LegMeasures {
            stance_fraction: Some(stance.len() as f64 / contact.len() as f64),
            peak_knee_flexion: knee
                .and_then(|(k, s)| peak(first_half, |i| s * cycle.q[i][k] * deg)),
            peak_ankle_dorsiflexion: ankle.and_then(|k| peak(&stance, |i| cycle.q[i][k] * deg)),
            peak_hip_abduction_torque: hip_add
                .and_then(|k| peak(&stance, |i| -cycle.torque[i][k] / mass)),
            peak_ankle_plantarflexion_torque: ankle
                .and_then(|k| peak(&stance, |i| -cycle.torque[i][k] / mass)),
            early_stance_ankle_plantarflexion_torque: ankle.map(|k| {
                first_half
                    .iter()
                    .map(|&i| -cycle.torque[i][k] / mass)
                    .sum::<f64>()
                    / first_half.len() as f64
            }),
        }
    }

    /// Rotation of the torso about the ground forward axis [rad] (first body-fixed X–Y–Z
    /// angle) at each coordinate sample (problem order); `None` without a `torso` body.
    pub fn trunk_frontal_angles(&self, q: &[Vec<f64>]) -> Result<Option<Vec<f64>>, ProblemError> {
        let Some(torso) = self.model.body_index(TRUNK_BODY) else {
            return Ok(None);
        };
        let model = &self.model;
        let err = |e: stride_multibody::MultibodyError| ProblemError::Model(e.to_string());
        let mut data = stride_multibody::Data::<f64>::new(model).map_err(err)?;
        let zero = vec![0.0; model.coordinates.len()];
        let mut angles = Vec::with_capacity(q.len());
        for qs in q {
            let qm = self.model_coordinates(qs);
            stride_multibody::forward_kinematics(model, &mut data, &qm, &zero).map_err(err)?;
            angles.push(frontal_rotation(&data.rotation[torso]));
        }
        Ok(Some(angles))
    }

    /// Trunk sway [deg] over a cycle (see [`ConditionMeasures::trunk_sway`]).
    fn trunk_sway(&self, cycle: &Trajectory) -> Result<Option<f64>, ProblemError> {
        if self.gait.is_planar(&self.model) {
            return Ok(None);
        }
        let Some(angles) = self.trunk_frontal_angles(&cycle.q)? else {
            return Ok(None);
        };
        let lo = angles.iter().copied().fold(f64::INFINITY, f64::min);
        let hi = angles.iter().copied().fold(f64::NEG_INFINITY, f64::max);
        Ok((hi >= lo).then(|| (hi - lo).to_degrees()))
    }

    /// Condition measures of a reconstructed gait cycle (see the module documentation).
    pub fn condition_measures(
        &self,
        cycle: &Trajectory,
    ) -> Result<ConditionMeasures, ProblemError> {
        Ok(ConditionMeasures {
            trunk_sway: self.trunk_sway(cycle)?,
            right: self.leg_measures(cycle, "r"),
            left: self.leg_measures(cycle, "l"),
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn rx(a: f64) -> Mat3<f64> {
        let (s, c) = a.sin_cos();
        [[1.0, 0.0, 0.0], [0.0, c, -s], [0.0, s, c]]
    }
    fn ry(a: f64) -> Mat3<f64> {
        let (s, c) = a.sin_cos();
        [[c, 0.0, s], [0.0, 1.0, 0.0], [-s, 0.0, c]]
    }
    fn rz(a: f64) -> Mat3<f64> {
        let (s, c) = a.sin_cos();
        [[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]]
    }
    fn mul(a: &Mat3<f64>, b: &Mat3<f64>) -> Mat3<f64> {
        let mut m = [[0.0; 3]; 3];
        for i in 0..3 {
            for j in 0..3 {
                m[i][j] = (0..3).map(|k| a[i][k] * b[k][j]).sum();
            }
        }
        m
    }

    #[test]
    fn frontal_rotation_recovers_the_first_body_fixed_angle() {
        for &(a, b, c) in &[(0.1, 0.2, -0.3), (-0.25, -0.4, 1.0), (0.05, 0.0, 0.0)] {
            let r = mul(&mul(&rx(a), &ry(b)), &rz(c));
            assert!((frontal_rotation(&r) - a).abs() < 1e-12, "{a} {b} {c}");
        }
    }

    #[test]
    fn stance_phase_takes_the_longest_run_and_wraps() {
        let c = [true, true, false, false, true, true, true, false];
        assert_eq!(stance_phase(&c), vec![4, 5, 6]);
        let w = [true, false, false, false, true, true];
        assert_eq!(stance_phase(&w), vec![4, 5, 0]);
        assert!(stance_phase(&[false; 4]).is_empty());
        assert_eq!(stance_phase(&[true; 3]), vec![0, 1, 2]);
    }

    /// A cycle of the default model at rest except for the named coordinates [rad].
    fn cycle(
        problem: &GaitProblem,
        n: usize,
        set: &dyn Fn(usize, &str) -> Option<f64>,
    ) -> Trajectory {
        let nq = problem.gait.coordinates.len();
        let mut t = Trajectory::default();
        for k in 0..n {
            let q: Vec<f64> = problem
                .gait
                .coordinates
                .iter()
                .map(|c| set(k, &c.name).unwrap_or(0.0))
                .collect();
            t.time.push(k as f64 * 0.01);
            t.q.push(q);
            t.torque.push(vec![0.0; nq]);
            t.grf_right.push([0.0; 3]);
            t.grf_left.push([0.0; 3]);
        }
        t
    }

    fn problem() -> GaitProblem {
        let model = stride_model::default_model::default_model();
        let settings = crate::settings::ProblemSettings {
            mesh_intervals: 10,
            ..Default::default()
        };
        GaitProblem::new(&model, &settings, &crate::data::walking_half_cycle()).unwrap()
    }

    /// Pelvis list and lumbar bending both rotate the torso about the forward axis at zero
    /// tilt and rotation, so the sway is the range of their sum.
    #[test]
    fn trunk_sway_is_the_range_of_list_plus_bending() {
        let p = problem();
        let n = 20;
        let phase = |k: usize| (2.0 * std::f64::consts::PI * k as f64 / n as f64).sin();
        let t = cycle(&p, n, &|k, name| match name {
            "pelvis_list" => Some(5f64.to_radians() * phase(k)),
            "lumbar_bending" => Some(3f64.to_radians() * phase(k)),
            "hip_flexion_r" => Some(0.3 * phase(k)),
            _ => None,
        });
        let sway = p.condition_measures(&t).unwrap().trunk_sway.unwrap();
        let expect = (0..n).map(|k| 8.0 * phase(k)).fold(f64::MIN, f64::max)
            - (0..n).map(|k| 8.0 * phase(k)).fold(f64::MAX, f64::min);
        assert!((sway - expect).abs() < 1e-9, "{sway} vs {expect}");
    }

    /// Stance measures read the stance samples only, with the model's sign conventions.
    #[test]
    fn leg_measures_cover_stance_only() {
        let p = problem();
        let n = 10;
        // Right knee (gait2392: flexion negative) flexes 30° at sample 2 (early stance), 40°
        // at sample 5 (late stance) and 60° at sample 8 (swing); ankle dorsiflexes 15° at
        // sample 3.
        let mut t = cycle(&p, n, &|k, name| match (name, k) {
            ("knee_angle_r", 2) => Some(-30f64.to_radians()),
            ("knee_angle_r", 5) => Some(-40f64.to_radians()),
            ("knee_angle_r", 8) => Some(-60f64.to_radians()),
            ("ankle_angle_r", 3) => Some(15f64.to_radians()),
            _ => None,
        });
        let ankle = p
            .gait
            .coordinates
            .iter()
            .position(|c| c.name == "ankle_angle_r")
            .unwrap();
        let hip = p
            .gait
            .coordinates
            .iter()
            .position(|c| c.name == "hip_adduction_r")
            .unwrap();
        for k in 0..6 {
            t.grf_right[k][1] = 600.0;
            t.torque[k][ankle] = -10.0 * k as f64; // plantarflexion rising through stance
            t.torque[k][hip] = -20.0;
        }
        t.torque[8][ankle] = -500.0; // swing: ignored
        let m = p.condition_measures(&t).unwrap();
        let r = &m.right;
        let mass = p.body_mass;
        assert_eq!(r.stance_fraction, Some(0.6));
        assert!((r.peak_knee_flexion.unwrap() - 30.0).abs() < 1e-9);
        assert!((r.peak_ankle_dorsiflexion.unwrap() - 15.0).abs() < 1e-9);
        assert!((r.peak_hip_abduction_torque.unwrap() - 20.0 / mass).abs() < 1e-12);
        assert!((r.peak_ankle_plantarflexion_torque.unwrap() - 50.0 / mass).abs() < 1e-12);
        // First half of the 6 stance samples: 0, 10, 20 N m.
        let early = r.early_stance_ankle_plantarflexion_torque.unwrap();
        assert!((early - 10.0 / mass).abs() < 1e-12);
        assert_eq!(m.left, LegMeasures::default());
    }
}
