//! Lagrangian consistency of the inverse dynamics on the full 31-coordinate subject model:
//! gravity torques = ∇V, ID(q, q̇, q̈) − ID(q, q̇, 0) = M(q) q̈ with M from the kinetic
//! energy, and velocity terms = d/dt ∂T/∂q̇ − ∂T/∂q (finite differences).

mod common;

use stride_model::Model;
use stride_multibody::*;

fn state(n: usize, seed: u64) -> Vec<f64> {
    // Deterministic pseudo-random values in (−0.5, 0.5).
    let mut s = seed;
    (0..n)
        .map(|_| {
            s = s
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            ((s >> 11) as f64 / (1u64 << 53) as f64) - 0.5
        })
        .collect()
}

fn energies(model: &Model, data: &mut Data<f64>, q: &[f64], v: &[f64]) -> (f64, f64) {
    forward_kinematics(model, data, q, v).unwrap();
    (kinetic_energy(model, data), potential_energy(model, data))
}

fn mass_matrix(model: &Model, data: &mut Data<f64>, q: &[f64]) -> Vec<Vec<f64>> {
    // T is exactly quadratic in v: M_ij = T(e_i + e_j) − T(e_i) − T(e_j), M_ii = 2 T(e_i).
    let n = q.len();
    let mut t1 = vec![0.0; n];
    let mut e = vec![0.0; n];
    for i in 0..n {
        e[i] = 1.0;
        t1[i] = energies(model, data, q, &e).0;
        e[i] = 0.0;
    }
    let mut m = vec![vec![0.0; n]; n];
    for i in 0..n {
        m[i][i] = 2.0 * t1[i];
        for j in 0..i {
            e[i] = 1.0;
            e[j] = 1.0;
            let tij = energies(model, data, q, &e).0;
            e[i] = 0.0;
            e[j] = 0.0;
            m[i][j] = tij - t1[i] - t1[j];
            m[j][i] = m[i][j];
        }
    }
    m
}

fn rel_err(a: &[f64], b: &[f64]) -> f64 {
    let num: f64 = a
        .iter()
        .zip(b)
        .map(|(x, y)| (x - y) * (x - y))
        .sum::<f64>()
        .sqrt();
    let den: f64 = b.iter().map(|y| y * y).sum::<f64>().sqrt();
    num / den.max(1e-12)
}

#[test]
fn lagrangian_consistency_subject_model() {
    let Some(model) = common::subject_model(false) else {
        return;
    };
    check_lagrangian(model);
}

#[test]
fn lagrangian_consistency_imported_osim_model() {
    let Some(root) = common::shared() else {
        return;
    };
    let path = root.join("reference/models/subject1_v2.osim");
    match stride_model::osim::load_osim(&path) {
        Ok(model) => check_lagrangian(model),
        Err(e) => eprintln!("skipping: cannot load {}: {e}", path.display()),
    }
}

fn check_lagrangian(mut model: Model) {
    model.contacts.clear();
    let n = model.coordinates.len();
    assert_eq!(n, 31);
    let mut data = Data::<f64>::new(&model).unwrap();
    let mut q = state(n, 1);
    q[4] += 0.9;
    let v: Vec<f64> = state(n, 2).iter().map(|x| 4.0 * x).collect();
    let a: Vec<f64> = state(n, 3).iter().map(|x| 20.0 * x).collect();
    let zero = vec![0.0; n];
    let mut tau_g = vec![0.0; n];
    inverse_dynamics(&model, &mut data, &q, &zero, &zero, &mut tau_g).unwrap();

    // 1. Static torques = ∂V/∂q.
    let h = 1e-6;
    let mut grad_v = vec![0.0; n];
    let mut grad_t = vec![0.0; n];
    for i in 0..n {
        let mut qp = q.clone();
        let mut qm = q.clone();
        qp[i] += h;
        qm[i] -= h;
        let (tp, vp) = energies(&model, &mut data, &qp, &v);
        let (tm, vm) = energies(&model, &mut data, &qm, &v);
        grad_v[i] = (vp - vm) / (2.0 * h);
        grad_t[i] = (tp - tm) / (2.0 * h);
    }
    let e_g = rel_err(&tau_g, &grad_v);
    eprintln!("gravity torques vs grad V: relative error {e_g:.2e}");
    assert!(e_g < 1e-6);

    // 2. Mass matrix.
    let m = mass_matrix(&model, &mut data, &q);
    let mut tau_a = vec![0.0; n];
    let mut tau_0 = vec![0.0; n];
    inverse_dynamics(&model, &mut data, &q, &v, &a, &mut tau_a).unwrap();
    inverse_dynamics(&model, &mut data, &q, &v, &zero, &mut tau_0).unwrap();
    let diff: Vec<f64> = tau_a.iter().zip(&tau_0).map(|(x, y)| x - y).collect();
    let ma: Vec<f64> = (0..n)
        .map(|i| (0..n).map(|j| m[i][j] * a[j]).sum())
        .collect();
    let e_m = rel_err(&diff, &ma);
    eprintln!("ID(q,v,a) − ID(q,v,0) vs M a: relative error {e_m:.2e}");
    assert!(e_m < 1e-6);

    // 3. Velocity terms: c = Ṁ v − ∂T/∂q with Ṁ v by central differences along v.
    let eps = 1e-5;
    let qp: Vec<f64> = q.iter().zip(&v).map(|(x, y)| x + eps * y).collect();
    let qm: Vec<f64> = q.iter().zip(&v).map(|(x, y)| x - eps * y).collect();
    let mp = mass_matrix(&model, &mut data, &qp);
    let mm = mass_matrix(&model, &mut data, &qm);
    let c_ref: Vec<f64> = (0..n)
        .map(|i| {
            (0..n)
                .map(|j| (mp[i][j] - mm[i][j]) / (2.0 * eps) * v[j])
                .sum::<f64>()
                - grad_t[i]
        })
        .collect();
    let c: Vec<f64> = tau_0.iter().zip(&tau_g).map(|(x, y)| x - y).collect();
    let e_c = rel_err(&c, &c_ref);
    eprintln!("velocity terms vs d/dt dT/dv − dT/dq: relative error {e_c:.2e}");
    assert!(e_c < 1e-6);
}
