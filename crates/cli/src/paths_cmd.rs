//! `stride model paths`: muscle–tendon lengths and moment arms along a motion, from the
//! path geometry (wrapping included) or from a fitted polynomial geometry.

use anyhow::Context;
use clap::Args;
use std::fmt::Write as _;
use std::path::PathBuf;
use stride_geometry::{
    polynomial_length, polynomial_moment_arm, poses_from_motion, GeometryFile, MissingCoordinates,
    PathGeometry,
};

/// Arguments of `stride model paths`.
#[derive(Args)]
pub struct PathsArgs {
    /// The OpenSim model file.
    pub file: PathBuf,
    /// Motion (OpenSim .mot/.sto, columns named after coordinates or OpenSim 4 state paths
    /// such as stride's states.sto; every unlocked coordinate but the coupled ones, which
    /// follow their constraint).
    #[arg(long)]
    pub motion: PathBuf,
    /// Output CSV (default: standard output).
    #[arg(long)]
    pub out: Option<PathBuf>,
    /// Replace the output CSV when it exists.
    #[arg(long)]
    pub force: bool,
    /// Evaluate this fitted geometry (from `stride model fit --out`) instead of the paths.
    #[arg(long)]
    pub geometry: Option<PathBuf>,
}

/// Fills the lengths [m] and the moment arms [m] (muscle-major, every coordinate) at `q`.
type Evaluate = dyn FnMut(&[f64], &mut [f64], &mut [f64]);

/// Run `stride model paths`: CSV `frame,muscle,length_m,ma_<coordinate>…` [m].
pub fn run(args: PathsArgs) -> anyhow::Result<()> {
    let mut model = stride_model::osim::load_osim(&args.file)
        .with_context(|| format!("loading {}", args.file.display()))?;
    let poses = poses_from_motion(&model, &args.motion, MissingCoordinates::Error)?;
    let nc = model.coordinates.len();
    let nm = model.muscles.len();
    let mut csv = String::from("frame,muscle,length_m");
    for c in &model.coordinates {
        let _ = write!(csv, ",ma_{}", c.name);
    }
    csv.push('\n');
    // Per frame: lengths [m] and moment arms [muscle][coordinate] [m].
    let mut lengths = vec![0.0; nm];
    let mut arms = vec![0.0; nm * nc];
    let mut evaluate: Box<Evaluate> = match &args.geometry {
        Some(g) => {
            GeometryFile::read(g)?.apply(&mut model)?;
            let polys = model.path_polynomials.clone();
            Box::new(move |q, l, a| {
                a.fill(0.0);
                for (m, p) in polys.iter().enumerate() {
                    let Some(p) = p else {
                        l[m] = f64::NAN;
                        continue;
                    };
                    l[m] = polynomial_length(p, q);
                    for (j, &c) in p.coordinates.iter().enumerate() {
                        a[m * nc + c] = polynomial_moment_arm(p, q, j);
                    }
                }
            })
        }
        None => {
            let mut geo = PathGeometry::new(&model)?;
            let mut buf = vec![0.0; nm];
            Box::new(move |q, l, a| {
                geo.lengths(q, l);
                for c in 0..nc {
                    geo.moment_arms(q, c, &mut buf);
                    for (m, v) in buf.iter().enumerate() {
                        a[m * nc + c] = *v;
                    }
                }
            })
        }
    };
    for f in 0..poses.len() {
        evaluate(poses.pose(f), &mut lengths, &mut arms);
        for (m, mu) in model.muscles.iter().enumerate() {
            let _ = write!(csv, "{f},{},{:.9}", mu.name, lengths[m]);
            for v in &arms[m * nc..(m + 1) * nc] {
                let _ = write!(csv, ",{v:.9}");
            }
            csv.push('\n');
        }
    }
    match &args.out {
        Some(out) => {
            crate::out_file::check_new_file(out, args.force)?;
            stride_files::write_atomic(out, csv.as_bytes())
                .with_context(|| format!("writing {}", out.display()))?;
            eprintln!(
                "wrote {} ({} frames, {nm} muscles)",
                out.display(),
                poses.len()
            );
        }
        None => print!("{csv}"),
    }
    Ok(())
}
