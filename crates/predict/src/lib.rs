//! stride-predict: predictions of gait on top of the problem of `stride-ocp`.
//!
//! - [`predict`]: multi-start solves (each guess first on a coarse mesh: presolve), warm
//!   starts from a neighbouring optimum (continuation), the kept solve.
//! - [`results`]: the result folder of a prediction, written whole through one staging
//!   folder, and its rewrite with the current definitions.
//! - [`solution`]: the kept solution of a result folder (`solution.json`).
//! - [`outputs`]: the files of a result folder (OpenSim files, tables).
//! - [`figures`]: the gait figures of a result folder, with the experimental reference.
//! - [`track`]: tracking solves, first on a coarse mesh (the prediction's presolve).
//! - [`track_output`]: the result folder of a tracking solve (`stride track`).
//! - [`error`]: why a prediction or the writing of its results failed.

pub mod error;
pub mod figures;
pub mod outputs;
pub mod predict;
pub mod results;
pub mod solution;
pub mod track;
pub mod track_output;
