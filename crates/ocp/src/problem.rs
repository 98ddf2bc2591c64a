//! The gait problem: model (after the settings' changes), gait view, layout, bounds and
//! scaling — everything the transcription needs, built once from settings.

use crate::bounds::CoordinateBounds;
use crate::experimental::Kinematics;
use crate::gait::{GaitModel, GaitModelError};
use crate::layout::{Layout, Point};
use crate::passive_rules::PassiveCost;
use crate::settings::{
    BoundsRule, CycleKind, ProblemSettings, PROSTHESIS_BODIES, PROSTHESIS_REMOVED_MUSCLES,
};
use stride_model::Model;

/// Scale factors: NLP variable = physical value / scale (FORMULATION 8.8).
#[derive(Clone, Debug)]
pub struct Scaling {
    /// Coordinates [rad or m], per problem coordinate.
    pub q: Vec<f64>,
    /// Speeds, per problem coordinate.
    pub v: Vec<f64>,
    /// Accelerations, per problem coordinate.
    pub a: Vec<f64>,
    /// Normalised tendon force (5).
    pub tendon_force: f64,
    /// Activation derivative [s⁻¹] (100).
    pub activation_rate: f64,
    /// Normalised tendon-force derivative [s⁻¹] (100).
    pub tendon_force_rate: f64,
    /// Arm torque [N m] (150; the arm torque balance is divided by it).
    pub arm_torque: f64,
}

impl Scaling {
    /// Scale factors from coordinate bounds.
    pub fn new(b: &CoordinateBounds) -> Self {
        Self {
            q: b.q.iter().map(|r| r.scale()).collect(),
            v: b.v.iter().map(|r| r.scale()).collect(),
            a: b.a.iter().map(|r| r.scale()).collect(),
            tendon_force: 5.0,
            activation_rate: 100.0,
            tendon_force_rate: 100.0,
            arm_torque: 150.0,
        }
    }
}

/// Why a problem could not be built.
#[derive(Debug, thiserror::Error)]
pub enum ProblemError {
    /// Invalid settings.
    #[error(transparent)]
    Settings(#[from] crate::settings::SettingsError),
    /// The model does not suit a gait problem.
    #[error(transparent)]
    Gait(#[from] GaitModelError),
    /// Experimental data unusable.
    #[error(transparent)]
    Kinematics(#[from] crate::experimental::KinematicsError),
    /// Bounds settings unusable.
    #[error(transparent)]
    Bounds(#[from] crate::bounds::BoundsError),
    /// A model function could not be prepared.
    #[error("model: {0}")]
    Model(String),
    /// A distance constraint names a body the model does not have.
    #[error("distance constraint `{0}`–`{1}`: the model has no body `{2}` (remove it from `min_distances` or from the model's settings file)")]
    UnknownBody(String, String, String),
    /// The gait outputs need a body the model does not have.
    #[error("the model has no body `{0}` (the gait outputs need both calcanei, `calcn_r` and `calcn_l`)")]
    MissingBody(String),
    /// A muscle named in the settings does not exist.
    #[error("strength: unknown muscle `{0}`")]
    UnknownMuscle(String),
    /// The prosthesis needs a body or muscle the model does not have.
    #[error("prosthesis: the model has no {kind} `{name}`")]
    Prosthesis {
        /// `body` or `muscle`.
        kind: &'static str,
        /// Its name.
        name: String,
    },
}

/// Apply the prosthesis changes of the settings (FORMULATION 12.1) to a model's bodies:
/// lighter shank and foot. The muscles it removes are checked here and taken out of the
/// problem by [`GaitProblem::removed_muscles`].
pub fn apply_prosthesis(
    model: &mut Model,
    p: &crate::settings::Prosthesis,
) -> Result<(), ProblemError> {
    for name in PROSTHESIS_BODIES {
        let b = model
            .body_index(name)
            .ok_or_else(|| ProblemError::Prosthesis {
                kind: "body",
                name: name.into(),
            })?;
        let body = &mut model.bodies[b];
        body.mass *= p.mass_scale;
        body.inertia.iter_mut().for_each(|i| *i *= p.inertia_scale);
    }
    for name in PROSTHESIS_REMOVED_MUSCLES {
        model
            .muscle_index(name)
            .ok_or_else(|| ProblemError::Prosthesis {
                kind: "muscle",
                name: name.into(),
            })?;
    }
    Ok(())
}

/// Muscle activation time constants [s] (Raasch model).
pub const TAU_ACTIVATION: f64 = 0.015;
/// Muscle deactivation time constant [s].
pub const TAU_DEACTIVATION: f64 = 0.060;
/// Arm actuator excitation–activation time constant [s].
pub const TAU_ARM: f64 = 0.035;
/// Maximal normalised tendon force (upper bound of the state).
pub const MAX_TENDON_FORCE: f64 = 5.0;
/// Weight of body weight used for %BW and energies [m s⁻²].
pub const GRAVITY: f64 = 9.81;

/// Muscles of the predefined weakness groups, by right-side base name (both legs).
pub fn strength_group(name: &str) -> &'static [&'static str] {
    match name {
        "hip" => &[
            "glut_med1",
            "glut_med2",
            "glut_med3",
            "glut_min1",
            "glut_min2",
            "glut_min3",
            "semimem",
            "semiten",
            "bifemlh",
            "sar",
            "add_long",
            "add_brev",
            "add_mag1",
            "add_mag2",
            "add_mag3",
            "tfl",
            "pect",
            "grac",
            "glut_max1",
            "glut_max2",
            "glut_max3",
            "iliacus",
            "psoas",
            "quad_fem",
            "gem",
            "peri",
            "rect_fem",
        ],
        "plantarflexors" => &[
            "flex_dig", "flex_hal", "lat_gas", "med_gas", "per_brev", "per_long", "soleus",
            "tib_post",
        ],
        _ => &[],
    }
}

/// A fully specified gait optimal control problem (before transcription derivatives).
#[derive(Clone, Debug)]
pub struct GaitProblem {
    /// The settings it was built from.
    pub settings: ProblemSettings,
    /// The model after the settings' changes (strength, contraction velocity).
    pub model: Model,
    /// Coordinate roles and mirror maps.
    pub gait: GaitModel,
    /// NLP variable layout.
    pub layout: Layout,
    /// Bounds of coordinates, speeds and accelerations.
    pub bounds: CoordinateBounds,
    /// Scale factors.
    pub scaling: Scaling,
    /// Body mass used in the cost, %BW and the cost of transport [kg].
    pub body_mass: f64,
    /// Whether the passive-torque cost counts only the limit torques (PredSim) rather
    /// than the whole passive torques (the 2019 formulation).
    pub passive_cost_limit_only: bool,
}

impl GaitProblem {
    /// Build the problem from a model, settings and the experimental kinematics that define
    /// the bounds (average walking cycle of the simulated duration).
    pub fn new(
        model: &Model,
        settings: &ProblemSettings,
        bounds_data: &stride_model::storage::Storage,
    ) -> Result<Self, ProblemError> {
        settings.validate()?;
        let mut model = model.clone();
        for m in &mut model.muscles {
            m.max_contraction_velocity = settings.max_contraction_velocity;
        }
        for c in &mut model.contacts {
            c.parameters.friction_transition_smoothing = settings.contact_friction_smoothing;
        }
        for change in &settings.strength {
            let mut names: Vec<String> = change.muscles.clone();
            if let Some(g) = &change.group {
                for base in strength_group(g) {
                    names.push(format!("{base}_l"));
                    names.push(format!("{base}_r"));
                }
            }
            for name in names {
                let i = model
                    .muscle_index(&name)
                    .ok_or_else(|| ProblemError::UnknownMuscle(name.clone()))?;
                model.muscles[i].max_isometric_force *= change.scale;
            }
        }
        if let Some(p) = &settings.prosthesis {
            apply_prosthesis(&mut model, p)?;
        }
        if let Some(path) = &settings.contact_geometry {
            crate::contact_geometry::ContactGeometry::read(path)
                .and_then(|g| g.apply(&mut model, &path.display().to_string()))
                .map_err(|e| ProblemError::Model(e.to_string()))?;
        }
        let mut gait = GaitModel::new(&model)?;
        let generated = crate::passive_rules::apply(&mut model, &gait, &settings.passive);
        if generated {
            gait = GaitModel::new(&model)?;
        }
        let passive_cost_limit_only = match settings.passive.cost {
            PassiveCost::Auto => generated,
            PassiveCost::Total => false,
            PassiveCost::Limit => true,
        };
        let data = Kinematics::matching(bounds_data, &gait, "bounds kinematics")?;
        let bounds = match settings.bounds {
            BoundsRule::Data => CoordinateBounds::new(&gait, &data, settings)?,
            BoundsRule::Predsim => {
                let height = crate::standing::gait_standing_height(&model, &gait)
                    .map_err(|e| ProblemError::Model(format!("bounds = \"predsim\": {e}")))?;
                CoordinateBounds::predsim(&gait, settings, height)?
            }
        };
        let scaling = Scaling::new(&bounds);
        let na = gait.actuator_driven().len();
        let layout = Layout::new(settings.mesh_intervals, gait.nm(), gait.nq(), na);
        let body_mass = model.total_mass();
        Ok(Self {
            settings: settings.clone(),
            model,
            gait,
            layout,
            bounds,
            scaling,
            body_mass,
            passive_cost_limit_only,
        })
    }

    /// Scaled lower and upper bounds of every NLP variable.
    pub fn variable_bounds(&self) -> (Vec<f64>, Vec<f64>) {
        let l = &self.layout;
        let s = &self.scaling;
        let mut lo = vec![f64::NEG_INFINITY; l.len()];
        let mut hi = vec![f64::INFINITY; l.len()];
        let [t0, t1] = self.settings.duration_bounds_or_default();
        lo[l.tf()] = t0;
        hi[l.tf()] = t1;
        let a_min = self.settings.activation_min;
        let removed = self.removed_muscles();
        let mut points: Vec<Point> = (0..=l.n).map(Point::Mesh).collect();
        for k in 0..l.n {
            for j in 1..=3 {
                points.push(Point::Col(k, j));
            }
        }
        for &p in &points {
            for m in 0..l.nm {
                let a_max = if removed[m] { a_min } else { 1.0 };
                (lo[l.a(p, m)], hi[l.a(p, m)]) = (a_min, a_max);
                (lo[l.f(p, m)], hi[l.f(p, m)]) = (0.0, MAX_TENDON_FORCE / s.tendon_force);
            }
            for i in 0..l.nq {
                let (bq, bv) = (self.bounds.q[i], self.bounds.v[i]);
                (lo[l.q(p, i)], hi[l.q(p, i)]) = (bq.lo / s.q[i], bq.hi / s.q[i]);
                (lo[l.v(p, i)], hi[l.v(p, i)]) = (bv.lo / s.v[i], bv.hi / s.v[i]);
            }
            for i in 0..l.na {
                (lo[l.arm(p, i)], hi[l.arm(p, i)]) = (-1.0, 1.0);
            }
        }
        // The forward translation starts at 0 (a bound on the first mesh point).
        let tx = self.gait.forward_translation;
        (lo[l.q(Point::Mesh(0), tx)], hi[l.q(Point::Mesh(0), tx)]) = (0.0, 0.0);
        for k in 0..l.n {
            for m in 0..l.nm {
                lo[l.u_da(k, m)] = -1.0 / (s.activation_rate * TAU_DEACTIVATION);
                hi[l.u_da(k, m)] = 1.0 / (s.activation_rate * TAU_ACTIVATION);
            }
            for i in 0..l.na {
                (lo[l.e_arm(k, i)], hi[l.e_arm(k, i)]) = (-1.0, 1.0);
            }
            for j in 1..=3 {
                for m in 0..l.nm {
                    (lo[l.u_df(k, j, m)], hi[l.u_df(k, j, m)]) = (-1.0, 1.0);
                }
                for i in 0..l.nq {
                    let b = self.bounds.a[i];
                    (lo[l.u_dv(k, j, i)], hi[l.u_dv(k, j, i)]) = (b.lo / s.a[i], b.hi / s.a[i]);
                }
            }
        }
        (lo, hi)
    }

    /// Per problem muscle: whether the settings remove it (the prosthesis' ankle and
    /// subtalar muscles). A removed muscle keeps its states so that the muscle vectors stay
    /// in left–right pairs, but its activation is held at the lower bound and it adds
    /// neither force to the skeleton nor terms to the cost.
    pub fn removed_muscles(&self) -> Vec<bool> {
        self.gait
            .muscles
            .iter()
            .map(|&mi| {
                self.settings.prosthesis.is_some()
                    && PROSTHESIS_REMOVED_MUSCLES.contains(&self.model.muscles[mi].name.as_str())
            })
            .collect()
    }

    /// Whether the problem is a symmetric half cycle (vs a periodic full cycle).
    pub fn is_half_cycle(&self) -> bool {
        self.settings.cycle == CycleKind::HalfSymmetric
    }

    /// Mirror a physical coordinate vector (left↔right swap, lateral components negated).
    pub fn mirror_coordinates(&self, q: &[f64]) -> Vec<f64> {
        self.gait
            .coordinates
            .iter()
            .map(|c| q[c.mirror] * c.mirror_sign)
            .collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn weakness_groups_match_formulation_12_2() {
        // 27 hip muscles and 8 plantarflexors per leg (FORMULATION 12.2).
        assert_eq!(strength_group("hip").len(), 27);
        assert_eq!(strength_group("plantarflexors").len(), 8);
        let hip = strength_group("hip");
        for m in [
            "glut_med3",
            "add_mag3",
            "glut_max3",
            "rect_fem",
            "peri",
            "gem",
        ] {
            assert!(hip.contains(&m), "{m}");
        }
        let mut all = hip.to_vec();
        all.sort();
        all.dedup();
        assert_eq!(all.len(), 27, "no duplicates");
    }

    #[test]
    fn contact_friction_smoothing_reaches_every_sphere() {
        let model = stride_model::default_model::default_model();
        assert!(model
            .contacts
            .iter()
            .all(|c| c.parameters.friction_transition_smoothing == 0.0));
        for eps in [crate::settings::CONTACT_FRICTION_SMOOTHING, 0.0, 0.2] {
            let settings = ProblemSettings {
                mesh_intervals: 4,
                contact_friction_smoothing: eps,
                ..Default::default()
            };
            let p = GaitProblem::new(&model, &settings, &crate::bounds::bounds_data(&settings))
                .unwrap();
            assert_eq!(p.model.contacts.len(), 12);
            for c in &p.model.contacts {
                assert_eq!(
                    c.parameters.friction_transition_smoothing, eps,
                    "{}",
                    c.name
                );
            }
        }
    }

    #[test]
    fn prosthesis_changes_the_published_masses() {
        let model = stride_model::default_model::default_model();
        let mut m = model.clone();
        apply_prosthesis(&mut m, &crate::settings::Prosthesis::default()).unwrap();
        // FORMULATION 12.1: masses after −35 % and the new body mass.
        let expected = [
            ("tibia_r", 1.809420105393108),
            ("talus_r", 0.048804318419234),
            ("calcn_r", 0.610053980240428),
            ("toes_r", 0.105710153696061),
        ];
        for (name, mass) in expected {
            let b = m.body_index(name).unwrap();
            assert!((m.bodies[b].mass - mass).abs() < 1e-9, "{name}");
            let b0 = model.body_index(name).unwrap();
            assert!((m.bodies[b].inertia[0] - 0.4 * model.bodies[b0].inertia[0]).abs() < 1e-15);
        }
        // The published 60.6140512 kg is 4.5e-5 kg above our sum: the nominal model's body
        // masses add up to 61.99995 kg, not 62 (FORMULATION 1, A.2).
        assert!(
            (m.total_mass() - 60.6140512).abs() < 1e-4,
            "{}",
            m.total_mass()
        );
    }

    /// The default model with the paper's prosthesis, full cycle, 4 intervals.
    fn prosthesis_problem() -> (Model, ProblemSettings, GaitProblem) {
        use crate::settings::Prosthesis;
        let settings = ProblemSettings {
            cycle: CycleKind::FullPeriodic,
            mesh_intervals: 4,
            prosthesis: Some(Prosthesis::default()),
            ..Default::default()
        };
        let model = stride_model::default_model::default_model();
        let p =
            GaitProblem::new(&model, &settings, &crate::bounds::bounds_data(&settings)).unwrap();
        (model, settings, p)
    }

    #[test]
    fn prosthetic_joints_have_a_linear_passive_torque() {
        let (_, _, p) = prosthesis_problem();
        let node = crate::node::NodeModel::new(&p).unwrap();
        let mut x = p
            .initial_guess(crate::guess::GuessKind::QuasiRandom, None)
            .unwrap();
        let l = &p.layout;
        let pt = Point::Col(0, 1);
        let set = |x: &mut Vec<f64>, name: &str, q: f64| {
            let i = p.gait.index_of(name).unwrap();
            x[l.q(pt, i)] = q / p.scaling.q[i];
            i
        };
        let ar = set(&mut x, "ankle_angle_r", 0.1);
        let sr = set(&mut x, "subtalar_angle_r", -0.05);
        let al = set(&mut x, "ankle_angle_l", 0.1);
        let io = crate::transcription::NodeInputs {
            nm: l.nm,
            nq: l.nq,
            na: l.na,
        };
        let xin: Vec<f64> = io.global_indices(l, 0, 1).iter().map(|&g| x[g]).collect();
        let mut ws = node.workspace::<f64>().unwrap();
        let out = node.sample(&mut ws, &xin);
        // T = −k q with k = 800 N m/rad (FORMULATION 12.1).
        assert!((out.passive[ar] + 80.0).abs() < 1e-9, "{}", out.passive[ar]);
        assert!((out.passive[sr] - 40.0).abs() < 1e-9, "{}", out.passive[sr]);
        // The left (biological) ankle keeps its exponential passive torque.
        assert!((out.passive[al] + 80.0).abs() > 1.0, "{}", out.passive[al]);
    }

    #[test]
    fn prosthesis_removes_the_right_ankle_muscles_from_forces_and_cost() {
        let (model, settings, p) = prosthesis_problem();
        let removed = p.removed_muscles();
        assert_eq!(removed.iter().filter(|&&r| r).count(), 12);
        let muscle = |name: &str| {
            let mi = p.model.muscle_index(name).unwrap();
            p.gait.muscles.iter().position(|&x| x == mi).unwrap()
        };
        let (sol_r, sol_l) = (muscle("soleus_r"), muscle("soleus_l"));
        assert!(removed[sol_r] && !removed[sol_l]);
        // a removed muscle keeps its force: the model is not changed, the problem is
        assert_eq!(
            p.model.muscles[p.gait.muscles[sol_r]].max_isometric_force,
            model.muscles[model.muscle_index("soleus_r").unwrap()].max_isometric_force
        );
        // its activation is held at the lower bound at every point
        let l = &p.layout;
        let (lo, hi) = p.variable_bounds();
        for pt in [Point::Mesh(0), Point::Col(2, 3)] {
            let k = l.a(pt, sol_r);
            assert_eq!(
                (lo[k], hi[k]),
                (settings.activation_min, settings.activation_min)
            );
            assert_eq!(hi[l.a(pt, sol_l)], 1.0);
        }
        // raising a removed muscle's force or activation changes neither the torque
        // balance of the right ankle nor the cost; the left soleus changes both
        let node = crate::node::NodeModel::new(&p).unwrap();
        let x = p
            .initial_guess(crate::guess::GuessKind::QuasiRandom, None)
            .unwrap();
        let io = crate::transcription::NodeInputs {
            nm: l.nm,
            nq: l.nq,
            na: l.na,
        };
        let xin: Vec<f64> = io.global_indices(l, 1, 2).iter().map(|&g| x[g]).collect();
        let mut ws = node.workspace::<f64>().unwrap();
        let eval = |ws: &mut crate::node::NodeWorkspace<f64>, xin: &[f64]| {
            let mut y = vec![0.0; node.n_outputs()];
            node.eval(ws, xin, &mut y);
            y
        };
        let y0 = eval(&mut ws, &xin);
        let o = node.outputs();
        let balance = |y: &[f64], name: &str| {
            let i = p.gait.index_of(name).unwrap();
            let t = p.gait.muscle_driven().iter().position(|&c| c == i).unwrap();
            y[o.root + t]
        };
        let cost = |y: &[f64]| y[o.n_path()];
        for (m, side, changes) in [
            (sol_r, "ankle_angle_r", false),
            (sol_l, "ankle_angle_l", true),
        ] {
            let mut x1 = xin.clone();
            x1[io.f() + m] *= 2.0;
            x1[io.a() + m] = 0.6;
            let y1 = eval(&mut ws, &x1);
            let (db, dc) = (
                (balance(&y1, side) - balance(&y0, side)).abs(),
                (cost(&y1) - cost(&y0)).abs(),
            );
            assert_eq!(db > 1e-6, changes, "{side}: torque balance change {db}");
            assert_eq!(dc > 1e-9, changes, "{side}: cost change {dc}");
        }
        // no metabolic energy is counted for a removed muscle
        let out = node.sample(&mut ws, &xin);
        assert_eq!(out.metabolic_bhargava[sol_r], 0.0);
        assert!(out.metabolic_bhargava[sol_l] > 0.0);
    }
}
