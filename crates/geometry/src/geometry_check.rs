//! Whether the muscle polynomials of a geometry file belong to a model: a polynomial
//! must span only coordinates that move its muscle's path, and give the path's length at
//! the model's default pose. A file fitted to another model, or one whose muscle names
//! were swapped, fails with the muscle named instead of solving the wrong problem.

use crate::error::GeometryError;
use crate::path::PathGeometry;
use crate::poly::polynomial_length;
use stride_model::Model;

/// Smallest length difference [m] between a polynomial and its path at the default pose
/// that is refused; larger for a polynomial whose fit was worse (5 × its RMS error).
pub const MIN_LENGTH_MISMATCH_M: f64 = 0.02;

/// Check the muscle polynomials of `model` (already set from `source`, a geometry file)
/// against its muscle paths; their lengths at the default pose only when `lengths_too`
/// (a fit over the coordinate ranges, which holds there).
pub fn check_polynomials(
    model: &Model,
    source: &str,
    lengths_too: bool,
) -> Result<(), GeometryError> {
    if model.muscles.is_empty() {
        return Ok(());
    }
    let mut g = PathGeometry::new(model)?;
    let q: Vec<f64> = model.coordinates.iter().map(|c| c.default_value).collect();
    let mut lengths = vec![0.0; model.muscles.len()];
    g.lengths(&q, &mut lengths);
    let err = |what: String| GeometryError::File {
        path: source.to_string(),
        what,
    };
    for (m, p) in model.path_polynomials.iter().enumerate() {
        let Some(p) = p else { continue };
        let name = &model.muscles[m].name;
        if let Some(&c) = p.coordinates.iter().find(|&&c| !g.depends(m, c)) {
            return Err(err(format!(
                "muscle {name}: its polynomial spans coordinate {}, which does not move the muscle's path in model {} (fitted to another model, or muscle names swapped?)",
                model.coordinates[c].name, model.name
            )));
        }
        if !lengths_too {
            continue;
        }
        let l = polynomial_length(p, &q);
        let tol = MIN_LENGTH_MISMATCH_M.max(5.0 * p.rmse_length.unwrap_or(0.0));
        let diff = (l - lengths[m]).abs();
        if diff.is_nan() || diff > tol {
            return Err(err(format!(
                "muscle {name}: polynomial length {l:.4} m at the default pose differs from the path length {:.4} m of model {} by more than {tol} m (fitted to another model, or muscle names swapped?)",
                lengths[m], model.name
            )));
        }
    }
    Ok(())
}
