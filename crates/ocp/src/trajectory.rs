//! The solution as trajectories in physical units: the simulated half cycle on the mesh,
//! the full gait cycle reconstructed from it (FORMULATION 11.1–11.2), and the outcome
//! measures (11.3).

use crate::layout::Point;
use crate::node::{NodeModel, SampleOutputs};
use crate::problem::{GaitProblem, ProblemError, TAU_ACTIVATION, TAU_DEACTIVATION};
use crate::transcription::NodeInputs;
use serde::Serialize;
use stride_muscle::activation::ActivationDynamics;

/// Vertical force above which a foot is in contact [N].
pub const CONTACT_THRESHOLD: f64 = 20.0;

/// Trajectories over a gait cycle (or the simulated half cycle): one row per sample.
///
/// State-type series (q, v, activations, tendon forces, arm activations) and
/// control-type series (accelerations, tendon-force rates, activation rates, arm
/// excitations, torques, ground reaction forces) are aligned sample by sample.
#[derive(Clone, Debug, Default, Serialize)]
pub struct Trajectory {
    /// Sample times [s].
    pub time: Vec<f64>,
    /// Coordinates [rad or m], problem order.
    pub q: Vec<Vec<f64>>,
    /// Speeds [rad s⁻¹ or m s⁻¹].
    pub v: Vec<Vec<f64>>,
    /// Accelerations [rad s⁻² or m s⁻²].
    pub qdd: Vec<Vec<f64>>,
    /// Muscle activations, problem muscle order.
    pub activation: Vec<Vec<f64>>,
    /// Activation rates [s⁻¹].
    pub activation_rate: Vec<Vec<f64>>,
    /// Normalised tendon forces.
    pub tendon_force: Vec<Vec<f64>>,
    /// Normalised tendon-force rates [s⁻¹].
    pub tendon_force_rate: Vec<Vec<f64>>,
    /// Arm activations.
    pub arm_activation: Vec<Vec<f64>>,
    /// Arm excitations.
    pub arm_excitation: Vec<Vec<f64>>,
    /// Generalised forces from inverse dynamics [N m or N].
    pub torque: Vec<Vec<f64>>,
    /// Ground reaction force on the right foot [N] (x, y, z ground).
    pub grf_right: Vec<[f64; 3]>,
    /// Ground reaction force on the left foot [N].
    pub grf_left: Vec<[f64; 3]>,
    /// Ground reaction moment of the right foot about the ground origin [N m].
    pub grm_right: Vec<[f64; 3]>,
    /// Ground reaction moment of the left foot about the ground origin [N m].
    pub grm_left: Vec<[f64; 3]>,
}

/// The simulated half (or full) cycle on the mesh, in physical units.
#[derive(Clone, Debug)]
pub struct MeshSolution {
    /// Samples k = 0..N−1 (state-type at mesh point k, control-type at mesh point k+1 ≡
    /// collocation point 3 of interval k), and the final state (mesh point N).
    pub half: Trajectory,
    /// Coordinates at mesh point N.
    pub q_final: Vec<f64>,
    /// Duration [s].
    pub duration: f64,
    /// Distance travelled by the pelvis [m].
    pub distance: f64,
    /// Calcaneus origins (right, left) at mesh points 0..=N [m].
    pub calcaneus: Vec<[[f64; 3]; 2]>,
}

fn push_sample(t: &mut Trajectory, s: &SampleOutputs, groups: [usize; 2]) {
    t.torque.push(s.tau.clone());
    let g = |i: usize| s.group_force.get(i).copied().unwrap_or([0.0; 3]);
    let m = |i: usize| s.group_moment.get(i).copied().unwrap_or([0.0; 3]);
    // The ground reaction on the foot is the contact force on the foot body.
    t.grf_right.push(g(groups[0]));
    t.grf_left.push(g(groups[1]));
    t.grm_right.push(m(groups[0]));
    t.grm_left.push(m(groups[1]));
}

impl GaitProblem {
    /// Physical trajectories of the solution `x` on the mesh.
    pub fn mesh_solution(&self, node: &NodeModel, x: &[f64]) -> Result<MeshSolution, ProblemError> {
        let l = &self.layout;
        let s = &self.scaling;
        let n = l.n;
        let tf = x[l.tf()];
        let h = tf / n as f64;
        let io = NodeInputs {
            nm: l.nm,
            nq: l.nq,
            na: l.na,
        };
        let mut ws = node.workspace::<f64>()?;
        let names = node.contact_groups()?;
        let right = names.iter().position(|g| g == "right").unwrap_or(0);
        let left = names.iter().position(|g| g == "left").unwrap_or(1);
        let calcn = |side: &str| {
            self.model
                .body_index(&format!("calcn_{side}"))
                .ok_or_else(|| ProblemError::MissingBody(format!("calcn_{side}")))
        };
        let (cr, cl) = (calcn("r")?, calcn("l")?);
        let mut t = Trajectory::default();
        let mut calcaneus = Vec::with_capacity(n + 1);
        let state_at = |p: Point| -> Vec<f64> {
            let mut xin = vec![0.0; io.len()];
            for m in 0..l.nm {
                xin[io.a() + m] = x[l.a(p, m)];
                xin[io.f() + m] = x[l.f(p, m)];
            }
            for i in 0..l.nq {
                xin[io.q() + i] = x[l.q(p, i)];
                xin[io.v() + i] = x[l.v(p, i)];
            }
            for i in 0..l.na {
                xin[io.arm() + i] = x[l.arm(p, i)];
            }
            xin
        };
        for k in 0..=n {
            let xin = state_at(Point::Mesh(k));
            let out = node.sample(&mut ws, &xin);
            calcaneus.push([out.body_origins[cr], out.body_origins[cl]]);
            if k == n {
                break;
            }
            t.time.push(k as f64 * h);
            t.q.push((0..l.nq).map(|i| xin[io.q() + i] * s.q[i]).collect());
            t.v.push((0..l.nq).map(|i| xin[io.v() + i] * s.v[i]).collect());
            t.activation
                .push((0..l.nm).map(|m| xin[io.a() + m]).collect());
            t.tendon_force.push(
                (0..l.nm)
                    .map(|m| xin[io.f() + m] * s.tendon_force)
                    .collect(),
            );
            t.arm_activation
                .push((0..l.na).map(|i| xin[io.arm() + i]).collect());
            // Control-type quantities at collocation point 3 of interval k.
            let mut xc = state_at(Point::Col(k, 3));
            for m in 0..l.nm {
                xc[io.df() + m] = x[l.u_df(k, 3, m)];
                xc[io.da() + m] = x[l.u_da(k, m)];
            }
            for i in 0..l.nq {
                xc[io.qdd() + i] = x[l.u_dv(k, 3, i)];
            }
            for i in 0..l.na {
                xc[io.e_arm() + i] = x[l.e_arm(k, i)];
            }
            let out = node.sample(&mut ws, &xc);
            push_sample(&mut t, &out, [right, left]);
            t.qdd
                .push((0..l.nq).map(|i| xc[io.qdd() + i] * s.a[i]).collect());
            t.tendon_force_rate.push(
                (0..l.nm)
                    .map(|m| xc[io.df() + m] * s.tendon_force_rate)
                    .collect(),
            );
            t.activation_rate.push(
                (0..l.nm)
                    .map(|m| xc[io.da() + m] * s.activation_rate)
                    .collect(),
            );
            t.arm_excitation
                .push((0..l.na).map(|i| xc[io.e_arm() + i]).collect());
        }
        let tx = self.gait.forward_translation;
        let q_final: Vec<f64> = (0..l.nq)
            .map(|i| x[l.q(Point::Mesh(n), i)] * s.q[i])
            .collect();
        let distance = q_final[tx] - t.q[0][tx];
        Ok(MeshSolution {
            half: t,
            q_final,
            duration: tf,
            distance,
            calcaneus,
        })
    }

    fn mirror_muscles(&self, v: &[f64]) -> Vec<f64> {
        self.gait.muscle_mirror.iter().map(|&m| v[m]).collect()
    }

    fn mirror_arms(&self, v: &[f64]) -> Vec<f64> {
        let arms = self.gait.actuator_driven();
        arms.iter()
            .map(|&ci| {
                let mc = self.gait.coordinates[ci].mirror;
                v[arms.iter().position(|&x| x == mc).unwrap_or(0)]
            })
            .collect()
    }

    /// Sample `g` of the periodic extension of the half cycle: half `h` is mirrored when
    /// odd, and shifted forward by h·d.
    fn extended_sample(&self, m: &MeshSolution, g: usize, control: bool) -> Trajectory {
        let n = self.layout.n as isize;
        // State-type sample g ↔ mesh point g mod N of half g / N; control-type sample g
        // ↔ mesh point ((g − 1) mod N) + 1 of half (g − 1) / N (floored), stored at index
        // (g − 1) mod N: control sample 0 is mesh point N of half −1, the mirrored half
        // before the simulated one.
        let g = g as isize - isize::from(control);
        let (half, k) = (g.div_euclid(n), g.rem_euclid(n) as usize);
        let t = &m.half;
        let mirrored = half.rem_euclid(2) == 1 && self.is_half_cycle();
        let shift = half as f64 * m.distance;
        let tx = self.gait.forward_translation;
        let mut s = Trajectory::default();
        let mq = |v: &[f64]| {
            if mirrored {
                self.mirror_coordinates(v)
            } else {
                v.to_vec()
            }
        };
        let mm = |v: &[f64]| {
            if mirrored {
                self.mirror_muscles(v)
            } else {
                v.to_vec()
            }
        };
        let ma = |v: &[f64]| {
            if mirrored {
                self.mirror_arms(v)
            } else {
                v.to_vec()
            }
        };
        if control {
            s.qdd.push(mq(&t.qdd[k]));
            s.torque.push(mq(&t.torque[k]));
            s.activation_rate.push(mm(&t.activation_rate[k]));
            s.tendon_force_rate.push(mm(&t.tendon_force_rate[k]));
            s.arm_excitation.push(ma(&t.arm_excitation[k]));
            let flip_f = |f: [f64; 3]| [f[0], f[1], -f[2]];
            let flip_m = |f: [f64; 3]| [-f[0], -f[1], f[2]];
            let (fr, fl, mr, ml) = if mirrored {
                (
                    flip_f(t.grf_left[k]),
                    flip_f(t.grf_right[k]),
                    flip_m(t.grm_left[k]),
                    flip_m(t.grm_right[k]),
                )
            } else {
                (t.grf_right[k], t.grf_left[k], t.grm_right[k], t.grm_left[k])
            };
            // The forces act where the shifted feet are: their moments about the ground
            // origin move with them.
            s.grf_right.push(fr);
            s.grf_left.push(fl);
            s.grm_right.push(moment_shifted_forward(mr, fr, shift));
            s.grm_left.push(moment_shifted_forward(ml, fl, shift));
        } else {
            let mut q = mq(&t.q[k]);
            q[tx] += shift;
            s.q.push(q);
            s.v.push(mq(&t.v[k]));
            s.activation.push(mm(&t.activation[k]));
            s.tendon_force.push(mm(&t.tendon_force[k]));
            s.arm_activation.push(ma(&t.arm_activation[k]));
        }
        s
    }

    /// The full gait cycle (2N samples) starting at right heel strike, reconstructed from the
    /// symmetric half cycle; a full-cycle problem is re-ordered to start at right heel strike.
    pub fn gait_cycle(&self, m: &MeshSolution) -> Trajectory {
        let vy_r: Vec<f64> = m.half.grf_right.iter().map(|f| f[1]).collect();
        let vy_l: Vec<f64> = m.half.grf_left.iter().map(|f| f[1]).collect();
        let start = cycle_start(&vy_r, &vy_l, self.is_half_cycle());
        self.gait_cycle_from(m, start)
    }

    /// The full gait cycle (2N samples for a half-cycle problem, N for a full-cycle one)
    /// starting at sample `start` of the periodic extension of the simulated interval
    /// (mesh point `start`, counted over the mirrored and shifted repetitions), with the
    /// forward position of its first sample at 0.
    pub fn gait_cycle_from(&self, m: &MeshSolution, start: usize) -> Trajectory {
        let n = self.layout.n;
        let total = if self.is_half_cycle() { 2 * n } else { n };
        let h = m.duration / n as f64;
        let mut out = Trajectory::default();
        for i in 0..total {
            let g = start + i;
            let st = self.extended_sample(m, g, false);
            let ct = self.extended_sample(m, g, true);
            out.time.push(i as f64 * h);
            out.q.extend(st.q);
            out.v.extend(st.v);
            out.activation.extend(st.activation);
            out.tendon_force.extend(st.tendon_force);
            out.arm_activation.extend(st.arm_activation);
            out.qdd.extend(ct.qdd);
            out.torque.extend(ct.torque);
            out.activation_rate.extend(ct.activation_rate);
            out.tendon_force_rate.extend(ct.tendon_force_rate);
            out.arm_excitation.extend(ct.arm_excitation);
            out.grf_right.extend(ct.grf_right);
            out.grf_left.extend(ct.grf_left);
            out.grm_right.extend(ct.grm_right);
            out.grm_left.extend(ct.grm_left);
        }
        let tx = self.gait.forward_translation;
        let x0 = out.q[0][tx];
        out.q.iter_mut().for_each(|q| q[tx] -= x0);
        for (m, f) in out
            .grm_right
            .iter_mut()
            .zip(&out.grf_right)
            .chain(out.grm_left.iter_mut().zip(&out.grf_left))
        {
            *m = moment_shifted_forward(*m, *f, -x0);
        }
        out
    }

    /// Excitations recovered from activations and their rates (FORMULATION 2).
    pub fn excitations(&self, t: &Trajectory) -> Vec<Vec<f64>> {
        let act = ActivationDynamics {
            tau_activation: TAU_ACTIVATION,
            tau_deactivation: TAU_DEACTIVATION,
        };
        t.activation
            .iter()
            .zip(&t.activation_rate)
            .map(|(a, da)| {
                a.iter()
                    .zip(da)
                    .map(|(&a, &da)| act.excitation(a, da))
                    .collect()
            })
            .collect()
    }
}

/// Moment about the ground origin [N m] of a force `f` [N] whose moment about the origin is
/// `m` [N m], after the force's point of application moved forward (ground x) by `dx` [m]:
/// m + (dx, 0, 0) × f.
pub fn moment_shifted_forward(m: [f64; 3], f: [f64; 3], dx: f64) -> [f64; 3] {
    [m[0], m[1] - dx * f[2], m[2] + dx * f[1]]
}

/// The sample (control-type index `g` of the periodic extension) where the reconstructed
/// cycle starts: right heel strike. `vy_r`, `vy_l`: vertical forces [N] at mesh points
/// 1..=N of the solved interval; `half`: a symmetric half cycle, whose mirrored second half
/// has the left foot's forces on the right foot.
///
/// FORMULATION 11.2's rule first (the right foot's heel strike in the half cycle, else the
/// left foot's, which is the right foot's in the mirrored half). That rule finds nothing
/// when the strike falls exactly on the junction of two halves (the right foot ends the half
/// in swing and the left foot is in stance throughout): then the strike is found on the
/// right foot's periodic series over the whole cycle.
pub fn cycle_start(vy_r: &[f64], vy_l: &[f64], half: bool) -> usize {
    let n = vy_r.len();
    if let Some(s) = heel_strike(vy_r) {
        return s;
    }
    if half {
        if let Some(s) = heel_strike(vy_l) {
            return s + n;
        }
        let cycle: Vec<f64> = vy_r.iter().chain(vy_l).copied().collect();
        return periodic_heel_strike(&cycle).map_or(0, |j| j + 1);
    }
    periodic_heel_strike(vy_r).map_or(0, |j| j + 1)
}

/// Heel strike (0-based index) in a periodic vertical-force series [N]: the first sample at
/// or above the contact threshold after the longest run of samples below it (the swing, not
/// a brief graze). `None` when the foot is always or never in contact.
pub fn periodic_heel_strike(vy: &[f64]) -> Option<usize> {
    let n = vy.len();
    let below = |i: usize| vy[i % n] < CONTACT_THRESHOLD;
    // Start scanning just after a sample in contact, so that no run wraps around.
    let first_contact = (0..n).find(|&i| !below(i))?;
    (0..n).find(|&i| below(i))?;
    let mut best: Option<(usize, usize)> = None; // (run length, strike index)
    let mut run = 0;
    for step in 1..=n {
        let i = first_contact + step;
        if below(i) {
            run += 1;
        } else {
            if run > 0 && best.is_none_or(|(len, _)| run > len) {
                best = Some((run, i % n));
            }
            run = 0;
        }
    }
    best.map(|(_, i)| i)
}

/// Index (mesh point, 1..=N) of heel strike in a vertical-force series sampled at mesh
/// points 1..=N (FORMULATION 11.2): the sample after the last one below the threshold, or,
/// when the series ends below it, the first sample above it (unless that is sample 1).
pub fn heel_strike(vy: &[f64]) -> Option<usize> {
    let n = vy.len();
    let last_below = vy.iter().rposition(|&f| f < CONTACT_THRESHOLD)?;
    if last_below + 1 < n {
        return Some(last_below + 2);
    }
    let first_above = vy.iter().position(|&f| f >= CONTACT_THRESHOLD)?;
    if first_above == 0 {
        None
    } else {
        Some(first_above + 1)
    }
}

impl GaitProblem {
    /// The node model's physical quantities (muscle forces, fibre states, metabolic rates,
    /// the terms of the torque balances, ...) at every sample of a reconstructed gait cycle.
    pub fn cycle_samples(
        &self,
        node: &NodeModel,
        cycle: &Trajectory,
    ) -> Result<Vec<SampleOutputs>, ProblemError> {
        let l = &self.layout;
        let s = &self.scaling;
        let io = NodeInputs {
            nm: l.nm,
            nq: l.nq,
            na: l.na,
        };
        let mut ws = node.workspace::<f64>()?;
        let samples = (0..cycle.time.len()).map(|i| {
            let mut xin = vec![0.0; io.len()];
            for k in 0..l.nm {
                xin[io.a() + k] = cycle.activation[i][k];
                xin[io.f() + k] = cycle.tendon_force[i][k] / s.tendon_force;
                xin[io.df() + k] = cycle.tendon_force_rate[i][k] / s.tendon_force_rate;
            }
            for k in 0..l.nq {
                xin[io.q() + k] = cycle.q[i][k] / s.q[k];
                xin[io.v() + k] = cycle.v[i][k] / s.v[k];
                xin[io.qdd() + k] = cycle.qdd[i][k] / s.a[k];
            }
            for k in 0..l.na {
                xin[io.arm() + k] = cycle.arm_activation[i][k];
                xin[io.e_arm() + k] = cycle.arm_excitation[i][k];
            }
            node.sample(&mut ws, &xin)
        });
        Ok(samples.collect())
    }
}

/// Smallest prominence of a counted ground reaction force peak [fraction of body weight]:
/// ripples smaller than this are not separate peaks.
pub const PEAK_MIN_PROMINENCE: f64 = 0.05;
/// Smallest height of a counted ground reaction force peak [fraction of body weight].
pub const PEAK_MIN_HEIGHT: f64 = 0.5;

/// Indices of the peaks of a periodic signal (one cycle, last sample not repeating the
/// first) that are at least `min_height` high and stand out by at least `min_prominence`:
/// the drop to the higher of the two lowest points before a higher sample is reached on
/// either side (topographic prominence; for the highest peak, the drop to the minimum).
pub fn prominent_peaks(v: &[f64], min_prominence: f64, min_height: f64) -> Vec<usize> {
    let n = v.len();
    if n < 3 {
        return Vec::new();
    }
    // lowest value passed on the way from peak i in direction `step` (±1) until a strictly
    // higher sample or a full turn
    let valley = |i: usize, step: isize| -> f64 {
        let mut low = v[i];
        let mut k = i;
        for _ in 1..n {
            k = (k as isize + step).rem_euclid(n as isize) as usize;
            if v[k] > v[i] {
                break;
            }
            low = low.min(v[k]);
        }
        low
    };
    (0..n)
        .filter(|&i| {
            let (prev, next) = (v[(i + n - 1) % n], v[(i + 1) % n]);
            // a plateau counts once, at its first sample
            v[i] > prev && v[i] >= next && v[i] >= min_height
        })
        .filter(|&i| v[i] - valley(i, -1).max(valley(i, 1)) >= min_prominence)
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Vertical force in body weights: stance from 2% to 58% of the cycle at 0.85 body
    /// weight with two Gaussian humps at `t1`, `t2` (cycle fraction) and a ripple of
    /// amplitude `ripple`, zero in swing.
    fn two_hump(n: usize, t1: f64, t2: f64, ripple: f64) -> Vec<f64> {
        (0..n)
            .map(|i| {
                let t = i as f64 / n as f64;
                let g = |c: f64| (-((t - c) / 0.08).powi(2)).exp();
                if (0.02..0.58).contains(&t) {
                    0.85 + 0.3 * (g(t1) + g(t2)) + ripple * (t * 120.0).sin()
                } else {
                    0.0
                }
            })
            .collect()
    }

    #[test]
    fn prominent_peaks_ignore_ripples_and_shallow_dips() {
        // double-hump stance force with a 1% ripple: two peaks near 15% and 45%
        let v = two_hump(200, 0.15, 0.45, 0.01);
        let p = prominent_peaks(&v, 0.05, 0.5);
        assert_eq!(p.len(), 2, "{p:?}");
        assert!((p[0] as f64 / 200.0 - 0.15).abs() < 0.03, "{p:?}");
        assert!((p[1] as f64 / 200.0 - 0.45).abs() < 0.03, "{p:?}");
        // every local maximum of the ripple is counted without the prominence test
        assert!(prominent_peaks(&v, 0.0, 0.5).len() > 2);
        // humps close together: the dip between them is under 5% of the peak, one peak
        let v = two_hump(200, 0.25, 0.31, 0.0);
        assert_eq!(prominent_peaks(&v, 0.05, 0.5).len(), 1);
        // a peak lower than the height threshold is not counted
        let v: Vec<f64> = two_hump(200, 0.15, 0.45, 0.0)
            .iter()
            .map(|f| 0.4 * f)
            .collect();
        assert!(prominent_peaks(&v, 0.05, 0.5).is_empty());
    }

    #[test]
    fn prominent_peaks_of_a_periodic_signal_count_a_wrapping_peak_once() {
        // one cosine hump centred on the cycle boundary, a plateau of two equal samples
        let n = 100;
        let mut v: Vec<f64> = (0..n)
            .map(|i| (2.0 * std::f64::consts::PI * i as f64 / n as f64).cos())
            .collect();
        assert_eq!(prominent_peaks(&v, 0.05, 0.5), vec![0]);
        v[1] = v[0];
        assert_eq!(prominent_peaks(&v, 0.05, 0.5), vec![0]);
        assert!(prominent_peaks(&v[..2], 0.0, 0.0).is_empty());
    }

    #[test]
    fn periodic_heel_strike_follows_the_longest_swing() {
        // Strike at index 0, seen only across the wrap-around.
        assert_eq!(periodic_heel_strike(&[300.0, 200.0, 0.0, 0.0]), Some(0));
        assert_eq!(
            periodic_heel_strike(&[0.0, 0.0, 100.0, 300.0, 0.0]),
            Some(2)
        );
        // A graze in swing (one sample above) is not the strike.
        let graze = [300.0, 250.0, 0.0, 0.0, 30.0, 0.0, 0.0, 0.0, 200.0, 300.0];
        assert_eq!(periodic_heel_strike(&graze), Some(8));
        assert_eq!(periodic_heel_strike(&[300.0, 300.0]), None);
        assert_eq!(periodic_heel_strike(&[0.0, 0.0]), None);
    }

    #[test]
    fn the_cycle_starts_at_right_heel_strike_even_on_the_junction_of_two_halves() {
        // Right foot: strike inside the half at mesh point 3.
        let r = [0.0, 0.0, 400.0, 500.0];
        let l = [500.0, 400.0, 0.0, 0.0];
        assert_eq!(cycle_start(&r, &l, true), 3);
        // Right foot ends the half in swing, left foot strikes at mesh point 3: the right
        // foot strikes there in the mirrored half (sample N + 3).
        let r = [500.0, 0.0, 0.0, 0.0];
        let l = [0.0, 0.0, 300.0, 500.0];
        assert_eq!(cycle_start(&r, &l, true), 4 + 3);
        // The strike on the junction (the case of a converged quasi-random solution): the
        // right foot leaves stance and ends in swing (12 N < 20 N), the left foot is in
        // stance throughout, so the right foot strikes at the first sample of the mirrored
        // half (46 N): sample N + 1. The reference rule finds no strike in either foot.
        let r = [512.0, 246.0, 0.0, 12.0];
        let l = [46.0, 506.0, 550.0, 556.0];
        assert_eq!(heel_strike(&r), None);
        assert_eq!(heel_strike(&l), None);
        assert_eq!(cycle_start(&r, &l, true), 4 + 1);
        // A full periodic cycle whose strike is at its first sample.
        assert_eq!(cycle_start(&[300.0, 200.0, 0.0, 0.0], &[], false), 1);
        // Only a right foot always or never in contact has no strike: the cycle starts at
        // sample 0 (mesh point 0).
        assert_eq!(cycle_start(&[300.0; 4], &[300.0; 4], true), 0);
        assert_eq!(cycle_start(&[0.0; 4], &[0.0; 4], true), 0);
        assert_eq!(cycle_start(&[300.0; 4], &[], false), 0);
        assert_eq!(cycle_start(&[0.0, 0.0, 0.0, 30.0], &[], false), 4);
    }

    #[test]
    fn heel_strike_follows_the_reference_rule() {
        // Swing (below) then stance: heel strike = first sample in stance.
        assert_eq!(heel_strike(&[0.0, 0.0, 100.0, 300.0, 200.0]), Some(3));
        // Stance then swing until the end: first sample above the threshold after a sample below.
        assert_eq!(heel_strike(&[300.0, 200.0, 0.0, 0.0, 0.0]), None);
        assert_eq!(heel_strike(&[0.0, 200.0, 300.0, 0.0, 0.0]), Some(2));
        // Always in stance: no heel strike.
        assert_eq!(heel_strike(&[300.0, 300.0]), None);
    }
}
