//! CSV tables of a gait cycle: one row per sample, the unit of every column in its header
//! (`hip_flexion_r [deg]`).

use crate::error::{write_err, PredictError};
use crate::figures::CycleTables;
use std::collections::BTreeMap;
use std::fmt::Write as _;
use std::path::Path;
use stride_files::write_atomic;

/// The name of a table column without its unit: `hip_flexion_r [deg]` → `hip_flexion_r`.
pub fn column_name(header: &str) -> &str {
    header
        .find(" [")
        .map_or(header, |i| &header[..i])
        .trim_end()
}

/// CSV text: a `time [s]` column, then one column per label with its unit, one row per
/// sample.
pub(super) fn csv(labels: &[String], units: &[&str], time: &[f64], rows: &[Vec<f64>]) -> String {
    let mut s = String::from("time [s]");
    for (l, u) in labels.iter().zip(units) {
        let _ = write!(s, ",{l} [{u}]");
    }
    s.push('\n');
    for (t, r) in time.iter().zip(rows) {
        let _ = write!(s, "{t}");
        for v in r {
            let _ = write!(s, ",{v}");
        }
        s.push('\n');
    }
    s
}

/// Write `text` to `dir/file`.
pub(super) fn write_file(dir: &Path, file: &str, text: &str) -> Result<(), PredictError> {
    let p = dir.join(file);
    write_atomic(&p, text.as_bytes()).map_err(|e| write_err(&p, e))
}

/// Write the joint angle, torque and power tables, activations, excitations, ground
/// reaction forces and the trunk sway.
pub(super) fn write_tables(t: &CycleTables, dir: &Path) -> Result<(), PredictError> {
    let n = t.coordinates.len();
    let rotational = |i: usize| t.rotational.get(i).copied().unwrap_or(true);
    let per_coordinate = |rot: &'static str, trans: &'static str| -> Vec<&'static str> {
        (0..n)
            .map(|i| if rotational(i) { rot } else { trans })
            .collect()
    };
    let dimensionless = vec!["-"; t.muscles.len()];
    let percent_bw = vec!["% BW"; t.grf_labels.len()];
    for (file, labels, units, rows) in [
        (
            "joint_angles.csv",
            &t.coordinates,
            per_coordinate("deg", "m"),
            &t.angles,
        ),
        (
            "joint_torques.csv",
            &t.coordinates,
            per_coordinate("N m", "N"),
            &t.torques,
        ),
        (
            "joint_powers.csv",
            &t.coordinates,
            per_coordinate("W", "W"),
            &t.powers,
        ),
        (
            "activations.csv",
            &t.muscles,
            dimensionless.clone(),
            &t.activations,
        ),
        ("excitations.csv", &t.muscles, dimensionless, &t.excitations),
        ("grf.csv", &t.grf_labels, percent_bw, &t.grf_bw),
    ] {
        write_file(dir, file, &csv(labels, &units, &t.time, rows))?;
    }
    // Torso rotation about the forward axis over the cycle (its range is the trunk sway).
    if let Some(angles) = &t.trunk_sway {
        let rows: Vec<Vec<f64>> = angles.iter().map(|&a| vec![a]).collect();
        let text = csv(&["trunk_sway".to_string()], &["deg"], &t.time, &rows);
        write_file(dir, "trunk_sway.csv", &text)?;
    }
    Ok(())
}

/// Units of the outcome measures in `summary.json` (key → unit; `-` for dimensionless
/// numbers and counts), recorded there as the `units` table.
pub fn summary_units() -> BTreeMap<&'static str, &'static str> {
    [
        ("body_mass", "kg"),
        ("cost_of_transport", "J kg^-1 m^-1"),
        ("cost_of_transport_cost_model", "J kg^-1 m^-1"),
        ("stride_length", "m"),
        ("step_width", "m"),
        ("stride_frequency", "strides s^-1"),
        ("speed", "m s^-1"),
        ("cycle_duration", "s"),
        ("stance_fraction_right", "fraction of the cycle"),
        ("stance_fraction_left", "fraction of the cycle"),
        ("double_support_fraction", "fraction of the cycle"),
        ("stance_phases_right", "-"),
        ("vertical_grf_peaks_right", "-"),
        ("trunk_sway", "deg"),
        ("peak_knee_flexion", "deg"),
        ("peak_ankle_dorsiflexion", "deg"),
        ("peak_hip_abduction_torque", "N m kg^-1"),
        ("peak_ankle_plantarflexion_torque", "N m kg^-1"),
        ("early_stance_ankle_plantarflexion_torque", "N m kg^-1"),
        ("stance_fraction", "fraction of the cycle"),
        ("objective", "-"),
        ("constraint_violation", "-"),
    ]
    .into_iter()
    .collect()
}

#[cfg(test)]
mod tests {
    use super::column_name;

    #[test]
    fn column_names_drop_the_unit() {
        assert_eq!(column_name("hip_flexion_r [deg]"), "hip_flexion_r");
        assert_eq!(column_name("right_x [% BW]"), "right_x");
        assert_eq!(column_name("trunk_sway"), "trunk_sway");
    }
}
