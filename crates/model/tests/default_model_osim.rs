//! The shipped OpenSim file of the built-in model (`data/default_model.osim`, written into
//! every result folder of the built-in model) describes the model that is simulated: read
//! back with stride's importer it has the built-in model's gravity, bodies, coordinates,
//! muscles, contact spheres and arm actuators.

use stride_model::default_model::{default_model, DEFAULT_MODEL_OSIM};
use stride_model::osim::parse_osim;

fn close(a: f64, b: f64) -> bool {
    (a - b).abs() <= 1e-12 * (1.0 + a.abs().max(b.abs()))
}

#[test]
fn the_shipped_osim_is_the_built_in_model() {
    let built_in = default_model();
    let osim = parse_osim(DEFAULT_MODEL_OSIM, "default_model.osim").unwrap();
    assert_eq!(osim.gravity, built_in.gravity);
    let names = |m: &stride_model::Model| -> Vec<String> {
        m.bodies.iter().map(|b| b.name.clone()).collect()
    };
    assert_eq!(names(&osim), names(&built_in));
    for (a, b) in osim.bodies.iter().zip(&built_in.bodies) {
        assert!(close(a.mass, b.mass), "mass of {}", a.name);
    }
    let coords = |m: &stride_model::Model| -> Vec<String> {
        m.coordinates.iter().map(|c| c.name.clone()).collect()
    };
    assert_eq!(coords(&osim), coords(&built_in));
    assert_eq!(osim.muscles.len(), built_in.muscles.len());
    for (a, b) in osim.muscles.iter().zip(&built_in.muscles) {
        assert_eq!(a.name, b.name);
    }
    assert_eq!(osim.contacts.len(), 12);
    for b in &built_in.contacts {
        let a = osim
            .contacts
            .iter()
            .find(|c| c.name == b.name)
            .unwrap_or_else(|| panic!("contact {} missing", b.name));
        assert_eq!(osim.bodies[a.body].name, built_in.bodies[b.body].name);
        assert!(close(a.radius, b.radius), "{}", a.name);
        for k in 0..3 {
            assert!(close(a.location[k], b.location[k]), "{}", a.name);
            assert!(close(a.plane_point[k], b.plane_point[k]), "{}", a.name);
            assert!(close(a.plane_normal[k], b.plane_normal[k]), "{}", a.name);
        }
        let (p, q) = (&a.parameters, &b.parameters);
        for (x, y) in [
            (p.stiffness, q.stiffness),
            (p.dissipation, q.dissipation),
            (p.static_friction, q.static_friction),
            (p.dynamic_friction, q.dynamic_friction),
            (p.viscous_friction, q.viscous_friction),
            (p.transition_velocity, q.transition_velocity),
            (p.constant_contact_force, q.constant_contact_force),
            (p.hertz_smoothing, q.hertz_smoothing),
            (p.hunt_crossley_smoothing, q.hunt_crossley_smoothing),
        ] {
            assert!(close(x, y), "{}: {x} against {y}", a.name);
        }
    }
    assert_eq!(osim.actuators.len(), built_in.actuators.len());
    for b in &built_in.actuators {
        let a = osim.actuators.iter().find(|a| a.name == b.name).unwrap();
        assert_eq!(a.coordinate, b.coordinate, "{}", a.name);
        assert!(close(a.optimal_force, b.optimal_force));
        assert_eq!(a.control_range, b.control_range);
    }
}
