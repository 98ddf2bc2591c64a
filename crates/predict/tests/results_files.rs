//! Result files of a prediction: written atomically, readable as OpenSim storage files whose
//! column labels are the model's coordinate names. The "solution" here is the data-informed
//! guess (a physically meaningful walking cycle), so the files can be checked without a solve.

mod common;

use std::path::PathBuf;
use stride_model::storage::Storage;
use stride_ocp::problem::GaitProblem;
use stride_predict::{predict, results};
use stride_solve::solver::SolverOptions;

/// The data-informed walking guess on 10 intervals (`continuous`: its states at the end of
/// each interval those of the next mesh point), written as the kept solution of a
/// prediction into `<temp>/stride-<tag>-<pid>/run`.
struct GuessResults {
    model: stride_model::Model,
    problem: GaitProblem,
    solved: Vec<predict::Solved>,
    dir: PathBuf,
    out: PathBuf,
    summary: results::Summary,
}

fn guess_results(tag: &str, continuous: bool) -> GuessResults {
    let (model, problem, mut solved) = common::guess_solved(10);
    if continuous {
        common::continuous(&problem, &mut solved[0].result.x);
    }
    let dir = std::env::temp_dir().join(format!("stride-{tag}-{}", std::process::id()));
    let out = dir.join("run");
    let summary = results::write_results(
        &problem,
        &solved,
        Some(0),
        "test",
        &SolverOptions::default(),
        &out,
    )
    .unwrap();
    GuessResults {
        model,
        problem,
        solved,
        dir,
        out,
        summary,
    }
}

#[test]
fn results_are_valid_storage_files() {
    let GuessResults {
        model,
        problem,
        solved,
        dir,
        out,
        summary,
    } = guess_results("results", false);
    let motion = Storage::read(&out.join("motion.mot")).unwrap();
    assert_eq!(motion.in_degrees, Some(true));
    assert_eq!(motion.rows.len(), 20, "full cycle = 2N samples");
    for c in &model.coordinates {
        assert!(motion.column_index(&c.name).is_some(), "column {}", c.name);
    }
    assert!(motion.column_index("soleus_r/activation").is_some());
    let grf = Storage::read(&out.join("grf.mot")).unwrap();
    assert!(grf.column_index("r_ground_force_vy").is_some());
    // The experimental walking cycle starts at a heel strike and has about one body weight
    // of vertical force on average over a cycle.
    let o = summary.outcomes.unwrap();
    assert!(o.stride_length > 0.8 && o.stride_length < 2.0, "{o:?}");
    // Condition measures of the experimental kinematics: trunk sway near the subject's
    // 3.0° (range of the mean series of walking_trunk_sway.csv). The guess is not
    // dynamically consistent (the feet sink into the ground for most of the cycle), so only
    // the presence of the stance measures is checked here.
    let m = &o.conditions;
    let sway = m.trunk_sway.unwrap();
    assert!(sway > 2.0 && sway < 5.0, "trunk sway {sway}");
    for leg in [&m.right, &m.left] {
        assert!(
            leg.peak_knee_flexion.is_some()
                && leg.early_stance_ankle_plantarflexion_torque.is_some()
        );
    }
    for f in [
        "summary.json",
        "model.osim",
        "grf.xml",
        "states.sto",
        "controls.sto",
        "trajectory.sto",
        "muscle_forces.csv",
        "fiber_lengths.csv",
        "fiber_velocities.csv",
        "metabolic_power.csv",
        "joint_angles.csv",
        "activations.csv",
        "excitations.csv",
        "grf.csv",
        "trunk_sway.csv",
    ] {
        assert!(out.join(f).exists(), "{f}");
    }
    // The solver options are recorded with the results.
    let json = std::fs::read_to_string(out.join("summary.json")).unwrap();
    assert!(
        json.contains("\"solver_options\"") && json.contains("\"linear_solver\""),
        "summary.json without the solver options"
    );
    // No temporary folder left behind.
    let leftovers: Vec<_> = std::fs::read_dir(&dir)
        .unwrap()
        .filter_map(|e| e.ok())
        .filter(|e| e.file_name().to_string_lossy().contains("partial"))
        .collect();
    assert!(leftovers.is_empty());

    // Rewriting the folder from the same solution gives back the cycle files as written
    // (here: a table edited by hand, the outcomes removed from summary.json), keeps the
    // other files (the solver log, a user's note and subfolder) and lets the caller add files.
    let angles = std::fs::read_to_string(out.join("joint_angles.csv")).unwrap();
    let log = std::fs::read_to_string(out.join("solver_log_data-informed-walking.csv")).unwrap();
    std::fs::write(out.join("joint_angles.csv"), "stale").unwrap();
    std::fs::write(out.join("note.txt"), "kept").unwrap();
    std::fs::create_dir(out.join("notes")).unwrap();
    std::fs::write(out.join("notes").join("a.txt"), "kept too").unwrap();
    let mut summary_json: serde_json::Value = serde_json::from_str(&json).unwrap();
    summary_json["outcomes"] = serde_json::Value::Null;
    std::fs::write(out.join("summary.json"), summary_json.to_string()).unwrap();
    let x = &solved[0].result.x;
    let rewritten = results::rewrite_results(&problem, x, &out, |cycle, tmp| {
        std::fs::write(tmp.join("extra.txt"), format!("{}", cycle.time.len())).unwrap();
        Ok(())
    })
    .unwrap();
    assert_eq!(rewritten.stride_length, o.stride_length);
    assert_eq!(
        std::fs::read_to_string(out.join("joint_angles.csv")).unwrap(),
        angles
    );
    assert_eq!(
        std::fs::read_to_string(out.join("solver_log_data-informed-walking.csv")).unwrap(),
        log
    );
    assert_eq!(
        std::fs::read_to_string(out.join("note.txt")).unwrap(),
        "kept"
    );
    assert_eq!(
        std::fs::read_to_string(out.join("notes").join("a.txt")).unwrap(),
        "kept too"
    );
    assert_eq!(
        std::fs::read_to_string(out.join("extra.txt")).unwrap(),
        "20"
    );
    let after: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("summary.json")).unwrap()).unwrap();
    assert_eq!(
        after["outcomes"]["stride_length"].as_f64(),
        Some(o.stride_length)
    );
    assert_eq!(after["guesses"][0]["guess"], "data-informed-walking");
    // A failure while rewriting leaves the folder as it was, with no temporary folder.
    std::fs::write(out.join("joint_angles.csv"), "stale").unwrap();
    let e = results::rewrite_results(&problem, x, &out, |_, tmp| {
        Err(stride_predict::error::PredictError::Write {
            path: tmp.display().to_string(),
            reason: "test".into(),
        })
    })
    .unwrap_err();
    assert!(e.to_string().contains("test"), "{e}");
    assert_eq!(
        std::fs::read_to_string(out.join("joint_angles.csv")).unwrap(),
        "stale"
    );
    let names: Vec<String> = std::fs::read_dir(&dir)
        .unwrap()
        .filter_map(|e| e.ok())
        .map(|e| e.file_name().to_string_lossy().into_owned())
        .collect();
    assert_eq!(names, ["run"], "only the result folder remains");
    // A folder without summary.json is an error that names the file.
    std::fs::remove_file(out.join("summary.json")).unwrap();
    let e = results::rewrite_results(&problem, x, &out, |_, _| Ok(())).unwrap_err();
    assert!(e.to_string().starts_with("reading ") && e.to_string().contains("summary.json"));
    std::fs::remove_dir_all(&dir).unwrap();
}

/// Units are in every CSV header and in `summary.json`; the states file names OpenSim 4
/// state paths and holds the motion's coordinates in radians.
#[test]
fn tables_carry_units_and_states_carry_opensim_paths() {
    let r = guess_results("units", false);
    let header = |f: &str| {
        let text = std::fs::read_to_string(r.out.join(f)).unwrap();
        text.lines().next().unwrap().to_string()
    };
    for f in [
        "joint_angles.csv",
        "joint_torques.csv",
        "joint_powers.csv",
        "activations.csv",
        "excitations.csv",
        "grf.csv",
        "trunk_sway.csv",
        "muscle_forces.csv",
        "fiber_lengths.csv",
        "fiber_velocities.csv",
        "metabolic_power.csv",
        "muscle_torques.csv",
        "passive_torques.csv",
        "actuator_torques.csv",
    ] {
        let h = header(f);
        assert!(h.starts_with("time [s],"), "{f}: {h}");
        assert!(h.split(',').all(|c| c.ends_with(']')), "{f}: {h}");
    }
    assert!(header("joint_angles.csv").contains(",knee_angle_r [deg],"));
    assert!(header("joint_angles.csv").contains(",pelvis_tx [m],"));
    assert!(header("joint_torques.csv").contains(",knee_angle_r [N m],"));
    assert!(header("muscle_forces.csv").contains(",soleus_r [N],"));
    assert_eq!(header("muscle_torques.csv"), header("joint_torques.csv"));
    // the built-in model has no ligaments
    assert!(!r.out.join("ligament_torques.csv").exists());
    assert!(!r.out.join("ligament_lengths.csv").exists());
    let json: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(r.out.join("summary.json")).unwrap())
            .unwrap();
    for key in r.summary.outcomes.iter().flat_map(|o| {
        serde_json::to_value(o)
            .unwrap()
            .as_object()
            .unwrap()
            .keys()
            .cloned()
            .collect::<Vec<_>>()
    }) {
        if key != "right" && key != "left" {
            assert!(json["units"][&key].is_string(), "no unit for {key}");
        }
    }
    let states = Storage::read(&r.out.join("states.sto")).unwrap();
    let motion = Storage::read(&r.out.join("motion.mot")).unwrap();
    assert_eq!(states.in_degrees, Some(false));
    let knee = states
        .column("/jointset/knee_r/knee_angle_r/value")
        .unwrap();
    let knee_deg = motion.column("knee_angle_r").unwrap();
    for (a, b) in knee.iter().zip(&knee_deg) {
        assert!((a.to_degrees() - b).abs() < 1e-9);
    }
    assert!(states.column("/forceset/soleus_r/activation").is_some());
    assert!(states.column("/forceset/soleus_r/fiber_length").is_some());
    let controls = Storage::read(&r.out.join("controls.sto")).unwrap();
    assert!(controls.column("/forceset/soleus_r").is_some());
    assert!(controls.column("/forceset/arm_flex_r_torque").is_some());
    std::fs::remove_dir_all(&r.dir).unwrap();
}

/// Whenever a foot carries load, its centre of pressure in `grf.mot` lies under that foot:
/// within the ground-plane footprint of the foot's contact spheres that are at or near the
/// ground (1 cm margin, plus the shift of tangential forces acting below the plane), placed
/// by the model's kinematics at the coordinates of `motion.mot` (an independent route:
/// forward kinematics of the written motion, not the contact moments).
#[test]
fn each_foot_centre_of_pressure_lies_under_that_foot() {
    use stride_multibody::{forward_kinematics, point_position, Data};
    let r = guess_results("cop", true);
    let model = &r.model;
    let motion = Storage::read(&r.out.join("motion.mot")).unwrap();
    let grf = Storage::read(&r.out.join("grf.mot")).unwrap();
    assert_eq!(motion.rows.len(), grf.rows.len());
    let mut data = Data::<f64>::new(model).unwrap();
    let nc = model.coordinates.len();
    let mut checked = [0usize; 2];
    for (row, forces) in motion.rows.iter().zip(&grf.rows) {
        let q: Vec<f64> = model
            .coordinates
            .iter()
            .map(|c| {
                let v = row[motion.column_index(&c.name).unwrap()];
                if c.motion_type == stride_model::MotionType::Rotational {
                    v.to_radians()
                } else {
                    v
                }
            })
            .collect();
        forward_kinematics(model, &mut data, &q, &vec![0.0; nc]).unwrap();
        for (k, side) in ["r", "l"].iter().enumerate() {
            let col = |c: &str| {
                forces[grf
                    .column_index(&format!("{side}_ground_force_{c}"))
                    .unwrap()]
            };
            if col("vy") < 20.0 {
                continue;
            }
            let spheres: Vec<([f64; 3], f64)> = model
                .contacts
                .iter()
                .filter(|c| model.bodies[c.body].name.ends_with(&format!("_{side}")))
                .map(|c| (point_position(&data, c.body, c.location), c.radius))
                .collect();
            assert_eq!(spheres.len(), 6);
            // spheres whose lowest point is within 2 cm of the ground carry the load
            let near: Vec<[f64; 3]> = spheres
                .iter()
                .filter(|(p, rad)| p[1] - rad < 0.02)
                .map(|(p, _)| *p)
                .collect();
            assert!(
                !near.is_empty(),
                "{side} foot loaded with no sphere near the ground"
            );
            // A contact force acts midway through its sphere's overlap with the ground: its
            // tangential part, applied that far below the ground plane, moves the centre of
            // pressure on the plane by depth × tangential / normal force.
            let depth = spheres
                .iter()
                .map(|(p, rad)| 0.5 * (rad - p[1]).max(0.0))
                .fold(0.0, f64::max);
            for (axis, c, f) in [(0, "px", "vx"), (2, "pz", "vz")] {
                let margin = 0.01 + depth * col(f).abs() / col("vy");
                let lo = near.iter().map(|p| p[axis]).fold(f64::INFINITY, f64::min);
                let hi = near
                    .iter()
                    .map(|p| p[axis])
                    .fold(f64::NEG_INFINITY, f64::max);
                let cop = col(c);
                assert!(
                    cop > lo - margin && cop < hi + margin,
                    "t = {}: {side} centre of pressure {c} = {cop:.3} m outside the foot's \
                     contact spheres [{lo:.3}, {hi:.3}] m (force {:.0} N; spheres {spheres:?})",
                    row[0],
                    col("vy")
                );
            }
            checked[k] += 1;
        }
    }
    assert!(
        checked[0] > 3 && checked[1] > 3,
        "loaded samples {checked:?}"
    );
    std::fs::remove_dir_all(&r.dir).unwrap();
}

/// `write_results` on the data-informed walking guess (no solve) writes the figures
/// next to the tables.
#[test]
fn write_results_writes_the_figures() {
    let (_, problem, solved) = common::guess_solved(10);
    let dir = std::env::temp_dir().join(format!("stride-figures-{}", std::process::id()));
    let out = dir.join("run");
    results::write_results(
        &problem,
        &solved,
        Some(0),
        "test",
        &SolverOptions::default(),
        &out,
    )
    .unwrap();
    for name in ["figure_kinematics", "figure_kinetics", "figure_activations"] {
        let svg = std::fs::read_to_string(out.join(format!("{name}.svg"))).unwrap();
        stride_plot::png::parse_svg(&svg).unwrap();
        let png = std::fs::read(out.join(format!("{name}.png"))).unwrap();
        assert_eq!(&png[1..4], b"PNG", "{name}");
    }
    // The tables still hold one row per sample of the 2N-sample cycle.
    let angles = std::fs::read_to_string(out.join("joint_angles.csv")).unwrap();
    assert_eq!(angles.lines().count(), 1 + 20);
    std::fs::remove_dir_all(&dir).unwrap();
}
