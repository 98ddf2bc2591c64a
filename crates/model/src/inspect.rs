//! Human-readable tables describing a model (used by `stride model inspect`).

use crate::model::{CoordinateForceLaw, JointKind, Model, MotionType, PathPointKind};
use std::fmt::Write as _;

fn v3(v: [f64; 3]) -> String {
    format!("({:.6}, {:.6}, {:.6})", v[0], v[1], v[2])
}

fn g(x: f64) -> String {
    if x.is_infinite() {
        if x > 0.0 { "inf" } else { "-inf" }.to_string()
    } else {
        format!("{x:.6}")
    }
}

/// The De Groote–Fregly options of a muscle that differ from the standard curves.
fn de_groote_options(mu: &crate::model::Muscle) -> String {
    let mut o = String::new();
    if mu.active_force_width_scale != 1.0 {
        o += &format!("  active width x{}", mu.active_force_width_scale);
    }
    if mu.ignore_passive_fiber_force {
        o += "  no passive fibre force";
    }
    o
}

/// Render all tables of a model: coordinates, bodies and total mass [kg], joints,
/// muscles, contact spheres, actuators, passive torques, polynomial geometry and the
/// unsupported elements of the source file.
pub fn render(model: &Model) -> String {
    let mut s = String::new();
    let m = model;
    let _ = writeln!(
        s,
        "model `{}`: {} bodies (+ ground), {} joints, {} coordinates, {} muscles, {} contact spheres, {} actuators",
        m.name,
        m.bodies.len().saturating_sub(1),
        m.joints.len(),
        m.coordinates.len(),
        m.muscles.len(),
        m.contacts.len(),
        m.actuators.len()
    );
    let _ = writeln!(s, "gravity {} m/s^2", v3(m.gravity));

    let _ = writeln!(s, "\nCOORDINATES");
    let _ = writeln!(
        s,
        "{:>3}  {:<20} {:<14} {:<6} {:>24} {:>10}  locked",
        "#", "name", "joint", "type", "range", "default"
    );
    for (i, c) in m.coordinates.iter().enumerate() {
        let ty = match c.motion_type {
            MotionType::Rotational => "rot",
            MotionType::Translational => "trans",
            MotionType::Coupled => "coupl",
        };
        let joint = m
            .joints
            .get(c.joint)
            .map(|j| j.name.as_str())
            .unwrap_or("?");
        let _ = writeln!(
            s,
            "{:>3}  {:<20} {:<14} {:<6} {:>24} {:>10.6}  {}",
            i,
            c.name,
            joint,
            ty,
            format!("[{}, {}]", g(c.range[0]), g(c.range[1])),
            c.default_value,
            if c.locked { "yes" } else { "no" }
        );
    }

    let _ = writeln!(s, "\nBODIES");
    let _ = writeln!(
        s,
        "{:<12} {:>10}  {:<34} inertia [xx yy zz xy xz yz] (kg m^2)",
        "name", "mass (kg)", "centre of mass (m)"
    );
    for b in &m.bodies {
        let _ = writeln!(
            s,
            "{:<12} {:>10.6}  {:<34} [{}]",
            b.name,
            b.mass,
            v3(b.com),
            b.inertia
                .iter()
                .map(|x| format!("{x:.6e}"))
                .collect::<Vec<_>>()
                .join(" ")
        );
    }
    let _ = writeln!(s, "total mass {:.6} kg", m.total_mass());

    let _ = writeln!(s, "\nJOINTS");
    for j in &m.joints {
        let kind = match &j.kind {
            JointKind::Weld => "weld".to_string(),
            JointKind::Custom {
                rotations,
                translations,
            } => {
                let n = rotations
                    .iter()
                    .chain(translations.iter())
                    .filter(|a| a.coordinate.is_some())
                    .count();
                format!("custom ({n} coordinate axes)")
            }
        };
        let _ = writeln!(
            s,
            "{:<16} {:<26} {} -> {}   offset in parent {}",
            j.name,
            kind,
            m.bodies[j.parent].name,
            m.bodies[j.child].name,
            v3(j.frame_in_parent.location)
        );
    }

    let _ = writeln!(s, "\nMUSCLES");
    let _ = writeln!(
        s,
        "{:<14} {:>8} {:>9} {:>9} {:>9} {:>6}  points (fixed/cond/moving)  f_ST  sigma (MPa)",
        "name", "F_max(N)", "l_opt(m)", "l_ts(m)", "alpha", "v_max"
    );
    for mu in &m.muscles {
        let (mut f, mut c, mut mv) = (0, 0, 0);
        for p in &mu.path {
            match p.kind {
                PathPointKind::Fixed => f += 1,
                PathPointKind::Conditional { .. } => c += 1,
                PathPointKind::Moving { .. } => mv += 1,
            }
        }
        let path = match &mu.path_function {
            Some(p) => format!(
                "polynomial, order {} ({} terms)",
                p.order,
                p.coefficients.len()
            ),
            None => format!("{f:>2}/{c}/{mv}"),
        };
        let _ = writeln!(
            s,
            "{:<14} {:>8.1} {:>9.6} {:>9.6} {:>9.6} {:>6.1}  {:<27} {:.4} {:.5}{}",
            mu.name,
            mu.max_isometric_force,
            mu.optimal_fiber_length,
            mu.tendon_slack_length,
            mu.pennation_angle_at_optimal,
            mu.max_contraction_velocity,
            path,
            mu.slow_twitch_fraction,
            mu.specific_tension / 1e6,
            de_groote_options(mu)
        );
    }

    let _ = writeln!(s, "\nCONTACT SPHERES");
    for c in &m.contacts {
        let p = &c.parameters;
        let _ = writeln!(
            s,
            "{:<32} {:<8} at {} r={:.4} m  E={:e} c={} mu_s={} mu_d={} mu_v={} v_t={}  plane {} normal {}",
            c.name,
            m.bodies[c.body].name,
            v3(c.location),
            c.radius,
            p.stiffness,
            p.dissipation,
            p.static_friction,
            p.dynamic_friction,
            p.viscous_friction,
            p.transition_velocity,
            v3(c.plane_point),
            v3(c.plane_normal)
        );
    }
    if m.contacts.is_empty() {
        let _ = writeln!(s, "(none)");
    }

    let _ = writeln!(s, "\nACTUATORS");
    for a in &m.actuators {
        let tau = match a.activation_time_constant {
            Some(t) => format!("  activation time constant {t} s"),
            None => String::new(),
        };
        let _ = writeln!(
            s,
            "{:<20} {:<16} optimal force {:>8.2}  control [{}, {}]{tau}",
            a.name,
            m.coordinates[a.coordinate].name,
            a.optimal_force,
            g(a.control_range[0]),
            g(a.control_range[1])
        );
    }
    if m.actuators.is_empty() {
        let _ = writeln!(s, "(none)");
    }

    let _ = writeln!(
        s,
        "\nPASSIVE TORQUES  T = k1 exp(k2 (q - th2)) + k3 exp(k4 (q - th1)) - d qdot"
    );
    for p in &m.passive_torques {
        let _ = writeln!(
            s,
            "{:<18} k = [{:>7.2} {:>7.2} {:>7.2} {:>7.2}]  th1 {:>8.4}  th2 {:>8.4}  d {}",
            m.coordinates[p.coordinate].name,
            p.k[0],
            p.k[1],
            p.k[2],
            p.k[3],
            p.theta[0],
            p.theta[1],
            p.damping
        );
    }
    if m.passive_torques.is_empty() {
        let _ = writeln!(s, "(none)");
    }

    render_other_forces(&mut s, m);

    let _ = writeln!(s, "\nPOLYNOMIAL GEOMETRY");
    let fitted: Vec<(usize, &crate::model::PathPolynomial)> = m
        .path_polynomials
        .iter()
        .enumerate()
        .filter_map(|(i, p)| p.as_ref().map(|p| (i, p)))
        .collect();
    if fitted.is_empty() {
        let _ = writeln!(s, "(none: muscle geometry from the path points only)");
    } else {
        let max_l = fitted
            .iter()
            .filter_map(|(_, p)| p.rmse_length)
            .fold(0.0, f64::max);
        let max_d = fitted
            .iter()
            .filter_map(|(_, p)| p.rmse_moment_arm)
            .fold(0.0, f64::max);
        let _ = writeln!(
            s,
            "{} of {} muscles; largest fit RMS error: length {:.2} mm, moment arm {:.2} mm",
            fitted.len(),
            m.muscles.len(),
            max_l * 1e3,
            max_d * 1e3
        );
        for (i, p) in fitted {
            let coords: Vec<&str> = p
                .coordinates
                .iter()
                .map(|c| m.coordinates[*c].name.as_str())
                .collect();
            let name = m.muscles.get(i).map(|mu| mu.name.as_str()).unwrap_or("?");
            let _ = writeln!(
                s,
                "{:<14} order {}  {:>3} terms  {}",
                name,
                p.order,
                p.coefficients.len(),
                coords.join(", ")
            );
        }
    }

    if !m.unsupported.is_empty() {
        let _ = writeln!(
            s,
            "\nWARNING: {} element(s) of the source file were not imported:",
            m.unsupported.len()
        );
        for u in &m.unsupported {
            let _ = writeln!(
                s,
                "  line {:>6}  {} `{}` ({}): {}",
                u.line, u.element, u.name, u.path, u.reason
            );
        }
    }
    s
}

/// Ligaments, coordinate couplers and coordinate forces (only the sections the model has).
fn render_other_forces(s: &mut String, m: &Model) {
    if !m.ligaments.is_empty() {
        let _ = writeln!(s, "\nLIGAMENTS");
        for l in &m.ligaments {
            let _ = writeln!(
                s,
                "{:<32} resting length {:.6} m  pcsa force {:.3} N  {} path points",
                l.name,
                l.resting_length,
                l.pcsa_force,
                l.path.len()
            );
        }
    }
    if !m.couplers.is_empty() {
        let _ = writeln!(s, "\nCOUPLED COORDINATES (eliminated by substitution)");
        for c in &m.couplers {
            let _ = writeln!(
                s,
                "{:<24} {} = f({})",
                c.name, m.coordinates[c.dependent].name, m.coordinates[c.independent].name
            );
        }
    }
    if !m.coordinate_forces.is_empty() {
        let _ = writeln!(s, "\nCOORDINATE FORCES");
        for f in &m.coordinate_forces {
            let law = match &f.law {
                CoordinateForceLaw::CoordinateLimit {
                    lower_limit,
                    upper_limit,
                    ..
                } => format!("limit force, limits [{lower_limit}, {upper_limit}]"),
                CoordinateForceLaw::Spring {
                    stiffness,
                    rest_length,
                    viscosity,
                } => format!("spring k {stiffness} rest {rest_length} viscosity {viscosity}"),
                CoordinateForceLaw::Expression(e) => format!("expression {}", e.source()),
            };
            let _ = writeln!(
                s,
                "{:<24} {:<16} {law}",
                f.name, m.coordinates[f.coordinate].name
            );
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn renders_default_model_sections() {
        let m = crate::default_model::default_model();
        let s = render(&m);
        for h in [
            "COORDINATES",
            "BODIES",
            "total mass 62.000000 kg",
            "JOINTS",
            "MUSCLES",
            "CONTACT SPHERES",
            "ACTUATORS",
            "PASSIVE TORQUES",
            "POLYNOMIAL GEOMETRY",
        ] {
            assert!(s.contains(h), "missing {h}");
        }
    }
}
