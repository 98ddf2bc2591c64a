//! `stride study FILE --slurm`: a study submitted to Slurm as job arrays over its output
//! folder on a shared file system. Each array task runs one case, or one continuation
//! chain, with `stride study FILE --case …`; the arrays follow each other (waves, see
//! [`stride_study::tasks`]) and a last job writes the report with `stride report`.

use anyhow::{bail, Context};
use clap::Args;
use std::path::{Path, PathBuf};
use std::process::Command;
use stride_study::spec::{SlurmSection, Study};
use stride_study::tasks::Task;

/// Slurm options of `stride study` (each overrides the study file's `[slurm]` key).
#[derive(Args, Clone, Debug, Default)]
pub struct SlurmArgs {
    /// Submit the study to Slurm as job arrays (one task per case or continuation chain)
    /// and a final report job; with --dry-run, print the job scripts and `sbatch` lines.
    #[arg(long)]
    pub slurm: bool,
    /// Slurm partition (default: the cluster's default partition).
    #[arg(long, requires = "slurm")]
    pub partition: Option<String>,
    /// Time limit per case, in Slurm's format (`minutes`, `HH:MM:SS`, `D-HH:MM`, …;
    /// default: twice the solver time limit plus 5 minutes).
    #[arg(long, requires = "slurm")]
    pub time: Option<String>,
    /// Memory per task (e.g. `4G`; default: the largest case's estimated peak × 1.5
    /// plus 512 MB).
    #[arg(long, requires = "slurm")]
    pub mem: Option<String>,
    /// CPUs per task, also the solver threads of each case (default: the study's
    /// `threads_per_case`).
    #[arg(long, requires = "slurm")]
    pub cpus_per_task: Option<usize>,
    /// Array tasks running at once (`--array=…%N`; default: no limit).
    #[arg(long, requires = "slurm")]
    pub throttle: Option<usize>,
    /// A further `sbatch` option, written into the job scripts (repeatable), e.g.
    /// `--sbatch-arg=--account=gait`.
    #[arg(long = "sbatch-arg", requires = "slurm", allow_hyphen_values = true)]
    pub sbatch_args: Vec<String>,
}

/// Checked submission settings.
#[derive(Clone, Debug, PartialEq)]
pub struct Settings {
    /// Partition, if not the cluster's default.
    pub partition: Option<String>,
    /// Time limit of one case [s].
    pub case_time_s: u64,
    /// Memory per task [MB].
    pub mem_mb: u64,
    /// CPUs per task.
    pub cpus: usize,
    /// Array tasks at once.
    pub throttle: Option<usize>,
    /// Further `sbatch` options.
    pub extra: Vec<String>,
}

/// Seconds of a Slurm time limit (`minutes`, `minutes:seconds`, `hours:minutes:seconds`,
/// `days-hours`, `days-hours:minutes`, `days-hours:minutes:seconds`).
pub fn parse_time(text: &str) -> anyhow::Result<u64> {
    let bad = || {
        anyhow::anyhow!(
            "time `{text}`: expected a positive Slurm time limit (`minutes`, `HH:MM:SS`, `D-HH:MM`, …)"
        )
    };
    let t = text.trim();
    let (days, rest) = match t.split_once('-') {
        Some((d, r)) => (Some(d), r),
        None => (None, t),
    };
    let num = |s: &str| -> anyhow::Result<u64> {
        if s.is_empty() || !s.bytes().all(|b| b.is_ascii_digit()) {
            return Err(bad());
        }
        s.parse().map_err(|_| bad())
    };
    let parts: Vec<u64> = rest.split(':').map(num).collect::<Result<_, _>>()?;
    let secs = match (days, parts.as_slice()) {
        (None, [m]) => m * 60,
        (None, [m, s]) => m * 60 + s,
        (None, [h, m, s]) => h * 3600 + m * 60 + s,
        (Some(d), [h]) => num(d)? * 86400 + h * 3600,
        (Some(d), [h, m]) => num(d)? * 86400 + h * 3600 + m * 60,
        (Some(d), [h, m, s]) => num(d)? * 86400 + h * 3600 + m * 60 + s,
        _ => return Err(bad()),
    };
    if secs == 0 {
        return Err(bad());
    }
    Ok(secs)
}

/// Slurm's `D-HH:MM:SS` for `secs`.
pub fn format_time(secs: u64) -> String {
    let (d, r) = (secs / 86400, secs % 86400);
    format!("{d}-{:02}:{:02}:{:02}", r / 3600, (r % 3600) / 60, r % 60)
}

/// Megabytes of a Slurm memory size (`4096`, `4096M`, `4G`, `1T`; no unit: MB).
pub fn parse_mem(text: &str) -> anyhow::Result<u64> {
    let bad = || anyhow::anyhow!("mem `{text}`: expected a positive size such as `4G` or `4096M`");
    let t = text.trim();
    let (digits, scale) = match t.char_indices().last() {
        Some((i, c)) if c.is_ascii_alphabetic() => {
            let scale = match c.to_ascii_uppercase() {
                'K' => 1.0 / 1024.0,
                'M' => 1.0,
                'G' => 1024.0,
                'T' => 1024.0 * 1024.0,
                _ => return Err(bad()),
            };
            (&t[..i], scale)
        }
        _ => (t, 1.0),
    };
    if digits.is_empty() || !digits.bytes().all(|b| b.is_ascii_digit()) {
        return Err(bad());
    }
    let mb = (digits.parse::<f64>().map_err(|_| bad())? * scale).ceil() as u64;
    if mb == 0 {
        return Err(bad());
    }
    Ok(mb)
}

/// The submission settings: command line over `[slurm]` over defaults (`default_time_s`
/// per case, `default_mem_mb`, `default_cpus`); every value checked, the partition against
/// `sinfo`'s list when `sinfo` answers. Errors name the setting and, for the study file's
/// values, the file.
pub fn settings(
    args: &SlurmArgs,
    file: &SlurmSection,
    study_file: &Path,
    defaults: (u64, u64, usize),
) -> anyhow::Result<Settings> {
    let in_file = || format!("{}: [slurm]", study_file.display());
    let case_time_s = match (&args.time, &file.time) {
        (Some(t), _) => parse_time(t).context("--time")?,
        (None, Some(t)) => parse_time(t).with_context(in_file)?,
        (None, None) => defaults.0,
    };
    let mem_mb = match (&args.mem, &file.mem) {
        (Some(m), _) => parse_mem(m).context("--mem")?,
        (None, Some(m)) => parse_mem(m).with_context(in_file)?,
        (None, None) => defaults.1,
    };
    let cpus = args
        .cpus_per_task
        .or(file.cpus_per_task)
        .unwrap_or(defaults.2);
    if cpus == 0 {
        bail!("cpus_per_task = 0: must be at least 1");
    }
    let throttle = args.throttle.or(file.throttle);
    if throttle == Some(0) {
        bail!("throttle = 0: must be at least 1 (array tasks at once)");
    }
    let partition = args.partition.clone().or_else(|| file.partition.clone());
    if let Some(p) = &partition {
        if let Some(known) = known_partitions() {
            if !known.iter().any(|k| k == p) {
                bail!(
                    "partition `{p}` is not one of this cluster's partitions ({}, from sinfo)",
                    known.join(", ")
                );
            }
        }
    }
    let mut extra = file.extra_args.clone();
    extra.extend(args.sbatch_args.iter().cloned());
    if let Some(e) = extra.iter().find(|e| !e.starts_with('-')) {
        bail!("sbatch argument `{e}`: expected an option starting with `-`");
    }
    Ok(Settings {
        partition,
        case_time_s,
        mem_mb,
        cpus,
        throttle,
        extra,
    })
}

/// The cluster's partitions (`sinfo`), or `None` when `sinfo` cannot tell.
fn known_partitions() -> Option<Vec<String>> {
    let out = Command::new("sinfo")
        .args(["-h", "-o", "%R"])
        .output()
        .ok()?;
    if !out.status.success() {
        return None;
    }
    let list: Vec<String> = String::from_utf8_lossy(&out.stdout)
        .lines()
        .map(|l| l.trim().to_string())
        .filter(|l| !l.is_empty())
        .collect();
    (!list.is_empty()).then_some(list)
}

/// A word quoted for the shell (single quotes).
fn sh(word: &str) -> String {
    format!("'{}'", word.replace('\'', r"'\''"))
}

/// What the job scripts run and where they write.
pub struct Job<'a> {
    /// The study.
    pub study: &'a Study,
    /// The `stride` program (absolute path).
    pub program: PathBuf,
    /// The study file (absolute path).
    pub file: PathBuf,
    /// The output folder (absolute path, on the shared file system).
    pub out: PathBuf,
    /// Pass `--retry-failed` to the tasks.
    pub retry_failed: bool,
    /// Checked settings.
    pub settings: Settings,
}

impl Job<'_> {
    fn header(&self, name: &str, time_s: u64, log: &str) -> String {
        let s = &self.settings;
        let mut t = String::from("#!/bin/bash\n");
        t += &format!("#SBATCH --job-name={name}\n");
        t += &format!("#SBATCH --time={}\n", format_time(time_s));
        t += &format!("#SBATCH --mem={}M\n", s.mem_mb);
        t += &format!("#SBATCH --cpus-per-task={}\n", s.cpus);
        if let Some(p) = &s.partition {
            t += &format!("#SBATCH --partition={p}\n");
        }
        t += &format!(
            "#SBATCH --output={}\n",
            self.out.join("slurm").join(log).display()
        );
        for e in &s.extra {
            t += &format!("#SBATCH {e}\n");
        }
        t
    }

    fn name(&self) -> String {
        let n: String = (self.study.header.name.chars())
            .map(|c| {
                if c.is_ascii_alphanumeric() || c == '-' || c == '_' {
                    c
                } else {
                    '_'
                }
            })
            .collect();
        format!("stride-{n}")
    }

    /// The job script of one wave of tasks: a Slurm array, one task per element.
    pub fn wave_script(&self, wave: usize, tasks: &[Task]) -> String {
        let longest = tasks.iter().map(Vec::len).max().unwrap_or(1) as u64;
        let mut t = self.header(
            &format!("{}-{wave}", self.name()),
            self.settings.case_time_s * longest,
            "%x-%A_%a.out",
        );
        let throttle = self
            .settings
            .throttle
            .map(|n| format!("%{n}"))
            .unwrap_or_default();
        t += &format!("#SBATCH --array=0-{}{throttle}\n", tasks.len() - 1);
        t += "# Each array task runs one case, or one continuation chain in order, into the\n";
        t += "# study folder; a finished case is skipped, so resubmitting runs only what is missing.\n";
        t += "set -eu\ntasks=(\n";
        for task in tasks {
            let names: Vec<&str> = task
                .iter()
                .map(|&i| self.study.cases[i].name.as_str())
                .collect();
            t += &format!("  {}\n", sh(&names.join(",")));
        }
        t += ")\n";
        t += &format!(
            "exec {} study {} --out {} --threads {}{} --case \"${{tasks[$SLURM_ARRAY_TASK_ID]}}\"\n",
            sh(&self.program.display().to_string()),
            sh(&self.file.display().to_string()),
            sh(&self.out.display().to_string()),
            self.settings.cpus,
            if self.retry_failed { " --retry-failed" } else { "" }
        );
        t
    }

    /// The job script of the final report (`stride report`).
    pub fn report_script(&self) -> String {
        let mut t = self.header(&format!("{}-report", self.name()), 1800, "%x-%j.out");
        t += &format!(
            "exec {} report {}\n",
            sh(&self.program.display().to_string()),
            sh(&self.out.display().to_string())
        );
        t
    }
}

/// Folder of the job scripts and logs inside a study folder.
pub fn scripts_dir(out: &Path) -> PathBuf {
    out.join("slurm")
}

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

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn slurm_times_and_sizes_parse_and_bad_ones_are_refused() {
        assert_eq!(parse_time("90").unwrap(), 5400);
        assert_eq!(parse_time("1:30").unwrap(), 90);
        assert_eq!(parse_time("02:00:00").unwrap(), 7200);
        assert_eq!(parse_time("1-2").unwrap(), 93600);
        assert_eq!(parse_time("1-00:30:00").unwrap(), 88200);
        for bad in ["-5", "0", "", "1h", "1:2:3:4", "-1-2", "a-1"] {
            let e = parse_time(bad).unwrap_err().to_string();
            assert!(e.contains(&format!("time `{bad}`")), "{e}");
        }
        assert_eq!(format_time(93600 + 61), "1-02:01:01");
        assert_eq!(parse_mem("4G").unwrap(), 4096);
        assert_eq!(parse_mem("1500").unwrap(), 1500);
        assert_eq!(parse_mem("2048k").unwrap(), 2);
        for bad in ["0", "-4G", "4X", "G", "1.5G"] {
            assert!(parse_mem(bad).is_err(), "{bad}");
        }
        assert_eq!(sh("it's"), r"'it'\''s'");
    }
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

/// `stride study FILE --slurm [--dry-run]`: plan the waves of the unfinished selected
/// cases, write the job scripts into `<out>/slurm/` and submit them (or print them).
pub fn run(
    args: &crate::study_cmd::StudyArgs,
    study: &Study,
    model: &stride_model::Model,
    out: &Path,
    selected: &dyn Fn(usize) -> bool,
) -> anyhow::Result<()> {
    let cpus = args.threads.unwrap_or(study.header.threads_per_case);
    let defaults = (default_case_time(study), default_mem(study, model)?, cpus);
    let settings = settings(&args.slurm, &study.slurm, &args.file, defaults)?;
    let absolute = |p: &Path| -> anyhow::Result<PathBuf> {
        Ok(if p.is_absolute() {
            p.to_path_buf()
        } else {
            std::env::current_dir()?.join(p)
        })
    };
    let job = Job {
        study,
        program: std::env::current_exe().context("locating the stride program")?,
        file: absolute(&args.file)?,
        out: absolute(out)?,
        retry_failed: args.retry_failed,
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
        stride_model::storage::write_atomic(path, text.as_bytes())
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
