//! Standing equilibrium of the subject model on its 12 contact spheres: bisection on
//! pelvis_ty until the total vertical contact force equals body weight.

mod common;

use stride_multibody::*;

#[test]
fn standing_posture_supports_body_weight() {
    let Some(model) = common::subject_model(false) else {
        return;
    };
    assert_eq!(model.contacts.len(), 12);
    let n = model.coordinates.len();
    let ty = model.coordinate_index("pelvis_ty").unwrap();
    let mut q: Vec<f64> = model
        .coordinates
        .iter()
        .map(|c| if c.locked { c.default_value } else { 0.0 })
        .collect();
    let zero = vec![0.0; n];
    let mut data = Data::<f64>::new(&model).unwrap();
    let mut out = SkeletonOutput::new(&model, &data);
    assert_eq!(
        data.groups.names,
        vec!["right".to_string(), "left".to_string()]
    );
    let weight = model.total_mass() * 9.81;
    let mut vertical = |h: f64, out: &mut SkeletonOutput<f64>| {
        q[ty] = h;
        skeleton_dynamics(&model, &mut data, &q, &zero, &zero, out).unwrap();
        out.group_force.iter().map(|f| f[1]).sum::<f64>()
    };
    // Force decreases with height: bracket and bisect.
    let (mut lo, mut hi) = (0.7, 1.2);
    assert!(vertical(lo, &mut out) > weight && vertical(hi, &mut out) < weight);
    for _ in 0..60 {
        let mid = 0.5 * (lo + hi);
        if vertical(mid, &mut out) > weight {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    let f = vertical(0.5 * (lo + hi), &mut out);
    assert!((f - weight).abs() < 0.01 * weight, "{f} vs {weight}");
    // With the contact force equal to the weight, the pelvis_ty residual of the inverse
    // dynamics (an independent path through the force recursion) must vanish.
    assert!(
        out.tau[ty].abs() < 0.01 * weight,
        "pelvis_ty residual {}",
        out.tau[ty]
    );
    // Both feet carry load and no friction is generated at rest.
    let max_pen = out
        .spheres
        .iter()
        .map(|s| s.indentation)
        .fold(f64::MIN, f64::max);
    eprintln!(
        "standing: pelvis_ty = {:.5} m, vertical force {f:.3} N (weight {weight:.3} N), right {:.2} N, left {:.2} N, max penetration {:.2} mm",
        0.5 * (lo + hi),
        out.group_force[0][1],
        out.group_force[1][1],
        1e3 * max_pen
    );
    for (s, r) in model.contacts.iter().zip(&out.spheres) {
        eprintln!(
            "  {:14} δ = {:7.3} mm, f_n = {:8.3} N",
            s.name,
            1e3 * r.indentation,
            r.normal_force
        );
        assert!(r.force[0].abs() < 1e-9 && r.force[2].abs() < 1e-9);
    }
    for g in &out.group_force {
        assert!(g[1] > 0.1 * weight);
    }
}
