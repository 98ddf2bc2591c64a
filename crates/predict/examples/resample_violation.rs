//! Development driver: constraint violation, by group, of a coarse optimum resampled to a
//! finer mesh. `resample_violation <coarse N> <fine N> [qr|di]`.
use std::sync::Arc;
use stride_ocp::{
    guess::GuessKind, node::NodeModel, problem::GaitProblem, settings::ProblemSettings,
    tape_node::TapeNode, transcription::Transcription,
};
use stride_solve::nlp::Nlp;
use stride_solve::solver::SolverOptions;

fn main() {
    let a: Vec<String> = std::env::args().collect();
    let nc: usize = a[1].parse().unwrap();
    let nf: usize = a[2].parse().unwrap();
    let guess = if a.get(3).map(|s| s.as_str()) == Some("qr") {
        GuessKind::QuasiRandom
    } else {
        GuessKind::DataInformedWalking
    };
    let model = stride_model::default_model::default_model();
    let settings = |n| ProblemSettings {
        mesh_intervals: n,
        ..Default::default()
    };
    let options = SolverOptions {
        threads: 1,
        ..stride_predict::predict::prediction_options()
    };
    let solver = stride_solve::ipm::InteriorPoint::new();
    let (coarse, solved) = stride_predict::predict::solve_guesses(
        &model,
        &settings(nc),
        &[guess],
        None,
        &solver,
        &options,
        &|_, _| {},
    )
    .unwrap();
    let fine = GaitProblem::new(
        &model,
        &settings(nf),
        &stride_ocp::bounds::bounds_data(&settings(nf)),
    )
    .unwrap();
    let x = fine
        .guess_from_full_solution(&coarse, &solved[0].result.x)
        .unwrap();
    let node = NodeModel::new(&fine).unwrap();
    let tape = Arc::new(TapeNode::for_problem(&fine, &node, &x).unwrap());
    let tr = Transcription::new(fine.clone(), tape, x.clone());
    let (mut xl, mut xu) = (vec![0.0; tr.n()], vec![0.0; tr.n()]);
    let (mut gl, mut gu) = (vec![0.0; tr.m()], vec![0.0; tr.m()]);
    tr.bounds(&mut xl, &mut xu, &mut gl, &mut gu);
    let mut g = vec![0.0; tr.m()];
    tr.constraints(&x, &mut g).unwrap();
    let l = &fine.layout;
    let ns = l.n_states();
    let n_nodes = 3 * l.n;
    let out = node.outputs();
    let n_path = out.n_path();
    let per = ns + n_path;
    let path_group = |o: usize| -> &'static str {
        if o < out.root {
            "path root"
        } else if o < out.hill() - out.arms {
            "path torque"
        } else if o < out.hill() {
            "path arm"
        } else if o < out.activation() {
            "path hill"
        } else if o < out.distance() {
            "path excit"
        } else {
            "path dist"
        }
    };
    let mut groups: std::collections::BTreeMap<String, (f64, f64)> = Default::default();
    for (i, &v) in g.iter().enumerate() {
        let viol = (gl[i] - v).max(v - gu[i]).max(0.0);
        let name = if i < n_nodes * per {
            let o = i % per;
            if o < ns {
                let kind = if o < l.nm {
                    "col a"
                } else if o < 2 * l.nm {
                    "col F"
                } else if o < 2 * l.nm + l.nq {
                    "col q"
                } else if o < 2 * l.nm + 2 * l.nq {
                    "col v"
                } else {
                    "col arm"
                };
                kind.to_string()
            } else {
                path_group(o - ns).to_string()
            }
        } else if i < n_nodes * per + ns * l.n {
            "continuity".into()
        } else {
            "other".into()
        };
        let e = groups.entry(name).or_insert((0.0, 0.0));
        e.0 = e.0.max(viol);
        e.1 += viol;
    }
    let bounds = x
        .iter()
        .zip(xl.iter().zip(&xu))
        .map(|(&v, (&lo, &hi))| (lo - v).max(v - hi).max(0.0))
        .fold(0.0, f64::max);
    println!("m {}, variable bound violation {bounds:e}", tr.m());
    let mut v: Vec<_> = groups.into_iter().collect();
    v.sort_by(|a, b| b.1 .0.partial_cmp(&a.1 .0).unwrap());
    for (k, (mx, sum)) in v.iter().take(25) {
        println!("{k:12} max {mx:10.3e} sum {sum:10.3e}");
    }
}
