//! Hostile and inconsistent inputs are refused with one line naming what is wrong, before
//! anything is solved or written: values that would change a Slurm job script, readers fed
//! an endless device, model settings out of their physical range, geometry files of another
//! model, a shipped model's name in a study folder, the documented time limit.

mod common;

use common::{rejects, stride};
use std::path::{Path, PathBuf};

fn scratch(tag: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("stride-inputs-{tag}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

fn text(b: &[u8]) -> String {
    String::from_utf8_lossy(b).into_owned()
}

/// `args` and `extra`.
fn with_arg<'a>(args: &[&'a str], extra: &'a str) -> Vec<&'a str> {
    [args, &[extra]].concat()
}

const TINY_STUDY: &str = "[study]\nname = \"tiny\"\noutput = \"out\"\nmodel = \"gait1018\"\n\n[base]\nmesh_intervals = 5\n";

#[test]
fn job_script_values_cannot_add_shell_lines() {
    let d = scratch("slurm");
    let study = d.join("tiny.toml");
    std::fs::write(&study, TINY_STUDY).unwrap();
    let s = study.to_str().unwrap();
    let out = d.join("out");
    let o = out.to_str().unwrap();
    let dry = ["study", s, "--out", o, "--slurm", "--dry-run"];
    let with = |extra| with_arg(&dry, extra);
    rejects(
        &with("--sbatch-arg=--account=x\nrm -rf ~/data"),
        "control character '\\n'",
    );
    rejects(
        &with("--partition=a b;c"),
        "partition `a b;c`: expected a Slurm name",
    );
    rejects(&with("--sbatch-arg=-A x;y"), "expected a Slurm name");
    rejects(&with("--sbatch-arg=--time=1h"), "time `1h`");
    // the same rules for the study file's [slurm] table, naming the file
    let bad = format!("{TINY_STUDY}\n[slurm]\nextra_args = [\"--account=x\\nrm -rf ~/data\"]\n");
    std::fs::write(&study, bad).unwrap();
    rejects(&dry, "tiny.toml: [slurm].extra_args");
    std::fs::write(
        &study,
        format!("{TINY_STUDY}\n[slurm]\npartition = \"a\\nb\"\n"),
    )
    .unwrap();
    rejects(&dry, "tiny.toml: [slurm]");
    // good values are written one #SBATCH line each, quoted when they hold a space or `#`
    std::fs::write(&study, TINY_STUDY).unwrap();
    let args = [
        &dry[..],
        &["--sbatch-arg=--comment=a #b", "--partition=gpu,cpu"],
    ]
    .concat();
    let r = stride(&args);
    assert!(r.status.success(), "{}", text(&r.stderr));
    let script = text(&r.stdout);
    assert!(script.contains("#SBATCH \"--comment=a #b\"\n"), "{script}");
    assert!(script.contains("#SBATCH --partition=gpu,cpu\n"), "{script}");
    for line in script.lines().filter(|l| l.starts_with("#SBATCH")) {
        assert!(!line.contains("rm -rf"), "{line}");
    }
    assert!(!out.exists(), "a dry run writes nothing");
    let _ = std::fs::remove_dir_all(&d);
}

#[test]
fn an_endless_settings_file_is_refused_at_the_cap() {
    for args in [
        &[
            "predict",
            "--model",
            "gait1018",
            "--model-settings",
            "/dev/zero",
        ][..],
        &["track", "--config", "/dev/zero"][..],
    ] {
        rejects(args, "larger than the 16 MB accepted");
    }
    rejects(
        &["predict", "--model", "gait1018", "--geometry", "/dev/zero"],
        "larger than the 64 MB accepted",
    );
}

/// A copy of the shipped gait1018 model file in `d`, with `settings` beside it when given.
fn gait1018_in(d: &Path, settings: Option<&str>) -> PathBuf {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("../model/data/models/gait1018");
    let osim = d.join("gait1018.osim");
    std::fs::copy(root.join("gait1018.osim"), &osim).unwrap();
    if let Some(s) = settings {
        std::fs::write(d.join("gait1018.toml"), s).unwrap();
    }
    osim
}

fn shipped_geometry() -> String {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("../model/data/models/gait1018");
    std::fs::read_to_string(root.join("gait1018.geometry.json")).unwrap()
}

#[test]
fn model_settings_out_of_range_name_the_file_and_key() {
    let d = scratch("settings");
    let sphere = "[[contact.spheres]]\nname = \"heel\"\nbody = \"calcn_r\"\nlocation = [0.0, 0.0, 0.0]\nradius = 0.03\n";
    let geometry = d.join("g.json");
    std::fs::write(&geometry, shipped_geometry()).unwrap();
    for (settings, needle) in [
        (
            format!("[contact.parameters]\nstiffness = -1e6\n{sphere}"),
            "`contact.parameters.stiffness`: -1000000.0 is out of range",
        ),
        (
            format!("[contact.parameters]\nstatic_friction = -5\n{sphere}"),
            "`contact.parameters.static_friction`: -5.0 is out of range",
        ),
        (
            format!("[contact.parameters]\ntransition_velocity = 0.0\n{sphere}"),
            "`contact.parameters.transition_velocity`",
        ),
        (
            format!("[contact.parameters]\ndissipation = nan\n{sphere}"),
            "`contact.parameters.dissipation`: NaN is out of range",
        ),
        (
            sphere.replace("0.03", "1e300"),
            "`contact.spheres[0].radius`: 1e300 is out of range",
        ),
        (
            format!("{sphere}{sphere}"),
            "`contact.spheres[1].name`: `heel` is also the name of contact.spheres[0]",
        ),
        (
            "[[actuators]]\ncoordinate = \"lumbar_extension\"\noptimal_force = 100.0\ncontrol_range = [1.0, -1.0]\n".into(),
            "`actuators[0].control_range`: [1.0, -1.0] must be finite with lower ≤ upper",
        ),
    ] {
        let osim = gait1018_in(&d, Some(&settings));
        let o = osim.to_str().unwrap();
        let g = geometry.to_str().unwrap();
        let args = ["predict", "--quiet", "--model", o, "--geometry", g];
        rejects(&args, needle);
        rejects(&args, "gait1018.toml");
    }
    // a folder where the settings file would be is an error, not a model without settings
    std::fs::remove_file(d.join("gait1018.toml")).unwrap();
    std::fs::create_dir(d.join("gait1018.toml")).unwrap();
    let osim = gait1018_in(&d, None);
    rejects(
        &[
            "predict",
            "--quiet",
            "--model",
            osim.to_str().unwrap(),
            "--geometry",
            geometry.to_str().unwrap(),
        ],
        "gait1018.toml: is a folder, not a file",
    );
    let _ = std::fs::remove_dir_all(&d);
}

#[test]
fn geometry_files_of_another_model_are_refused() {
    let d = scratch("geometry");
    let osim = gait1018_in(&d, None);
    let o = osim.to_str().unwrap();
    let g = d.join("g.json");
    let gs = g.to_str().unwrap();
    let shipped = shipped_geometry();
    let args = ["predict", "--model", o, "--geometry", gs];
    // the model file changed after the fit
    let mut edited = std::fs::read_to_string(&osim).unwrap();
    edited.push_str("\n<!-- edited -->\n");
    std::fs::write(&osim, edited).unwrap();
    std::fs::write(&g, &shipped).unwrap();
    rejects(
        &args,
        "fitted to a model file with content hash b355f1b731868032871695f92088a919",
    );
    // swapped muscle names (no hash to compare): found from the paths
    let mut v: serde_json::Value = serde_json::from_str(&shipped).unwrap();
    v["model_hash"] = serde_json::Value::Null;
    let muscles = v["muscles"].as_array_mut().unwrap();
    let (a, b) = (muscles[0].clone(), muscles[9].clone());
    (muscles[0], muscles[9]) = (b, a.clone());
    std::fs::write(&g, v.to_string()).unwrap();
    rejects(&args, &format!("muscle {}", a.as_str().unwrap()));
    // a muscle the model lacks
    v["muscles"][0] = "nosuch_r".into();
    std::fs::write(&g, v.to_string()).unwrap();
    rejects(&args, "has muscles the model lacks: nosuch_r");
    // corrupt coefficients
    for bad in ["1e300", "NaN"] {
        let text = shipped.replacen(
            "\"coefficients\": [",
            &format!("\"coefficients\": [{bad}, "),
            1,
        );
        let mut v: serde_json::Value = match serde_json::from_str(&text) {
            Ok(v) => v,
            Err(_) => {
                // NaN is not JSON: the reader names the file and the position
                std::fs::write(&g, &text).unwrap();
                rejects(&args, "g.json");
                continue;
            }
        };
        let p = &mut v["path_polynomials"][0];
        let e0 = p["exponents"][0].clone();
        p["exponents"].as_array_mut().unwrap().push(e0);
        std::fs::write(&g, v.to_string()).unwrap();
        rejects(&args, "coefficient 1e300 is not finite or larger than 1000");
    }
    let _ = std::fs::remove_dir_all(&d);
}

#[test]
fn a_study_folder_of_a_shipped_model_is_viewed() {
    let d = scratch("view");
    std::fs::write(d.join("study.toml"), TINY_STUDY).unwrap();
    let case = d.join("cases").join("base");
    std::fs::create_dir_all(&case).unwrap();
    let data = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/gait1018_prediction");
    for f in ["motion.mot", "grf.mot"] {
        std::fs::copy(data.join(f), case.join(f)).unwrap();
    }
    let o = stride(&["view", d.to_str().unwrap()]);
    assert!(o.status.success(), "{}", text(&o.stderr));
    let page = std::fs::read_to_string(d.join("view.html")).unwrap();
    assert!(page.contains("calcn_r"), "the page draws gait1018's bodies");
    let _ = std::fs::remove_dir_all(&d);
}

#[test]
fn predict_help_states_the_time_limit_it_applies() {
    let o = stride(&["predict", "--help"]);
    let help = text(&o.stdout);
    let line = help
        .lines()
        .skip_while(|l| !l.contains("--time-limit"))
        .take(3)
        .collect::<String>();
    assert!(line.contains("[default: 1800]"), "{line}");
    assert!(!line.contains("none"), "{line}");
}

#[test]
fn tracking_windows_and_measured_forces_are_checked_by_name() {
    let d = scratch("track");
    for (window, needle) in [
        ("4,4", "window [4, 4] s: its end must come after its start"),
        (
            "4.2,3.5",
            "window [4.2, 3.5] s: its end must come after its start",
        ),
    ] {
        rejects(
            &[
                "track",
                "--window",
                window,
                "--out",
                d.join("o").to_str().unwrap(),
            ],
            needle,
        );
    }
    let _ = std::fs::remove_dir_all(&d);
}
