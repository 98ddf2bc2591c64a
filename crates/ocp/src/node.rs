//! The model function of one collocation point, generic over the scalar (FORMULATION A.1):
//! unscale, muscle geometry, Hill model, metabolic rates, passive torques, ligament
//! moments, inverse dynamics with contact, then the path constraints (8.4) and the cost
//! integrand (8.6).
//!
//! One source of truth: the same generic code is recorded on a tape for the optimiser and
//! evaluated on `f64` for post-processing.

use crate::problem::{GaitProblem, ProblemError, TAU_ACTIVATION, TAU_DEACTIVATION};
use crate::settings::MetabolicModelName;
use crate::transcription::NodeInputs;
use stride_ad::Scalar;
use stride_model::BodyId;
use stride_multibody::{Data, SkeletonOutput};
use stride_muscle::activation::{ActivationDynamics, ARM_DAMPING};
use stride_muscle::{hill_equilibrium, HillParams, MetabolicModel, MusclePaths, PathWorkspace};

/// Everything the node function needs, built once per problem (immutable).
#[derive(Clone, Debug)]
pub struct NodeModel {
    /// The (modified) model.
    pub model: stride_model::Model,
    /// Node input offsets.
    pub inputs: NodeInputs,
    /// Model coordinate index of each problem coordinate.
    coord_model: Vec<usize>,
    /// Locked model coordinates and their values.
    locked: Vec<(usize, f64)>,
    /// Problem indices of the root coordinates.
    root: Vec<usize>,
    /// Problem indices of the muscle-driven coordinates, with their passive torque element.
    muscle_driven: Vec<(usize, Option<usize>)>,
    /// Per muscle-driven coordinate: stiffness k [N m rad⁻¹] of a prosthetic joint whose
    /// passive torque is −k q (not in the cost), `None` for a biological joint.
    prosthetic: Vec<Option<f64>>,
    /// Problem indices of the actuator-driven coordinates.
    actuator_driven: Vec<usize>,
    /// Per actuator-driven coordinate: whether it moves an arm (its acceleration is a slack
    /// control) rather than the torso (its acceleration is in the acceleration cost).
    actuator_is_arm: Vec<bool>,
    /// Per actuator-driven coordinate: its passive torque element when that has a limit
    /// torque (else the arm damping applies).
    actuator_passive: Vec<Option<usize>>,
    /// Per actuator-driven coordinate: optimal force / arm torque scale (1 for 150 N m).
    actuator_gain: Vec<f64>,
    /// The passive-torque cost counts only limit torques (PredSim) instead of the whole
    /// passive torques.
    limit_only_cost: bool,
    /// Per problem coordinate: the model's coordinate force elements (springs) acting on it.
    springs: Vec<Vec<usize>>,
    /// Per muscle-driven coordinate: (problem muscle, flat moment-arm index); removed
    /// muscles have no terms.
    torque_terms: Vec<Vec<(usize, usize)>>,
    /// Per problem muscle: removed by the settings (no force, no cost terms).
    removed: Vec<bool>,
    /// Model muscle index of each problem muscle.
    muscle_model: Vec<usize>,
    /// Hill parameters per problem muscle.
    hill: Vec<HillParams>,
    /// Polynomial geometry over model coordinates, indexed by model muscle.
    paths: MusclePaths,
    /// The model's ligaments: length polynomials and force laws.
    ligaments: crate::ligaments::Ligaments,
    /// Metabolic model of the cost.
    metabolic: MetabolicModel,
    /// Metabolic exponent p.
    exponent: f64,
    /// Body pairs of the distance constraints and their squared bounds [m²].
    distances: Vec<(BodyId, BodyId, f64, f64)>,
    /// Scale factors of q, v, qdd per problem coordinate.
    s_q: Vec<f64>,
    s_v: Vec<f64>,
    s_a: Vec<f64>,
    s_f: f64,
    s_df: f64,
    s_da: f64,
    s_arm: f64,
    /// Raw weights and body mass.
    weights: crate::settings::Weights,
    body_mass: f64,
    activation: ActivationDynamics,
    /// Tracking terms: the cost tracks measured data given as constant inputs after the
    /// variable inputs, and the root residuals equal measured values (`None`: prediction).
    tracking: Option<crate::tracking_terms::TrackingTerms>,
    /// Static parameters: inputs after the variable inputs (before the tracking
    /// constants), scaled as NLP variables.
    statics: crate::statics::StaticParameters,
}

/// Number of path-constraint outputs and their order.
#[derive(Clone, Copy, Debug)]
pub struct NodeOutputs {
    /// Root residuals.
    pub root: usize,
    /// Muscle-driven torque balances.
    pub muscle_driven: usize,
    /// Arm torque balances.
    pub arms: usize,
    /// Muscles (Hill residuals; twice that for activation constraints).
    pub muscles: usize,
    /// Distance constraints.
    pub distances: usize,
}

impl NodeOutputs {
    /// Offset of the Hill residuals.
    pub fn hill(&self) -> usize {
        self.root + self.muscle_driven + self.arms
    }
    /// Offset of the activation constraints (e ≥ 0 block, then e ≤ 1 block).
    pub fn activation(&self) -> usize {
        self.hill() + self.muscles
    }
    /// Offset of the distance constraints.
    pub fn distance(&self) -> usize {
        self.activation() + 2 * self.muscles
    }
    /// Number of path constraints.
    pub fn n_path(&self) -> usize {
        self.distance() + self.distances
    }
}

/// Per-thread scratch of the node function for scalar `T` (no allocation per call).
pub struct NodeWorkspace<T: Scalar> {
    data: Data<T>,
    paths: PathWorkspace<T>,
    q: Vec<T>,
    v: Vec<T>,
    qdd: Vec<T>,
    skeleton: SkeletonOutput<T>,
    lmt: Vec<T>,
    vmt: Vec<T>,
    arms: Vec<T>,
    tendon: Vec<T>,
    /// Passive torque per problem coordinate [N m or N] (0 for the root).
    passive: Vec<T>,
    /// Ligament lengths, moment arms and forces.
    ligaments: crate::ligaments::LigamentWorkspace<T>,
}

/// Metabolic model of the cost from the settings name.
pub fn metabolic_model(name: MetabolicModelName) -> MetabolicModel {
    match name {
        MetabolicModelName::Bhargava2004 => MetabolicModel::Bhargava2004,
        MetabolicModelName::Umberger2003 => MetabolicModel::Umberger2003,
        MetabolicModelName::Umberger2010 => MetabolicModel::Umberger2010,
        MetabolicModelName::Uchida2016 => MetabolicModel::Uchida2016,
        MetabolicModelName::Umberger2010Hl => MetabolicModel::Umberger2010LengtheningHeat2003,
        MetabolicModelName::Umberger2010Neg => MetabolicModel::Umberger2010NegativeWork2003,
    }
}

impl NodeModel {
    /// Prepare the node function of a problem.
    pub fn new(p: &GaitProblem) -> Result<Self, ProblemError> {
        let model = p.model.clone();
        let g = &p.gait;
        let inputs = NodeInputs {
            nm: g.nm(),
            nq: g.nq(),
            na: g.actuator_driven().len(),
        };
        let paths =
            MusclePaths::from_model(&model).map_err(|e| ProblemError::Model(e.to_string()))?;
        let coord_model: Vec<usize> = g.coordinates.iter().map(|c| c.model_index).collect();
        let ligaments = crate::ligaments::Ligaments::new(&model, &coord_model)?;
        let muscle_model = g.muscles.clone();
        let mut hill = Vec::with_capacity(g.nm());
        for &mi in &muscle_model {
            let m = &model.muscles[mi];
            let k_t = p.settings.tendon_stiffness * m.tendon_stiffness_scale;
            let h = HillParams::from_muscle(m)
                .and_then(|h| h.with_tendon_stiffness(k_t))
                .map_err(|e| ProblemError::Model(e.to_string()))?;
            hill.push(h);
        }
        let ocp_of_model: Vec<Option<usize>> = (0..model.muscles.len())
            .map(|mi| muscle_model.iter().position(|&x| x == mi))
            .collect();
        let muscle_driven: Vec<(usize, Option<usize>)> = g
            .muscle_driven()
            .into_iter()
            .map(|i| (i, g.coordinates[i].passive))
            .collect();
        let removed = p.removed_muscles();
        let torque_terms = muscle_driven
            .iter()
            .map(|&(i, _)| {
                let c = g.coordinates[i].model_index;
                let mut terms = Vec::new();
                if p.settings.passive.toes == crate::passive_rules::ToeDrive::Passive
                    && crate::passive_rules::is_toe(&g.coordinates[i].name)
                {
                    return terms;
                }
                for (mi, om) in ocp_of_model.iter().enumerate() {
                    let poly = paths.polynomial(mi);
                    if let (Some(om), Some(k)) =
                        (om, poly.coordinates().iter().position(|&x| x == c))
                    {
                        if removed[*om] {
                            continue;
                        }
                        terms.push((*om, paths.moment_arm_range(mi).start + k));
                    }
                }
                terms
            })
            .collect();
        let prosthetic = muscle_driven
            .iter()
            .map(|&(i, _)| {
                p.settings.prosthesis.as_ref().and_then(|pr| {
                    crate::settings::PROSTHESIS_COORDINATES
                        .contains(&g.coordinates[i].name.as_str())
                        .then_some(pr.stiffness)
                })
            })
            .collect();
        let mut distances = Vec::new();
        let listed = p.settings.min_distances.as_ref();
        for d in listed.unwrap_or(&model.distance_constraints) {
            let body = |n: &str| {
                model.body_index(n).ok_or_else(|| {
                    let [a, b] = d.bodies.clone();
                    ProblemError::UnknownBody(a, b, n.to_string())
                })
            };
            distances.push((
                body(&d.bodies[0])?,
                body(&d.bodies[1])?,
                d.min * d.min,
                d.max * d.max,
            ));
        }
        let s = &p.scaling;
        let actuator_passive = g
            .actuator_driven()
            .into_iter()
            .map(|i| {
                g.coordinates[i]
                    .passive
                    .filter(|&pi| model.passive_torques[pi].has_limit())
            })
            .collect();
        let actuator_gain = g
            .actuator_driven()
            .into_iter()
            .map(|i| match g.coordinates[i].actuation {
                crate::gait::Actuation::Actuator(a) => {
                    model.actuators[a].optimal_force / s.arm_torque
                }
                _ => 1.0,
            })
            .collect();
        let actuator_is_arm = g
            .actuator_driven()
            .into_iter()
            .map(|i| crate::gait::is_arm_coordinate(&model, g.coordinates[i].model_index))
            .collect();
        let springs = g
            .coordinates
            .iter()
            .map(|c| {
                (0..model.coordinate_forces.len())
                    .filter(|&f| model.coordinate_forces[f].coordinate == c.model_index)
                    .collect()
            })
            .collect();
        Ok(Self {
            springs,
            actuator_passive,
            actuator_gain,
            limit_only_cost: p.passive_cost_limit_only,
            inputs,
            coord_model,
            ligaments,
            locked: g.locked.clone(),
            root: g.root(),
            muscle_driven,
            prosthetic,
            actuator_driven: g.actuator_driven(),
            actuator_is_arm,
            torque_terms,
            removed,
            muscle_model,
            hill,
            paths,
            metabolic: metabolic_model(p.settings.metabolic_model),
            exponent: p.settings.metabolic_exponent,
            distances,
            s_q: s.q.clone(),
            s_v: s.v.clone(),
            s_a: s.a.clone(),
            s_f: s.tendon_force,
            s_df: s.tendon_force_rate,
            s_da: s.activation_rate,
            s_arm: s.arm_torque,
            weights: p.settings.weights,
            body_mass: p.body_mass,
            activation: ActivationDynamics {
                tau_activation: TAU_ACTIVATION,
                tau_deactivation: TAU_DEACTIVATION,
            },
            model,
            tracking: None,
            statics: Default::default(),
        })
    }

    /// The node function of a tracking problem: the same model, with the cost and root
    /// residual targets of `terms`.
    pub fn with_tracking(mut self, terms: crate::tracking_terms::TrackingTerms) -> Self {
        self.tracking = Some(terms);
        self
    }

    /// The node function with the static parameters `statics` as inputs after the variable
    /// inputs (and before any tracking constants).
    pub fn with_statics(mut self, statics: crate::statics::StaticParameters) -> Self {
        self.statics = statics;
        self
    }

    /// The static parameters the node function reads.
    pub fn statics(&self) -> &crate::statics::StaticParameters {
        &self.statics
    }

    /// Offset of the tracking constants in the inputs (after the variable inputs and the
    /// static parameters).
    fn data_offset(&self) -> usize {
        self.inputs.len() + self.statics.len()
    }

    /// Number of inputs: the variable inputs, the static parameters and the tracking
    /// constants.
    pub fn n_inputs(&self) -> usize {
        self.data_offset() + self.tracking.as_ref().map_or(0, |t| t.n_data())
    }

    /// Sizes of the path-constraint outputs.
    pub fn outputs(&self) -> NodeOutputs {
        NodeOutputs {
            root: self.root.len(),
            muscle_driven: self.muscle_driven.len(),
            arms: self.actuator_driven.len(),
            muscles: self.hill.len(),
            distances: self.distances.len(),
        }
    }

    /// Number of outputs (path constraints + cost integrand).
    pub fn n_outputs(&self) -> usize {
        self.outputs().n_path() + 1
    }

    /// Bounds of the path constraints.
    pub fn constraint_bounds(&self) -> Vec<(f64, f64)> {
        let o = self.outputs();
        let mut b = vec![(0.0, 0.0); o.hill() + o.muscles];
        let [[lo0, hi0], [lo1, hi1]] = self.activation.constraint_bounds();
        b.extend(std::iter::repeat_n((lo0, hi0), o.muscles));
        b.extend(std::iter::repeat_n((lo1, hi1), o.muscles));
        b.extend(self.distances.iter().map(|&(_, _, lo, hi)| (lo, hi)));
        b
    }

    /// A workspace for scalar `T`.
    pub fn workspace<T: Scalar>(&self) -> Result<NodeWorkspace<T>, ProblemError> {
        let nc = self.model.coordinates.len();
        let nm = self.model.muscles.len();
        let data = Data::new(&self.model).map_err(|e| ProblemError::Model(e.to_string()))?;
        Ok(NodeWorkspace {
            skeleton: SkeletonOutput::new(&self.model, &data),
            data,
            paths: PathWorkspace::for_paths(&self.paths),
            q: vec![T::zero(); nc],
            v: vec![T::zero(); nc],
            qdd: vec![T::zero(); nc],
            lmt: vec![T::zero(); nm],
            vmt: vec![T::zero(); nm],
            arms: vec![T::zero(); self.paths.n_moment_arms()],
            tendon: vec![T::zero(); self.hill.len()],
            passive: vec![T::zero(); self.coord_model.len()],
            ligaments: self.ligaments.workspace(),
        })
    }

    /// Evaluate the node function: `x` are the node inputs (scaled NLP variables), `y` the
    /// path constraints followed by the cost integrand L.
    pub fn eval<T: Scalar>(&self, ws: &mut NodeWorkspace<T>, x: &[T], y: &mut [T]) {
        let io = self.inputs;
        let o = self.outputs();
        let nm = io.nm;
        // Unscale into model-ordered coordinate vectors.
        for &(c, val) in &self.locked {
            ws.q[c] = T::cst(val);
            ws.v[c] = T::zero();
            ws.qdd[c] = T::zero();
        }
        for (i, &c) in self.coord_model.iter().enumerate() {
            ws.q[c] = x[io.q() + i] * self.s_q[i];
            ws.v[c] = x[io.v() + i] * self.s_v[i];
            ws.qdd[c] = x[io.qdd() + i] * self.s_a[i];
        }
        // Muscle geometry (all model muscles).
        self.paths
            .evaluate(
                &ws.q,
                &ws.v,
                &mut ws.paths,
                &mut ws.lmt,
                &mut ws.vmt,
                &mut ws.arms,
            )
            .expect("path workspace sized at construction");
        self.ligaments.evaluate(&ws.q, &mut ws.ligaments);
        // Hill model, metabolic rates, activation constraints.
        let mut sum_e = T::zero();
        let mut sum_a2 = T::zero();
        let mut sum_da2 = T::zero();
        let mut sum_df2 = T::zero();
        for m in 0..nm {
            let mi = self.muscle_model[m];
            let a = x[io.a() + m];
            let ft = x[io.f() + m] * self.s_f;
            let dft = x[io.df() + m] * self.s_df;
            let da = x[io.da() + m] * self.s_da;
            let h = hill_equilibrium(&self.hill[m], a, ft, dft, ws.lmt[mi], ws.vmt[mi]);
            y[o.hill() + m] = h.residual;
            ws.tendon[m] = h.tendon_force;
            let [c0, c1] = self.activation.constraints(a, da);
            y[o.activation() + m] = c0;
            y[o.activation() + nm + m] = c1;
            sum_da2 += x[io.da() + m].sq();
            sum_df2 += x[io.df() + m].sq();
            if self.removed[m] {
                continue;
            }
            if self.weights.metabolic != 0.0 {
                let e = self.metabolic.rate(&self.hill[m], a, &h).total;
                sum_e += if self.exponent == self.exponent.round() {
                    e.powi(self.exponent as i32)
                } else {
                    e.powf(self.exponent)
                };
            }
            sum_a2 += a * a;
        }
        // Inverse dynamics with contact (sphere geometry from the static parameters).
        let geometry = self.statics.sets_contact().then(|| {
            let scaled = &x[io.len()..self.data_offset()];
            self.statics.sphere_geometry(&self.model, scaled)
        });
        stride_multibody::skeleton_dynamics_with_geometry(
            &self.model,
            &mut ws.data,
            &ws.q,
            &ws.v,
            &ws.qdd,
            geometry.as_deref(),
            &mut ws.skeleton,
        )
        .expect("skeleton workspace sized at construction");
        let tau = &ws.skeleton.tau;
        let mut out = 0;
        for (r, &i) in self.root.iter().enumerate() {
            let residual = match &self.tracking {
                Some(t) => tau[self.coord_model[i]] - x[self.data_offset() + t.root_offset() + r],
                None => tau[self.coord_model[i]],
            };
            y[out] = match self.ligaments.moment(i, &ws.ligaments) {
                Some(m) => residual - m,
                None => residual,
            };
            out += 1;
        }
        let mut sum_tp2 = T::zero();
        for (t, &(i, passive)) in self.muscle_driven.iter().enumerate() {
            let c = self.coord_model[i];
            let mut muscle = T::zero();
            for &(m, arm) in &self.torque_terms[t] {
                muscle += ws.arms[arm] * ws.tendon[m];
            }
            let tp = match (self.prosthetic[t], passive) {
                (Some(k), _) => ws.q[c] * (-k),
                (None, Some(pi)) => stride_muscle::passive::passive_torque(
                    &self.model.passive_torques[pi],
                    ws.q[c],
                    ws.v[c],
                ),
                (None, None) => T::zero(),
            };
            let tp = self.add_springs(i, tp, ws.q[c], ws.v[c]);
            ws.passive[i] = tp;
            if let Some(m) = self.ligaments.moment(i, &ws.ligaments) {
                muscle += m;
            }
            if self.limit_only_cost {
                if let Some(pi) = passive.filter(|&pi| self.model.passive_torques[pi].has_limit()) {
                    let tl = stride_muscle::passive::limit_torque(
                        &self.model.passive_torques[pi],
                        ws.q[c],
                    );
                    sum_tp2 += tl * tl;
                }
            } else if self.prosthetic[t].is_none() {
                sum_tp2 += tp * tp;
            }
            y[out] = tau[c] - (muscle + tp);
            out += 1;
        }
        let mut sum_e_arm2 = T::zero();
        let mut sum_arm_acc2 = T::zero();
        let mut sum_torso_acc2 = T::zero();
        for (k, &i) in self.actuator_driven.iter().enumerate() {
            let c = self.coord_model[i];
            let (tp, limit) = match self.actuator_passive[k] {
                Some(pi) => {
                    let e = &self.model.passive_torques[pi];
                    let tp = stride_muscle::passive::passive_torque(e, ws.q[c], ws.v[c]);
                    (tp, Some(stride_muscle::passive::limit_torque(e, ws.q[c])))
                }
                None => (-ws.v[c] * ARM_DAMPING, None),
            };
            let tp = self.add_springs(i, tp, ws.q[c], ws.v[c]);
            ws.passive[i] = tp;
            match (self.limit_only_cost, limit) {
                (false, _) => sum_tp2 += tp * tp,
                (true, Some(tl)) => sum_tp2 += tl * tl,
                (true, None) => {}
            }
            let gain = self.actuator_gain[k];
            let torque = if gain == 1.0 {
                x[io.arm() + k]
            } else {
                x[io.arm() + k] * gain
            };
            let tp = match self.ligaments.moment(i, &ws.ligaments) {
                Some(m) => tp + m,
                None => tp,
            };
            y[out] = tau[c] / self.s_arm - (torque + tp / self.s_arm);
            out += 1;
            sum_e_arm2 += x[io.e_arm() + k].sq();
            if self.actuator_is_arm[k] {
                sum_arm_acc2 += x[io.qdd() + i].sq();
            } else {
                sum_torso_acc2 += x[io.qdd() + i].sq();
            }
        }
        // Distances between body origins in the ground x–z plane.
        for (k, &(b0, b1, _, _)) in self.distances.iter().enumerate() {
            let p0 = ws.skeleton.body_origins[b0];
            let p1 = ws.skeleton.body_origins[b1];
            y[o.distance() + k] = (p0[0] - p1[0]).sq() + (p0[2] - p1[2]).sq();
        }
        if let Some(t) = &self.tracking {
            let slack = (sum_da2 / nm as f64 + sum_df2 / nm as f64) * t.weights.slack_controls;
            let tracked = crate::tracking_terms::TrackedModel {
                x,
                data: &x[self.data_offset()..],
                q_offset: io.q(),
                qdd_offset: io.qdd(),
                nq: io.nq,
                tau: &self.coord_model.iter().map(|&c| tau[c]).collect::<Vec<T>>(),
                force: &ws.skeleton.group_force,
                moment: &ws.skeleton.group_moment,
            };
            y[o.n_path()] = t.cost(&tracked, sum_a2 / nm as f64) + slack;
            return;
        }
        // Cost integrand (means over the elements of each norm; accelerations scaled).
        // (torso accelerations of actuated coordinates that are not arms count here)
        let mut sum_acc2 = sum_torso_acc2;
        let n_arms = self.actuator_is_arm.iter().filter(|&&a| a).count();
        let mut n_acc = self.actuator_driven.len() - n_arms;
        for &i in self
            .root
            .iter()
            .chain(self.muscle_driven.iter().map(|(i, _)| i))
        {
            sum_acc2 += x[io.qdd() + i].sq();
            n_acc += 1;
        }
        let w = &self.weights;
        let nmf = nm as f64;
        // activity and metabolic means are over the muscles the model keeps
        let n_kept = self.removed.iter().filter(|&&r| !r).count().max(1) as f64;
        let na = self.actuator_driven.len().max(1) as f64;
        let n_prosthetic = self.prosthetic.iter().filter(|k| k.is_some()).count();
        let n_tp = if self.limit_only_cost {
            self.n_limit_torques()
        } else {
            self.muscle_driven.len() + self.actuator_driven.len() - n_prosthetic
        }
        .max(1) as f64;
        let mut l = sum_a2 * (w.activation / n_kept)
            + sum_acc2 * (w.acceleration / n_acc.max(1) as f64)
            + sum_tp2 * (w.passive_torque / n_tp)
            + sum_e_arm2 * (w.arm_excitation / na)
            + (sum_da2 / nmf + sum_df2 / nmf + sum_arm_acc2 / n_arms.max(1) as f64)
                * w.slack_controls;
        if w.metabolic != 0.0 {
            l += sum_e * (w.metabolic / n_kept / self.body_mass);
        }
        y[o.n_path()] = l;
    }
}

/// Physical quantities of one sample, for post-processing (f64 only).
#[derive(Clone, Debug, Default)]
pub struct SampleOutputs {
    /// Generalised forces of the problem coordinates [N m or N].
    pub tau: Vec<f64>,
    /// Contact force of each contact group (foot) [N], ground frame.
    pub group_force: Vec<[f64; 3]>,
    /// Contact moment of each group about the ground origin [N m].
    pub group_moment: Vec<[f64; 3]>,
    /// Origin of every body in ground [m].
    pub body_origins: Vec<[f64; 3]>,
    /// Metabolic rate per problem muscle of the cost's model [W] (0 for removed muscles).
    pub metabolic: Vec<f64>,
    /// Metabolic rate per problem muscle with Bhargava 2004 (for the cost of transport) [W]
    /// (0 for removed muscles).
    pub metabolic_bhargava: Vec<f64>,
    /// Tendon force per problem muscle [N] (0 for removed muscles).
    pub tendon_force: Vec<f64>,
    /// Fibre length per problem muscle [m] (0 for removed muscles).
    pub fiber_length: Vec<f64>,
    /// Fibre lengthening velocity per problem muscle [m s⁻¹] (0 for removed muscles).
    pub fiber_velocity: Vec<f64>,
    /// Passive torque per problem coordinate (0 where none) [N m]: joint limit torques and
    /// damping, springs on the coordinate, a prosthesis' spring.
    pub passive: Vec<f64>,
    /// Muscle moment per problem coordinate, Σ moment arm × tendon force [N m] (0 on
    /// coordinates no muscle drives).
    pub muscle: Vec<f64>,
    /// Ideal actuator torque per problem coordinate [N m] (0 on coordinates no actuator
    /// drives).
    pub actuator: Vec<f64>,
    /// Generalised force of the ligaments per problem coordinate, −Σ F ∂l/∂q [N m or N]
    /// (0 on coordinates no ligament spans).
    pub ligament: Vec<f64>,
    /// Length of each model ligament [m].
    pub ligament_length: Vec<f64>,
    /// Tension of each model ligament [N].
    pub ligament_force: Vec<f64>,
}

impl NodeModel {
    /// `tp` plus the generalised forces of the model's springs on problem coordinate `i`
    /// at value `q` and speed `v` (`tp` itself when it has none).
    fn add_springs<T: Scalar>(&self, i: usize, tp: T, q: T, v: T) -> T {
        self.springs[i].iter().fold(tp, |t, &f| {
            t + stride_multibody::elements::coordinate_force(
                &self.model.coordinate_forces[f].law,
                q,
                v,
            )
        })
    }

    /// Number of driven coordinates with a limit torque (the passive-torque cost terms of
    /// PredSim).
    fn n_limit_torques(&self) -> usize {
        let has = |p: Option<usize>| p.is_some_and(|pi| self.model.passive_torques[pi].has_limit());
        self.muscle_driven.iter().filter(|(_, p)| has(*p)).count()
            + self.actuator_passive.iter().filter(|p| has(**p)).count()
    }

    /// Evaluate the node function on `f64` and collect the physical quantities.
    pub fn sample(&self, ws: &mut NodeWorkspace<f64>, x: &[f64]) -> SampleOutputs {
        let mut y = vec![0.0; self.n_outputs()];
        self.eval(ws, x, &mut y);
        let io = self.inputs;
        let mut out = SampleOutputs {
            tau: self
                .coord_model
                .iter()
                .map(|&c| ws.skeleton.tau[c])
                .collect(),
            group_force: ws.skeleton.group_force.clone(),
            group_moment: ws.skeleton.group_moment.clone(),
            body_origins: ws.skeleton.body_origins.clone(),
            tendon_force: (0..io.nm)
                .map(|m| if self.removed[m] { 0.0 } else { ws.tendon[m] })
                .collect(),
            passive: vec![0.0; self.coord_model.len()],
            ..Default::default()
        };
        for m in 0..io.nm {
            let mi = self.muscle_model[m];
            let a = x[io.a() + m];
            let h = hill_equilibrium(
                &self.hill[m],
                a,
                x[io.f() + m] * self.s_f,
                x[io.df() + m] * self.s_df,
                ws.lmt[mi],
                ws.vmt[mi],
            );
            if self.removed[m] {
                out.metabolic.push(0.0);
                out.metabolic_bhargava.push(0.0);
                out.fiber_length.push(0.0);
                out.fiber_velocity.push(0.0);
                continue;
            }
            out.fiber_length.push(h.fiber_length);
            out.fiber_velocity.push(h.fiber_velocity);
            out.metabolic
                .push(self.metabolic.rate(&self.hill[m], a, &h).total);
            out.metabolic_bhargava.push(
                MetabolicModel::Bhargava2004
                    .rate(&self.hill[m], a, &h)
                    .total,
            );
        }
        for &i in self
            .muscle_driven
            .iter()
            .map(|(i, _)| i)
            .chain(&self.actuator_driven)
        {
            out.passive[i] = ws.passive[i];
        }
        self.torque_sources(ws, x, &mut out);
        out
    }

    /// The muscle, actuator and ligament terms of the torque balances (the generalised
    /// forces they equal with the passive torques) at input `x`, after [`Self::eval`].
    fn torque_sources(&self, ws: &NodeWorkspace<f64>, x: &[f64], out: &mut SampleOutputs) {
        let nq = self.coord_model.len();
        out.muscle = vec![0.0; nq];
        out.actuator = vec![0.0; nq];
        for (t, &(i, _)) in self.muscle_driven.iter().enumerate() {
            out.muscle[i] = self.torque_terms[t]
                .iter()
                .map(|&(m, arm)| ws.arms[arm] * ws.tendon[m])
                .sum();
        }
        for (k, &i) in self.actuator_driven.iter().enumerate() {
            out.actuator[i] = x[self.inputs.arm() + k] * self.actuator_gain[k] * self.s_arm;
        }
        out.ligament = (0..nq)
            .map(|i| self.ligaments.moment(i, &ws.ligaments).unwrap_or(0.0))
            .collect();
        out.ligament_length = ws.ligaments.length.clone();
        out.ligament_force = ws.ligaments.force.clone();
    }

    /// Names of the contact groups (feet) in the order of `SampleOutputs::group_force`.
    pub fn contact_groups(&self) -> Result<Vec<String>, ProblemError> {
        let data: Data<f64> =
            Data::new(&self.model).map_err(|e| ProblemError::Model(e.to_string()))?;
        Ok(data.groups.names.clone())
    }
}
