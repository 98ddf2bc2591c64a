//! `stride bench geometry`: path evaluation per pose (lengths, and lengths with the moment
//! arms about every coordinate) and the polynomial fit of each model, on one thread.

use anyhow::Context;
use clap::Args;
use std::path::PathBuf;
use std::time::Instant;
use stride_geometry::{fit_model, random_poses, FitModelOptions, FitSettings, PathGeometry};

/// Arguments of `stride bench geometry`.
#[derive(Args)]
pub struct GeometryArgs {
    /// OpenSim model files.
    #[arg(required = true)]
    pub models: Vec<PathBuf>,
    /// Poses of the path-evaluation timing.
    #[arg(long, default_value_t = 500)]
    pub poses: usize,
    /// Skip the polynomial fit (only time the path evaluation).
    #[arg(long)]
    pub no_fit: bool,
}

/// Run `stride bench geometry`: one markdown row per model.
pub fn run(a: GeometryArgs) -> anyhow::Result<()> {
    println!("| model | muscles | wraps | lengths [µs/pose] | lengths + all moment arms [µs/pose] | fit [s] | fit poses | muscles above 3 mm |");
    println!("|---|---|---|---|---|---|---|---|");
    for path in &a.models {
        let model = stride_model::osim::load_osim(path)
            .with_context(|| format!("loading {}", path.display()))?;
        let mut geo = PathGeometry::new(&model)?;
        let poses = random_poses(&model, a.poses.max(1), 3);
        let nm = model.muscles.len();
        let mut out = vec![0.0; nm];
        let t0 = Instant::now();
        for s in 0..poses.len() {
            geo.lengths(poses.pose(s), &mut out);
        }
        let lengths_us = t0.elapsed().as_secs_f64() * 1e6 / poses.len() as f64;
        let t0 = Instant::now();
        for s in 0..poses.len() {
            geo.lengths(poses.pose(s), &mut out);
            for c in 0..model.coordinates.len() {
                geo.moment_arms(poses.pose(s), c, &mut out);
            }
        }
        let all_us = t0.elapsed().as_secs_f64() * 1e6 / poses.len() as f64;
        let (fit_s, n_fit, above) = if a.no_fit {
            ("-".to_string(), "-".to_string(), "-".to_string())
        } else {
            let settings = FitSettings::default();
            let fit_poses = random_poses(&model, settings.n_samples, settings.seed.unwrap_or(1));
            let t0 = Instant::now();
            let report = fit_model(&model, &fit_poses, &FitModelOptions::default())?;
            let names: Vec<&str> = report
                .failures()
                .iter()
                .map(|r| r.muscle.as_str())
                .collect();
            (
                format!("{:.1}", t0.elapsed().as_secs_f64()),
                fit_poses.len().to_string(),
                if names.is_empty() {
                    "none".into()
                } else {
                    names.join(", ")
                },
            )
        };
        let wraps: usize = model.muscles.iter().map(|m| m.wraps.len()).sum();
        println!(
            "| {} | {nm} | {wraps} | {lengths_us:.1} | {all_us:.1} | {fit_s} | {n_fit} | {above} |",
            path.file_name()
                .map_or_else(String::new, |f| f.to_string_lossy().into_owned())
        );
    }
    Ok(())
}
