//! Record-once tapes: the muscle functions recorded at one point and replayed at others
//! must reproduce the f64 evaluation there (no hidden branching on values).

mod common;

use common::{hill_params, polynomials, shared};
use stride_ad::{Tape, Var};
use stride_muscle::activation::ActivationDynamics;
use stride_muscle::{
    hill_equilibrium, MetabolicModel, MusclePaths, PathPolynomialEval, PathWorkspace,
};

#[test]
fn hill_and_metabolics_replay_at_other_points() {
    let Some(sh) = shared() else { return };
    let p = hill_params(&sh, "soleus_r");
    let act = ActivationDynamics::default();
    let node = |x: &[Var]| -> Vec<Var> {
        let h = hill_equilibrium(&p, x[0], x[1], x[2], x[3], x[4]);
        let mut out = vec![h.residual, h.tendon_force, act.excitation(x[0], x[2])];
        out.extend(
            MetabolicModel::ALL
                .iter()
                .map(|m| m.rate(&p, x[0], &h).total),
        );
        out
    };
    // Recorded while shortening with ȧ-like input > 0; replayed lengthening with < 0.
    let tape = Tape::record(&[0.5, 0.5, 1.0, 0.29, -0.05], node).unwrap();
    let mut ws = tape.workspace();
    for x in [[0.2, 0.8, -3.0, 0.30, 0.15], [0.9, 0.1, 0.0, 0.28, 0.0]] {
        let mut y = vec![0.0; tape.n_outputs()];
        tape.eval(&x, &mut ws, &mut y).unwrap();
        let h = hill_equilibrium(&p, x[0], x[1], x[2], x[3], x[4]);
        let mut want = vec![h.residual, h.tendon_force, act.excitation(x[0], x[2])];
        want.extend(
            MetabolicModel::ALL
                .iter()
                .map(|m| m.rate(&p, x[0], &h).total),
        );
        for (k, (a, b)) in y.iter().zip(&want).enumerate() {
            assert!(
                (a - b).abs() <= 1e-12 * b.abs().max(1.0),
                "output {k}: tape {a} vs f64 {b}"
            );
        }
    }
}

#[test]
fn geometry_replays_and_reports_tape_size() {
    let Some(sh) = shared() else { return };
    let polys: Vec<PathPolynomialEval> = polynomials(&sh)
        .iter()
        .enumerate()
        .map(|(m, (_, p))| PathPolynomialEval::new(m, p).unwrap())
        .collect();
    let paths = MusclePaths::new(polys, 9).unwrap();
    let n = paths.n_muscles();
    let na = paths.n_moment_arms();
    let run = |x: &[Var]| -> Vec<Var> {
        let mut ws = PathWorkspace::<Var>::for_paths(&paths);
        let zero = <Var as stride_ad::Scalar>::zero();
        let (mut l, mut v, mut r) = (vec![zero; n], vec![zero; n], vec![zero; na]);
        paths
            .evaluate(&x[..9], &x[9..], &mut ws, &mut l, &mut v, &mut r)
            .unwrap();
        l.into_iter().chain(v).chain(r).collect()
    };
    let x0: Vec<f64> = (0..18).map(|i| 0.1 * i as f64 - 0.5).collect();
    let tape = Tape::record(&x0, run).unwrap();
    eprintln!("geometry tape for {n} polynomials: {:?}", tape.stats());
    let x1: Vec<f64> = (0..18).map(|i| 0.3 - 0.05 * i as f64).collect();
    let mut y = vec![0.0; tape.n_outputs()];
    tape.eval(&x1, &mut tape.workspace(), &mut y).unwrap();
    let mut ws = PathWorkspace::for_paths(&paths);
    let (mut l, mut v, mut r) = (vec![0.0; n], vec![0.0; n], vec![0.0; na]);
    paths
        .evaluate(&x1[..9], &x1[9..], &mut ws, &mut l, &mut v, &mut r)
        .unwrap();
    let want: Vec<f64> = l.into_iter().chain(v).chain(r).collect();
    for (k, (a, b)) in y.iter().zip(&want).enumerate() {
        assert!(
            (a - b).abs() <= 1e-12 * b.abs().max(1.0),
            "output {k}: tape {a} vs f64 {b}"
        );
    }
}
