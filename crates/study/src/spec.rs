//! Study files: the `[study]`, `[base]` and `[grid]` tables, and their expansion into
//! named cases, each a complete, validated [`ProblemSettings`] with one initial guess.

use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use stride_ocp::model_defaults::{merge_tables as merge, ModelProblemDefaults};
use stride_ocp::settings::{ProblemSettings, RunSettings};
use toml::Value;

/// Why a study file could not be read or expanded.
#[derive(Debug, thiserror::Error)]
pub enum SpecError {
    /// The file could not be read.
    #[error("{file}: {reason}")]
    Read {
        /// Study file.
        file: String,
        /// Why.
        reason: String,
    },
    /// The TOML (or a table's keys) is malformed.
    #[error("{file}: {reason}")]
    Parse {
        /// Study file.
        file: String,
        /// What is wrong (the TOML parser names the key).
        reason: String,
    },
    /// One expanded case has invalid settings.
    #[error("{file}: case `{case}`: {reason}")]
    Case {
        /// Study file.
        file: String,
        /// Case name.
        case: String,
        /// What is wrong (names the key).
        reason: String,
    },
    /// The grid itself is inconsistent.
    #[error("{file}: [grid] {reason}")]
    Grid {
        /// Study file.
        file: String,
        /// What is wrong.
        reason: String,
    },
}

/// Solver options of a study (same meaning as `stride predict`'s `[solver]`).
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SolverSpec {
    /// Backend name (`ipm`, `ipopt`).
    pub backend: Option<String>,
    /// Hessian: `hybrid` (default with `ipm`), `limited-memory` or `exact`.
    pub hessian: Option<String>,
    /// Convergence tolerance.
    pub tol: Option<f64>,
    /// Iteration limit.
    pub max_iter: Option<usize>,
    /// Wall-time limit per case [s].
    pub time_limit: Option<f64>,
    /// Centrality correctors per iteration (ipm only; default 2 with the hybrid Hessian).
    pub centrality_correctors: Option<usize>,
    /// Coarse mesh on which each standard guess is solved first (default 10 below finer
    /// meshes; 0: none).
    pub presolve_mesh: Option<usize>,
}

/// The `[study]` table: identity, output, parallelism, solver.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct StudyHeader {
    /// Study name (used in reports).
    pub name: String,
    /// Output folder (relative paths are relative to the working directory).
    pub output: PathBuf,
    /// Cases solved at the same time.
    #[serde(default = "one")]
    pub jobs: usize,
    /// Threads per case for the function evaluations (the KKT factorisation uses one).
    #[serde(default = "one")]
    pub threads_per_case: usize,
    /// OpenSim model file, with its settings file `<model>.toml` beside it, or a shipped
    /// model's name (`falisse2022`, …) (default: the built-in subject model).
    #[serde(default)]
    pub model: Option<PathBuf>,
    /// Guesses when the grid has no `guesses` axis.
    #[serde(default = "default_guesses")]
    pub guesses: Vec<String>,
    /// Speed [m s⁻¹] where continuation chains start (1.33 in the paper).
    #[serde(default = "default_anchor")]
    pub continuation_anchor: f64,
    /// Let continuation guesses start from the last iterate of a case that did not
    /// converge (development aid while the solver is not yet converging; off in the paper).
    #[serde(default)]
    pub continue_from_unconverged: bool,
    /// Solver options.
    #[serde(default)]
    pub solver: SolverSpec,
}

impl StudyHeader {
    /// The solver and parallelism values of the file, for the checks shared with the
    /// command line ([`RunSettings::validate`]).
    pub fn run_settings(&self) -> RunSettings {
        let s = &self.solver;
        RunSettings {
            tol: s.tol,
            max_iter: s.max_iter,
            time_limit: s.time_limit,
            centrality_correctors: s.centrality_correctors,
            presolve_mesh: s.presolve_mesh,
            threads: Some(self.threads_per_case),
            jobs: Some(self.jobs),
        }
    }
}

fn one() -> usize {
    1
}
fn default_anchor() -> f64 {
    1.33
}
fn default_guesses() -> Vec<String> {
    vec!["quasi-random".into(), "data-informed-walking".into()]
}

/// The initial guess of one case (its name in study files, its tag in case names).
pub use stride_ocp::guess::InitialGuess as CaseGuess;

/// One case of a study: complete settings and one initial guess.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Case {
    /// Stable readable name, also the folder name (e.g. `speed_1.33__hip50__qr`).
    pub name: String,
    /// The name without the guess tag: cases of one group differ only by their guess.
    pub group: String,
    /// Values of the grid axes for this case (axis name → value as written).
    pub axes: BTreeMap<String, String>,
    /// Complete, validated settings.
    pub settings: ProblemSettings,
    /// Initial guess.
    pub guess: CaseGuess,
    /// For continuation guesses: candidate source cases, most preferred first (the closest
    /// speed towards the anchor in the same chain, …, then the anchor cases).
    pub sources: Vec<usize>,
}

/// A parsed, expanded and validated study.
#[derive(Clone, Debug)]
pub struct Study {
    /// The `[study]` table.
    pub header: StudyHeader,
    /// Settings of `[base]` over the model's problem defaults (a case with exactly these is
    /// the study's reference).
    pub base: ProblemSettings,
    /// Every case, dependencies before dependants.
    pub cases: Vec<Case>,
    /// The study file's text (hashed to guard resumption).
    pub source_text: String,
    /// Where it was read from.
    pub path: PathBuf,
    /// The `[slurm]` table (cluster submission settings; empty when absent).
    pub slurm: SlurmSection,
}

/// The `[slurm]` table of a study file: how `stride study --slurm` submits the study as a
/// Slurm job array. Every key is optional (defaults: the cluster's partition, time and
/// memory from the cases' estimated needs); the command line overrides each. Values are
/// checked by the CLI before anything is submitted.
#[derive(Clone, Debug, Default, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SlurmSection {
    /// Partition (`sbatch --partition`).
    pub partition: Option<String>,
    /// Time limit per case, in Slurm's format (`minutes`, `HH:MM:SS`, `D-HH:MM`, …); a
    /// chain task gets it once per case of its chain.
    pub time: Option<String>,
    /// Memory per task (`sbatch --mem`, e.g. `"4G"`).
    pub mem: Option<String>,
    /// CPUs per task (`sbatch --cpus-per-task`); also the solver threads of each case.
    pub cpus_per_task: Option<usize>,
    /// Array tasks running at once (`--array=…%N`).
    pub throttle: Option<usize>,
    /// Further `sbatch` options, each as one argument (e.g. `"--account=gait"`).
    #[serde(default)]
    pub extra_args: Vec<String>,
}

/// Raw file layout (before expansion).
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawFile {
    study: StudyHeader,
    #[serde(default)]
    base: Option<toml::Table>,
    #[serde(default)]
    grid: Option<toml::Table>,
    #[serde(default)]
    slurm: SlurmSection,
}

/// Read, expand and validate a study file.
pub fn load(path: &Path) -> Result<Study, SpecError> {
    let read_err = |reason: String| SpecError::Read {
        file: path.display().to_string(),
        reason,
    };
    let bytes = stride_model::storage::read_limited(path, MAX_STUDY_FILE_BYTES)
        .map_err(|e| read_err(e.to_string()))?;
    let text = String::from_utf8(bytes).map_err(|e| {
        let at = e.utf8_error().valid_up_to();
        let line = 1 + e.as_bytes()[..at].iter().filter(|&&b| b == b'\n').count();
        read_err(format!("line {line}: not UTF-8 text"))
    })?;
    parse(&text, path)
}

/// Most cases a study may expand to.
pub const MAX_CASES: usize = 10_000;

/// Largest study file read [bytes].
pub const MAX_STUDY_FILE_BYTES: u64 = 16 << 20;

/// Format a grid value for a case name (floats without trailing zeros).
fn value_label(v: &Value) -> String {
    match v {
        Value::Float(f) => format!("{f}"),
        Value::Integer(i) => format!("{i}"),
        Value::String(s) => s.clone(),
        Value::Boolean(b) => format!("{b}"),
        other => other.to_string(),
    }
}

fn sanitize(s: &str) -> String {
    s.chars()
        .map(|c| {
            if c.is_ascii_alphanumeric() || c == '.' || c == '-' || c == '_' {
                c
            } else {
                '-'
            }
        })
        .collect()
}

/// Set a dotted key (`weights.metabolic`) in a table.
fn set_dotted(t: &mut toml::Table, key: &str, v: Value) {
    let mut parts = key.split('.').peekable();
    let mut cur = t;
    while let Some(p) = parts.next() {
        if parts.peek().is_none() {
            cur.insert(p.to_string(), v);
            return;
        }
        let entry = cur
            .entry(p.to_string())
            .or_insert_with(|| Value::Table(toml::Table::new()));
        if !entry.is_table() {
            *entry = Value::Table(toml::Table::new());
        }
        cur = entry.as_table_mut().expect("just made a table");
    }
}

/// One named partial override of the settings (`[[grid.conditions]]`).
struct Condition {
    name: String,
    table: toml::Table,
}

/// Parse a study from its text; `path` names the file in errors.
pub fn parse(text: &str, path: &Path) -> Result<Study, SpecError> {
    let file = path.display().to_string();
    let raw: RawFile = toml::from_str(text).map_err(|e| SpecError::Parse {
        file: file.clone(),
        reason: e.to_string(),
    })?;
    let h = &raw.study;
    let grid_err = |reason: String| SpecError::Grid {
        file: file.clone(),
        reason,
    };
    h.run_settings().validate().map_err(|e| SpecError::Parse {
        file: file.clone(),
        reason: format!("[study]: {e}"),
    })?;
    // The model's problem defaults lie under [base].
    let defaults = ModelProblemDefaults::of_named_model(h.model.as_deref(), None).map_err(|e| {
        SpecError::Parse {
            file: file.clone(),
            reason: format!("model: {e}"),
        }
    })?;
    let base = defaults.under(&raw.base.unwrap_or_default());
    // The base must be valid settings (typos are reported against [base]).
    let base_settings: ProblemSettings =
        Value::Table(base.clone())
            .try_into()
            .map_err(|e: toml::de::Error| SpecError::Parse {
                file: file.clone(),
                reason: format!("[base]: {}", e.message()),
            })?;
    base_settings.validate().map_err(|e| SpecError::Parse {
        file: file.clone(),
        reason: format!("[base]: {e}"),
    })?;
    let mut grid = raw.grid.unwrap_or_default();
    // Guess axis.
    let guess_names: Vec<String> = match grid.remove("guesses") {
        Some(Value::Array(a)) => a
            .iter()
            .map(|v| {
                v.as_str()
                    .map(str::to_string)
                    .ok_or_else(|| grid_err("`guesses` must be a list of strings".into()))
            })
            .collect::<Result<_, _>>()?,
        Some(_) => return Err(grid_err("`guesses` must be a list of strings".into())),
        None => h.guesses.clone(),
    };
    let mut guesses = Vec::new();
    for g in &guess_names {
        let parsed = CaseGuess::parse(g).ok_or_else(|| {
            grid_err(format!(
                "unknown guess `{g}` (quasi-random, data-informed-walking, data-informed-running, full-os, partial-os)"
            ))
        })?;
        if guesses.contains(&parsed) {
            return Err(grid_err(format!("guess `{g}` listed twice")));
        }
        guesses.push(parsed);
    }
    if guesses.is_empty() {
        return Err(grid_err("no initial guess".into()));
    }
    // Conditions.
    let mut conditions: Vec<Condition> = Vec::new();
    match grid.remove("conditions") {
        None => {}
        Some(Value::Array(a)) => {
            for (i, c) in a.into_iter().enumerate() {
                let Value::Table(mut t) = c else {
                    return Err(grid_err(format!("conditions[{i}] must be a table")));
                };
                let name = match t.remove("name") {
                    Some(Value::String(s)) if !s.is_empty() => s,
                    _ => {
                        return Err(grid_err(format!(
                            "conditions[{i}] needs a non-empty string `name`"
                        )))
                    }
                };
                if conditions.iter().any(|c| c.name == name) {
                    return Err(grid_err(format!("condition name `{name}` used twice")));
                }
                conditions.push(Condition { name, table: t });
            }
        }
        Some(_) => return Err(grid_err("`conditions` must be an array of tables".into())),
    }
    // Value axes (sorted by key for stable names).
    let mut axes: Vec<(String, Vec<Value>)> = Vec::new();
    for (k, v) in grid {
        let Value::Array(values) = v else {
            return Err(grid_err(format!("axis `{k}` must be a list of values")));
        };
        if values.is_empty() {
            return Err(grid_err(format!("axis `{k}` is empty")));
        }
        axes.push((k, values));
    }
    axes.sort_by(|a, b| a.0.cmp(&b.0));

    // Cartesian product of axes × conditions (no condition: one unnamed), bounded.
    let count = axes
        .iter()
        .map(|(_, v)| v.len())
        .chain([conditions.len().max(1), guesses.len()])
        .try_fold(1usize, |n, k| n.checked_mul(k))
        .filter(|&n| n <= MAX_CASES);
    if count.is_none() {
        return Err(grid_err(format!(
            "the grid expands to more than {MAX_CASES} cases; split the study"
        )));
    }
    let mut combos: Vec<(Vec<usize>, Option<usize>)> = vec![(vec![], None)];
    for (_, values) in &axes {
        combos = combos
            .into_iter()
            .flat_map(|(idx, c)| {
                (0..values.len()).map(move |j| {
                    let mut i = idx.clone();
                    i.push(j);
                    (i, c)
                })
            })
            .collect();
    }
    if !conditions.is_empty() {
        combos = combos
            .into_iter()
            .flat_map(|(idx, _)| (0..conditions.len()).map(move |c| (idx.clone(), Some(c))))
            .collect();
    }

    struct Group {
        name: String,
        axes: BTreeMap<String, String>,
        settings: ProblemSettings,
    }
    let mut groups: Vec<Group> = Vec::new();
    for (idx, cond) in &combos {
        let mut table = base.clone();
        let mut parts = Vec::new();
        let mut labels = BTreeMap::new();
        if let Some(c) = cond {
            merge(&mut table, &conditions[*c].table);
            parts.push(sanitize(&conditions[*c].name));
            labels.insert("condition".to_string(), conditions[*c].name.clone());
        }
        let mut axis_parts = Vec::new();
        for ((k, values), &j) in axes.iter().zip(idx) {
            set_dotted(&mut table, k, values[j].clone());
            let label = value_label(&values[j]);
            axis_parts.push(format!("{}_{}", sanitize(k), sanitize(&label)));
            labels.insert(k.clone(), label);
        }
        axis_parts.extend(parts);
        let name = if axis_parts.is_empty() {
            "base".to_string()
        } else {
            axis_parts.join("__")
        };
        let settings: ProblemSettings =
            Value::Table(table)
                .try_into()
                .map_err(|e: toml::de::Error| SpecError::Case {
                    file: file.clone(),
                    case: name.clone(),
                    reason: e.message().to_string(),
                })?;
        settings.validate().map_err(|e| SpecError::Case {
            file: file.clone(),
            case: name.clone(),
            reason: e.to_string(),
        })?;
        if groups.iter().any(|g| g.name == name) {
            return Err(grid_err(format!("two cases are both named `{name}`")));
        }
        groups.push(Group {
            name,
            axes: labels,
            settings,
        });
    }

    // Cases: standard guesses first (so that anchors precede chains), then continuation
    // cases ordered by distance of their speed from the anchor.
    let anchor = h.continuation_anchor;
    let at_anchor = |s: &ProblemSettings| (s.speed - anchor).abs() < 1e-9;
    let mut cases: Vec<Case> = Vec::new();
    for g in &groups {
        for &guess in guesses.iter().filter(|g| !g.is_continuation()) {
            cases.push(Case {
                name: format!("{}__{}", g.name, guess.tag()),
                group: g.name.clone(),
                axes: g.axes.clone(),
                settings: g.settings.clone(),
                guess,
                sources: vec![],
            });
        }
    }
    let continuation: Vec<CaseGuess> = guesses
        .iter()
        .copied()
        .filter(|g| g.is_continuation())
        .collect();
    if !continuation.is_empty() {
        if !axes.iter().any(|(k, _)| k == "speed") {
            return Err(grid_err(
                "continuation guesses (full-os, partial-os) need a `speed` axis".into(),
            ));
        }
        if !groups.iter().any(|g| at_anchor(&g.settings)) {
            return Err(grid_err(format!(
                "continuation guesses need the anchor speed {anchor} m/s in the `speed` axis"
            )));
        }
        // The chain key: every axis value except the speed.
        let chain_key = |g: &Group| {
            let mut a = g.axes.clone();
            a.remove("speed");
            a
        };
        let mut order: Vec<usize> = (0..groups.len())
            .filter(|&i| !at_anchor(&groups[i].settings))
            .collect();
        order.sort_by(|&a, &b| {
            let da = (groups[a].settings.speed - anchor).abs();
            let db = (groups[b].settings.speed - anchor).abs();
            da.total_cmp(&db).then(a.cmp(&b))
        });
        for &guess in &continuation {
            for &gi in &order {
                let g = &groups[gi];
                let key = chain_key(g);
                let v = g.settings.speed;
                let side = (v - anchor).signum();
                // Same chain, strictly between the anchor and v: closest to v first.
                let mut chain: Vec<(f64, usize)> = cases
                    .iter()
                    .enumerate()
                    .filter(|(_, c)| {
                        c.guess == guess
                            && chain_key_of(c) == key
                            && (c.settings.speed - anchor).signum() == side
                            && (c.settings.speed - anchor).abs() < (v - anchor).abs()
                    })
                    .map(|(i, c)| ((v - c.settings.speed).abs(), i))
                    .collect();
                chain.sort_by(|a, b| a.0.total_cmp(&b.0));
                let mut sources: Vec<usize> = chain.into_iter().map(|(_, i)| i).collect();
                sources.extend(cases.iter().enumerate().filter_map(|(i, c)| {
                    (!c.guess.is_continuation() && at_anchor(&c.settings) && chain_key_of(c) == key)
                        .then_some(i)
                }));
                cases.push(Case {
                    name: format!("{}__{}", g.name, guess.tag()),
                    group: g.name.clone(),
                    axes: g.axes.clone(),
                    settings: g.settings.clone(),
                    guess,
                    sources,
                });
            }
        }
    }
    Ok(Study {
        header: raw.study,
        base: base_settings,
        cases,
        source_text: text.to_string(),
        path: path.to_path_buf(),
        slurm: raw.slurm,
    })
}

fn chain_key_of(c: &Case) -> BTreeMap<String, String> {
    let mut a = c.axes.clone();
    a.remove("speed");
    a
}

/// The axis names that vary across a study's cases (for the index table).
pub fn varying_axes(cases: &[Case]) -> Vec<String> {
    let mut keys: Vec<String> = cases.iter().flat_map(|c| c.axes.keys().cloned()).collect();
    keys.sort();
    keys.dedup();
    keys
}

/// Which cases match any of `patterns` (case names with `*` for any run of characters
/// and `?` for one character). A pattern that matches no case is an error naming it.
pub fn select_cases(cases: &[Case], patterns: &[String]) -> Result<Vec<bool>, String> {
    let mut selected = vec![false; cases.len()];
    for p in patterns {
        let mut any = false;
        for (s, c) in selected.iter_mut().zip(cases) {
            if glob_match(p.as_bytes(), c.name.as_bytes()) {
                *s = true;
                any = true;
            }
        }
        if !any {
            return Err(format!(
                "--only: `{p}` matches no case of the study (see --dry-run for the names)"
            ));
        }
    }
    Ok(selected)
}

/// `*` / `?` wildcard match of a whole name.
fn glob_match(p: &[u8], s: &[u8]) -> bool {
    // Iterative matching with one backtrack point (the last `*`).
    let (mut i, mut j) = (0, 0);
    let mut star: Option<(usize, usize)> = None;
    while j < s.len() {
        if i < p.len() && (p[i] == b'?' || p[i] == s[j]) {
            i += 1;
            j += 1;
        } else if i < p.len() && p[i] == b'*' {
            star = Some((i, j));
            i += 1;
        } else if let Some((si, sj)) = star {
            i = si + 1;
            j = sj + 1;
            star = Some((si, sj + 1));
        } else {
            return false;
        }
    }
    p[i..].iter().all(|&c| c == b'*')
}

#[cfg(test)]
mod tests {
    use super::glob_match;

    #[test]
    fn wildcards_match_whole_names() {
        let m = |p: &str, s: &str| glob_match(p.as_bytes(), s.as_bytes());
        assert!(m("speed_2.*__dir", "speed_2.33__dir"));
        assert!(!m("speed_2.*__dir", "speed_2.33__diw"));
        assert!(!m("speed_2.*", "speed_1.33__dir"));
        assert!(m("*", ""));
        assert!(m("speed_?.33__*", "speed_1.33__qr"));
        assert!(!m("speed_1.33", "speed_1.33__qr"));
        assert!(m("*__q*", "speed_1.33__qr"));
        assert!(m("a*b*c", "aXbYbZc"));
        assert!(!m("a*b*c", "aXbYbZ"));
    }
}
