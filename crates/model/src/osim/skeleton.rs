//! Bodies, joints and coordinates of OpenSim 3.x (joints inside bodies) and 4.x
//! (`JointSet` with offset frames) models.

use super::functions::{is_function_tag, parse_function, parse_function_in};
use super::xml::report;
use super::xml::{
    child, child_text, elements, last_component, mul, name_of, objects, rot_xyz, tag, text, Ctx, El,
};
use super::OsimError;
use crate::model::{
    Body, BodyId, Coordinate, CoordinateCoupler, Function, Joint, JointKind, Model, MotionType,
    Offset, TransformAxis, UnsupportedElement,
};
use std::collections::HashMap;

/// Frame lookup tables shared by joints, path points and contact geometry.
pub(crate) struct Frames<'a, 'i> {
    /// Body name → index (ground = 0).
    pub bodies: HashMap<String, BodyId>,
    /// 4.x joint name → joint element (for offset frames owned by joints).
    pub joints: HashMap<String, El<'a, 'i>>,
}

impl<'a, 'i> Frames<'a, 'i> {
    /// Body of a 3.x `<body>` reference or a 4.x frame path, with the offset of the
    /// referenced frame in that body. `at` locates errors.
    pub fn resolve(
        &self,
        ctx: &Ctx,
        at: El,
        reference: &str,
        local_frames: Option<El<'a, 'i>>,
    ) -> Result<(BodyId, Offset), OsimError> {
        let name = last_component(reference);
        if reference.is_empty() {
            return Err(ctx.err(at, "empty frame reference"));
        }
        // 1. An offset frame listed in the owning joint's `frames`.
        if let Some(frames) = local_frames {
            if let Some(f) = find_offset_frame(frames, name) {
                return self.offset_frame(ctx, f);
            }
        }
        // 2. A body (or the ground).
        if let Some(&b) = self.bodies.get(name) {
            return Ok((b, Offset::default()));
        }
        // 3. `/jointset/<joint>/<frame>`: an offset frame owned by another joint.
        let parts: Vec<&str> = reference.split('/').filter(|p| !p.is_empty()).collect();
        if let Some(i) = parts.iter().position(|p| *p == "jointset") {
            if let (Some(j), Some(f)) = (parts.get(i + 1), parts.get(i + 2)) {
                if let Some(jel) = self.joints.get(*j) {
                    if let Some(frames) = child(*jel, "frames") {
                        if let Some(fel) = find_offset_frame(frames, f) {
                            return self.offset_frame(ctx, fel);
                        }
                    }
                }
            }
        }
        Err(ctx.err(
            at,
            format!("`{reference}` names no body or frame of the model"),
        ))
    }

    /// Body and offset of a `PhysicalOffsetFrame` whose parent is a body.
    fn offset_frame(&self, ctx: &Ctx, f: El) -> Result<(BodyId, Offset), OsimError> {
        let parent_el = ctx.req(f, "socket_parent")?;
        let parent = text(parent_el);
        let pname = last_component(parent);
        let body = *self.bodies.get(pname).ok_or_else(|| {
            ctx.err(
                parent_el,
                format!(
                    "`{parent}` is not a body (offset frames on offset frames are not supported)"
                ),
            )
        })?;
        Ok((
            body,
            Offset {
                location: ctx.opt_vec3(f, "translation", [0.0; 3])?,
                orientation: ctx.opt_vec3(f, "orientation", [0.0; 3])?,
            },
        ))
    }

    /// Body and location in that body of a point given in a referenced frame.
    pub fn point_in_body(
        &self,
        ctx: &Ctx,
        at: El,
        reference: &str,
        location: [f64; 3],
    ) -> Result<(BodyId, [f64; 3]), OsimError> {
        let (b, off) = self.resolve(ctx, at, reference, None)?;
        let r = rot_xyz(off.orientation);
        let p = mul(&r, location);
        Ok((
            b,
            [
                off.location[0] + p[0],
                off.location[1] + p[1],
                off.location[2] + p[2],
            ],
        ))
    }
}

fn find_offset_frame<'a, 'i>(frames: El<'a, 'i>, name: &str) -> Option<El<'a, 'i>> {
    elements(frames).find(|f| name_of(*f) == name)
}

/// A joint as read from the file, before topological ordering.
struct RawJoint<'a, 'i> {
    el: El<'a, 'i>,
    parent: BodyId,
    child: BodyId,
    frame_in_parent: Offset,
    frame_in_child: Offset,
    coords: Vec<El<'a, 'i>>,
}

/// Read bodies, joints and coordinates into `model`; returns the frame tables.
pub(crate) fn read_skeleton<'a, 'i>(
    ctx: &Ctx<'a, 'i>,
    model_el: El<'a, 'i>,
    v4: bool,
    model: &mut Model,
) -> Result<Frames<'a, 'i>, OsimError> {
    let body_set = ctx.req(model_el, "BodySet")?;
    let mut frames = Frames {
        bodies: HashMap::new(),
        joints: HashMap::new(),
    };
    let ground_name = if v4 {
        child(model_el, "Ground")
            .map(name_of)
            .filter(|n| !n.is_empty())
            .unwrap_or("ground")
    } else {
        "ground"
    };
    model.bodies[0].name = ground_name.to_string();
    frames.bodies.insert(ground_name.to_string(), 0);
    let body_els: Vec<El> = objects(body_set)
        .into_iter()
        .filter(|b| tag(*b) == "Body")
        .collect();
    for b in &body_els {
        let name = name_of(*b);
        if !v4 && name == ground_name {
            continue;
        }
        if name.is_empty() {
            return Err(ctx.err(*b, "body without a name"));
        }
        if frames.bodies.contains_key(name) {
            return Err(ctx.err(*b, format!("duplicate body name `{name}`")));
        }
        let mass = ctx.req_f64(*b, "mass")?;
        if !(mass >= 0.0 && mass.is_finite()) {
            return Err(ctx.err(ctx.req(*b, "mass")?, format!("invalid mass {mass}")));
        }
        let com = ctx.opt_vec3(*b, "mass_center", [0.0; 3])?;
        let inertia = if v4 {
            match child(*b, "inertia") {
                Some(i) => ctx.arr_of::<6>(i)?,
                None => [0.0; 6],
            }
        } else {
            [
                ctx.opt_f64(*b, "inertia_xx", 0.0)?,
                ctx.opt_f64(*b, "inertia_yy", 0.0)?,
                ctx.opt_f64(*b, "inertia_zz", 0.0)?,
                ctx.opt_f64(*b, "inertia_xy", 0.0)?,
                ctx.opt_f64(*b, "inertia_xz", 0.0)?,
                ctx.opt_f64(*b, "inertia_yz", 0.0)?,
            ]
        };
        frames.bodies.insert(name.to_string(), model.bodies.len());
        model.bodies.push(Body {
            name: name.to_string(),
            mass,
            com,
            inertia,
        });
    }

    // Raw joints in file order.
    let mut raw = Vec::new();
    if v4 {
        let joint_set = ctx.req(model_el, "JointSet")?;
        for j in objects(joint_set) {
            frames.joints.insert(name_of(j).to_string(), j);
        }
        for j in objects(joint_set) {
            let local = child(j, "frames");
            let pel = ctx.req(j, "socket_parent_frame")?;
            let cel = ctx.req(j, "socket_child_frame")?;
            let (parent, frame_in_parent) = frames.resolve(ctx, pel, text(pel), local)?;
            let (childb, frame_in_child) = frames.resolve(ctx, cel, text(cel), local)?;
            let coords = child(j, "coordinates")
                .map(|c| elements(c).filter(|e| tag(*e) == "Coordinate").collect())
                .unwrap_or_default();
            raw.push(RawJoint {
                el: j,
                parent,
                child: childb,
                frame_in_parent,
                frame_in_child,
                coords,
            });
        }
    } else {
        for b in &body_els {
            let Some(jwrap) = child(*b, "Joint") else {
                continue;
            };
            let Some(j) = elements(jwrap).next() else {
                continue;
            };
            let pel = ctx.req(j, "parent_body")?;
            let pname = text(pel);
            let parent = *frames
                .bodies
                .get(pname)
                .ok_or_else(|| ctx.err(pel, format!("unknown parent body `{pname}`")))?;
            let childb = frames.bodies[name_of(*b)];
            if ctx.opt_bool(j, "reverse", false)? {
                return Err(ctx.err(ctx.req(j, "reverse")?, "reversed joints are not supported"));
            }
            let coords = child(j, "CoordinateSet")
                .map(|cs| {
                    objects(cs)
                        .into_iter()
                        .filter(|e| tag(*e) == "Coordinate")
                        .collect()
                })
                .unwrap_or_default();
            raw.push(RawJoint {
                el: j,
                parent,
                child: childb,
                frame_in_parent: Offset {
                    location: ctx.opt_vec3(j, "location_in_parent", [0.0; 3])?,
                    orientation: ctx.opt_vec3(j, "orientation_in_parent", [0.0; 3])?,
                },
                frame_in_child: Offset {
                    location: ctx.opt_vec3(j, "location", [0.0; 3])?,
                    orientation: ctx.opt_vec3(j, "orientation", [0.0; 3])?,
                },
                coords,
            });
        }
    }

    // Every non-ground body is the child of exactly one joint.
    let mut joint_of_child: Vec<Option<usize>> = vec![None; model.bodies.len()];
    for (k, r) in raw.iter().enumerate() {
        if r.child == 0 {
            return Err(ctx.err(r.el, "the ground cannot be the child of a joint"));
        }
        if r.child == r.parent {
            return Err(ctx.err(r.el, "joint connects a body to itself"));
        }
        if let Some(prev) = joint_of_child[r.child] {
            return Err(ctx.err(
                r.el,
                format!(
                    "body `{}` is already the child of joint `{}` (closed loops are not supported)",
                    model.bodies[r.child].name,
                    name_of(raw[prev].el)
                ),
            ));
        }
        joint_of_child[r.child] = Some(k);
    }
    for (b, j) in joint_of_child.iter().enumerate().skip(1) {
        if j.is_none() {
            let el = body_els
                .iter()
                .find(|e| name_of(**e) == model.bodies[b].name)
                .copied()
                .unwrap_or(body_set);
            return Err(ctx.err(el, "body is not the child of any joint"));
        }
    }

    // Topological order: parent before child (stable w.r.t. file order).
    let mut order = Vec::with_capacity(raw.len());
    let mut placed = vec![false; model.bodies.len()];
    placed[0] = true;
    let mut done = vec![false; raw.len()];
    while order.len() < raw.len() {
        let before = order.len();
        for (k, r) in raw.iter().enumerate() {
            if !done[k] && placed[r.parent] {
                done[k] = true;
                placed[r.child] = true;
                order.push(k);
            }
        }
        if order.len() == before {
            let k = (0..raw.len()).find(|k| !done[*k]).unwrap_or(0);
            return Err(ctx.err(raw[k].el, "joint is not connected to the ground"));
        }
    }
    let mut sorted_index = vec![0; raw.len()];
    for (s, &k) in order.iter().enumerate() {
        sorted_index[k] = s;
    }

    // Coordinates in file order.
    let mut coord_index: HashMap<String, usize> = HashMap::new();
    for (k, r) in raw.iter().enumerate() {
        for c in &r.coords {
            let name = name_of(*c);
            if name.is_empty() {
                return Err(ctx.err(*c, "coordinate without a name"));
            }
            if coord_index.contains_key(name) {
                return Err(ctx.err(*c, format!("duplicate coordinate name `{name}`")));
            }
            let range = match child(*c, "range") {
                Some(rn) if !text(rn).is_empty() => ctx.arr_of::<2>(rn)?,
                _ => [f64::NEG_INFINITY, f64::INFINITY],
            };
            if range[0].is_nan() || range[1].is_nan() || range[0] > range[1] {
                let rn = child(*c, "range").unwrap_or(*c);
                return Err(ctx.err(
                    rn,
                    format!(
                        "coordinate range [{}, {}] needs two numbers with min ≤ max",
                        range[0], range[1]
                    ),
                ));
            }
            let motion_type = if v4 {
                infer_motion_type(r.el, name, r.coords.iter().position(|e| e == c))
            } else {
                match child_text(*c, "motion_type") {
                    "" | "rotational" => MotionType::Rotational,
                    "translational" => MotionType::Translational,
                    "coupled" => MotionType::Coupled,
                    other => {
                        return Err(ctx.err(
                            ctx.req(*c, "motion_type")?,
                            format!("unknown motion type `{other}`"),
                        ))
                    }
                }
            };
            coord_index.insert(name.to_string(), model.coordinates.len());
            model.coordinates.push(Coordinate {
                name: name.to_string(),
                joint: sorted_index[k],
                motion_type,
                range,
                default_value: ctx.opt_f64(*c, "default_value", 0.0)?,
                locked: ctx.opt_bool(*c, "locked", false)?,
            });
        }
    }

    // Joints in topological order.
    for &k in &order {
        let r = &raw[k];
        let kind = joint_kind(ctx, r, &coord_index, &mut model.unsupported)?;
        model.joints.push(Joint {
            name: name_of(r.el).to_string(),
            parent: r.parent,
            child: r.child,
            frame_in_parent: r.frame_in_parent,
            frame_in_child: r.frame_in_child,
            kind,
        });
    }
    Ok(frames)
}

/// 4.x: a coordinate is translational when a translation axis of its joint uses it (or,
/// for the fixed-axis joints, when its place `index` among the joint's coordinates is a
/// translation).
fn infer_motion_type(joint: El, coord: &str, index: Option<usize>) -> MotionType {
    let k = index.unwrap_or(0);
    match tag(joint) {
        "SliderJoint" => return MotionType::Translational,
        "PlanarJoint" if k >= 1 => return MotionType::Translational,
        "FreeJoint" if k >= 3 => return MotionType::Translational,
        "CustomJoint" => {}
        _ => return MotionType::Rotational,
    }
    let Some(st) = child(joint, "SpatialTransform") else {
        return MotionType::Rotational;
    };
    // OpenSim's rule (CustomJoint): go through rotation1–3 then translation1–3; an axis
    // whose function is a `LinearFunction` of slope ±1 in the coordinate makes it
    // rotational or translational (the last such axis decides); any other function makes
    // it coupled unless a pure axis decides.
    let mut motion: Option<MotionType> = None;
    for ax in elements(st) {
        let uses = child_text(ax, "coordinates")
            .split_whitespace()
            .any(|c| c == coord);
        if !uses {
            continue;
        }
        if unit_linear_function(ax) {
            motion = Some(if name_of(ax).starts_with("translation") {
                MotionType::Translational
            } else {
                MotionType::Rotational
            });
        } else if motion.is_none() {
            motion = Some(MotionType::Coupled);
        }
    }
    // A coordinate no axis uses has no motion type in OpenSim; stride counts it as an angle.
    motion.unwrap_or(MotionType::Rotational)
}

/// Whether the function of a `TransformAxis` is a `LinearFunction` of slope +1 or −1 (the
/// axis angle or displacement is the coordinate itself, up to sign and offset).
fn unit_linear_function(axis: El) -> bool {
    let direct = elements(axis).find(|e| tag(*e) == "LinearFunction");
    let nested = child(axis, "function").and_then(|f| elements(f).next());
    let Some(f) = direct.or(nested).filter(|f| tag(*f) == "LinearFunction") else {
        return false;
    };
    let slope = child_text(f, "coefficients")
        .split_whitespace()
        .next()
        .and_then(|t| t.parse::<f64>().ok());
    matches!(slope, Some(s) if s == 1.0 || s == -1.0)
}

fn const_axis(axis: [f64; 3]) -> TransformAxis {
    TransformAxis {
        axis,
        coordinate: None,
        function: Function::Constant(0.0),
    }
}

fn unit_axes() -> [[f64; 3]; 3] {
    [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]]
}

/// A joint with fixed axes: the joint's coordinates drive `rotations` (axes in F, applied
/// as successive body-fixed rotations) and then `translations` (along F axes) in order.
fn fixed_axes(
    ctx: &Ctx,
    r: &RawJoint,
    coord_index: &HashMap<String, usize>,
    rotations: &[usize],
    translations: &[usize],
) -> Result<JointKind, OsimError> {
    let e = unit_axes();
    let n = rotations.len() + translations.len();
    if r.coords.len() != n {
        return Err(ctx.err(
            r.el,
            format!(
                "a {} needs exactly {n} coordinate(s), found {}",
                tag(r.el),
                r.coords.len()
            ),
        ));
    }
    let mut coords = r.coords.iter().map(|c| coord_index[name_of(*c)]);
    let driven = |axis: usize, c: Option<usize>| TransformAxis {
        axis: e[axis],
        coordinate: c,
        function: Function::Linear {
            slope: 1.0,
            intercept: 0.0,
        },
    };
    // Constant rotation slots take the unit axes not driven, so the three stay distinct.
    let mut rot_axes: Vec<usize> = rotations.to_vec();
    rot_axes.extend((0..3).filter(|a| !rotations.contains(a)));
    let rot: Vec<TransformAxis> = rot_axes
        .iter()
        .enumerate()
        .map(|(k, &a)| {
            if k < rotations.len() {
                driven(a, coords.next())
            } else {
                const_axis(e[a])
            }
        })
        .collect();
    let [r1, r2, r3] = <[TransformAxis; 3]>::try_from(rot).map_err(|_| ctx.err(r.el, "axes"))?;
    let mut trans = [const_axis(e[0]), const_axis(e[1]), const_axis(e[2])];
    for &a in translations {
        trans[a] = driven(a, coords.next());
    }
    let [t1, t2, t3] = trans;
    Ok(JointKind::Custom {
        rotations: [r1, r2, r3],
        translations: [t1, t2, t3],
    })
}

/// Kinematics of one joint. The fixed-axis joints follow Simbody's mobilisers: `PinJoint`
/// rotates about F's z axis; `SliderJoint` translates along F's x; `PlanarJoint`
/// (coordinates rz, tx, ty) rotates about z and translates along F's x and y;
/// `UniversalJoint` (rx, ry) rotates about x and then the new y; `GimbalJoint` and
/// `BallJoint` (rx, ry, rz) by body-fixed x–y–z angles; `FreeJoint` (rx, ry, rz, tx, ty,
/// tz) adds translations along F's axes. For `BallJoint` and `FreeJoint` stride's speeds
/// are the angle rates, where OpenSim's are the angular velocity.
fn joint_kind(
    ctx: &Ctx,
    r: &RawJoint,
    coord_index: &HashMap<String, usize>,
    unsupported: &mut Vec<UnsupportedElement>,
) -> Result<JointKind, OsimError> {
    let axes = |rot: &[usize], trans: &[usize]| fixed_axes(ctx, r, coord_index, rot, trans);
    match tag(r.el) {
        "WeldJoint" => Ok(JointKind::Weld),
        "PinJoint" => axes(&[2], &[]),
        "SliderJoint" => axes(&[], &[0]),
        "PlanarJoint" => axes(&[2], &[0, 1]),
        "UniversalJoint" => axes(&[0, 1], &[]),
        "GimbalJoint" | "BallJoint" => axes(&[0, 1, 2], &[]),
        "FreeJoint" => axes(&[0, 1, 2], &[0, 1, 2]),
        "CustomJoint" => custom_joint(ctx, r, coord_index, unsupported),
        other => Err(ctx.err(
            r.el,
            format!(
                "unsupported joint type `{other}` (supported: CustomJoint, PinJoint, \
                 SliderJoint, PlanarJoint, UniversalJoint, GimbalJoint, BallJoint, \
                 FreeJoint, WeldJoint)"
            ),
        )),
    }
}

/// A `CustomJoint`: its `SpatialTransform` of three rotation and three translation axes.
fn custom_joint(
    ctx: &Ctx,
    r: &RawJoint,
    coord_index: &HashMap<String, usize>,
    unsupported: &mut Vec<UnsupportedElement>,
) -> Result<JointKind, OsimError> {
    let e = unit_axes();
    let st = ctx.req(r.el, "SpatialTransform")?;
    let names = [
        "rotation1",
        "rotation2",
        "rotation3",
        "translation1",
        "translation2",
        "translation3",
    ];
    let mut axes: Vec<TransformAxis> = Vec::with_capacity(6);
    for (k, n) in names.iter().enumerate() {
        let ax = elements(st).find(|a| name_of(*a) == *n);
        let Some(ax) = ax else {
            axes.push(const_axis(e[k % 3]));
            continue;
        };
        axes.push(transform_axis(ctx, ax, coord_index, unsupported)?);
    }
    let Ok([r1, r2, r3, t1, t2, t3]) = <[TransformAxis; 6]>::try_from(axes) else {
        return Err(ctx.err(st, "expected six transform axes"));
    };
    Ok(JointKind::Custom {
        rotations: [r1, r2, r3],
        translations: [t1, t2, t3],
    })
}

/// One `TransformAxis`.
fn transform_axis(
    ctx: &Ctx,
    ax: El,
    coord_index: &HashMap<String, usize>,
    unsupported: &mut Vec<UnsupportedElement>,
) -> Result<TransformAxis, OsimError> {
    let axis_el = ctx.req(ax, "axis")?;
    let a = ctx.arr_of::<3>(axis_el)?;
    let norm = (a[0] * a[0] + a[1] * a[1] + a[2] * a[2]).sqrt();
    if norm.is_nan() || norm <= 1e-12 {
        return Err(ctx.err(axis_el, "transform axis has zero length"));
    }
    let axis = [a[0] / norm, a[1] / norm, a[2] / norm];
    let names: Vec<&str> = child_text(ax, "coordinates").split_whitespace().collect();
    let mut coordinate = None;
    if let Some(first) = names.first() {
        let c = *coord_index.get(*first).ok_or_else(|| {
            ctx.err(
                ctx.req(ax, "coordinates").unwrap_or(ax),
                format!("unknown coordinate `{first}`"),
            )
        })?;
        coordinate = Some(c);
        if names.len() > 1 {
            unsupported.push(UnsupportedElement {
                element: "TransformAxis".into(),
                name: name_of(ax).into(),
                path: ctx.path(ax),
                line: ctx.line(ax),
                reason: format!(
                    "function of several coordinates ({}); only `{first}` is used",
                    names.join(", ")
                ),
            });
        }
    }
    let function = match child(ax, "function") {
        Some(f) => parse_function_in(ctx, f)?,
        // Older files put the function element directly inside the axis.
        None if elements(ax).any(|e| is_function_tag(tag(e))) => {
            let f = elements(ax)
                .find(|e| is_function_tag(tag(*e)))
                .unwrap_or(ax);
            parse_function(ctx, f)?
        }
        None if coordinate.is_some() => Function::Linear {
            slope: 1.0,
            intercept: 0.0,
        },
        None => Function::Constant(0.0),
    };
    Ok(TransformAxis {
        axis,
        coordinate,
        function,
    })
}

/// Read the `ConstraintSet`: `CoordinateCouplerConstraint`s become [`CoordinateCoupler`]s;
/// disabled constraints are reported; any other enforced constraint is an error.
pub(crate) fn read_constraints(
    ctx: &Ctx,
    constraints: &[El],
    v4: bool,
    model: &mut Model,
) -> Result<(), OsimError> {
    for &c in constraints {
        let enforced = if v4 {
            ctx.opt_bool(c, "isEnforced", true)?
        } else {
            !ctx.opt_bool(c, "isDisabled", false)?
        };
        if !enforced {
            report(ctx, model, c, "constraint is disabled in the file");
            continue;
        }
        if tag(c) != "CoordinateCouplerConstraint" {
            return Err(ctx.err(
                c,
                format!(
                    "constraint `{}` of type `{}` is not supported: it would change the \
                     dynamics (supported: CoordinateCouplerConstraint)",
                    name_of(c),
                    tag(c)
                ),
            ));
        }
        let coupler = coupler(ctx, c, model)?;
        model.coordinates[coupler.dependent].motion_type = MotionType::Coupled;
        model.couplers.push(coupler);
    }
    Ok(())
}

/// One `CoordinateCouplerConstraint` (one independent coordinate).
fn coupler(ctx: &Ctx, c: El, model: &Model) -> Result<CoordinateCoupler, OsimError> {
    let coord = |t: &str| -> Result<usize, OsimError> {
        let el = ctx.req(c, t)?;
        let names: Vec<&str> = text(el).split_whitespace().collect();
        match names.as_slice() {
            [one] => model.coordinate_index(one).ok_or_else(|| {
                ctx.err(
                    el,
                    format!(
                        "coordinate coupler `{}`: unknown coordinate `{one}`",
                        name_of(c)
                    ),
                )
            }),
            _ => Err(ctx.err(
                el,
                format!(
                    "coordinate coupler `{}`: expected one coordinate name, found `{}`",
                    name_of(c),
                    text(el)
                ),
            )),
        }
    };
    let independent = coord("independent_coordinate_names")?;
    let dependent = coord("dependent_coordinate_name")?;
    if independent == dependent {
        return Err(ctx.err(c, "a coordinate cannot be coupled to itself"));
    }
    let f = parse_function_in(ctx, ctx.req(c, "coupled_coordinates_function")?)?;
    let scale = ctx.opt_f64(c, "scale_factor", 1.0)?;
    let function = if scale == 1.0 {
        f
    } else {
        Function::Multiplier {
            scale,
            function: Box::new(f),
        }
    };
    Ok(CoordinateCoupler {
        name: name_of(c).to_string(),
        dependent,
        independent,
        function,
    })
}
