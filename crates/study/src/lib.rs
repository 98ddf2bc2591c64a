//! stride-study: study files, parameter sweeps and result stores for stride.
//!
//! - [`spec`]: study files (`[study]`, `[base]`, `[grid]`) expanded into named cases.
//! - [`store`]: the output folder (finished cases, study hash, `index.csv`).
//! - [`runner`]: parallel, resumable execution through a [`runner::CaseRunner`].
//! - [`predict_runner`]: the real runner (`stride_predict::predict`, continuation guesses).
//! - [`analysis`]: walk/run classification, transition speed, fits, speed series.
//! - [`report`]: the report of a study folder (`report.json`, tables, figures).
//! - [`conditions`]: conditions against the reference case (`conditions.csv`, figure).
//! - [`figures`]: COT and stride frequency versus speed (SVG, PNG).
//! - [`tasks`]: a study cut into tasks and waves for a batch scheduler (Slurm arrays).

pub mod analysis;
pub mod conditions;
pub mod figures;
pub mod predict_runner;
pub mod report;
pub mod runner;
pub mod spec;
pub mod store;
pub mod tasks;
