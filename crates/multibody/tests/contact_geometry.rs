//! Contact spheres with their centre and radius as generic scalars: with the model's own
//! values the result equals the model path, and dual-number derivatives of the ground
//! reaction forces and joint torques with respect to a sphere's x, z and radius match
//! central finite differences.

use stride_ad::{Dual, Scalar};
use stride_model::default_model::default_model;
use stride_multibody::*;

/// A standing-like pose with the right heel pressed into the ground.
fn pose(model: &stride_model::Model) -> (Vec<f64>, Vec<f64>, Vec<f64>) {
    let n = model.coordinates.len();
    let mut q: Vec<f64> = (0..n).map(|i| 0.02 * ((i as f64) * 0.9).sin()).collect();
    q[model.coordinate_index("pelvis_ty").unwrap()] = 0.92;
    let v: Vec<f64> = (0..n).map(|i| 0.1 * ((i as f64) * 1.7).cos()).collect();
    let a: Vec<f64> = (0..n).map(|i| ((i as f64) * 0.3).sin()).collect();
    (q, v, a)
}

fn run<T: Scalar>(
    model: &stride_model::Model,
    geometry: Option<&[SphereGeometry<T>]>,
) -> SkeletonOutput<T> {
    let (q, v, a) = pose(model);
    let c = |x: &[f64]| x.iter().map(|&y| T::cst(y)).collect::<Vec<T>>();
    let mut data = Data::<T>::new(model).unwrap();
    let mut out = SkeletonOutput::new(model, &data);
    skeleton_dynamics_with_geometry(model, &mut data, &c(&q), &c(&v), &c(&a), geometry, &mut out)
        .unwrap();
    out
}

#[test]
fn the_models_own_geometry_gives_the_model_path() {
    let model = default_model();
    let plain = run::<f64>(&model, None);
    let g = SphereGeometry::<f64>::of_model(&model);
    let with = run(&model, Some(&g));
    assert!(
        plain.group_force[0][1] > 10.0,
        "the pose loads the right foot"
    );
    for (a, b) in plain.tau.iter().zip(&with.tau) {
        assert!((a - b).abs() <= 1e-12 * a.abs().max(1.0), "{a} {b}");
    }
}

#[test]
fn derivatives_with_respect_to_sphere_centre_and_radius_match_finite_differences() {
    let model = default_model();
    // sphere 0 (right heel): x, z of the centre and the radius
    for field in 0..3 {
        let mut gd = SphereGeometry::<Dual>::of_model(&model);
        let set = |g: &mut [SphereGeometry<Dual>], d: Dual| match field {
            0 => g[0].location[0] += d,
            1 => g[0].location[2] += d,
            _ => g[0].radius += d,
        };
        set(&mut gd, Dual::new(0.0, 1.0));
        let od = run(&model, Some(&gd));
        let h = 1e-7;
        let shifted = |s: f64| {
            let mut g = SphereGeometry::<Dual>::of_model(&model);
            set(&mut g, Dual::new(s, 0.0));
            let g: Vec<SphereGeometry<f64>> = g
                .iter()
                .map(|x| SphereGeometry {
                    location: x.location.map(|v| v.re),
                    radius: x.radius.re,
                })
                .collect();
            run(&model, Some(&g))
        };
        let (p, m) = (shifted(h), shifted(-h));
        let mut checked = 0;
        for k in 0..3 {
            let fd = (p.group_force[0][k] - m.group_force[0][k]) / (2.0 * h);
            let ad = od.group_force[0][k].eps;
            assert!(
                (fd - ad).abs() <= 1e-5 * fd.abs().max(1.0),
                "field {field} force {k}: {ad} against {fd}"
            );
            checked += (fd.abs() > 1.0) as usize;
        }
        for i in 0..model.coordinates.len() {
            let fd = (p.tau[i] - m.tau[i]) / (2.0 * h);
            let ad = od.tau[i].eps;
            assert!(
                (fd - ad).abs() <= 1e-5 * fd.abs().max(1.0),
                "field {field} tau {i}: {ad} against {fd}"
            );
        }
        assert!(checked > 0, "field {field}: the force depends on it");
    }
}
