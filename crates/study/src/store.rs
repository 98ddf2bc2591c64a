//! The output folder of a study: one folder per finished case (`cases/<name>/`, appearing
//! atomically by renaming a temporary folder whose last file is `case.json`), the study
//! file and its hash, and `index.csv`.

use crate::spec::{Case, Study};
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;
use std::fmt::Write as _;
use std::path::{Path, PathBuf};
use std::sync::Arc;
use stride_files::claim::{Claim, ClaimError, Holder};
use stride_files::lock::{FileLock, LockError, LockMode};
use stride_files::result_dir::{self, OutputError, ResultKind};
use stride_files::write_atomic;

/// File marking a finished case (its record, written last inside the case folder).
pub const CASE_RECORD: &str = "case.json";
/// File holding the hash of the study file an output folder was made from.
pub const STUDY_HASH: &str = "study.hash";
/// Lock file of a study output folder: a whole-study run holds it exclusively (its process
/// id written inside); runners of single cases (cluster array tasks) hold it shared, each
/// with a claim on the case it runs ([`Store::claim`]).
pub const STUDY_LOCK: &str = ".lock";

/// Folder of the case claim files (`<case>.lock`, [`stride_files::claim`]): a claim file
/// names the live or last process that ran the case.
pub const CLAIMS: &str = "claims";

/// Why the output folder could not be used.
#[derive(Debug, thiserror::Error)]
pub enum StoreError {
    /// A filesystem operation failed.
    #[error("{path}: {reason}")]
    Io {
        /// Path.
        path: String,
        /// Why.
        reason: String,
    },
    /// The folder was made from another study file.
    #[error("{folder} was made from a different study file (hash {found}, this file {expected}); use another output folder or --force")]
    OtherStudy {
        /// Output folder.
        folder: String,
        /// Hash recorded in the folder.
        found: String,
        /// Hash of this study file.
        expected: String,
    },
    /// The selected cases cannot run on their own.
    #[error("{0}")]
    Selection(String),
    /// The output folder cannot hold a study.
    #[error(transparent)]
    Output(#[from] OutputError),
    /// Another process runs a study in the folder.
    #[error("{folder}: another stride process{} is running a study in this folder; wait for it to finish or use another output folder", stride_files::lock::holder_text(*.holder, .host.as_deref()))]
    Busy {
        /// Output folder.
        folder: String,
        /// Process id of the holder, when known.
        holder: Option<u32>,
        /// Host of the holder, when known.
        host: Option<String>,
    },
    /// A case record that cannot be read.
    #[error(
        "{path}: corrupt case record ({reason}); remove the case folder to run the case again"
    )]
    Corrupt {
        /// Record file.
        path: String,
        /// Why.
        reason: String,
    },
}

pub(crate) fn io_err(path: &Path, e: impl ToString) -> StoreError {
    StoreError::Io {
        path: path.display().to_string(),
        reason: e.to_string(),
    }
}

/// Final state of a case.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum CaseStatus {
    /// The solver converged.
    Converged,
    /// Solver error, not converged, panic, or no solution to continue from.
    Failed,
    /// Not run (yet).
    NotRun,
}

impl CaseStatus {
    /// Name used in tables.
    pub fn as_str(&self) -> &'static str {
        match self {
            Self::Converged => "converged",
            Self::Failed => "failed",
            Self::NotRun => "not run",
        }
    }
}

/// A number written as JSON `null` (NaN) read back as NaN.
fn null_as_nan<'de, D: serde::Deserializer<'de>>(d: D) -> Result<f64, D::Error> {
    Ok(Option::<f64>::deserialize(d)?.unwrap_or(f64::NAN))
}

/// Gait outcome measures of a converged case (FORMULATION 11.3).
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct Metrics {
    /// Cost of transport (Bhargava, basal included) [J kg⁻¹ m⁻¹].
    pub cost_of_transport: f64,
    /// Stride length [m].
    pub stride_length: f64,
    /// Stride frequency [strides s⁻¹].
    pub stride_frequency: f64,
    /// Step width [m]; NaN (written as null) for a planar model.
    #[serde(deserialize_with = "null_as_nan")]
    pub step_width: f64,
    /// Fraction of the cycle in double support.
    pub double_support_fraction: f64,
    /// Correlation of the normalised COM potential and forward kinetic energies over the
    /// cycle (> 0: in phase, running; < 0: out of phase, walking); `None` if not computed.
    pub energy_phase_correlation: Option<f64>,
}

/// What a case runner reports back.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct CaseOutcome {
    /// Whether the solver converged.
    pub converged: bool,
    /// Solver status or error text.
    pub reason: String,
    /// Final objective.
    pub objective: Option<f64>,
    /// Solver iterations.
    pub iterations: Option<usize>,
    /// Outcome measures (converged cases).
    pub metrics: Option<Metrics>,
    /// Whether the case folder holds a solution usable by continuation guesses.
    pub solution_written: bool,
}

/// The record of a finished case (`case.json`).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct CaseRecord {
    /// Case name.
    pub name: String,
    /// Group (name without the guess).
    pub group: String,
    /// Initial guess as written in study files.
    pub guess: String,
    /// Grid axis values.
    pub axes: BTreeMap<String, String>,
    /// Imposed speed [m s⁻¹].
    pub speed: f64,
    /// Final status.
    pub status: CaseStatus,
    /// Why it failed (or the solver status).
    pub reason: String,
    /// Final objective.
    pub objective: Option<f64>,
    /// Solver iterations.
    pub iterations: Option<usize>,
    /// Wall time of the case [s].
    pub time_s: f64,
    /// Case whose solution seeded a continuation guess.
    pub continued_from: Option<String>,
    /// Outcome measures.
    pub metrics: Option<Metrics>,
    /// Whether the case folder holds a solution usable by continuation guesses.
    #[serde(default)]
    pub solution_written: bool,
}

/// FNV-1a 64-bit hash of bytes, as 16 hex digits (identifies a study file's text).
pub fn fnv1a64(bytes: &[u8]) -> String {
    let mut h: u64 = 0xcbf2_9ce4_8422_2325;
    for &b in bytes {
        h ^= b as u64;
        h = h.wrapping_mul(0x0000_0100_0000_01b3);
    }
    format!("{h:016x}")
}

/// Paths of a study output folder, and the lock of the run writing it.
#[derive(Clone, Debug)]
pub struct Store {
    /// Output folder.
    pub root: PathBuf,
    /// The folder's lock, held while this store (or a clone) exists; `None` for a
    /// read-only view.
    lock: Option<Arc<FileLock>>,
    /// Batch job named in this store's case claims (`-`: none).
    job: String,
}

/// Take the exclusive lock of the study output folder `root` (which exists).
pub fn lock_study(root: &Path) -> Result<FileLock, StoreError> {
    lock_study_as(root, LockMode::Exclusive)
}

fn lock_study_as(root: &Path, mode: LockMode) -> Result<FileLock, StoreError> {
    FileLock::try_lock(&root.join(STUDY_LOCK), mode).map_err(|e| match e {
        LockError::Held { holder, host, .. } => StoreError::Busy {
            folder: root.display().to_string(),
            holder,
            host,
        },
        LockError::Io { path, reason } => StoreError::Io { path, reason },
    })
}

impl Store {
    /// A read-only view of the study output folder `root` (reports): no lock is taken.
    pub fn at(root: &Path) -> Self {
        Self {
            root: root.to_path_buf(),
            lock: None,
            job: "-".into(),
        }
    }

    /// This store, naming `job` (a batch job id such as Slurm's `12345_7`) in its claims.
    pub fn with_job(mut self, job: &str) -> Self {
        self.job = job.to_string();
        self
    }

    /// Whether this store holds the folder's lock.
    pub fn is_locked(&self) -> bool {
        self.lock.is_some()
    }

    /// Open (creating if needed) the output folder of `study` for a run: refuse a folder
    /// that is not a study folder ([`result_dir::inspect`]), one in use by another process
    /// (the lock is held as long as the store exists), or one made from a different study
    /// file unless `force`; then remove the temporary folders of killed runs.
    pub fn open(root: &Path, study: &Study, force: bool) -> Result<Self, StoreError> {
        Self::open_as(root, study, force, LockMode::Exclusive)
    }

    /// [`Store::open`] for one of many runners of single cases working in the folder at
    /// once (cluster array tasks, possibly on several hosts): the folder's lock is shared
    /// (refused only while a whole-study run holds it), each case is claimed before it
    /// runs ([`Store::claim`]), and only this host's dead processes' temporary files are
    /// removed.
    pub fn open_shared(root: &Path, study: &Study, force: bool) -> Result<Self, StoreError> {
        Self::open_as(root, study, force, LockMode::Shared)
    }

    fn open_as(
        root: &Path,
        study: &Study,
        force: bool,
        mode: LockMode,
    ) -> Result<Self, StoreError> {
        result_dir::inspect(root, ResultKind::Study)?;
        result_dir::check_writable(root)?;
        let cases = root.join("cases");
        std::fs::create_dir_all(&cases).map_err(|e| io_err(&cases, e))?;
        let claims = root.join(CLAIMS);
        std::fs::create_dir_all(&claims).map_err(|e| io_err(&claims, e))?;
        let lock = lock_study_as(root, mode)?;
        let hash = fnv1a64(study.source_text.as_bytes());
        let hash_file = root.join(STUDY_HASH);
        let found = std::fs::read_to_string(&hash_file)
            .ok()
            .map(|f| f.trim().to_string());
        if let Some(found) = &found {
            if *found != hash && !force {
                return Err(StoreError::OtherStudy {
                    folder: root.display().to_string(),
                    found: found.clone(),
                    expected: hash,
                });
            }
        }
        let store = Self {
            root: root.to_path_buf(),
            lock: Some(Arc::new(lock)),
            job: "-".into(),
        };
        // Shared openers write the same files (atomically): only when something differs.
        let copy = root.join("study.toml");
        let same_copy = std::fs::read_to_string(&copy).is_ok_and(|t| t == study.source_text);
        if mode == LockMode::Exclusive
            || found.as_deref() != Some(hash.as_str())
            || !same_copy
            || result_dir::marker_kind(root).is_none()
        {
            result_dir::write_marker(root, ResultKind::Study).map_err(|e| io_err(root, e))?;
            write_atomic(&hash_file, format!("{hash}\n").as_bytes())
                .map_err(|e| io_err(&hash_file, e))?;
            write_atomic(&copy, study.source_text.as_bytes()).map_err(|e| io_err(&copy, e))?;
        }
        // Temporary files and case work folders of killed runs: of this host's dead
        // processes; with the exclusive lock no other run can be in flight, so all of them.
        for dir in [root, cases.as_path()] {
            result_dir::clean_stale(dir);
            result_dir::clean_temp_files(dir);
        }
        if mode == LockMode::Exclusive {
            for (name, _) in stride_files::reserve::work_folders(&cases) {
                stride_files::reserve::clean_work_of(&cases, &name);
            }
        }
        Ok(store)
    }

    /// Claim file of a case (`claims/<name>.lock`).
    pub fn claim_path(&self, name: &str) -> PathBuf {
        self.root.join(CLAIMS).join(format!("{name}.lock"))
    }

    /// Claim case `name` for this process before running it: `Ok(Err(holder))` when a live
    /// process (here or on another host) has it. The claim holder removes what killed runs
    /// of the case left (its work folder, whichever host made it).
    pub fn claim(&self, name: &str) -> Result<Result<Claim, Holder>, StoreError> {
        match Claim::try_take(&self.claim_path(name), &self.job) {
            Ok(c) => {
                stride_files::reserve::clean_work_of(&self.cases_dir(), name);
                Ok(Ok(c))
            }
            Err(ClaimError::Held { holder, .. }) => Ok(Err(holder)),
            Err(ClaimError::Io { path, reason }) => Err(StoreError::Io { path, reason }),
        }
    }

    /// Folder of finished cases.
    pub fn cases_dir(&self) -> PathBuf {
        self.root.join("cases")
    }

    /// Final folder of a case.
    pub fn case_dir(&self, name: &str) -> PathBuf {
        self.cases_dir().join(name)
    }

    /// The record of a finished case (`None`: not run); an unreadable record is an error.
    pub fn record(&self, name: &str) -> Result<Option<CaseRecord>, StoreError> {
        let p = self.case_dir(name).join(CASE_RECORD);
        let text = match std::fs::read_to_string(&p) {
            Err(e) if e.kind() == std::io::ErrorKind::NotFound => return Ok(None),
            Err(e) => return Err(io_err(&p, e)),
            Ok(t) => t,
        };
        serde_json::from_str(&text)
            .map(Some)
            .map_err(|e| StoreError::Corrupt {
                path: p.display().to_string(),
                reason: e.to_string(),
            })
    }

    /// Write a case's folder whole ([`result_dir::write_staged`]): `run` gets a fresh
    /// staging folder (in the work folder `cases/.stride-work.<name>`), writes the case's
    /// result files into it once and returns the case's record, which is written last; the
    /// folder then replaces the case's final folder.
    pub fn write_case(
        &self,
        name: &str,
        run: impl FnOnce(&Path) -> CaseRecord,
    ) -> Result<(), StoreError> {
        let dst = self.case_dir(name);
        let io = |e| io_err(&dst, e);
        result_dir::write_staged(&dst, "partial", ResultKind::Prediction, io, |tmp| {
            let record = run(tmp);
            let p = tmp.join(CASE_RECORD);
            let json = serde_json::to_string_pretty(&record).map_err(|e| io_err(&p, e))?;
            write_atomic(&p, json.as_bytes()).map_err(|e| io_err(&p, e))
        })
    }

    /// Rewrite `index.csv` atomically: one row per case, finished or not.
    pub fn write_index(
        &self,
        cases: &[Case],
        records: &[Option<CaseRecord>],
        axes: &[String],
    ) -> Result<(), StoreError> {
        let p = self.root.join("index.csv");
        write_atomic(&p, index_csv(cases, records, axes).as_bytes()).map_err(|e| io_err(&p, e))
    }
}

fn csv_field(s: &str) -> String {
    if s.contains([',', '"', '\n']) {
        format!("\"{}\"", s.replace('"', "\"\""))
    } else {
        s.to_string()
    }
}

fn opt<T: std::fmt::Display>(v: Option<T>) -> String {
    v.map(|x| x.to_string()).unwrap_or_default()
}

/// The index table: name, varying axes, guess, status, reason, objective, iterations,
/// time, cost of transport, stride length, stride frequency, step width, double support,
/// energy phase correlation.
pub fn index_csv(cases: &[Case], records: &[Option<CaseRecord>], axes: &[String]) -> String {
    let mut s = String::from("name");
    for a in axes {
        s.push(',');
        s.push_str(&csv_field(a));
    }
    s.push_str(",guess,status,reason,objective,iterations,time_s,cost_of_transport,stride_length_m,stride_frequency_per_s,step_width_m,double_support_fraction,energy_phase_correlation,continued_from\n");
    for (c, r) in cases.iter().zip(records) {
        s.push_str(&csv_field(&c.name));
        for a in axes {
            s.push(',');
            s.push_str(&csv_field(c.axes.get(a).map(String::as_str).unwrap_or("")));
        }
        let _ = write!(s, ",{}", c.guess);
        match r {
            None => s.push_str(",not run,,,,,,,,,,,\n"),
            Some(r) => {
                let m = r.metrics.as_ref();
                let _ = writeln!(
                    s,
                    ",{},{},{},{},{:.3},{},{},{},{},{},{},{}",
                    r.status.as_str(),
                    csv_field(&r.reason),
                    opt(r.objective),
                    opt(r.iterations),
                    r.time_s,
                    opt(m.map(|m| m.cost_of_transport)),
                    opt(m.map(|m| m.stride_length)),
                    opt(m.map(|m| m.stride_frequency)),
                    opt(m.map(|m| m.step_width)),
                    opt(m.map(|m| m.double_support_fraction)),
                    opt(m.and_then(|m| m.energy_phase_correlation)),
                    csv_field(r.continued_from.as_deref().unwrap_or("")),
                );
            }
        }
    }
    s
}
