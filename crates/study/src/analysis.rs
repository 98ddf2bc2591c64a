//! Analysis of a study (FORMULATION 11.3 and 13.2): walk/run classification from the phase
//! of the centre-of-mass energies, transition speed, cost of transport and stride
//! frequency versus speed with least-squares fits and their R².

use serde::Serialize;
use std::collections::BTreeMap;
use stride_ocp::settings::ProblemSettings;

/// Gait type from the phase of the centre-of-mass energies.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum GaitType {
    /// Potential and forward kinetic energy out of phase (pendulum exchange).
    Walking,
    /// Potential and forward kinetic energy in phase (spring-mass bouncing).
    Running,
}

fn min_max_normalise(x: &[f64]) -> Vec<f64> {
    let lo = x.iter().copied().fold(f64::INFINITY, f64::min);
    let hi = x.iter().copied().fold(f64::NEG_INFINITY, f64::max);
    let range = hi - lo;
    x.iter()
        .map(|v| if range > 0.0 { (v - lo) / range } else { 0.0 })
        .collect()
}

/// Pearson correlation of two equally long series (0 when either is constant).
pub fn correlation(a: &[f64], b: &[f64]) -> f64 {
    let n = a.len().min(b.len());
    if n == 0 {
        return 0.0;
    }
    let ma = a[..n].iter().sum::<f64>() / n as f64;
    let mb = b[..n].iter().sum::<f64>() / n as f64;
    let (mut sab, mut saa, mut sbb) = (0.0, 0.0, 0.0);
    for i in 0..n {
        let (da, db) = (a[i] - ma, b[i] - mb);
        sab += da * db;
        saa += da * da;
        sbb += db * db;
    }
    if saa <= 0.0 || sbb <= 0.0 {
        0.0
    } else {
        sab / (saa * sbb).sqrt()
    }
}

/// Correlation over a gait cycle of the min–max normalised potential energy m g y [J] and
/// forward kinetic energy ½ m v_x² [J] of the centre of mass, from its height `y` [m] and
/// forward velocity `vx` [m s⁻¹] sampled over the cycle: > 0 in phase, < 0 out of phase.
pub fn energy_phase_correlation(y: &[f64], vx: &[f64], mass: f64, gravity: f64) -> f64 {
    let ep: Vec<f64> = y.iter().map(|y| mass * gravity * y).collect();
    let ek: Vec<f64> = vx.iter().map(|v| 0.5 * mass * v * v).collect();
    correlation(&min_max_normalise(&ep), &min_max_normalise(&ek))
}

/// Walking when the COM energies are out of phase (correlation < 0), running otherwise.
pub fn classify(correlation: f64) -> GaitType {
    if correlation > 0.0 {
        GaitType::Running
    } else {
        GaitType::Walking
    }
}

/// Walk-to-run transition speed [m s⁻¹]: the lowest running speed (FORMULATION 11.3).
pub fn transition_speed(points: &[(f64, GaitType)]) -> Option<f64> {
    points
        .iter()
        .filter(|p| p.1 == GaitType::Running)
        .map(|p| p.0)
        .min_by(f64::total_cmp)
}

/// A least-squares polynomial fit.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Fit {
    /// Coefficients, constant first: y = c₀ + c₁ x + c₂ x² …
    pub coefficients: Vec<f64>,
    /// Coefficient of determination R² = 1 − SS_res/SS_tot.
    pub r_squared: f64,
    /// Number of points fitted.
    pub n: usize,
}

impl Fit {
    /// Value of the fitted polynomial at `x`.
    pub fn eval(&self, x: f64) -> f64 {
        self.coefficients
            .iter()
            .rev()
            .fold(0.0, |acc, c| acc * x + c)
    }

    /// Whether the polynomial passes through every point (as many points as coefficients),
    /// so that its R² says nothing.
    pub fn is_exact(&self) -> bool {
        self.n <= self.coefficients.len()
    }

    /// The fit's quality for reports: "R² = 0.98" (with `decimals` decimals), or "exact
    /// through 3 points" when the polynomial has no residual degrees of freedom.
    pub fn quality(&self, decimals: usize) -> String {
        if self.is_exact() {
            format!("exact through {} points", self.n)
        } else {
            format!("R² = {:.*}", decimals, self.r_squared)
        }
    }
}

/// Least-squares polynomial of `degree` through (x, y); `None` with fewer than degree + 1
/// points or a singular system (repeated x).
pub fn polyfit(x: &[f64], y: &[f64], degree: usize) -> Option<Fit> {
    let n = x.len().min(y.len());
    let m = degree + 1;
    if n < m {
        return None;
    }
    // Normal equations with x centred and scaled for conditioning.
    let xm = x[..n].iter().sum::<f64>() / n as f64;
    let xs = x[..n]
        .iter()
        .map(|v| (v - xm).abs())
        .fold(0.0, f64::max)
        .max(1e-300);
    let mut a = vec![vec![0.0; m + 1]; m];
    for k in 0..n {
        let t = (x[k] - xm) / xs;
        let pw: Vec<f64> = (0..m).map(|p| t.powi(p as i32)).collect();
        for r in 0..m {
            for c in 0..m {
                a[r][c] += pw[r] * pw[c];
            }
            a[r][m] += pw[r] * y[k];
        }
    }
    // Gaussian elimination with partial pivoting.
    for col in 0..m {
        let piv = (col..m).max_by(|&i, &j| a[i][col].abs().total_cmp(&a[j][col].abs()))?;
        if a[piv][col].abs() < 1e-12 * n as f64 {
            return None;
        }
        a.swap(col, piv);
        let pivot_row = a[col].clone();
        for (r, row) in a.iter_mut().enumerate() {
            if r != col {
                let f = row[col] / pivot_row[col];
                for (x, p) in row.iter_mut().zip(&pivot_row).skip(col) {
                    *x -= f * p;
                }
            }
        }
    }
    let b: Vec<f64> = (0..m).map(|i| a[i][m] / a[i][i]).collect();
    // Back to coefficients in x: Σ b_p ((x − xm)/xs)^p.
    let mut coefficients = vec![0.0; m];
    for (p, bp) in b.iter().enumerate() {
        // (x − xm)^p = Σ_k C(p,k) x^k (−xm)^(p−k)
        let mut binom = 1.0;
        for (k, c) in coefficients.iter_mut().enumerate().take(p + 1) {
            if k > 0 {
                binom = binom * (p - k + 1) as f64 / k as f64;
            }
            *c += bp / xs.powi(p as i32) * binom * (-xm).powi((p - k) as i32);
        }
    }
    let mean = y[..n].iter().sum::<f64>() / n as f64;
    let mut fit = Fit {
        coefficients,
        r_squared: 0.0,
        n,
    };
    let ss_tot: f64 = y[..n].iter().map(|v| (v - mean).powi(2)).sum();
    let ss_res: f64 = (0..n).map(|k| (y[k] - fit.eval(x[k])).powi(2)).sum();
    fit.r_squared = if ss_tot > 0.0 {
        1.0 - ss_res / ss_tot
    } else {
        1.0
    };
    Some(fit)
}

/// Literature stride frequency [strides s⁻¹] at a walking speed [m s⁻¹] (Hansen et al.
/// 2017, FORMULATION 11.3): (34.2 + 16.2 v)/60.
pub fn literature_stride_frequency(speed: f64) -> f64 {
    (34.2 + 16.2 * speed) / 60.0
}

/// The selected (lowest-objective converged) case of one group.
#[derive(Clone, Debug, Serialize)]
pub struct Selected {
    /// Group name (case name without the guess).
    pub group: String,
    /// Grid axis values.
    pub axes: BTreeMap<String, String>,
    /// Kept case.
    pub case: String,
    /// Its guess.
    pub guess: String,
    /// Objective.
    pub objective: Option<f64>,
    /// Speed [m s⁻¹].
    pub speed: f64,
    /// Cost of transport [J kg⁻¹ m⁻¹].
    pub cost_of_transport: Option<f64>,
    /// Stride frequency [strides s⁻¹].
    pub stride_frequency: Option<f64>,
    /// Stride length [m].
    pub stride_length: Option<f64>,
    /// Walking or running (when the COM energies were computed).
    pub gait: Option<GaitType>,
}

/// Speed dependence within one chain (same axes except the speed).
#[derive(Clone, Debug, Serialize)]
pub struct SpeedSeries {
    /// Axis values shared by the series (everything but the speed).
    pub key: BTreeMap<String, String>,
    /// Selected cases, by increasing speed.
    pub points: Vec<Selected>,
    /// Lowest running speed [m s⁻¹].
    pub transition_speed: Option<f64>,
    /// Quadratic fit of COT over walking speeds (up to and including the transition).
    pub cot_walking_fit: Option<Fit>,
    /// Linear fit of COT over running speeds (from the transition).
    pub cot_running_fit: Option<Fit>,
    /// Linear fit of stride frequency over walking speeds.
    pub stride_frequency_walking_fit: Option<Fit>,
}

/// The distinct meshes of `settings` as figure captions state them, joined by `; `.
pub fn mesh_caption<'a>(settings: impl Iterator<Item = &'a ProblemSettings>) -> String {
    let mut meshes: Vec<String> = Vec::new();
    for s in settings {
        let m = stride_predict::figures::mesh_caption(s);
        if !meshes.contains(&m) {
            meshes.push(m);
        }
    }
    meshes.join("; ")
}

/// Classification, transition and fits of one speed series.
pub fn speed_series_of(key: BTreeMap<String, String>, points: Vec<Selected>) -> SpeedSeries {
    let classified: Vec<(f64, GaitType)> = points
        .iter()
        .filter_map(|p| p.gait.map(|g| (p.speed, g)))
        .collect();
    let transition = transition_speed(&classified);
    let split = transition.unwrap_or(f64::INFINITY);
    let pairs = |f: &dyn Fn(&Selected) -> Option<f64>, keep: &dyn Fn(f64) -> bool| {
        let (x, y): (Vec<f64>, Vec<f64>) = points
            .iter()
            .filter(|p| keep(p.speed))
            .filter_map(|p| f(p).map(|v| (p.speed, v)))
            .unzip();
        (x, y)
    };
    let walk = |v: f64| v <= split + 1e-9;
    let run = |v: f64| transition.is_some() && v >= split - 1e-9;
    let (xw, yw) = pairs(&|p| p.cost_of_transport, &walk);
    let (xr, yr) = pairs(&|p| p.cost_of_transport, &run);
    let (xf, yf) = pairs(&|p| p.stride_frequency, &|v| v < split - 1e-9);
    SpeedSeries {
        key,
        transition_speed: transition,
        cot_walking_fit: polyfit(&xw, &yw, 2),
        cot_running_fit: polyfit(&xr, &yr, 1),
        stride_frequency_walking_fit: polyfit(&xf, &yf, 1),
        points,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::f64::consts::PI;

    fn cycle(n: usize) -> Vec<f64> {
        (0..n).map(|k| k as f64 / n as f64).collect()
    }

    #[test]
    fn anti_phase_com_energies_are_walking_and_in_phase_running() {
        let t = cycle(100);
        // Walking: COM highest at mid-stance when it is slowest (energies out of phase).
        let y: Vec<f64> = t
            .iter()
            .map(|t| 0.95 + 0.02 * (4.0 * PI * t).cos())
            .collect();
        let vx_walk: Vec<f64> = t.iter().map(|t| 1.3 - 0.1 * (4.0 * PI * t).cos()).collect();
        let vx_run: Vec<f64> = t.iter().map(|t| 3.0 + 0.1 * (4.0 * PI * t).cos()).collect();
        let cw = energy_phase_correlation(&y, &vx_walk, 62.0, 9.81);
        let cr = energy_phase_correlation(&y, &vx_run, 62.0, 9.81);
        assert!(cw < -0.99, "{cw}");
        assert!(cr > 0.99, "{cr}");
        assert_eq!(classify(cw), GaitType::Walking);
        assert_eq!(classify(cr), GaitType::Running);
        // Quarter-period lag: uncorrelated for a pure sinusoid pair.
        let s: Vec<f64> = t.iter().map(|t| (2.0 * PI * t).sin()).collect();
        let c: Vec<f64> = t.iter().map(|t| (2.0 * PI * t).cos()).collect();
        assert!(correlation(&s, &c).abs() < 1e-12);
    }

    #[test]
    fn exact_polynomials_are_recovered_with_unit_r_squared() {
        let x: Vec<f64> = (0..15).map(|k| 0.73 + 0.1 * k as f64).collect();
        let y: Vec<f64> = x.iter().map(|x| 3.2 - 1.5 * x + 0.9 * x * x).collect();
        let f = polyfit(&x, &y, 2).unwrap();
        assert!((f.r_squared - 1.0).abs() < 1e-12, "{}", f.r_squared);
        for (c, e) in f.coefficients.iter().zip([3.2, -1.5, 0.9]) {
            assert!((c - e).abs() < 1e-9, "{c} vs {e}");
        }
        let y1: Vec<f64> = x.iter().map(|x| 0.5 + 2.0 * x).collect();
        let f1 = polyfit(&x, &y1, 1).unwrap();
        assert!(
            (f1.coefficients[0] - 0.5).abs() < 1e-12 && (f1.coefficients[1] - 2.0).abs() < 1e-12
        );
        assert!((f1.r_squared - 1.0).abs() < 1e-12);
        assert!(polyfit(&x[..2], &y[..2], 2).is_none());
        let exact = polyfit(&x[..3], &y[..3], 2).unwrap();
        assert!(exact.is_exact() && exact.quality(2).starts_with("exact through 3"));
        assert!(!f.is_exact() && f.quality(3).starts_with("R² = "));
    }

    #[test]
    fn r_squared_of_a_line_through_symmetric_data_is_analytic() {
        // y = x² on x = −1, 0, 1 with a linear fit: the line is y = 2/3, SS_res = SS_tot.
        let f = polyfit(&[-1.0, 0.0, 1.0], &[1.0, 0.0, 1.0], 1).unwrap();
        assert!(f.r_squared.abs() < 1e-12);
        assert!((f.coefficients[0] - 2.0 / 3.0).abs() < 1e-12);
    }

    #[test]
    fn transition_is_the_lowest_running_speed_and_fits_split_there() {
        let speeds: Vec<f64> = (0..21).map(|k| 0.73 + 0.1 * k as f64).collect();
        let pts: Vec<Selected> = speeds
            .iter()
            .map(|&v| {
                let run = v > 2.2;
                Selected {
                    group: format!("speed_{v}"),
                    axes: BTreeMap::from([("speed".to_string(), format!("{v}"))]),
                    case: String::new(),
                    guess: "quasi-random".into(),
                    objective: Some(1.0),
                    speed: v,
                    cost_of_transport: Some(if run {
                        1.0 + 1.5 * v
                    } else {
                        5.0 - 3.0 * v + v * v
                    }),
                    stride_frequency: Some(0.6 + 0.3 * v),
                    stride_length: None,
                    gait: Some(if run {
                        GaitType::Running
                    } else {
                        GaitType::Walking
                    }),
                }
            })
            .collect();
        let s = speed_series_of(BTreeMap::new(), pts);
        let t = s.transition_speed.unwrap();
        assert!((t - 2.23).abs() < 1e-9, "{t}");
        // The walking fit includes the transition speed whose COT lies on the running line,
        // so it is not exact; the running fit and the stride-frequency fit are exact.
        assert!((s.cot_running_fit.unwrap().r_squared - 1.0).abs() < 1e-12);
        let sf = s.stride_frequency_walking_fit.unwrap();
        assert!((sf.r_squared - 1.0).abs() < 1e-12);
        assert_eq!(sf.n, 15);
        assert_eq!(s.cot_walking_fit.unwrap().n, 16);
        assert!((literature_stride_frequency(1.33) - (34.2 + 16.2 * 1.33) / 60.0).abs() < 1e-15);
    }
}
