//! The fuzzing loop: runs the seeds, then mutates random corpus entries, keeps those that
//! reach new (edge, hit-count) pairs, saves them (when small) to the corpus folder and saves
//! every input that panics to the crash folder. Before each run the input is written to a
//! file, so that a supervising process can keep an input that aborts the process (stack
//! overflow, allocation failure).

use crate::coverage;
use crate::mutate::{mutate, Rng};
use crate::targets::Target;
use std::io::Write as _;
use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

/// How to fuzz one target.
#[derive(Clone, Debug)]
pub struct Config {
    /// Target.
    pub target: Target,
    /// Corpus folder: read at the start, new inputs of at most `save_limit` bytes saved.
    pub corpus_dir: PathBuf,
    /// Extra seed files or folders (read only), e.g. the reference models.
    pub seeds: Vec<PathBuf>,
    /// Folder for inputs that panic.
    pub crash_dir: PathBuf,
    /// File holding the input being run (for the supervisor).
    pub current: PathBuf,
    /// Wall time to fuzz [s].
    pub seconds: f64,
    /// Random seed.
    pub seed: u64,
    /// Largest input produced [bytes].
    pub max_len: usize,
    /// Largest new input saved to the corpus folder [bytes].
    pub save_limit: usize,
}

/// Counts at the end of a run.
#[derive(Clone, Copy, Debug, Default)]
pub struct Stats {
    /// Inputs run.
    pub execs: u64,
    /// Corpus entries (seeds and kept inputs).
    pub corpus: usize,
    /// Instrumented edges hit at least once.
    pub covered: usize,
    /// Instrumented edges in the build.
    pub edges: usize,
    /// Inputs that panicked.
    pub crashes: usize,
}

impl std::fmt::Display for Stats {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "execs {} corpus {} edges {}/{} crashes {}",
            self.execs, self.corpus, self.covered, self.edges, self.crashes
        )
    }
}

/// FNV-1a hash of an input, as a file name.
fn name_of(data: &[u8]) -> String {
    let mut h: u64 = 0xcbf2_9ce4_8422_2325;
    for &b in data {
        h = (h ^ b as u64).wrapping_mul(0x0000_0100_0000_01b3);
    }
    format!("{h:016x}")
}

/// Every file directly in `path` (or `path` itself when it is a file).
fn files(path: &Path) -> Vec<PathBuf> {
    match std::fs::read_dir(path) {
        Ok(rd) => {
            let mut v: Vec<PathBuf> = rd
                .flatten()
                .map(|e| e.path())
                .filter(|p| p.is_file())
                .collect();
            v.sort();
            v
        }
        Err(_) if path.is_file() => vec![path.to_path_buf()],
        Err(_) => Vec::new(),
    }
}

struct Fuzzer {
    cfg: Config,
    corpus: Vec<Vec<u8>>,
    seen: Vec<u8>,
    stats: Stats,
}

impl Fuzzer {
    /// Run one input; returns the number of new coverage pairs, or the panic message.
    fn exec(&mut self, data: &[u8]) -> Result<usize, String> {
        if let Ok(mut f) = std::fs::File::create(&self.cfg.current) {
            let _ = f.write_all(data);
        }
        coverage::reset();
        let target = self.cfg.target;
        let r = std::panic::catch_unwind(|| target.run(data));
        self.stats.execs += 1;
        let new = coverage::merge_new(&mut self.seen);
        r.map(|()| new).map_err(|p| {
            p.downcast_ref::<String>()
                .cloned()
                .or_else(|| p.downcast_ref::<&str>().map(|s| s.to_string()))
                .unwrap_or_else(|| "panic".into())
        })
    }

    fn crash(&mut self, data: &[u8], message: &str) {
        self.stats.crashes += 1;
        let _ = std::fs::create_dir_all(&self.cfg.crash_dir);
        let p = self.cfg.crash_dir.join(format!("crash-{}", name_of(data)));
        let _ = std::fs::write(&p, data);
        eprintln!("panic: {message}; input saved as {}", p.display());
    }

    fn keep(&mut self, data: Vec<u8>) {
        if data.len() <= self.cfg.save_limit {
            let _ = std::fs::create_dir_all(&self.cfg.corpus_dir);
            let _ = std::fs::write(self.cfg.corpus_dir.join(name_of(&data)), &data);
        }
        self.corpus.push(data);
    }
}

/// Fuzz `cfg.target` for `cfg.seconds`, printing statistics every 10 s to stderr.
pub fn fuzz(cfg: Config) -> Stats {
    std::panic::set_hook(Box::new(|_| {}));
    let mut fz = Fuzzer {
        cfg: cfg.clone(),
        corpus: Vec::new(),
        seen: Vec::new(),
        stats: Stats::default(),
    };
    let mut inputs: Vec<PathBuf> = files(&cfg.corpus_dir);
    for s in &cfg.seeds {
        inputs.extend(files(s));
    }
    for p in inputs {
        let Ok(data) = std::fs::read(&p) else {
            continue;
        };
        if let Err(m) = fz.exec(&data) {
            fz.crash(&data, &m);
        }
        fz.corpus.push(data);
    }
    if fz.corpus.is_empty() {
        fz.corpus.push(Vec::new());
    }
    let mut rng = Rng::new(cfg.seed);
    let start = Instant::now();
    let mut last = Instant::now();
    let dict = cfg.target.dictionary();
    while start.elapsed().as_secs_f64() < cfg.seconds {
        // the smaller of two random entries: small inputs run fast and mutate to the point
        let (a, b) = (rng.below(fz.corpus.len()), rng.below(fz.corpus.len()));
        let pick = if fz.corpus[a].len() <= fz.corpus[b].len() {
            a
        } else {
            b
        };
        let mut data = fz.corpus[pick].clone();
        let other = &fz.corpus[rng.below(fz.corpus.len())];
        mutate(&mut data, &mut rng, dict, &other.clone(), cfg.max_len);
        match fz.exec(&data) {
            Ok(0) => {}
            Ok(_) => fz.keep(data),
            Err(m) => fz.crash(&data, &m),
        }
        if last.elapsed() > Duration::from_secs(10) {
            last = Instant::now();
            eprintln!(
                "{:>6.0} s  {}",
                start.elapsed().as_secs_f64(),
                fz.snapshot()
            );
        }
    }
    fz.snapshot()
}

impl Fuzzer {
    fn snapshot(&self) -> Stats {
        Stats {
            corpus: self.corpus.len(),
            covered: coverage::covered(&self.seen),
            edges: coverage::edges(),
            ..self.stats
        }
    }
}

/// Run every file of `paths` (files or folders) once through `target`; returns the files
/// that panicked with their messages.
pub fn check(target: Target, paths: &[PathBuf]) -> Vec<(PathBuf, String)> {
    let mut failed = Vec::new();
    for p in paths.iter().flat_map(|p| files(p)) {
        let Ok(data) = std::fs::read(&p) else {
            continue;
        };
        if let Err(e) = std::panic::catch_unwind(|| target.run(&data)) {
            let m = e
                .downcast_ref::<String>()
                .cloned()
                .or_else(|| e.downcast_ref::<&str>().map(|s| s.to_string()))
                .unwrap_or_else(|| "panic".into());
            failed.push((p, m));
        }
    }
    failed
}

/// Reduce the corpus folder of `target` to the files that reach new edges, smallest first
/// (seed files, named `seed-*`, are always kept); returns the files kept and removed.
/// Needs the instrumented build (an error otherwise: without coverage every file would go).
pub fn minimize(target: Target, dir: &Path) -> Result<(usize, usize), String> {
    if coverage::edges() <= 1 {
        return Err("minimize needs the instrumented build (fuzz/rustc-sancov.sh)".into());
    }
    let mut paths = files(dir);
    paths.sort_by_key(|p| {
        let seed = p
            .file_name()
            .is_some_and(|n| n.to_string_lossy().starts_with("seed-"));
        (!seed, std::fs::metadata(p).map_or(0, |m| m.len()))
    });
    let mut seen = Vec::new();
    let (mut kept, mut removed) = (0, 0);
    for p in paths {
        let Ok(data) = std::fs::read(&p) else {
            continue;
        };
        coverage::reset();
        let _ = std::panic::catch_unwind(|| target.run(&data));
        let new = coverage::merge_new_edges(&mut seen);
        let seed = p
            .file_name()
            .is_some_and(|n| n.to_string_lossy().starts_with("seed-"));
        if new > 0 || seed {
            kept += 1;
        } else if std::fs::remove_file(&p).is_ok() {
            removed += 1;
        }
    }
    Ok((kept, removed))
}
