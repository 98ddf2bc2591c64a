//! The same code on dual numbers: derivatives of skeleton_dynamics (with contact) match
//! finite differences; a joint whose translations are a SimmSpline and a polynomial of
//! the coordinate (chain rule through f', f'') is consistent with its Lagrangian.

#![allow(clippy::needless_range_loop)]

mod common;

use stride_ad::Dual;
use stride_model::*;
use stride_multibody::*;

#[test]
fn dual_derivatives_of_skeleton_dynamics_match_finite_differences() {
    let Some(model) = common::subject_model(false) else {
        return;
    };
    let n = model.coordinates.len();
    let mut q: Vec<f64> = (0..n).map(|i| 0.02 * ((i as f64) * 0.9).sin()).collect();
    q[model.coordinate_index("pelvis_ty").unwrap()] = 0.955;
    let v: Vec<f64> = (0..n).map(|i| 0.1 * ((i as f64) * 1.7).cos()).collect();
    let a: Vec<f64> = (0..n).map(|i| 2.0 * ((i as f64) * 0.3).sin()).collect();
    // Direction in (q, v, a) space.
    let dq: Vec<f64> = (0..n).map(|i| ((i as f64) * 2.1).cos()).collect();
    let dv: Vec<f64> = (0..n).map(|i| ((i as f64) * 0.5).sin()).collect();
    let da: Vec<f64> = (0..n).map(|i| ((i as f64) * 1.1).cos()).collect();

    let mut data_d = Data::<Dual>::new(&model).unwrap();
    let mut out_d = SkeletonOutput::new(&model, &data_d);
    let mk = |x: &[f64], d: &[f64]| -> Vec<Dual> {
        x.iter().zip(d).map(|(x, d)| Dual::new(*x, *d)).collect()
    };
    skeleton_dynamics(
        &model,
        &mut data_d,
        &mk(&q, &dq),
        &mk(&v, &dv),
        &mk(&a, &da),
        &mut out_d,
    )
    .unwrap();

    let mut data = Data::<f64>::new(&model).unwrap();
    let mut out = SkeletonOutput::new(&model, &data);
    let h = 1e-6;
    let shift = |x: &[f64], d: &[f64], s: f64| -> Vec<f64> {
        x.iter().zip(d).map(|(x, d)| x + s * d).collect()
    };
    skeleton_dynamics(
        &model,
        &mut data,
        &shift(&q, &dq, h),
        &shift(&v, &dv, h),
        &shift(&a, &da, h),
        &mut out,
    )
    .unwrap();
    let tp = out.tau.clone();
    let fp = out.group_force.clone();
    skeleton_dynamics(
        &model,
        &mut data,
        &shift(&q, &dq, -h),
        &shift(&v, &dv, -h),
        &shift(&a, &da, -h),
        &mut out,
    )
    .unwrap();
    let mut max_rel: f64 = 0.0;
    for i in 0..n {
        let fd = (tp[i] - out.tau[i]) / (2.0 * h);
        let ad = out_d.tau[i].eps;
        max_rel = max_rel.max((fd - ad).abs() / (1.0 + ad.abs()));
    }
    for g in 0..2 {
        for c in 0..3 {
            let fd = (fp[g][c] - out.group_force[g][c]) / (2.0 * h);
            let ad = out_d.group_force[g][c].eps;
            max_rel = max_rel.max((fd - ad).abs() / (1.0 + ad.abs()));
        }
    }
    eprintln!("dual vs central differences: max relative difference {max_rel:.2e}");
    assert!(max_rel < 1e-5);
    // Contact is active in this pose.
    assert!(out_d.group_force.iter().any(|f| f[1].re > 10.0));
}

/// A single body on a joint: rotation q about z, translations x = spline(q), y = poly(q).
fn spline_joint_model() -> Model {
    let spline = Function::SimmSpline {
        x: vec![-2.0, -1.0, -0.2, 0.5, 1.0, 2.0],
        y: vec![0.01, -0.02, 0.0, 0.03, 0.01, -0.01],
    };
    let ax = |axis, f: Function| TransformAxis {
        axis,
        coordinate: Some(0),
        function: f,
    };
    let mut m = Model::default();
    m.bodies.push(Body {
        name: "shank".into(),
        mass: 3.0,
        com: [0.05, -0.2, 0.01],
        inertia: [0.04, 0.005, 0.035, 0.001, -0.002, 0.0005],
    });
    m.coordinates.push(Coordinate {
        name: "q".into(),
        joint: 0,
        motion_type: MotionType::Rotational,
        range: [-2.0, 2.0],
        default_value: 0.0,
        locked: false,
    });
    m.joints.push(Joint {
        name: "knee".into(),
        parent: 0,
        child: 1,
        frame_in_parent: Offset {
            location: [0.0, 1.0, 0.0],
            orientation: [0.1, -0.2, 0.3],
        },
        frame_in_child: Offset {
            location: [0.01, 0.02, 0.0],
            orientation: [0.0, 0.15, 0.0],
        },
        kind: JointKind::Custom {
            rotations: [
                ax(
                    [0.0, 0.0, 2.0],
                    Function::Linear {
                        slope: 1.0,
                        intercept: 0.0,
                    },
                ),
                TransformAxis {
                    axis: [1.0, 0.0, 0.0],
                    coordinate: None,
                    function: Function::Constant(0.2),
                },
                ax(
                    [0.0, 1.0, 0.0],
                    Function::Linear {
                        slope: -0.5,
                        intercept: 0.1,
                    },
                ),
            ],
            translations: [
                ax([1.0, 0.0, 0.0], spline),
                ax(
                    [0.0, 1.0, 0.0],
                    Function::Polynomial {
                        coefficients: vec![0.01, -0.02, 0.005],
                    },
                ),
                TransformAxis {
                    axis: [0.0, 0.0, 1.0],
                    coordinate: None,
                    function: Function::Constant(0.0),
                },
            ],
        },
    });
    m
}

#[test]
fn spline_driven_joint_is_lagrangian() {
    let model = spline_joint_model();
    let mut data = Data::<f64>::new(&model).unwrap();
    let energy = |data: &mut Data<f64>, q: f64, v: f64| {
        forward_kinematics(&model, data, &[q], &[v]).unwrap();
        (kinetic_energy(&model, data), potential_energy(&model, data))
    };
    for &(q, v, a) in &[(0.3, 1.5, -2.0), (-0.7, -0.8, 4.0), (1.4, 2.0, 0.5)] {
        let mut tau = [0.0];
        inverse_dynamics(&model, &mut data, &[q], &[v], &[a], &mut tau).unwrap();
        // Lagrange: τ = M a + ½ M'(q) v² + V'(q), with M = 2 T(q, 1).
        let h = 1e-5;
        let m_of = |data: &mut Data<f64>, q: f64| 2.0 * energy(data, q, 1.0).0;
        let m = m_of(&mut data, q);
        let dm = (m_of(&mut data, q + h) - m_of(&mut data, q - h)) / (2.0 * h);
        let dv = (energy(&mut data, q + h, 0.0).1 - energy(&mut data, q - h, 0.0).1) / (2.0 * h);
        let expect = m * a + 0.5 * dm * v * v + dv;
        assert!(
            (tau[0] - expect).abs() < 1e-7 * (1.0 + expect.abs()),
            "{} vs {expect}",
            tau[0]
        );
    }
}

/// Inputs `[q, v, a]` of the subject model at a pose parameterised by `s`.
fn pose(model: &Model, s: f64, h: f64) -> Vec<f64> {
    let n = model.coordinates.len();
    let mut x = vec![0.0; 3 * n];
    for i in 0..n {
        x[i] = 0.03 * ((i as f64) * 0.9 + s).sin();
        x[n + i] = 0.2 * ((i as f64) * 1.7 + s).cos();
        x[2 * n + i] = 2.0 * ((i as f64) * 0.3 - s).sin();
    }
    x[model.coordinate_index("pelvis_ty").unwrap()] = h;
    x
}

#[test]
fn tape_recorded_once_is_valid_at_other_contact_states() {
    use stride_ad::{Scalar, Tape, Var};
    let Some(model) = common::subject_model(false) else {
        return;
    };
    let n = model.coordinates.len();
    let n_out = n + 6;
    let run = |x: &[Var]| -> Vec<Var> {
        let mut data = Data::<Var>::new(&model).unwrap();
        let mut out = SkeletonOutput::new(&model, &data);
        skeleton_dynamics(
            &model,
            &mut data,
            &x[..n],
            &x[n..2 * n],
            &x[2 * n..],
            &mut out,
        )
        .unwrap();
        let mut y = out.tau.clone();
        for g in &out.group_force {
            y.extend_from_slice(g);
        }
        y
    };
    // Record with the feet in the air; evaluate standing and sliding.
    let tape = Tape::record(&pose(&model, 0.0, 1.2), run).unwrap();
    let mut ws = tape.workspace();
    let mut y = vec![0.0; n_out];
    let mut data = Data::<f64>::new(&model).unwrap();
    let mut out = SkeletonOutput::new(&model, &data);
    for (s, h) in [(0.3, 0.955), (1.1, 0.95), (2.0, 0.97)] {
        let x = pose(&model, s, h);
        tape.eval(&x, &mut ws, &mut y).unwrap();
        skeleton_dynamics(
            &model,
            &mut data,
            &x[..n],
            &x[n..2 * n],
            &x[2 * n..],
            &mut out,
        )
        .unwrap();
        let fy = out.group_force[0][1] + out.group_force[1][1];
        assert!(fy > 10.0, "pose {s}: contact inactive ({fy} N)");
        for i in 0..n {
            assert!(
                (y[i] - out.tau[i]).abs() <= 1e-9 * (1.0 + out.tau[i].abs()),
                "tau[{i}]"
            );
        }
        for g in 0..2 {
            for c in 0..3 {
                let r = out.group_force[g][c];
                assert!((y[n + 3 * g + c] - r).abs() <= 1e-9 * (1.0 + r.abs()));
            }
        }
    }
    let _ = Var::cst(0.0);
}

#[test]
fn tape_follows_spline_segments() {
    use stride_ad::{Tape, Var};
    let model = spline_joint_model();
    let run = |x: &[Var]| -> Vec<Var> {
        let mut data = Data::<Var>::new(&model).unwrap();
        let mut tau = vec![x[0]];
        inverse_dynamics(&model, &mut data, &x[..1], &x[1..2], &x[2..], &mut tau).unwrap();
        tau
    };
    let tape = Tape::record(&[-1.5, 0.7, 1.0], run).unwrap();
    let mut ws = tape.workspace();
    let mut data = Data::<f64>::new(&model).unwrap();
    for &(q, v, a) in &[
        (-0.5, 1.0, 2.0),
        (0.7, -2.0, 0.3),
        (1.6, 0.4, -1.0),
        (2.5, 1.0, 1.0),
    ] {
        let mut y = [0.0];
        tape.eval(&[q, v, a], &mut ws, &mut y).unwrap();
        let mut tau = [0.0];
        inverse_dynamics(&model, &mut data, &[q], &[v], &[a], &mut tau).unwrap();
        assert!(
            (y[0] - tau[0]).abs() <= 1e-12 * (1.0 + tau[0].abs()),
            "q = {q}: {} vs {}",
            y[0],
            tau[0]
        );
    }
}
