//! Problem settings: every option of a gait prediction, with defaults that reproduce the
//! paper's nominal simulation (Falisse et al. 2019, 1.33 m s⁻¹, 50 mesh intervals, v2
//! transcription). Read from the `[problem]` part of a study file (TOML); unknown keys are
//! errors.

use serde::{Deserialize, Serialize};

/// Everything that defines one gait optimal control problem.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct ProblemSettings {
    /// Imposed average forward speed of the pelvis [m s⁻¹].
    pub speed: f64,
    /// Number of mesh intervals over the simulated duration (half cycle: 50 in the paper).
    pub mesh_intervals: usize,
    /// Simulated duration: symmetric half gait cycle or periodic full gait cycle.
    pub cycle: CycleKind,
    /// Cost-function weights (a goal with weight 0 is dropped).
    pub weights: Weights,
    /// Exponent applied to each muscle's metabolic rate in the cost (2 nominal, 1 = not squared).
    pub metabolic_exponent: f64,
    /// Metabolic energy model used in the cost.
    pub metabolic_model: MetabolicModelName,
    /// Lower bound of muscle activations (0.05 nominal; 0.1–0.2 for co-contraction).
    pub activation_min: f64,
    /// Maximal contraction velocity [optimal fibre lengths per second] (10 nominal).
    pub max_contraction_velocity: f64,
    /// Tendon stiffness k_T of the normalised tendon force–length curve (35 nominal); a
    /// muscle's k_T is this times its model `tendon_stiffness_scale`.
    pub tendon_stiffness: f64,
    /// Half-width of the smooth transition of min(v_slip / v_t, 1) in every contact
    /// sphere's friction law, as a fraction of the transition velocity v_t (0.01: ±2 mm/s
    /// around 0.2 m/s; 0: the reference's exact minimum, whose kink can stall Newton steps).
    pub contact_friction_smoothing: f64,
    /// Maximal isometric force changes (weakness) applied before solving.
    pub strength: Vec<StrengthChange>,
    /// Bounds of the half-cycle (or cycle) duration [s]; default [0.1, 1] (half cycle).
    pub duration_bounds: Option<[f64; 2]>,
    /// Manual bound overrides of coordinates, applied after the data-driven bounds.
    pub coordinate_bounds: Vec<CoordinateBound>,
    /// Transcription variant.
    pub transcription: TranscriptionVariant,
    /// Minimum horizontal distances between body origins (prevent segment interpenetration);
    /// absent: the model's own (`distances` of its settings file).
    pub min_distances: Option<Vec<DistanceConstraint>>,
    /// Passive transtibial prosthesis on the right leg (FORMULATION 12.1); needs
    /// `cycle = "full-periodic"`.
    pub prosthesis: Option<Prosthesis>,
    /// Contact geometry file (TOML, as `stride track --calibrate-contact` writes it) whose
    /// sphere centres and radii replace the model's; unset: the model's spheres.
    pub contact_geometry: Option<std::path::PathBuf>,
    /// Passive joint torques of models without a passive torque table, springs and
    /// damping of selected coordinates, and how the toes are driven.
    pub passive: crate::passive_rules::PassiveSettings,
    /// Rule of the duration guess of the standard initial guesses: the paper's
    /// (0.595 s at 1.33 m s⁻¹) or PredSim's table (0.65 s at 1.33 m s⁻¹).
    #[serde(skip_serializing_if = "DurationGuess::is_paper")]
    pub guess_duration: DurationGuess,
    /// Rule of the coordinate, speed and acceleration bounds (and so of their scale
    /// factors): the paper's, from experimental data matched by coordinate name, or
    /// PredSim's default table for every coordinate.
    #[serde(skip_serializing_if = "BoundsRule::is_data")]
    pub bounds: BoundsRule,
}

/// Rule of the bounds of the coordinate-related variables (FORMULATION 8.7, PREDSIM.md §7.4).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum BoundsRule {
    /// The paper's: experimental kinematics matched by coordinate name, widened (positions
    /// 2 ranges, speeds and accelerations 3 ranges on each side), with its manual bounds;
    /// coordinates without data get PredSim's rule.
    #[default]
    Data,
    /// PredSim's for every coordinate: its default table by name, else the model's range
    /// and ±10 / ±155 ranges for speed / acceleration; the pelvis height within [0.5, 1.2]
    /// × the standing pelvis height; the forward position in [0, 2] m.
    Predsim,
}

impl BoundsRule {
    /// Whether this is the paper's rule (the default, left out of written settings).
    pub fn is_data(&self) -> bool {
        *self == Self::Data
    }
}

/// Rule of the half-cycle duration [s] that the quasi-random and data-informed guesses
/// start from, as a function of the speed (FORMULATION 10, PREDSIM.md §7.5).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum DurationGuess {
    /// The paper's: 0.70 s at 0.73 m s⁻¹, 0.0175 s shorter per 0.1 m s⁻¹.
    #[default]
    Paper,
    /// PredSim's table: 0.70 s at 0.73 m s⁻¹, 0.35/42 s shorter per listed 0.1 m s⁻¹ step,
    /// the entry of the first listed speed at or above the speed.
    Predsim,
}

impl DurationGuess {
    /// Whether this is the paper's rule (the default, left out of written settings).
    pub fn is_paper(&self) -> bool {
        *self == Self::Paper
    }
}

/// Default half-width of the friction law's smoothed transition at v_slip = v_t (a
/// fraction of v_t; decision 0004).
pub const CONTACT_FRICTION_SMOOTHING: f64 = 0.01;

/// Right-leg passive transtibial prosthesis: ankle and subtalar muscles removed, passive
/// ankle and subtalar torques T = −k q, lighter shank and foot (FORMULATION 12.1).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct Prosthesis {
    /// Stiffness k of the prosthetic ankle and subtalar joints [N m rad⁻¹] (800).
    pub stiffness: f64,
    /// Factor on the masses of tibia_r, talus_r, calcn_r, toes_r (0.65: −35 %).
    pub mass_scale: f64,
    /// Factor on the moments of inertia of those bodies (0.4: −60 %).
    pub inertia_scale: f64,
}

impl Default for Prosthesis {
    /// The paper's prosthesis.
    fn default() -> Self {
        Self {
            stiffness: 800.0,
            mass_scale: 0.65,
            inertia_scale: 0.4,
        }
    }
}

/// Right-leg muscles removed by the prosthesis (the 12 crossing the ankle or subtalar).
pub const PROSTHESIS_REMOVED_MUSCLES: [&str; 12] = [
    "med_gas_r",
    "lat_gas_r",
    "soleus_r",
    "tib_post_r",
    "flex_dig_r",
    "flex_hal_r",
    "tib_ant_r",
    "per_brev_r",
    "per_long_r",
    "per_tert_r",
    "ext_dig_r",
    "ext_hal_r",
];

/// Right-leg bodies lightened by the prosthesis.
pub const PROSTHESIS_BODIES: [&str; 4] = ["tibia_r", "talus_r", "calcn_r", "toes_r"];

/// Coordinates driven by the prosthesis's passive torque −k q.
pub const PROSTHESIS_COORDINATES: [&str; 2] = ["ankle_angle_r", "subtalar_angle_r"];

pub use stride_model::model_settings::DistanceConstraint;

impl Default for ProblemSettings {
    /// The paper's nominal problem.
    fn default() -> Self {
        Self {
            speed: 1.33,
            mesh_intervals: 50,
            cycle: CycleKind::HalfSymmetric,
            weights: Weights::default(),
            metabolic_exponent: 2.0,
            metabolic_model: MetabolicModelName::Bhargava2004,
            activation_min: 0.05,
            max_contraction_velocity: 10.0,
            tendon_stiffness: 35.0,
            contact_friction_smoothing: CONTACT_FRICTION_SMOOTHING,
            strength: Vec::new(),
            duration_bounds: None,
            coordinate_bounds: Vec::new(),
            transcription: TranscriptionVariant::V2,
            min_distances: None,
            prosthesis: None,
            contact_geometry: None,
            passive: Default::default(),
            guess_duration: DurationGuess::Paper,
            bounds: BoundsRule::Data,
        }
    }
}

/// Which part of the gait cycle is simulated and how its ends are linked.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum CycleKind {
    /// Half gait cycle with left–right symmetry between start and end (paper nominal).
    HalfSymmetric,
    /// Full gait cycle with periodic states (asymmetric gaits, e.g. the prosthesis).
    FullPeriodic,
}

/// Raw weights of the cost terms (each squared norm is a mean over its elements).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct Weights {
    /// Metabolic energy rate term W_E (500).
    pub metabolic: f64,
    /// Muscle activity term W_A (2000).
    pub activation: f64,
    /// Joint acceleration term W_acc of the lower limbs, pelvis and trunk (50000).
    pub acceleration: f64,
    /// Passive joint torque term W_pass (1000).
    pub passive_torque: f64,
    /// Arm excitation term W_arm (1e6).
    pub arm_excitation: f64,
    /// Penalty on the remaining controls W_u (0.001).
    pub slack_controls: f64,
}

impl Default for Weights {
    /// The paper's nominal weights.
    fn default() -> Self {
        Self {
            metabolic: 500.0,
            activation: 2000.0,
            acceleration: 50000.0,
            passive_torque: 1000.0,
            arm_excitation: 1.0e6,
            slack_controls: 0.001,
        }
    }
}

/// Metabolic energy models available for the cost (FORMULATION section 7).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum MetabolicModelName {
    /// Bhargava et al. 2004, smooth (nominal).
    Bhargava2004,
    /// Umberger et al. 2003.
    Umberger2003,
    /// Umberger 2010.
    Umberger2010,
    /// Uchida et al. 2016.
    Uchida2016,
    /// Umberger 2010 with the lengthening heat of 2003.
    #[serde(rename = "umberger2010_hl")]
    Umberger2010Hl,
    /// Umberger 2010 with the negative work of 2003.
    #[serde(rename = "umberger2010_neg")]
    Umberger2010Neg,
}

/// Scale the maximal isometric force of a muscle group or of named muscles.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct StrengthChange {
    /// A predefined group (`hip`, `plantarflexors`) — both legs.
    #[serde(default)]
    pub group: Option<String>,
    /// Muscles by name.
    #[serde(default)]
    pub muscles: Vec<String>,
    /// Factor on the maximal isometric force (0.5 = 50% weaker).
    pub scale: f64,
}

/// A manual bound on a coordinate's value [rad or m] (either side may be omitted).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct CoordinateBound {
    /// Coordinate name.
    pub coordinate: String,
    /// Lower bound [rad or m].
    #[serde(default)]
    pub lower: Option<f64>,
    /// Upper bound [rad or m].
    #[serde(default)]
    pub upper: Option<f64>,
}

/// Transcription variant of the reference implementation (FORMULATION section 14).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum TranscriptionVariant {
    /// Current reference (v2): path constraints at every collocation point, slack controls.
    V2,
}

/// A settings value outside its allowed range.
#[derive(Debug, thiserror::Error, PartialEq)]
#[error("invalid setting `{key}` = {value}: {reason}")]
pub struct SettingsError {
    /// Dotted key of the offending setting.
    pub key: String,
    /// The value as written.
    pub value: String,
    /// What is allowed.
    pub reason: String,
}

fn check(ok: bool, key: &str, value: impl ToString, reason: &str) -> Result<(), SettingsError> {
    if ok {
        Ok(())
    } else {
        Err(SettingsError {
            key: key.into(),
            value: value.to_string(),
            reason: reason.into(),
        })
    }
}

/// Largest mesh accepted (intervals per simulated duration); the memory a mesh needs is
/// checked separately against the machine ([`crate::size`]).
pub const MAX_MESH_INTERVALS: usize = 10_000;

/// A finite number in the closed range `[lo, hi]`.
fn within(v: f64, lo: f64, hi: f64) -> bool {
    v.is_finite() && v >= lo && v <= hi
}

impl ProblemSettings {
    /// Check every value against its allowed range (finite and physically meaningful; the
    /// message gives the range).
    pub fn validate(&self) -> Result<(), SettingsError> {
        check(
            within(self.speed, 0.0, 12.0) && self.speed > 0.0,
            "speed",
            self.speed,
            "must lie in (0, 12] m/s (human walking and running)",
        )?;
        check(
            (2..=MAX_MESH_INTERVALS).contains(&self.mesh_intervals),
            "mesh_intervals",
            self.mesh_intervals,
            &format!("must lie in 2..={MAX_MESH_INTERVALS}"),
        )?;
        check(
            within(self.metabolic_exponent, 0.0, 4.0) && self.metabolic_exponent > 0.0,
            "metabolic_exponent",
            self.metabolic_exponent,
            "must lie in (0, 4]",
        )?;
        check(
            (0.0..1.0).contains(&self.activation_min),
            "activation_min",
            self.activation_min,
            "must lie in [0, 1)",
        )?;
        check(
            within(self.max_contraction_velocity, 0.0, 100.0)
                && self.max_contraction_velocity > 0.0,
            "max_contraction_velocity",
            self.max_contraction_velocity,
            "must lie in (0, 100] optimal fibre lengths per second",
        )?;
        check(
            within(self.tendon_stiffness, 0.0, 1000.0) && self.tendon_stiffness > 0.0,
            "tendon_stiffness",
            self.tendon_stiffness,
            "must lie in (0, 1000]",
        )?;
        check(
            (0.0..=0.5).contains(&self.contact_friction_smoothing),
            "contact_friction_smoothing",
            self.contact_friction_smoothing,
            "must lie in [0, 0.5] (a fraction of the transition velocity)",
        )?;
        self.validate_weights()?;
        if let Some([lo, hi]) = self.duration_bounds {
            check(
                within(lo, 0.0, 10.0) && within(hi, 0.0, 10.0) && lo > 0.0 && hi > lo,
                "duration_bounds",
                format!("[{lo}, {hi}]"),
                "must satisfy 0 < lower < upper ≤ 10 (s)",
            )?;
        }
        self.validate_strength()?;
        self.validate_prosthesis()?;
        self.validate_passive()?;
        for (i, d) in self.min_distances.iter().flatten().enumerate() {
            check(
                within(d.min, 0.0, 10.0) && within(d.max, 0.0, 10.0) && d.max > d.min,
                &format!("min_distances[{i}]"),
                format!("[{}, {}]", d.min, d.max),
                "needs 0 ≤ min < max ≤ 10 (m)",
            )?;
        }
        for (i, b) in self.coordinate_bounds.iter().enumerate() {
            let key = format!("coordinate_bounds[{i}]");
            let shown = format!("{} [{:?}, {:?}]", b.coordinate, b.lower, b.upper);
            for v in [b.lower, b.upper].into_iter().flatten() {
                check(!v.is_nan(), &key, &shown, "a bound must be a number")?;
            }
            if let (Some(lo), Some(hi)) = (b.lower, b.upper) {
                check(lo <= hi, &key, &shown, "lower bound exceeds upper bound")?;
            }
        }
        Ok(())
    }

    fn validate_weights(&self) -> Result<(), SettingsError> {
        let w = &self.weights;
        for (k, v) in [
            ("weights.metabolic", w.metabolic),
            ("weights.activation", w.activation),
            ("weights.acceleration", w.acceleration),
            ("weights.passive_torque", w.passive_torque),
            ("weights.arm_excitation", w.arm_excitation),
            ("weights.slack_controls", w.slack_controls),
        ] {
            check(within(v, 0.0, 1e12), k, v, "must lie in [0, 1e12]")?;
        }
        Ok(())
    }

    fn validate_strength(&self) -> Result<(), SettingsError> {
        for (i, s) in self.strength.iter().enumerate() {
            check(
                within(s.scale, 0.0, 10.0) && s.scale > 0.0,
                &format!("strength[{i}].scale"),
                s.scale,
                "must lie in (0, 10]",
            )?;
            check(
                s.group.is_some() || !s.muscles.is_empty(),
                &format!("strength[{i}]"),
                "{}",
                "needs a `group` or a list of `muscles`",
            )?;
            if let Some(g) = &s.group {
                check(
                    g == "hip" || g == "plantarflexors",
                    &format!("strength[{i}].group"),
                    g,
                    "known groups: hip, plantarflexors",
                )?;
            }
        }
        Ok(())
    }

    fn validate_passive(&self) -> Result<(), SettingsError> {
        let p = &self.passive;
        check(
            within(p.damping, 0.0, 1e4),
            "passive.damping",
            p.damping,
            "must lie in [0, 1e4] N m s/rad",
        )?;
        Ok(())
    }

    fn validate_prosthesis(&self) -> Result<(), SettingsError> {
        let Some(p) = &self.prosthesis else {
            return Ok(());
        };
        check(
            self.cycle == CycleKind::FullPeriodic,
            "prosthesis",
            "{..}",
            "an asymmetric gait needs `cycle = \"full-periodic\"`",
        )?;
        check(
            within(p.stiffness, 0.0, 1e5),
            "prosthesis.stiffness",
            p.stiffness,
            "must lie in [0, 1e5] N m/rad",
        )?;
        for (k, v) in [
            ("prosthesis.mass_scale", p.mass_scale),
            ("prosthesis.inertia_scale", p.inertia_scale),
        ] {
            check(v > 0.0 && v <= 1.0, k, v, "must lie in (0, 1]")?;
        }
        Ok(())
    }

    /// Duration bounds [s] actually used (half cycle [0.1, 1], full cycle [0.6, 2]).
    pub fn duration_bounds_or_default(&self) -> [f64; 2] {
        self.duration_bounds.unwrap_or(match self.cycle {
            CycleKind::HalfSymmetric => [0.1, 1.0],
            CycleKind::FullPeriodic => [0.6, 2.0],
        })
    }
}

/// Solver and parallelism settings as given on the command line or in a study file
/// (`None`: not given, the default applies). `stride predict`, `stride study` and study
/// files check them with the same [`RunSettings::validate`].
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct RunSettings {
    /// Convergence tolerance.
    pub tol: Option<f64>,
    /// Iteration limit per solve.
    pub max_iter: Option<usize>,
    /// Wall-time limit per solve [s].
    pub time_limit: Option<f64>,
    /// Centrality correctors per interior-point iteration.
    pub centrality_correctors: Option<usize>,
    /// Coarse presolve mesh (0: none).
    pub presolve_mesh: Option<usize>,
    /// Evaluation threads per solve (per case in a study).
    pub threads: Option<usize>,
    /// Cases solved at the same time (studies).
    pub jobs: Option<usize>,
}

/// Largest iteration limit, thread count and job count accepted.
pub const MAX_ITER: usize = 1_000_000;
/// Largest thread or job count accepted.
pub const MAX_THREADS: usize = 1024;
/// Largest wall-time limit accepted [s] (one week).
pub const MAX_TIME_LIMIT_S: f64 = 604_800.0;

impl RunSettings {
    /// Check every given value against its range (the message gives the range).
    pub fn validate(&self) -> Result<(), SettingsError> {
        if let Some(t) = self.tol {
            check(
                within(t, 0.0, 1.0) && t > 0.0,
                "tol",
                t,
                "must lie in (0, 1]",
            )?;
        }
        if let Some(n) = self.max_iter {
            check(
                (1..=MAX_ITER).contains(&n),
                "max_iter",
                n,
                &format!("must lie in 1..={MAX_ITER}"),
            )?;
        }
        if let Some(t) = self.time_limit {
            check(
                within(t, 0.0, MAX_TIME_LIMIT_S) && t > 0.0,
                "time_limit",
                t,
                &format!("must lie in (0, {MAX_TIME_LIMIT_S}] s"),
            )?;
        }
        if let Some(n) = self.centrality_correctors {
            check(n <= 10, "centrality_correctors", n, "must lie in 0..=10")?;
        }
        if let Some(n) = self.presolve_mesh {
            check(
                n <= MAX_MESH_INTERVALS,
                "presolve_mesh",
                n,
                &format!("must lie in 0..={MAX_MESH_INTERVALS}"),
            )?;
        }
        for (k, v) in [("threads", self.threads), ("jobs", self.jobs)] {
            if let Some(n) = v {
                check(
                    (1..=MAX_THREADS).contains(&n),
                    k,
                    n,
                    &format!("must lie in 1..={MAX_THREADS}"),
                )?;
            }
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn defaults_are_the_paper_nominal_case() {
        let s = ProblemSettings::default();
        s.validate().unwrap();
        assert_eq!(s.speed, 1.33);
        assert_eq!(s.mesh_intervals, 50);
        assert_eq!(s.weights.arm_excitation, 1e6);
    }

    #[test]
    fn unknown_keys_are_rejected_with_their_name() {
        let e = toml::from_str::<ProblemSettings>("sped = 1.2").unwrap_err();
        assert!(e.to_string().contains("sped"), "{e}");
        let e = toml::from_str::<ProblemSettings>("[weights]\nmetabolik = 1").unwrap_err();
        assert!(e.to_string().contains("metabolik"), "{e}");
    }

    #[test]
    fn out_of_range_values_name_the_key() {
        let s: ProblemSettings = toml::from_str("speed = -1.0").unwrap();
        assert_eq!(s.validate().unwrap_err().key, "speed");
        let s: ProblemSettings = toml::from_str("mesh_intervals = 0").unwrap();
        assert_eq!(s.validate().unwrap_err().key, "mesh_intervals");
        let s: ProblemSettings =
            toml::from_str("[[strength]]\ngroup = \"knee\"\nscale = 0.5").unwrap();
        assert_eq!(s.validate().unwrap_err().key, "strength[0].group");
        for (text, key) in [
            ("speed = 1e9", "speed"),
            ("speed = nan", "speed"),
            ("max_contraction_velocity = inf", "max_contraction_velocity"),
            ("mesh_intervals = 100000", "mesh_intervals"),
            (
                "[[coordinate_bounds]]\ncoordinate = \"q\"\nlower = nan",
                "coordinate_bounds[0]",
            ),
            (
                "[[coordinate_bounds]]\ncoordinate = \"q\"\nlower = 1.0\nupper = 0.0",
                "coordinate_bounds[0]",
            ),
            ("[weights]\nmetabolic = inf", "weights.metabolic"),
        ] {
            let s: ProblemSettings = toml::from_str(text).unwrap();
            let e = s.validate().unwrap_err();
            assert_eq!(e.key, key, "{text}");
            assert!(
                e.reason.contains("must")
                    || e.reason.contains("exceeds")
                    || e.reason.contains("bound"),
                "{e}"
            );
        }
        let e = ProblemSettings {
            speed: 1e9,
            ..Default::default()
        }
        .validate()
        .unwrap_err();
        assert_eq!(e.to_string(), "invalid setting `speed` = 1000000000: must lie in (0, 12] m/s (human walking and running)");
        for v in ["-0.01", "0.6", "nan"] {
            let s: ProblemSettings =
                toml::from_str(&format!("contact_friction_smoothing = {v}")).unwrap();
            let e = s.validate().unwrap_err();
            assert_eq!(e.key, "contact_friction_smoothing", "{v}");
        }
    }

    #[test]
    fn run_settings_are_checked_with_their_range() {
        assert!(RunSettings::default().validate().is_ok());
        let ok = RunSettings {
            tol: Some(1e-4),
            max_iter: Some(3),
            time_limit: Some(60.0),
            centrality_correctors: Some(2),
            presolve_mesh: Some(0),
            threads: Some(2),
            jobs: Some(1),
        };
        ok.validate().unwrap();
        for (bad, key) in [
            (
                RunSettings {
                    max_iter: Some(0),
                    ..ok
                },
                "max_iter",
            ),
            (
                RunSettings {
                    tol: Some(f64::NAN),
                    ..ok
                },
                "tol",
            ),
            (
                RunSettings {
                    time_limit: Some(f64::INFINITY),
                    ..ok
                },
                "time_limit",
            ),
            (
                RunSettings {
                    threads: Some(0),
                    ..ok
                },
                "threads",
            ),
            (
                RunSettings {
                    jobs: Some(0),
                    ..ok
                },
                "jobs",
            ),
        ] {
            let e = bad.validate().unwrap_err();
            assert_eq!(e.key, key);
            assert!(e.reason.starts_with("must lie in"), "{e}");
        }
    }

    #[test]
    fn prosthesis_defaults_are_the_paper_values_and_need_a_full_cycle() {
        let s: ProblemSettings = toml::from_str("[prosthesis]").unwrap();
        assert_eq!(s.prosthesis, Some(Prosthesis::default()));
        let p = s.prosthesis.clone().unwrap();
        assert_eq!(
            (p.stiffness, p.mass_scale, p.inertia_scale),
            (800.0, 0.65, 0.4)
        );
        assert_eq!(s.validate().unwrap_err().key, "prosthesis");
        let s: ProblemSettings =
            toml::from_str("cycle = \"full-periodic\"\n[prosthesis]\nmass_scale = 1.5").unwrap();
        assert_eq!(s.validate().unwrap_err().key, "prosthesis.mass_scale");
        let e = toml::from_str::<ProblemSettings>("[prosthesis]\nstifness = 1").unwrap_err();
        assert!(e.to_string().contains("stifness"), "{e}");
    }
}
