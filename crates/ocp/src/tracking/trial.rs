//! The measured trial a tracking problem follows: joint angles (inverse kinematics), ground
//! reaction forces of both feet and optionally net joint torques (inverse dynamics), read,
//! checked against the model and the time window, filtered and sampled at any time.

use crate::experimental::Kinematics;
use crate::gait::GaitModel;
use std::path::{Path, PathBuf};
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
    /// The window is empty, reversed or not finite.
    #[error("window [{t0}, {t1}] s: the end must be after the start")]
    EmptyWindow {
        /// Window start [s].
        t0: f64,
        /// Window end [s].
        t1: f64,
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
    /// Ground reaction forces, centres of pressure and free torques (`.mot`).
    pub grf: (String, Storage),
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
            torques: Some(parse(GAIT_1_ID, "gait_1_id.sto")),
        }
    }

    /// Reads the files of a trial.
    pub fn read(motion: &Path, grf: &Path, torques: Option<&PathBuf>) -> Result<Self, TrialError> {
        Ok(Self {
            motion: read(motion)?,
            grf: read(grf)?,
            torques: torques.map(|p| read(p)).transpose()?,
        })
    }
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
    grf_time: Vec<f64>,
    /// Per GRF sample: right then left foot, the 9 columns of [`GRF_COLUMNS`].
    grf: Vec<[f64; 18]>,
    tau_time: Vec<f64>,
    tau: Vec<Vec<f64>>,
    /// Window [s].
    pub window: [f64; 2],
}

/// Linear interpolation of `rows` (one per time of `time`) at `t` (clamped at the ends).
fn interp<const N: usize>(time: &[f64], t: f64, row: impl Fn(usize) -> [f64; N]) -> [f64; N] {
    let n = time.len();
    let s = time.partition_point(|&x| x <= t).clamp(1, n - 1) - 1;
    let w = ((t - time[s]) / (time[s + 1] - time[s])).clamp(0.0, 1.0);
    let (a, b) = (row(s), row(s + 1));
    std::array::from_fn(|i| a[i] + w * (b[i] - a[i]))
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
    let inside = time.len() >= 2 && t0 < t1 && t0 >= d0 - 1e-9 && t1 <= d1 + 1e-9;
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
    /// Checks and prepares `files` for `gait` over `window` [s]; the right foot's GRF
    /// columns start with `prefixes[0]`, the left foot's with `prefixes[1]`; the joint
    /// angles are low-pass filtered at `cutoff_hz` [Hz] (0: not filtered).
    pub fn new(
        files: &TrialFiles,
        gait: &GaitModel,
        window: [f64; 2],
        prefixes: [&str; 2],
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
        let (gname, grf_s) = &files.grf;
        let grf_time = grf_s.time();
        check_window(gname, &grf_time, window)?;
        let (mut cols, mut names) = (Vec::with_capacity(18), Vec::with_capacity(18));
        for prefix in prefixes {
            for c in GRF_COLUMNS {
                let name = format!("{prefix}{c}");
                cols.push(grf_s.column(&name).ok_or(TrialError::MissingColumn {
                    file: gname.clone(),
                    column: name.clone(),
                })?);
                names.push(name);
            }
        }
        check_finite(gname, &grf_time, &names, &cols)?;
        let grf = (0..grf_time.len())
            .map(|s| std::array::from_fn(|i| cols[i][s]))
            .collect();
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
            grf_time,
            grf,
            tau_time,
            tau,
            window,
        })
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
        let g = interp::<18>(&self.grf_time, t, |s| self.grf[s]);
        let (mut grf, mut grt) = ([0.0; 6], [0.0; 6]);
        for foot in 0..2 {
            let c = &g[9 * foot..9 * foot + 9];
            let f = [c[0], c[1], c[2]];
            let p = [c[3] - self.tx_offset, c[4], c[5]];
            let m = [
                p[1] * f[2] - p[2] * f[1] + c[6],
                p[2] * f[0] - p[0] * f[2] + c[7],
                p[0] * f[1] - p[1] * f[0] + c[8],
            ];
            grf[3 * foot..3 * foot + 3].copy_from_slice(&f);
            grt[3 * foot..3 * foot + 3].copy_from_slice(&m);
        }
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

    /// Per coordinate: (min, max) of position, speed and acceleration over the window.
    pub fn ranges(&self) -> [Vec<(f64, f64)>; 3] {
        let k = &self.kin;
        let [t0, t1] = self.window;
        let inside: Vec<usize> = (0..k.time.len())
            .filter(|&s| k.time[s] >= t0 - 1e-9 && k.time[s] <= t1 + 1e-9)
            .collect();
        let nq = k.q.first().map_or(0, Vec::len);
        let range = |rows: &Vec<Vec<f64>>| -> Vec<(f64, f64)> {
            (0..nq)
                .map(|i| {
                    inside
                        .iter()
                        .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), &s| {
                            (lo.min(rows[s][i]), hi.max(rows[s][i]))
                        })
                })
                .collect()
        };
        [range(&k.q), range(&k.v), range(&k.a)]
    }
}
