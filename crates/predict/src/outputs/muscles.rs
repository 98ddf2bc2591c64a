//! Per-muscle tables of a gait cycle: tendon force, fibre length and velocity, metabolic
//! power.

use super::tables::{csv, write_file};
use crate::error::PredictError;
use crate::figures::CycleTables;
use std::path::Path;
use stride_ocp::node::SampleOutputs;

/// Write `muscle_forces.csv` (tendon force [N]), `fiber_lengths.csv` [m],
/// `fiber_velocities.csv` (lengthening positive [m s⁻¹]) and `metabolic_power.csv`
/// (Bhargava et al. 2004 rate of each muscle [W], the model of the reported cost of
/// transport) from the node outputs `samples` of every cycle sample.
pub(super) fn write_muscle_tables(
    t: &CycleTables,
    samples: &[SampleOutputs],
    dir: &Path,
) -> Result<(), PredictError> {
    type Column = fn(&SampleOutputs) -> &Vec<f64>;
    let tables: [(&str, &str, Column); 4] = [
        ("muscle_forces.csv", "N", |s| &s.tendon_force),
        ("fiber_lengths.csv", "m", |s| &s.fiber_length),
        ("fiber_velocities.csv", "m/s", |s| &s.fiber_velocity),
        ("metabolic_power.csv", "W", |s| &s.metabolic_bhargava),
    ];
    let units_of = |u: &'static str| vec![u; t.muscles.len()];
    for (file, unit, column) in tables {
        let rows: Vec<Vec<f64>> = samples.iter().map(|s| column(s).clone()).collect();
        write_file(dir, file, &csv(&t.muscles, &units_of(unit), &t.time, &rows))?;
    }
    Ok(())
}
