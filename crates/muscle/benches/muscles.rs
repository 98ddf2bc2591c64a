//! Benchmark of the per-node muscle evaluation in f64 for the 92 muscles of the paper's
//! model (reference tables under /work/shared): polynomial geometry, Hill residuals,
//! Bhargava metabolics. Prints a table of time per call.
//!
//! Run: `cargo bench -p stride-muscle --bench muscles`.

use std::hint::black_box;
use std::path::{Path, PathBuf};
use std::time::Instant;

use stride_model::PathPolynomial;
use stride_muscle::{
    hill_equilibrium, HillOutput, HillParams, MetabolicModel, MusclePaths, PathPolynomialEval,
    PathWorkspace,
};

/// Coordinates of the benchmark's q vector: 0..9 the right-leg vector of FORMULATION 4.1
/// (hip ×3, knee, ankle, subtalar, lumbar ×3), 9..15 the left hip ×3, knee, ankle, subtalar.
const N_Q: usize = 15;

fn json(path: &Path) -> serde_json::Value {
    serde_json::from_str(&std::fs::read_to_string(path).expect("read json")).expect("parse json")
}

fn load(shared: &Path) -> (Vec<HillParams>, MusclePaths) {
    let refdir = shared.join("reference/muscles");
    let csv = std::fs::read_to_string(refdir.join("mt_parameters_subject1.csv")).unwrap();
    let met = json(&refdir.join("metabolic_parameters.json"));
    let met = met["per_muscle_ocp_order"].as_array().unwrap();
    let mut params = Vec::new();
    for (i, line) in csv.lines().skip(1).filter(|l| !l.is_empty()).enumerate() {
        let f: Vec<&str> = line.split(',').collect();
        let x = |k: usize| f[k].parse::<f64>().unwrap();
        let m = &met[i];
        params.push(
            HillParams::new(
                f[1],
                x(5),
                x(6),
                x(7),
                x(8),
                x(10),
                m["specific_tension_MPa"].as_f64().unwrap() * 1e6,
                m["slow_twitch_fraction"].as_f64().unwrap(),
            )
            .unwrap(),
        );
    }
    let poly = json(&refdir.join("polynomials_subject1.json"));
    let rows = poly["muscles"].as_array().unwrap();
    let map = &poly["use_in_ocp"]["mapping_ocp_index_to_row"];
    let mut polys = Vec::new();
    for ocp in 1..=params.len() {
        let row = map[ocp.to_string()].as_u64().unwrap() as usize;
        let m = &rows[row - 1];
        let left_leg = ocp <= 43;
        let coordinates = m["coordinate_columns"]
            .as_array()
            .unwrap()
            .iter()
            .map(|c| {
                let c = c.as_u64().unwrap() as usize;
                if left_leg && c < 6 {
                    9 + c
                } else {
                    c
                }
            })
            .collect();
        let p = PathPolynomial {
            coordinates,
            order: m["order"].as_u64().unwrap() as u32,
            exponents: m["exponents"]
                .as_array()
                .unwrap()
                .iter()
                .map(|e| {
                    e.as_array()
                        .unwrap()
                        .iter()
                        .map(|v| v.as_u64().unwrap() as u8)
                        .collect()
                })
                .collect(),
            coefficients: m["coefficients"]
                .as_array()
                .unwrap()
                .iter()
                .map(|c| c.as_f64().unwrap())
                .collect(),
            rmse_length: None,
            rmse_moment_arm: None,
        };
        polys.push(PathPolynomialEval::new(ocp - 1, &p).unwrap());
    }
    (params, MusclePaths::new(polys, N_Q).unwrap())
}

/// CPU time of this thread [ns] from `/proc/thread-self/schedstat` (Linux), if available;
/// used because the benchmark machine is shared and wall time includes waiting.
fn thread_cpu_ns() -> Option<u64> {
    let s = std::fs::read_to_string("/proc/thread-self/schedstat").ok()?;
    s.split_whitespace().next()?.parse().ok()
}

/// Median over `reps` batches of the time per call [µs] of `f`, `iters` calls per batch:
/// `(wall, cpu)`, cpu = on-CPU time of the thread (NaN when unavailable).
fn time(mut f: impl FnMut(), iters: usize, reps: usize) -> (f64, f64) {
    for _ in 0..iters {
        f();
    }
    let mut wall = Vec::with_capacity(reps);
    let mut cpu = Vec::with_capacity(reps);
    for _ in 0..reps {
        let c0 = thread_cpu_ns();
        let s = Instant::now();
        for _ in 0..iters {
            f();
        }
        wall.push(s.elapsed().as_secs_f64() * 1e6 / iters as f64);
        let c1 = thread_cpu_ns();
        cpu.push(match (c0, c1) {
            (Some(a), Some(b)) => (b - a) as f64 * 1e-3 / iters as f64,
            _ => f64::NAN,
        });
    }
    let median = |mut v: Vec<f64>| {
        v.sort_by(|a, b| a.total_cmp(b));
        v[v.len() / 2]
    };
    (median(wall), median(cpu))
}

fn main() {
    let shared = PathBuf::from(concat!(env!("CARGO_MANIFEST_DIR"), "/../../../shared"));
    if !shared.join("reference/muscles").is_dir() {
        eprintln!(
            "skipping benchmark: reference data not found at {}",
            shared.display()
        );
        return;
    }
    let (params, paths) = load(&shared);
    let n = params.len();
    let q: Vec<f64> = (0..N_Q).map(|i| 0.1 + 0.03 * i as f64 - 0.2).collect();
    let qdot: Vec<f64> = (0..N_Q).map(|i| 1.5 - 0.2 * i as f64).collect();
    let a: Vec<f64> = (0..n).map(|m| 0.05 + 0.9 * (m as f64 / n as f64)).collect();
    let ft: Vec<f64> = (0..n)
        .map(|m| 0.1 + 0.8 * ((m * 7 % 13) as f64 / 13.0))
        .collect();
    let dft: Vec<f64> = (0..n)
        .map(|m| -2.0 + 4.0 * ((m * 5 % 11) as f64 / 11.0))
        .collect();

    let mut ws = PathWorkspace::for_paths(&paths);
    let (mut lmt, mut vmt) = (vec![0.0; n], vec![0.0; n]);
    let mut arms = vec![0.0; paths.n_moment_arms()];
    let mut res = vec![0.0; n];
    let mut hill: Vec<HillOutput<f64>> =
        vec![hill_equilibrium(&params[0], 0.1, 0.1, 0.0, 0.3, 0.0); n];
    let mut edot = vec![0.0; n];
    paths
        .evaluate(&q, &qdot, &mut ws, &mut lmt, &mut vmt, &mut arms)
        .unwrap();

    let iters = 20_000;
    let reps = 9;
    let t_geom = time(
        || {
            paths
                .evaluate(
                    black_box(&q),
                    black_box(&qdot),
                    &mut ws,
                    &mut lmt,
                    &mut vmt,
                    &mut arms,
                )
                .unwrap();
        },
        iters,
        reps,
    );
    let t_hill = time(
        || {
            for m in 0..n {
                hill[m] =
                    hill_equilibrium(&params[m], black_box(a[m]), ft[m], dft[m], lmt[m], vmt[m]);
                res[m] = hill[m].residual;
            }
        },
        iters,
        reps,
    );
    let t_bh = time(
        || {
            for m in 0..n {
                edot[m] = MetabolicModel::Bhargava2004
                    .rate(&params[m], black_box(a[m]), &hill[m])
                    .total;
            }
        },
        iters,
        reps,
    );
    let t_all = time(
        || {
            paths
                .evaluate(
                    black_box(&q),
                    black_box(&qdot),
                    &mut ws,
                    &mut lmt,
                    &mut vmt,
                    &mut arms,
                )
                .unwrap();
            for m in 0..n {
                let h =
                    hill_equilibrium(&params[m], black_box(a[m]), ft[m], dft[m], lmt[m], vmt[m]);
                res[m] = h.residual;
                edot[m] = MetabolicModel::Bhargava2004
                    .rate(&params[m], a[m], &h)
                    .total;
            }
        },
        iters,
        reps,
    );
    let mut other = Vec::new();
    for model in MetabolicModel::ALL.iter().skip(1) {
        let t = time(
            || {
                for m in 0..n {
                    edot[m] = model.rate(&params[m], black_box(a[m]), &hill[m]).total;
                }
            },
            iters / 4,
            reps,
        );
        other.push((*model, t));
    }
    black_box((&res, &edot, &arms));

    println!(
        "muscle layer, f64, {n} muscles ({} moment arms), median of {reps} batches",
        paths.n_moment_arms()
    );
    println!(
        "{:<48} {:>12} {:>12}",
        "function", "wall µs/call", "cpu µs/call"
    );
    let row = |name: &str, t: (f64, f64)| println!("{name:<48} {:>12.3} {:>12.3}", t.0, t.1);
    row("polynomial geometry (l_MT, v_MT, moment arms)", t_geom);
    row("Hill residuals + side outputs", t_hill);
    row(
        "geometry + Hill",
        (t_geom.0 + t_hill.0, t_geom.1 + t_hill.1),
    );
    row("Bhargava 2004 metabolic rate", t_bh);
    for (m, t) in other {
        row(&format!("{m:?} metabolic rate"), t);
    }
    row("geometry + Hill + Bhargava (one pass)", t_all);
}
