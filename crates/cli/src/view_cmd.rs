//! `stride view`: write a self-contained HTML page (works offline from the file system)
//! that animates a result folder's gait cycle in 3D, or every case of a study folder.

use anyhow::Context;
use clap::Args;
use std::path::{Path, PathBuf};
use stride_model::Model;
use stride_view::{folder, ViewOptions};

/// Page written into a result or study folder.
pub const VIEW_FILE: &str = "view.html";

/// Arguments of `stride view`.
#[derive(Args)]
pub struct ViewArgs {
    /// Result folder (`stride predict`, a study case) or study output folder (`stride study`).
    pub folder: PathBuf,
    /// OpenSim model (or shipped model's name) the folder was predicted with (default: the
    /// folder's `.osim` when it has one, else the study file's model, else the built-in
    /// model).
    #[arg(long)]
    pub model: Option<PathBuf>,
    /// Page to write (default: `<folder>/view.html`, replaced when it exists).
    #[arg(long)]
    pub out: Option<PathBuf>,
    /// Replace the page named by `--out` when it exists.
    #[arg(long)]
    pub force: bool,
    /// Frames per gait cycle (default 100 for a result folder, 50 per case of a study).
    #[arg(long)]
    pub frames: Option<usize>,
}

/// Run `stride view`: write the page and print its path.
pub fn run(args: ViewArgs) -> anyhow::Result<()> {
    if let Some(out) = &args.out {
        crate::out_file::check_new_file(out, args.force)?;
    }
    let model = view_model(&args.folder, args.model.as_deref())?;
    let options = ViewOptions {
        frames: args.frames,
    };
    let page = write_page(&args.folder, &model, args.out.as_deref(), &options)?;
    println!("{}", page.display());
    Ok(())
}

/// The page written at the end of `stride predict` and `stride study` into their output
/// folder (`view.html`), with the model they solved; prints its path.
pub fn write_default(folder: &Path, model: &Model) -> anyhow::Result<()> {
    let page = write_page(folder, model, None, &ViewOptions::default())
        .context("writing the viewer page (the results are complete; `stride view` retries)")?;
    println!("viewer page {}", page.display());
    Ok(())
}

/// Write the page of `folder` (a study folder when it has `study.toml` and `cases/`, else a
/// result folder) to `out` (default `<folder>/view.html`, then listed in the folder's
/// marker as stride's file) atomically; returns its path.
fn write_page(
    folder: &Path,
    model: &Model,
    out: Option<&Path>,
    options: &ViewOptions,
) -> anyhow::Result<PathBuf> {
    let html = if folder::is_study_folder(folder) {
        stride_view::study_page(model, folder, options)?
    } else {
        stride_view::result_page(model, folder, options)?
    };
    let path = out.map_or_else(|| folder.join(VIEW_FILE), Path::to_path_buf);
    stride_files::write_atomic(&path, html.as_bytes())
        .with_context(|| format!("writing {}", path.display()))?;
    if out.is_none() {
        stride_files::result_dir::record_file(folder, VIEW_FILE)
            .with_context(|| format!("recording {VIEW_FILE} in {}", folder.display()))?;
    }
    Ok(path)
}

/// The model of a folder: `--model`, else its `.osim`, else (study folder) the study file's
/// `model` (an `.osim` or a shipped model's name), else the built-in model.
fn view_model(folder: &Path, model: Option<&Path>) -> anyhow::Result<Model> {
    let load = |p: &Path| {
        crate::model_load::load_for_view(p)
            .with_context(|| format!("loading model {}", p.display()))
    };
    if let Some(p) = model {
        return load(p);
    }
    if let Some(p) = folder::model_file(folder)? {
        return load(&p);
    }
    if folder::is_study_folder(folder) {
        let study = stride_study::spec::load(&folder.join("study.toml"))?;
        if let Some(p) = &study.header.model {
            return load(p);
        }
    }
    Ok(stride_model::default_model::default_model())
}
