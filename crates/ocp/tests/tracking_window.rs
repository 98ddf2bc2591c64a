//! Tracking windows anywhere inside the data: a window whose ends fall between the samples
//! of the motion gives finite bounds that hold the measured values at its ends; an empty or
//! reversed window is an error saying so.

use stride_ocp::tracking::{TrackSettings, TrackingProblem};

fn problem(window: [f64; 2]) -> Result<TrackingProblem, String> {
    let model = stride_model::default_model::default_model();
    let settings = TrackSettings {
        mesh_intervals: 2,
        window,
        ..Default::default()
    };
    TrackingProblem::new(&model, &settings).map_err(|e| e.to_string())
}

#[test]
fn a_window_between_two_motion_samples_has_bounds_holding_its_ends() {
    // gait_1's motion is sampled every 10 ms: no sample lies inside [3.452, 3.457] s
    let tp = problem([3.452, 3.457]).unwrap();
    let b = &tp.problem.bounds;
    for (i, r) in b.q.iter().chain(&b.v).chain(&b.a).enumerate() {
        assert!(
            r.lo.is_finite() && r.hi.is_finite() && r.lo < r.hi,
            "bound {i}: {r:?}"
        );
    }
    for t in tp.trial.window {
        let s = tp.trial.sample(t);
        for (i, (q, r)) in s.q.iter().zip(&b.q).enumerate() {
            assert!(
                r.lo <= *q && *q <= r.hi,
                "q{i} = {q} at {t} s outside {r:?}"
            );
        }
    }
    assert!(tp.x0.iter().all(|v| v.is_finite()));
}

#[test]
fn an_empty_or_reversed_window_is_an_error_saying_so() {
    for w in [[3.5, 3.5], [3.6, 3.5]] {
        let m = problem(w).err().unwrap();
        assert!(m.contains("empty or reversed"), "{w:?}: {m}");
        assert!(!m.contains("not inside the data"), "{m}");
    }
}

#[test]
fn grf_prefixes_with_an_external_loads_file_is_an_error() {
    let settings = TrackSettings {
        motion: Some("ik.mot".into()),
        grf: Some("grf.xml".into()),
        grf_prefixes: Some(["r_".into(), "l_".into()]),
        ..Default::default()
    };
    let model = stride_model::default_model::default_model();
    let m = TrackingProblem::new(&model, &settings)
        .err()
        .unwrap()
        .to_string();
    assert!(
        m.contains("grf_prefixes") && m.contains("ExternalLoads"),
        "{m}"
    );
}
