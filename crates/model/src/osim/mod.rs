//! OpenSim .osim import (formats 30000 and 40000).
//!
//! [`load_osim`] reads a file, [`parse_osim`] a string. Imported: bodies; joints
//! (`CustomJoint` with any of the functions of [`crate::Function`], `PinJoint`,
//! `SliderJoint`, `PlanarJoint`, `UniversalJoint`, `GimbalJoint`, `BallJoint`,
//! `FreeJoint`, `WeldJoint`); coordinates with OpenSim's motion types;
//! `CoordinateCouplerConstraint`s; muscles of the Thelen 2003, Millard 2012, De
//! Groote–Fregly 2016 (with its active curve width and passive force options) and
//! rigid-tendon classes (their common Hill parameters) on paths of fixed, conditional and
//! moving points or on a `FunctionBasedPath` with a `MultivariatePolynomialFunction`;
//! `CoordinateActuator`s and `ActivationCoordinateActuator`s;
//! `SmoothSphereHalfSpaceForce` contacts; `Ligament`s; `CoordinateLimitForce`s,
//! `SpringGeneralizedForce`s and `ExpressionBasedCoordinateForce`s. These are read from
//! the classic sets and from the component tree (the model's `<components>` and nested
//! ones, `ComponentSet`). Any other joint, constraint or force element is an error naming
//! it and its line (it would change the dynamics); path wrapping, other component types
//! and options stride does not model are listed in [`Model::unsupported`]; visual and
//! bookkeeping content is counted in one summary entry there.

mod components;
mod forces;
mod function_path;
mod functions;
pub(crate) mod input;
mod skeleton;
mod wrap;
mod xml;

use crate::model::{Model, UnsupportedElement};
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use xml::{child, elements, objects, tag, text, Ctx};

pub use input::MAX_XML_DEPTH;

/// Largest `.osim` file read [bytes] (OpenSim models are a few MB; parsing takes about ten
/// times the file size in memory).
pub const MAX_OSIM_BYTES: u64 = 64 << 20;

/// Errors of the `.osim` importer; messages name the file, line and element path.
#[derive(Debug, thiserror::Error)]
pub enum OsimError {
    /// The file could not be read.
    #[error("{path}: {error}")]
    Io {
        /// File concerned.
        path: PathBuf,
        /// Underlying I/O error (part of the message, not a separate cause, so that it is
        /// printed once).
        error: std::io::Error,
    },
    /// The file is not well-formed XML.
    #[error("{source_name}:{line}:{column}: malformed XML: {message}")]
    Xml {
        /// File name.
        source_name: String,
        /// Line (1-based).
        line: usize,
        /// Column (1-based).
        column: usize,
        /// Parser message.
        message: String,
    },
    /// A required value is missing or invalid.
    #[error("{source_name}:{line}: {path}: {message}")]
    Invalid {
        /// File name.
        source_name: String,
        /// Line (1-based) of the element.
        line: usize,
        /// Element path, e.g. `Model/BodySet/objects/Body[name=femur_r]/mass`.
        path: String,
        /// What is wrong.
        message: String,
    },
}

/// Read an OpenSim model file (`Version` 30000–4xxxx, at most [`MAX_OSIM_BYTES`], UTF-8 or
/// declared ISO-8859-1) into a [`Model`].
pub fn load_osim(path: &Path) -> Result<Model, OsimError> {
    let bytes =
        crate::storage::read_limited(path, MAX_OSIM_BYTES).map_err(|error| OsimError::Io {
            path: path.to_path_buf(),
            error,
        })?;
    let mut model = parse_osim_bytes(&bytes, &path.display().to_string())?;
    model.source_file = Some(path.to_path_buf());
    Ok(model)
}

/// Parse the bytes of an OpenSim model (UTF-8, or ISO-8859-1 when declared);
/// `source_name` labels error messages.
pub fn parse_osim_bytes(bytes: &[u8], source_name: &str) -> Result<Model, OsimError> {
    parse_osim(&input::decode(bytes, source_name)?, source_name)
}

/// Parse the text of an OpenSim model (elements nested at most [`MAX_XML_DEPTH`] deep);
/// `source_name` labels error messages.
pub fn parse_osim(text_in: &str, source_name: &str) -> Result<Model, OsimError> {
    input::check_depth(text_in, MAX_XML_DEPTH, source_name)?;
    let opts = roxmltree::ParsingOptions {
        allow_dtd: true,
        ..Default::default()
    };
    let doc = roxmltree::Document::parse_with_options(text_in, opts).map_err(|e| {
        let pos = e.pos();
        OsimError::Xml {
            source_name: source_name.to_string(),
            line: pos.row as usize,
            column: pos.col as usize,
            message: e.to_string(),
        }
    })?;
    let ctx = Ctx {
        doc: &doc,
        source: source_name,
    };
    let root = doc.root_element();
    if tag(root) != "OpenSimDocument" {
        return Err(ctx.err(
            root,
            format!(
                "root element is `{}`, expected `OpenSimDocument`",
                tag(root)
            ),
        ));
    }
    let version: u32 = match root.attribute("Version") {
        Some(v) => v
            .trim()
            .parse()
            .map_err(|_| ctx.err(root, format!("Version attribute `{v}` is not an integer")))?,
        None => return Err(ctx.err(root, "missing Version attribute")),
    };
    if version < 30000 {
        return Err(ctx.err(
            root,
            format!("OpenSim file format {version} is not supported (need 30000 or later)"),
        ));
    }
    let model_el = ctx.req(root, "Model")?;
    let v4 = child(model_el, "JointSet").is_some() || version >= 40000;

    let mut model = Model {
        name: model_el.attribute("name").unwrap_or("").to_string(),
        ..Default::default()
    };
    // OpenSim's default when the file gives none: standard gravity along −y.
    model.gravity = match child(model_el, "gravity") {
        Some(g) => ctx.arr_of::<3>(g)?,
        None => [0.0, -9.80665, 0.0],
    };
    if let Some(u) = child(model_el, "length_units") {
        let t = text(u);
        if !t.is_empty() && t != "meters" && t != "m" {
            return Err(ctx.err(
                u,
                format!("length units `{t}` are not supported (need meters)"),
            ));
        }
    }
    let frames = skeleton::read_skeleton(&ctx, model_el, v4, &mut model)?;
    let tree = components::gather(model_el);
    skeleton::read_constraints(&ctx, &tree.constraints, v4, &mut model)?;
    wrap::read_wrap_objects(&ctx, model_el, &frames, &mut model)?;
    forces::read_forces(&ctx, &tree.forces, &tree.geometry, v4, &frames, &mut model)?;
    for o in &tree.others {
        xml::report(
            &ctx,
            &mut model,
            *o,
            format!("model component of type `{}` is not read", tag(*o)),
        );
    }
    report_other_content(&ctx, model_el, &mut model);
    Ok(model)
}

/// Visual and bookkeeping content → one summary entry (the component tree is read by
/// [`components::gather`]).
fn report_other_content(ctx: &Ctx, model_el: xml::El, model: &mut Model) {
    let mut skipped: BTreeMap<String, usize> = BTreeMap::new();
    for c in elements(model_el) {
        match tag(c) {
            "credits" | "publications" | "length_units" | "force_units" | "gravity" | "BodySet"
            | "JointSet" | "ForceSet" | "ContactGeometrySet" | "Ground" | "ConstraintSet"
            | "ComponentSet" | "components" => {}
            "MarkerSet" | "ControllerSet" | "ProbeSet" => {
                for o in objects(c) {
                    *skipped.entry(tag(o).to_string()).or_default() += 1;
                }
            }
            other => {
                *skipped.entry(other.to_string()).or_default() += 1;
            }
        }
    }
    // Visual content.
    for n in model_el.descendants().filter(|n| n.is_element()) {
        let t = tag(n);
        if matches!(
            t,
            "VisibleObject" | "attached_geometry" | "FrameGeometry" | "Appearance"
        ) {
            *skipped.entry(t.to_string()).or_default() += 1;
        }
    }
    if !skipped.is_empty() {
        let list: Vec<String> = skipped.iter().map(|(k, n)| format!("{n} {k}")).collect();
        model.unsupported.push(UnsupportedElement {
            element: "(visual/bookkeeping)".into(),
            name: String::new(),
            path: "Model".into(),
            line: ctx.line(model_el),
            reason: format!("skipped, no mechanics: {}", list.join(", ")),
        });
    }
}

#[cfg(test)]
mod tests;
