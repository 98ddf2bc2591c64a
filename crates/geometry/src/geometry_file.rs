//! The fitted-geometry file written by `stride model fit` and read by `stride predict`
//! (`--geometry`, study key `geometry`, or the per-user cache): polynomials keyed by muscle
//! (and ligament) and coordinate names, the fitting settings, the accuracy of every muscle
//! and ligament and the content hash of the model file it was fitted to.

use crate::error::GeometryError;
use crate::geometry_check::check_polynomials;
use crate::model_fit::{fit_ligaments, fit_model, FitModelOptions, FitReport};
use crate::samples::random_poses;
use serde::{Deserialize, Serialize};
use std::path::{Path, PathBuf};
use stride_model::input_file::read_text_limited;
use stride_model::{Model, PathPolynomial};

/// Format tag of the file (first key), so that other JSON files are rejected clearly.
pub const FORMAT: &str = "stride-muscle-geometry-1";

/// Largest geometry file read [bytes] (a fit of a hundred muscles is about 0.5 MB).
pub const MAX_GEOMETRY_BYTES: u64 = 64 << 20;

/// Largest polynomial coefficient accepted [m per rad^k or m per m^k]: fitted lengths are
/// below a metre, but a high-order term over a small coordinate range (a few centimetres of
/// a translation, a narrow wrap) takes coefficients of 10³–10⁴; this bound refuses only
/// values that overflow the derivatives (corrupt files), not such fits.
pub const MAX_COEFFICIENT: f64 = 1.0e9;

/// How the fitting poses were made.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct FitSettings {
    /// Number of poses.
    pub n_samples: usize,
    /// Seed of the random poses (`None` when the poses came from a motion file).
    pub seed: Option<u64>,
    /// Lowest and highest polynomial order tried.
    pub orders: [u32; 2],
    /// Accuracy target on the RMS length and moment-arm errors [m].
    pub tolerance: f64,
}

impl Default for FitSettings {
    /// The fit made on first use: 5000 random poses in the paper's ranges (seed 1),
    /// orders 3–9, 3 mm.
    fn default() -> Self {
        Self {
            n_samples: 5000,
            seed: Some(1),
            orders: [3, 9],
            tolerance: 3e-3,
        }
    }
}

/// Accuracy of one muscle's polynomial on the fitting poses.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct MuscleAccuracy {
    /// Muscle name.
    pub muscle: String,
    /// Retained order (0: spans no coordinate, no polynomial).
    pub order: u32,
    /// RMS length error [mm].
    pub rms_length_mm: f64,
    /// Largest RMS moment-arm error over the spanned coordinates [mm].
    pub max_rms_moment_arm_mm: f64,
    /// Both within the tolerance.
    pub meets_tolerance: bool,
}

/// The fitted muscle geometry of one model file.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct GeometryFile {
    /// Always [`FORMAT`].
    pub format: String,
    /// Model name.
    pub model: String,
    /// [`content_hash`] of the model file fitted (`None` when unknown).
    pub model_hash: Option<String>,
    /// Fitting settings.
    pub settings: FitSettings,
    /// Model coordinate names (polynomial coordinate indices refer to this list).
    pub coordinates: Vec<String>,
    /// Muscle names, same order as `path_polynomials`.
    pub muscles: Vec<String>,
    /// Polynomial of every muscle (`None` when it spans no coordinate).
    pub path_polynomials: Vec<Option<PathPolynomial>>,
    /// Accuracy of every muscle.
    pub accuracy: Vec<MuscleAccuracy>,
    /// Ligament names, same order as `ligament_polynomials` (empty for a model without
    /// ligaments).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub ligaments: Vec<String>,
    /// Length polynomial of every ligament (`None` when it spans no coordinate).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub ligament_polynomials: Vec<Option<PathPolynomial>>,
    /// Accuracy of every ligament (the `muscle` field holds the ligament's name).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub ligament_accuracy: Vec<MuscleAccuracy>,
}

/// The accuracy rows of a fit report.
fn accuracy(report: &FitReport) -> Vec<MuscleAccuracy> {
    report
        .rows
        .iter()
        .map(|r| MuscleAccuracy {
            muscle: r.muscle.clone(),
            order: r.order,
            rms_length_mm: r.rms_length_mm,
            max_rms_moment_arm_mm: r.max_rms_moment_arm_mm,
            meets_tolerance: r.meets_tolerance,
        })
        .collect()
}

impl GeometryFile {
    /// The file for `report`, fitted to `model` (file hash `model_hash`).
    pub fn new(
        model: &Model,
        model_hash: Option<String>,
        settings: FitSettings,
        report: &FitReport,
    ) -> Self {
        Self {
            format: FORMAT.to_string(),
            model: model.name.clone(),
            model_hash,
            settings,
            coordinates: model.coordinates.iter().map(|c| c.name.clone()).collect(),
            muscles: model.muscles.iter().map(|m| m.name.clone()).collect(),
            path_polynomials: report.polynomials.clone(),
            accuracy: accuracy(report),
            ligaments: Vec::new(),
            ligament_polynomials: Vec::new(),
            ligament_accuracy: Vec::new(),
        }
    }

    /// The file with the ligament fit `report` of `model` added.
    pub fn with_ligaments(mut self, model: &Model, report: &FitReport) -> Self {
        self.ligaments = model.ligaments.iter().map(|l| l.name.clone()).collect();
        self.ligament_polynomials = report.polynomials.clone();
        self.ligament_accuracy = accuracy(report);
        self
    }

    /// Reads a geometry file (at most [`MAX_GEOMETRY_BYTES`]); a file that is not one
    /// (e.g. an `.osim`) is an error that says so.
    pub fn read(path: &Path) -> Result<Self, GeometryError> {
        let text =
            read_text_limited(path, MAX_GEOMETRY_BYTES).map_err(|e| GeometryError::File {
                path: path.display().to_string(),
                what: format!("cannot read: {e}"),
            })?;
        Self::parse(&text, &path.display().to_string())
    }

    /// Parses the text of a geometry file; `source` names it in errors.
    pub fn parse(text: &str, source: &str) -> Result<Self, GeometryError> {
        let err = |what: String| GeometryError::File {
            path: source.to_string(),
            what,
        };
        let value: serde_json::Value = serde_json::from_str(text).map_err(|e| {
            err(format!(
                "not a stride muscle-geometry file (written by `stride model fit --out`): {e}"
            ))
        })?;
        if value.get("format").and_then(|f| f.as_str()) != Some(FORMAT) {
            return Err(err(format!(
                "not a stride muscle-geometry file: `format` is not \"{FORMAT}\""
            )));
        }
        let file: Self = serde_json::from_value(value).map_err(|e| err(e.to_string()))?;
        file.check_shape().map_err(err)?;
        Ok(file)
    }

    /// The file is consistent in itself: one polynomial per muscle and ligament, exponent
    /// tuples as long as the coordinate lists, coordinate indices in range, coefficients
    /// finite and at most [`MAX_COEFFICIENT`].
    fn check_shape(&self) -> Result<(), String> {
        let lists = [
            ("muscles", &self.muscles, &self.path_polynomials),
            ("ligaments", &self.ligaments, &self.ligament_polynomials),
        ];
        for (kind, names, polys) in lists {
            if names.len() != polys.len() {
                return Err(format!(
                    "{} {kind} but {} polynomials",
                    names.len(),
                    polys.len()
                ));
            }
            for (name, p) in names.iter().zip(polys) {
                if let Some(p) = p {
                    self.check_polynomial(p)
                        .map_err(|e| format!("{kind} {name}: {e}"))?;
                }
            }
        }
        Ok(())
    }

    fn check_polynomial(&self, p: &PathPolynomial) -> Result<(), String> {
        if let Some(c) = p.coordinates.iter().find(|&&c| c >= self.coordinates.len()) {
            return Err(format!("coordinate index {c} out of range"));
        }
        if p.exponents.len() != p.coefficients.len() {
            return Err(format!(
                "{} exponent tuples but {} coefficients",
                p.exponents.len(),
                p.coefficients.len()
            ));
        }
        if p.exponents.iter().any(|e| e.len() != p.coordinates.len()) {
            return Err(format!(
                "an exponent tuple is not {} long (one per coordinate)",
                p.coordinates.len()
            ));
        }
        if let Some(c) =
            (p.coefficients.iter()).find(|c| !c.is_finite() || c.abs() > MAX_COEFFICIENT)
        {
            return Err(format!(
                "coefficient {c:?} is not finite or larger than {MAX_COEFFICIENT} in magnitude"
            ));
        }
        Ok(())
    }

    /// Refuses the file when it records the content hash of a model file other than
    /// `model_bytes` (the model file `model_path` it is used with).
    pub fn check_model_hash(
        &self,
        model_bytes: &[u8],
        source: &str,
        model_path: &str,
    ) -> Result<(), GeometryError> {
        let hash = content_hash(model_bytes);
        match &self.model_hash {
            Some(h) if *h != hash => Err(GeometryError::File {
                path: source.to_string(),
                what: format!(
                    "fitted to a model file with content hash {h}, but {model_path} has hash {hash} (fit it again with `stride model fit {model_path} --out …`)"
                ),
            }),
            _ => Ok(()),
        }
    }

    /// Writes the file atomically (nothing is left behind on failure).
    pub fn write(&self, path: &Path) -> Result<(), GeometryError> {
        let text = serde_json::to_string_pretty(self).map_err(|e| GeometryError::File {
            path: path.display().to_string(),
            what: e.to_string(),
        })?;
        stride_files::write_atomic(path, text.as_bytes()).map_err(|e| GeometryError::File {
            path: path.display().to_string(),
            what: e.to_string(),
        })
    }

    /// Sets `model.path_polynomials` (and each ligament's `path_polynomial`) from this
    /// file, matching muscles, ligaments and coordinates by name; every muscle of the
    /// model must be in the file; a ligament missing from it keeps no polynomial.
    pub fn apply(&self, model: &mut Model) -> Result<(), GeometryError> {
        self.check_muscle_names(model)?;
        let mut polys = Vec::with_capacity(model.muscles.len());
        for m in &model.muscles {
            let k = self
                .muscles
                .iter()
                .position(|n| *n == m.name)
                .ok_or_else(|| GeometryError::Model {
                    what: format!(
                        "{}: muscle {} has no polynomial in the geometry file (fitted to model {})",
                        model.name, m.name, self.model
                    ),
                })?;
            let p = self.path_polynomials.get(k).cloned().flatten();
            polys.push(self.renumber(model, "muscle", &m.name, p)?);
        }
        let mut ligament_polys = Vec::with_capacity(model.ligaments.len());
        for l in &model.ligaments {
            let p = self
                .ligaments
                .iter()
                .position(|n| *n == l.name)
                .and_then(|k| self.ligament_polynomials.get(k).cloned().flatten());
            ligament_polys.push(self.renumber(model, "ligament", &l.name, p)?);
        }
        model.path_polynomials = polys;
        for (l, p) in model.ligaments.iter_mut().zip(ligament_polys) {
            l.path_polynomial = p;
        }
        // a fit to the poses of a motion file holds only near them, not necessarily at the
        // default pose: its lengths are not compared there
        let at_default_pose = self.settings.seed.is_some();
        check_polynomials(
            model,
            &format!("geometry file of model {}", self.model),
            at_default_pose,
        )
    }

    /// The file's muscles are the model's: no name twice, none the model lacks.
    fn check_muscle_names(&self, model: &Model) -> Result<(), GeometryError> {
        let err = |what: String| GeometryError::Model {
            what: format!(
                "{}: the geometry file (fitted to model {}) {what}",
                model.name, self.model
            ),
        };
        for (i, n) in self.muscles.iter().enumerate() {
            if self.muscles[..i].contains(n) {
                return Err(err(format!("lists muscle {n} twice")));
            }
        }
        let foreign: Vec<&str> = (self.muscles.iter())
            .filter(|n| model.muscle_index(n).is_none())
            .map(String::as_str)
            .collect();
        if !foreign.is_empty() {
            return Err(err(format!(
                "has muscles the model lacks: {}",
                foreign.join(", ")
            )));
        }
        Ok(())
    }

    /// Polynomial `p` of the element `kind name` with its coordinate indices turned from
    /// this file's into `model`'s.
    fn renumber(
        &self,
        model: &Model,
        kind: &str,
        name: &str,
        p: Option<PathPolynomial>,
    ) -> Result<Option<PathPolynomial>, GeometryError> {
        let Some(mut p) = p else {
            return Ok(None);
        };
        for c in p.coordinates.iter_mut() {
            let coordinate = self
                .coordinates
                .get(*c)
                .ok_or_else(|| GeometryError::Model {
                    what: format!(
                        "geometry file: {kind} {name}: coordinate index {c} out of range"
                    ),
                })?;
            *c = model
                .coordinate_index(coordinate)
                .ok_or_else(|| GeometryError::Model {
                    what: format!(
                        "{}: coordinate {coordinate} of {kind} {name}'s polynomial is not in the model",
                        model.name
                    ),
                })?;
        }
        Ok(Some(p))
    }
}

/// Content hash of a model file: 128 bits (two FNV-1a 64-bit hashes with different
/// offsets), hexadecimal — a cache key, not a cryptographic digest.
pub fn content_hash(bytes: &[u8]) -> String {
    let fnv = |basis: u64| {
        bytes.iter().fold(basis, |h, b| {
            (h ^ u64::from(*b)).wrapping_mul(0x0000_0100_0000_01b3)
        })
    };
    format!(
        "{:016x}{:016x}",
        fnv(0xcbf2_9ce4_8422_2325),
        fnv(0x6c62_272e_07bb_0142)
    )
}

/// True when a polynomial of `file` spans a coupled coordinate of `model` (a fit made
/// before coupled coordinates followed their constraint), so that it is fitted again.
fn spans_coupled(file: &GeometryFile, model: &Model) -> bool {
    let coupled: Vec<&str> = model
        .couplers
        .iter()
        .map(|k| model.coordinates[k.dependent].name.as_str())
        .collect();
    file.path_polynomials
        .iter()
        .chain(&file.ligament_polynomials)
        .flatten()
        .flat_map(|p| &p.coordinates)
        .any(|&c| {
            file.coordinates
                .get(c)
                .is_some_and(|n| coupled.contains(&n.as_str()))
        })
}

/// Where a model's geometry came from.
#[derive(Clone, Debug, PartialEq)]
pub enum GeometrySource {
    /// Read from the cache file.
    Cached(PathBuf),
    /// Fitted now and written to the cache file.
    Fitted(PathBuf),
}

/// The fitted geometry of the model file whose content is `model_bytes` (already parsed
/// into `model`): read from `cache_dir` when a fit of the same content and settings is
/// there, else fitted with `settings` and stored there.
pub fn cached_geometry(
    model: &Model,
    model_bytes: &[u8],
    cache_dir: &Path,
    settings: &FitSettings,
) -> Result<(GeometryFile, GeometrySource), GeometryError> {
    let hash = content_hash(model_bytes);
    let path = cache_dir.join(format!("geometry-{hash}.json"));
    if let Ok(file) = GeometryFile::read(&path) {
        if file.model_hash.as_deref() == Some(hash.as_str())
            && file.settings == *settings
            && !spans_coupled(&file, model)
        {
            return Ok((file, GeometrySource::Cached(path)));
        }
    }
    let poses = random_poses(model, settings.n_samples, settings.seed.unwrap_or(1));
    let mut options = FitModelOptions::default();
    options.fit.min_order = settings.orders[0];
    options.fit.max_order = settings.orders[1];
    options.fit.tolerance = settings.tolerance;
    let report = fit_model(model, &poses, &options)?;
    let mut file = GeometryFile::new(model, Some(hash), settings.clone(), &report);
    if !model.ligaments.is_empty() {
        file = file.with_ligaments(model, &fit_ligaments(model, &poses, &options)?);
    }
    std::fs::create_dir_all(cache_dir).map_err(|e| GeometryError::File {
        path: cache_dir.display().to_string(),
        what: format!("cannot create the cache folder: {e}"),
    })?;
    file.write(&path)?;
    Ok((file, GeometrySource::Fitted(path)))
}
