//! Which foot each force of an ExternalLoads file pushes on: the data columns of the right
//! and the left foot's ground reaction, from the bodies the forces are applied to and the
//! bodies the model's contact spheres sit on.

use stride_model::external_loads::{ExternalForce, ExternalLoads, ExternalLoadsError};
use stride_model::{BodyId, Model};
use stride_multibody::ContactGroups;

/// Names of the feet, in the order of a trial's GRF (right, left).
const FEET: [&str; 2] = ["right", "left"];

/// The bodies of each foot (right, left): the bodies the foot's contact spheres sit on
/// (a body named `*_r` or `*_l`), the parents of those bodies (a force on `calcn_r` when
/// the spheres sit on `calcn_r` and `toes_r`, or on `talus_r` above them) and every body
/// below them.
pub fn foot_bodies(model: &Model) -> [Vec<BodyId>; 2] {
    let groups = ContactGroups::left_right(model);
    std::array::from_fn(|side| {
        let contact = &groups.bodies[side];
        let mut bodies: Vec<BodyId> = contact.clone();
        for &b in contact {
            if let Some(j) = model.joint_of_body(b) {
                bodies.push(model.joints[j].parent);
            }
        }
        // bodies below the contact bodies (joints are not ordered: repeat to a fixed point)
        let mut grown = true;
        while grown {
            grown = false;
            for j in &model.joints {
                if bodies.contains(&j.parent) && !bodies.contains(&j.child) {
                    bodies.push(j.child);
                    grown = true;
                }
            }
        }
        bodies.retain(|&b| b != 0);
        bodies.sort_unstable();
        bodies.dedup();
        bodies
    })
}

/// The error of force `f` of `loads` about its element `element`.
fn force_error(
    loads: &ExternalLoads,
    f: &ExternalForce,
    element: &str,
    reason: String,
) -> ExternalLoadsError {
    ExternalLoadsError::Force {
        path: loads.path.display().to_string(),
        line: f.line,
        force: f.name.clone(),
        element: element.into(),
        reason,
    }
}

/// The foot (0 right, 1 left) force `f` acts on, checked: its body is a body of `model`
/// and a foot, its force and point are expressed in ground.
fn foot_of(
    loads: &ExternalLoads,
    f: &ExternalForce,
    model: &Model,
    feet: &[Vec<BodyId>; 2],
) -> Result<usize, ExternalLoadsError> {
    for (element, frame) in [
        ("force_expressed_in_body", &f.force_expressed_in_body),
        ("point_expressed_in_body", &f.point_expressed_in_body),
    ] {
        if frame != "ground" {
            let reason = format!("`{frame}`: a frame other than ground is not supported");
            return Err(force_error(loads, f, element, reason));
        }
    }
    let body = &f.applied_to_body;
    let Some(b) = model.body_index(body) else {
        let reason = format!("`{body}` is not a body of the model");
        return Err(force_error(loads, f, "applied_to_body", reason));
    };
    match feet.iter().position(|foot| foot.contains(&b)) {
        Some(side) => Ok(side),
        None => {
            let names = |side: usize| -> String {
                let n: Vec<&str> = feet[side]
                    .iter()
                    .map(|&b| model.bodies[b].name.as_str())
                    .collect();
                n.join(", ")
            };
            let reason = format!(
                "`{body}` is not a foot of the model (right foot: {}; left foot: {})",
                names(0),
                names(1)
            );
            Err(force_error(loads, f, "applied_to_body", reason))
        }
    }
}

/// The data columns (force x y z, point x y z, torque x y z) of the right and the left
/// foot's ground reaction in the data file of `loads`: one applied force per foot, on a
/// body of that foot ([`foot_bodies`]), expressed in ground.
pub fn foot_columns(
    loads: &ExternalLoads,
    model: &Model,
) -> Result<[[String; 9]; 2], ExternalLoadsError> {
    let feet = foot_bodies(model);
    let mut found: [Option<&ExternalForce>; 2] = [None, None];
    for f in loads.enabled() {
        let side = foot_of(loads, f, model, &feet)?;
        if let Some(other) = found[side] {
            let reason = format!(
                "`{}`: ExternalForce `{}` already acts on the {} foot (one force per foot)",
                f.applied_to_body, other.name, FEET[side]
            );
            return Err(force_error(loads, f, "applied_to_body", reason));
        }
        found[side] = Some(f);
    }
    let path = loads.path.display().to_string();
    let mut columns: [[String; 9]; 2] = Default::default();
    for side in 0..2 {
        let Some(f) = found[side] else {
            return Err(ExternalLoadsError::Unusable {
                path,
                reason: format!(
                    "no applied ExternalForce acts on the {} foot (one force per foot is needed)",
                    FEET[side]
                ),
            });
        };
        columns[side] = f.columns();
    }
    Ok(columns)
}

#[cfg(test)]
mod tests;
