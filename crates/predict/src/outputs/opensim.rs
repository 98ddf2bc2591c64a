//! Result files that OpenSim 4 and Moco open as they are: the model, the motion, the ground
//! reactions with their external-loads description, and states and controls named by their
//! OpenSim component paths.

use super::tables::write_file;
use crate::error::{write_err, PredictError};
use std::path::Path;
use stride_model::default_model::{default_model, DEFAULT_MODEL_OSIM};
use stride_model::storage::Storage;
use stride_model::{Model, MotionType};
use stride_ocp::gait::Actuation;
use stride_ocp::node::SampleOutputs;
use stride_ocp::problem::GaitProblem;
use stride_ocp::trajectory::Trajectory;

/// The model that produced the result (a copy of the user's `.osim`, or the built-in model).
pub const MODEL_FILE: &str = "model.osim";
/// Coordinates [deg or m] of every model coordinate and muscle activations over the cycle.
pub const MOTION_FILE: &str = "motion.mot";
/// Ground reaction force, centre of pressure and free moment of each foot, in ground.
pub const GRF_FILE: &str = "grf.mot";
/// OpenSim `ExternalLoads` applying `grf.mot` to `calcn_r` and `calcn_l`.
pub const GRF_XML_FILE: &str = "grf.xml";
/// OpenSim inverse-dynamics setup of the folder (`opensim-cmd run-tool id_setup.xml`).
pub const ID_SETUP_FILE: &str = "id_setup.xml";
/// Folder (inside the result folder) where the inverse-dynamics setup writes its torques.
pub const ID_RESULTS_DIR: &str = "inverse_dynamics";
/// Coordinate values and speeds, muscle activations and fibre lengths (OpenSim state paths).
pub const STATES_FILE: &str = "states.sto";
/// Muscle excitations and arm actuator controls (OpenSim actuator paths).
pub const CONTROLS_FILE: &str = "controls.sto";
/// States, controls and coordinate accelerations (Moco derivatives) in one file with the
/// header of a Moco trajectory.
pub const TRAJECTORY_FILE: &str = "trajectory.sto";

/// Contact groups written to `grf.mot`: column prefix and the foot body the loads act on.
const FEET: [(&str, &str); 2] = [("r", "calcn_r"), ("l", "calcn_l")];

/// Every model coordinate [rad or m] (model order) of one sample whose problem coordinates
/// are `q`: locked coordinates at the value the problem holds them at, coupled ones at
/// their constraint's value, coordinates the problem does not use at their default value.
pub fn model_coordinates(problem: &GaitProblem, q: &[f64]) -> Vec<f64> {
    let g = &problem.gait;
    let mut out: Vec<f64> = problem
        .model
        .coordinates
        .iter()
        .map(|c| c.default_value)
        .collect();
    for &(c, v) in &g.locked {
        out[c] = v;
    }
    for (i, gc) in g.coordinates.iter().enumerate() {
        out[gc.model_index] = q[i];
    }
    let mut v = vec![0.0; out.len()];
    g.couple(&mut out, &mut v, None);
    out
}

/// Every model coordinate's value [rad or m], speed [rad s⁻¹ or m s⁻¹] and acceleration
/// [rad s⁻² or m s⁻²] at cycle sample `s`, as [`model_coordinates`] (coordinates the
/// problem does not move at rest; coupled ones from their independent coordinate).
fn model_state(problem: &GaitProblem, cycle: &Trajectory, s: usize) -> [Vec<f64>; 3] {
    let mut q = model_coordinates(problem, &cycle.q[s]);
    let mut v = vec![0.0; q.len()];
    let mut a = vec![0.0; q.len()];
    for (i, gc) in problem.gait.coordinates.iter().enumerate() {
        v[gc.model_index] = cycle.v[s][i];
        a[gc.model_index] = cycle.qdd[s][i];
    }
    problem.gait.couple(&mut q, &mut v, Some(&mut a));
    [q, v, a]
}

/// Write `model.osim`: a copy of the `.osim` the model was imported from, the shipped
/// OpenSim file of the built-in model, or that of a model shipped with stride (by its
/// model name). A model built in code (none of these) gets no model file.
pub(super) fn write_model(model: &Model, dir: &Path) -> Result<(), PredictError> {
    let p = dir.join(MODEL_FILE);
    match &model.source_file {
        Some(src) => {
            std::fs::copy(src, &p)
                .map_err(|e| write_err(&p, format!("copying {}: {e}", src.display())))?;
            Ok(())
        }
        None if model.name == default_model().name => {
            write_file(dir, MODEL_FILE, DEFAULT_MODEL_OSIM)
        }
        None => match stride_model::shipped::shipped_by_model_name(&model.name) {
            Some(s) => write_file(dir, MODEL_FILE, s.osim),
            None => Ok(()),
        },
    }
}

/// Write `motion.mot`: every model coordinate (rotations in degrees) and the muscle
/// activations (`<muscle>/activation`).
pub(super) fn write_motion(
    problem: &GaitProblem,
    cycle: &Trajectory,
    dir: &Path,
) -> Result<(), PredictError> {
    let model = &problem.model;
    let mut labels = vec!["time".to_string()];
    labels.extend(model.coordinates.iter().map(|c| c.name.clone()));
    labels.extend(
        problem
            .gait
            .muscles
            .iter()
            .map(|&m| format!("{}/activation", model.muscles[m].name)),
    );
    let rows = (0..cycle.time.len())
        .map(|s| {
            let mut row = vec![cycle.time[s]];
            let q = model_coordinates(problem, &cycle.q[s]);
            row.extend(model.coordinates.iter().zip(q).map(|(c, v)| {
                if c.motion_type == MotionType::Rotational {
                    v.to_degrees()
                } else {
                    v
                }
            }));
            row.extend(&cycle.activation[s]);
            row
        })
        .collect();
    write_storage("motion", Some(true), labels, rows, &[], dir, MOTION_FILE)
}

/// Write `grf.mot` (per foot: force [N], centre of pressure [m] on the ground plane, and
/// the free moment about the plane normal [N m] as the torque columns, all in ground) and
/// `grf.xml`, the OpenSim `ExternalLoads` that applies them to the feet.
pub(super) fn write_ground_reactions(
    problem: &GaitProblem,
    cycle: &Trajectory,
    dir: &Path,
) -> Result<(), PredictError> {
    let (plane_point, normal) = problem
        .model
        .contacts
        .first()
        .map_or(([0.0; 3], [0.0, 1.0, 0.0]), |c| {
            (c.plane_point, c.plane_normal)
        });
    let mut labels = vec!["time".to_string()];
    for (side, _) in FEET {
        for k in ["vx", "vy", "vz", "px", "py", "pz"] {
            labels.push(format!("{side}_ground_force_{k}"));
        }
    }
    for (side, _) in FEET {
        for k in ["x", "y", "z"] {
            labels.push(format!("{side}_ground_torque_{k}"));
        }
    }
    let rows = (0..cycle.time.len())
        .map(|s| {
            let mut row = vec![cycle.time[s]];
            let mut torques = Vec::new();
            for (f, m) in [
                (cycle.grf_right[s], cycle.grm_right[s]),
                (cycle.grf_left[s], cycle.grm_left[s]),
            ] {
                let (cop, free) =
                    stride_multibody::center_of_pressure(f, m, plane_point, normal, 1e-3)
                        .unwrap_or((plane_point, 0.0));
                row.extend(f);
                row.extend(cop);
                torques.extend(normal.map(|n| n * free));
            }
            row.extend(torques);
            row
        })
        .collect();
    write_storage(
        "ground_reaction_forces",
        Some(false),
        labels,
        rows,
        &[],
        dir,
        GRF_FILE,
    )?;
    write_file(dir, GRF_XML_FILE, &external_loads_xml())
}

/// Write `id_setup.xml`, an OpenSim `InverseDynamicsTool` setup that computes the net joint
/// torques of `joint_torques.csv` from the folder's files: `model.osim` with every model
/// force excluded (muscles, passive elements and the contact spheres, whose forces
/// `grf.mot` already holds: applying both would count the ground reactions twice),
/// `motion.mot` unfiltered, the ground reactions through `grf.xml`, over the cycle's times
/// `t` [s]. The torques go to `inverse_dynamics/inverse_dynamics.sto`.
pub(super) fn write_id_setup(t: &[f64], dir: &Path) -> Result<(), PredictError> {
    let (t0, t1) = (
        t.first().copied().unwrap_or(0.0),
        t.last().copied().unwrap_or(0.0),
    );
    let xml = format!(
        "<?xml version=\"1.0\" encoding=\"UTF-8\" ?>\n<OpenSimDocument Version=\"40000\">\n\
         \t<InverseDynamicsTool name=\"inverse_dynamics\">\n\
         \t\t<results_directory>{ID_RESULTS_DIR}</results_directory>\n\
         \t\t<model_file>{MODEL_FILE}</model_file>\n\
         \t\t<time_range>{t0:.9} {t1:.9}</time_range>\n\
         \t\t<forces_to_exclude>All</forces_to_exclude>\n\
         \t\t<external_loads_file>{GRF_XML_FILE}</external_loads_file>\n\
         \t\t<coordinates_file>{MOTION_FILE}</coordinates_file>\n\
         \t\t<lowpass_cutoff_frequency_for_coordinates>-1</lowpass_cutoff_frequency_for_coordinates>\n\
         \t\t<output_gen_force_file>inverse_dynamics.sto</output_gen_force_file>\n\
         \t</InverseDynamicsTool>\n</OpenSimDocument>\n"
    );
    write_file(dir, ID_SETUP_FILE, &xml)
}

/// The OpenSim `ExternalLoads` document of `grf.mot`: one `ExternalForce` per foot, force,
/// point and torque expressed in ground.
fn external_loads_xml() -> String {
    let mut s = String::from(
        "<?xml version=\"1.0\" encoding=\"UTF-8\" ?>\n<OpenSimDocument Version=\"40000\">\n\
         \t<ExternalLoads name=\"ground_reactions\">\n\t\t<objects>\n",
    );
    for (side, body) in FEET {
        s.push_str(&format!(
            "\t\t\t<ExternalForce name=\"{body}_ground_reaction\">\n\
             \t\t\t\t<applied_to_body>{body}</applied_to_body>\n\
             \t\t\t\t<force_expressed_in_body>ground</force_expressed_in_body>\n\
             \t\t\t\t<point_expressed_in_body>ground</point_expressed_in_body>\n\
             \t\t\t\t<force_identifier>{side}_ground_force_v</force_identifier>\n\
             \t\t\t\t<point_identifier>{side}_ground_force_p</point_identifier>\n\
             \t\t\t\t<torque_identifier>{side}_ground_torque_</torque_identifier>\n\
             \t\t\t\t<data_source_name>{GRF_FILE}</data_source_name>\n\
             \t\t\t</ExternalForce>\n"
        ));
    }
    s.push_str(&format!(
        "\t\t</objects>\n\t\t<groups />\n\t\t<datafile>{GRF_FILE}</datafile>\n\
         \t</ExternalLoads>\n</OpenSimDocument>\n"
    ));
    s
}

/// State columns (OpenSim paths) and their values at every cycle sample: coordinate values
/// [rad or m] and speeds, then muscle activations and fibre lengths [m].
fn states(problem: &GaitProblem, cycle: &Trajectory, samples: &[SampleOutputs]) -> Table {
    let model = &problem.model;
    let g = &problem.gait;
    let mut labels = Vec::new();
    for c in &model.coordinates {
        let path = format!("/jointset/{}/{}", model.joints[c.joint].name, c.name);
        labels.push(format!("{path}/value"));
        labels.push(format!("{path}/speed"));
    }
    for &m in &g.muscles {
        labels.push(format!("/forceset/{}/activation", model.muscles[m].name));
    }
    for &m in &g.muscles {
        labels.push(format!("/forceset/{}/fiber_length", model.muscles[m].name));
    }
    let rows = (0..cycle.time.len())
        .map(|s| {
            let [q, v, _] = model_state(problem, cycle, s);
            let mut row: Vec<f64> = q.iter().zip(&v).flat_map(|(a, b)| [*a, *b]).collect();
            row.extend(&cycle.activation[s]);
            row.extend(&samples[s].fiber_length);
            row
        })
        .collect();
    Table { labels, rows }
}

/// Acceleration columns (Moco's derivative names, `/jointset/<joint>/<coordinate>/accel`)
/// of every model coordinate [rad s⁻² or m s⁻²] at every cycle sample: the accelerations
/// the solution's dynamics hold at that point (zero for coordinates the problem does not
/// move, coupled ones from their independent coordinate), so that inverse dynamics need not differentiate the motion.
fn accelerations(problem: &GaitProblem, cycle: &Trajectory) -> Table {
    let model = &problem.model;
    let labels = model
        .coordinates
        .iter()
        .map(|c| format!("/jointset/{}/{}/accel", model.joints[c.joint].name, c.name))
        .collect();
    let rows = (0..cycle.qdd.len())
        .map(|s| {
            let [_, _, a] = model_state(problem, cycle, s);
            a
        })
        .collect();
    Table { labels, rows }
}

/// Control columns (OpenSim actuator paths) and their values at every cycle sample: muscle
/// excitations, then the arm actuators' controls — their activations, which times the
/// optimal force give the simulated torque.
fn controls(problem: &GaitProblem, cycle: &Trajectory) -> Table {
    let model = &problem.model;
    let g = &problem.gait;
    let mut labels: Vec<String> = g
        .muscles
        .iter()
        .map(|&m| format!("/forceset/{}", model.muscles[m].name))
        .collect();
    labels.extend(
        g.actuator_driven()
            .iter()
            .map(|&ci| match g.coordinates[ci].actuation {
                Actuation::Actuator(a) => format!("/forceset/{}", model.actuators[a].name),
                _ => format!("/forceset/{}_actuator", g.coordinates[ci].name),
            }),
    );
    let excitations = problem.excitations(cycle);
    let rows = excitations
        .into_iter()
        .zip(&cycle.arm_activation)
        .map(|(mut e, arm)| {
            e.extend(arm);
            e
        })
        .collect();
    Table { labels, rows }
}

/// Named columns, one row per cycle sample (time not included).
struct Table {
    labels: Vec<String>,
    rows: Vec<Vec<f64>>,
}

/// Write `states.sto`, `controls.sto` and `trajectory.sto` (both, and the coordinate
/// accelerations as Moco derivatives, with the header keys of a Moco trajectory) over the
/// gait cycle, angles in radians.
pub(super) fn write_states_and_controls(
    problem: &GaitProblem,
    cycle: &Trajectory,
    samples: &[SampleOutputs],
    dir: &Path,
) -> Result<(), PredictError> {
    let st = states(problem, cycle, samples);
    let ct = controls(problem, cycle);
    let (l, r) = with_time(&cycle.time, &[&st]);
    write_storage("states", Some(false), l, r, &[], dir, STATES_FILE)?;
    let (l, r) = with_time(&cycle.time, &[&ct]);
    write_storage("controls", Some(false), l, r, &[], dir, CONTROLS_FILE)?;
    let at = accelerations(problem, cycle);
    let (l, r) = with_time(&cycle.time, &[&st, &ct, &at]);
    let (ns, nc) = (st.labels.len().to_string(), ct.labels.len().to_string());
    let nd = at.labels.len().to_string();
    let moco = [
        ("num_states", ns.as_str()),
        ("num_controls", nc.as_str()),
        ("num_input_controls", "0"),
        ("num_multipliers", "0"),
        ("num_derivatives", nd.as_str()),
        ("num_slacks", "0"),
        ("num_parameters", "0"),
    ];
    write_storage("trajectory", Some(false), l, r, &moco, dir, TRAJECTORY_FILE)
}

/// The columns of `tables` side by side after a `time` column.
fn with_time(time: &[f64], tables: &[&Table]) -> (Vec<String>, Vec<Vec<f64>>) {
    let mut labels = vec!["time".to_string()];
    tables
        .iter()
        .for_each(|t| labels.extend(t.labels.iter().cloned()));
    let rows = time
        .iter()
        .enumerate()
        .map(|(s, &t)| {
            let mut row = vec![t];
            tables.iter().for_each(|x| row.extend(&x.rows[s]));
            row
        })
        .collect();
    (labels, rows)
}

/// Write an OpenSim storage file `dir/file` with extra header keys `meta`.
fn write_storage(
    name: &str,
    in_degrees: Option<bool>,
    labels: Vec<String>,
    rows: Vec<Vec<f64>>,
    meta: &[(&str, &str)],
    dir: &Path,
    file: &str,
) -> Result<(), PredictError> {
    let p = dir.join(file);
    let storage = Storage {
        name: name.into(),
        in_degrees,
        labels,
        rows,
    };
    let mut text = storage.to_text().map_err(|e| write_err(&p, e))?;
    if !meta.is_empty() {
        let keys: String = meta.iter().map(|(k, v)| format!("{k}={v}\n")).collect();
        text = text.replacen("endheader\n", &format!("{keys}endheader\n"), 1);
    }
    write_file(dir, file, &text)
}
