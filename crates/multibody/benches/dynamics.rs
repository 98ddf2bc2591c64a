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
}
