//! `stride track --grf loads.xml`: the ExternalLoads file names the foot bodies and the
//! columns of the forces. A trial tracked through such a file follows the forces of the
//! right feet; bad files get a one-line error naming the file and the element, a non-zero
//! exit and no output folder.

mod common;
use common::rejects;
use std::path::{Path, PathBuf};

/// A fresh scratch folder for one test.
fn scratch(tag: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("stride-loads-{tag}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

fn s(p: &Path) -> String {
    p.display().to_string()
}

/// The shipped 2D model's own predicted gait (`tests/data/gait1018_prediction`).
fn prediction(file: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/data/gait1018_prediction")
        .join(file)
}

/// An ExternalLoads file of `forces` (name, body, identifier prefix, extra elements) with
/// the data file `datafile`.
fn loads_xml(forces: &[(&str, &str, &str, &str)], datafile: &str) -> String {
    let objects: String = forces
        .iter()
        .map(|(name, body, p, extra)| {
            format!(
                "      <ExternalForce name=\"{name}\">\n        <applied_to_body>{body}</applied_to_body>\n\
                 <force_expressed_in_body>ground</force_expressed_in_body>\n{extra}\n\
                 <force_identifier>{p}ground_force_v</force_identifier>\n\
                 <point_identifier>{p}ground_force_p</point_identifier>\n\
                 <torque_identifier>{p}ground_torque_</torque_identifier>\n      </ExternalForce>\n"
            )
        })
        .collect();
    format!(
        "<?xml version=\"1.0\" encoding=\"UTF-8\" ?>\n<OpenSimDocument Version=\"40000\">\n  \
         <ExternalLoads name=\"trial\">\n    <objects>\n{objects}    </objects>\n    \
         <datafile>{datafile}</datafile>\n  </ExternalLoads>\n</OpenSimDocument>\n"
    )
}

/// The forces of the prediction's `grf.mot` (prefixes `r_`, `l_`), left foot first.
const FEET: [(&str, &str, &str, &str); 2] = [
    ("left", "calcn_l", "l_", ""),
    ("right", "calcn_r", "r_", ""),
];

#[test]
fn gait1018_tracking_its_prediction_through_an_external_loads_file_follows_its_forces() {
    let d = scratch("gait1018");
    std::fs::copy(prediction("grf.mot"), d.join("grf.mot")).unwrap();
    let xml = d.join("grf.xml");
    std::fs::write(&xml, loads_xml(&FEET, "grf.mot")).unwrap();
    let out = d.join("out");
    let motion = prediction("motion.mot");
    let run = common::stride(&[
        "track",
        "--model",
        "gait1018",
        "--motion",
        &s(&motion),
        "--grf",
        &s(&xml),
        "--window",
        "0.1,0.9",
        "--mesh",
        "20",
        "--filter-cutoff",
        "0",
        "--out",
        &s(&out),
        "--quiet",
    ]);
    assert!(run.status.success(), "{run:?}");
    let summary: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("summary.json")).unwrap()).unwrap();
    assert_eq!(summary["status"], "Optimal");
    // with the feet swapped the errors would be of the order of body weight
    for bw in summary["errors"]["grf_percent_body_weight"]
        .as_array()
        .unwrap()
    {
        assert!(bw.as_f64().unwrap() < 5.0, "GRF RMSE {bw} % of body weight");
    }
    let _ = std::fs::remove_dir_all(&d);
}

/// Runs `stride track --model gait1018` on its prediction with the GRF file `grf` and
/// checks the rejection: one line containing each of `needles`, nothing written.
fn rejected(d: &Path, grf: &Path, extra: &[&str], needles: &[&str]) {
    let out = d.join("out");
    let (motion, grf, out_s) = (s(&prediction("motion.mot")), s(grf), s(&out));
    let mut args = vec![
        "track", "--model", "gait1018", "--motion", &motion, "--grf", &grf, "--out", &out_s,
        "--quiet",
    ];
    args.extend_from_slice(extra);
    for needle in needles {
        rejects(&args, needle);
    }
    assert!(!out.exists(), "{} was written", out.display());
}

#[test]
fn an_external_loads_file_with_bad_bodies_or_data_is_rejected_and_nothing_is_written() {
    let d = scratch("bad");
    std::fs::copy(prediction("grf.mot"), d.join("grf.mot")).unwrap();
    let xml = d.join("loads.xml");
    let window = ["--window", "0.1,0.9"];
    let case = |forces: &[(&str, &str, &str, &str)], datafile: &str, needles: &[&str]| {
        std::fs::write(&xml, loads_xml(forces, datafile)).unwrap();
        rejected(&d, &xml, &window, needles);
    };
    let [left, right] = FEET;
    case(
        &[("left", "foot_l", "l_", ""), right],
        "grf.mot",
        &[
            "loads.xml",
            "ExternalForce `left`",
            "`foot_l` is not a body of the model",
        ],
    );
    case(
        &[left, right],
        "missing.mot",
        &["loads.xml", "<datafile>", "missing.mot", "no such file"],
    );
    case(
        &[("left", "tibia_l", "l_", ""), right],
        "grf.mot",
        &["loads.xml", "`tibia_l` is not a foot"],
    );
    case(
        &[left, ("right", "calcn_r", "x_", "")],
        "grf.mot",
        &["loads.xml", "<datafile>", "no column `x_ground_force_vx`"],
    );
    case(
        &[left, right, ("again", "toes_r", "r_", "")],
        "grf.mot",
        &[
            "loads.xml",
            "ExternalForce `again`",
            "already acts on the right foot",
        ],
    );
    let frame = "<point_expressed_in_body>calcn_r</point_expressed_in_body>";
    case(
        &[left, ("right", "calcn_r", "r_", frame)],
        "grf.mot",
        &["loads.xml", "<point_expressed_in_body>", "not supported"],
    );
    let off = "<appliesForce>false</appliesForce>";
    case(
        &[left, ("right", "calcn_r", "r_", off)],
        "grf.mot",
        &[
            "loads.xml",
            "no applied ExternalForce acts on the right foot",
        ],
    );
    let _ = std::fs::remove_dir_all(&d);
}

#[test]
fn an_empty_or_reversed_window_is_rejected_saying_so() {
    let d = scratch("window");
    let grf = prediction("grf.mot");
    for w in ["0.5,0.5", "0.9,0.1"] {
        rejected(&d, &grf, &["--window", w], &["empty or reversed"]);
    }
    let _ = std::fs::remove_dir_all(&d);
}
