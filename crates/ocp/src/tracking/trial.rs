//! The measured trial a tracking problem follows: joint angles (inverse kinematics), ground
//! reaction forces of both feet and optionally net joint torques (inverse dynamics), read,
//! checked against the model and the time window, filtered and sampled at any time.

use super::ground_reactions::GroundReactions;
use super::series::interp;
use crate::experimental::Kinematics;
use crate::gait::GaitModel;
use std::path::{Path, PathBuf};
use stride_model::external_loads::{ExternalLoads, ExternalLoadsError};
use stride_model::storage::Storage;

const GAIT_1_IK: &str = include_str!("../../data/gait_1_ik.mot");
const GAIT_1_ID: &str = include_str!("../../data/gait_1_id.sto");
const GAIT_1_GRF: &str = include_str!("../../data/gait_1_grf.mot");

/// Why a trial cannot be tracked; every message names the file and the column or time.
#[derive(Debug, thiserror::Error)]
pub enum TrialError {
    /// A file could not be read.
    #[error("{0}")]
    Read(String),
    /// A tracked coordinate that the model does not have.
    #[error("{file}: tracked column `{column}` names no coordinate of the model")]
    UnknownCoordinate {
        /// File.
        file: String,
        /// Column.
        column: String,
    },
    /// A column the tracking needs is missing.
    #[error("{file}: no column `{column}`")]
    MissingColumn {
        /// File.
        file: String,
        /// Column.
        column: String,
    },
    /// The window is empty or reversed.
    #[error("window [{t0}, {t1}] s: its end must come after its start (the window is empty or reversed)")]
    EmptyWindow {
        /// Window start [s].
        t0: f64,
        /// Window end [s].
        t1: f64,
    },
    /// An ExternalLoads file, its data file, or how its forces map onto the feet.
    #[error(transparent)]
    ExternalLoads(#[from] ExternalLoadsError),
    /// Two columns of the motion give the same coordinate.
    #[error("{file}: column `{column}` gives coordinate `{coordinate}`, which another column already gives")]
    DuplicateColumn {
        /// File.
        file: String,
        /// The second column.
        column: String,
        /// The coordinate.
        coordinate: String,
    },
    /// A coupled coordinate could not be computed from its constraint.
    #[error("{file}: coordinate `{coordinate}` from constraint `{constraint}`: {reason}")]
    Coupled {
        /// File.
        file: String,
        /// The dependent coordinate.
        coordinate: String,
        /// The constraint.
        constraint: String,
        /// Why.
        reason: String,
    },
    /// The window lies (partly) outside the data.
    #[error("{file}: window [{t0}, {t1}] s is not inside the data ({d0} to {d1} s)")]
    Window {
        /// File.
        file: String,
        /// Window start [s].
        t0: f64,
        /// Window end [s].
        t1: f64,
        /// First time of the data [s].
        d0: f64,
        /// Last time of the data [s].
        d1: f64,
    },
    /// A measured value the tracking uses is NaN or infinite.
    #[error("{file}: column `{column}` is not finite ({value}) at t = {time} s")]
    NotFinite {
        /// File.
        file: String,
        /// Column.
        column: String,
        /// Time of the row [s].
        time: f64,
        /// The value.
        value: f64,
    },
    /// Kinematics unusable.
    #[error(transparent)]
    Kinematics(#[from] crate::experimental::KinematicsError),
}

/// The files of a trial and their names for messages.
#[derive(Clone, Debug)]
pub struct TrialFiles {
    /// Joint angles (`.mot`, degrees or radians as its header says).
    pub motion: (String, Storage),
    /// Ground reaction forces, centres of pressure and free torques (`.mot`; the data
    /// file of `loads` when the forces come from an ExternalLoads file).
    pub grf: (String, Storage),
    /// The ExternalLoads file that names the bodies and columns of the forces, if given.
    pub loads: Option<ExternalLoads>,
    /// Net joint torques (`.sto`, `<coordinate>_moment` / `_force` columns), if tracked.
    pub torques: Option<(String, Storage)>,
}

/// Reads a storage file, naming it in the error.
fn read(path: &Path) -> Result<(String, Storage), TrialError> {
    let name = path.display().to_string();
    let s = Storage::read(path).map_err(|e| {
        let message = e.to_string();
        // storage errors of a file already start with its name
        TrialError::Read(if message.starts_with(&name) {
            message
        } else {
            format!("{name}: {message}")
        })
    })?;
    Ok((name, s))
}

impl TrialFiles {
    /// The paper's TrackSim trial gait_1 of subject1 (shipped with stride; MIT licence,
    /// via 3dpredictsim; 3.30–4.40 s, GRF at 200 Hz).
    pub fn gait_1() -> Self {
        let parse = |text: &str, name: &str| {
            let s = Storage::parse(text, Path::new(name)).expect("shipped file parses");
            (name.to_string(), s)
        };
        Self {
            motion: parse(GAIT_1_IK, "gait_1_ik.mot"),
            grf: parse(GAIT_1_GRF, "gait_1_grf.mot"),
            loads: None,
            torques: Some(parse(GAIT_1_ID, "gait_1_id.sto")),
        }
    }

    /// Reads the files of a trial; `grf` is a storage file (`.mot`/`.sto`) or an
    /// ExternalLoads file (`.xml`), whose data file is read.
    pub fn read(motion: &Path, grf: &Path, torques: Option<&PathBuf>) -> Result<Self, TrialError> {
        let motion = read(motion)?;
        let (grf, loads) = if is_external_loads(grf) {
            let loads = ExternalLoads::read(grf)?;
            let data = loads.read_data()?;
            ((loads.datafile.display().to_string(), data), Some(loads))
        } else {
            (read(grf)?, None)
        };
        Ok(Self {
            motion,
            grf,
            loads,
            torques: torques.map(|p| read(p)).transpose()?,
        })
    }
}

/// Whether `path` names an ExternalLoads file (extension `.xml`, any case).
pub fn is_external_loads(path: &Path) -> bool {
    path.extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("xml"))
}

/// Column prefixes of the two feet in a GRF file (right, left) and the column names of
/// one foot after its prefix: force, centre of pressure, free torque.
pub const GRF_COLUMNS: [&str; 9] = [
    "ground_force_vx",
    "ground_force_vy",
    "ground_force_vz",
    "ground_force_px",
    "ground_force_py",
    "ground_force_pz",
    "ground_torque_x",
    "ground_torque_y",
    "ground_torque_z",
];

/// The column prefixes (right, left foot) of the GRF files stride knows: OpenSim's example
/// trials such as the shipped gait_1 (`1_ground_force_vx`, `ground_force_vx`) and the
/// `grf.mot` of a stride prediction (`r_ground_force_vx`, `l_ground_force_vx`).
pub const KNOWN_GRF_PREFIXES: [[&str; 2]; 2] = [["1_", ""], ["r_", "l_"]];

/// The first of [`KNOWN_GRF_PREFIXES`] whose force columns `grf` has for both feet (the
/// first convention when none matches, so that the error names its missing column).
pub fn detect_grf_prefixes(grf: &Storage) -> [&'static str; 2] {
    let has = |p: &[&str; 2]| {
        p.iter()
            .all(|f| grf.column(&format!("{f}{}", GRF_COLUMNS[0])).is_some())
    };
    KNOWN_GRF_PREFIXES
        .into_iter()
        .find(has)
        .unwrap_or(KNOWN_GRF_PREFIXES[0])
}

/// The nine columns of one foot whose GRF columns start with `prefix` ([`GRF_COLUMNS`]).
pub fn prefixed_columns(prefix: &str) -> [String; 9] {
    GRF_COLUMNS.map(|c| format!("{prefix}{c}"))
}

/// The measured quantities at one time, in SI units and problem coordinate order.
#[derive(Clone, Debug, Default)]
pub struct Sample {
    /// Coordinates [rad or m].
    pub q: Vec<f64>,
    /// Speeds.
    pub v: Vec<f64>,
    /// Accelerations.
    pub a: Vec<f64>,
    /// GRF, right x y z then left x y z [N].
    pub grf: [f64; 6],
    /// GRT about the ground origin, same order [N m].
    pub grt: [f64; 6],
    /// Generalised forces from inverse dynamics [N m or N] (empty without torques).
    pub tau: Vec<f64>,
}

/// A trial ready to be sampled: filtered kinematics, forces, torques.
#[derive(Clone, Debug)]
pub struct Trial {
    kin: Kinematics,
    /// Forward-translation offset removed from the kinematics and the centres of pressure [m].
    pub tx_offset: f64,
    grf: GroundReactions,
    tau_time: Vec<f64>,
    tau: Vec<Vec<f64>>,
    /// Window [s].
    pub window: [f64; 2],
}

/// Checks that every value of `columns` (named `names`, one value per time of `time`) of
/// `file` is finite.
fn check_finite(
    file: &str,
    time: &[f64],
    names: &[String],
    columns: &[Vec<f64>],
) -> Result<(), TrialError> {
    for (name, col) in names.iter().zip(columns) {
        if let Some((s, v)) = col.iter().enumerate().find(|(_, v)| !v.is_finite()) {
            return Err(TrialError::NotFinite {
                file: file.into(),
                column: name.clone(),
                time: time.get(s).copied().unwrap_or(f64::NAN),
                value: *v,
            });
        }
    }
    Ok(())
}

/// Checks that `window` lies inside the times of `file`.
fn check_window(file: &str, time: &[f64], window: [f64; 2]) -> Result<(), TrialError> {
    let d0 = time.first().copied().unwrap_or(f64::NAN);
    let d1 = time.last().copied().unwrap_or(f64::NAN);
    let [t0, t1] = window;
    if t1.partial_cmp(&t0) != Some(std::cmp::Ordering::Greater) {
        return Err(TrialError::EmptyWindow { t0, t1 });
    }
    let inside = time.len() >= 2 && t0 >= d0 - 1e-9 && t1 <= d1 + 1e-9;
    if !inside {
        return Err(TrialError::Window {
            file: file.into(),
            t0,
            t1,
            d0,
            d1,
        });
    }
    Ok(())
}

impl Trial {
    /// Checks and prepares `files` for `gait` over `window` [s] (any window inside the
    /// data: its ends may fall between samples); `grf_columns` are the right then the left
    /// foot's GRF columns (force x y z [N], centre of pressure x y z [m], free torque x y z
    /// [N m]); the joint angles are low-pass filtered at `cutoff_hz` [Hz] (0: not filtered).
    pub fn new(
        files: &TrialFiles,
        gait: &GaitModel,
        window: [f64; 2],
        grf_columns: &[[String; 9]; 2],
        cutoff_hz: f64,
    ) -> Result<Self, TrialError> {
        let [t0, t1] = window;
        if !(t0.is_finite() && t1.is_finite() && t0 < t1) {
            return Err(TrialError::EmptyWindow { t0, t1 });
        }
        let (mname, motion) = &files.motion;
        check_window(mname, &motion.time(), window)?;
        let mut kin = Kinematics::from_storage_filtered(motion, gait, mname, cutoff_hz)?;
        let tx = gait.forward_translation;
        let tx_offset = interp::<1>(&kin.time, window[0], |s| [kin.q[s][tx]])[0];
        kin.q.iter_mut().for_each(|r| r[tx] -= tx_offset);
        let grf = Self::ground_reactions(files, grf_columns, window)?;
        let (mut tau_time, mut tau) = (Vec::new(), Vec::new());
        if let Some((tname, ts)) = &files.torques {
            tau_time = ts.time();
            check_window(tname, &tau_time, window)?;
            let mut columns = Vec::with_capacity(gait.nq());
            let mut found = Vec::with_capacity(gait.nq());
            for c in &gait.coordinates {
                let names = [format!("{}_moment", c.name), format!("{}_force", c.name)];
                let Some((n, col)) = names.iter().find_map(|n| Some((n, ts.column(n)?))) else {
                    return Err(TrialError::MissingColumn {
                        file: tname.clone(),
                        column: names[0].clone(),
                    });
                };
                columns.push(col);
                found.push(n.clone());
            }
            check_finite(tname, &tau_time, &found, &columns)?;
            tau = (0..tau_time.len())
                .map(|s| columns.iter().map(|c| c[s]).collect())
                .collect();
        }
        Ok(Self {
            kin,
            tx_offset,
            grf,
            tau_time,
            tau,
            window,
        })
    }

    /// The ground reactions of `files` in the columns `grf_columns` (right then left foot,
    /// the nine of [`GRF_COLUMNS`] each), checked to cover `window` [s].
    pub fn ground_reactions(
        files: &TrialFiles,
        grf_columns: &[[String; 9]; 2],
        window: [f64; 2],
    ) -> Result<GroundReactions, TrialError> {
        let (name, grf) = &files.grf;
        let time = grf.time();
        check_window(name, &time, window)?;
        let mut columns: [Vec<f64>; 18] = Default::default();
        for (c, label) in columns.iter_mut().zip(grf_columns.iter().flatten()) {
            *c = grf.column(label).ok_or_else(|| TrialError::MissingColumn {
                file: name.clone(),
                column: label.clone(),
            })?;
        }
        let labels: Vec<String> = grf_columns.iter().flatten().cloned().collect();
        check_finite(name, &time, &labels, &columns)?;
        Ok(GroundReactions::new(time, &columns))
    }

    /// Whether the trial has joint torques.
    pub fn has_torques(&self) -> bool {
        !self.tau.is_empty()
    }

    /// The measured quantities at time `t` [s] (trial time).
    pub fn sample(&self, t: f64) -> Sample {
        let k = &self.kin;
        let nq = k.q.first().map_or(0, Vec::len);
        let lin = |rows: &Vec<Vec<f64>>| -> Vec<f64> {
            (0..nq)
                .map(|i| interp::<1>(&k.time, t, |s| [rows[s][i]])[0])
                .collect()
        };
        let (grf, grt) = self.grf.at(t, self.tx_offset);
        let tau = if self.has_torques() {
            (0..nq)
                .map(|i| interp::<1>(&self.tau_time, t, |s| [self.tau[s][i]])[0])
                .collect()
        } else {
            Vec::new()
        };
        Sample {
            q: lin(&k.q),
            v: lin(&k.v),
            a: lin(&k.a),
            grf,
            grt,
            tau,
        }
    }

    /// Per coordinate: (min, max) of position, speed and acceleration over the window
    /// (the samples inside it and the values interpolated at its ends).
    pub fn ranges(&self) -> [Vec<(f64, f64)>; 3] {
        let k = &self.kin;
        let [t0, t1] = self.window;
        let ends = [self.sample(t0), self.sample(t1)];
        let mut rows: Vec<[&[f64]; 3]> = (0..k.time.len())
            .filter(|&s| k.time[s] >= t0 - 1e-9 && k.time[s] <= t1 + 1e-9)
            .map(|s| [&k.q[s][..], &k.v[s][..], &k.a[s][..]])
            .collect();
        rows.extend(ends.iter().map(|e| [&e.q[..], &e.v[..], &e.a[..]]));
        let nq = k.q.first().map_or(0, Vec::len);
        std::array::from_fn(|m| {
            (0..nq)
                .map(|i| {
                    rows.iter()
                        .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), r| {
                            (lo.min(r[m][i]), hi.max(r[m][i]))
                        })
                })
                .collect()
        })
    }
}

#[cfg(test)]
mod tests;
