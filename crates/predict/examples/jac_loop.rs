//! Development driver: time the gait NLP's constraint Jacobian (50 intervals, data-informed
//! walking guess, node cache cleared before every call) and print the median.
//! `cargo run --release -p stride-predict --example jac_loop -- [reps] [threads] [hessian]`;
//! with `hessian` the Lagrangian Hessian (multipliers 1, cold cache) is timed instead. With
//! `JAC_OUT=<file>` the values are also written as little-endian `f64` (to compare builds
//! bit for bit).
use stride_ocp::{guess::GuessKind, settings::ProblemSettings};
use stride_solve::nlp::Nlp;
fn main() {
    let reps: usize = std::env::args()
        .nth(1)
        .and_then(|s| s.parse().ok())
        .unwrap_or(200);
    let model = stride_model::default_model::default_model();
    let settings = ProblemSettings {
        mesh_intervals: 50,
        ..Default::default()
    };
    let nlp =
        stride_predict::predict::transcribe(&model, &settings, GuessKind::DataInformedWalking)
            .unwrap();
    let mut x = vec![0.0; nlp.n()];
    nlp.initial_point(&mut x);
    let hessian = std::env::args().nth(3).as_deref() == Some("hessian");
    let nnz = if hessian {
        nlp.hessian_structure().nnz()
    } else {
        nlp.jacobian_structure().nnz()
    };
    let mut jac = vec![0.0; nnz];
    let lambda = vec![1.0; nlp.m()];
    let th: usize = std::env::args()
        .nth(2)
        .and_then(|s| s.parse().ok())
        .unwrap_or(1);
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(th)
        .build()
        .unwrap();
    pool.install(|| {
        let mut v = Vec::new();
        for _ in 0..reps {
            nlp.clear_cache();
            let t = std::time::Instant::now();
            if hessian {
                nlp.hessian_values(&x, 1.0, &lambda, &mut jac).unwrap();
            } else {
                nlp.jacobian_values(&x, &mut jac).unwrap();
            }
            v.push(t.elapsed().as_secs_f64() * 1e3);
        }
        v.sort_by(|a, b| a.partial_cmp(b).unwrap());
        let s: f64 = jac.iter().map(|x| x.abs()).sum();
        if let Ok(f) = std::env::var("JAC_OUT") {
            let bytes: Vec<u8> = jac.iter().flat_map(|v| v.to_le_bytes()).collect();
            std::fs::write(f, bytes).unwrap();
        }
        println!(
            "{} median {:.2} ms min {:.2} (checksum {s:.12e})",
            if hessian { "hessian" } else { "jacobian" },
            v[v.len() / 2],
            v[0]
        );
    });
}
