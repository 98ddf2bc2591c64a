//! The gait problem: model (after the settings' changes), gait view, layout, bounds and
//! scaling — everything the transcription needs, built once from settings.

use crate::bounds::CoordinateBounds;
use crate::experimental::Kinematics;
use crate::gait::{GaitModel, GaitModelError};
use crate::layout::{Layout, Point};
use crate::settings::{CycleKind, ProblemSettings};
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
    /// A body named in the settings does not exist.
    #[error("min_distances: unknown body `{0}`")]
    UnknownBody(String),
    /// A muscle named in the settings does not exist.
    #[error("strength: unknown muscle `{0}`")]
    UnknownMuscle(String),
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
        let gait = GaitModel::new(&model)?;
        let data = Kinematics::from_storage(bounds_data, &gait, "bounds kinematics")?;
        let bounds = CoordinateBounds::new(&gait, &data, settings)?;
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
        let mut points: Vec<Point> = (0..=l.n).map(Point::Mesh).collect();
        for k in 0..l.n {
            for j in 1..=3 {
                points.push(Point::Col(k, j));
            }
        }
        for &p in &points {
            for m in 0..l.nm {
                (lo[l.a(p, m)], hi[l.a(p, m)]) = (a_min, 1.0);
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
