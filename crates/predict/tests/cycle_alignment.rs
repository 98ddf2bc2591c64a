//! Sample alignment of the reconstructed gait cycle: on every row (the first and the last
//! included, for every possible start of the cycle) the ground reaction forces, their
//! moments about the ground origin and the generalised forces equal what the contact model
//! and inverse dynamics give for that row's own state (q, v) and acceleration. The
//! solution vector is a guess made consistent with the constraints that link samples
//! (continuity at mesh points, symmetry or periodicity of the ends), which is what an
//! optimum satisfies; the built-in model on a 4-interval mesh, half and full cycle.

mod common;

use stride_ocp::settings::{CycleKind, ProblemSettings};
use stride_ocp::{bounds::bounds_data, guess::GuessKind, node::NodeModel, problem::GaitProblem};
use stride_predict::predict::guess_point;

/// Intervals of the test mesh.
const MESH: usize = 4;
/// Tolerance of the generalised forces [N m or N]: the built-in model's left and right
/// segments are mirror images only to the precision of its model file, so the inverse
/// dynamics of a mirrored state differs from the mirrored inverse dynamics by up to
/// 2·10⁻⁴ N m (the contact spheres mirror exactly).
const TORQUE_TOL: f64 = 1e-3;

fn close(a: &[f64], b: &[f64], tol: f64) -> bool {
    a.iter()
        .zip(b)
        .all(|(x, y)| (x - y).abs() <= tol * (1.0 + y.abs()))
}

/// Every row of the cycles starting at every sample of the periodic extension.
fn check_alignment(cycle: CycleKind) {
    let settings = ProblemSettings {
        mesh_intervals: MESH,
        cycle,
        ..Default::default()
    };
    let model = stride_model::default_model::default_model();
    let p = GaitProblem::new(&model, &settings, &bounds_data(&settings)).unwrap();
    let node = NodeModel::new(&p).unwrap();
    let x = common::consistent(&p, guess_point(&p, GuessKind::DataInformedWalking).unwrap());
    let mesh = p.mesh_solution(&node, &x).unwrap();
    let groups = node.contact_groups().unwrap();
    let right = groups.iter().position(|g| g == "right").unwrap();
    let left = groups.iter().position(|g| g == "left").unwrap();
    let total = if p.is_half_cycle() { 2 * MESH } else { MESH };
    let mut largest: f64 = 0.0;
    for start in 0..=total {
        let c = p.gait_cycle_from(&mesh, start);
        assert_eq!(c.time.len(), total);
        let samples = p.cycle_samples(&node, &c).unwrap();
        for (row, s) in samples.iter().enumerate() {
            let at = format!("start {start}, row {row}");
            let pairs = [
                (c.grf_right[row], s.group_force[right], "right force"),
                (c.grf_left[row], s.group_force[left], "left force"),
                (c.grm_right[row], s.group_moment[right], "right moment"),
                (c.grm_left[row], s.group_moment[left], "left moment"),
            ];
            for (written, model, what) in pairs {
                assert!(
                    close(&written, &model, 1e-9),
                    "{at}: {what} {written:?} vs contact model {model:?}"
                );
                largest = largest.max(model[1].abs());
            }
            assert!(
                c.torque[row]
                    .iter()
                    .zip(&s.tau)
                    .all(|(a, b)| (a - b).abs() <= TORQUE_TOL),
                "{at}: torques {:?} vs inverse dynamics {:?}",
                c.torque[row],
                s.tau
            );
        }
    }
    // the guess has its feet on the ground: the check is not one of zeros
    assert!(largest > 100.0, "largest vertical force {largest} N");
}

#[test]
fn every_row_of_a_half_cycle_reconstruction_matches_its_own_state() {
    check_alignment(CycleKind::HalfSymmetric);
}

#[test]
fn every_row_of_a_full_cycle_matches_its_own_state() {
    check_alignment(CycleKind::FullPeriodic);
}
