//! Initial guesses (FORMULATION section 10, ESM Table S1), built in physical units and
//! then scaled. Muscle and arm parts are constant; the final mesh point is the mirror of
//! the first; collocation points copy the mesh point that starts their interval.

use crate::experimental::Kinematics;
use crate::layout::{Layout, Point};
use crate::problem::Scaling;
use crate::settings::ProblemSettings;

/// Which initial guess to build.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum GuessKind {
    /// Upright "sliding" posture moving at the target speed.
    QuasiRandom,
    /// Average experimental walking kinematics.
    DataInformedWalking,
    /// Average experimental running kinematics.
    DataInformedRunning,
}

impl std::fmt::Display for GuessKind {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(match self {
            GuessKind::QuasiRandom => "quasi-random",
            GuessKind::DataInformedWalking => "data-informed-walking",
            GuessKind::DataInformedRunning => "data-informed-running",
        })
    }
}

/// Guess of the half-cycle duration [s] at a speed [m s⁻¹]: 0.70 s at 0.73 m s⁻¹, 0.0175 s
/// shorter per 0.1 m s⁻¹ (0.595 s at 1.33 m s⁻¹).
pub fn duration_guess(speed: f64) -> f64 {
    0.70 - 0.0175 * (speed - 0.73) / 0.1
}

/// PredSim's guess of the half-cycle duration [s] at a speed [m s⁻¹] (PREDSIM.md §7.5):
/// listed speeds 0.73 + 0.1 k m s⁻¹ (k = 0…42) with durations 0.70 − 0.35 k/42 s, the entry
/// of the first listed speed at or above `speed` (a speed within 1e-9 m s⁻¹ of a listed one
/// is that one); above 4.93 m s⁻¹ 0.8277 − 0.175 v; never below 0.15 s. 0.65 s at 1.25 and
/// 1.33 m s⁻¹.
pub fn duration_guess_predsim(speed: f64) -> f64 {
    const LISTED: usize = 42;
    let t = match (0..=LISTED).find(|&k| 0.73 + 0.1 * k as f64 >= speed - 1e-9) {
        Some(k) => 0.70 - 0.35 * k as f64 / LISTED as f64,
        None => 0.8277 - 0.175 * speed,
    };
    t.max(0.15)
}

/// Half-cycle duration guess [s] of `rule` at `speed` [m s⁻¹].
pub fn duration_guess_by(rule: crate::settings::DurationGuess, speed: f64) -> f64 {
    match rule {
        crate::settings::DurationGuess::Paper => duration_guess(speed),
        crate::settings::DurationGuess::Predsim => duration_guess_predsim(speed),
    }
}

/// Constant muscle and arm parts of every guess (activation 0.1, F̃_T 0.1, derivatives
/// 0.01 s⁻¹, arm activation and excitation 0.1).
#[derive(Clone, Copy, Debug)]
pub struct MuscleGuess {
    /// Muscle activation.
    pub activation: f64,
    /// Normalised tendon force.
    pub tendon_force: f64,
    /// Activation derivative [s⁻¹].
    pub activation_rate: f64,
    /// Normalised tendon-force derivative [s⁻¹].
    pub tendon_force_rate: f64,
    /// Arm activation and excitation.
    pub arm: f64,
}

impl MuscleGuess {
    /// The paper's values; the activation guess follows the co-contraction lower bound
    /// (0.1 + a_min − 0.05 when a_min > 0.05).
    pub fn for_settings(settings: &ProblemSettings) -> Self {
        let activation = if settings.activation_min > 0.05 {
            settings.activation_min + 0.05
        } else {
            0.1
        };
        Self {
            activation,
            tendon_force: 0.1,
            activation_rate: 0.01,
            tendon_force_rate: 0.01,
            arm: 0.1,
        }
    }
}

/// Coordinate trajectories of a guess at mesh points 0..N−1 (physical units).
pub struct CoordinateGuess {
    /// Positions per mesh point.
    pub q: Vec<Vec<f64>>,
    /// Speeds per mesh point.
    pub v: Vec<Vec<f64>>,
    /// Accelerations per mesh point.
    pub a: Vec<Vec<f64>>,
}

/// Quasi-random coordinates: all zero except forward translation spread over the distance
/// t_f·v and vertical translation at the standing pelvis height `height` [m] (0.9385 m for
/// the paper's model, [`crate::standing`]); forward speed = v.
pub fn quasi_random(
    n: usize,
    nq: usize,
    [tx, ty]: [usize; 2],
    height: f64,
    tf: f64,
    speed: f64,
) -> CoordinateGuess {
    let mut q = vec![vec![0.0; nq]; n];
    let mut v = vec![vec![0.0; nq]; n];
    let a = vec![vec![0.0; nq]; n];
    for k in 0..n {
        q[k][tx] = tf * speed * k as f64 / (n - 1) as f64;
        q[k][ty] = height;
        v[k][tx] = speed;
    }
    CoordinateGuess { q, v, a }
}

/// Data-informed coordinates: the experimental cycle resampled at N mesh points, forward
/// translation shifted to start at 0.
pub fn data_informed(data: &Kinematics, n: usize, tx: usize) -> CoordinateGuess {
    let r = data.resample(n);
    let mut q = r.q;
    let x0 = q[0][tx];
    q.iter_mut().for_each(|row| row[tx] -= x0);
    CoordinateGuess { q, v: r.v, a: r.a }
}

/// Assemble the scaled NLP vector of a guess. `mirror` maps a physical state vector at the
/// first mesh point to its mirror (used for the final mesh point of a symmetric half cycle;
/// identity for a periodic full cycle), `tx` is the forward translation index.
#[allow(clippy::too_many_arguments)]
pub fn assemble(
    layout: &Layout,
    scaling: &Scaling,
    coords: &CoordinateGuess,
    muscles: &MuscleGuess,
    tf: f64,
    tx: usize,
    mirror_q: &dyn Fn(&[f64]) -> Vec<f64>,
    mirror_v: &dyn Fn(&[f64]) -> Vec<f64>,
) -> Vec<f64> {
    let n = layout.n;
    let mut x = vec![0.0; layout.len()];
    x[layout.tf()] = tf;
    // Coordinates at mesh points 0..N-1 and the final point N.
    let mut q_mesh = coords.q.clone();
    let mut v_mesh = coords.v.clone();
    let mut last_q = mirror_q(&coords.q[0]);
    let inc = coords.q[n - 1][tx] - coords.q[n - 2][tx];
    last_q[tx] = coords.q[n - 1][tx] + inc;
    q_mesh.push(last_q);
    v_mesh.push(mirror_v(&coords.v[0]));
    let mut points: Vec<(Point, usize)> = (0..=n).map(|k| (Point::Mesh(k), k)).collect();
    for k in 0..n {
        for j in 1..=3 {
            points.push((Point::Col(k, j), k));
        }
    }
    for &(p, k) in &points {
        for i in 0..layout.nq {
            x[layout.q(p, i)] = q_mesh[k][i] / scaling.q[i];
            x[layout.v(p, i)] = v_mesh[k][i] / scaling.v[i];
        }
        for m in 0..layout.nm {
            x[layout.a(p, m)] = muscles.activation;
            x[layout.f(p, m)] = muscles.tendon_force / scaling.tendon_force;
        }
        for i in 0..layout.na {
            x[layout.arm(p, i)] = muscles.arm;
        }
    }
    for k in 0..n {
        for m in 0..layout.nm {
            x[layout.u_da(k, m)] = muscles.activation_rate / scaling.activation_rate;
        }
        for i in 0..layout.na {
            x[layout.e_arm(k, i)] = muscles.arm;
        }
        for j in 1..=3 {
            for m in 0..layout.nm {
                x[layout.u_df(k, j, m)] = muscles.tendon_force_rate / scaling.tendon_force_rate;
            }
            for i in 0..layout.nq {
                x[layout.u_dv(k, j, i)] = coords.a[k][i] / scaling.a[i];
            }
        }
    }
    x
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn initial_guesses_are_written_and_read_by_their_study_file_names() {
        let all = [
            ("quasi-random", "qr"),
            ("data-informed-walking", "diw"),
            ("data-informed-running", "dir"),
            ("full-os", "fos"),
            ("partial-os", "pos"),
        ];
        for (name, tag) in all {
            let g = InitialGuess::parse(name).unwrap();
            assert_eq!(g.to_string(), name);
            assert_eq!(g.tag(), tag);
            assert_eq!(g.is_continuation(), tag.ends_with("os"));
            let json = serde_json::to_string(&g).unwrap();
            assert_eq!(json, format!("\"{name}\""));
            assert_eq!(serde_json::from_str::<InitialGuess>(&json).unwrap(), g);
        }
        assert_eq!(
            InitialGuess::from(GuessKind::DataInformedWalking),
            InitialGuess::parse("di-walking").unwrap()
        );
        let e = serde_json::from_str::<InitialGuess>("\"full\"").unwrap_err();
        assert!(
            e.to_string().contains("unknown initial guess `full`"),
            "{e}"
        );
    }

    #[test]
    fn duration_guess_matches_the_reference_table() {
        assert!((duration_guess(1.33) - 0.595).abs() < 1e-12);
        assert!((duration_guess(0.73) - 0.70).abs() < 1e-12);
        assert!((duration_guess(2.73) - 0.35).abs() < 1e-12);
    }

    #[test]
    fn predsim_duration_guess_matches_its_table() {
        // PREDSIM.md §7.5: listed speeds 0.73 + 0.1 k, durations 0.70 − 0.35 k/42; 0.65 s at
        // 1.33 m/s; 1.25 m/s is not listed and takes the entry of 1.33 m/s.
        let close = |v: f64, t: f64| (duration_guess_predsim(v) - t).abs() < 1e-12;
        assert!(close(1.33, 0.65));
        assert!(close(1.25, 0.65));
        assert!(close(1.23, 0.70 - 0.35 * 5.0 / 42.0));
        assert!(close(0.73, 0.70) && close(0.5, 0.70));
        assert!(close(4.93, 0.35));
        assert!(close(6.0, 0.15));
    }
}

impl crate::problem::GaitProblem {
    /// The scaled NLP vector of an initial guess; data-informed guesses need the
    /// experimental kinematics (`data`) of the matching gait.
    pub fn initial_guess(
        &self,
        kind: GuessKind,
        data: Option<&Kinematics>,
    ) -> Result<Vec<f64>, GuessError> {
        let l = &self.layout;
        let half_tf = duration_guess_by(self.settings.guess_duration, self.settings.speed);
        let tf = match self.settings.cycle {
            crate::settings::CycleKind::HalfSymmetric => half_tf,
            crate::settings::CycleKind::FullPeriodic => 2.0 * half_tf,
        };
        let tx = self.gait.forward_translation;
        let ty = self.gait.vertical_translation;
        let coords = match kind {
            GuessKind::QuasiRandom => {
                let height = crate::standing::gait_standing_height(&self.model, &self.gait)?;
                quasi_random(l.n, l.nq, [tx, ty], height, tf, self.settings.speed)
            }
            GuessKind::DataInformedWalking | GuessKind::DataInformedRunning => {
                let data = data.ok_or(GuessError::MissingData(kind))?;
                data_informed(data, l.n, tx)
            }
        };
        let half = self.is_half_cycle();
        let mirror_q = |q: &[f64]| {
            if half {
                self.mirror_coordinates(q)
            } else {
                q.to_vec()
            }
        };
        Ok(assemble(
            l,
            &self.scaling,
            &coords,
            &MuscleGuess::for_settings(&self.settings),
            tf,
            tx,
            &mirror_q,
            &mirror_q,
        ))
    }
}

/// Why a guess could not be built.
#[derive(Debug, thiserror::Error)]
pub enum GuessError {
    /// A data-informed guess without data.
    #[error("the {0} guess needs experimental kinematics")]
    MissingData(GuessKind),
    /// The quasi-random guess without a standing pelvis height.
    #[error("quasi-random guess: {0}")]
    Standing(#[from] crate::standing::StandingError),
}

/// Which part of a neighbouring optimal solution seeds a continuation guess
/// (FORMULATION 10.3).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum ContinuationKind {
    /// The entire optimal NLP vector (t_f, states, controls), rescaled to this problem.
    FullSolution,
    /// Only the joint positions (re-filtered and splined); muscle and arm parts as usual.
    PartialSolution,
}

/// Where a solve's initial point came from: a guess built from the settings alone or a
/// continuation from a neighbouring solution. Written as its study-file name
/// (`quasi-random`, `data-informed-walking`, `data-informed-running`, `full-os`,
/// `partial-os`) in `summary.json`, case records and file names.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[serde(into = "String", try_from = "String")]
pub enum InitialGuess {
    /// A guess built from the settings alone (quasi-random, data-informed walking or running).
    Standard(GuessKind),
    /// A guess built from the solution of a neighbouring case.
    Continuation(ContinuationKind),
}

impl InitialGuess {
    /// Parse a guess name as written in study files (also the short tags `qr`,
    /// `di-walking`, `di-running`, and `full-solution`, `partial-solution`).
    pub fn parse(s: &str) -> Option<Self> {
        Some(match s.trim() {
            "quasi-random" | "qr" => Self::Standard(GuessKind::QuasiRandom),
            "data-informed-walking" | "di-walking" => {
                Self::Standard(GuessKind::DataInformedWalking)
            }
            "data-informed-running" | "di-running" => {
                Self::Standard(GuessKind::DataInformedRunning)
            }
            "full-os" | "full-solution" => Self::Continuation(ContinuationKind::FullSolution),
            "partial-os" | "partial-solution" => {
                Self::Continuation(ContinuationKind::PartialSolution)
            }
            _ => return None,
        })
    }

    /// Short tag used in case names.
    pub fn tag(&self) -> &'static str {
        match self {
            Self::Standard(GuessKind::QuasiRandom) => "qr",
            Self::Standard(GuessKind::DataInformedWalking) => "diw",
            Self::Standard(GuessKind::DataInformedRunning) => "dir",
            Self::Continuation(ContinuationKind::FullSolution) => "fos",
            Self::Continuation(ContinuationKind::PartialSolution) => "pos",
        }
    }

    /// Whether the guess needs a finished neighbouring solution.
    pub fn is_continuation(&self) -> bool {
        matches!(self, Self::Continuation(_))
    }
}

impl std::fmt::Display for InitialGuess {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Self::Standard(g) => write!(f, "{g}"),
            Self::Continuation(ContinuationKind::FullSolution) => f.write_str("full-os"),
            Self::Continuation(ContinuationKind::PartialSolution) => f.write_str("partial-os"),
        }
    }
}

impl From<GuessKind> for InitialGuess {
    fn from(g: GuessKind) -> Self {
        Self::Standard(g)
    }
}

impl From<InitialGuess> for String {
    fn from(g: InitialGuess) -> String {
        g.to_string()
    }
}

impl TryFrom<String> for InitialGuess {
    type Error = String;
    fn try_from(s: String) -> Result<Self, String> {
        Self::parse(&s).ok_or_else(|| format!("unknown initial guess `{s}`"))
    }
}

/// Why a continuation guess could not be built from a solution.
#[derive(Debug, thiserror::Error)]
pub enum ContinuationError {
    /// The source solution has another variable layout.
    #[error("source solution layout {from:?} differs from the problem's {target:?} (mesh intervals, muscles, coordinates, arm actuators)")]
    Layout {
        /// (N, muscles, coordinates, arms) of the source.
        from: [usize; 4],
        /// (N, muscles, coordinates, arms) of the problem.
        target: [usize; 4],
    },
    /// The source solves another cycle (half with symmetry vs full with periodicity).
    #[error("source solution covers {from} gait cycle, the problem {target}")]
    Cycle {
        /// "a half" or "a full" (source).
        from: &'static str,
        /// "a half" or "a full" (problem).
        target: &'static str,
    },
    /// The source vector has the wrong length.
    #[error("source solution has {got} variables, its layout needs {expected}")]
    Length {
        /// Length given.
        got: usize,
        /// Length expected.
        expected: usize,
    },
    /// The source coordinate samples are unusable.
    #[error("source coordinates: {0}")]
    Coordinates(String),
}

fn layout_dims(l: &Layout) -> [usize; 4] {
    [l.n, l.nm, l.nq, l.na]
}

/// Time of point `p` as a fraction of the duration (0 at mesh point 0, 1 at mesh point N).
fn point_time(l: &Layout, p: Point) -> f64 {
    let tau = crate::radau::points();
    match p {
        Point::Mesh(k) => k as f64 / l.n as f64,
        Point::Col(k, j) => (k as f64 + tau[j]) / l.n as f64,
    }
}

/// Source interval of `l` that holds normalised time `t` (the last one for t = 1), and the
/// local time in it (0 at its start, 1 at its end).
fn locate(l: &Layout, t: f64) -> (usize, f64) {
    let s = t * l.n as f64;
    let k = (s.max(0.0).floor() as usize).min(l.n - 1);
    (k, s - k as f64)
}

/// The NLP vector `x` of layout `from` carried to layout `to` (same muscles, coordinates
/// and arm actuators, any number of mesh intervals) in normalised time, following the
/// source's own collocation polynomials: states from the cubic of the source interval
/// through its mesh and collocation points, collocation-point controls (tendon-force rates,
/// accelerations) from the quadratic through the interval's three collocation points (the
/// derivative of that cubic at a solution), interval controls (activation rates, arm
/// excitations) from the source interval holding the target interval's midpoint, the final
/// mesh point copied (so a symmetric half cycle stays closed), t_f unchanged. A target
/// interval inside one source interval then meets the collocation equations of the
/// activations, tendon forces and speeds exactly; the remaining violation is the dynamics
/// at the new points. The collocation points of a target interval use the source interval
/// of its midpoint, so a polynomial is never evaluated across a source mesh point there.
/// Values between samples may pass a bound the samples meet (a polynomial's extremum); the
/// solver's bound push moves them back.
pub fn resample_solution(from: &Layout, x: &[f64], to: &Layout) -> Vec<f64> {
    let mut out = vec![0.0; to.len()];
    out[to.tf()] = x[from.tf()];
    let source_points = |k: usize| {
        [
            Point::Mesh(k),
            Point::Col(k, 1),
            Point::Col(k, 2),
            Point::Col(k, 3),
        ]
    };
    let put_states = |out: &mut [f64], p: Point, ks: usize, tau: f64| {
        let w = crate::radau::state_weights(tau);
        let src = source_points(ks);
        for s in 0..to.n_states() {
            out[to.state(p, s)] = (0..4).map(|r| w[r] * x[from.state(src[r], s)]).sum();
        }
    };
    // mesh points: the source interval holding them; the last one copied
    for k in 0..to.n {
        let (ks, tau) = locate(from, k as f64 / to.n as f64);
        put_states(&mut out, Point::Mesh(k), ks, tau);
    }
    for s in 0..to.n_states() {
        out[to.state(Point::Mesh(to.n), s)] = x[from.state(Point::Mesh(from.n), s)];
    }
    type ColIndex = fn(&Layout, usize, usize, usize) -> usize;
    let per_col: [(usize, ColIndex); 2] = [(from.nm, Layout::u_df), (from.nq, Layout::u_dv)];
    type IntervalIndex = fn(&Layout, usize, usize) -> usize;
    let per_interval: [(usize, IntervalIndex); 2] =
        [(from.nm, Layout::u_da), (from.na, Layout::e_arm)];
    for k in 0..to.n {
        // everything inside a target interval comes from the source interval of its midpoint
        let (ks, _) = locate(from, (k as f64 + 0.5) / to.n as f64);
        for j in 1..=3 {
            let tau = point_time(to, Point::Col(k, j)) * from.n as f64 - ks as f64;
            put_states(&mut out, Point::Col(k, j), ks, tau);
            let w = crate::radau::collocation_weights(tau);
            for (width, index) in per_col {
                for i in 0..width {
                    out[index(to, k, j, i)] =
                        (0..3).map(|r| w[r] * x[index(from, ks, r + 1, i)]).sum();
                }
            }
        }
        for (width, index) in per_interval {
            for i in 0..width {
                out[index(to, k, i)] = x[index(from, ks, i)];
            }
        }
    }
    out
}

impl crate::problem::GaitProblem {
    /// Full-OS guess: the solution `x` of `source` (same muscles, coordinates and arm
    /// actuators; another mesh is resampled by [`resample_solution`]), with positions,
    /// speeds and accelerations unscaled by the source's scale factors and rescaled by this
    /// problem's.
    pub fn guess_from_full_solution(
        &self,
        source: &crate::problem::GaitProblem,
        x: &[f64],
    ) -> Result<Vec<f64>, ContinuationError> {
        let (l, ls) = (&self.layout, &source.layout);
        if layout_dims(l)[1..] != layout_dims(ls)[1..] {
            return Err(ContinuationError::Layout {
                from: layout_dims(ls),
                target: layout_dims(l),
            });
        }
        if self.is_half_cycle() != source.is_half_cycle() {
            let name = |half: bool| if half { "a half" } else { "a full" };
            return Err(ContinuationError::Cycle {
                from: name(source.is_half_cycle()),
                target: name(self.is_half_cycle()),
            });
        }
        if x.len() != ls.len() {
            return Err(ContinuationError::Length {
                got: x.len(),
                expected: ls.len(),
            });
        }
        let (s, so) = (&self.scaling, &source.scaling);
        let x = if l.n == ls.n {
            x.to_vec()
        } else {
            resample_solution(ls, x, l)
        };
        let x = &x;
        let mut out = x.to_vec();
        let mut points: Vec<Point> = (0..=l.n).map(Point::Mesh).collect();
        for k in 0..l.n {
            for j in 1..=3 {
                points.push(Point::Col(k, j));
            }
        }
        for &p in &points {
            for i in 0..l.nq {
                out[l.q(p, i)] = x[l.q(p, i)] * so.q[i] / s.q[i];
                out[l.v(p, i)] = x[l.v(p, i)] * so.v[i] / s.v[i];
            }
        }
        for k in 0..l.n {
            for j in 1..=3 {
                for i in 0..l.nq {
                    out[l.u_dv(k, j, i)] = x[l.u_dv(k, j, i)] * so.a[i] / s.a[i];
                }
            }
        }
        Ok(out)
    }

    /// Partial-OS guess: joint positions `q[sample][coordinate]` [rad or m] (problem order)
    /// at `time` [s] from a neighbouring solution (its first N cycle samples), low-pass
    /// filtered and splined as the experimental data to obtain speeds and accelerations;
    /// muscle and arm parts as in every guess; t_f = the duration of those samples.
    pub fn guess_from_coordinates(
        &self,
        time: &[f64],
        q: &[Vec<f64>],
    ) -> Result<Vec<f64>, ContinuationError> {
        let l = &self.layout;
        if time.len() != q.len() || q.iter().any(|r| r.len() != l.nq) {
            return Err(ContinuationError::Coordinates(format!(
                "{} times and {} rows of {} coordinates expected",
                time.len(),
                q.len(),
                l.nq
            )));
        }
        let mut labels = vec!["time".to_string()];
        labels.extend(self.gait.coordinates.iter().map(|c| c.name.clone()));
        let rows = time
            .iter()
            .zip(q)
            .map(|(&t, r)| std::iter::once(t).chain(r.iter().copied()).collect())
            .collect();
        let storage = stride_model::storage::Storage {
            name: "neighbouring solution".into(),
            in_degrees: Some(false),
            labels,
            rows,
        };
        let kin = Kinematics::from_storage(&storage, &self.gait, "neighbouring solution")
            .map_err(|e| ContinuationError::Coordinates(e.to_string()))?;
        let tx = self.gait.forward_translation;
        let coords = data_informed(&kin, l.n, tx);
        let tf = time[time.len() - 1] - time[0];
        let half = self.is_half_cycle();
        let mirror = |q: &[f64]| {
            if half {
                self.mirror_coordinates(q)
            } else {
                q.to_vec()
            }
        };
        Ok(assemble(
            l,
            &self.scaling,
            &coords,
            &MuscleGuess::for_settings(&self.settings),
            tf,
            tx,
            &mirror,
            &mirror,
        ))
    }
}

#[cfg(test)]
mod continuation_tests {
    use super::*;
    use crate::problem::GaitProblem;

    /// Every state point of `l` in time order: per interval its mesh point and its three
    /// collocation points, then the final mesh point.
    fn state_points(l: &Layout) -> Vec<Point> {
        let mut pts = Vec::with_capacity(4 * l.n + 1);
        for k in 0..l.n {
            pts.push(Point::Mesh(k));
            pts.extend((1..=3).map(|j| Point::Col(k, j)));
        }
        pts.push(Point::Mesh(l.n));
        pts
    }

    fn problem(speed: f64) -> GaitProblem {
        let settings = ProblemSettings {
            speed,
            mesh_intervals: 10,
            ..Default::default()
        };
        GaitProblem::new(
            &stride_model::default_model::default_model(),
            &settings,
            &crate::bounds::bounds_data(&settings),
        )
        .unwrap()
    }

    #[test]
    fn quasi_random_guess_of_the_paper_model_stands_at_the_papers_height() {
        // FORMULATION 10.1: pelvis_ty 0.9385 m, t_f 0.595 s at 1.33 m/s, pelvis_tx from 0
        // to t_f·v over mesh points 0..N−1
        let p = problem(1.33);
        let x = p.initial_guess(GuessKind::QuasiRandom, None).unwrap();
        let (l, s) = (&p.layout, &p.scaling);
        let (tx, ty) = (p.gait.forward_translation, p.gait.vertical_translation);
        for k in [0, 4, l.n] {
            assert!((x[l.q(Point::Mesh(k), ty)] * s.q[ty] - 0.9385).abs() < 1e-12);
        }
        assert!((x[l.tf()] - 0.595).abs() < 1e-12);
        let last = x[l.q(Point::Mesh(l.n - 1), tx)] * s.q[tx];
        assert!((last - 0.595 * 1.33).abs() < 1e-12);
    }

    #[test]
    fn full_solution_keeps_physical_values_across_scale_factors() {
        let (a, b) = (problem(1.33), problem(2.33));
        let x = a.initial_guess(GuessKind::QuasiRandom, None).unwrap();
        assert_eq!(a.guess_from_full_solution(&a, &x).unwrap(), x);
        let y = b.guess_from_full_solution(&a, &x).unwrap();
        let l = &a.layout;
        let p = Point::Col(3, 2);
        let mut rescaled = 0;
        for i in 0..l.nq {
            assert!((y[l.q(p, i)] * b.scaling.q[i] - x[l.q(p, i)] * a.scaling.q[i]).abs() < 1e-12);
            assert!((y[l.v(p, i)] * b.scaling.v[i] - x[l.v(p, i)] * a.scaling.v[i]).abs() < 1e-12);
            if a.scaling.v[i] != b.scaling.v[i] && x[l.v(p, i)] != 0.0 {
                rescaled += 1;
            }
        }
        assert!(
            rescaled > 0,
            "the two speeds have different speed scale factors"
        );
        assert_eq!(y[l.tf()], x[l.tf()]);
        let short = &x[..x.len() - 1];
        assert!(b.guess_from_full_solution(&a, short).is_err());
        let with = |s: ProblemSettings| {
            GaitProblem::new(
                &stride_model::default_model::default_model(),
                &s,
                &crate::bounds::bounds_data(&s),
            )
            .unwrap()
        };
        // another mesh is resampled; another cycle is refused
        let c = with(ProblemSettings {
            mesh_intervals: 12,
            ..Default::default()
        });
        assert_eq!(
            c.guess_from_full_solution(&a, &x).unwrap().len(),
            c.layout.len()
        );
        let full = with(ProblemSettings {
            mesh_intervals: 10,
            cycle: crate::settings::CycleKind::FullPeriodic,
            ..Default::default()
        });
        let e = full.guess_from_full_solution(&a, &x).unwrap_err();
        assert!(matches!(e, ContinuationError::Cycle { .. }), "{e}");
        assert!(e.to_string().contains("half"), "{e}");
    }

    /// Values of kind `kind`, component `i`: a cubic in normalised time `t`.
    fn cubic(kind: usize, i: usize, t: f64) -> f64 {
        let (a, b) = (0.1 * (kind + 1) as f64, 1e-3 * i as f64);
        a + b + (0.5 - 0.01 * i as f64) * t - 0.7 * t * t + (0.3 + b) * t * t * t
    }

    /// The derivative in t of any kind's cubic of component `i`.
    fn cubic_rate(i: usize, t: f64) -> f64 {
        let b = 1e-3 * i as f64;
        (0.5 - 0.01 * i as f64) - 1.4 * t + 3.0 * (0.3 + b) * t * t
    }

    /// A point of layout `l` whose states are cubics in time, whose collocation controls are
    /// their (quadratic) rates and whose interval controls are numbered by interval.
    fn cubic_in_time(l: &Layout) -> Vec<f64> {
        let mut x = vec![0.0; l.len()];
        x[l.tf()] = 0.55;
        for p in state_points(l) {
            for s in 0..l.n_states() {
                x[l.state(p, s)] = cubic(0, s, point_time(l, p));
            }
        }
        for k in 0..l.n {
            for j in 1..=3 {
                let t = point_time(l, Point::Col(k, j));
                for m in 0..l.nm {
                    x[l.u_df(k, j, m)] = cubic_rate(m, t);
                }
                for i in 0..l.nq {
                    x[l.u_dv(k, j, i)] = cubic_rate(i, t);
                }
            }
            for m in 0..l.nm {
                x[l.u_da(k, m)] = (100 * k + m) as f64;
            }
            for i in 0..l.na {
                x[l.e_arm(k, i)] = (100 * k + 50 + i) as f64;
            }
        }
        x
    }

    #[test]
    fn resampling_reproduces_cubic_trajectories_on_another_mesh() {
        // a cubic state and its quadratic rate are what one collocation interval holds, so
        // a trajectory that is one cubic throughout is carried to any mesh exactly
        for (nf, nt) in [(10, 25), (10, 50), (7, 3), (4, 9)] {
            let (from, to) = (Layout::new(nf, 3, 4, 2), Layout::new(nt, 3, 4, 2));
            let x = cubic_in_time(&from);
            let y = resample_solution(&from, &x, &to);
            assert_eq!(y.len(), to.len());
            assert_eq!(y[to.tf()], 0.55);
            let expect = cubic_in_time(&to);
            let close = |a: f64, b: f64| (a - b).abs() < 1e-12;
            for p in state_points(&to) {
                for s in 0..to.n_states() {
                    let (got, want) = (y[to.state(p, s)], expect[to.state(p, s)]);
                    assert!(
                        close(got, want),
                        "{nf}→{nt} {p:?} state {s}: {got} vs {want}"
                    );
                }
            }
            for k in 0..to.n {
                for j in 1..=3 {
                    for i in 0..to.nq {
                        assert!(close(y[to.u_dv(k, j, i)], expect[to.u_dv(k, j, i)]));
                    }
                    for m in 0..to.nm {
                        assert!(close(y[to.u_df(k, j, m)], expect[to.u_df(k, j, m)]));
                    }
                }
                // interval controls from the source interval holding the target midpoint
                let ks = ((k as f64 + 0.5) / nt as f64 * nf as f64) as usize;
                for m in 0..to.nm {
                    assert_eq!(y[to.u_da(k, m)], x[from.u_da(ks, m)]);
                }
                for i in 0..to.na {
                    assert_eq!(y[to.e_arm(k, i)], x[from.e_arm(ks, i)]);
                }
            }
        }
    }

    #[test]
    fn resampling_a_piecewise_trajectory_follows_each_interval_and_keeps_the_end() {
        // Independent samples per interval (no common polynomial): a target point inside a
        // source interval takes that interval's cubic, so a target on a refined mesh whose
        // intervals nest in the source's reproduces the source at its own points; the last
        // mesh point is the source's last, whatever the polynomial gives there.
        let (from, to) = (Layout::new(5, 2, 3, 1), Layout::new(15, 2, 3, 1));
        let x: Vec<f64> = (0..from.len())
            .map(|i| ((i * 7919) % 101) as f64 / 100.0)
            .collect();
        let y = resample_solution(&from, &x, &to);
        let tau = crate::radau::points();
        for ks in 0..from.n {
            for s in 0..from.n_states() {
                // source mesh point ks is target mesh point 3 ks
                assert!(
                    (y[to.state(Point::Mesh(3 * ks), s)] - x[from.state(Point::Mesh(ks), s)]).abs()
                        < 1e-12
                );
            }
        }
        for s in 0..from.n_states() {
            assert_eq!(
                y[to.state(Point::Mesh(to.n), s)],
                x[from.state(Point::Mesh(from.n), s)]
            );
            // a target collocation point in source interval 2, evaluated by hand
            let t = point_time(&to, Point::Col(7, 2)) * 5.0 - 2.0;
            let src = [
                Point::Mesh(2),
                Point::Col(2, 1),
                Point::Col(2, 2),
                Point::Col(2, 3),
            ];
            let want: f64 = (0..4)
                .map(|r| {
                    let l: f64 = (0..4)
                        .filter(|&q| q != r)
                        .map(|q| (t - tau[q]) / (tau[r] - tau[q]))
                        .product();
                    l * x[from.state(src[r], s)]
                })
                .sum();
            assert!((y[to.state(Point::Col(7, 2), s)] - want).abs() < 1e-12);
        }
    }

    #[test]
    fn partial_solution_of_a_still_posture_has_zero_speeds() {
        // Constant coordinates: filtering and splining keep them, speeds and accelerations
        // vanish, t_f is the duration of the samples, pelvis_tx starts at 0.
        let p = problem(1.33);
        let l = &p.layout;
        let n = l.n;
        let time: Vec<f64> = (0..n).map(|k| 0.06 * k as f64).collect();
        let row: Vec<f64> = (0..l.nq).map(|i| 0.01 * i as f64 + 0.1).collect();
        let q = vec![row.clone(); n];
        let x = p.guess_from_coordinates(&time, &q).unwrap();
        assert!((x[l.tf()] - 0.06 * (n - 1) as f64).abs() < 1e-12);
        let tx = p.gait.forward_translation;
        let pt = Point::Mesh(4);
        for i in 0..l.nq {
            let expect = if i == tx { 0.0 } else { row[i] };
            assert!(
                (x[l.q(pt, i)] * p.scaling.q[i] - expect).abs() < 1e-9,
                "q {i}"
            );
            assert!((x[l.v(pt, i)] * p.scaling.v[i]).abs() < 1e-8, "v {i}");
            assert!((x[l.u_dv(4, 1, i)] * p.scaling.a[i]).abs() < 1e-6, "a {i}");
        }
        let m = MuscleGuess::for_settings(&p.settings);
        assert_eq!(x[l.a(pt, 0)], m.activation);
        assert!(p.guess_from_coordinates(&time[..3], &q[..3]).is_err());
    }
}
