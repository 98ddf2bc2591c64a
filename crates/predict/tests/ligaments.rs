//! Ligament moments of `DHondt_et_al_2024_4seg` (26 ligaments): the generalised force on
//! each coordinate against −F(l)·∂l/∂q with ∂l/∂q by central differences of the fitted
//! length polynomial, the moments entering the torque balances of the spanned
//! coordinates and nothing else (not the cost), and the torque tables of a result folder:
//! ligament lengths, forces and moments against the same independent computation, the
//! written terms closing the torque balance up to the node's own residual. The derivatives
//! of a small D'Hondt problem are checked in `predsim_models.rs`.

mod common;

use stride_geometry::polynomial_length;
use stride_model::Model;
use stride_muscle::ligament::LigamentLaw;
use stride_ocp::bounds::bounds_data;
use stride_ocp::layout::Point;
use stride_ocp::ligaments::Ligaments;
use stride_ocp::passive_rules::PassiveCost;
use stride_ocp::{
    guess::GuessKind, node::NodeModel, problem::GaitProblem, settings::ProblemSettings,
};
use stride_predict::predict::guess_point;

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
    let m = common::shipped_model("dhondt2024");
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
    let with = common::shipped_model("dhondt2024");
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

/// A CSV table of a result folder: column names (units dropped) and rows.
fn table(dir: &std::path::Path, file: &str) -> (Vec<String>, Vec<Vec<f64>>) {
    let text = std::fs::read_to_string(dir.join(file)).unwrap();
    let mut lines = text.lines();
    let header = lines.next().unwrap().split(',').skip(1);
    let names = header
        .map(|h| stride_predict::outputs::column_name(h).to_string())
        .collect();
    let rows = lines
        .map(|l| l.split(',').skip(1).map(|v| v.parse().unwrap()).collect())
        .collect();
    (names, rows)
}

/// The node input of row `i` of a reconstructed cycle (as the result files evaluate it).
fn row_input(p: &GaitProblem, c: &stride_ocp::trajectory::Trajectory, i: usize) -> Vec<f64> {
    let (l, s) = (&p.layout, &p.scaling);
    let io = stride_ocp::transcription::NodeInputs {
        nm: l.nm,
        nq: l.nq,
        na: l.na,
    };
    let mut x = vec![0.0; io.len()];
    for m in 0..l.nm {
        x[io.a() + m] = c.activation[i][m];
        x[io.f() + m] = c.tendon_force[i][m] / s.tendon_force;
        x[io.df() + m] = c.tendon_force_rate[i][m] / s.tendon_force_rate;
    }
    for k in 0..l.nq {
        x[io.q() + k] = c.q[i][k] / s.q[k];
        x[io.v() + k] = c.v[i][k] / s.v[k];
        x[io.qdd() + k] = c.qdd[i][k] / s.a[k];
    }
    for k in 0..l.na {
        x[io.arm() + k] = c.arm_activation[i][k];
    }
    x
}

/// Torque-balance residual [N m or N] of every problem coordinate from the node's path
/// constraints at input `x`: inverse dynamics minus the muscle, passive, actuator and
/// ligament torques (0 at an optimum, to the solver's tolerance).
fn balance_residuals(p: &GaitProblem, node: &NodeModel, x: &[f64]) -> Vec<f64> {
    let mut ws = node.workspace::<f64>().unwrap();
    let mut y = vec![0.0; node.n_outputs()];
    node.eval(&mut ws, x, &mut y);
    let o = node.outputs();
    let mut r = vec![0.0; p.layout.nq];
    let g = &p.gait;
    let rows = g.root().into_iter().chain(g.muscle_driven());
    for (k, i) in rows.enumerate() {
        r[i] = y[k];
    }
    for (k, i) in g.actuator_driven().into_iter().enumerate() {
        r[i] = y[o.root + o.muscle_driven + k] * p.scaling.arm_torque;
    }
    r
}

/// Relative tolerance of the torque balance from the files. `joint_torques.csv` holds the
/// inverse dynamics of the simulated samples, mirrored and shifted forward onto the rows of
/// the cycle; the other tables are evaluated at each row's own state. The D'Hondt model is
/// invariant to either only nearly: its left and right segments are mirror images to the
/// precision of its model file, and its contact forces change by 1·10⁻⁷ of their value
/// when the pelvis moves forward by 0.3 m. Gaps up to 5·10⁻⁶ of the torque; a missing term
/// would be of the order of the term.
const BALANCE_TOL: f64 = 2e-5;

/// Checks one row of the ligament tables (`lengths`, `forces` per ligament and `moment` of
/// problem coordinate k) against the fitted length polynomials at the problem coordinates
/// `q_row`, the moments against −Σ F ∂l/∂q by central differences; returns the largest
/// moment [N m].
fn check_ligaments(
    m: &Model,
    p: &GaitProblem,
    q_row: &[f64],
    (lengths, forces): (&[f64], &[f64]),
    moment: impl Fn(usize) -> f64,
) -> f64 {
    let h = 1e-6;
    let mut q: Vec<f64> = m.coordinates.iter().map(|c| c.default_value).collect();
    for (k, gc) in p.gait.coordinates.iter().enumerate() {
        q[gc.model_index] = q_row[k];
    }
    let mut expected = vec![0.0; q_row.len()];
    for (j, l) in m.ligaments.iter().enumerate() {
        let poly = l.path_polynomial.as_ref().unwrap();
        let length = polynomial_length(poly, &q);
        let law = LigamentLaw::for_name(&l.name);
        let force = law.force(l.pcsa_force, l.resting_length, length);
        assert!((lengths[j] - length).abs() < 1e-12, "{}: length", l.name);
        assert!(
            (forces[j] - force).abs() < 1e-9 * (1.0 + force),
            "{}",
            l.name
        );
        for (k, gc) in p.gait.coordinates.iter().enumerate() {
            let (mut qp, mut qm) = (q.clone(), q.clone());
            qp[gc.model_index] += h;
            qm[gc.model_index] -= h;
            let dl = (polynomial_length(poly, &qp) - polynomial_length(poly, &qm)) / (2.0 * h);
            expected[k] -= force * dl;
        }
    }
    let mut largest: f64 = 0.0;
    for (k, e) in expected.iter().enumerate() {
        let got = moment(k);
        let name = &p.gait.coordinates[k].name;
        assert!(
            (got - e).abs() <= 1e-6 * (1.0 + e.abs()),
            "{name}: {got} vs {e}"
        );
        largest = largest.max(got.abs());
    }
    largest
}

#[test]
fn result_tables_close_the_torque_balance_with_the_ligament_moments() {
    let m = common::shipped_model("dhondt2024");
    let p = problem(&m, 3);
    let node = NodeModel::new(&p).unwrap();
    let mut x = guess_point(&p, GuessKind::DataInformedWalking).unwrap();
    // dorsiflex the midtarsal and toe joints throughout to stretch the plantar ligaments
    let l = &p.layout;
    let points = (0..=l.n).map(Point::Mesh);
    let points = points.chain((0..l.n).flat_map(|k| (1..=3).map(move |j| Point::Col(k, j))));
    for pt in points {
        for name in ["mtj_angle_r", "mtp_angle_r", "mtj_angle_l", "mtp_angle_l"] {
            let i = p.gait.index_of(name).unwrap();
            x[l.q(pt, i)] = 0.3 / p.scaling.q[i];
        }
    }
    let x = common::consistent(&p, x);
    let mesh = p.mesh_solution(&node, &x).unwrap();
    let cycle = p.gait_cycle(&mesh);
    let dir = std::env::temp_dir().join(format!("stride-ligament-tables-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    stride_predict::outputs::write_cycle(&p, &node, &cycle, &dir).unwrap();
    let (coords, total) = table(&dir, "joint_torques.csv");
    let terms: Vec<Vec<Vec<f64>>> = ["muscle", "passive", "actuator", "ligament"]
        .iter()
        .map(|t| {
            let (names, rows) = table(&dir, &format!("{t}_torques.csv"));
            assert_eq!(names, coords, "{t}_torques.csv columns");
            rows
        })
        .collect();
    let names: Vec<String> = m.ligaments.iter().map(|l| l.name.clone()).collect();
    let (lnames, lengths) = table(&dir, "ligament_lengths.csv");
    let (fnames, forces) = table(&dir, "ligament_forces.csv");
    assert_eq!((&lnames, &fnames), (&names, &names));
    let _ = std::fs::remove_dir_all(&dir);
    let (mut worst, mut largest): (f64, f64) = (0.0, 0.0);
    for (i, q_row) in cycle.q.iter().enumerate() {
        // the torque balance closes from the files up to the node's residual
        let residual = balance_residuals(&p, &node, &row_input(&p, &cycle, i));
        for (c, name) in coords.iter().enumerate() {
            let sum: f64 = terms.iter().map(|t| t[i][c]).sum();
            let gap = total[i][c] - sum - residual[c];
            let rel = gap.abs() / (1.0 + total[i][c].abs());
            assert!(rel < BALANCE_TOL, "row {i} {name}: {gap}");
            worst = worst.max(rel);
        }
        let moment = |k: usize| terms[3][i][k];
        let l = check_ligaments(&m, &p, q_row, (&lengths[i], &forces[i]), moment);
        largest = largest.max(l);
    }
    println!(
        "torque balance from the files beyond the node's residual: {worst:.1e} of the \
         torque; largest ligament moment {largest:.2} N m"
    );
    assert!(largest > 1.0, "no ligament is stretched: {largest} N m");
}
