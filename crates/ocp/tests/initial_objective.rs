//! End-to-end check of the transcription (FORMULATION Appendix B): with the nominal
//! settings and the data-informed walking guess, the objective at the initial point of the
//! reference implementation is 8,881.106.

use stride_ocp::data;
use stride_ocp::experimental::Kinematics;
use stride_ocp::guess::GuessKind;
use stride_ocp::node::NodeModel;
use stride_ocp::problem::GaitProblem;
use stride_ocp::settings::ProblemSettings;
use stride_ocp::tape_node::TapeNode;
use stride_ocp::transcription::Transcription;
use stride_solve::nlp::Nlp;

#[test]
fn objective_at_the_data_informed_guess_matches_the_reference() {
    let model = stride_model::default_model::default_model();
    let settings = ProblemSettings::default();
    let walking = data::walking_half_cycle();
    let problem = GaitProblem::new(&model, &settings, &walking).unwrap();
    assert_eq!(problem.layout.len(), 73_401);
    let kin = Kinematics::from_storage(&walking, &problem.gait, "walking").unwrap();
    let x0 = problem
        .initial_guess(GuessKind::DataInformedWalking, Some(&kin))
        .unwrap();
    let node = NodeModel::new(&problem).unwrap();
    let tape = TapeNode::for_problem(&problem, &node, &x0).unwrap();
    let tr = Transcription::new(problem, tape, x0.clone());
    assert_eq!(tr.m(), 68_400 + 28_200);
    let j = tr.objective(&x0).unwrap();
    println!("objective at the data-informed guess: {j:.6}");
    assert!((j - 8881.106).abs() < 5e-3, "objective {j} != 8881.106");
}
