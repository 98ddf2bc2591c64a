//! Wrap objects (`WrapObjectSet` of each body) and the path wraps of muscles
//! (`PathWrapSet` of a `GeometryPath`).

use super::skeleton::Frames;
use super::xml::{child, name_of, objects, tag, text, Ctx, El};
use super::OsimError;
use crate::model::{Model, PathWrap, WrapObject, WrapQuadrant, WrapShape};

/// Read the wrap objects of every body (and of the 4.x ground) into `model.wrap_objects`.
pub(crate) fn read_wrap_objects(
    ctx: &Ctx,
    model_el: El,
    frames: &Frames,
    model: &mut Model,
) -> Result<(), OsimError> {
    let mut owners: Vec<El> = Vec::new();
    if let Some(g) = child(model_el, "Ground") {
        owners.push(g);
    }
    if let Some(bs) = child(model_el, "BodySet") {
        owners.extend(objects(bs));
    }
    for owner in owners {
        let Some(set) = child(owner, "WrapObjectSet") else {
            continue;
        };
        let body = *frames.bodies.get(name_of(owner)).ok_or_else(|| {
            ctx.err(
                owner,
                format!("`{}` owns wrap objects but is not a body", name_of(owner)),
            )
        })?;
        for w in objects(set) {
            let object = wrap_object(ctx, w, body)?;
            if model.wrap_objects.iter().any(|o| o.name == object.name) {
                return Err(ctx.err(w, format!("duplicate wrap object `{}`", object.name)));
            }
            model.wrap_objects.push(object);
        }
    }
    Ok(())
}

/// One wrap object: placement, quadrant and shape.
fn wrap_object(ctx: &Ctx, w: El, body: usize) -> Result<WrapObject, OsimError> {
    let positive = |t: &str| -> Result<f64, OsimError> {
        let v = ctx.req_f64(w, t)?;
        if v > 0.0 && v.is_finite() {
            Ok(v)
        } else {
            Err(ctx.err(ctx.req(w, t)?, format!("must be positive, found {v}")))
        }
    };
    let shape = match tag(w) {
        "WrapCylinder" => WrapShape::Cylinder {
            radius: positive("radius")?,
            length: positive("length")?,
        },
        "WrapSphere" => WrapShape::Sphere {
            radius: positive("radius")?,
        },
        "WrapEllipsoid" => {
            let el = ctx.req(w, "dimensions")?;
            let radii = ctx.arr_of::<3>(el)?;
            if radii.iter().any(|r| !(*r > 0.0 && r.is_finite())) {
                return Err(ctx.err(el, format!("semi-axes must be positive, found {radii:?}")));
            }
            WrapShape::Ellipsoid { radii }
        }
        "WrapTorus" => {
            let inner_radius = positive("inner_radius")?;
            let outer_radius = positive("outer_radius")?;
            if outer_radius <= inner_radius {
                return Err(ctx.err(
                    ctx.req(w, "outer_radius")?,
                    format!(
                        "must exceed inner_radius {inner_radius} (the tube's radius), found \
                         {outer_radius}"
                    ),
                ));
            }
            WrapShape::Torus {
                inner_radius,
                outer_radius,
            }
        }
        other => {
            return Err(ctx.err(
                w,
                format!(
                    "wrap object `{}` has the unsupported class `{other}` (supported: \
                     WrapCylinder, WrapSphere, WrapEllipsoid, WrapTorus)",
                    name_of(w)
                ),
            ))
        }
    };
    Ok(WrapObject {
        name: name_of(w).to_string(),
        body,
        rotation: ctx.opt_vec3(w, "xyz_body_rotation", [0.0; 3])?,
        translation: ctx.opt_vec3(w, "translation", [0.0; 3])?,
        quadrant: quadrant(ctx, w)?,
        active: ctx.opt_bool(w, "active", true)?,
        shape,
    })
}

/// The `quadrant` property: `±x`, `±y`, `±z` (sign optional for +) or `all` / absent.
fn quadrant(ctx: &Ctx, w: El) -> Result<Option<WrapQuadrant>, OsimError> {
    let Some(el) = child(w, "quadrant") else {
        return Ok(None);
    };
    let t = text(el);
    if t.is_empty() || t.eq_ignore_ascii_case("all") || t == "Unassigned" {
        return Ok(None);
    }
    let (sign, axis) = match t.strip_prefix('-') {
        Some(a) => (-1, a),
        None => (1, t.strip_prefix('+').unwrap_or(t)),
    };
    let axis = match axis {
        "x" | "X" => 0,
        "y" | "Y" => 1,
        "z" | "Z" => 2,
        _ => {
            return Err(ctx.err(
                el,
                format!("quadrant `{t}` is not one of all, x, -x, y, -y, z, -z"),
            ))
        }
    };
    Ok(Some(WrapQuadrant { axis, sign }))
}

/// The `PathWrapSet` of a geometry path: each wrap names a wrap object of the model.
pub(crate) fn read_path_wraps(
    ctx: &Ctx,
    geometry_path: El,
    n_points: usize,
    model: &Model,
) -> Result<Vec<PathWrap>, OsimError> {
    let Some(set) = child(geometry_path, "PathWrapSet") else {
        return Ok(Vec::new());
    };
    let mut wraps = Vec::new();
    for w in objects(set) {
        if tag(w) != "PathWrap" {
            return Err(ctx.err(w, format!("expected a PathWrap, found `{}`", tag(w))));
        }
        let oel = ctx.req(w, "wrap_object")?;
        let name = text(oel);
        let object = model
            .wrap_objects
            .iter()
            .position(|o| o.name == name)
            .ok_or_else(|| ctx.err(oel, format!("unknown wrap object `{name}`")))?;
        let range = match child(w, "range") {
            Some(r) => {
                let v = ctx.arr_of::<2>(r)?;
                let bad = v
                    .iter()
                    .any(|x| x.fract() != 0.0 || *x > n_points as f64 || *x < -1.0);
                if bad {
                    return Err(ctx.err(
                        r,
                        format!("range {v:?} must be point numbers 1..={n_points} or -1"),
                    ));
                }
                [v[0] as i32, v[1] as i32]
            }
            None => [-1, -1],
        };
        let method = match child(w, "method") {
            Some(m) if !text(m).is_empty() => text(m).to_string(),
            _ => "hybrid".to_string(),
        };
        if !matches!(method.as_str(), "hybrid" | "midpoint" | "axial") {
            return Err(ctx.err(
                w,
                format!("wrap method `{method}` is not one of hybrid, midpoint, axial"),
            ));
        }
        wraps.push(PathWrap {
            object,
            range,
            method,
        });
    }
    Ok(wraps)
}
