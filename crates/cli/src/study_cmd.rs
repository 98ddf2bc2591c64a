//! `stride study <file>`: run every case of a study file (parallel, resumable) and write
//! its report; `stride report <folder>`: analyse a study output folder again.

use crate::predict_cmd;
use anyhow::Context;
use clap::Args;
use std::path::{Path, PathBuf};
use stride_ocp::settings::RunSettings;
use stride_solve::solver::SolverOptions;
use stride_study::predict_runner::{
    check_cases, measures_from_solution, rewrite_case, PredictRunner, Rewritten,
};
use stride_study::report;
use stride_study::runner::{run_study, RunOptions};
use stride_study::spec;
use stride_study::store::{lock_study, Store};

/// Arguments of `stride study`.
#[derive(Args)]
pub struct StudyArgs {
    /// Study file (TOML) with `[study]`, `[base]` and `[grid]`.
    pub file: PathBuf,
    /// Output folder (overrides `[study] output`).
    #[arg(long)]
    pub out: Option<PathBuf>,
    /// Cases solved at the same time (overrides `[study] jobs`; not with --case or
    /// --slurm, whose tasks run one case at a time).
    #[arg(long, conflicts_with_all = ["case", "slurm"])]
    pub jobs: Option<usize>,
    /// Evaluation threads per case (overrides `[study] threads_per_case`).
    #[arg(long)]
    pub threads: Option<usize>,
    /// Iteration limit per case (overrides `[study.solver] max_iter`).
    #[arg(long)]
    pub max_iter: Option<usize>,
    /// Resume into a study folder made from a different study file.
    #[arg(long)]
    pub force: bool,
    /// Run failed cases again.
    #[arg(long)]
    pub retry_failed: bool,
    /// Run only the cases whose names match one of these comma-separated patterns
    /// (`*` any characters, `?` one), e.g. `'speed_2.*__dir,speed_1.33__*'`; the
    /// others stay as they are (finished, or not run until a later run).
    #[arg(long, value_delimiter = ',')]
    pub only: Vec<String>,
    /// Run only these cases (comma-separated names, or indices from 0 in the study's
    /// order), in this order, one at a time, alongside other runners of the same folder
    /// (cluster array tasks): each case is claimed before it runs, a finished or claimed
    /// case is skipped; no report is written (`stride report` does).
    #[arg(long, value_delimiter = ',', conflicts_with_all = ["only", "slurm", "status"])]
    pub case: Vec<String>,
    /// Show which cases are finished (converged, failed), running (a live claim, on any
    /// host) or missing, from the output folder alone, and exit.
    #[arg(long, conflicts_with_all = ["slurm", "dry_run"])]
    pub status: bool,
    /// Submission to a Slurm cluster.
    #[command(flatten)]
    pub slurm: crate::slurm::SlurmArgs,
    /// Only expand and validate: list the cases (those selected by `--only`) and exit;
    /// with --slurm, print the job scripts and `sbatch` lines instead of submitting.
    #[arg(long)]
    pub dry_run: bool,
    /// No progress output.
    #[arg(long)]
    pub quiet: bool,
    /// Do not write the viewer page (`view.html`, see `stride view`).
    #[arg(long)]
    pub no_view: bool,
}

/// Arguments of `stride report`.
#[derive(Args)]
pub struct ReportArgs {
    /// Output folder of a study.
    pub folder: PathBuf,
    /// First rewrite every finished case's result files (motion, tables, figures, outcomes)
    /// from its solution with this version's definitions; solver logs and times are kept.
    #[arg(long)]
    pub rewrite_cases: bool,
}

/// Run `stride study`.
pub fn run(args: StudyArgs) -> anyhow::Result<()> {
    let study = spec::load(&args.file)?;
    let h = &study.header;
    let s = &h.solver;
    // the command line's values are checked by the same rules as the study file's
    RunSettings {
        threads: args.threads,
        jobs: args.jobs,
        max_iter: args.max_iter,
        ..Default::default()
    }
    .validate()?;
    // the same names, defaults and checks as `stride predict`, errors prefixed by the section
    let section = || format!("{}: [study.solver]", args.file.display());
    let backend_name = s.backend.as_deref().unwrap_or("ipm");
    let solver = predict_cmd::backend(backend_name).with_context(section)?;
    let hessian =
        predict_cmd::parse_hessian(s.hessian.as_deref(), backend_name).with_context(section)?;
    let threads = args.threads.unwrap_or(h.threads_per_case);
    let options = SolverOptions {
        threads,
        ..predict_cmd::prediction_options(
            s.tol,
            args.max_iter.or(s.max_iter),
            hessian,
            s.time_limit,
            s.centrality_correctors,
        )
        .with_context(section)?
    };
    predict_cmd::check_correctors(&options, backend_name).with_context(section)?;
    let model = study_model(h.model.as_deref())?;
    let jobs = args.jobs.unwrap_or(h.jobs);
    if let Some(largest) = study.cases.iter().max_by_key(|c| {
        let full = c.settings.cycle != stride_ocp::settings::CycleKind::HalfSymmetric;
        (c.settings.mesh_intervals, full)
    }) {
        crate::limits::check_memory(&model, &largest.settings, jobs, "cases solved at once")
            .with_context(|| format!("{}: case `{}`", args.file.display(), largest.name))?;
    }
    check_cases(&model, &study.cases, s.presolve_mesh)
        .map_err(|e| anyhow::anyhow!("{}: {e}", args.file.display()))?;
    let out = args.out.clone().unwrap_or_else(|| h.output.clone());
    if args.status {
        return crate::status_cmd::print(&study, &out);
    }
    let only = if !args.case.is_empty() {
        Some(case_mask(&study, &args.case).with_context(|| args.file.display().to_string())?)
    } else if args.only.is_empty() {
        None
    } else {
        Some(
            spec::select_cases(&study.cases, &args.only)
                .map_err(|e| anyhow::anyhow!("{}: {e}", args.file.display()))?,
        )
    };
    if args.slurm.slurm {
        let selected = |i: usize| only.as_ref().is_none_or(|m| m[i]);
        let request = crate::slurm::Request {
            file: &args.file,
            threads: args.threads,
            max_iter: args.max_iter,
            force: args.force,
            retry_failed: args.retry_failed,
            dry_run: args.dry_run,
            slurm: &args.slurm,
        };
        return crate::slurm::run(&request, &study, &model, &out, &selected);
    }
    let selected = |i: usize| only.as_ref().is_none_or(|m| m[i]);
    if args.dry_run {
        for (i, c) in study.cases.iter().enumerate() {
            if selected(i) {
                println!("{}", c.name);
            }
        }
        let n = (0..study.cases.len()).filter(|&i| selected(i)).count();
        println!("{n} of {} cases", study.cases.len());
        return Ok(());
    }
    let single = !args.case.is_empty();
    let store = if single {
        Store::open_shared(&out, &study, args.force)?.with_job(&batch_job())
    } else {
        Store::open(&out, &study, args.force)?
    };
    let jobs = if single { 1 } else { jobs };
    if !args.quiet && !single {
        eprintln!(
            "study `{}`: {} cases, {jobs} at a time, {threads} solver thread(s) each, output {}",
            h.name,
            study.cases.len(),
            out.display()
        );
    }
    let runner = PredictRunner {
        model,
        solver,
        options,
        write_unconverged: h.continue_from_unconverged,
        presolve_mesh: s.presolve_mesh,
    };
    let summary = run_study(
        &study,
        &store,
        &runner,
        &RunOptions {
            jobs,
            progress: (!args.quiet).then_some(say as fn(&str)),
            retry_failed: args.retry_failed,
            only: only.clone(),
        },
    )?;
    if single {
        return finish_cases(&store, &study, &only.unwrap_or_default(), summary.elsewhere);
    }
    let recompute = |dir: &Path| measures_from_solution(&runner.model, dir);
    let report = report::report_folder_with(&out, Some(&recompute))?;
    let left_out = if summary.not_selected > 0 {
        format!(", {} not selected", summary.not_selected)
    } else {
        String::new()
    };
    println!(
        "{} cases: {} converged, {} failed ({} run now, {} already done{left_out}); index {}, report {}",
        study.cases.len(),
        summary.converged,
        summary.failed,
        summary.ran,
        summary.skipped,
        out.join("index.csv").display(),
        out.join("report.json").display()
    );
    print_series(&report);
    if !args.no_view && report.converged > 0 {
        crate::view_cmd::write_default(&out, &runner.model)?;
    }
    if summary.failed > 0 {
        // the study ran to the end and its report is written, but not every case converged:
        // exit 2 (as `stride predict` does for an unconverged solve) so scripts can tell
        eprintln!(
            "{} of {} cases failed (reasons in {})",
            summary.failed,
            study.cases.len(),
            out.join("index.csv").display()
        );
        std::process::exit(2);
    }
    Ok(())
}

fn print_series(report: &report::Report) {
    let finished = report.converged + report.failed;
    if finished > 0 {
        let mean = report.case_time_s / finished as f64;
        println!(
            "case wall time: {:.2} h over {finished} finished cases, {:.1} min per case, {:.1} cases per hour one at a time",
            report.case_time_s / 3600.0,
            mean / 60.0,
            3600.0 / mean
        );
    }
    // Studies without a speed axis: one line per condition against the reference.
    if let (true, Some(t)) = (report.speed_series.is_empty(), &report.conditions) {
        println!("conditions (change from the reference in parentheses):");
        for line in stride_study::conditions::conditions_text(t) {
            println!("  {line}");
        }
    }
    for s in &report.speed_series {
        let key: Vec<String> = s.key.iter().map(|(k, v)| format!("{k}={v}")).collect();
        println!(
            "speed series [{}]: {} speeds, transition {}",
            key.join(", "),
            s.points.len(),
            s.transition_speed
                .map(|t| format!("{t} m/s"))
                .unwrap_or_else(|| "none".into())
        );
        for (what, f) in [
            ("COT walking (quadratic)", &s.cot_walking_fit),
            ("COT running (linear)", &s.cot_running_fit),
            (
                "stride frequency walking (linear)",
                &s.stride_frequency_walking_fit,
            ),
        ] {
            if let Some(f) = f {
                println!("  {what}: {} over {} speeds", f.quality(3), f.n);
            }
        }
    }
}

/// The model of a study: its `model` (a shipped model's name, or an `.osim` file with
/// its settings file beside it and its fitted geometry), else the built-in model.
fn study_model(path: Option<&Path>) -> anyhow::Result<stride_model::Model> {
    crate::model_load::load_model(path, None, None, false).context("loading model")
}

/// Rewrite the result files of every finished case of a study folder from its solution;
/// an error names every case that could not be rewritten (those folders are unchanged).
fn rewrite_cases(
    model: &stride_model::Model,
    study: &spec::Study,
    folder: &Path,
) -> anyhow::Result<()> {
    let (mut done, mut skipped, mut failed) = (0, 0, Vec::new());
    for case in &study.cases {
        let dir = folder.join("cases").join(&case.name);
        if !dir.is_dir() {
            continue;
        }
        match rewrite_case(model, &dir) {
            Ok(Rewritten::Rewritten) => {
                done += 1;
                println!("rewrote {}", dir.display());
            }
            Ok(Rewritten::NoSolution) => skipped += 1,
            Err(e) => failed.push(format!("{}: {e}", case.name)),
        }
    }
    println!("{done} case folders rewritten, {skipped} without a kept solution left as they are");
    if !failed.is_empty() {
        anyhow::bail!(
            "{} case folders could not be rewritten (left unchanged):\n  {}",
            failed.len(),
            failed.join("\n  ")
        );
    }
    Ok(())
}

/// Run `stride report`.
pub fn report(args: ReportArgs) -> anyhow::Result<()> {
    // The condition measures are recomputed from the case solutions with the study's model.
    let study = spec::load(&args.folder.join("study.toml"))?;
    let model = study_model(study.header.model.as_deref())?;
    if args.rewrite_cases {
        // case folders are swapped: not while a study runs in the folder
        let _lock = lock_study(&args.folder)?;
        rewrite_cases(&model, &study, &args.folder)?;
    }
    let recompute = |dir: &Path| measures_from_solution(&model, dir);
    let report = report::report_folder_with(&args.folder, Some(&recompute))?;
    println!(
        "study `{}`: {} cases, {} converged, {} failed, {} not run; {} groups selected; report {}",
        report.study,
        report.cases,
        report.converged,
        report.failed,
        report.not_run,
        report.selected.len(),
        args.folder.join("report.json").display()
    );
    print_series(&report);
    Ok(())
}

/// The mask of the cases named by `--case` (names, or indices from 0).
fn case_mask(study: &spec::Study, names: &[String]) -> anyhow::Result<Vec<bool>> {
    let mut mask = vec![false; study.cases.len()];
    for n in names {
        let i = study
            .cases
            .iter()
            .position(|c| c.name == *n)
            .or_else(|| n.parse::<usize>().ok().filter(|&i| i < study.cases.len()))
            .ok_or_else(|| {
                anyhow::anyhow!(
                    "--case {n}: no case of this name, nor an index below {} (`stride study FILE --dry-run` lists them)",
                    study.cases.len()
                )
            })?;
        mask[i] = true;
    }
    Ok(mask)
}

/// The batch job this process runs in, as Slurm names it (`<array job>_<task>`, or the
/// job id), `-` outside a batch job: written into case claims.
fn batch_job() -> String {
    let var = |k: &str| std::env::var(k).ok().filter(|v| !v.is_empty());
    match (var("SLURM_ARRAY_JOB_ID"), var("SLURM_ARRAY_TASK_ID")) {
        (Some(j), Some(t)) => format!("{j}_{t}"),
        _ => var("SLURM_JOB_ID").unwrap_or_else(|| "-".into()),
    }
}

/// End of a `--case` run: one line per selected case; exit 2 when one of them failed, 3
/// when one was left to another runner.
fn finish_cases(
    store: &Store,
    study: &spec::Study,
    mask: &[bool],
    elsewhere: usize,
) -> anyhow::Result<()> {
    let mut failed = 0;
    for (c, _) in study.cases.iter().zip(mask).filter(|(_, &m)| m) {
        let state = match store.record(&c.name)? {
            Some(r) => {
                if r.status != stride_study::store::CaseStatus::Converged {
                    failed += 1;
                }
                format!("{} ({})", r.status.as_str(), r.reason)
            }
            None => "not run here".to_string(),
        };
        println!("{}: {state}", c.name);
    }
    if failed > 0 {
        std::process::exit(2);
    }
    if elsewhere > 0 {
        eprintln!("{elsewhere} case(s) left to other runners that hold them");
        std::process::exit(3);
    }
    Ok(())
}

/// Prints one progress line of a study run on stderr.
fn say(line: &str) {
    eprintln!("{line}");
}
