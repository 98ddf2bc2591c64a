//! Muscles on an OpenSim `FunctionBasedPath` keep the model's own length polynomial as
//! their geometry: the fit returns it unchanged (exact by definition), next to fitted
//! muscles of the same model.

use std::path::Path;
use stride_geometry::model_fit::{fit_model, FitModelOptions};
use stride_geometry::samples::random_poses;
use stride_model::osim::load_osim;

#[test]
fn fit_keeps_the_models_own_polynomials() {
    let p = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../model/tests/data/opensim/two_link_components.osim");
    let model = load_osim(&p).unwrap();
    let poses = random_poses(&model, 200, 1);
    let report = fit_model(&model, &poses, &FitModelOptions::default()).unwrap();
    for (m, muscle) in model.muscles.iter().enumerate() {
        let own = muscle.path_function.as_ref().unwrap();
        assert_eq!(report.polynomials[m].as_ref(), Some(own), "{}", muscle.name);
        let row = &report.rows[m];
        assert!(row.meets_tolerance && row.order == own.order, "{row:?}");
        let names: Vec<&str> = own
            .coordinates
            .iter()
            .map(|&c| model.coordinates[c].name.as_str())
            .collect();
        assert_eq!(row.spanned, names);
    }
}
