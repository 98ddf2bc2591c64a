//! The component tree of a model. OpenSim allows forces, constraints and contact geometry
//! in the classic sets (`ForceSet`, `ConstraintSet`, `ContactGeometrySet`) and also in the
//! `<components>` list of the model or of any component, at any depth (models built with
//! `addComponent`, such as Moco's), and in the `ComponentSet` of older files. This module
//! gathers them by kind, in file order, so that each kind is read by one reader.

use super::xml::{child, elements, objects, tag, El};

/// The mechanical elements of a model wherever they sit in the file.
pub(crate) struct Tree<'a, 'i> {
    /// Force elements (muscles, actuators, contacts, passive forces).
    pub forces: Vec<El<'a, 'i>>,
    /// Constraints.
    pub constraints: Vec<El<'a, 'i>>,
    /// Contact geometry (spheres, half-spaces, ...).
    pub geometry: Vec<El<'a, 'i>>,
    /// Components of other types (not read; reported by the caller).
    pub others: Vec<El<'a, 'i>>,
}

/// What a component is, from its OpenSim class name.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Kind {
    Force,
    Constraint,
    Geometry,
    Other,
}

/// The kind of an OpenSim class: forces are the classes OpenSim derives from `Force` (their
/// names end in `Force`, `Actuator` or `Muscle`, plus `Ligament`); constraints end in
/// `Constraint`; contact geometry starts with `Contact`.
fn kind(t: &str) -> Kind {
    if t.ends_with("Constraint") {
        Kind::Constraint
    } else if t.starts_with("Contact") && !t.ends_with("Force") {
        Kind::Geometry
    } else if t.ends_with("Force")
        || t.ends_with("Actuator")
        || t.ends_with("Muscle")
        || matches!(t, "Ligament" | "Bushing" | "Blankevoort1991Ligament")
    {
        Kind::Force
    } else {
        Kind::Other
    }
}

/// Gather the forces, constraints and contact geometry of the model element: the classic
/// sets first, then every `<components>` list in the file (the model's and nested ones)
/// and the `ComponentSet`.
pub(crate) fn gather<'a, 'i>(model_el: El<'a, 'i>) -> Tree<'a, 'i> {
    let set = |name: &str| child(model_el, name).map(objects).unwrap_or_default();
    let mut tree = Tree {
        forces: set("ForceSet"),
        constraints: set("ConstraintSet"),
        geometry: set("ContactGeometrySet"),
        others: Vec::new(),
    };
    let lists = model_el
        .descendants()
        .filter(|n| n.is_element() && tag(*n) == "components");
    let members = lists
        .flat_map(elements)
        .chain(set("ComponentSet"))
        .collect::<Vec<_>>();
    for c in members {
        match kind(tag(c)) {
            Kind::Force => tree.forces.push(c),
            Kind::Constraint => tree.constraints.push(c),
            Kind::Geometry => tree.geometry.push(c),
            Kind::Other => tree.others.push(c),
        }
    }
    tree
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn kinds_of_opensim_classes() {
        for t in [
            "DeGrooteFregly2016Muscle",
            "SmoothSphereHalfSpaceForce",
            "CoordinateActuator",
            "ExpressionBasedCoordinateForce",
            "Ligament",
        ] {
            assert_eq!(kind(t), Kind::Force, "{t}");
        }
        assert_eq!(kind("CoordinateCouplerConstraint"), Kind::Constraint);
        assert_eq!(kind("ContactSphere"), Kind::Geometry);
        assert_eq!(kind("ContactHalfSpace"), Kind::Geometry);
        assert_eq!(kind("Marker"), Kind::Other);
        assert_eq!(kind("PhysicalOffsetFrame"), Kind::Other);
    }
}
