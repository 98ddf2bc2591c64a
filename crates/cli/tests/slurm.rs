//! Studies through a real Slurm: a single-node cluster is started on this machine
//! (`tools/slurm_local/start.sh`: munged, slurmctld, slurmd with a generated slurm.conf),
//! a small study (three speeds at 10 intervals and a two-link continuation chain) is
//! submitted with `stride study --slurm`, one task is killed with SIGKILL mid-case, the
//! same command is submitted again, and the finished study must equal a local run of the
//! same file (index.csv and report.json without the wall times), each case run once.
//! Skipped with the reason printed when not root, without the Slurm and munge programs, or
//! when the daemons do not start.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};
use std::time::{Duration, Instant};

const STUDY: &str = r#"[study]
name = "cluster"
output = "unused"
jobs = 2
continuation_anchor = 1.33
guesses = ["data-informed-walking"]

[study.solver]
presolve_mesh = 0

[base]
mesh_intervals = 10

[grid]
speed = [1.33, 1.43, 1.53]
guesses = ["data-informed-walking", "full-os"]
"#;

const CASES: [&str; 5] = [
    "speed_1.33__diw",
    "speed_1.43__diw",
    "speed_1.53__diw",
    "speed_1.43__fos",
    "speed_1.53__fos",
];

/// A running single-node cluster, stopped when dropped.
struct Cluster {
    dir: PathBuf,
    conf: PathBuf,
}

fn tools() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../tools/slurm_local")
}

impl Cluster {
    /// Start the cluster in `dir`, or say why not.
    fn start(dir: &Path) -> Result<Cluster, String> {
        let id = Command::new("id")
            .arg("-u")
            .output()
            .map_err(|e| e.to_string())?;
        if String::from_utf8_lossy(&id.stdout).trim() != "0" {
            return Err("not root (slurmd runs jobs as root here)".into());
        }
        let have = Command::new("sh")
            .args([
                "-c",
                "for p in munged slurmctld slurmd sbatch squeue sinfo; do command -v $p || exit 1; done",
            ])
            .output()
            .map_err(|e| e.to_string())?;
        if !have.status.success() || String::from_utf8_lossy(&have.stdout).lines().count() < 6 {
            return Err("the packages slurm-wlm and munge are not installed".into());
        }
        let port = 17000 + 2 * (std::process::id() % 2000);
        let out = Command::new(tools().join("start.sh"))
            .arg(dir)
            .arg(port.to_string())
            .output()
            .map_err(|e| e.to_string())?;
        let cluster = Cluster {
            dir: dir.to_path_buf(),
            conf: dir.join("slurm.conf"),
        };
        if !out.status.success() {
            return Err(format!(
                "the Slurm daemons did not start: {}",
                String::from_utf8_lossy(&out.stderr).trim()
            ));
        }
        Ok(cluster)
    }

    /// Run a command with this cluster's configuration.
    fn run(&self, program: &str, args: &[&str], cwd: &Path) -> Output {
        Command::new(program)
            .args(args)
            .current_dir(cwd)
            .env("SLURM_CONF", &self.conf)
            .output()
            .expect("running a command")
    }

    /// Wait until no job is queued or running.
    fn wait_idle(&self, cwd: &Path, limit: Duration) {
        let start = Instant::now();
        loop {
            let q = self.run("squeue", &["-h", "-o", "%i %T"], cwd);
            if q.status.success() && q.stdout.is_empty() {
                return;
            }
            assert!(
                start.elapsed() < limit,
                "jobs still queued after {limit:?}: {}",
                text(&q.stdout)
            );
            std::thread::sleep(Duration::from_millis(500));
        }
    }
}

impl Drop for Cluster {
    fn drop(&mut self) {
        let _ = Command::new(tools().join("stop.sh"))
            .arg(&self.dir)
            .output();
    }
}

fn text(b: &[u8]) -> String {
    String::from_utf8_lossy(b).into_owned()
}

fn stride() -> &'static str {
    env!("CARGO_BIN_EXE_stride")
}

/// index.csv without its wall-time column.
fn index_without_times(out: &Path) -> Vec<String> {
    let t = std::fs::read_to_string(out.join("index.csv")).unwrap();
    let mut lines = t.lines();
    let header: Vec<&str> = lines.next().unwrap().split(',').collect();
    let col = header.iter().position(|h| *h == "time_s").unwrap();
    t.lines()
        .map(|l| {
            let mut f: Vec<&str> = l.split(',').collect();
            f.remove(col);
            f.join(",")
        })
        .collect()
}

/// report.json without wall times.
fn report_without_times(out: &Path) -> serde_json::Value {
    fn strip(v: &mut serde_json::Value) {
        match v {
            serde_json::Value::Object(m) => {
                m.retain(|k, _| !k.ends_with("time_s"));
                m.values_mut().for_each(strip);
            }
            serde_json::Value::Array(a) => a.iter_mut().for_each(strip),
            _ => {}
        }
    }
    let mut v =
        serde_json::from_str(&std::fs::read_to_string(out.join("report.json")).unwrap()).unwrap();
    strip(&mut v);
    v
}

/// Kill (SIGKILL) the stride process of the first live claim whose case has been running
/// for a second; the name of its case.
fn kill_one_running_case(out: &Path, limit: Duration) -> String {
    let start = Instant::now();
    loop {
        assert!(start.elapsed() < limit, "no case started within {limit:?}");
        for name in CASES {
            let claim = std::fs::read_to_string(out.join("claims").join(format!("{name}.lock")));
            let Some(pid) = claim
                .ok()
                .and_then(|t| t.split_whitespace().nth(1).map(str::to_string))
            else {
                continue;
            };
            let staging = out
                .join("cases")
                .join(format!(".stride-work.{name}"))
                .join("partial")
                .is_dir();
            if staging && !out.join("cases").join(name).exists() {
                std::thread::sleep(Duration::from_secs(1));
                let k = Command::new("kill").args(["-9", &pid]).status().unwrap();
                if k.success() && !out.join("cases").join(name).exists() {
                    return name.to_string();
                }
            }
        }
        std::thread::sleep(Duration::from_millis(100));
    }
}

/// Lines `<case>: <status> …` that the tasks printed when they finished a case.
fn finished_lines(out: &Path) -> Vec<String> {
    let mut lines = Vec::new();
    for e in std::fs::read_dir(out.join("slurm")).unwrap().flatten() {
        if e.path().extension().is_some_and(|x| x == "out") {
            let t = std::fs::read_to_string(e.path()).unwrap();
            lines.extend(
                t.lines()
                    .filter(|l| CASES.iter().any(|c| l.starts_with(&format!("{c}: "))))
                    .map(str::to_string),
            );
        }
    }
    lines
}

#[test]
fn a_study_through_slurm_survives_a_killed_task_and_equals_a_local_run() {
    let d = std::env::temp_dir().join(format!("stride-slurm-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    let cluster = match Cluster::start(&d.join("cluster")) {
        Ok(c) => c,
        Err(why) => {
            eprintln!("skipping the Slurm test: {why}");
            let _ = std::fs::remove_dir_all(&d);
            return;
        }
    };
    std::fs::write(d.join("cluster.toml"), STUDY).unwrap();
    let on_slurm = d.join("on_slurm");
    let slurm_args = [
        "study",
        "cluster.toml",
        "--out",
        "on_slurm",
        "--slurm",
        "--time",
        "20",
    ];
    // bad settings are refused before anything is submitted
    for (bad, needle) in [
        ("--time=-5", "time `-5`"),
        ("--partition=nosuch", "partition `nosuch` is not one of"),
    ] {
        let mut args = slurm_args[..5].to_vec();
        args.push(bad);
        let o = cluster.run(stride(), &args, &d);
        assert_eq!(o.status.code(), Some(1), "{}", text(&o.stderr));
        assert!(text(&o.stderr).contains(needle), "{}", text(&o.stderr));
        assert!(!on_slurm.exists());
    }
    // first submission; one task is killed mid-case
    let o = cluster.run(stride(), &slurm_args, &d);
    assert!(o.status.success(), "{}{}", text(&o.stdout), text(&o.stderr));
    let killed = kill_one_running_case(&on_slurm, Duration::from_secs(600));
    cluster.wait_idle(&d, Duration::from_secs(1200));
    let status = cluster.run(
        stride(),
        &["study", "cluster.toml", "--out", "on_slurm", "--status"],
        &d,
    );
    let st = text(&status.stdout);
    assert!(st.contains(&format!("{killed}: missing")), "{st}");
    // resubmission: only what is missing runs
    let o = cluster.run(stride(), &slurm_args, &d);
    assert!(o.status.success(), "{}{}", text(&o.stdout), text(&o.stderr));
    cluster.wait_idle(&d, Duration::from_secs(1200));
    let status = cluster.run(
        stride(),
        &["study", "cluster.toml", "--out", "on_slurm", "--status"],
        &d,
    );
    let st = text(&status.stdout);
    assert!(st.contains("0 running, 0 missing"), "{st}");
    let mut lines = finished_lines(&on_slurm);
    lines.sort();
    for c in CASES {
        let n = lines
            .iter()
            .filter(|l| l.starts_with(&format!("{c}: ")))
            .count();
        assert_eq!(n, 1, "case {c} finished {n} times: {lines:?}");
    }
    let leftovers: Vec<_> = std::fs::read_dir(on_slurm.join("cases"))
        .unwrap()
        .flatten()
        .filter(|e| e.file_name().to_string_lossy().starts_with('.'))
        .map(|e| e.file_name())
        .collect();
    assert!(leftovers.is_empty(), "{leftovers:?}");
    drop(cluster);
    // the same study run locally
    let o = Command::new(stride())
        .args([
            "study",
            "cluster.toml",
            "--out",
            "local",
            "--no-view",
            "--quiet",
        ])
        .current_dir(&d)
        .output()
        .unwrap();
    assert!(
        o.status.code().is_some_and(|c| c == 0 || c == 2),
        "{}",
        text(&o.stderr)
    );
    assert_eq!(
        index_without_times(&on_slurm),
        index_without_times(&d.join("local"))
    );
    assert_eq!(
        report_without_times(&on_slurm),
        report_without_times(&d.join("local"))
    );
    std::fs::remove_dir_all(&d).unwrap();
}

#[test]
fn dry_run_prints_array_scripts_and_bad_settings_are_refused_before_submitting() {
    let d = std::env::temp_dir().join(format!("stride-slurm-dry-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    let file = d.join("cluster.toml");
    std::fs::write(
        &file,
        format!("{STUDY}\n[slurm]\nthrottle = 2\nextra_args = [\"--account=gait\"]\n"),
    )
    .unwrap();
    let f = file.to_str().unwrap();
    let run = |extra: &[&str]| {
        let mut args = vec!["study", f, "--out", "o", "--slurm", "--dry-run"];
        args.extend(extra);
        Command::new(stride())
            .args(&args)
            .current_dir(&d)
            .output()
            .unwrap()
    };
    let o = run(&["--time", "0:45:00", "--mem", "2G"]);
    let t = text(&o.stdout);
    assert!(o.status.success(), "{}", text(&o.stderr));
    for line in [
        "#SBATCH --array=0-2%2",
        "#SBATCH --array=0-0%2",
        "#SBATCH --time=0-00:45:00",
        "#SBATCH --time=0-01:30:00",
        "#SBATCH --mem=2048M",
        "#SBATCH --account=gait",
        "'speed_1.43__fos,speed_1.53__fos'",
        "--dependency=afterany:$J0:$J1",
        "5 cases in 4 tasks, 2 array job(s) and a report job",
    ] {
        assert!(t.contains(line), "{line} missing from:\n{t}");
    }
    assert!(!d.join("o").exists(), "a dry run writes nothing");
    for (bad, needle) in [
        ("--time=-5", "time `-5`"),
        ("--mem=0", "mem `0`"),
        ("--throttle=0", "throttle = 0"),
    ] {
        let o = run(&[bad]);
        let err = text(&o.stderr);
        assert_eq!(o.status.code(), Some(1), "{bad}: {err}");
        assert!(
            err.contains(needle) && err.lines().count() == 1,
            "{bad}: {err}"
        );
    }
    std::fs::write(&file, format!("{STUDY}\n[slurm]\ntime = \"1:xx\"\n")).unwrap();
    let err = text(&run(&[]).stderr);
    assert!(
        err.contains("cluster.toml: [slurm]") && err.contains("time `1:xx`"),
        "{err}"
    );
    std::fs::remove_dir_all(&d).unwrap();
}
