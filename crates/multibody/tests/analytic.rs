//! Analytic checks: single and double pendulum inverse dynamics, sphere contact values.

use stride_model::*;
use stride_multibody::contact::{friction_coefficient, normal_force};
use stride_multibody::*;

fn revolute(name: &str, parent: usize, child: usize, loc: [f64; 3], coord: usize) -> Joint {
    let zero = |axis| TransformAxis {
        axis,
        coordinate: None,
        function: Function::Constant(0.0),
    };
    Joint {
        name: name.into(),
        parent,
        child,
        frame_in_parent: Offset {
            location: loc,
            orientation: [0.0; 3],
        },
        frame_in_child: Offset::default(),
        kind: JointKind::Custom {
            rotations: [
                TransformAxis {
                    axis: [0.0, 0.0, 1.0],
                    coordinate: Some(coord),
                    function: Function::Linear {
                        slope: 1.0,
                        intercept: 0.0,
                    },
                },
                zero([1.0, 0.0, 0.0]),
                zero([0.0, 1.0, 0.0]),
            ],
            translations: [
                zero([1.0, 0.0, 0.0]),
                zero([0.0, 1.0, 0.0]),
                zero([0.0, 0.0, 1.0]),
            ],
        },
    }
}

fn coord(name: &str, joint: usize) -> Coordinate {
    Coordinate {
        name: name.into(),
        joint,
        motion_type: MotionType::Rotational,
        range: [-3.0, 3.0],
        default_value: 0.0,
        locked: false,
    }
}

fn link(name: &str, mass: f64, l: f64, izz: f64) -> Body {
    Body {
        name: name.into(),
        mass,
        com: [0.0, -l, 0.0],
        inertia: [izz, izz, izz, 0.0, 0.0, 0.0],
    }
}

#[test]
fn single_pendulum() {
    let (m, l, i, g) = (2.5, 0.4, 0.03, 9.81);
    let mut model = Model::default();
    model.bodies.push(link("link", m, l, i));
    model.joints.push(revolute("pin", 0, 1, [0.1, 1.0, 0.0], 0));
    model.coordinates.push(coord("q", 0));
    let mut data = Data::<f64>::new(&model).unwrap();
    let mut tau = [0.0];
    for &(q, v, a) in &[(0.3, 1.2, -2.0), (-1.1, -0.5, 3.0), (2.0, 0.0, 0.0)] {
        inverse_dynamics(&model, &mut data, &[q], &[v], &[a], &mut tau).unwrap();
        let expect = (i + m * l * l) * a + m * g * l * f64::sin(q);
        assert!((tau[0] - expect).abs() < 1e-12, "{} vs {expect}", tau[0]);
    }
}

#[test]
fn double_pendulum_point_masses() {
    let (m1, m2, l1, l2, g) = (1.3, 0.7, 0.5, 0.35, 9.81);
    let mut model = Model::default();
    model.bodies.push(link("a", m1, l1, 0.0));
    model.bodies.push(link("b", m2, l2, 0.0));
    model.joints.push(revolute("j1", 0, 1, [0.0; 3], 0));
    model.joints.push(revolute("j2", 1, 2, [0.0, -l1, 0.0], 1));
    model.coordinates.push(coord("q1", 0));
    model.coordinates.push(coord("q2", 1));
    let mut data = Data::<f64>::new(&model).unwrap();
    let mut tau = [0.0; 2];
    let (q, v, a) = ([0.4, -0.7], [1.1, -2.3], [0.5, 1.7]);
    inverse_dynamics(&model, &mut data, &q, &v, &a, &mut tau).unwrap();
    // Absolute angles from the downward vertical.
    let (p1, p2) = (q[0], q[0] + q[1]);
    let (w1, w2) = (v[0], v[0] + v[1]);
    let (a1, a2) = (a[0], a[0] + a[1]);
    let d = p1 - p2;
    let q_p1 = (m1 + m2) * l1 * l1 * a1
        + m2 * l1 * l2 * d.cos() * a2
        + m2 * l1 * l2 * d.sin() * w2 * w2
        + (m1 + m2) * g * l1 * p1.sin();
    let q_p2 = m2 * l2 * l2 * a2 + m2 * l1 * l2 * d.cos() * a1 - m2 * l1 * l2 * d.sin() * w1 * w1
        + m2 * g * l2 * p2.sin();
    assert!(
        (tau[0] - (q_p1 + q_p2)).abs() < 1e-12,
        "{} vs {}",
        tau[0],
        q_p1 + q_p2
    );
    assert!((tau[1] - q_p2).abs() < 1e-12, "{} vs {}", tau[1], q_p2);
}

#[test]
fn sphere_normal_force_reference_values() {
    let p = ContactParameters::default();
    for &(d, f) in &[(0.01, 90.352), (0.005, 36.553), (0.02, 242.971)] {
        let fnorm: f64 = normal_force(&p, 0.032, d, 0.0);
        assert!((fnorm - f).abs() < 1.5e-3, "δ = {d}: {fnorm} vs {f}");
    }
    // Unsmoothed Hertz constant 4/3 k sqrt(R k) = 84,327.4 N m^-3/2.
    let k = 0.5 * 1e6f64.powf(2.0 / 3.0);
    assert!((4.0 / 3.0 * k * (0.032 * k).sqrt() - 84_327.4).abs() < 0.1);
}

#[test]
fn dissipation_and_no_pull() {
    let p = ContactParameters::default();
    let f0: f64 = normal_force(&p, 0.032, 0.01, 0.0);
    // Well inside the Hunt–Crossley regime the factor is (1 + 1.5 c δ̇) times the switch.
    for &dd in &[0.2, -0.1] {
        let f: f64 = normal_force(&p, 0.032, 0.01, dd);
        let sw = 0.5 + 0.5 * f64::tanh(50.0 * (dd + 2.0 / 6.0));
        assert!((f - f0 * (1.0 + 3.0 * dd) * sw).abs() < 1e-9);
    }
    // Fast separation (δ̇ < −2/(3c)): the switch removes the pulling force; what is left
    // is the smooth tail of the formula (−0.023 N at δ̇ = −0.4 m/s), below 0.1% of f0.
    for &dd in &[-0.4, -1.0, -5.0] {
        let f: f64 = normal_force(&p, 0.032, 0.01, dd);
        let sw = 0.5 + 0.5 * f64::tanh(50.0 * (dd + 2.0 / 6.0));
        assert!((f - f0 * (1.0 + 3.0 * dd) * sw).abs() < 1e-9);
        assert!(f.abs() < 1e-3 * f0, "δ̇ = {dd}: {f}");
    }
    // Out of contact (2 cm gap): only the tanh tail remains, f_H(0.02)·σ(−6) ≈ 1.5e-3 N.
    let f: f64 = normal_force(&p, 0.032, -0.02, 0.0);
    let tail = 84_327.4 * (4.1e-4f64).powf(0.75) * (0.5 + 0.5 * f64::tanh(-6.0));
    assert!((f - tail).abs() < 1e-6 && f < 2e-3, "{f} vs {tail}");
}

#[test]
fn friction_opposes_sliding() {
    let p = ContactParameters::default();
    let origin = [0.0, 0.5, 0.0];
    // Sphere centre 1 cm into the ground; body translating along +x and −z.
    let center = [0.3, 0.032 - 0.01, 0.1];
    for &(vx, vz) in &[(0.05, 0.0), (0.5, -0.2), (-1.0, 0.3)] {
        let r = sphere_force(
            &p,
            0.032,
            center,
            origin,
            [vx, 0.0, vz],
            [0.0; 3],
            [0.0; 3],
            [0.0, 1.0, 0.0],
        );
        let vs = (vx * vx + vz * vz + 1e-5f64).sqrt();
        let mu: f64 = friction_coefficient(&p, vs);
        let vrel = vs / 0.2;
        let mu_ref = 0.8 * vrel.min(1.0) + 0.5 * vs;
        assert!((mu - mu_ref).abs() < 1e-14);
        let ft = [r.force[0], r.force[2]];
        let mag = (ft[0] * ft[0] + ft[1] * ft[1]).sqrt();
        let expect = r.normal_force * mu * (vx * vx + vz * vz).sqrt() / vs;
        assert!((mag - expect).abs() < 1e-10 * expect.max(1.0));
        // Opposes the sliding direction.
        assert!(ft[0] * vx + ft[1] * vz < 0.0);
        assert!((r.force[1] - r.normal_force).abs() < 1e-12);
        // Contact point midway through the overlap.
        assert!((r.point[1] - (-0.005)).abs() < 1e-12);
    }
}

#[test]
fn friction_transition_smoothing_removes_the_kink_and_stays_close() {
    let exact = ContactParameters::default();
    let eps = 0.01;
    let smooth = ContactParameters {
        friction_transition_smoothing: eps,
        ..exact
    };
    let mu = |p: &ContactParameters, v: f64| -> f64 { friction_coefficient(p, v) };
    // Analytic bounds (μ_s = μ_d = 0.8, v_t = 0.2): the smoothed law lies below the exact one,
    // by 0.8 ε/2 at the kink and by about 0.8 ε² / (4 |v_rel − 1|) away from it.
    for &v in &[0.003, 0.05, 0.15, 0.19, 0.2, 0.21, 0.3, 1.0, 3.0] {
        let gap = mu(&exact, v) - mu(&smooth, v);
        let d = (v / 0.2 - 1.0f64).abs();
        let bound = 0.8 * 0.5 * ((d * d + eps * eps).sqrt() - d);
        assert!(
            gap >= 0.0 && (gap - bound).abs() < 1e-14,
            "v = {v}: {gap} vs {bound}"
        );
        assert!(gap <= 0.8 * eps / 2.0 + 1e-15);
    }
    // The exact law's slope jumps at v_t (0.8/0.2 + 0.5 below, 0.5 above); the smoothed
    // law's one-sided slopes agree there and its slope is the mean of the two.
    let h = 1e-7;
    let slope = |p: &ContactParameters, a: f64, b: f64| (mu(p, b) - mu(p, a)) / (b - a);
    let (below, above) = (slope(&exact, 0.2 - h, 0.2), slope(&exact, 0.2, 0.2 + h));
    assert!((below - 4.5).abs() < 1e-6 && (above - 0.5).abs() < 1e-6);
    let (below, above) = (slope(&smooth, 0.2 - h, 0.2), slope(&smooth, 0.2, 0.2 + h));
    assert!((below - above).abs() < 1e-3, "{below} vs {above}");
    assert!((below - 2.5).abs() < 1e-3, "{below}");
    // 0 (the model default) is the reference's law 0.8 min(v/0.2, 1) + 0.5 v, also at the kink.
    for &v in &[0.1, 0.2 - 1e-9, 0.2, 0.2 + 1e-9, 0.25] {
        let reference = 0.8 * (v / 0.2f64).min(1.0) + 0.5 * v;
        assert!((mu(&exact, v) - reference).abs() < 1e-15, "v = {v}");
    }
}

#[test]
fn inclined_plane_uses_its_normal() {
    let p = ContactParameters::default();
    let s = std::f64::consts::FRAC_1_SQRT_2;
    let n = [s, s, 0.0];
    // Centre at distance R − 0.01 from the plane along n.
    let c = [n[0] * 0.022, n[1] * 0.022, 0.0];
    let r = sphere_force(&p, 0.032, c, [0.0; 3], [0.0; 3], [0.0; 3], [0.0; 3], n);
    assert!((r.indentation - 0.01).abs() < 1e-14);
    assert!((r.force[0] - r.normal_force * s).abs() < 1e-9);
    assert!((r.force[1] - r.normal_force * s).abs() < 1e-9);
}

#[test]
fn bad_sizes_are_errors() {
    let mut model = Model::default();
    model.bodies.push(link("link", 1.0, 0.3, 0.01));
    model.joints.push(revolute("pin", 0, 1, [0.0; 3], 0));
    model.coordinates.push(coord("q", 0));
    let mut data = Data::<f64>::new(&model).unwrap();
    let mut tau = [0.0];
    let e = inverse_dynamics(&model, &mut data, &[0.0, 1.0], &[0.0], &[0.0], &mut tau);
    assert!(matches!(e, Err(MultibodyError::Length { .. })));
    model.joints[0].parent = 5;
    assert!(matches!(
        Data::<f64>::new(&model),
        Err(MultibodyError::Topology { .. })
    ));
}

#[test]
fn center_of_pressure_recovers_point_and_free_moment() {
    // Force F at P = (0.3, 0, −0.1) on the ground plane plus free moment 2 N m about +y.
    let f = [30.0, 600.0, -12.0];
    let p = [0.3, 0.0, -0.1];
    let m = [
        p[1] * f[2] - p[2] * f[1],
        p[2] * f[0] - p[0] * f[2],
        p[0] * f[1] - p[1] * f[0] + 0.0,
    ];
    let m = [m[0], m[1] + 2.0, m[2]];
    let (cop, free) = center_of_pressure(f, m, [0.0; 3], [0.0, 1.0, 0.0], 1.0).unwrap();
    for k in 0..3 {
        assert!((cop[k] - p[k]).abs() < 1e-12);
    }
    assert!((free - 2.0).abs() < 1e-12);
    assert!(
        center_of_pressure([0.0, 0.5, 0.0], [0.0; 3], [0.0; 3], [0.0, 1.0, 0.0], 1.0).is_none()
    );
}
