//! Running a study: cases in parallel (dependencies first), resumable, each failure
//! recorded without stopping the others, `index.csv` rewritten after every case. Each case
//! is claimed before it runs ([`Store::claim`]): a case claimed by another live runner (an
//! array task on another node) is left to it, together with the cases that wait for it.

use crate::spec::{varying_axes, Case, Study};
use crate::store::{CaseOutcome, CaseRecord, CaseStatus, Store, StoreError};
use std::path::Path;
use std::sync::{Condvar, Mutex};
use std::time::{Duration, Instant};

/// Solves one case; the real runner calls `predict`, tests use fakes.
pub trait CaseRunner: Sync {
    /// Solve `case`, writing its result files into `dir` (a fresh temporary folder);
    /// `source` is the finished folder of the case whose solution seeds a continuation
    /// guess; `progress` is told the solver's iteration count as it advances. An `Err` is a
    /// failure reason (the study goes on).
    fn run(
        &self,
        case: &Case,
        source: Option<&Path>,
        dir: &Path,
        progress: &(dyn Fn(usize) + Sync),
    ) -> Result<CaseOutcome, String>;
}

/// How to run a study.
#[derive(Clone, Debug)]
pub struct RunOptions {
    /// Cases solved at the same time.
    pub jobs: usize,
    /// Receives the progress lines (one per finished case with the counts and an estimate
    /// of the time left, and every minute the running cases); `None`: no progress.
    pub progress: Option<fn(&str)>,
    /// Run failed cases again (converged ones are always kept).
    pub retry_failed: bool,
    /// Run only these cases (a mask over the study's cases; `None`: all). The others are
    /// left as they are: finished ones are kept, unfinished ones stay not run.
    pub only: Option<Vec<bool>>,
}

/// Counts at the end of a run.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct RunSummary {
    /// Cases converged (this run or before).
    pub converged: usize,
    /// Cases failed.
    pub failed: usize,
    /// Cases already finished before this run (skipped).
    pub skipped: usize,
    /// Cases run now.
    pub ran: usize,
    /// Unfinished cases left out by the selection (`RunOptions::only`).
    pub not_selected: usize,
    /// Cases left to another live runner that had claimed them (with the cases waiting for
    /// them).
    pub elsewhere: usize,
}

#[derive(Clone, Copy, PartialEq, Eq)]
enum State {
    Pending,
    Running,
    Done,
    /// Unfinished and not selected: not run now.
    Excluded,
    /// Claimed by another runner, or waiting for such a case: not run here.
    Elsewhere,
}

struct Shared {
    state: Vec<State>,
    records: Vec<Option<CaseRecord>>,
    running: usize,
    ran: usize,
    /// Cases found finished by another runner when claimed.
    adopted: usize,
    time_spent: Duration,
    error: Option<StoreError>,
    /// Start time of each case in flight.
    started: Vec<Option<Instant>>,
    /// Latest solver iteration of each case in flight.
    iterations: Vec<usize>,
    /// Set when every worker has stopped.
    finished: bool,
    /// Longest chain of waiting cases that each case starts ([`chain_lengths`]).
    chain: Vec<usize>,
}

fn panic_text(p: Box<dyn std::any::Any + Send>) -> String {
    if let Some(s) = p.downcast_ref::<&str>() {
        s.to_string()
    } else if let Some(s) = p.downcast_ref::<String>() {
        s.clone()
    } else {
        "unknown panic".into()
    }
}

fn format_duration(d: Duration) -> String {
    let s = d.as_secs();
    if s >= 3600 {
        format!("{}h{:02}m", s / 3600, (s % 3600) / 60)
    } else if s >= 60 {
        format!("{}m{:02}s", s / 60, s % 60)
    } else {
        format!("{s}s")
    }
}

/// Run every unfinished case of `study` into `store` with `runner`.
pub fn run_study(
    study: &Study,
    store: &Store,
    runner: &dyn CaseRunner,
    opts: &RunOptions,
) -> Result<RunSummary, StoreError> {
    let cases = &study.cases;
    let axes = varying_axes(cases);
    let mut records: Vec<Option<CaseRecord>> = cases
        .iter()
        .map(|c| store.record(&c.name))
        .collect::<Result<_, _>>()?;
    if opts.retry_failed {
        for r in &mut records {
            if r.as_ref()
                .is_some_and(|r| r.status != CaseStatus::Converged)
            {
                *r = None;
            }
        }
    }
    let skipped = records.iter().filter(|r| r.is_some()).count();
    let state: Vec<State> = records
        .iter()
        .enumerate()
        .map(|(i, r)| {
            if r.is_some() {
                State::Done
            } else if opts.only.as_ref().is_some_and(|m| !m[i]) {
                State::Excluded
            } else {
                State::Pending
            }
        })
        .collect();
    // A selected case must not wait for a case that will not run.
    for (i, c) in cases.iter().enumerate() {
        if state[i] != State::Pending {
            continue;
        }
        if let Some(&s) = c.sources.iter().find(|&&s| state[s] == State::Excluded) {
            return Err(StoreError::Selection(format!(
                "case `{}` continues from `{}`, which is not finished and not selected",
                c.name, cases[s].name
            )));
        }
    }
    let not_selected = state.iter().filter(|&&s| s == State::Excluded).count();
    store.write_index(cases, &records, &axes)?;
    let shared = Mutex::new(Shared {
        state,
        records,
        running: 0,
        started: vec![None; cases.len()],
        iterations: vec![0; cases.len()],
        finished: false,
        ran: 0,
        adopted: 0,
        time_spent: Duration::ZERO,
        error: None,
        chain: chain_lengths(cases),
    });
    let wake = Condvar::new();
    let jobs = opts.jobs.max(1);
    std::thread::scope(|scope| {
        let workers: Vec<_> = (0..jobs)
            .map(|_| scope.spawn(|| worker(study, store, runner, opts, &axes, &shared, &wake)))
            .collect();
        if let Some(say) = opts.progress {
            let (shared, wake) = (&shared, &wake);
            scope.spawn(move || heartbeat(cases, shared, wake, say));
        }
        for w in workers {
            let _ = w.join();
        }
        shared.lock().unwrap_or_else(|e| e.into_inner()).finished = true;
        wake.notify_all();
    });
    let sh = shared.into_inner().unwrap_or_else(|e| e.into_inner());
    if let Some(e) = sh.error {
        return Err(e);
    }
    let count = |s: CaseStatus| {
        sh.records
            .iter()
            .filter(|r| r.as_ref().is_some_and(|r| r.status == s))
            .count()
    };
    Ok(RunSummary {
        converged: count(CaseStatus::Converged),
        failed: count(CaseStatus::Failed),
        skipped: skipped + sh.adopted,
        ran: sh.ran,
        not_selected,
        elsewhere: sh.state.iter().filter(|&&s| s == State::Elsewhere).count(),
    })
}

/// Length of the longest continuation chain that starts at each case (the case and the
/// cases that wait for it, transitively; 1 for a case nothing waits for). Sources come
/// before their dependants in the case list.
pub fn chain_lengths(cases: &[Case]) -> Vec<usize> {
    let mut len = vec![1usize; cases.len()];
    for j in (0..cases.len()).rev() {
        for &s in &cases[j].sources {
            len[s] = len[s].max(len[j] + 1);
        }
    }
    len
}

/// Pick the next case whose sources are all finished: the one that starts the longest
/// chain of waiting cases (so that a continuation chain, which runs one case at a time,
/// does not end up alone at the end of the study), the first in the list among equals.
fn next_ready(sh: &Shared, cases: &[Case]) -> Option<usize> {
    (0..cases.len())
        .filter(|&i| {
            sh.state[i] == State::Pending
                && cases[i].sources.iter().all(|&s| sh.state[s] == State::Done)
        })
        .min_by_key(|&i| (std::cmp::Reverse(sh.chain[i]), i))
}

/// Runs case `i` of `cases` into its staging folder `tmp`, from the folder of its source
/// case when it continues one, counting its iterations in `shared`; a panic of the runner
/// becomes the case's error.
fn run_case(
    cases: &[Case],
    i: usize,
    source: Option<usize>,
    store: &Store,
    runner: &dyn CaseRunner,
    shared: &Mutex<Shared>,
    tmp: &Path,
) -> Result<CaseOutcome, String> {
    let case = &cases[i];
    if case.guess.is_continuation() && source.is_none() {
        let candidates: Vec<&str> = case
            .sources
            .iter()
            .map(|&s| cases[s].name.as_str())
            .collect();
        return Err(format!(
            "no converged solution to continue from (candidates: {})",
            candidates.join(", ")
        ));
    }
    let src_dir = source.map(|s| store.case_dir(&cases[s].name));
    let progress = |iter: usize| {
        shared.lock().unwrap_or_else(|e| e.into_inner()).iterations[i] = iter;
    };
    std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| {
        runner.run(case, src_dir.as_deref(), tmp, &progress)
    }))
    .unwrap_or_else(|p| Err(format!("panic: {}", panic_text(p))))
}

fn worker(
    study: &Study,
    store: &Store,
    runner: &dyn CaseRunner,
    opts: &RunOptions,
    axes: &[String],
    shared: &Mutex<Shared>,
    wake: &Condvar,
) {
    let cases = &study.cases;
    loop {
        // Take a ready case (or stop when nothing is left).
        let (i, source) = {
            let mut sh = shared.lock().unwrap_or_else(|e| e.into_inner());
            loop {
                if sh.error.is_some() {
                    return;
                }
                if let Some(i) = next_ready(&sh, cases) {
                    sh.state[i] = State::Running;
                    sh.running += 1;
                    sh.started[i] = Some(Instant::now());
                    sh.iterations[i] = 0;
                    let source = pick_source(
                        &cases[i],
                        cases,
                        &sh.records,
                        study.header.continue_from_unconverged,
                    );
                    break (i, source);
                }
                if !sh.state.contains(&State::Pending) {
                    return;
                }
                sh = wake.wait(sh).unwrap_or_else(|e| e.into_inner());
            }
        };
        let case = &cases[i];
        let Some(_claim) = claim_case(store, opts, cases, i, shared, wake) else {
            continue;
        };
        let start = Instant::now();
        let continued_from = source.map(|s| cases[s].name.clone());
        let mut written = None;
        let finish = store.write_case(&case.name, |tmp| {
            let outcome = run_case(cases, i, source, store, runner, shared, tmp);
            let record = make_record(case, continued_from.clone(), outcome, start.elapsed());
            written = Some(record.clone());
            record
        });
        let elapsed = start.elapsed();
        // a case that could not be staged has the staging error as its reason
        let record = written.unwrap_or_else(|| {
            let reason = finish.as_ref().err().map(ToString::to_string);
            make_record(
                case,
                continued_from,
                Err(reason.unwrap_or_default()),
                elapsed,
            )
        });
        let mut sh = shared.lock().unwrap_or_else(|e| e.into_inner());
        sh.running -= 1;
        sh.started[i] = None;
        sh.state[i] = State::Done;
        sh.ran += 1;
        sh.time_spent += elapsed;
        if let Err(e) = finish {
            sh.error = Some(e);
        } else {
            sh.records[i] = Some(record.clone());
            // cases finished meanwhile by other runners of the folder are listed too
            let on_disk: Vec<Option<CaseRecord>> = (sh.records.iter().zip(cases))
                .map(|(r, c)| r.clone().or_else(|| store.record(&c.name).ok().flatten()))
                .collect();
            if let Err(e) = store.write_index(cases, &on_disk, axes) {
                sh.error = Some(e);
            }
        }
        if let Some(say) = opts.progress {
            say(&progress_line(&sh, cases.len(), opts.jobs, &record));
        }
        drop(sh);
        wake.notify_all();
    }
}

/// Claim case `i` (marked running) for this runner: `None` when it is not to be run here
/// (another live runner holds it: it and its waiting cases are left to that runner; another
/// runner finished it meanwhile: its record is taken; or the store failed).
fn claim_case(
    store: &Store,
    opts: &RunOptions,
    cases: &[Case],
    i: usize,
    shared: &Mutex<Shared>,
    wake: &Condvar,
) -> Option<stride_files::claim::Claim> {
    let claimed = store.claim(&cases[i].name).and_then(|c| {
        let record = store.record(&cases[i].name)?;
        Ok((c, record))
    });
    let mut sh = shared.lock().unwrap_or_else(|e| e.into_inner());
    let line = match claimed {
        Ok((Ok(claim), None)) => return Some(claim),
        Ok((Ok(claim), Some(r))) if opts.retry_failed && r.status != CaseStatus::Converged => {
            return Some(claim)
        }
        Ok((Ok(_), Some(r))) => {
            let line = format!(
                "{}: finished by another runner ({})",
                r.name,
                r.status.as_str()
            );
            sh.records[i] = Some(r);
            sh.state[i] = State::Done;
            sh.adopted += 1;
            line
        }
        Ok((Err(holder), _)) => {
            sh.state[i] = State::Elsewhere;
            for (j, c) in cases.iter().enumerate().skip(i + 1) {
                if sh.state[j] == State::Pending
                    && c.sources.iter().any(|&s| sh.state[s] == State::Elsewhere)
                {
                    sh.state[j] = State::Elsewhere;
                }
            }
            format!("{}: left to {holder}, which runs it", cases[i].name)
        }
        Err(e) => {
            sh.error = Some(e);
            String::new()
        }
    };
    sh.running -= 1;
    sh.started[i] = None;
    drop(sh);
    if let (Some(say), false) = (opts.progress, line.is_empty()) {
        say(&line);
    }
    wake.notify_all();
    None
}

/// The source of a continuation case: the closest usable case of its own chain, else the
/// lowest-objective usable case at the anchor speed (FORMULATION 10.3). Usable = converged,
/// or with a written solution when `loose`.
fn pick_source(
    case: &Case,
    cases: &[Case],
    records: &[Option<CaseRecord>],
    loose: bool,
) -> Option<usize> {
    let usable = |s: usize| {
        records[s]
            .as_ref()
            .is_some_and(|r| r.status == CaseStatus::Converged || (loose && r.solution_written))
    };
    let chain = case
        .sources
        .iter()
        .copied()
        .find(|&s| cases[s].guess.is_continuation() && usable(s));
    chain.or_else(|| {
        case.sources
            .iter()
            .copied()
            .filter(|&s| !cases[s].guess.is_continuation() && usable(s))
            .min_by(|&a, &b| {
                let obj = |i: usize| {
                    let r = records[i].as_ref();
                    // Converged before unconverged, then by objective.
                    (
                        r.is_none_or(|r| r.status != CaseStatus::Converged),
                        r.and_then(|r| r.objective).unwrap_or(f64::INFINITY),
                    )
                };
                let (ca, oa) = obj(a);
                let (cb, ob) = obj(b);
                ca.cmp(&cb).then(oa.total_cmp(&ob))
            })
    })
}

fn make_record(
    case: &Case,
    continued_from: Option<String>,
    outcome: Result<CaseOutcome, String>,
    elapsed: Duration,
) -> CaseRecord {
    let (status, reason, objective, iterations, metrics, solution_written) = match outcome {
        Ok(o) => (
            if o.converged {
                CaseStatus::Converged
            } else {
                CaseStatus::Failed
            },
            o.reason,
            o.objective,
            o.iterations,
            o.metrics,
            o.solution_written,
        ),
        Err(reason) => (CaseStatus::Failed, reason, None, None, None, false),
    };
    CaseRecord {
        name: case.name.clone(),
        group: case.group.clone(),
        guess: case.guess.to_string(),
        axes: case.axes.clone(),
        speed: case.settings.speed,
        status,
        reason,
        objective,
        iterations,
        time_s: elapsed.as_secs_f64(),
        continued_from: if case.guess.is_continuation() {
            continued_from
        } else {
            None
        },
        metrics,
        solution_written,
    }
}

/// Every `HEARTBEAT` while cases run, say which ones, for how long and at which solver
/// iteration.
fn heartbeat(cases: &[Case], shared: &Mutex<Shared>, wake: &Condvar, say: fn(&str)) {
    let mut sh = shared.lock().unwrap_or_else(|e| e.into_inner());
    let mut last = Instant::now();
    while !sh.finished {
        let (g, _) = wake
            .wait_timeout(sh, HEARTBEAT)
            .unwrap_or_else(|e| e.into_inner());
        sh = g;
        if sh.finished || last.elapsed() < HEARTBEAT {
            continue;
        }
        last = Instant::now();
        let running: Vec<String> = sh
            .started
            .iter()
            .enumerate()
            .filter_map(|(i, t)| {
                t.map(|t| {
                    format!(
                        "{} ({}, iteration {})",
                        cases[i].name,
                        format_duration(t.elapsed()),
                        sh.iterations[i]
                    )
                })
            })
            .collect();
        if !running.is_empty() {
            say(&format!("  running: {}", running.join(", ")));
        }
    }
}

/// Interval of the "still running" lines.
const HEARTBEAT: Duration = Duration::from_secs(60);

fn progress_line(sh: &Shared, total: usize, jobs: usize, last: &CaseRecord) -> String {
    let done = sh.state.iter().filter(|s| **s == State::Done).count();
    let failed = sh
        .records
        .iter()
        .filter(|r| r.as_ref().is_some_and(|r| r.status == CaseStatus::Failed))
        .count();
    let excluded = sh.state.iter().filter(|s| **s == State::Excluded).count();
    let remaining = total - done - sh.running - excluded;
    let eta = if sh.ran > 0 {
        let per_case = sh.time_spent / sh.ran as u32;
        format_duration(per_case * ((remaining + sh.running) as u32) / jobs.max(1) as u32)
    } else {
        "?".into()
    };
    let left_out = if excluded > 0 {
        format!(", {excluded} not selected")
    } else {
        String::new()
    };
    format!(
        "[{done}/{total} done, {failed} failed, {} running, {remaining} remaining{left_out}, ~{eta} left] {}: {} {} ({:.1} s)",
        sh.running,
        last.name,
        last.status.as_str(),
        last.reason,
        last.time_s
    )
}
