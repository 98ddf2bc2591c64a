//! `stride-fuzz`: coverage-guided fuzzing of stride's input readers (see `fuzz/README.md`).
//!
//! `stride-fuzz run <target> [--seconds S] [--seed N] [--seeds PATH]...` supervises a
//! worker process: an input that aborts the worker (stack overflow, failed allocation) is
//! saved to `fuzz/crashes/<target>/` and the worker restarts for the remaining time.
//! `stride-fuzz check <target> PATH...` runs files once (regressions); `stride-fuzz
//! minimize <target>` keeps only the corpus files that add coverage.

use std::path::PathBuf;
use std::process::Command;
use std::time::Instant;
use stride_fuzz::engine::{check, fuzz, minimize, Config};
use stride_fuzz::targets::Target;

/// The fuzz folder (corpus, crashes) of this source tree.
fn fuzz_dir() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

struct Args {
    mode: String,
    target: Target,
    seconds: f64,
    seed: u64,
    seeds: Vec<PathBuf>,
    paths: Vec<PathBuf>,
}

fn parse_args() -> Result<Args, String> {
    let mut it = std::env::args().skip(1);
    let mode = it
        .next()
        .ok_or("usage: stride-fuzz run|check <target> ...")?;
    let name = it
        .next()
        .ok_or("missing target (osim, storage, study, model_settings, geometry)")?;
    let target = Target::from_name(&name).ok_or(format!(
        "unknown target `{name}` (osim, storage, study, model_settings, geometry)"
    ))?;
    let mut a = Args {
        mode,
        target,
        seconds: 60.0,
        seed: 1,
        seeds: Vec::new(),
        paths: Vec::new(),
    };
    while let Some(k) = it.next() {
        let mut value = || it.next().ok_or(format!("{k} needs a value"));
        match k.as_str() {
            "--seconds" => a.seconds = value()?.parse().map_err(|e| format!("--seconds: {e}"))?,
            "--seed" => a.seed = value()?.parse().map_err(|e| format!("--seed: {e}"))?,
            "--seeds" => a.seeds.push(PathBuf::from(value()?)),
            _ => a.paths.push(PathBuf::from(k)),
        }
    }
    Ok(a)
}

fn config(a: &Args) -> Config {
    let name = a.target.name();
    Config {
        target: a.target,
        corpus_dir: fuzz_dir().join("corpus").join(name),
        seeds: a.seeds.clone(),
        crash_dir: fuzz_dir().join("crashes").join(name),
        current: std::env::temp_dir().join(format!("stride-fuzz-{name}-{}.cur", a.seed)),
        seconds: a.seconds,
        seed: a.seed,
        max_len: 4 << 20,
        save_limit: 4 << 10,
    }
}

/// Run workers until the time is up, keeping the input of every worker that died.
fn supervise(a: &Args) -> Result<(), String> {
    let cfg = config(a);
    let start = Instant::now();
    let mut round = 0u64;
    loop {
        let left = a.seconds - start.elapsed().as_secs_f64();
        if left <= 0.5 {
            return Ok(());
        }
        let exe = std::env::current_exe().map_err(|e| e.to_string())?;
        let mut cmd = Command::new(exe);
        cmd.args([
            "worker",
            a.target.name(),
            "--seconds",
            &format!("{left:.1}"),
        ])
        .args(["--seed", &(a.seed + round).to_string()]);
        for s in &a.seeds {
            cmd.arg("--seeds").arg(s);
        }
        let status = cmd.status().map_err(|e| e.to_string())?;
        if status.success() {
            return Ok(());
        }
        let data = std::fs::read(&cfg.current).unwrap_or_default();
        std::fs::create_dir_all(&cfg.crash_dir).map_err(|e| e.to_string())?;
        let p = cfg.crash_dir.join(format!("abort-{}-{}", a.seed, round));
        std::fs::write(&p, data).map_err(|e| e.to_string())?;
        eprintln!("worker died ({status}); its input saved as {}", p.display());
        round += 1;
    }
}

fn main() {
    let result = parse_args().and_then(|a| match a.mode.as_str() {
        "run" => supervise(&a),
        "worker" => {
            let t = Instant::now();
            let stats = fuzz(config(&a));
            println!(
                "{}: {stats} in {:.0} s ({:.0} execs/s)",
                a.target.name(),
                t.elapsed().as_secs_f64(),
                stats.execs as f64 / t.elapsed().as_secs_f64()
            );
            Ok(())
        }
        "check" => {
            let failed = check(a.target, &a.paths);
            for (p, m) in &failed {
                eprintln!("{}: panicked: {m}", p.display());
            }
            if failed.is_empty() {
                Ok(())
            } else {
                Err(format!("{} inputs panicked", failed.len()))
            }
        }
        "minimize" => minimize(a.target, &config(&a).corpus_dir).map(|(kept, removed)| {
            println!(
                "{}: kept {kept} corpus files, removed {removed}",
                a.target.name()
            );
        }),
        other => Err(format!("unknown mode `{other}` (run, check, minimize)")),
    });
    if let Err(e) = result {
        eprintln!("error: {e}");
        std::process::exit(1);
    }
}
