//! Result folders open in OpenSim 4 as they are, checked with OpenSim's own Python bindings
//! by `tools/opensim_reference/check_result_folder.py`.
//!
//! - With OpenSim available (`STRIDE_OPENSIM_PYTHON`, else `/work/venv-opensim/bin/python`),
//!   the script checks a folder written here from the data-informed walking guess: the model
//!   loads, the states file's labels are state paths of that model, the controls' are its
//!   actuators, the Moco trajectory reads, `grf.xml` loads as ExternalLoads, OpenSim's
//!   inverse dynamics from the trajectory's accelerations reproduces `joint_torques.csv`
//!   within 5 % of each torque's range, and each loaded foot's centre of pressure lies under
//!   it. (The guess is not dynamically consistent, but the torques are its inverse dynamics;
//!   only the tool that differentiates `motion.mot` is not compared here: the guess's
//!   accelerations are not those of its motion.)
//! - The script's output for the nominal prediction (`stride predict`, 50 intervals) is
//!   committed in `tools/opensim_reference/checked/` (see its README); this test checks that
//!   OpenSim's inverse dynamics of that folder (its model, `grf.mot` through `grf.xml`, and
//!   the coordinate values, speeds and accelerations of `trajectory.sto`) reproduced
//!   `joint_torques.csv` within 5 % of each torque's range (hip, knee, ankle, subtalar,
//!   lumbar), that the centre of pressure of each loaded foot lay under that foot, and that
//!   OpenSim's InverseDynamicsTool, which differentiates splines through `motion.mot`
//!   instead, stayed within 8 % (the collocation's accelerations jump at heel strike), so a
//!   change of the recorded agreement shows in review.

mod common;

use std::path::{Path, PathBuf};
use std::process::Command;
use stride_predict::results;
use stride_solve::solver::SolverOptions;

fn repo() -> PathBuf {
    PathBuf::from(concat!(env!("CARGO_MANIFEST_DIR"), "/../.."))
}

fn opensim_python() -> Option<PathBuf> {
    let p = std::env::var_os("STRIDE_OPENSIM_PYTHON")
        .map(PathBuf::from)
        .unwrap_or_else(|| PathBuf::from("/work/venv-opensim/bin/python"));
    let ok = Command::new(&p)
        .args(["-c", "import opensim"])
        .output()
        .is_ok_and(|o| o.status.success());
    if ok {
        Some(p)
    } else {
        eprintln!(
            "skipping: no OpenSim Python at {} (set STRIDE_OPENSIM_PYTHON)",
            p.display()
        );
        None
    }
}

/// The data-informed walking guess on 10 intervals, with the states at the end of each
/// interval those of the next mesh point (as in any solution), written as a result folder
/// in `out`.
fn write_guess_folder(out: &Path) {
    let (_, problem, mut solved) = common::guess_solved(10);
    common::continuous(&problem, &mut solved[0].result.x);
    results::write_results(
        &problem,
        &solved,
        Some(0),
        "test",
        &SolverOptions::default(),
        out,
    )
    .unwrap();
}

#[test]
fn opensim_opens_a_result_folder() {
    let Some(python) = opensim_python() else {
        return;
    };
    let dir = std::env::temp_dir().join(format!("stride-opensim-{}", std::process::id()));
    let out = dir.join("run");
    write_guess_folder(&out);
    let script = repo().join("tools/opensim_reference/check_result_folder.py");
    let o = Command::new(python)
        .arg(&script)
        .arg(&out)
        .current_dir(&dir)
        .output()
        .unwrap();
    let stdout = String::from_utf8_lossy(&o.stdout);
    let last = stdout.lines().last().unwrap_or_default();
    let checks: serde_json::Value = serde_json::from_str(last)
        .unwrap_or_else(|e| panic!("{e}: {stdout}\n{}", String::from_utf8_lossy(&o.stderr)));
    for key in [
        "model_loads",
        "states_are_paths",
        "controls_are_paths",
        "moco_trajectory",
        "external_loads",
        "inverse_dynamics_within_tolerance",
        "center_of_pressure_under_foot",
    ] {
        assert_eq!(checks[key], true, "{key}: {checks}");
    }
    eprintln!(
        "OpenSim inverse dynamics of the guess folder: at most {} of a torque's range",
        checks["inverse_dynamics_worst"]
    );
    assert!(checks["states_columns"].as_u64().unwrap() > 2 * 31);
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn recorded_opensim_inverse_dynamics_agrees_with_the_joint_torques() {
    let f = repo().join("tools/opensim_reference/checked/predict_nominal.json");
    let v: serde_json::Value = serde_json::from_str(&std::fs::read_to_string(&f).unwrap()).unwrap();
    for key in [
        "model_loads",
        "states_are_paths",
        "controls_are_paths",
        "moco_trajectory",
        "external_loads",
    ] {
        assert_eq!(v[key], true, "{}: {key}", f.display());
    }
    let id = v["inverse_dynamics"].as_object().unwrap();
    let mut names: Vec<String> = ["r", "l"]
        .iter()
        .flat_map(|side| {
            [
                "hip_flexion",
                "hip_adduction",
                "hip_rotation",
                "knee_angle",
                "ankle_angle",
                "subtalar_angle",
            ]
            .map(|c| format!("{c}_{side}"))
        })
        .collect();
    names.extend(["lumbar_extension", "lumbar_bending", "lumbar_rotation"].map(String::from));
    let tool = v["inverse_dynamics_tool"].as_object().unwrap();
    for name in names {
        let with_accelerations = id[&name]["fraction_of_range"].as_f64().unwrap();
        assert!(
            with_accelerations <= 0.05,
            "{name} differs by {with_accelerations} of its range"
        );
        // from splines through the motion: the heel-strike impact is not followed
        let splined = tool[&name]["fraction_of_range"].as_f64().unwrap();
        assert!(splined <= 0.08, "{name} differs by {splined} of its range");
    }
    assert_eq!(v["center_of_pressure_under_foot"], true, "{}", f.display());
    for side in ["r", "l"] {
        let c = &v["center_of_pressure"][side];
        assert!(c["loaded_samples"].as_u64().unwrap() > 20, "{side}: {c}");
        assert!(
            c["max_distance_outside"].as_f64().unwrap() <= 0.01,
            "{side}: {c}"
        );
    }
}
