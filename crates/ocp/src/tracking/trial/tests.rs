use super::*;
use crate::tracking::feet::foot_columns;
use stride_model::default_model::default_model;

#[test]
fn gait2392_pipeline_forces_equal_the_data_file_columns_of_each_foot() {
    let root = Path::new(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../../../shared/reference/models/opensim/gait2392_pipeline"
    ));
    if !root.is_dir() {
        eprintln!("skipped: {} is absent", root.display());
        return;
    }
    let files = TrialFiles::read(
        &root.join("subject01_walk1_ik.mot"),
        &root.join("subject01_walk1_grf.xml"),
        None,
    )
    .unwrap();
    let loads = files.loads.as_ref().unwrap();
    let columns = foot_columns(loads, &default_model()).unwrap();
    let grf = Trial::ground_reactions(&files, &columns, [0.6, 2.0]).unwrap();
    // the data file read on its own; the xml applies `ground_*` to calcn_r, `1_ground_*`
    // to calcn_l
    let data = Storage::read(&root.join("subject01_walk1_grf.mot")).unwrap();
    let col = |c: &str| data.column(c).unwrap();
    let time = data.time();
    for row in [400, 700, 1150] {
        let (f, m) = grf.at(time[row], 0.25);
        for (foot, prefix) in [(0, ""), (1, "1_")] {
            let v = |c: &str| col(&format!("{prefix}{c}"))[row];
            let force = [
                v("ground_force_vx"),
                v("ground_force_vy"),
                v("ground_force_vz"),
            ];
            let p = [
                v("ground_force_px") - 0.25,
                v("ground_force_py"),
                v("ground_force_pz"),
            ];
            let t = [
                v("ground_torque_x"),
                v("ground_torque_y"),
                v("ground_torque_z"),
            ];
            let moment = [
                p[1] * force[2] - p[2] * force[1] + t[0],
                p[2] * force[0] - p[0] * force[2] + t[1],
                p[0] * force[1] - p[1] * force[0] + t[2],
            ];
            for k in 0..3 {
                assert!(
                    (f[3 * foot + k] - force[k]).abs() < 1e-9,
                    "row {row} foot {foot}"
                );
                assert!(
                    (m[3 * foot + k] - moment[k]).abs() < 1e-9,
                    "row {row} foot {foot}"
                );
            }
        }
        assert!(f[1] > 0.0 || f[4] > 0.0, "row {row}: no vertical force");
    }
}

#[test]
fn an_empty_or_reversed_window_is_an_error_saying_so() {
    let time = [0.0, 1.0, 2.0];
    for w in [[1.0, 1.0], [1.5, 0.5]] {
        let m = check_window("m.mot", &time, w).unwrap_err().to_string();
        assert!(m.contains("empty or reversed"), "{m}");
    }
    assert!(check_window("m.mot", &time, [0.25, 0.75]).is_ok());
    let m = check_window("m.mot", &time, [0.5, 2.5])
        .unwrap_err()
        .to_string();
    assert!(
        m.contains("m.mot") && m.contains("not inside the data"),
        "{m}"
    );
}
