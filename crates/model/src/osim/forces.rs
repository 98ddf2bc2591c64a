//! Forces: muscles with their paths, coordinate actuators (plain and with activation
//! dynamics), smooth sphere–half-space contacts, ligaments, coordinate limit forces and
//! generalised springs. Any other force element is an error: it would change the dynamics.

use super::functions::parse_function_in;
use super::skeleton::Frames;
use super::xml::{child, last_component, mul, name_of, objects, rot_xyz, tag, text};
use super::xml::{report, Ctx, El};
use super::OsimError;
use crate::contact_check::check_sphere_radius;
use crate::expression::Expression;
use crate::model::{
    ContactParameters, ContactSphere, CoordinateActuator, CoordinateForce, CoordinateForceLaw,
    Ligament, Model, MotionType, Muscle, MuscleKind, PathPoint, PathPointKind,
};
use std::collections::HashMap;

/// Read the force elements `forces` (of the `ForceSet` and the component tree) with the
/// contact geometry `geometry` they reference into `model`.
pub(crate) fn read_forces<'a, 'i>(
    ctx: &Ctx<'a, 'i>,
    forces: &[El<'a, 'i>],
    geometry: &[El<'a, 'i>],
    v4: bool,
    frames: &Frames<'a, 'i>,
    model: &mut Model,
) -> Result<(), OsimError> {
    let geometry: HashMap<&str, El> = geometry.iter().map(|e| (name_of(*e), *e)).collect();
    let mut used_geometry: Vec<&str> = Vec::new();
    for &f in forces {
        let disabled = if v4 {
            !ctx.opt_bool(f, "appliesForce", true)?
        } else {
            ctx.opt_bool(f, "isDisabled", false)?
        };
        if disabled {
            report(ctx, model, f, "force element is disabled in the file");
            continue;
        }
        if let Some(kind) = muscle_kind(tag(f)) {
            let m = muscle(ctx, f, kind, v4, frames, model)?;
            model.muscles.push(m);
            continue;
        }
        match tag(f) {
            "CoordinateActuator" | "ActivationCoordinateActuator" => {
                let a = actuator(ctx, f, model)?;
                model.actuators.push(a);
            }
            "SmoothSphereHalfSpaceForce" => {
                let c = contact(ctx, f, v4, frames, &geometry, &mut used_geometry)?;
                model.contacts.push(c);
            }
            "Ligament" => {
                let l = ligament(ctx, f, v4, frames, model)?;
                model.ligaments.push(l);
            }
            "CoordinateLimitForce"
            | "SpringGeneralizedForce"
            | "ExpressionBasedCoordinateForce" => {
                let c = coordinate_force(ctx, f, model)?;
                model.coordinate_forces.push(c);
            }
            other => {
                return Err(ctx.err(
                    f,
                    format!(
                        "force `{}` of type `{other}` is not supported: it would change the \
                         dynamics (supported: muscles, CoordinateActuator, \
                         ActivationCoordinateActuator, SmoothSphereHalfSpaceForce, Ligament, \
                         CoordinateLimitForce, SpringGeneralizedForce, \
                         ExpressionBasedCoordinateForce; disable it with \
                         appliesForce false to import the rest)",
                        name_of(f)
                    ),
                ));
            }
        }
    }
    for (name, g) in &geometry {
        if !used_geometry.contains(name) {
            report(
                ctx,
                model,
                *g,
                "contact geometry not used by any SmoothSphereHalfSpaceForce",
            );
        }
    }
    Ok(())
}

/// The muscle class of a force tag, if it is a muscle stride reads (its parameters map
/// onto the De Groote 2016 model, PREDSIM.md §3.4).
fn muscle_kind(t: &str) -> Option<MuscleKind> {
    Some(match t {
        "Thelen2003Muscle" => MuscleKind::Thelen2003,
        "Millard2012EquilibriumMuscle" => MuscleKind::Millard2012Equilibrium,
        "Millard2012AccelerationMuscle" => MuscleKind::Millard2012Acceleration,
        "DeGrooteFregly2016Muscle" => MuscleKind::DeGrooteFregly2016,
        "RigidTendonMuscle" => MuscleKind::RigidTendon,
        _ => return None,
    })
}

/// A `CoordinateActuator` or `ActivationCoordinateActuator`.
fn actuator(ctx: &Ctx, f: El, model: &Model) -> Result<CoordinateActuator, OsimError> {
    let coordinate = coordinate_ref(ctx, ctx.req(f, "coordinate")?, model)?;
    let activation_time_constant = if tag(f) == "ActivationCoordinateActuator" {
        let tau = ctx.opt_f64(f, "activation_time_constant", 0.01)?;
        if !(tau > 0.0 && tau.is_finite()) {
            let at = child(f, "activation_time_constant").unwrap_or(f);
            return Err(ctx.err(at, format!("must be positive, found {tau}")));
        }
        Some(tau)
    } else {
        None
    };
    let control_range = [
        ctx.opt_f64(f, "min_control", f64::NEG_INFINITY)?,
        ctx.opt_f64(f, "max_control", f64::INFINITY)?,
    ];
    let [lo, hi] = control_range;
    if lo.is_nan() || hi.is_nan() || lo > hi {
        let at = child(f, "max_control").unwrap_or(f);
        return Err(ctx.err(
            at,
            format!(
                "control range [{}, {}]: min_control must not exceed max_control",
                control_range[0], control_range[1]
            ),
        ));
    }
    Ok(CoordinateActuator {
        name: name_of(f).to_string(),
        coordinate,
        optimal_force: ctx.opt_f64(f, "optimal_force", 1.0)?,
        control_range,
        activation_time_constant,
    })
}

/// One `Ligament`: its parameters, force–length curve and path points.
fn ligament(
    ctx: &Ctx,
    f: El,
    v4: bool,
    frames: &Frames,
    model: &mut Model,
) -> Result<Ligament, OsimError> {
    let gp = ctx.req(f, "GeometryPath")?;
    let path = geometry_path_points(ctx, gp, "ligament", v4, frames, model)?;
    let wraps = super::wrap::read_path_wraps(ctx, gp, path.len(), model)?;
    let curve = super::xml::elements(f)
        .find(|e| name_of(*e) == "force_length_curve" || tag(*e) == "force_length_curve")
        .ok_or_else(|| ctx.missing(f, "force_length_curve"))?;
    let force_length = if tag(curve) == "force_length_curve" {
        parse_function_in(ctx, curve)?
    } else {
        super::functions::parse_function(ctx, curve)?
    };
    let positive = |t: &str| -> Result<f64, OsimError> {
        let v = ctx.req_f64(f, t)?;
        if v > 0.0 && v.is_finite() {
            Ok(v)
        } else {
            Err(ctx.err(ctx.req(f, t)?, format!("must be positive, found {v}")))
        }
    };
    Ok(Ligament {
        name: name_of(f).to_string(),
        resting_length: positive("resting_length")?,
        pcsa_force: positive("pcsa_force")?,
        force_length,
        path,
        wraps,
        path_polynomial: None,
    })
}

/// A `CoordinateLimitForce`, `SpringGeneralizedForce` or `ExpressionBasedCoordinateForce`.
fn coordinate_force(ctx: &Ctx, f: El, model: &Model) -> Result<CoordinateForce, OsimError> {
    let coordinate = coordinate_ref(ctx, ctx.req(f, "coordinate")?, model)?;
    let law = if tag(f) == "ExpressionBasedCoordinateForce" {
        let el = ctx.req(f, "expression")?;
        let e = Expression::parse(text(el), &["q", "qdot"]).map_err(|e| {
            ctx.err(
                el,
                format!("ExpressionBasedCoordinateForce `{}`: {e}", name_of(f)),
            )
        })?;
        CoordinateForceLaw::Expression(e)
    } else if tag(f) == "SpringGeneralizedForce" {
        CoordinateForceLaw::Spring {
            stiffness: ctx.opt_f64(f, "stiffness", 0.0)?,
            rest_length: ctx.opt_f64(f, "rest_length", 0.0)?,
            viscosity: ctx.opt_f64(f, "viscosity", 0.0)?,
        }
    } else {
        let transition = ctx.req_f64(f, "transition")?;
        let upper_stiffness = ctx.req_f64(f, "upper_stiffness")?;
        let lower_stiffness = ctx.req_f64(f, "lower_stiffness")?;
        if !(transition > 0.0 && upper_stiffness > 0.0 && lower_stiffness > 0.0) {
            return Err(ctx.err(
                f,
                "CoordinateLimitForce needs positive transition, upper_stiffness and \
                 lower_stiffness",
            ));
        }
        CoordinateForceLaw::CoordinateLimit {
            upper_stiffness,
            upper_limit: ctx.req_f64(f, "upper_limit")?,
            lower_stiffness,
            lower_limit: ctx.req_f64(f, "lower_limit")?,
            damping: ctx.opt_f64(f, "damping", 0.0)?,
            transition,
            // OpenSim scales by π/180 for a rotational coordinate only (not a coupled one).
            rotational: model.coordinates[coordinate].motion_type == MotionType::Rotational,
        }
    };
    Ok(CoordinateForce {
        name: name_of(f).to_string(),
        coordinate,
        law,
    })
}

/// The path points of a `GeometryPath` (at least two) of a muscle or ligament (`owner`
/// names it in errors).
fn geometry_path_points(
    ctx: &Ctx,
    gp: El,
    owner: &str,
    v4: bool,
    frames: &Frames,
    model: &mut Model,
) -> Result<Vec<PathPoint>, OsimError> {
    let pps = ctx.req(gp, "PathPointSet")?;
    let mut path = Vec::new();
    for p in objects(pps) {
        path.push(path_point(ctx, p, v4, frames, model)?);
    }
    if path.len() < 2 {
        return Err(ctx.err(
            pps,
            format!(
                "a {owner} path needs at least 2 points, found {}",
                path.len()
            ),
        ));
    }
    Ok(path)
}

/// One Hill-type muscle.
fn muscle(
    ctx: &Ctx,
    f: El,
    kind: MuscleKind,
    v4: bool,
    frames: &Frames,
    model: &mut Model,
) -> Result<Muscle, OsimError> {
    let (path, wraps, path_function) = match child(f, "FunctionBasedPath") {
        Some(fbp) => {
            let p = super::function_path::function_based_path(ctx, f, fbp, model)?;
            (Vec::new(), Vec::new(), Some(p))
        }
        None => {
            let gp = ctx.req(f, "GeometryPath")?;
            let path = geometry_path_points(ctx, gp, "muscle", v4, frames, model)?;
            let wraps = super::wrap::read_path_wraps(ctx, gp, path.len(), model)?;
            (path, wraps, None)
        }
    };
    let positive = |tagname: &str, v: f64| -> Result<f64, OsimError> {
        if v > 0.0 && v.is_finite() {
            Ok(v)
        } else {
            Err(ctx.err(ctx.req(f, tagname)?, format!("must be positive, found {v}")))
        }
    };
    let mut m = Muscle {
        name: name_of(f).to_string(),
        kind,
        max_isometric_force: positive(
            "max_isometric_force",
            ctx.req_f64(f, "max_isometric_force")?,
        )?,
        optimal_fiber_length: positive(
            "optimal_fiber_length",
            ctx.req_f64(f, "optimal_fiber_length")?,
        )?,
        tendon_slack_length: positive(
            "tendon_slack_length",
            ctx.req_f64(f, "tendon_slack_length")?,
        )?,
        pennation_angle_at_optimal: ctx.opt_f64(f, "pennation_angle_at_optimal", 0.0)?,
        max_contraction_velocity: ctx.opt_f64(f, "max_contraction_velocity", 10.0)?,
        path,
        wraps,
        path_function,
        slow_twitch_fraction: 0.5,
        specific_tension: 0.25e6,
        tendon_stiffness_scale: 1.0,
        passive_fibre_shift: 1.0,
        passive_fibre_scale: 1.0,
        active_force_width_scale: 1.0,
        ignore_passive_fiber_force: false,
        metabolic_smoothing: crate::model::default_metabolic_smoothing(),
    };
    if kind == MuscleKind::DeGrooteFregly2016 {
        de_groote_options(ctx, f, &mut m, model)?;
    }
    Ok(m)
}

/// The options of an OpenSim `DeGrooteFregly2016Muscle` beyond the common Hill parameters:
/// the active curve width and the passive fibre force take effect; a rigid tendon, no
/// activation dynamics, another tendon strain or fibre damping than stride's (compliant
/// tendon, activation dynamics, 0.049 and 0.01) are reported, as stride does not model
/// them per muscle.
fn de_groote_options(ctx: &Ctx, f: El, m: &mut Muscle, model: &mut Model) -> Result<(), OsimError> {
    let width = ctx.opt_f64(f, "active_force_width_scale", 1.0)?;
    if !(width >= 1.0 && width.is_finite()) {
        let at = child(f, "active_force_width_scale").unwrap_or(f);
        return Err(ctx.err(at, format!("must be at least 1, found {width}")));
    }
    m.active_force_width_scale = width;
    m.ignore_passive_fiber_force = ctx.opt_bool(f, "ignore_passive_fiber_force", false)?;
    if ctx.opt_bool(f, "ignore_tendon_compliance", false)? {
        report(
            ctx,
            model,
            f,
            "ignore_tendon_compliance is true: stride models every tendon as compliant \
             (De Groote 2016 tendon force state), so this muscle's tendon stretches",
        );
    }
    if ctx.opt_bool(f, "ignore_activation_dynamics", false)? {
        report(
            ctx,
            model,
            f,
            "ignore_activation_dynamics is true: stride keeps the activation dynamics",
        );
    }
    // stride's tendon curve (k_T = 35 × the muscle's tendon_stiffness_scale, set in the
    // model's settings) and its fibre damping 0.01 (FORMULATION 3).
    for (tagname, stride_value, hint) in [
        (
            "tendon_strain_at_one_norm_force",
            0.049,
            "set tendon_stiffness_scale in the model's settings",
        ),
        ("fiber_damping", 0.01, "stride's fibre damping is fixed"),
    ] {
        let v = ctx.opt_f64(f, tagname, stride_value)?;
        if v != stride_value {
            report(
                ctx,
                model,
                f,
                format!("{tagname} {v} is not used: stride uses {stride_value} ({hint})"),
            );
        }
    }
    Ok(())
}

/// Coordinate index named by element `el` (plain name or 4.x component path).
fn coordinate_ref(ctx: &Ctx, el: El, model: &Model) -> Result<usize, OsimError> {
    let t = text(el);
    let name = last_component(t);
    model
        .coordinate_index(name)
        .ok_or_else(|| ctx.err(el, format!("unknown coordinate `{t}`")))
}

/// One path point (fixed, conditional or moving).
fn path_point(
    ctx: &Ctx,
    p: El,
    v4: bool,
    frames: &Frames,
    model: &Model,
) -> Result<PathPoint, OsimError> {
    let body_tag = if v4 { "socket_parent_frame" } else { "body" };
    let bel = ctx.req(p, body_tag)?;
    let location = ctx.opt_vec3(p, "location", [0.0; 3])?;
    let (body, off) = frames.resolve(ctx, bel, text(bel), None)?;
    let rot = rot_xyz(off.orientation);
    let to_body = |l: [f64; 3]| {
        let q = mul(&rot, l);
        [
            off.location[0] + q[0],
            off.location[1] + q[1],
            off.location[2] + q[2],
        ]
    };
    let offset_is_identity = off.location == [0.0; 3] && off.orientation == [0.0; 3];
    let kind = match tag(p) {
        "PathPoint" => PathPointKind::Fixed,
        "ConditionalPathPoint" => {
            let ctag = if v4 {
                "socket_coordinate"
            } else {
                "coordinate"
            };
            let coordinate = coordinate_ref(ctx, ctx.req(p, ctag)?, model)?;
            let range = ctx.arr_of::<2>(ctx.req(p, "range")?)?;
            PathPointKind::Conditional { coordinate, range }
        }
        "MovingPathPoint" => {
            if !offset_is_identity {
                return Err(ctx.err(bel, "moving path points on offset frames are not supported"));
            }
            let mut components: [Option<(usize, crate::model::Function)>; 3] = [None, None, None];
            for (k, axis) in ["x", "y", "z"].iter().enumerate() {
                let Some(fel) = child(p, &format!("{axis}_location")) else {
                    continue;
                };
                let ctag = if v4 {
                    format!("socket_{axis}_coordinate")
                } else {
                    format!("{axis}_coordinate")
                };
                let cel = ctx.req(p, &ctag)?;
                let c = coordinate_ref(ctx, cel, model)?;
                components[k] = Some((c, parse_function_in(ctx, fel)?));
            }
            PathPointKind::Moving { components }
        }
        other => {
            return Err(ctx.err(
                p,
                format!(
                    "unsupported path point type `{other}` (supported: PathPoint, \
                     ConditionalPathPoint, MovingPathPoint)"
                ),
            ))
        }
    };
    Ok(PathPoint {
        name: name_of(p).to_string(),
        body,
        location: to_body(location),
        kind,
    })
}

/// One `SmoothSphereHalfSpaceForce` with its sphere and half-space.
fn contact<'g>(
    ctx: &Ctx,
    f: El,
    v4: bool,
    frames: &Frames,
    geometry: &HashMap<&'g str, El>,
    used: &mut Vec<&'g str>,
) -> Result<ContactSphere, OsimError> {
    let (stag, htag) = if v4 {
        ("socket_sphere", "socket_half_space")
    } else {
        ("contact_sphere", "contact_half_space")
    };
    let mut geom = |t: &str| -> Result<El, OsimError> {
        let el = ctx.req(f, t)?;
        let name = last_component(text(el));
        let (k, g) = geometry
            .get_key_value(name)
            .ok_or_else(|| ctx.err(el, format!("unknown contact geometry `{}`", text(el))))?;
        if !used.contains(k) {
            used.push(k);
        }
        Ok(*g)
    };
    let sphere = geom(stag)?;
    let half = geom(htag)?;
    if tag(sphere) != "ContactSphere" {
        return Err(ctx.err(sphere, "expected a ContactSphere"));
    }
    if tag(half) != "ContactHalfSpace" {
        return Err(ctx.err(half, "expected a ContactHalfSpace"));
    }
    let sfel = frame_el(ctx, sphere, v4)?;
    let (body, location) = frames.point_in_body(
        ctx,
        sfel,
        text(sfel),
        ctx.opt_vec3(sphere, "location", [0.0; 3])?,
    )?;
    let radius = ctx.req_f64(sphere, "radius")?;
    if let Err(e) = check_sphere_radius(radius) {
        return Err(ctx.err(ctx.req(sphere, "radius")?, format!("radius {}", e.message)));
    }
    // The half-space: OpenSim's solid occupies x > 0 of its own frame, so the outward
    // normal is −x of that frame, expressed in ground.
    let hfel = frame_el(ctx, half, v4)?;
    let (hbody, hoff) = frames.resolve(ctx, hfel, text(hfel), None)?;
    if hbody != 0 {
        return Err(ctx.err(hfel, "contact half-spaces must be fixed to the ground"));
    }
    let r_frame = rot_xyz(hoff.orientation);
    let hloc = ctx.opt_vec3(half, "location", [0.0; 3])?;
    let r_geom = rot_xyz(ctx.opt_vec3(half, "orientation", [0.0; 3])?);
    let p = mul(&r_frame, hloc);
    let plane_point = [
        hoff.location[0] + p[0],
        hoff.location[1] + p[1],
        hoff.location[2] + p[2],
    ];
    let ex = mul(&r_frame, mul(&r_geom, [1.0, 0.0, 0.0]));
    // Clean rounding noise of the trigonometric functions (e.g. cos(π/2) ≈ 6e-17).
    let clean = |v: f64| if v.abs() < 1e-12 { 0.0 } else { -v };
    let plane_normal = [clean(ex[0]), clean(ex[1]), clean(ex[2])];
    let d = ContactParameters::default();
    let parameters = ContactParameters {
        stiffness: ctx.opt_f64(f, "stiffness", d.stiffness)?,
        dissipation: ctx.opt_f64(f, "dissipation", d.dissipation)?,
        static_friction: ctx.opt_f64(f, "static_friction", d.static_friction)?,
        dynamic_friction: ctx.opt_f64(f, "dynamic_friction", d.dynamic_friction)?,
        viscous_friction: ctx.opt_f64(f, "viscous_friction", d.viscous_friction)?,
        transition_velocity: ctx.opt_f64(f, "transition_velocity", d.transition_velocity)?,
        constant_contact_force: ctx.opt_f64(
            f,
            "constant_contact_force",
            d.constant_contact_force,
        )?,
        hertz_smoothing: ctx.opt_f64(f, "hertz_smoothing", d.hertz_smoothing)?,
        hunt_crossley_smoothing: ctx.opt_f64(
            f,
            "hunt_crossley_smoothing",
            d.hunt_crossley_smoothing,
        )?,
        ..d
    };
    if let Err(e) = parameters.check() {
        let at = child(f, e.key).unwrap_or(f);
        return Err(ctx.err(at, format!("{} {}", e.key, e.message)));
    }
    Ok(ContactSphere {
        name: name_of(f).to_string(),
        body,
        location,
        radius,
        parameters,
        plane_point,
        plane_normal,
    })
}

/// The element naming the frame of a contact geometry (`socket_frame` or `body_name`).
fn frame_el<'a, 'i>(ctx: &Ctx, g: El<'a, 'i>, v4: bool) -> Result<El<'a, 'i>, OsimError> {
    let t = if v4 { "socket_frame" } else { "body_name" };
    match child(g, t).or_else(|| child(g, "body")) {
        Some(e) => Ok(e),
        None => Err(ctx.missing(g, t)),
    }
}
