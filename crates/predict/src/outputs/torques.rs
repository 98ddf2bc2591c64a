//! The terms of the torque balances over a gait cycle, one table per source with the
//! columns of `joint_torques.csv`: on every coordinate the inverse-dynamics generalised
//! force equals muscle + passive + actuator (+ ligament) torques, to the solver's
//! tolerance. Ligament tables are written only for a model with ligaments.

use super::tables::{csv, write_file};
use crate::error::PredictError;
use crate::figures::CycleTables;
use std::path::Path;
use stride_model::Model;
use stride_ocp::node::SampleOutputs;

/// Write `muscle_torques.csv`, `passive_torques.csv`, `actuator_torques.csv` and, when
/// `model` has ligaments, `ligament_torques.csv` (generalised forces per coordinate [N m or
/// N]), `ligament_lengths.csv` [m] and `ligament_forces.csv` [N] (per ligament) from the
/// node outputs `samples` of every cycle sample.
pub(super) fn write_torque_tables(
    t: &CycleTables,
    model: &Model,
    samples: &[SampleOutputs],
    dir: &Path,
) -> Result<(), PredictError> {
    type Column = fn(&SampleOutputs) -> &Vec<f64>;
    let has_ligaments = !model.ligaments.is_empty();
    let mut tables: Vec<(&str, Column)> = vec![
        ("muscle_torques.csv", |s| &s.muscle),
        ("passive_torques.csv", |s| &s.passive),
        ("actuator_torques.csv", |s| &s.actuator),
    ];
    if has_ligaments {
        tables.push(("ligament_torques.csv", |s| &s.ligament));
    }
    let units: Vec<&str> = (0..t.coordinates.len())
        .map(|i| match t.rotational.get(i) {
            Some(false) => "N",
            _ => "N m",
        })
        .collect();
    let rows =
        |column: Column| -> Vec<Vec<f64>> { samples.iter().map(|s| column(s).clone()).collect() };
    for (file, column) in tables {
        write_file(
            dir,
            file,
            &csv(&t.coordinates, &units, &t.time, &rows(column)),
        )?;
    }
    if has_ligaments {
        let names: Vec<String> = model.ligaments.iter().map(|l| l.name.clone()).collect();
        let per_ligament: [(&str, &str, Column); 2] = [
            ("ligament_lengths.csv", "m", |s| &s.ligament_length),
            ("ligament_forces.csv", "N", |s| &s.ligament_force),
        ];
        for (file, unit, column) in per_ligament {
            let units = vec![unit; names.len()];
            write_file(dir, file, &csv(&names, &units, &t.time, &rows(column)))?;
        }
    }
    Ok(())
}
