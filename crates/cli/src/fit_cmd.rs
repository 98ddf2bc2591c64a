//! `stride model fit`: polynomial muscle-tendon geometry from path points.

use anyhow::Context;
use clap::Args;
use serde::Serialize;
use std::path::PathBuf;
use std::time::Instant;
use stride_geometry::{fit_model, poses_from_motion, random_poses, FitModelOptions, FitOptions};
use stride_model::PathPolynomial;

/// Arguments of `stride model fit`.
#[derive(Args)]
pub struct FitArgs {
    /// The OpenSim model file.
    pub file: PathBuf,
    /// Poses to fit on (OpenSim .mot, columns named after coordinates, angles in degrees);
    /// default: random poses in the ranges of the paper.
    #[arg(long)]
    pub samples: Option<PathBuf>,
    /// Number of random poses when no --samples file is given.
    #[arg(long, default_value_t = 5000)]
    pub n_samples: usize,
    /// Seed of the random poses.
    #[arg(long, default_value_t = 1)]
    pub seed: u64,
    /// Write the fitted polynomials to this JSON file (atomically).
    #[arg(long)]
    pub out: Option<PathBuf>,
    /// Lowest polynomial order tried.
    #[arg(long, default_value_t = 3)]
    pub min_order: u32,
    /// Highest polynomial order.
    #[arg(long, default_value_t = 9)]
    pub max_order: u32,
    /// Accuracy target on the RMS length and moment-arm errors [mm].
    #[arg(long, default_value_t = 3.0)]
    pub tolerance_mm: f64,
}

/// The fitted geometry file: polynomials in model muscle order, keyed by muscle name.
#[derive(Serialize)]
struct FittedGeometry<'a> {
    /// Model name.
    model: &'a str,
    /// Model coordinate names (the indices of `PathPolynomial::coordinates` refer to them).
    coordinates: Vec<&'a str>,
    /// Muscle names, same order as `path_polynomials`.
    muscles: Vec<&'a str>,
    /// Fitted polynomial per muscle (null when the muscle spans no coordinate).
    path_polynomials: &'a [Option<PathPolynomial>],
}

/// Run `stride model fit`.
pub fn run(args: FitArgs) -> anyhow::Result<()> {
    let model = stride_model::osim::load_osim(&args.file)
        .with_context(|| format!("loading {}", args.file.display()))?;
    let poses = match &args.samples {
        Some(p) => poses_from_motion(&model, p)?,
        None => random_poses(&model, args.n_samples, args.seed),
    };
    if poses.is_empty() {
        anyhow::bail!("no poses to fit on");
    }
    let options = FitModelOptions {
        fit: FitOptions {
            min_order: args.min_order,
            max_order: args.max_order,
            tolerance: args.tolerance_mm * 1e-3,
        },
        ..FitModelOptions::default()
    };
    let t0 = Instant::now();
    let report = fit_model(&model, &poses, &options)?;
    let elapsed = t0.elapsed().as_secs_f64();
    print!("{}", report.table());
    for w in report.warnings() {
        println!("{w}");
    }
    println!(
        "fitted {} muscles on {} poses in {:.1} s",
        model.muscles.len(),
        poses.len(),
        elapsed
    );
    if let Some(out) = &args.out {
        let file = FittedGeometry {
            model: &model.name,
            coordinates: model.coordinates.iter().map(|c| c.name.as_str()).collect(),
            muscles: model.muscles.iter().map(|m| m.name.as_str()).collect(),
            path_polynomials: &report.polynomials,
        };
        let text = serde_json::to_string_pretty(&file)?;
        stride_model::storage::write_atomic(out, text.as_bytes())
            .with_context(|| format!("writing {}", out.display()))?;
        println!("wrote {}", out.display());
    }
    Ok(())
}
