//! `stride model adapt`: the model settings file that makes an OpenSim model predict
//! walking (foot contact spheres, torque actuators, passive torques; decision 0008); and
//! the same adaptation done on the fly when `--model X.osim` comes without a settings
//! file and cannot walk as it is, cached per user as the fitted geometry is (keyed by the
//! model file's content).

use anyhow::Context as _;
use clap::Args;
use std::path::{Path, PathBuf};
use stride_files::write_atomic;
use stride_geometry::content_hash;
use stride_model::model_settings::ModelSettings;
use stride_model::Model;
use stride_ocp::adapt::{adapt, reasons, Adaptation, Reference, DEFAULT_REFERENCE};

/// Version of the adaptation rule, part of the cache file name: a cached file written by
/// an older rule is not reused.
const RULE_VERSION: u32 = 1;

/// Name of the adapted settings file in a result folder.
pub(crate) const RESULT_FILE: &str = "model_settings.toml";

/// Arguments of `stride model adapt`.
#[derive(Args)]
pub struct AdaptArgs {
    /// The OpenSim model file.
    pub file: PathBuf,
    /// Shipped model whose foot contact spheres (scaled to this model's feet), contact
    /// law, metabolic parameters and distance constraints are copied.
    #[arg(long, default_value = DEFAULT_REFERENCE)]
    pub like: String,
    /// Settings file to write; default `<model>.toml` beside the model, which `--model`
    /// then reads by itself.
    #[arg(long)]
    pub out: Option<PathBuf>,
    /// Replace an existing settings file.
    #[arg(long)]
    pub force: bool,
}

/// The `.osim` file `path` read and imported (no settings applied), with its bytes.
fn import(path: &Path) -> anyhow::Result<(Model, Vec<u8>)> {
    let bytes = std::fs::read(path).with_context(|| format!("reading model {}", path.display()))?;
    let model = stride_model::osim::parse_osim(
        &String::from_utf8_lossy(&bytes),
        &path.display().to_string(),
    )?;
    Ok((model, bytes))
}

/// The adaptation of `model` (from `path`) like the shipped model `like`, as settings
/// file text checked to read back and apply to the model.
fn adapted_text(model: &Model, path: &Path, like: &str) -> anyhow::Result<(Adaptation, String)> {
    let reference = Reference::shipped(like)?;
    let a = adapt(model, &reference)?;
    let text = a.text(model, &path.display().to_string());
    let name = format!("adapted settings of {}", path.display());
    ModelSettings::parse(&text, &name)?.apply(&mut model.clone(), &name)?;
    Ok((a, text))
}

/// Run `stride model adapt`.
pub fn run(args: AdaptArgs) -> anyhow::Result<()> {
    let (model, _) = import(&args.file)?;
    let out = args.out.unwrap_or_else(|| args.file.with_extension("toml"));
    if out == args.file {
        anyhow::bail!("--out {}: that is the model file", out.display());
    }
    if out.exists() && !args.force {
        anyhow::bail!(
            "{}: the file exists; pass --force to replace it, or --out another file",
            out.display()
        );
    }
    let (a, text) = adapted_text(&model, &args.file, &args.like)?;
    write_atomic(&out, text.as_bytes()).with_context(|| format!("writing {}", out.display()))?;
    let actuated: Vec<&str> = a
        .settings
        .actuators
        .iter()
        .map(|x| x.coordinate.as_str())
        .collect();
    println!(
        "wrote {}: {} contact spheres of {} (feet scaled by {:.4} right, {:.4} left), {} torque actuators{}, {} passive torque entries, {} metabolic entries, {} distance constraints",
        out.display(),
        a.spheres.len(),
        a.reference,
        a.feet[0].factor,
        a.feet[1].factor,
        actuated.len(),
        if actuated.is_empty() { String::new() } else { format!(" ({})", actuated.join(", ")) },
        a.settings.passive_torques.table.len(),
        a.metabolic_copied,
        a.settings.distances.len(),
    );
    Ok(())
}

/// The settings file of `--model path` adapted on the fly, when `path` is an `.osim` file
/// given without a settings file (`settings`), with none beside it, that cannot walk as
/// it is; read from the per-user cache (`cache_dir`) or written there. Says on stderr, in
/// one line, that the model was adapted and where the file is.
pub(crate) fn auto_settings(
    model: Option<&Path>,
    settings: Option<&Path>,
    cache_dir: Option<PathBuf>,
) -> anyhow::Result<Option<PathBuf>> {
    let Some(path) = model else {
        return Ok(None);
    };
    let is_osim = path
        .extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("osim"));
    if settings.is_some() || !is_osim || !path.is_file() || ModelSettings::beside(path).is_some() {
        return Ok(None);
    }
    let (m, bytes) = import(path)?;
    let why = reasons(&m);
    if why.is_empty() {
        return Ok(None);
    }
    let dir = cache_dir.context(
        "no cache folder for the adapted model settings (set XDG_CACHE_HOME or HOME, or run `stride model adapt` and pass --model-settings)",
    )?;
    let file = dir.join(format!(
        "adapted-v{RULE_VERSION}-{}-{DEFAULT_REFERENCE}.toml",
        content_hash(&bytes)
    ));
    if !file.is_file() {
        let (_, text) = adapted_text(&m, path, DEFAULT_REFERENCE)?;
        std::fs::create_dir_all(&dir)
            .with_context(|| format!("creating the cache folder {}", dir.display()))?;
        write_atomic(&file, text.as_bytes())
            .with_context(|| format!("writing {}", file.display()))?;
    }
    eprintln!(
        "adapted {} to walk ({}): its model settings are in {} (edit a copy and pass it with --model-settings)",
        path.display(),
        why.join("; "),
        file.display()
    );
    Ok(Some(file))
}

/// Copy the adapted settings file `adapted` into the result folder `out` as
/// [`RESULT_FILE`].
pub(crate) fn copy_into(adapted: &Path, out: &Path) -> anyhow::Result<()> {
    let bytes = std::fs::read(adapted).with_context(|| format!("reading {}", adapted.display()))?;
    let to = out.join(RESULT_FILE);
    write_atomic(&to, &bytes).with_context(|| format!("writing {}", to.display()))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// OpenSim's 2D test model (no contact spheres, no lumbar muscle), when present.
    fn gait10dof() -> Option<PathBuf> {
        let p = PathBuf::from(concat!(
            env!("CARGO_MANIFEST_DIR"),
            "/../../../shared/reference/models/opensim/gait10dof18musc.osim"
        ));
        if p.is_file() {
            Some(p)
        } else {
            eprintln!("skipped: {} is absent", p.display());
            None
        }
    }

    #[test]
    fn a_model_without_contact_is_adapted_once_and_cached_by_content() {
        let Some(src) = gait10dof() else { return };
        let dir = std::env::temp_dir().join(format!("stride-adapt-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        std::fs::create_dir_all(&dir).unwrap();
        let model = dir.join("walker.osim");
        std::fs::copy(&src, &model).unwrap();
        let cache = dir.join("cache");
        let first = auto_settings(Some(&model), None, Some(cache.clone()))
            .unwrap()
            .unwrap();
        assert!(first.starts_with(&cache));
        let text = std::fs::read_to_string(&first).unwrap();
        assert!(text.contains("coordinate = \"lumbar_extension\""), "{text}");
        assert_eq!(text.matches("[[contact.spheres]]").count(), 12);
        // the same content elsewhere: the same cached file
        let other = dir.join("other.osim");
        std::fs::copy(&src, &other).unwrap();
        let again = auto_settings(Some(&other), None, Some(cache.clone()))
            .unwrap()
            .unwrap();
        assert_eq!(again, first);
        // a settings file given or beside the model, or a shipped model: no adaptation
        let given = dir.join("given.toml");
        assert!(
            auto_settings(Some(&model), Some(&given), Some(cache.clone()))
                .unwrap()
                .is_none()
        );
        std::fs::write(dir.join("walker.toml"), "").unwrap();
        assert!(auto_settings(Some(&model), None, Some(cache.clone()))
            .unwrap()
            .is_none());
        assert!(
            auto_settings(Some(Path::new("gait1018")), None, Some(cache))
                .unwrap()
                .is_none()
        );
        std::fs::remove_dir_all(&dir).unwrap();
    }

    #[test]
    fn adapt_refuses_to_overwrite_and_names_the_file() {
        let Some(src) = gait10dof() else { return };
        let dir = std::env::temp_dir().join(format!("stride-adapt-out-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        std::fs::create_dir_all(&dir).unwrap();
        let out = dir.join("m.toml");
        std::fs::write(&out, "# mine\n").unwrap();
        let args = |force| AdaptArgs {
            file: src.clone(),
            like: DEFAULT_REFERENCE.into(),
            out: Some(out.clone()),
            force,
        };
        let e = run(args(false)).unwrap_err().to_string();
        assert!(e.contains("m.toml") && e.contains("--force"), "{e}");
        assert_eq!(std::fs::read_to_string(&out).unwrap(), "# mine\n");
        run(args(true)).unwrap();
        let back = ModelSettings::read(&out).unwrap();
        assert_eq!(back.contact.spheres.len(), 12);
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
