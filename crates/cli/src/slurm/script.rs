//! The job scripts of `stride study --slurm`: one Slurm array per wave of tasks and the
//! final report job.

use super::settings::{format_time, Settings};
use super::words::sbatch_word;
use std::path::{Path, PathBuf};
use stride_study::spec::Study;
use stride_study::tasks::Task;

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
    /// Iteration limit per case passed to the tasks (`--max-iter`).
    pub max_iter: Option<usize>,
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
            t += &format!("#SBATCH {}\n", sbatch_word(&format!("--partition={p}")));
        }
        let output = self.out.join("slurm").join(log);
        let output = format!("--output={}", output.display());
        t += &format!("#SBATCH {}\n", sbatch_word(&output));
        for e in &s.extra {
            t += &format!("#SBATCH {}\n", sbatch_word(e));
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
            self.task_options()
        );
        t
    }

    /// The options of `stride study` that the tasks get from the submitting command.
    fn task_options(&self) -> String {
        let mut o = String::new();
        if self.retry_failed {
            o += " --retry-failed";
        }
        if let Some(n) = self.max_iter {
            o += &format!(" --max-iter {n}");
        }
        o
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

#[cfg(test)]
mod tests {
    #[test]
    fn words_are_quoted_for_the_shell() {
        assert_eq!(super::sh("it's"), r"'it'\''s'");
    }
}
