//! Benchmark: time per call (f64) of the multibody functions on the subject model
//! (31 coordinates, 12 contact spheres). Prints a table; `cargo bench -p stride-multibody`.

#[path = "../tests/common/mod.rs"]
mod common;

use std::hint::black_box;
use std::time::Instant;

use stride_multibody::*;

/// CPU time of this thread [s] from /proc (insensitive to other processes' load), if available.
fn thread_cpu_time() -> Option<f64> {
    let s = std::fs::read_to_string("/proc/thread-self/schedstat").ok()?;
    let ns: f64 = s.split_whitespace().next()?.parse().ok()?;
    Some(ns * 1e-9)
}

/// Wall-clock and on-CPU time per call [s].
fn time_per_call(mut f: impl FnMut(), min_seconds: f64) -> (f64, f64) {
    for _ in 0..1000 {
        f();
    }
    let mut n = 1000u64;
    loop {
        let t0 = Instant::now();
        let c0 = thread_cpu_time();
        for _ in 0..n {
            f();
        }
        let dt = t0.elapsed().as_secs_f64();
        let dc = match (c0, thread_cpu_time()) {
            (Some(a), Some(b)) => b - a,
            _ => f64::NAN,
        };
        if dt > min_seconds {
            return (dt / n as f64, dc / n as f64);
        }
        n *= 4;
    }
}

fn main() {
    let Some(model) = common::subject_model(false) else {
        return;
    };
    let n = model.coordinates.len();
    let mut data = Data::<f64>::new(&model).unwrap();
    let mut out = SkeletonOutput::new(&model, &data);
    let mut q: Vec<f64> = (0..n).map(|i| 0.05 * ((i as f64) * 0.7).sin()).collect();
    q[model.coordinate_index("pelvis_ty").unwrap()] = 0.95;
    let v: Vec<f64> = (0..n).map(|i| 0.5 * ((i as f64) * 1.3).cos()).collect();
    let a: Vec<f64> = (0..n).map(|i| 3.0 * ((i as f64) * 0.4).sin()).collect();
    let mut tau = vec![0.0; n];
    println!(
        "stride-multibody dynamics benchmark: {n} coordinates, {} spheres, f64",
        model.contacts.len()
    );
    println!("{:<40} {:>12} {:>12}", "function", "wall/call", "cpu/call");
    let rows: Vec<(&str, (f64, f64))> = vec![
        (
            "forward_kinematics (q, v)",
            time_per_call(
                || forward_kinematics(&model, &mut data, black_box(&q), black_box(&v)).unwrap(),
                0.5,
            ),
        ),
        (
            "inverse_dynamics (no contact)",
            time_per_call(
                || {
                    inverse_dynamics(
                        &model,
                        &mut data,
                        black_box(&q),
                        black_box(&v),
                        black_box(&a),
                        &mut tau,
                    )
                    .unwrap()
                },
                0.5,
            ),
        ),
        (
            "skeleton_dynamics (ID + 12 spheres)",
            time_per_call(
                || {
                    skeleton_dynamics(
                        &model,
                        &mut data,
                        black_box(&q),
                        black_box(&v),
                        black_box(&a),
                        &mut out,
                    )
                    .unwrap()
                },
                0.5,
            ),
        ),
    ];
    for (name, (w, c)) in rows {
        println!("{name:<40} {:>9.3} µs {:>9.3} µs", w * 1e6, c * 1e6);
    }

    // The same function recorded once on a tape (inputs q, v, qdd; outputs tau and the
    // two foot forces), as the optimal control problem uses it.
    use stride_ad::{Tape, Var};
    let mut x0 = q.clone();
    x0.extend_from_slice(&v);
    x0.extend_from_slice(&a);
    let t0 = Instant::now();
    let tape = Tape::record(&x0, |x: &[Var]| {
        let mut d = Data::<Var>::new(&model).unwrap();
        let mut o = SkeletonOutput::new(&model, &d);
        skeleton_dynamics(&model, &mut d, &x[..n], &x[n..2 * n], &x[2 * n..], &mut o).unwrap();
        let mut y = o.tau.clone();
        for g in &o.group_force {
            y.extend_from_slice(g);
        }
        y
    })
    .unwrap();
    let rec = t0.elapsed().as_secs_f64();
    let st = tape.stats();
    println!(
        "tape: {} ops, Jacobian {} nonzeros ({} colours), Hessian {} nonzeros; recording + analysis {:.1} ms",
        st.n_ops,
        st.jac_nnz,
        st.jac_colours,
        st.hes_nnz,
        rec * 1e3
    );
    let mut ws = tape.workspace();
    let mut y = vec![0.0; tape.n_outputs()];
    let mut jac = vec![0.0; st.jac_nnz];
    let (w, c) = time_per_call(|| tape.eval(black_box(&x0), &mut ws, &mut y).unwrap(), 0.5);
    println!(
        "{:<40} {:>9.3} µs {:>9.3} µs",
        "tape eval",
        w * 1e6,
        c * 1e6
    );
    let (w, c) = time_per_call(
        || {
            tape.jacobian(black_box(&x0), &mut ws, &mut y, &mut jac)
                .unwrap()
        },
        0.5,
    );
    println!(
        "{:<40} {:>9.3} µs {:>9.3} µs",
        "tape Jacobian (values + all entries)",
        w * 1e6,
        c * 1e6
    );
}
