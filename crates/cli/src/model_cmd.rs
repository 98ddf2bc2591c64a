//! `stride model ...`: inspect, fit and build musculoskeletal models.

use anyhow::Context as _;
use clap::Subcommand;
use std::path::PathBuf;
use stride_files::write_atomic;
use stride_model::default_model::{build_default_model, default_model, default_model_json};

/// Model subcommands.
#[derive(Subcommand)]
pub enum ModelCommand {
    /// Print coordinates, bodies and masses, joints, muscles, contacts, actuators, passive
    /// torques, polynomial geometry and unsupported elements of an `.osim` file (or of the
    /// built-in model when no file is given).
    Inspect {
        /// The OpenSim model file, or a shipped model's name (with its settings applied);
        /// omit for the built-in default model.
        file: Option<PathBuf>,
    },
    /// Regenerate the built-in model (`crates/model/data/default_model.json`) from the
    /// reference data: subject1_v2.osim + contacts + passive torques + metabolic
    /// parameters + polynomial geometry + arm actuators.
    BuildDefault {
        /// The reference data folder (`shared/reference`).
        #[arg(long)]
        reference: PathBuf,
        /// Output file.
        #[arg(long, default_value = "crates/model/data/default_model.json")]
        out: PathBuf,
        /// Folder of the shipped `subject1` import: `subject1_v2.osim`, its settings file
        /// and the paper's polynomial geometry as a geometry file.
        #[arg(long, default_value = "crates/model/data/models/subject1")]
        models: PathBuf,
    },
    /// Write the model settings file that makes an OpenSim model predict walking: foot
    /// contact spheres of a shipped model scaled to its feet, torque actuators on the
    /// coordinates no muscle crosses, PredSim's passive torques and bounds.
    Adapt(crate::adapt_cmd::AdaptArgs),
    /// Fit polynomial muscle-tendon geometry to the path points of an `.osim` file and print the accuracy table.
    Fit(crate::fit_cmd::FitArgs),
    /// Muscle-tendon lengths and moment arms about every coordinate along a motion (CSV),
    /// from the path geometry with wrapping, or from a fitted geometry (`--geometry`).
    Paths(crate::paths_cmd::PathsArgs),
}

/// Run a model subcommand.
pub fn run(cmd: ModelCommand) -> anyhow::Result<()> {
    match cmd {
        ModelCommand::Inspect { file } => {
            let shipped = file
                .as_deref()
                .filter(|f| !f.exists())
                .and_then(|f| f.to_str())
                .and_then(stride_model::shipped::shipped);
            let model = match (&file, shipped) {
                (Some(f), Some(_)) => crate::model_load::load_model(Some(f), None, None, true)?,
                (Some(f), None) => stride_model::osim::load_osim(f)?,
                (None, _) => default_model(),
            };
            print!("{}", stride_model::inspect::render(&model));
            Ok(())
        }
        ModelCommand::BuildDefault {
            reference,
            out,
            models,
        } => {
            let model = build_default_model(&reference)?;
            crate::build_default::write_subject1(&model, &reference, &models)?;
            let text = default_model_json(&model)?;
            write_atomic(&out, text.as_bytes())
                .with_context(|| format!("writing {}", out.display()))?;
            println!(
                "wrote {} and the subject1 import in {} ({} bytes): {} coordinates, {} muscles, {} contacts, {} passive torques, {} actuators",
                out.display(),
                models.display(),
                text.len(),
                model.coordinates.len(),
                model.muscles.len(),
                model.contacts.len(),
                model.passive_torques.len(),
                model.actuators.len()
            );
            Ok(())
        }
        ModelCommand::Adapt(args) => crate::adapt_cmd::run(args),
        ModelCommand::Fit(args) => crate::fit_cmd::run(args),
        ModelCommand::Paths(args) => crate::paths_cmd::run(args),
    }
}
