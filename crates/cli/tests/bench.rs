//! `stride bench`: the solver tables at a tiny size, and argument validation.

mod common;
use common::{rejects, stride};

#[test]
fn bench_solver_at_five_intervals_prints_both_tables_and_converges() {
    let out = stride(&[
        "bench",
        "solver",
        "--sizes",
        "5",
        "--backend",
        "all",
        "--hessian",
        "exact,limited-memory",
        "--time-limit",
        "60",
    ]);
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(
        out.status.success(),
        "{text}\n{}",
        String::from_utf8_lossy(&out.stderr)
    );
    assert!(text.contains("## KKT factorisation"), "{text}");
    assert!(text.contains("## Full solves"), "{text}");
    // 5 intervals × 10 links: 5·110 + 20 = 570 variables.
    let rows: Vec<&str> = text.lines().filter(|l| l.starts_with("| 5 |")).collect();
    let backends = if cfg!(feature = "ipopt") { 2 } else { 1 };
    assert_eq!(rows.len(), 1 + 2 * backends, "{text}");
    assert!(rows[0].starts_with("| 5 | 570 | "), "{}", rows[0]);
    let exact = rows
        .iter()
        .find(|r| r.starts_with("| 5 | 570 | stride-ipm | exact |"))
        .expect("ipm exact row");
    assert!(
        exact.contains("| Optimal |") || exact.contains("| Acceptable |"),
        "{exact}"
    );
    assert!(
        rows.iter()
            .any(|r| r.starts_with("| 5 | 570 | stride-ipm | l-bfgs(6) |")),
        "{text}"
    );
    if !cfg!(feature = "ipopt") {
        assert!(text.contains("`all` runs ipm only"), "{text}");
    }
}

#[test]
fn bench_rejects_bad_arguments_with_one_line() {
    rejects(&["bench", "solver", "--sizes", "25,0"], "size 0");
    rejects(
        &["bench", "solver", "--backend", "newton"],
        "unknown backend `newton`",
    );
    rejects(
        &["bench", "solver", "--hessian", "exact,bfgs"],
        "unknown hessian `bfgs`",
    );
    rejects(
        &["bench", "solver", "--time-limit", "0"],
        "`time_limit` = 0",
    );
    rejects(&["bench", "derivatives", "--mesh", "0"], "mesh_intervals");
    rejects(&["bench", "derivatives", "--reps", "0"], "--reps 0");
    rejects(&["bench", "predict", "--mesh", "0"], "mesh_intervals");
    rejects(
        &["bench", "predict", "--backend", "fast"],
        "unknown backend `fast`",
    );
    rejects(
        &["bench", "predict", "--hessian", "newton"],
        "unknown hessian `newton`",
    );
    rejects(
        &["bench", "predict", "--guess", "standing"],
        "unknown initial guess `standing`",
    );
    rejects(
        &["bench", "predict", "--presolve-mesh", "50"],
        "presolve_mesh 50: the coarse mesh must have fewer intervals than the mesh (50)",
    );
    rejects(
        &["bench", "predict", "--presolve-mesh", "1"],
        "presolve_mesh 1",
    );
    rejects(&["bench", "track", "--mesh", "1"], "--mesh 1");
    rejects(
        &["bench", "track", "--hessian", "newton"],
        "unknown hessian `newton`",
    );
    rejects(&["bench", "track", "--max-iter", "0"], "--max-iter 0");
    if !cfg!(feature = "ipopt") {
        rejects(
            &["bench", "solver", "--backend", "ipopt"],
            "--features ipopt",
        );
        rejects(
            &["bench", "predict", "--backend", "ipopt"],
            "--features ipopt",
        );
    }
}
