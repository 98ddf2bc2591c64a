//! `stride model fit`: polynomial muscle-tendon geometry from path points.

use anyhow::Context;
use clap::Args;
use std::path::PathBuf;
use std::time::Instant;
use stride_geometry::{
    content_hash, fit_ligaments, fit_model, poses_from_motion, random_poses, FitModelOptions,
    FitOptions, FitSettings, GeometryFile, MissingCoordinates,
};
use stride_model::input_file::read_limited;
use stride_model::osim::MAX_OSIM_BYTES;

/// Arguments of `stride model fit`.
#[derive(Args)]
pub struct FitArgs {
    /// The OpenSim model file.
    pub file: PathBuf,
    /// Poses to fit on (OpenSim .mot/.sto, columns named after coordinates or OpenSim 4
    /// state paths, angles in degrees unless `inDegrees=no`; coordinates without a column
    /// at their default, coupled ones from their constraint); default: random poses in the
    /// ranges of the paper.
    #[arg(long)]
    pub samples: Option<PathBuf>,
    /// Number of random poses when no --samples file is given.
    #[arg(long, default_value_t = 5000)]
    pub n_samples: usize,
    /// Seed of the random poses.
    #[arg(long, default_value_t = 1)]
    pub seed: u64,
    /// Write the fitted geometry to this file (JSON, atomically), for `stride predict
    /// --geometry`, the study key `geometry` and `stride model paths --geometry`.
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

/// Run `stride model fit`.
pub fn run(args: FitArgs) -> anyhow::Result<()> {
    let bytes = read_limited(&args.file, MAX_OSIM_BYTES)
        .with_context(|| format!("reading model {}", args.file.display()))?;
    let model = stride_model::osim::parse_osim(
        &String::from_utf8_lossy(&bytes),
        &args.file.display().to_string(),
    )?;
    let poses = match &args.samples {
        Some(p) => poses_from_motion(&model, p, MissingCoordinates::Default)?,
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
    let failures: Vec<&str> = report
        .failures()
        .iter()
        .map(|r| r.muscle.as_str())
        .collect();
    if failures.is_empty() {
        println!("every muscle within {:.1} mm", args.tolerance_mm);
    } else {
        println!(
            "{} muscle(s) above the {:.1} mm threshold: {}",
            failures.len(),
            args.tolerance_mm,
            failures.join(", ")
        );
    }
    let ligaments = if model.ligaments.is_empty() {
        None
    } else {
        let report = fit_ligaments(&model, &poses, &options)?;
        print!("{}", report.table());
        for w in report.warnings() {
            println!("{w}");
        }
        Some(report)
    };
    if let Some(out) = &args.out {
        let settings = FitSettings {
            n_samples: poses.len(),
            seed: args.samples.is_none().then_some(args.seed),
            orders: [args.min_order, args.max_order],
            tolerance: args.tolerance_mm * 1e-3,
        };
        let mut file = GeometryFile::new(&model, Some(content_hash(&bytes)), settings, &report);
        if let Some(l) = &ligaments {
            file = file.with_ligaments(&model, l);
        }
        file.write(out)?;
        println!("wrote {}", out.display());
    }
    Ok(())
}
