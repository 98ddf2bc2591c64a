//! Contact-model calibration (FORMULATION 12.6): the horizontal centre (x, z in the body
//! frame) and radius of each right-foot contact sphere as static parameters, applied to the
//! left foot mirrored (z → −z), bounded to the generic value ± 0.025 m (centres) and
//! ± 50 % (radii).

use super::TrackError;
use crate::contact_geometry::ContactGeometry;
use crate::statics::{ParameterTarget, StaticParameter, StaticParameters};

use stride_model::Model;

/// Half-width of the bounds of a sphere centre coordinate around its generic value [m].
pub const CENTER_RANGE: f64 = 0.025;
/// Half-width of the bounds of a radius, as a fraction of its generic value.
pub const RADIUS_RANGE: f64 = 0.5;

/// Mirror pairs (right sphere, left sphere) of `model`: every sphere named `<base>_r` with
/// a sphere `<base>_l` whose centre is the right one's with z negated.
fn mirror_pairs(model: &Model) -> Result<Vec<(usize, usize)>, TrackError> {
    let mut pairs = Vec::new();
    for (i, s) in model.contacts.iter().enumerate() {
        let Some(base) = s.name.strip_suffix("_r") else {
            continue;
        };
        let left = format!("{base}_l");
        let Some(j) = model.contacts.iter().position(|c| c.name == left) else {
            return Err(TrackError::Settings(format!(
                "calibrate_contact: contact sphere `{}` has no left counterpart `{left}`",
                s.name
            )));
        };
        let (a, b) = (s.location, model.contacts[j].location);
        let mirrored = (a[0] - b[0]).abs() < 1e-9
            && (a[1] - b[1]).abs() < 1e-9
            && (a[2] + b[2]).abs() < 1e-9
            && (s.radius - model.contacts[j].radius).abs() < 1e-12;
        if !mirrored {
            return Err(TrackError::Settings(format!(
                "calibrate_contact: contact spheres `{}` and `{left}` are not mirror images (x, y, −z, same radius)",
                s.name
            )));
        }
        pairs.push((i, j));
    }
    if pairs.is_empty() {
        return Err(TrackError::Settings(
            "calibrate_contact: the model has no contact spheres named `<name>_r` / `<name>_l`"
                .into(),
        ));
    }
    Ok(pairs)
}

/// The static parameters of the calibration for `model`: (x, z) of every right-foot
/// sphere in model order, then their radii; the generic values are the initial guess.
pub fn contact_parameters(model: &Model) -> Result<StaticParameters, TrackError> {
    let pairs = mirror_pairs(model)?;
    let mut list = Vec::new();
    for &(r, l) in &pairs {
        let s = &model.contacts[r];
        for (axis, label) in [(0, "x"), (2, "z")] {
            let v = s.location[axis];
            list.push(StaticParameter {
                name: format!("{}_{label}", s.name),
                lower: v - CENTER_RANGE,
                upper: v + CENTER_RANGE,
                initial: v,
                targets: vec![
                    ParameterTarget::SphereCenter {
                        sphere: r,
                        axis,
                        sign: 1.0,
                    },
                    ParameterTarget::SphereCenter {
                        sphere: l,
                        axis,
                        sign: if axis == 2 { -1.0 } else { 1.0 },
                    },
                ],
            });
        }
    }
    for &(r, l) in &pairs {
        let s = &model.contacts[r];
        list.push(StaticParameter {
            name: format!("{}_radius", s.name),
            lower: s.radius * (1.0 - RADIUS_RANGE),
            upper: s.radius * (1.0 + RADIUS_RANGE),
            initial: s.radius,
            targets: vec![
                ParameterTarget::SphereRadius { sphere: r },
                ParameterTarget::SphereRadius { sphere: l },
            ],
        });
    }
    let p = StaticParameters { list };
    p.check(model)
        .map_err(|e| TrackError::Settings(e.to_string()))?;
    Ok(p)
}

/// The contact geometry of `model` with the static parameters whose NLP variables are
/// `scaled` (in the order of `statics`).
pub fn calibrated_geometry(
    model: &Model,
    statics: &StaticParameters,
    scaled: &[f64],
) -> ContactGeometry {
    let mut g = ContactGeometry::of_model(model);
    for (e, s) in g
        .sphere
        .iter_mut()
        .zip(statics.sphere_geometry::<f64>(model, scaled))
    {
        e.location = s.location;
        e.radius = s.radius;
    }
    g
}

/// CSV of the calibrated parameters: name, value, lower and upper bound, generic value
/// [m], and the bound the value ends at (`lower`, `upper`, or empty; see
/// [`crate::statics::AT_BOUND_FRACTION`]), for the NLP variables `scaled`.
pub fn parameters_csv(statics: &StaticParameters, scaled: &[f64]) -> String {
    let mut s = String::from("parameter,value_m,lower_m,upper_m,generic_m,at_bound\n");
    for p in statics.reports(scaled) {
        s += &format!(
            "{},{},{},{},{},{}\n",
            p.name,
            p.value,
            p.lower,
            p.upper,
            p.initial,
            p.at_bound.unwrap_or("")
        );
    }
    s
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_built_in_model_has_the_papers_18_parameters_with_its_bounds() {
        let model = stride_model::default_model::default_model();
        let p = contact_parameters(&model).unwrap();
        assert_eq!(p.len(), 18);
        // FORMULATION 1.5 / 12.6: s1 x = 0.00190115788407966 ± 0.025; radii 0.016–0.048.
        assert_eq!(p.list[0].name, "sphere_1_r_x");
        assert!((p.list[0].lower - (0.00190115788407966 - 0.025)).abs() < 1e-15);
        assert_eq!(p.list[1].name, "sphere_1_r_z");
        assert!((p.list[1].upper - (-0.00382630379623308 + 0.025)).abs() < 1e-15);
        for r in &p.list[12..] {
            assert!((r.lower - 0.016).abs() < 1e-15 && (r.upper - 0.048).abs() < 1e-15);
        }
        // the left foot gets the mirrored value of every parameter
        let scaled: Vec<f64> = p.list.iter().map(|q| q.scale(q.initial + 0.001)).collect();
        let g = calibrated_geometry(&model, &p, &scaled);
        for i in 0..6 {
            let (r, l) = (&g.sphere[i], &g.sphere[i + 6]);
            assert_eq!(r.location[0], l.location[0]);
            assert_eq!(r.location[2], -l.location[2]);
            let want = model.contacts[i].location[0] + 0.001;
            assert!((r.location[0] - want).abs() < 1e-15);
            assert_eq!(r.location[1], model.contacts[i].location[1]);
            assert_eq!(r.radius, l.radius);
        }
    }
}
