//! The joint-angle columns of a trial in the model's terms: a column named by an OpenSim 4
//! state path (`/jointset/<joint>/<coordinate>/value`, as Moco and stride's `states.sto`
//! write them) is renamed to its coordinate, and a coordinate that a
//! `CoordinateCouplerConstraint` computes from another is appended when the motion lacks it
//! (as OpenSim's assembly of a pose does).

use super::trial::TrialError;
use stride_model::storage::Storage;
use stride_model::{Model, MotionType};

/// The coordinate named by the state path `label` (`/jointset/<joint>/<coordinate>/value`),
/// or `None` for any other label (plain names, speeds, muscle states).
pub fn state_path_coordinate(label: &str) -> Option<&str> {
    let rest = label.strip_prefix("/jointset/")?.strip_suffix("/value")?;
    match rest.split('/').collect::<Vec<_>>()[..] {
        [joint, coordinate] if !joint.is_empty() && !coordinate.is_empty() => Some(coordinate),
        _ => None,
    }
}

/// `motion` with its state-path columns renamed to their coordinates and the coupled
/// coordinates of `model` it lacks appended (in the units of the file: degrees for
/// rotations when it is in degrees); `file` names it in messages.
pub fn motion_for_model(
    motion: &Storage,
    model: &Model,
    file: &str,
) -> Result<Storage, TrialError> {
    let mut out = motion.clone();
    for i in 0..out.labels.len() {
        let Some(c) = state_path_coordinate(&out.labels[i]).map(str::to_string) else {
            continue;
        };
        if out.labels.contains(&c) {
            return Err(TrialError::DuplicateColumn {
                file: file.into(),
                column: out.labels[i].clone(),
                coordinate: c,
            });
        }
        out.labels[i] = c;
    }
    append_coupled(&mut out, model, file)?;
    Ok(out)
}

/// Appends to `motion` the column of every coupled coordinate of `model` it lacks,
/// computed from its independent coordinate's column by the constraint's function.
fn append_coupled(motion: &mut Storage, model: &Model, file: &str) -> Result<(), TrialError> {
    let in_degrees = motion.in_degrees.unwrap_or(true);
    let to_file =
        |c: usize| match in_degrees && model.coordinates[c].motion_type == MotionType::Rotational {
            true => 180.0 / std::f64::consts::PI,
            false => 1.0,
        };
    for cp in &model.couplers {
        let dependent = &model.coordinates[cp.dependent].name;
        let independent = &model.coordinates[cp.independent].name;
        if motion.column(dependent).is_some() {
            continue;
        }
        let Some(x) = motion.column(independent) else {
            continue;
        };
        let f = cp.function.compile().map_err(|e| TrialError::Coupled {
            file: file.into(),
            coordinate: dependent.clone(),
            constraint: cp.name.clone(),
            reason: e.to_string(),
        })?;
        let (fi, fd) = (to_file(cp.independent), to_file(cp.dependent));
        motion.labels.push(dependent.clone());
        for (row, v) in motion.rows.iter_mut().zip(x) {
            row.push(f.eval_f64(v / fi)[0] * fd);
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use stride_model::{Coordinate, CoordinateCoupler, Function};

    /// A model of two rotational coordinates, `knee` and `patella`, with
    /// `patella = 0.5 knee² + 2 knee + 0.1` [rad].
    fn coupled_model() -> Model {
        let coordinate = |name: &str| Coordinate {
            name: name.into(),
            joint: 0,
            motion_type: MotionType::Rotational,
            range: [-3.0, 3.0],
            default_value: 0.0,
            locked: false,
        };
        Model {
            coordinates: vec![coordinate("knee"), coordinate("patella")],
            couplers: vec![CoordinateCoupler {
                name: "patella_coupler".into(),
                dependent: 1,
                independent: 0,
                function: Function::Polynomial {
                    coefficients: vec![0.5, 2.0, 0.1],
                },
            }],
            ..Model::default()
        }
    }

    fn storage(labels: &[&str], in_degrees: bool, rows: Vec<Vec<f64>>) -> Storage {
        Storage {
            name: "motion".into(),
            in_degrees: Some(in_degrees),
            labels: labels.iter().map(|l| l.to_string()).collect(),
            rows,
        }
    }

    #[test]
    fn a_coupled_coordinate_missing_from_the_motion_is_computed_in_the_files_units() {
        let model = coupled_model();
        let rows = vec![vec![0.0, 30.0], vec![0.1, -45.0]];
        let m = motion_for_model(&storage(&["time", "knee"], true, rows), &model, "m.mot").unwrap();
        let patella = m.column("patella").unwrap();
        for (deg, got) in [30.0_f64, -45.0].iter().zip(&patella) {
            let x = deg.to_radians();
            let want = (0.5 * x * x + 2.0 * x + 0.1).to_degrees();
            assert!((got - want).abs() < 1e-9, "{got} against {want}");
        }
        let rows = vec![vec![0.0, 0.3]];
        let m =
            motion_for_model(&storage(&["time", "knee"], false, rows), &model, "m.sto").unwrap();
        let want = 0.5 * 0.09 + 0.6 + 0.1;
        assert!((m.column("patella").unwrap()[0] - want).abs() < 1e-12);
    }

    #[test]
    fn a_coupled_coordinate_the_motion_has_is_kept_as_measured() {
        let rows = vec![vec![0.0, 30.0, 7.0]];
        let s = storage(&["time", "knee", "patella"], true, rows);
        let m = motion_for_model(&s, &coupled_model(), "m.mot").unwrap();
        assert_eq!(m, s);
    }

    #[test]
    fn state_path_columns_are_renamed_and_a_duplicate_is_an_error_naming_both() {
        let path = "/jointset/knee_joint/knee/value";
        let rows = vec![vec![0.0, 0.2, 1.0]];
        let s = storage(
            &["time", path, "/jointset/knee_joint/knee/speed"],
            false,
            rows,
        );
        let m = motion_for_model(&s, &coupled_model(), "states.sto").unwrap();
        assert_eq!(m.labels[1], "knee");
        assert_eq!(m.labels[2], "/jointset/knee_joint/knee/speed");
        assert!(m.column("patella").is_some());
        let s = storage(&["time", "knee", path], false, vec![vec![0.0, 0.2, 0.2]]);
        let e = motion_for_model(&s, &coupled_model(), "states.sto").unwrap_err();
        let m = e.to_string();
        assert!(
            m.contains("states.sto") && m.contains(path) && m.contains("`knee`"),
            "{m}"
        );
    }

    #[test]
    fn state_paths_name_their_coordinate_and_other_labels_none() {
        let c = state_path_coordinate("/jointset/hip_r/hip_flexion_r/value");
        assert_eq!(c, Some("hip_flexion_r"));
        assert_eq!(
            state_path_coordinate("/jointset/hip_r/hip_flexion_r/speed"),
            None
        );
        assert_eq!(state_path_coordinate("hip_flexion_r"), None);
        assert_eq!(state_path_coordinate("/forceset/soleus_r/activation"), None);
        assert_eq!(state_path_coordinate("/jointset//value"), None);
    }
}
