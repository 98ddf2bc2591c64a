//! The study logic (expansion, validation, parallel resumable runs, failures, index,
//! continuation order, report) with fake case runners: no solver involved.

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::Mutex;
use std::time::Duration;
use stride_study::runner::{run_study, CaseRunner, RunOptions};
use stride_study::spec::{self, Case, CaseGuess, SpecError};
use stride_study::store::{CaseOutcome, CaseStatus, Metrics, Store, StoreError};

fn temp(name: &str) -> PathBuf {
    let p = std::env::temp_dir().join(format!("stride-study-test-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&p);
    p
}

/// A fake runner: cost of transport 5 − 3v + v² (walking below 2.2 m/s), linear above;
/// fails or panics on named cases; records the order and concurrency of calls.
struct Fake {
    fail: Vec<String>,
    panic: Vec<String>,
    sleep: Duration,
    calls: Mutex<Vec<(String, Option<String>)>>,
    running: AtomicUsize,
    max_running: AtomicUsize,
}

impl Fake {
    fn new() -> Self {
        Self {
            fail: vec![],
            panic: vec![],
            sleep: Duration::ZERO,
            calls: Mutex::new(vec![]),
            running: AtomicUsize::new(0),
            max_running: AtomicUsize::new(0),
        }
    }
}

impl CaseRunner for Fake {
    fn run(
        &self,
        case: &Case,
        source: Option<&Path>,
        dir: &Path,
        progress: &(dyn Fn(usize) + Sync),
    ) -> Result<CaseOutcome, String> {
        progress(1);
        let now = self.running.fetch_add(1, Ordering::SeqCst) + 1;
        self.max_running.fetch_max(now, Ordering::SeqCst);
        std::thread::sleep(self.sleep);
        self.running.fetch_sub(1, Ordering::SeqCst);
        self.calls.lock().unwrap().push((
            case.name.clone(),
            source.map(|s| s.file_name().unwrap().to_string_lossy().to_string()),
        ));
        assert!(dir.exists());
        std::fs::write(dir.join("result.txt"), case.name.as_bytes()).unwrap();
        if self.panic.contains(&case.name) {
            panic!("fake panic in {}", case.name);
        }
        if self.fail.contains(&case.name) {
            return Ok(CaseOutcome {
                converged: false,
                reason: "MaxIterations".into(),
                objective: Some(9.0),
                iterations: Some(5),
                metrics: None,
                solution_written: false,
            });
        }
        let v = case.settings.speed;
        let run = v > 2.2;
        let bonus = match case.guess {
            CaseGuess::Standard(stride_ocp::guess::GuessKind::QuasiRandom) => 1.0,
            _ => 0.0,
        };
        Ok(CaseOutcome {
            converged: true,
            reason: "Converged".into(),
            objective: Some(100.0 + bonus),
            iterations: Some(42),
            metrics: Some(Metrics {
                cost_of_transport: if run {
                    1.0 + 1.5 * v
                } else {
                    5.0 - 3.0 * v + v * v
                },
                stride_length: v / (0.6 + 0.3 * v),
                stride_frequency: 0.6 + 0.3 * v,
                step_width: 0.1,
                double_support_fraction: if run { 0.0 } else { 0.2 },
                energy_phase_correlation: Some(if run { 0.9 } else { -0.9 }),
            }),
            solution_written: true,
        })
    }
}

const SMALL: &str = r#"
[study]
name = "small"
output = "unused"
jobs = 2

[base]
mesh_intervals = 4

[grid]
speed = [1.13, 1.23, 1.33, 1.43, 2.33]
guesses = ["quasi-random", "data-informed-walking", "full-os", "partial-os"]

[[grid.conditions]]
name = "nominal"

[[grid.conditions]]
name = "hip50"
strength = [{ group = "hip", scale = 0.5 }]
"#;

fn opts(jobs: usize) -> RunOptions {
    RunOptions {
        jobs,
        progress: None,
        retry_failed: false,
        only: None,
    }
}

#[test]
fn expansion_names_cases_and_orders_continuation_chains() {
    let s = spec::parse(SMALL, Path::new("small.toml")).unwrap();
    // 2 conditions × (5 speeds × 2 standard + 4 speeds × 2 continuation) = 36.
    assert_eq!(s.cases.len(), 36);
    let names: Vec<&str> = s.cases.iter().map(|c| c.name.as_str()).collect();
    assert!(names.contains(&"speed_1.33__hip50__qr"));
    assert!(names.contains(&"speed_2.33__nominal__fos"));
    assert!(!names.contains(&"speed_1.33__nominal__fos"));
    let idx = |n: &str| names.iter().position(|x| *x == n).unwrap();
    let c = &s.cases[idx("speed_1.13__nominal__fos")];
    let src: Vec<&str> = c.sources.iter().map(|&i| names[i]).collect();
    assert_eq!(
        src,
        [
            "speed_1.23__nominal__fos",
            "speed_1.33__nominal__qr",
            "speed_1.33__nominal__diw"
        ]
    );
    let c = &s.cases[idx("speed_2.33__hip50__pos")];
    let src: Vec<&str> = c.sources.iter().map(|&i| names[i]).collect();
    assert_eq!(
        src,
        [
            "speed_1.43__hip50__pos",
            "speed_1.33__hip50__qr",
            "speed_1.33__hip50__diw"
        ]
    );
    // Sources always come before their dependants.
    for (i, c) in s.cases.iter().enumerate() {
        assert!(c.sources.iter().all(|&j| j < i), "{}", c.name);
    }
    assert_eq!(c.axes.get("condition").map(String::as_str), Some("hip50"));
}

#[test]
fn cases_that_start_the_longest_chains_run_first() {
    let out = temp("chains");
    let study = spec::parse(SMALL, Path::new("small.toml")).unwrap();
    let chain = stride_study::runner::chain_lengths(&study.cases);
    let names: Vec<&str> = study.cases.iter().map(|c| c.name.as_str()).collect();
    let len = |n: &str| chain[names.iter().position(|x| *x == n).unwrap()];
    // 1.33 → 1.43 → 2.33 and 1.33 → 1.23 → 1.13 (fos and pos chains alike)
    assert_eq!(len("speed_1.33__nominal__qr"), 3);
    assert_eq!(len("speed_1.43__hip50__pos"), 2);
    assert_eq!(len("speed_1.23__nominal__fos"), 2);
    assert_eq!(len("speed_2.33__nominal__fos"), 1);
    assert_eq!(len("speed_1.13__nominal__qr"), 1);
    // one case at a time: the four anchors, then the eight middle links of the chains,
    // then everything else (in list order the standard cases of 1.13 m/s came first)
    let store = Store::open(&out, &study, false).unwrap();
    let fake = Fake::new();
    run_study(&study, &store, &fake, &opts(1)).unwrap();
    let calls = fake.calls.lock().unwrap().clone();
    let order: Vec<usize> = calls.iter().map(|c| len(&c.0)).collect();
    assert_eq!(order[..4], [3; 4], "{calls:?}");
    assert_eq!(order[4..12], [2; 8], "{calls:?}");
    assert!(order[12..].iter().all(|&l| l == 1));
    let _ = std::fs::remove_dir_all(&out);
}

#[test]
fn typos_and_bad_values_are_errors_naming_file_case_and_key() {
    let e = spec::parse(
        "[study]\nname='x'\noutput='o'\n[base]\nsped = 1.0\n",
        Path::new("a.toml"),
    )
    .unwrap_err();
    let t = e.to_string();
    assert!(t.contains("a.toml") && t.contains("sped"), "{t}");
    let e = spec::parse(
        "[study]\nname='x'\noutput='o'\njbos=2\n",
        Path::new("b.toml"),
    )
    .unwrap_err();
    assert!(e.to_string().contains("jbos"), "{e}");
    let e = spec::parse(
        "[study]\nname='x'\noutput='o'\n[grid]\nspeed=[1.0, -2.0]\n",
        Path::new("c.toml"),
    )
    .unwrap_err();
    match &e {
        SpecError::Case { case, reason, .. } => {
            assert_eq!(case, "speed_-2");
            assert!(reason.contains("speed"), "{reason}");
        }
        other => panic!("{other}"),
    }
    let e = spec::parse(
        "[study]\nname='x'\noutput='o'\n[[grid.conditions]]\nname='w'\nweights={metabolik=1.0}\n",
        Path::new("d.toml"),
    )
    .unwrap_err();
    let t = e.to_string();
    assert!(t.contains("case `w") && t.contains("metabolik"), "{t}");
    let e = spec::parse(
        "[study]\nname='x'\noutput='o'\n[grid]\nguesses=['full-os']\n",
        Path::new("e.toml"),
    )
    .unwrap_err();
    assert!(e.to_string().contains("speed"), "{e}");
    let e = spec::parse(
        "[study]\nname='x'\noutput='o'\n[grid]\nguesses=['quasi-randum']\n",
        Path::new("f.toml"),
    )
    .unwrap_err();
    assert!(e.to_string().contains("quasi-randum"), "{e}");
}

#[test]
fn study_runs_in_parallel_records_failures_and_resumes() {
    let out = temp("resume");
    let study = spec::parse(SMALL, Path::new("small.toml")).unwrap();
    let store = Store::open(&out, &study, false).unwrap();
    let mut fake = Fake::new();
    fake.sleep = Duration::from_millis(20);
    fake.fail = vec!["speed_1.23__nominal__fos".into()];
    fake.panic = vec!["speed_2.33__hip50__qr".into()];
    let summary = run_study(&study, &store, &fake, &opts(3)).unwrap();
    assert_eq!(summary.ran, 36);
    assert_eq!(summary.failed, 2);
    assert_eq!(summary.converged, 34);
    assert!(
        fake.max_running.load(Ordering::SeqCst) >= 2,
        "cases ran in parallel"
    );
    // Continuation sources are finished cases; the failed neighbour is skipped.
    let calls = fake.calls.lock().unwrap().clone();
    let pos = |n: &str| calls.iter().position(|c| c.0 == n).unwrap();
    let fos_113 = &calls[pos("speed_1.13__nominal__fos")];
    // Its chain neighbour failed: the lowest-objective anchor case (DI walking) is used.
    assert_eq!(fos_113.1.as_deref(), Some("speed_1.33__nominal__diw"));
    assert!(pos("speed_1.23__nominal__fos") < pos("speed_1.13__nominal__fos"));
    let pos_233 = &calls[pos("speed_2.33__hip50__pos")];
    assert_eq!(pos_233.1.as_deref(), Some("speed_1.43__hip50__pos"));
    // Records, result files and the index.
    let r = store.record("speed_2.33__hip50__qr").unwrap().unwrap();
    assert_eq!(r.status, CaseStatus::Failed);
    assert!(r.reason.contains("fake panic"), "{}", r.reason);
    assert!(out
        .join("cases/speed_1.33__nominal__qr/result.txt")
        .exists());
    let index = std::fs::read_to_string(out.join("index.csv")).unwrap();
    assert_eq!(index.lines().count(), 37);
    assert!(index
        .lines()
        .next()
        .unwrap()
        .starts_with("name,condition,speed,guess,status"));
    assert!(index.contains("speed_1.23__nominal__fos,nominal,1.23,full-os,failed,MaxIterations"));
    // While a run holds the folder, another is refused naming its process id.
    match Store::open(&out, &study, false) {
        Err(StoreError::Busy { holder, .. }) => assert_eq!(holder, Some(std::process::id())),
        other => panic!("{other:?}"),
    }
    drop(store);
    // Rerun: nothing to do. A killed run's work folder is cleaned; a user's folder is kept.
    let killed = out.join("cases/.stride-work.speed_1.13__nominal__qr");
    std::fs::create_dir_all(killed.join("partial")).unwrap();
    std::fs::write(killed.join("owner"), "gone 999 - 0\n").unwrap();
    std::fs::create_dir_all(out.join("cases/.tmp-speed_1.13__nominal__qr-999")).unwrap();
    let store = Store::open(&out, &study, false).unwrap();
    assert!(!killed.exists());
    assert!(out.join("cases/.tmp-speed_1.13__nominal__qr-999").exists());
    std::fs::remove_dir(out.join("cases/.tmp-speed_1.13__nominal__qr-999")).unwrap();
    let fake2 = Fake::new();
    let s2 = run_study(&study, &store, &fake2, &opts(2)).unwrap();
    assert_eq!((s2.ran, s2.skipped), (0, 36));
    assert!(fake2.calls.lock().unwrap().is_empty());
    // Losing a finished case (as after kill -9 before its rename) reruns only that case.
    std::fs::remove_dir_all(out.join("cases/speed_1.43__nominal__diw")).unwrap();
    let s3 = run_study(&study, &store, &fake2, &opts(2)).unwrap();
    assert_eq!(s3.ran, 1);
    // Retrying failed cases.
    let s4 = run_study(
        &study,
        &store,
        &Fake::new(),
        &RunOptions {
            jobs: 2,
            progress: None,
            retry_failed: true,
            only: None,
        },
    )
    .unwrap();
    assert_eq!((s4.ran, s4.failed), (2, 0));
    // Another study file into the same folder is refused unless forced.
    drop(store);
    let other = spec::parse(&SMALL.replace("jobs = 2", "jobs = 1"), Path::new("o.toml")).unwrap();
    match Store::open(&out, &other, false) {
        Err(StoreError::OtherStudy { .. }) => {}
        other => panic!("{other:?}"),
    }
    assert!(Store::open(&out, &other, true).is_ok());
    let _ = std::fs::remove_dir_all(&out);
}

#[test]
fn a_selection_runs_only_its_cases_and_a_later_run_completes_the_study() {
    let out = temp("only");
    let study = spec::parse(SMALL, Path::new("small.toml")).unwrap();
    let store = Store::open(&out, &study, false).unwrap();
    let names: Vec<&str> = study.cases.iter().map(|c| c.name.as_str()).collect();
    // A pattern that matches nothing is an error naming it.
    let e = spec::select_cases(&study.cases, &["speed_9*".into()]).unwrap_err();
    assert!(e.contains("`speed_9*` matches no case"), "{e}");
    // A continuation case without its sources cannot run alone.
    let mask = spec::select_cases(&study.cases, &["speed_1.43__nominal__fos".into()]).unwrap();
    let with = |only: Vec<bool>| RunOptions {
        only: Some(only),
        ..opts(2)
    };
    match run_study(&study, &store, &Fake::new(), &with(mask)) {
        Err(StoreError::Selection(e)) => assert!(
            e.contains("`speed_1.43__nominal__fos` continues from `speed_1.33__nominal__qr`"),
            "{e}"
        ),
        other => panic!("{other:?}"),
    }
    // The anchor cases and their first continuation: exactly these run.
    let patterns = [
        "speed_1.33__*".to_string(),
        "speed_1.43__nominal__?os".into(),
    ];
    let mask = spec::select_cases(&study.cases, &patterns).unwrap();
    let fake = Fake::new();
    let s1 = run_study(&study, &store, &fake, &with(mask.clone())).unwrap();
    let mut ran: Vec<String> = fake
        .calls
        .lock()
        .unwrap()
        .iter()
        .map(|c| c.0.clone())
        .collect();
    ran.sort();
    let mut want: Vec<String> = names
        .iter()
        .zip(&mask)
        .filter(|(_, &m)| m)
        .map(|(n, _)| n.to_string())
        .collect();
    want.sort();
    assert_eq!(ran, want);
    assert_eq!(want.len(), 6);
    assert_eq!((s1.ran, s1.not_selected), (6, 30));
    let index = std::fs::read_to_string(out.join("index.csv")).unwrap();
    assert!(index.contains("speed_1.13__nominal__qr,nominal,1.13,quasi-random,not run"));
    // The same command without the selection runs the other 30, none twice.
    let fake2 = Fake::new();
    let s2 = run_study(&study, &store, &fake2, &opts(2)).unwrap();
    assert_eq!((s2.ran, s2.skipped, s2.not_selected), (30, 6, 0));
    let calls = fake2.calls.lock().unwrap();
    assert!(calls.iter().all(|c| !want.contains(&c.0)));
    let _ = std::fs::remove_dir_all(&out);
}

#[test]
fn report_classifies_gaits_and_fits_speed_dependence() {
    let text = r#"
[study]
name = "sweep"
output = "unused"
jobs = 2
[grid]
speed = [0.73, 0.93, 1.13, 1.33, 1.53, 1.73, 1.93, 2.13, 2.33, 2.53, 2.73]
"#;
    let out = temp("report");
    let study = spec::parse(text, Path::new("sweep.toml")).unwrap();
    let store = Store::open(&out, &study, false).unwrap();
    run_study(&study, &store, &Fake::new(), &opts(2)).unwrap();
    let report = stride_study::report::report_folder(&out).unwrap();
    assert_eq!(report.cases, 22);
    // The cases' wall times add up to the report's total.
    let total: f64 = study
        .cases
        .iter()
        .map(|c| store.record(&c.name).unwrap().unwrap().time_s)
        .sum();
    assert!(total > 0.0 && (report.case_time_s - total).abs() < 1e-12);
    assert_eq!(report.selected.len(), 11);
    assert!(report
        .selected
        .iter()
        .all(|s| s.guess == "data-informed-walking"));
    let series = &report.speed_series[0];
    assert!((series.transition_speed.unwrap() - 2.33).abs() < 1e-12);
    // Walking COT exactly quadratic below the transition; the transition point itself is
    // on the running line, so the quadratic is exact only without it: check the running
    // line and the stride frequency (exact).
    assert!((series.cot_running_fit.as_ref().unwrap().r_squared - 1.0).abs() < 1e-12);
    assert!(
        (series
            .stride_frequency_walking_fit
            .as_ref()
            .unwrap()
            .r_squared
            - 1.0)
            .abs()
            < 1e-12
    );
    assert!(out.join("report.json").exists());
    assert!(out.join("selected.csv").exists());
    let csv = std::fs::read_to_string(out.join("speed_series_0.csv")).unwrap();
    assert_eq!(csv.lines().count(), 12);
    let svg = std::fs::read_to_string(out.join("figure_speed_series_0.svg")).unwrap();
    assert!(svg.contains("Cost of transport") && svg.contains("R² = 1.00"));
    assert!(out.join("figure_speed_series_0.png").exists());
    let _ = BTreeMap::<String, String>::new();
    if std::env::var_os("KEEP").is_none() {
        let _ = std::fs::remove_dir_all(&out);
    }
}

#[test]
fn a_bad_case_is_reported_before_anything_is_written() {
    let out = temp("bad");
    let text = format!(
        "[study]\nname='x'\noutput='{}'\n[grid]\nactivation_min=[0.1, 1.5]\n",
        out.display()
    );
    let e = spec::parse(&text, Path::new("bad.toml")).unwrap_err();
    assert!(e.to_string().contains("activation_min_1.5"), "{e}");
    assert!(e.to_string().contains("`activation_min`"), "{e}");
    assert!(!out.exists());
}

#[test]
fn single_case_runners_share_the_folder_and_leave_cases_claimed_elsewhere() {
    let out = temp("shared");
    let study = spec::parse(SMALL, Path::new("small.toml")).unwrap();
    let a = Store::open_shared(&out, &study, false).unwrap();
    let b = Store::open_shared(&out, &study, false).unwrap();
    assert!(matches!(
        Store::open(&out, &study, false),
        Err(StoreError::Busy { .. })
    ));
    let idx = |n: &str| study.cases.iter().position(|c| c.name == n).unwrap();
    // another host runs the DI-walking anchor; a killed task of a third host left a
    // staging folder of the quasi-random anchor
    std::fs::write(
        a.claim_path("speed_1.33__nominal__diw"),
        "elsewhere 1 9_1 0\n",
    )
    .unwrap();
    let stale = out.join("cases/.stride-work.speed_1.33__nominal__qr");
    std::fs::create_dir_all(stale.join("partial")).unwrap();
    std::fs::write(stale.join("owner"), "gone 77 - 0\n").unwrap();
    let mut mask = vec![false; study.cases.len()];
    for n in [
        "speed_1.33__nominal__qr",
        "speed_1.33__nominal__diw",
        "speed_1.23__nominal__fos",
        "speed_1.13__nominal__fos",
    ] {
        mask[idx(n)] = true;
    }
    let fake = Fake::new();
    let only = RunOptions {
        only: Some(mask.clone()),
        ..opts(1)
    };
    let s = run_study(&study, &a, &fake, &only).unwrap();
    assert_eq!((s.ran, s.elsewhere), (1, 3), "{s:?}");
    assert!(
        !stale.exists(),
        "the claim holder removes the case's staging folders"
    );
    assert!(a.record("speed_1.33__nominal__qr").unwrap().is_some());
    // the other host's claim goes stale: a second runner takes the rest, the finished case
    // is not run again
    let old = std::time::SystemTime::now() - Duration::from_secs(600);
    std::fs::File::options()
        .write(true)
        .open(a.claim_path("speed_1.33__nominal__diw"))
        .unwrap()
        .set_modified(old)
        .unwrap();
    let fake = Fake::new();
    let s = run_study(&study, &b, &fake, &only).unwrap();
    assert_eq!((s.ran, s.elsewhere), (3, 0), "{s:?}");
    let calls: Vec<String> = fake
        .calls
        .lock()
        .unwrap()
        .iter()
        .map(|c| c.0.clone())
        .collect();
    assert!(!calls.contains(&"speed_1.33__nominal__qr".to_string()));
    let index = std::fs::read_to_string(out.join("index.csv")).unwrap();
    assert_eq!(index.matches(",converged,").count(), 4, "{index}");
    std::fs::remove_dir_all(&out).unwrap();
}

#[test]
fn a_study_is_planned_as_waves_of_tasks_with_each_chain_in_one_task() {
    let study = spec::parse(SMALL, Path::new("small.toml")).unwrap();
    let waves = stride_study::tasks::plan(&study.cases, &|_| true);
    assert_eq!(waves.len(), 2);
    let mut seen = vec![0; study.cases.len()];
    for (w, tasks) in waves.iter().enumerate() {
        for t in tasks {
            assert!(t.windows(2).all(|p| p[0] < p[1]), "study order in a task");
            for &i in t {
                seen[i] += 1;
                assert_eq!(w > 0, study.cases[i].guess.is_continuation());
            }
            if w == 0 {
                assert_eq!(t.len(), 1);
            }
        }
    }
    assert!(seen.iter().all(|&n| n == 1));
    let task_of = |n: &str| {
        let i = study.cases.iter().position(|c| c.name == n).unwrap();
        waves[1].iter().position(|t| t.contains(&i)).unwrap()
    };
    assert_eq!(
        task_of("speed_1.13__nominal__fos"),
        task_of("speed_1.23__nominal__fos")
    );
    assert_ne!(
        task_of("speed_1.13__nominal__fos"),
        task_of("speed_1.13__hip50__fos")
    );
}
