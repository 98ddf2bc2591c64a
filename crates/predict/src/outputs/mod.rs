//! The files of a result folder that come from the reconstructed gait cycle.
//!
//! - [`tables`]: CSV tables with the unit of every column in its header, the trunk sway;
//! - [`muscles`]: per-muscle force, fibre length and velocity, metabolic power;
//! - [`torques`]: the terms of the torque balances (muscle, passive, actuator, ligament
//!   torques per coordinate), ligament lengths and forces;
//! - [`opensim`]: files OpenSim and Moco open as they are: the model (`model.osim`), the
//!   motion (`motion.mot`), ground reaction forces with their external-loads description
//!   (`grf.mot`, `grf.xml`), states, controls and both as a Moco trajectory (`states.sto`,
//!   `controls.sto`, `trajectory.sto`), and the inverse-dynamics setup that reproduces the
//!   joint torques (`id_setup.xml`).
//!
//! Figures are drawn by [`crate::figures`].

mod muscles;
mod opensim;
mod tables;
mod torques;

pub use opensim::{
    model_coordinates, CONTROLS_FILE, GRF_FILE, GRF_XML_FILE, ID_RESULTS_DIR, ID_SETUP_FILE,
    MODEL_FILE, MOTION_FILE, STATES_FILE, TRAJECTORY_FILE,
};
pub use tables::{column_name, summary_units};

use crate::error::{write_err, PredictError};
use crate::figures::{self, CycleTables};
use std::path::Path;
use stride_files::write_atomic;
use stride_ocp::node::NodeModel;
use stride_ocp::problem::GaitProblem;
use stride_ocp::trajectory::Trajectory;

/// Write every file of the reconstructed gait cycle `cycle` of `problem` into `dir`:
/// OpenSim files, CSV tables and figures.
pub fn write_cycle(
    problem: &GaitProblem,
    node: &NodeModel,
    cycle: &Trajectory,
    dir: &Path,
) -> Result<(), PredictError> {
    let samples = problem.cycle_samples(node, cycle)?;
    opensim::write_model(&problem.model, dir)?;
    opensim::write_motion(problem, cycle, dir)?;
    opensim::write_ground_reactions(problem, cycle, dir)?;
    opensim::write_id_setup(&cycle.time, dir)?;
    opensim::write_states_and_controls(problem, cycle, &samples, dir)?;
    let t = CycleTables::new(problem, cycle);
    tables::write_tables(&t, dir)?;
    muscles::write_muscle_tables(&t, &samples, dir)?;
    torques::write_torque_tables(&t, &problem.model, &samples, dir)?;
    let reference = stride_ocp::data::walking_reference();
    let mut figs = figures::gait_figures(&t, &reference);
    if problem.settings.prosthesis.is_some() {
        figs.extend(figures::prosthesis_figure(&t, &reference));
    }
    for (file, bytes) in figures::render_files(&figs).map_err(|e| write_err(dir, e))? {
        let p = dir.join(file);
        write_atomic(&p, &bytes).map_err(|e| write_err(&p, e))?;
    }
    Ok(())
}
