//! Submission settings of `stride study --slurm`: command-line options over the study
//! file's `[slurm]` table over defaults, each checked before anything is submitted.

use anyhow::{bail, Context};
use clap::Args;
use std::path::Path;
use std::process::Command;
use stride_study::spec::SlurmSection;

use super::words::{check_name, check_sbatch_arg, parse_mem, parse_time};

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
    /// A further `sbatch` option, one argument written `--name=value` into the job
    /// scripts (repeatable), e.g. `--sbatch-arg=--account=gait`.
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

/// Slurm's `D-HH:MM:SS` for `secs`.
pub fn format_time(secs: u64) -> String {
    let (d, r) = (secs / 86400, secs % 86400);
    format!("{d}-{:02}:{:02}:{:02}", r / 3600, (r % 3600) / 60, r % 60)
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
        let checked = check_name("partition", p, true);
        if args.partition.is_some() {
            checked.context("--partition")?;
        } else {
            checked.with_context(in_file)?;
        }
        if let Some(known) = known_partitions() {
            if !known.iter().any(|k| k == p) {
                bail!(
                    "partition `{p}` is not one of this cluster's partitions ({}, from sinfo)",
                    known.join(", ")
                );
            }
        }
    }
    for a in &file.extra_args {
        check_sbatch_arg(a).with_context(|| format!("{}.extra_args", in_file()))?;
    }
    for a in &args.sbatch_args {
        check_sbatch_arg(a).context("--sbatch-arg")?;
    }
    let mut extra = file.extra_args.clone();
    extra.extend(args.sbatch_args.iter().cloned());
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
    }
}
