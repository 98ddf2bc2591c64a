//! Fitting the polynomial geometry of every muscle (and every ligament) of a model from
//! its path points (FORMULATION 4.3–4.4) and the accuracy report.

use crate::error::GeometryError;
use crate::fit::{fit_polynomial, FitOptions, MuscleSamples, PolynomialFit};
use crate::path::PathGeometry;
use crate::samples::PoseSamples;
use std::fmt::Write as _;
use stride_model::{CoordId, Model, PathPolynomial};

/// Threshold on `|Σ_samples r|` above which a muscle spans a coordinate [m] (4.3).
pub const DEFAULT_SPAN_THRESHOLD: f64 = 1e-4;

/// Accuracy target of the ligament length fits [m] (0.1 mm): a ligament's force grows
/// exponentially with its strain, and 1 mm on a 15 cm plantar fascia is 0.7 % strain, so
/// ligaments are fitted more tightly than the muscles' 3 mm.
pub const LIGAMENT_TOLERANCE: f64 = 1e-4;

/// Settings of [`fit_model`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FitModelOptions {
    /// Order selection settings.
    pub fit: FitOptions,
    /// Spanning threshold on the summed moment arm [m].
    pub span_threshold: f64,
}

impl Default for FitModelOptions {
    /// The paper's settings (orders 3–9, 3 mm, 1e-4 m spanning threshold).
    fn default() -> Self {
        Self {
            fit: FitOptions::default(),
            span_threshold: DEFAULT_SPAN_THRESHOLD,
        }
    }
}

/// One line of the accuracy table.
#[derive(Clone, Debug, PartialEq)]
pub struct MuscleFitRow {
    /// Muscle name.
    pub muscle: String,
    /// Names of the spanned coordinates, in polynomial order.
    pub spanned: Vec<String>,
    /// Retained polynomial order (0 when the muscle spans no coordinate).
    pub order: u32,
    /// RMS length error over the samples [mm].
    pub rms_length_mm: f64,
    /// Largest RMS moment-arm error over the spanned coordinates [mm].
    pub max_rms_moment_arm_mm: f64,
    /// Both errors within the tolerance.
    pub meets_tolerance: bool,
}

/// Result of fitting a whole model.
#[derive(Clone, Debug)]
pub struct FitReport {
    /// What was fitted: `"muscle"` or `"ligament"` (the table's and warnings' wording).
    pub kind: &'static str,
    /// Accuracy of every muscle (or ligament), in model order; the `muscle` field of a
    /// row holds the element's name.
    pub rows: Vec<MuscleFitRow>,
    /// Fitted polynomial of every muscle (None when it spans no coordinate).
    pub polynomials: Vec<Option<PathPolynomial>>,
    /// Accuracy target used [m].
    pub tolerance: f64,
    /// Number of poses fitted.
    pub n_samples: usize,
}

impl FitReport {
    /// Muscles whose fit misses the tolerance at the maximal order.
    pub fn failures(&self) -> Vec<&MuscleFitRow> {
        self.rows.iter().filter(|r| !r.meets_tolerance).collect()
    }

    /// Human-readable accuracy table (one muscle per line).
    pub fn table(&self) -> String {
        let mut s = String::new();
        let w = self
            .rows
            .iter()
            .map(|r| r.muscle.len())
            .fold(14, usize::max);
        let _ = writeln!(
            s,
            "{:<w$} {:<70} {:>5} {:>12} {:>14} {:>6}",
            self.kind, "spanned coordinates", "order", "rms l [mm]", "max rms r [mm]", "ok"
        );
        for r in &self.rows {
            let _ = writeln!(
                s,
                "{:<w$} {:<70} {:>5} {:>12.3} {:>14.3} {:>6}",
                r.muscle,
                r.spanned.join(","),
                r.order,
                r.rms_length_mm,
                r.max_rms_moment_arm_mm,
                if r.meets_tolerance { "yes" } else { "NO" }
            );
        }
        s
    }

    /// One warning line per muscle that misses the tolerance.
    pub fn warnings(&self) -> Vec<String> {
        self.failures()
            .iter()
            .map(|r| {
                if r.spanned.is_empty() {
                    format!("warning: {} {} spans no coordinate; no polynomial fitted", self.kind, r.muscle)
                } else {
                    format!(
                        "warning: {} {} misses the {:.1} mm target at order {}: RMS length error {:.2} mm, largest RMS moment-arm error {:.2} mm",
                        self.kind,
                        r.muscle,
                        self.tolerance * 1e3,
                        r.order,
                        r.rms_length_mm,
                        r.max_rms_moment_arm_mm
                    )
                }
            })
            .collect()
    }
}

/// Path-point lengths and moment arms of every muscle at every pose.
#[derive(Clone, Debug)]
pub struct SampledGeometry {
    /// Coordinates whose moment arms were evaluated (all unlocked coordinates but the
    /// coupled ones, whose effect enters through their independent coordinate's).
    pub candidates: Vec<CoordId>,
    /// Spanned coordinates of each muscle (subset of `candidates`, model order).
    pub spanned: Vec<Vec<CoordId>>,
    /// Samples of each muscle over its spanned coordinates.
    pub muscles: Vec<MuscleSamples>,
}

/// Evaluates the muscle path geometry at every pose, detects the spanned coordinates
/// (`|Σ r| > span_threshold`, FORMULATION 4.3) and gathers per-muscle samples.
pub fn sample_geometry(
    model: &Model,
    poses: &PoseSamples,
    span_threshold: f64,
) -> Result<SampledGeometry, GeometryError> {
    check_poses(model, poses)?;
    sample_paths(model, &mut PathGeometry::new(model)?, poses, span_threshold)
}

/// An error unless `poses` have one value per coordinate of `model`.
fn check_poses(model: &Model, poses: &PoseSamples) -> Result<(), GeometryError> {
    if poses.n_coords != model.coordinates.len() {
        return Err(GeometryError::SampleShape {
            what: format!(
                "poses have {} coordinates, model {} has {}",
                poses.n_coords,
                model.name,
                model.coordinates.len()
            ),
        });
    }
    Ok(())
}

/// [`sample_geometry`] for the paths of `geo` (muscles or ligaments of `model`).
fn sample_paths(
    model: &Model,
    geo: &mut PathGeometry,
    poses: &PoseSamples,
    span_threshold: f64,
) -> Result<SampledGeometry, GeometryError> {
    let nm = geo.paths.len();
    let candidates: Vec<CoordId> = (0..model.coordinates.len())
        .filter(|&i| !model.coordinates[i].locked && geo.couplers.independent_of(i).is_none())
        .collect();
    let nc = candidates.len();
    let ns = poses.len();
    let mut lengths = vec![0.0; ns * nm];
    // Moment arms of every muscle about every candidate, muscle-major: [m][c][s] (f32 to
    // halve memory would lose accuracy near 1e-7 m; f64 kept).
    let mut arms = vec![0.0; nm * nc * ns];
    let mut buf = vec![0.0; nm];
    for s in 0..ns {
        let q = poses.pose(s);
        geo.lengths(q, &mut lengths[s * nm..(s + 1) * nm]);
        for (k, &c) in candidates.iter().enumerate() {
            geo.moment_arms(q, c, &mut buf);
            for (m, v) in buf.iter().enumerate() {
                arms[(m * nc + k) * ns + s] = *v;
            }
        }
    }
    let mut spanned = Vec::with_capacity(nm);
    let mut muscles = Vec::with_capacity(nm);
    for m in 0..nm {
        let ks: Vec<usize> = (0..nc)
            .filter(|&k| {
                let sum: f64 = arms[(m * nc + k) * ns..(m * nc + k + 1) * ns].iter().sum();
                sum.abs() > span_threshold
            })
            .collect();
        let coords: Vec<CoordId> = ks.iter().map(|&k| candidates[k]).collect();
        let n = coords.len();
        let mut ms = MuscleSamples {
            coords: coords.clone(),
            x: vec![0.0; ns * n],
            length: (0..ns).map(|s| lengths[s * nm + m]).collect(),
            moment_arms: vec![0.0; ns * n],
        };
        for s in 0..ns {
            let q = poses.pose(s);
            for (j, (&c, &k)) in coords.iter().zip(&ks).enumerate() {
                ms.x[s * n + j] = q[c];
                ms.moment_arms[s * n + j] = arms[(m * nc + k) * ns + s];
            }
        }
        spanned.push(coords);
        muscles.push(ms);
    }
    Ok(SampledGeometry {
        candidates,
        spanned,
        muscles,
    })
}

/// Fits the polynomial geometry of every muscle of `model` to its own path-point
/// geometry at `poses` (left muscles on left coordinates) and reports the accuracy.
pub fn fit_model(
    model: &Model,
    poses: &PoseSamples,
    options: &FitModelOptions,
) -> Result<FitReport, GeometryError> {
    let sampled = sample_geometry(model, poses, options.span_threshold)?;
    let names: Vec<&str> = model.muscles.iter().map(|m| m.name.as_str()).collect();
    let mut report = fit_sampled(model, "muscle", &names, &sampled, &options.fit)?;
    use_own_polynomials(model, &mut report);
    Ok(report)
}

/// Muscles whose length the model itself gives as a polynomial (OpenSim
/// `FunctionBasedPath`) keep that polynomial: it is their geometry, exact by definition.
fn use_own_polynomials(model: &Model, report: &mut FitReport) {
    for (m, muscle) in model.muscles.iter().enumerate() {
        let Some(p) = &muscle.path_function else {
            continue;
        };
        let row = &mut report.rows[m];
        row.spanned = p
            .coordinates
            .iter()
            .map(|&c| model.coordinates[c].name.clone())
            .collect();
        row.order = p.order;
        row.rms_length_mm = 0.0;
        row.max_rms_moment_arm_mm = 0.0;
        row.meets_tolerance = true;
        report.polynomials[m] = Some(p.clone());
    }
}

/// Fits the length polynomial of every ligament of `model` over the coordinates it spans
/// to its path-point geometry at `poses`, to [`LIGAMENT_TOLERANCE`] (orders and spanning
/// threshold of `options`), and reports the accuracy.
pub fn fit_ligaments(
    model: &Model,
    poses: &PoseSamples,
    options: &FitModelOptions,
) -> Result<FitReport, GeometryError> {
    check_poses(model, poses)?;
    let mut geo = PathGeometry::ligaments(model)?;
    let sampled = sample_paths(model, &mut geo, poses, options.span_threshold)?;
    let names: Vec<&str> = model.ligaments.iter().map(|l| l.name.as_str()).collect();
    let fit = FitOptions {
        tolerance: LIGAMENT_TOLERANCE,
        ..options.fit
    };
    fit_sampled(model, "ligament", &names, &sampled, &fit)
}

/// Fits one polynomial per sampled path (`names`: the elements' names, `kind` their kind).
fn fit_sampled(
    model: &Model,
    kind: &'static str,
    names: &[&str],
    sampled: &SampledGeometry,
    options: &FitOptions,
) -> Result<FitReport, GeometryError> {
    let mut rows = Vec::with_capacity(names.len());
    let mut polynomials = Vec::with_capacity(names.len());
    for (m, ms) in sampled.muscles.iter().enumerate() {
        let spanned: Vec<String> = ms
            .coords
            .iter()
            .map(|&c| model.coordinates[c].name.clone())
            .collect();
        if ms.coords.is_empty() {
            rows.push(MuscleFitRow {
                muscle: names[m].to_string(),
                spanned,
                order: 0,
                rms_length_mm: f64::NAN,
                max_rms_moment_arm_mm: f64::NAN,
                meets_tolerance: false,
            });
            polynomials.push(None);
            continue;
        }
        let fit: PolynomialFit = fit_polynomial(ms, options).map_err(|e| GeometryError::Model {
            what: format!("{kind} {}: {e}", names[m]),
        })?;
        rows.push(MuscleFitRow {
            muscle: names[m].to_string(),
            spanned,
            order: fit.polynomial.order,
            rms_length_mm: fit.rms_length * 1e3,
            max_rms_moment_arm_mm: fit.max_rms_moment_arm() * 1e3,
            meets_tolerance: fit.meets_tolerance,
        });
        polynomials.push(Some(fit.polynomial));
    }
    Ok(FitReport {
        kind,
        rows,
        polynomials,
        tolerance: options.tolerance,
        n_samples: sampled.muscles.first().map_or(0, |m| m.n_samples()),
    })
}
