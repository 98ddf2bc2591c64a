//! The physical ranges of the smooth sphere–half-space contact law, one rule for every
//! reader (`.osim` `SmoothSphereHalfSpaceForce` elements and the settings file's
//! `[contact]` table), so that a bad value is refused where it is read, by name, instead of
//! surfacing as a non-finite constraint Jacobian in the solver.

use crate::model::ContactParameters;

/// Largest contact-sphere radius accepted [m]: foot–ground contact spheres are centimetres;
/// a metre is far beyond any foot and far below values that overflow the contact law.
pub const MAX_SPHERE_RADIUS_M: f64 = 1.0;

/// Largest plane-strain modulus accepted [N m⁻²] (about a hundred times that of steel).
pub const MAX_CONTACT_STIFFNESS: f64 = 1.0e13;

/// A contact value out of its physical range: the parameter's key (as written in `.osim`
/// and settings files) and what is wrong.
#[derive(Clone, Debug, PartialEq)]
pub struct ContactValueError {
    /// Key of the parameter (`stiffness`, `radius`, …).
    pub key: &'static str,
    /// What is wrong, with the value.
    pub message: String,
}

fn out_of_range(key: &'static str, value: f64, range: &str) -> ContactValueError {
    ContactValueError {
        key,
        message: format!("{value:?} is out of range: must be {range}"),
    }
}

impl ContactParameters {
    /// Check every parameter against its physical range: stiffness in (0, 1e13] N m⁻²,
    /// dissipation ≥ 0, friction coefficients ≥ 0 with the dynamic one at most the static
    /// one (the Stribeck curve peaks at the static coefficient), transition velocity > 0,
    /// smoothing constants > 0, all finite.
    pub fn check(&self) -> Result<(), ContactValueError> {
        let finite = |key, v: f64, ok: bool, range| {
            if v.is_finite() && ok {
                Ok(())
            } else {
                Err(out_of_range(key, v, range))
            }
        };
        let s = self.stiffness;
        finite(
            "stiffness",
            s,
            s > 0.0 && s <= MAX_CONTACT_STIFFNESS,
            "in (0, 1e13] N/m²",
        )?;
        let d = self.dissipation;
        finite("dissipation", d, d >= 0.0, "finite and ≥ 0 s/m")?;
        let (mu_s, mu_d) = (self.static_friction, self.dynamic_friction);
        finite("static_friction", mu_s, mu_s >= 0.0, "finite and ≥ 0")?;
        finite("dynamic_friction", mu_d, mu_d >= 0.0, "finite and ≥ 0")?;
        if mu_d > mu_s {
            return Err(ContactValueError {
                key: "dynamic_friction",
                message: format!(
                    "{mu_d:?} is larger than static_friction {mu_s:?}: the dynamic coefficient must not exceed the static one"
                ),
            });
        }
        let v = self.viscous_friction;
        finite("viscous_friction", v, v >= 0.0, "finite and ≥ 0 s/m")?;
        let vt = self.transition_velocity;
        finite("transition_velocity", vt, vt > 0.0, "finite and > 0 m/s")?;
        let c = self.constant_contact_force;
        finite("constant_contact_force", c, c > 0.0, "finite and > 0")?;
        let bd = self.hertz_smoothing;
        finite("hertz_smoothing", bd, bd > 0.0, "finite and > 0 1/m")?;
        let bv = self.hunt_crossley_smoothing;
        finite(
            "hunt_crossley_smoothing",
            bv,
            bv > 0.0,
            "finite and > 0 s/m",
        )?;
        let e = self.friction_transition_smoothing;
        finite(
            "friction_transition_smoothing",
            e,
            (0.0..1.0).contains(&e),
            "in [0, 1)",
        )
    }
}

/// Check a contact sphere's radius [m]: finite, positive and at most
/// [`MAX_SPHERE_RADIUS_M`].
pub fn check_sphere_radius(radius: f64) -> Result<(), ContactValueError> {
    if radius.is_finite() && radius > 0.0 && radius <= MAX_SPHERE_RADIUS_M {
        Ok(())
    } else {
        Err(out_of_range("radius", radius, "in (0, 1] m"))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_default_law_passes_and_each_bad_value_is_named() {
        let d = ContactParameters::default();
        assert_eq!(d.check(), Ok(()));
        type Edit = fn(&mut ContactParameters);
        let bad: [(&str, Edit); 10] = [
            ("stiffness", |p| p.stiffness = -1e6),
            ("stiffness", |p| p.stiffness = 1e300),
            ("dissipation", |p| p.dissipation = f64::NAN),
            ("static_friction", |p| p.static_friction = -5.0),
            ("dynamic_friction", |p| p.dynamic_friction = 0.9),
            ("viscous_friction", |p| p.viscous_friction = -0.1),
            ("transition_velocity", |p| p.transition_velocity = 0.0),
            ("constant_contact_force", |p| {
                p.constant_contact_force = f64::INFINITY
            }),
            ("hertz_smoothing", |p| p.hertz_smoothing = 0.0),
            ("friction_transition_smoothing", |p| {
                p.friction_transition_smoothing = 1.0
            }),
        ];
        for (key, set) in bad {
            let mut p = d;
            set(&mut p);
            let e = p.check().unwrap_err();
            assert_eq!(e.key, key, "{}", e.message);
        }
        // zero dissipation and equal friction coefficients are physical
        let p = ContactParameters {
            dissipation: 0.0,
            ..d
        };
        assert_eq!(p.check(), Ok(()));
    }

    #[test]
    fn radii_outside_zero_to_one_metre_are_refused() {
        assert!(check_sphere_radius(0.032).is_ok());
        assert!(check_sphere_radius(1.0).is_ok());
        for r in [0.0, -0.01, 1e300, f64::NAN, f64::INFINITY] {
            assert_eq!(check_sphere_radius(r).unwrap_err().key, "radius", "{r}");
        }
    }
}
