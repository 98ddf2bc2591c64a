use super::*;

/// The OpenSim reference models folder, or `None` (with the reason printed) when absent.
fn opensim_models() -> Option<PathBuf> {
    let p = PathBuf::from(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../../../shared/reference/models/opensim"
    ));
    if p.is_dir() {
        Some(p)
    } else {
        eprintln!("skipped: {} is absent", p.display());
        None
    }
}

/// An ExternalLoads document with `forces` inside `<objects>` and `datafile`.
fn doc(forces: &str, datafile: &str) -> String {
    format!(
        "<?xml version=\"1.0\"?>\n<OpenSimDocument Version=\"40000\">\n<ExternalLoads name=\"x\">\n\
         <objects>\n{forces}</objects>\n<datafile>{datafile}</datafile>\n</ExternalLoads>\n\
         </OpenSimDocument>\n"
    )
}

/// One ExternalForce element on `body` with identifiers starting with `prefix` and the
/// extra elements `extra`.
fn force_xml(name: &str, body: &str, prefix: &str, extra: &str) -> String {
    format!(
        "<ExternalForce name=\"{name}\">\n<applied_to_body>{body}</applied_to_body>\n\
         <force_identifier>{prefix}ground_force_v</force_identifier>\n\
         <point_identifier>{prefix}ground_force_p</point_identifier>\n\
         <torque_identifier>{prefix}ground_torque_</torque_identifier>\n{extra}</ExternalForce>\n"
    )
}

#[test]
fn gait2392_pipeline_forces_are_read_with_bodies_identifiers_and_data_file() {
    let Some(root) = opensim_models() else { return };
    let xml = root.join("gait2392_pipeline/subject01_walk1_grf.xml");
    let l = ExternalLoads::read(&xml).unwrap();
    assert_eq!(l.forces.len(), 2);
    let [r, left] = [&l.forces[0], &l.forces[1]];
    assert_eq!(r.name, "ExternalForce_1");
    assert_eq!(r.applied_to_body, "calcn_r");
    assert_eq!(left.applied_to_body, "calcn_l");
    assert_eq!(r.force_expressed_in_body, "ground");
    assert_eq!(r.point_expressed_in_body, "ground");
    assert_eq!(r.force_identifier, "ground_force_v");
    assert_eq!(left.point_identifier, "1_ground_force_p");
    assert_eq!(left.torque_identifier, "1_ground_torque_");
    assert!(r.enabled && left.enabled);
    assert_eq!(
        l.datafile,
        root.join("gait2392_pipeline/subject01_walk1_grf.mot")
    );
    assert_eq!(left.columns()[0], "1_ground_force_vx");
    assert_eq!(left.columns()[8], "1_ground_torque_z");
    let data = l.read_data().unwrap();
    assert_eq!(data.n_rows(), 1501);
}

#[test]
fn moco_2d_walking_forces_are_read_with_bodies_identifiers_and_data_file() {
    let Some(root) = opensim_models() else { return };
    let l = ExternalLoads::read(&root.join("moco_example2DWalking/referenceGRF.xml")).unwrap();
    let names: Vec<&str> = l.forces.iter().map(|f| f.name.as_str()).collect();
    assert_eq!(names, ["Right_GRF", "Left_GRF"]);
    assert_eq!(l.forces[0].applied_to_body, "calcn_r");
    assert_eq!(l.forces[1].force_identifier, "ground_force_l_v");
    assert_eq!(l.forces[0].torque_identifier, "ground_torque_r_");
    assert!(l.forces.iter().all(|f| f.enabled));
    assert!(l
        .datafile
        .ends_with("moco_example2DWalking/referenceGRF.sto"));
    assert_eq!(l.read_data().unwrap().n_rows(), 50);
}

#[test]
fn disabled_forces_are_marked_in_both_versions_and_paths_are_reduced() {
    let forces = force_xml(
        "a",
        "/bodyset/calcn_r",
        "",
        "<isDisabled> true </isDisabled>\n",
    ) + &force_xml("b", "calcn_l", "1_", "<appliesForce>false</appliesForce>\n")
        + &force_xml(
            "c",
            "calcn_l",
            "2_",
            "<force_expressed_in_body>/ground</force_expressed_in_body>\n",
        );
    let l =
        ExternalLoads::parse(&doc(&forces, "sub/grf.mot"), Path::new("/data/loads.xml")).unwrap();
    assert_eq!(
        l.forces.iter().map(|f| f.enabled).collect::<Vec<_>>(),
        [false, false, true]
    );
    assert_eq!(l.forces[0].applied_to_body, "calcn_r");
    assert_eq!(l.forces[2].force_expressed_in_body, "ground");
    assert_eq!(l.enabled().count(), 1);
    assert_eq!(l.datafile, Path::new("/data/sub/grf.mot"));
}

/// Parses `text` as `bad.xml` and returns the one-line message of its error.
fn error_of(text: &str) -> String {
    let e = ExternalLoads::parse(text, Path::new("bad.xml")).unwrap_err();
    let m = e.to_string();
    assert!(m.starts_with("bad.xml"), "{m}");
    assert_eq!(m.lines().count(), 1, "{m}");
    m
}

#[test]
fn a_force_without_a_body_or_identifier_is_an_error_naming_the_force_and_element() {
    let no_body = "<ExternalForce name=\"right\"><force_identifier>f</force_identifier>\
                   <point_identifier>p</point_identifier><torque_identifier>t</torque_identifier>\
                   </ExternalForce>";
    let m = error_of(&doc(no_body, "grf.mot"));
    assert!(
        m.contains("`right`") && m.contains("<applied_to_body>"),
        "{m}"
    );
    let no_point = force_xml("left", "calcn_l", "", "").replace("ground_force_p", "");
    let m = error_of(&doc(&no_point, "grf.mot"));
    assert!(
        m.contains("`left`") && m.contains("<point_identifier>"),
        "{m}"
    );
    let bad_flag = force_xml("left", "calcn_l", "", "<isDisabled>maybe</isDisabled>");
    let m = error_of(&doc(&bad_flag, "grf.mot"));
    assert!(m.contains("<isDisabled>"), "{m}");
}

#[test]
fn a_file_without_forces_data_file_or_well_formed_xml_is_an_error_naming_it() {
    let one = force_xml("r", "calcn_r", "", "");
    assert!(error_of(&doc(&one, "")).contains("<datafile>"));
    assert!(error_of(&doc("", "grf.mot")).contains("no <ExternalForce>"));
    assert!(error_of("<OpenSimDocument><Model/></OpenSimDocument>").contains("<ExternalLoads>"));
    assert!(error_of("<OpenSimDocument><ExternalLoads>").contains("malformed XML"));
}

#[test]
fn a_missing_data_file_or_column_is_an_error_naming_the_xml_and_the_datafile() {
    let dir = std::env::temp_dir().join(format!("stride-external-loads-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let xml = dir.join("loads.xml");
    let forces = force_xml("r", "calcn_r", "", "");
    std::fs::write(&xml, doc(&forces, "grf.mot")).unwrap();
    let l = ExternalLoads::read(&xml).unwrap();
    let m = l.read_data().unwrap_err().to_string();
    assert!(m.contains("loads.xml") && m.contains("<datafile>"), "{m}");
    assert!(m.contains("grf.mot") && m.contains("no such file"), "{m}");
    let labels = "time\tground_force_vx\tground_force_vy\tground_force_vz\tground_force_px\t\
                  ground_force_py\tground_force_pz\tground_torque_x\tground_torque_y";
    let rows = "0\t1\t2\t3\t4\t5\t6\t7\t8\n";
    std::fs::write(
        dir.join("grf.mot"),
        format!("grf\nendheader\n{labels}\n{rows}"),
    )
    .unwrap();
    let m = l.read_data().unwrap_err().to_string();
    assert!(
        m.contains("loads.xml") && m.contains("`ground_torque_z`"),
        "{m}"
    );
    assert!(m.contains("`r`"), "{m}");
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn a_file_larger_than_the_cap_is_refused_before_parsing() {
    let dir = std::env::temp_dir().join(format!("stride-external-big-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let xml = dir.join("big.xml");
    let pad = " ".repeat(MAX_EXTERNAL_LOADS_BYTES as usize + 1);
    std::fs::write(&xml, pad).unwrap();
    let m = ExternalLoads::read(&xml).unwrap_err().to_string();
    assert!(m.contains("big.xml") && m.contains("larger than"), "{m}");
    let _ = std::fs::remove_dir_all(&dir);
}
