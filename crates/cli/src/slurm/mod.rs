//! `stride study FILE --slurm`: a study submitted to Slurm as job arrays over its output
//! folder on a shared file system. Each array task runs one case, or one continuation
//! chain, with `stride study FILE --case …`; the arrays follow each other (waves, see
//! [`stride_study::tasks`]) and a last job writes the report with `stride report`.

mod script;
mod settings;
mod words;

pub use settings::SlurmArgs;

use anyhow::{bail, Context};
use script::{scripts_dir, Job};
use std::path::{Path, PathBuf};
use std::process::Command;
use stride_study::spec::Study;

/// The `sbatch` command line of a script, after the jobs `after` (ids or shell variables).
pub fn sbatch_line(script: &Path, after: &[String]) -> Vec<String> {
    let mut v = vec!["sbatch".to_string(), "--parsable".to_string()];
    if !after.is_empty() {
        v.push(format!("--dependency=afterany:{}", after.join(":")));
    }
    v.push(script.display().to_string());
    v
}

/// Run an `sbatch` command line; the job id it prints.
pub fn submit(line: &[String]) -> anyhow::Result<String> {
    let out = Command::new(&line[0])
        .args(&line[1..])
        .output()
        .with_context(|| format!("running `{}` (is Slurm installed here?)", line.join(" ")))?;
    if !out.status.success() {
        bail!(
            "`{}` failed: {}",
            line.join(" "),
            String::from_utf8_lossy(&out.stderr).trim()
        );
    }
    let text = String::from_utf8_lossy(&out.stdout);
    let id = text.trim().split(';').next().unwrap_or("").to_string();
    if id.is_empty() || !id.bytes().all(|b| b.is_ascii_digit()) {
        bail!("`{}` printed no job id: {}", line.join(" "), text.trim());
    }
    Ok(id)
}

/// Default time limit of one case [s]: the presolve and the solve, each up to the solver
/// time limit, plus 5 minutes for loading and writing.
fn default_case_time(study: &Study) -> u64 {
    let limit = study
        .header
        .solver
        .time_limit
        .unwrap_or(crate::predict_cmd::DEFAULT_TIME_LIMIT_S);
    (2.0 * limit).ceil() as u64 + 300
}

/// Default memory per task [MB]: the largest case's estimated peak × 1.5 plus 512 MB.
fn default_mem(study: &Study, model: &stride_model::Model) -> anyhow::Result<u64> {
    let mut peak: f64 = 0.0;
    for c in &study.cases {
        peak = peak.max(stride_ocp::size::estimate(model, &c.settings)?.peak_bytes);
    }
    Ok((peak * 1.5 / 1048576.0).ceil() as u64 + 512)
}

/// What `stride study FILE --slurm` was asked on the command line.
pub struct Request<'a> {
    /// The study file as given.
    pub file: &'a Path,
    /// Evaluation threads per case (`--threads`).
    pub threads: Option<usize>,
    /// Iteration limit per case (`--max-iter`).
    pub max_iter: Option<usize>,
    /// Resume into a folder made from a different study file (`--force`).
    pub force: bool,
    /// Submit failed cases again (`--retry-failed`).
    pub retry_failed: bool,
    /// Print the job scripts instead of submitting them (`--dry-run`).
    pub dry_run: bool,
    /// The Slurm options.
    pub slurm: &'a SlurmArgs,
}

/// `stride study FILE --slurm [--dry-run]`: plan the waves of the unfinished selected
/// cases, write the job scripts into `<out>/slurm/` and submit them (or print them).
pub fn run(
    args: &Request,
    study: &Study,
    model: &stride_model::Model,
    out: &Path,
    selected: &dyn Fn(usize) -> bool,
) -> anyhow::Result<()> {
    let cpus = args.threads.unwrap_or(study.header.threads_per_case);
    let defaults = (default_case_time(study), default_mem(study, model)?, cpus);
    let settings = settings::settings(args.slurm, &study.slurm, args.file, defaults)?;
    let absolute = |p: &Path| -> anyhow::Result<PathBuf> {
        Ok(if p.is_absolute() {
            p.to_path_buf()
        } else {
            std::env::current_dir()?.join(p)
        })
    };
    let program = std::env::current_exe().context("locating the stride program")?;
    let (file, out) = (absolute(args.file)?, absolute(out)?);
    for (what, p) in [
        ("stride program", &program),
        ("study file", &file),
        ("output folder", &out),
    ] {
        words::check_no_control(what, &p.display().to_string())?;
    }
    let job = Job {
        study,
        program,
        file,
        out,
        retry_failed: args.retry_failed,
        max_iter: args.max_iter,
        settings,
    };
    let store = (!args.dry_run)
        .then(|| stride_study::store::Store::open(&job.out, study, args.force))
        .transpose()?;
    // finished cases are not submitted again (failed ones only with --retry-failed)
    let view = stride_study::store::Store::at(&job.out);
    let mut todo = vec![false; study.cases.len()];
    for (i, c) in study.cases.iter().enumerate() {
        let record = view.record(&c.name).ok().flatten();
        todo[i] = selected(i)
            && record.is_none_or(|r| {
                args.retry_failed && r.status != stride_study::store::CaseStatus::Converged
            });
    }
    drop(store);
    let waves = stride_study::tasks::plan(&study.cases, &|i| todo[i]);
    let n_tasks: usize = waves.iter().map(Vec::len).sum();
    if n_tasks == 0 {
        println!(
            "every selected case of {} is finished: nothing to submit",
            job.out.display()
        );
        return Ok(());
    }
    let dir = scripts_dir(&job.out);
    let mut scripts: Vec<(PathBuf, String)> = waves
        .iter()
        .enumerate()
        .map(|(w, tasks)| (dir.join(format!("wave{w}.sh")), job.wave_script(w, tasks)))
        .collect();
    scripts.push((dir.join("report.sh"), job.report_script()));
    let n_cases = todo.iter().filter(|&&t| t).count();
    if args.dry_run {
        for (path, text) in &scripts {
            println!("# {}\n{text}", path.display());
        }
        let mut vars: Vec<String> = Vec::new();
        for (w, (path, _)) in scripts.iter().enumerate() {
            println!("J{w}=$({})", sbatch_line(path, &vars).join(" "));
            vars.push(format!("$J{w}"));
        }
        println!(
            "{n_cases} cases in {n_tasks} tasks, {} array job(s) and a report job (dry run: nothing submitted)",
            waves.len()
        );
        return Ok(());
    }
    std::fs::create_dir_all(&dir).with_context(|| dir.display().to_string())?;
    for (path, text) in &scripts {
        stride_files::write_atomic(path, text.as_bytes())
            .with_context(|| path.display().to_string())?;
    }
    let mut ids: Vec<String> = Vec::new();
    for (path, _) in &scripts {
        let line = sbatch_line(path, &ids);
        let id = submit(&line).with_context(|| {
            if ids.is_empty() {
                "nothing was submitted".to_string()
            } else {
                format!("jobs {} were submitted (scancel them)", ids.join(", "))
            }
        })?;
        println!("{}  -> job {id}", line.join(" "));
        ids.push(id);
    }
    println!(
        "{n_cases} cases in {n_tasks} tasks submitted ({} array job(s), report job {}); `stride study {} --status` shows progress",
        waves.len(),
        ids.last().map(String::as_str).unwrap_or(""),
        args.file.display()
    );
    Ok(())
}
