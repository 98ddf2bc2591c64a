//! Ligament moments of `DHondt_et_al_2024_4seg` (26 ligaments): the generalised force on
//! each coordinate against −F(l)·∂l/∂q with ∂l/∂q by central differences of the fitted
//! length polynomial, the moments entering the torque balances of the spanned
//! coordinates and nothing else (not the cost). The derivatives of a small D'Hondt problem
//! are checked in `predsim_models.rs`.

use stride_geometry::{polynomial_length, GeometryFile};
use stride_model::model_settings::ModelSettings;
use stride_model::Model;
use stride_muscle::ligament::LigamentLaw;
use stride_ocp::bounds::bounds_data;
use stride_ocp::ligaments::Ligaments;
use stride_ocp::passive_rules::PassiveCost;
use stride_ocp::{
    guess::GuessKind, node::NodeModel, problem::GaitProblem, settings::ProblemSettings,
};
use stride_predict::predict::guess_point;

/// The shipped D'Hondt model with its settings file and fitted geometry.
fn dhondt() -> Model {
    let s = stride_model::shipped::shipped("dhondt2024").unwrap();
    let mut m = stride_model::osim::parse_osim(s.osim, s.file_name).unwrap();
    ModelSettings::parse(s.settings, "dhondt2024")
        .unwrap()
        .apply(&mut m, "dhondt2024")
        .unwrap();
    GeometryFile::parse(s.geometry, "dhondt2024")
        .unwrap()
        .apply(&mut m)
        .unwrap();
    m
}

/// A foot pose that stretches the plantar ligaments: dorsiflexed midtarsal and toes.
fn stretched_pose(m: &Model) -> Vec<f64> {
    let mut q: Vec<f64> = m.coordinates.iter().map(|c| c.default_value).collect();
    for (name, v) in [
        ("mtj_angle_r", 0.25),
        ("mtp_angle_r", 0.6),
        ("subtalar_angle_r", 0.1),
        ("ankle_angle_r", 0.2),
        ("mtj_angle_l", -0.1),
        ("mtp_angle_l", 0.3),
    ] {
        q[m.coordinate_index(name).unwrap()] = v;
    }
    q
}

#[test]
fn ligament_moment_is_minus_force_times_the_length_gradient() {
    let m = dhondt();
    assert_eq!(m.ligaments.len(), 26);
    let coords: Vec<usize> = (0..m.coordinates.len()).collect();
    let lig = Ligaments::new(&m, &coords).unwrap();
    let q = stretched_pose(&m);
    let mut ws = lig.workspace::<f64>();
    lig.evaluate(&q, &mut ws);
    let h = 1e-6;
    let mut spanned = 0;
    let mut largest: f64 = 0.0;
    for (c, coordinate) in m.coordinates.iter().enumerate() {
        let mut expected = 0.0;
        for l in &m.ligaments {
            let p = l.path_polynomial.as_ref().unwrap();
            let length = polynomial_length(p, &q);
            let force =
                LigamentLaw::for_name(&l.name).force(l.pcsa_force, l.resting_length, length);
            let (mut qp, mut qm) = (q.clone(), q.clone());
            qp[c] += h;
            qm[c] -= h;
            let dl = (polynomial_length(p, &qp) - polynomial_length(p, &qm)) / (2.0 * h);
            expected -= force * dl;
        }
        let got = lig.moment(c, &ws).unwrap_or(0.0);
        assert!(
            (got - expected).abs() <= 1e-6 * (1.0 + expected.abs()),
            "{}: {got} vs {expected}",
            coordinate.name
        );
        if got != 0.0 {
            spanned += 1;
            largest = largest.max(got.abs());
        }
    }
    // the plantar ligaments resist the dorsiflexed midtarsal joint
    let mtj = m.coordinate_index("mtj_angle_r").unwrap();
    let moment = lig.moment(mtj, &ws).unwrap();
    println!("{spanned} coordinates spanned; mtj_angle_r moment {moment:.2} N m; largest {largest:.2} N m");
    assert!(moment.abs() > 1.0, "{moment}");
}

fn problem(m: &Model, mesh: usize) -> GaitProblem {
    let mut s = ProblemSettings {
        mesh_intervals: mesh,
        ..Default::default()
    };
    s.passive.cost = PassiveCost::Limit;
    GaitProblem::new(m, &s, &bounds_data(&s)).unwrap()
}

#[test]
fn ligaments_enter_the_torque_balances_of_their_coordinates_only() {
    let with = dhondt();
    let mut without = with.clone();
    without.ligaments.clear();
    let eval = |m: &Model| {
        let p = problem(m, 3);
        let node = NodeModel::new(&p).unwrap();
        let x = guess_point(&p, GuessKind::QuasiRandom).unwrap();
        let io = stride_ocp::transcription::NodeInputs {
            nm: p.layout.nm,
            nq: p.layout.nq,
            na: p.layout.na,
        };
        let mut xin: Vec<f64> = io
            .global_indices(&p.layout, 1, 1)
            .iter()
            .map(|&g| x[g])
            .collect();
        // dorsiflex the right midtarsal and toe joints to stretch the plantar ligaments
        for name in ["mtj_angle_r", "mtp_angle_r"] {
            let i = p.gait.index_of(name).unwrap();
            xin[io.q() + i] = 0.3 / p.scaling.q[i];
        }
        let mut ws = node.workspace::<f64>().unwrap();
        let mut y = vec![0.0; node.n_outputs()];
        node.eval(&mut ws, &xin, &mut y);
        (p, node, y)
    };
    let (p, node, y1) = eval(&with);
    let (_, _, y0) = eval(&without);
    let o = node.outputs();
    let driven = p.gait.muscle_driven();
    let mut changed = Vec::new();
    for (k, (a, b)) in y1.iter().zip(&y0).take(o.n_path()).enumerate() {
        if (a - b).abs() > 1e-9 {
            assert!(
                k >= o.root && k < o.root + o.muscle_driven,
                "output {k} changed: {a} vs {b}"
            );
            changed.push(p.gait.coordinates[driven[k - o.root]].name.clone());
        }
    }
    // the cost integrand does not see the ligaments
    assert_eq!(y1[o.n_path()], y0[o.n_path()]);
    assert!(changed.iter().any(|c| c == "mtj_angle_r"), "{changed:?}");
    assert!(
        changed.iter().all(|c| c.contains("mtj")
            || c.contains("mtp")
            || c.contains("subtalar")
            || c.contains("ankle")),
        "{changed:?}"
    );
}
