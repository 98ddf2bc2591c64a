//! PredSim's three models (`Falisse_et_al_2022`, `gait1018`, `DHondt_et_al_2024_4seg`)
//! as gait problems: bounds from the data where they match and from the model where not
//! (or PredSim's table for every coordinate),
//! PredSim's limit torques (analytic values), the toes driven by their passive torque,
//! the 2D model's gait view, and derivatives of small problems (the four-segment foot
//! model with its ligaments too) against finite differences, on the models as shipped (settings file and fitted geometry).

mod common;

use stride_model::Model;
use stride_ocp::bounds::bounds_data;
use stride_ocp::passive_rules::{PassiveCost, ToeDrive};
use stride_ocp::{
    guess::GuessKind, node::NodeModel, problem::GaitProblem, settings::ProblemSettings,
    tape_node::TapeNode, transcription::Transcription,
};
use stride_predict::predict::guess_point;
use stride_solve::nlp::{check_derivatives, DerivativeCheckOptions};

/// PredSim's problem settings of the toes model: toes driven passively, limit torques
/// only in the cost.
fn toes_settings(mesh: usize) -> ProblemSettings {
    let mut s = ProblemSettings {
        mesh_intervals: mesh,
        ..Default::default()
    };
    s.passive.toes = ToeDrive::Passive;
    s.passive.cost = PassiveCost::Limit;
    s
}

fn problem(m: &Model, s: &ProblemSettings) -> GaitProblem {
    GaitProblem::new(m, s, &bounds_data(s)).unwrap()
}

#[test]
fn toes_get_model_bounds_and_predsims_passive_torque() {
    let m = common::shipped_model("falisse2022");
    let p = problem(&m, &toes_settings(4));
    assert_eq!(p.gait.nq(), 31);
    let i = p.gait.index_of("mtp_angle_l").unwrap();
    // PredSim's default bounds of the toes (PREDSIM.md §4)
    assert_eq!((p.bounds.q[i].lo, p.bounds.q[i].hi), (-0.5, 1.05));
    assert_eq!((p.bounds.v[i].lo, p.bounds.a[i].hi), (-13.0, 500.0));
    // the knee keeps its data-driven bounds
    let k = p.gait.index_of("knee_angle_l").unwrap();
    assert!(p.bounds.q[k].lo < -1.5 && p.bounds.q[k].hi > 0.2);
    // limit torques: hips, knees, ankles, subtalars, mtps and lumbar (17, PREDSIM §3.6)
    let limits = p.model.passive_torques.iter().filter(|t| t.has_limit());
    assert_eq!(limits.count(), 17);
    assert!(p.passive_cost_limit_only);
    let spring = |name: &str| {
        let c = p.model.coordinate_index(name).unwrap();
        p.model
            .coordinate_forces
            .iter()
            .find(|f| f.coordinate == c)
            .cloned()
    };
    assert!(spring("mtp_angle_l").is_some() && spring("knee_angle_l").is_none());
    // T = -k q - B q̇ + K1 e^{K2(q-θ2)} + K3 e^{K4(q-θ1)} at a few toe angles (PREDSIM §4)
    let c = p.gait.coordinates[i].model_index;
    let e = p
        .model
        .passive_torques
        .iter()
        .find(|t| t.coordinate == c)
        .unwrap();
    for (q, qd) in [(0.0, 0.0), (0.3, 1.0), (-0.2, -2.0), (1.2, 0.5)] {
        let expected = -25.0 * q - 2.0 * qd
            + (-0.9) * (14.87 * (q - 1.13446401379631f64)).exp()
            + 0.18 * (-70.08 * q).exp();
        let law = &spring("mtp_angle_l").unwrap().law;
        let got = stride_muscle::passive::passive_torque(e, q, qd)
            + stride_multibody::elements::coordinate_force(law, q, qd);
        assert!(
            (got - expected).abs() < 1e-12 * expected.abs().max(1.0),
            "{q}: {got} vs {expected}"
        );
    }
    // a knee limit torque at 10° beyond the flexion threshold (FORMULATION 6.1)
    let kc = p.gait.coordinates[k].model_index;
    let e = p
        .model
        .passive_torques
        .iter()
        .find(|t| t.coordinate == kc)
        .unwrap();
    let q = -2.4 - 10f64.to_radians();
    let expected = -6.09 * (33.94 * (q - 0.13)).exp() + 11.03 * (-11.33 * (q + 2.4)).exp();
    assert!((stride_muscle::passive::limit_torque(e, q) - expected).abs() < 1e-9);
}

#[test]
fn the_arms_of_the_3d_models_are_arms_and_they_are_not_planar() {
    for name in ["subject1", "falisse2022"] {
        let m = common::shipped_model(name);
        let p = problem(&m, &toes_settings(4));
        let g = &p.gait;
        let arms: Vec<&str> = g
            .actuator_driven()
            .into_iter()
            .filter(|&i| stride_ocp::gait::is_arm_coordinate(&m, g.coordinates[i].model_index))
            .map(|i| g.coordinates[i].name.as_str())
            .collect();
        assert_eq!(arms.len(), 8, "{name}: {arms:?}");
        assert!(arms.contains(&"elbow_flex_l") && arms.contains(&"arm_rot_r"));
        assert!(!g.is_planar(&m), "{name}");
    }
}

#[test]
fn passive_toes_carry_no_muscle_moment() {
    let m = common::shipped_model("falisse2022");
    for (toes, expect_muscle) in [(ToeDrive::Passive, false), (ToeDrive::Muscles, true)] {
        let mut s = toes_settings(3);
        s.passive.toes = toes;
        let p = problem(&m, &s);
        let node = NodeModel::new(&p).unwrap();
        let x = guess_point(&p, GuessKind::QuasiRandom).unwrap();
        let io = stride_ocp::transcription::NodeInputs {
            nm: p.layout.nm,
            nq: p.layout.nq,
            na: p.layout.na,
        };
        let xin: Vec<f64> = io
            .global_indices(&p.layout, 1, 2)
            .iter()
            .map(|&g| x[g])
            .collect();
        let mut ws = node.workspace::<f64>().unwrap();
        let eval = |ws: &mut _, xin: &[f64]| {
            let mut y = vec![0.0; node.n_outputs()];
            node.eval(ws, xin, &mut y);
            y
        };
        let y0 = eval(&mut ws, &xin);
        // raise the tendon force of the toe flexor: the toe balance changes only when
        // the muscles drive the toes
        let fl = p.model.muscle_index("flex_dig_r").unwrap();
        let om = p.gait.muscles.iter().position(|&x| x == fl).unwrap();
        let mut x1 = xin.clone();
        x1[io.f() + om] *= 3.0;
        let y1 = eval(&mut ws, &x1);
        let mtp = p.gait.index_of("mtp_angle_r").unwrap();
        let t = p
            .gait
            .muscle_driven()
            .iter()
            .position(|&c| c == mtp)
            .unwrap();
        let o = node.outputs();
        let d = (y1[o.root + t] - y0[o.root + t]).abs();
        assert_eq!(d > 1e-9, expect_muscle, "{toes:?}: {d}");
    }
}

#[test]
fn planar_model_has_no_lateral_coordinates_and_mirrors_its_legs() {
    let m = common::shipped_model("gait1018");
    let s = ProblemSettings {
        mesh_intervals: 4,
        ..Default::default()
    };
    let p = problem(&m, &s);
    let g = &p.gait;
    let names: Vec<&str> = g.coordinates.iter().map(|c| c.name.as_str()).collect();
    assert_eq!(g.nq(), 10, "{names:?}");
    assert_eq!(g.root().len(), 3);
    for c in &g.coordinates {
        assert!(
            !c.name.contains("list") && !c.name.contains("rotation") && !c.name.ends_with("tz")
        );
        assert_eq!(c.mirror_sign, 1.0, "{}", c.name);
        let mirror = &g.coordinates[c.mirror].name;
        let expected = stride_ocp::gait::mirror_name(&c.name);
        assert_eq!(mirror, &expected);
    }
    assert_eq!(g.coordinates[g.forward_translation].name, "pelvis_tx");
    assert_eq!(g.coordinates[g.vertical_translation].name, "pelvis_ty");
    assert_eq!(g.nm(), 18);
    for (k, &mm) in g.muscle_mirror.iter().enumerate() {
        let name = &m.muscles[g.muscles[k]].name;
        assert_eq!(
            m.muscles[g.muscles[mm]].name,
            stride_ocp::gait::mirror_name(name)
        );
    }
    // the lumbar actuator (300 N m) drives lumbar_extension, which keeps a limit torque
    let l = g.index_of("lumbar_extension").unwrap();
    assert!(matches!(
        g.coordinates[l].actuation,
        stride_ocp::gait::Actuation::Actuator(_)
    ));
    let c = g.coordinates[l].passive.unwrap();
    assert!(p.model.passive_torques[c].has_limit());
    // it is torso, not arm: its acceleration is in the acceleration cost (PREDSIM.md §8)
    assert!(!stride_ocp::gait::is_arm_coordinate(
        &m,
        g.coordinates[l].model_index
    ));
    assert!(g.is_planar(&m));
    // the half-cycle mirror keeps every coordinate's sign and swaps legs
    let q: Vec<f64> = (0..g.nq()).map(|i| i as f64).collect();
    let mq = p.mirror_coordinates(&q);
    let hr = g.index_of("hip_flexion_r").unwrap();
    let hl = g.index_of("hip_flexion_l").unwrap();
    assert_eq!((mq[hr], mq[hl]), (hl as f64, hr as f64));
}

/// Gradient and Jacobian of a 3-interval problem against central differences.
fn check_first_derivatives(m: &Model, s: &ProblemSettings) {
    let p = problem(m, s);
    let mut x = guess_point(&p, GuessKind::DataInformedWalking).unwrap();
    for (i, xi) in x.iter_mut().enumerate() {
        *xi += 1e-3 * ((i as f64 * 0.7548776662).fract() - 0.5);
    }
    let node = NodeModel::new(&p).unwrap();
    let tape = TapeNode::for_problem(&p, &node, &x).unwrap();
    let tr = Transcription::new(p, tape, x.clone());
    let r = check_derivatives(
        &tr,
        &x,
        &DerivativeCheckOptions {
            max_columns: 150,
            tol: 1e-6,
            ..Default::default()
        },
    )
    .unwrap();
    assert!(
        r.mismatches.is_empty(),
        "{:?}",
        &r.mismatches[..r.mismatches.len().min(5)]
    );
}

#[test]
fn toes_model_derivatives_match_finite_differences() {
    check_first_derivatives(&common::shipped_model("falisse2022"), &toes_settings(3));
}

#[test]
fn four_segment_foot_model_derivatives_match_finite_differences() {
    // ligament moments, shifted passive fibres and metabolic b = 100 included
    let mut s = toes_settings(3);
    s.passive.toes = ToeDrive::Muscles;
    check_first_derivatives(&common::shipped_model("dhondt2024"), &s);
}

#[test]
fn planar_model_derivatives_match_finite_differences() {
    let s = ProblemSettings {
        mesh_intervals: 3,
        ..Default::default()
    };
    check_first_derivatives(&common::shipped_model("gait1018"), &s);
}

#[test]
fn predsim_bounds_rule_takes_predsims_table_and_the_standing_height() {
    use stride_ocp::settings::BoundsRule;
    let m = common::shipped_model("gait1018");
    let settings = |bounds| ProblemSettings {
        mesh_intervals: 4,
        bounds,
        ..Default::default()
    };
    let s = settings(BoundsRule::Predsim);
    let p = GaitProblem::new(&m, &s, &bounds_data(&s)).unwrap();
    let i = |name: &str| p.gait.index_of(name).unwrap();
    let close = |r: stride_ocp::range::Range, lo: f64, hi: f64, what: &str| {
        assert!(
            (r.lo - lo).abs() < 1e-12 && (r.hi - hi).abs() < 1e-12,
            "{what}: {r:?} vs [{lo}, {hi}]"
        );
    };
    // PREDSIM.md §7.4, Default_Coordinate_Bounds.csv (rad, rad/s, rad/s²)
    let knee = i("knee_angle_r");
    let hip = i("hip_flexion_l");
    let table = [
        (
            p.bounds.q[knee],
            [-3.05478772880409, 1.69794152173642],
            "knee q",
        ),
        (
            p.bounds.v[knee],
            [-38.8846957065914, 39.5051541565237],
            "knee v",
        ),
        (
            p.bounds.a[knee],
            [-435.367703797436, 441.781759234749],
            "knee a",
        ),
        (
            p.bounds.q[hip],
            [-1.91811668705238, 2.11902321356129],
            "hip q",
        ),
    ];
    for (r, [lo, hi], what) in table {
        close(r, lo, hi, what);
    }
    assert!((p.scaling.a[knee] - 441.781759234749).abs() < 1e-12);
    // pelvis height: [0.5, 1.2] × the standing height, the sum of gait1018's joint
    // offsets from the pelvis to the right calcaneus plus PredSim's 2.5 cm
    let h = 0.063_835_397_331_130_1
        + 0.396_907_245_921_447
        + 0.415_694_825_374_905
        + 0.038_339_127_654_237_4
        + 0.025;
    close(p.bounds.q[i("pelvis_ty")], 0.5 * h, 1.2 * h, "pelvis_ty");
    close(p.bounds.q[i("pelvis_tx")], 0.0, 2.0, "pelvis_tx");
    // the table's pelvis tilt allows 20° of forward tilt; the walking data's rule 2.93°
    // (−0.051142 rad, the value PredSim's D'Hondt settings impose by hand)
    let tilt = i("pelvis_tilt");
    close(
        p.bounds.q[tilt],
        -0.349065850398866,
        0.0672853815966567,
        "pelvis_tilt",
    );
    let s = settings(BoundsRule::Data);
    let d = GaitProblem::new(&m, &s, &bounds_data(&s)).unwrap();
    assert!(
        (d.bounds.q[tilt].lo + 0.051142).abs() < 1e-5,
        "{:?}",
        d.bounds.q[tilt]
    );
}
