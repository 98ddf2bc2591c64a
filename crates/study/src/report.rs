//! The report of a study folder: the selected case per group, speed series with walk/run
//! classification and fits, the condition comparison, and the files and figures that show
//! them (`report.json`, `selected.csv`, `speed_series_<i>.csv`, figures).

use crate::analysis::{
    classify, literature_stride_frequency, mesh_caption, speed_series_of, Selected, SpeedSeries,
};
use crate::conditions::{condition_table, write_conditions, ConditionTable, MeasuresOf};
use crate::figures::write_speed_figures;
use crate::spec::{self, Case};
use crate::store::{io_err, CaseRecord, CaseStatus, Store, StoreError};
use serde::Serialize;
use std::collections::BTreeMap;
use std::fmt::Write as _;
use std::path::Path;
use stride_files::write_atomic;

/// `report.json`.
#[derive(Clone, Debug, Serialize)]
pub struct Report {
    /// Study name.
    pub study: String,
    /// Number of cases.
    pub cases: usize,
    /// Converged cases.
    pub converged: usize,
    /// Failed cases.
    pub failed: usize,
    /// Cases not run.
    pub not_run: usize,
    /// Wall time of the finished (converged or failed) cases, summed [s]: with `jobs`
    /// cases at a time the study's wall time is about this divided by `jobs`.
    pub case_time_s: f64,
    /// Selected case per group.
    pub selected: Vec<Selected>,
    /// Speed series (studies with a speed axis).
    pub speed_series: Vec<SpeedSeries>,
    /// Conditions against the reference case (filled by [`report_folder`]).
    pub conditions: Option<ConditionTable>,
    /// The mesh of the cases as figure captions state it.
    pub mesh: String,
}

/// Build the report from cases and their records.
pub fn build_report(name: &str, cases: &[Case], records: &[Option<CaseRecord>]) -> Report {
    let count = |s: CaseStatus| {
        records
            .iter()
            .filter(|r| r.as_ref().is_some_and(|r| r.status == s))
            .count()
    };
    // Groups in first-appearance order.
    let mut groups: Vec<&str> = Vec::new();
    for c in cases {
        if !groups.contains(&c.group.as_str()) {
            groups.push(&c.group);
        }
    }
    let mut selected = Vec::new();
    for g in &groups {
        let best = cases
            .iter()
            .zip(records)
            .filter(|(c, _)| c.group == *g)
            .filter_map(|(c, r)| r.as_ref().map(|r| (c, r)))
            .filter(|(_, r)| r.status == CaseStatus::Converged)
            .min_by(|a, b| {
                a.1.objective
                    .unwrap_or(f64::INFINITY)
                    .total_cmp(&b.1.objective.unwrap_or(f64::INFINITY))
            });
        if let Some((c, r)) = best {
            let m = r.metrics.as_ref();
            selected.push(Selected {
                group: c.group.clone(),
                axes: c.axes.clone(),
                case: c.name.clone(),
                guess: r.guess.clone(),
                objective: r.objective,
                speed: c.settings.speed,
                cost_of_transport: m.map(|m| m.cost_of_transport),
                stride_frequency: m.map(|m| m.stride_frequency),
                stride_length: m.map(|m| m.stride_length),
                gait: m.and_then(|m| m.energy_phase_correlation).map(classify),
            });
        }
    }
    let has_speed_axis = cases.iter().any(|c| c.axes.contains_key("speed"));
    let mut speed_series = Vec::new();
    if has_speed_axis {
        let mut keys: Vec<BTreeMap<String, String>> = Vec::new();
        for s in &selected {
            let mut k = s.axes.clone();
            k.remove("speed");
            if !keys.contains(&k) {
                keys.push(k);
            }
        }
        for key in keys {
            let mut points: Vec<Selected> = selected
                .iter()
                .filter(|s| {
                    let mut k = s.axes.clone();
                    k.remove("speed");
                    k == key
                })
                .cloned()
                .collect();
            points.sort_by(|a, b| a.speed.total_cmp(&b.speed));
            speed_series.push(speed_series_of(key, points));
        }
    }
    Report {
        study: name.into(),
        cases: cases.len(),
        converged: count(CaseStatus::Converged),
        failed: count(CaseStatus::Failed),
        not_run: records.iter().filter(|r| r.is_none()).count(),
        case_time_s: records.iter().flatten().map(|r| r.time_s).sum(),
        selected,
        speed_series,
        conditions: None,
        mesh: mesh_caption(cases.iter().map(|c| &c.settings)),
    }
}

fn o(v: Option<f64>) -> String {
    v.map(|x| x.to_string()).unwrap_or_default()
}

/// Read a study output folder (its copy of the study file and the case records), write
/// `index.csv`, `report.json`, `selected.csv` and one `speed_series_<i>.csv` per series, and the
/// condition comparison with the measures stored in the case summaries.
pub fn report_folder(folder: &Path) -> Result<Report, ReportError> {
    report_folder_with(folder, None)
}

/// [`report_folder`], with the condition measures recomputed by `recompute` (from each
/// case's solution, with the current definitions) where it succeeds.
pub fn report_folder_with(
    folder: &Path,
    recompute: Option<MeasuresOf>,
) -> Result<Report, ReportError> {
    let study_file = folder.join("study.toml");
    let study = spec::load(&study_file)?;
    let store = Store::at(folder);
    let records: Vec<Option<CaseRecord>> = study
        .cases
        .iter()
        .map(|c| store.record(&c.name))
        .collect::<Result<_, _>>()?;
    // index.csv from the records on disk (runners of single cases each wrote their view)
    store.write_index(&study.cases, &records, &spec::varying_axes(&study.cases))?;
    let mut report = build_report(&study.header.name, &study.cases, &records);
    let table = condition_table(&study, &report.selected, folder, recompute);
    // Written when at least one kept case has the measures in its summary.
    if table.rows.iter().any(|r| r.measures.is_some()) {
        report.conditions = Some(table);
    }
    write_report(folder, &report)?;
    Ok(report)
}

/// Write `report.json`, the CSV tables and the speed figures of a report into `folder`.
pub fn write_report(folder: &Path, report: &Report) -> Result<(), StoreError> {
    let p = folder.join("report.json");
    let json = serde_json::to_string_pretty(report).map_err(|e| io_err(&p, e))?;
    write_atomic(&p, json.as_bytes()).map_err(|e| io_err(&p, e))?;
    let mut s = String::from(
        "group,case,guess,speed,objective,cost_of_transport,stride_frequency,stride_length,gait\n",
    );
    for x in &report.selected {
        let _ = writeln!(
            s,
            "{},{},{},{},{},{},{},{},{}",
            x.group,
            x.case,
            x.guess,
            x.speed,
            o(x.objective),
            o(x.cost_of_transport),
            o(x.stride_frequency),
            o(x.stride_length),
            x.gait
                .map(|g| format!("{g:?}").to_lowercase())
                .unwrap_or_default()
        );
    }
    let p = folder.join("selected.csv");
    write_atomic(&p, s.as_bytes()).map_err(|e| io_err(&p, e))?;
    for (i, series) in report.speed_series.iter().enumerate() {
        let mut s = String::from(
            "speed,cost_of_transport,cot_fit,stride_frequency,stride_frequency_fit,stride_frequency_literature,gait\n",
        );
        for p in &series.points {
            let walking = series.transition_speed.is_none_or(|t| p.speed <= t + 1e-9);
            let cot_fit = if walking {
                series.cot_walking_fit.as_ref()
            } else {
                series.cot_running_fit.as_ref()
            };
            let _ = writeln!(
                s,
                "{},{},{},{},{},{},{}",
                p.speed,
                o(p.cost_of_transport),
                o(cot_fit.map(|f| f.eval(p.speed))),
                o(p.stride_frequency),
                o(series
                    .stride_frequency_walking_fit
                    .as_ref()
                    .map(|f| f.eval(p.speed))),
                literature_stride_frequency(p.speed),
                p.gait
                    .map(|g| format!("{g:?}").to_lowercase())
                    .unwrap_or_default()
            );
        }
        let p = folder.join(format!("speed_series_{i}.csv"));
        write_atomic(&p, s.as_bytes()).map_err(|e| io_err(&p, e))?;
    }
    write_speed_figures(folder, &report.speed_series, &report.mesh)?;
    if let Some(t) = &report.conditions {
        write_conditions(folder, t, &report.study)?;
    }
    Ok(())
}

/// Why a report could not be made.
#[derive(Debug, thiserror::Error)]
pub enum ReportError {
    /// The folder's study file is unusable.
    #[error(transparent)]
    Spec(#[from] spec::SpecError),
    /// Writing failed.
    #[error(transparent)]
    Store(#[from] StoreError),
}
