//! The adapted settings as a TOML model settings file, every entry commented with where
//! it came from.

use super::drive::{Drive, ACTUATOR_TIME_CONSTANT, ACTUATOR_TORQUE, DAMPING};
use super::Adaptation;
use crate::gait::side_of;
use std::fmt::Write as _;
use stride_model::Model;

/// A number as TOML reads it back exactly (always with a point or an exponent).
fn num(x: f64) -> String {
    format!("{x:?}")
}

/// A list of numbers as a TOML array.
fn nums(xs: &[f64]) -> String {
    let items: Vec<String> = xs.iter().map(|x| num(*x)).collect();
    format!("[{}]", items.join(", "))
}

/// A list of names as a TOML array.
fn names(xs: &[String]) -> String {
    let items: Vec<String> = xs.iter().map(|x| format!("{x:?}")).collect();
    format!("[{}]", items.join(", "))
}

/// Names of the coordinates driven as `drive`.
fn with_drive(a: &Adaptation, model: &Model, drive: Drive) -> Vec<String> {
    (model.coordinates.iter().zip(&a.drives))
        .filter(|(_, d)| **d == drive)
        .map(|(c, _)| c.name.clone())
        .collect()
}

/// The whole file.
pub(super) fn render(a: &Adaptation, model: &Model, model_file: &str) -> String {
    let mut t = String::new();
    header(&mut t, a, model, model_file);
    problem(&mut t);
    contact(&mut t, a);
    actuators(&mut t, a);
    passive(&mut t, a, model);
    distances(&mut t, a);
    metabolic(&mut t, a, model);
    t
}

fn header(t: &mut String, a: &Adaptation, model: &Model, model_file: &str) {
    let mass: f64 = model.bodies.iter().map(|b| b.mass).sum();
    let _ = writeln!(
        t,
        "# Model settings of {model_file} (model `{}`), written by `stride model adapt` with\n\
         # the feet of the shipped model `{}` (docs/decisions/0008-model-adapt.md). Edit this file\n\
         # and pass it back with --model-settings.",
        model.name, a.reference
    );
    if !a.reasons.is_empty() {
        let _ = writeln!(
            t,
            "# The model as it is cannot walk: {}.",
            a.reasons.join("; ")
        );
    }
    let _ = writeln!(
        t,
        "# From the .osim file, unchanged: body mass {mass:.3} kg, the coordinates' ranges (the\n\
         # bounds where PredSim's table has no entry), the muscles, and locked coordinates."
    );
    for (drive, what) in [
        (Drive::Locked, "locked in the .osim file, they stay locked"),
        (Drive::Coupled, "given by coupler constraints"),
        (Drive::Muscles, "driven by the muscles that cross them"),
        (Drive::ModelActuator, "driven by the .osim file's actuators"),
    ] {
        let list = with_drive(a, model, drive);
        if !list.is_empty() {
            let _ = writeln!(t, "# {what}: {}.", list.join(", "));
        }
    }
    t.push('\n');
}

fn problem(t: &mut String) {
    t.push_str(
        "[problem]\n\
         # PredSim's bounds: its default table by coordinate name, else the coordinate's range in\n\
         # the .osim file (PREDSIM.md §7.4).\n\
         bounds = \"predsim\"\n\
         # PredSim's passive-torque cost: the limit torques only.\n\
         passive = { cost = \"limit\" }\n\n",
    );
}

fn contact(t: &mut String, a: &Adaptation) {
    if a.spheres.is_empty() {
        t.push_str("# Contact: the .osim file's own spheres.\n\n");
        return;
    }
    let p = &a.settings.contact.parameters;
    let _ = writeln!(
        t,
        "[contact]\n\
         # Contact law of the spheres of `{}`, unchanged.\n\
         parameters = {{ stiffness = {}, dissipation = {}, static_friction = {}, dynamic_friction = {}, viscous_friction = {}, transition_velocity = {}, constant_contact_force = {}, hertz_smoothing = {}, hunt_crossley_smoothing = {} }}\n\
         plane_point = {}\n\
         plane_normal = {}\n",
        a.reference,
        num(p.stiffness),
        num(p.dissipation),
        num(p.static_friction),
        num(p.dynamic_friction),
        num(p.viscous_friction),
        num(p.transition_velocity),
        num(p.constant_contact_force),
        num(p.hertz_smoothing),
        num(p.hunt_crossley_smoothing),
        nums(&a.settings.contact.plane_point),
        nums(&a.settings.contact.plane_normal),
    );
    for f in &a.feet {
        let len =
            |x: Option<f64>| x.map_or("unknown (no toes body)".into(), |v| format!("{v:.5} m"));
        let _ = writeln!(
            t,
            "# Foot {}: heel-to-toes length (calcn_{s} origin to toes_{s} origin, default pose) {} against\n\
             # {} of `{}`: sphere centres (in the heel frame) and radii scaled by {:.5}\n\
             # (PredSim's AdaptOpenSimModel rule).",
            f.side,
            len(f.length),
            len(f.reference_length),
            a.reference,
            f.factor,
            s = f.side,
        );
    }
    let _ = writeln!(
        t,
        "# In the default pose the sphere bottoms lie within {:.2} mm of one plane: the model stands on\n\
         # all of them with its pelvis origin {} above the ground.\n",
        a.bottom_spread * 1e3,
        a.standing_height
            .map_or("(no pelvis body)".into(), |h| format!("{h:.4} m")),
    );
    for s in &a.spheres {
        let moved = if s.reference_body != s.setting.body {
            format!(
                ", moved from `{}` (not in this model) to the same place on the foot",
                s.reference_body
            )
        } else {
            String::new()
        };
        let lift = if s.lift.abs() >= 5e-7 {
            format!(
                ", lifted {:.2} mm onto the plane of the heel spheres",
                s.lift * 1e3
            )
        } else {
            String::new()
        };
        let _ = writeln!(
            t,
            "[[contact.spheres]]\n\
             # `{}` of `{}` on `{}`, scaled by {:.5}{moved}{lift}.\n\
             name = {:?}\n\
             body = {:?}\n\
             location = {}\n\
             radius = {}\n",
            s.setting.name,
            a.reference,
            s.reference_body,
            s.factor,
            s.setting.name,
            s.setting.body,
            nums(&s.setting.location),
            num(s.setting.radius),
        );
    }
}

fn actuators(t: &mut String, a: &Adaptation) {
    for x in &a.settings.actuators {
        let _ = writeln!(
            t,
            "[[actuators]]\n\
             # No muscle crosses `{}`: an ideal torque actuator as PredSim's arms ({ACTUATOR_TORQUE} N m,\n\
             # activation time constant {ACTUATOR_TIME_CONSTANT} s).\n\
             coordinate = {:?}\n\
             optimal_force = {}\n\
             activation_time_constant = {}\n",
            x.coordinate,
            x.coordinate,
            num(x.optimal_force),
            num(x.activation_time_constant.unwrap_or(ACTUATOR_TIME_CONSTANT)),
        );
    }
}

fn passive(t: &mut String, a: &Adaptation, model: &Model) {
    if a.settings.passive_torques.table.is_empty() {
        if !model.passive_torques.is_empty() {
            t.push_str("# Passive torques: the .osim file's own.\n\n");
        }
        return;
    }
    for e in &a.settings.passive_torques.table {
        let what = if e.k == [0.0; 4] {
            format!("damping {DAMPING} N m s/rad only: PredSim has no limit torque for these names")
        } else {
            let base = side_of(&e.coordinates[0]).0;
            format!("PredSim's limit torque of `{base}` (default_coord_lim_torq_coeff.csv) and damping {DAMPING} N m s/rad")
        };
        let _ = writeln!(
            t,
            "[[passive_torques.table]]\n\
             # {what}.\n\
             coordinates = {}\n\
             k = {}\n\
             theta = {}\n\
             damping = {}\n",
            names(&e.coordinates),
            nums(&e.k),
            nums(&e.theta),
            num(e.damping),
        );
    }
}

fn distances(t: &mut String, a: &Adaptation) {
    for d in &a.settings.distances {
        let _ = writeln!(
            t,
            "[[distances]]\n\
             # Distance constraint of `{}` (anti-clipping), unchanged.\n\
             bodies = {}\n\
             min = {}\n\
             max = {}\n",
            a.reference,
            names(&d.bodies),
            num(d.min),
            num(d.max),
        );
    }
}

fn metabolic(t: &mut String, a: &Adaptation, model: &Model) {
    let m = &a.settings.metabolic;
    let _ = writeln!(
        t,
        "[metabolic]\n\
         # Muscles without an entry below: PredSim's defaults; a left muscle uses its right\n\
         # muscle's entry. {} of the {} muscles have an entry of `{}` by name.\n\
         default_slow_twitch_fraction = {}\n\
         default_specific_tension_mpa = {}\n\
         mirror_left = {}\n\
         smoothing = {}\n",
        a.metabolic_copied,
        model.muscles.len(),
        a.reference,
        num(m.default_slow_twitch_fraction),
        num(m.default_specific_tension_mpa),
        m.mirror_left,
        num(m.smoothing),
    );
    if m.muscles.is_empty() {
        return;
    }
    let _ = writeln!(
        t,
        "[metabolic.muscles]\n# Slow-twitch fractions and specific tensions of `{}`'s muscles of the same name.",
        a.reference
    );
    for (name, e) in &m.muscles {
        let bare = name
            .chars()
            .all(|c| c.is_ascii_alphanumeric() || c == '_' || c == '-');
        let key = if bare {
            name.clone()
        } else {
            format!("{name:?}")
        };
        let _ = writeln!(
            t,
            "{key} = {{ slow_twitch_fraction = {}, specific_tension_mpa = {} }}",
            num(e.slow_twitch_fraction),
            num(e.specific_tension_mpa)
        );
    }
}
