//! Poses at which the path geometry is sampled for fitting (FORMULATION 4.4 step 1):
//! read from an OpenSim motion file, or drawn at random (seeded, reproducible).

use crate::couplers::Couplers;
use crate::error::GeometryError;
use std::path::Path;
use stride_model::storage::{coordinate_of_label, Storage};
use stride_model::{Model, MotionType};

/// A set of poses: full model coordinate vectors, row-major `n_samples × n_coords`
/// [rad or m].
#[derive(Clone, Debug, PartialEq)]
pub struct PoseSamples {
    /// Number of model coordinates per pose.
    pub n_coords: usize,
    /// Coordinate values, row-major.
    pub q: Vec<f64>,
}

impl PoseSamples {
    /// Number of poses.
    pub fn len(&self) -> usize {
        self.q.len().checked_div(self.n_coords).unwrap_or(0)
    }

    /// True when there is no pose.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// Coordinates of pose `i`.
    pub fn pose(&self, i: usize) -> &[f64] {
        &self.q[i * self.n_coords..(i + 1) * self.n_coords]
    }

    /// Every `step`-th pose (at most `max` of them), for quick checks.
    pub fn subsample(&self, step: usize, max: usize) -> Self {
        let step = step.max(1);
        let mut q = Vec::new();
        for i in (0..self.len()).step_by(step).take(max) {
            q.extend_from_slice(self.pose(i));
        }
        Self {
            n_coords: self.n_coords,
            q,
        }
    }
}

/// Sampling range [deg] of the paper (FORMULATION 4.4 step 1) for a coordinate's base name
/// (side suffix `_r`/`_l` removed).
pub fn paper_range_deg(base: &str) -> Option<[f64; 2]> {
    Some(match base {
        "hip_flexion" => [-70.0, 90.0],
        "hip_adduction" => [-30.0, 30.0],
        "hip_rotation" => [-30.0, 30.0],
        "knee_angle" => [-120.0, 10.0],
        "ankle_angle" => [-50.0, 40.0],
        "subtalar_angle" => [-45.0, 45.0],
        "lumbar_extension" => [-90.0, 90.0],
        "lumbar_bending" => [-45.0, 45.0],
        "lumbar_rotation" => [-45.0, 45.0],
        _ => return None,
    })
}

/// Coordinate name without its side suffix (`hip_flexion_r` → `hip_flexion`).
pub fn base_name(name: &str) -> &str {
    name.strip_suffix("_r")
        .or_else(|| name.strip_suffix("_l"))
        .unwrap_or(name)
}

/// Small deterministic pseudo-random generator (SplitMix64), so that sample sets are
/// reproducible from a seed independently of external crates.
#[derive(Clone, Debug)]
pub struct SplitMix64(u64);

impl SplitMix64 {
    /// Generator started from `seed`.
    pub fn new(seed: u64) -> Self {
        Self(seed)
    }
    /// Next 64 random bits.
    pub fn next_u64(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }
    /// Uniform number in [0, 1).
    pub fn uniform(&mut self) -> f64 {
        (self.next_u64() >> 11) as f64 / (1u64 << 53) as f64
    }
}

/// `n` random poses: coordinates with a paper range (4.4 step 1) drawn uniformly in it;
/// other free coordinates of joints not attached to the ground drawn in their model
/// range; coordinates of joints attached to the ground (pelvis) at 0; locked coordinates
/// at their default. A left coordinate takes the value drawn for its right twin, as in
/// the paper. A coupled coordinate is not drawn: it takes its constraint's value (NaN
/// when the model's couplers cannot be prepared, an error [`crate::PathGeometry::new`]
/// names).
pub fn random_poses(model: &Model, n: usize, seed: u64) -> PoseSamples {
    let couplers = Couplers::new(model).ok();
    let nc = model.coordinates.len();
    let mut rng = SplitMix64::new(seed);
    let mut q = vec![0.0; n * nc];
    // Twin of each left coordinate (index of the `_r` coordinate with the same base).
    let twin: Vec<Option<usize>> = model
        .coordinates
        .iter()
        .map(|c| {
            c.name
                .strip_suffix("_l")
                .and_then(|b| model.coordinate_index(&format!("{b}_r")))
        })
        .collect();
    for s in 0..n {
        let row = &mut q[s * nc..(s + 1) * nc];
        for (i, c) in model.coordinates.iter().enumerate() {
            if twin[i].is_some() || model.couplers.iter().any(|k| k.dependent == i) {
                continue;
            }
            let grounded = model
                .joints
                .get(c.joint)
                .map(|j| j.parent == 0)
                .unwrap_or(false);
            row[i] = if c.locked {
                c.default_value
            } else if grounded {
                0.0
            } else if let Some([lo, hi]) = paper_range_deg(base_name(&c.name)) {
                (lo + (hi - lo) * rng.uniform()).to_radians()
            } else {
                c.range[0] + (c.range[1] - c.range[0]) * rng.uniform()
            };
        }
        for (i, t) in twin.iter().enumerate() {
            if let Some(r) = t {
                row[i] = if model.coordinates[i].locked {
                    model.coordinates[i].default_value
                } else {
                    row[*r]
                };
            }
        }
        match &couplers {
            Some(c) => c.apply(row),
            None => model
                .couplers
                .iter()
                .for_each(|k| row[k.dependent] = f64::NAN),
        }
    }
    PoseSamples { n_coords: nc, q }
}

/// What [`poses_from_motion`] does with an unlocked, uncoupled coordinate the motion has
/// no column for.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum MissingCoordinates {
    /// An error naming the coordinate (a motion to evaluate must give every coordinate).
    Error,
    /// The coordinate takes its default value (fitting samples such as the paper's, which
    /// leave out the coordinates the fit does not vary).
    Default,
}

/// Reads poses from an OpenSim `.mot`/`.sto` file, mapping columns to coordinates by
/// name or by OpenSim 4 state path (`/jointset/<joint>/<coordinate>/value`; other state
/// columns are ignored). Rotational coordinates are converted from degrees when the
/// header says `inDegrees=yes`, or says nothing and the columns are named after the
/// coordinates (OpenSim writes states in radians). Locked coordinates take their default
/// and coupled coordinates their constraint's value, as OpenSim's assembly does; an
/// unlocked independent coordinate without a column is handled as `missing` says; a value
/// that is not finite is an error naming its row and column.
pub fn poses_from_motion(
    model: &Model,
    path: &Path,
    missing: MissingCoordinates,
) -> Result<PoseSamples, GeometryError> {
    let err = |what: String| GeometryError::Motion {
        path: path.display().to_string(),
        what,
    };
    let storage = Storage::read(path).map_err(|e| err(strip_path(&e.to_string(), path)))?;
    let couplers = Couplers::new(model)?;
    let map: Vec<Option<usize>> = storage
        .labels
        .iter()
        .map(|l| coordinate_of_label(l).and_then(|c| model.coordinate_index(c)))
        .collect();
    for (i, c) in model.coordinates.iter().enumerate() {
        let given = map.contains(&Some(i));
        let free = !c.locked && couplers.independent_of(i).is_none();
        if !given && free && missing == MissingCoordinates::Error {
            return Err(err(format!(
                "no column for coordinate `{}` (only locked and coupled coordinates may be \
                 left out)",
                c.name
            )));
        }
    }
    let in_degrees = storage.angles_in_degrees();
    let time = storage.column_index("time");
    let defaults: Vec<f64> = model.coordinates.iter().map(|c| c.default_value).collect();
    let mut q = Vec::with_capacity(storage.n_rows() * defaults.len());
    for (r, values) in storage.rows.iter().enumerate() {
        let mut row = defaults.clone();
        for (k, v) in values.iter().enumerate() {
            let Some(i) = map[k] else { continue };
            if model.coordinates[i].locked || couplers.independent_of(i).is_some() {
                continue;
            }
            if !v.is_finite() {
                let at = time.map_or(String::new(), |t| format!(" (time {})", values[t]));
                return Err(err(format!(
                    "data row {}{at}, column `{}`: {v} is not a coordinate value",
                    r + 1,
                    storage.labels[k]
                )));
            }
            let rot = model.coordinates[i].motion_type == MotionType::Rotational;
            row[i] = if rot && in_degrees {
                v.to_radians()
            } else {
                *v
            };
        }
        couplers.apply(&mut row);
        q.extend_from_slice(&row);
    }
    Ok(PoseSamples {
        n_coords: defaults.len(),
        q,
    })
}

/// A storage error's message without its leading `<path>:` (the motion error names the
/// file already).
fn strip_path(message: &str, path: &Path) -> String {
    let p = path.display().to_string();
    message
        .strip_prefix(&p)
        .map_or(message, |m| m.trim_start_matches(':').trim_start())
        .to_string()
}
