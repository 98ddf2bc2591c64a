//! Helpers over the `roxmltree` document: element paths, line numbers, typed values.

use super::OsimError;
use crate::model::{Model, UnsupportedElement};
use roxmltree::{Document, Node};

/// Reading context: the parsed document and the source name used in error messages.
pub(crate) struct Ctx<'a, 'input> {
    /// The parsed XML document.
    pub doc: &'a Document<'input>,
    /// File name (or other label) of the source, for messages.
    pub source: &'a str,
}

/// An XML element node of the document.
pub(crate) type El<'a, 'input> = Node<'a, 'input>;

impl<'a, 'input> Ctx<'a, 'input> {
    /// 1-based line of the start of a node.
    pub fn line(&self, n: El) -> usize {
        self.doc.text_pos_at(n.range().start).row as usize
    }

    /// Element path from `Model` down to `n`, e.g. `Model/BodySet/objects/Body[name=femur_r]`.
    pub fn path(&self, n: El) -> String {
        let mut parts: Vec<String> = n
            .ancestors()
            .filter(|a| a.is_element())
            .take_while(|a| a.tag_name().name() != "OpenSimDocument")
            .map(|a| match a.attribute("name") {
                Some(name) => format!("{}[name={}]", a.tag_name().name(), name),
                None => a.tag_name().name().to_string(),
            })
            .collect();
        parts.reverse();
        if parts.is_empty() {
            // the document's root element itself
            return n.tag_name().name().to_string();
        }
        parts.join("/")
    }

    /// An error located at element `n`.
    pub fn err(&self, n: El, message: impl Into<String>) -> OsimError {
        OsimError::Invalid {
            source_name: self.source.to_string(),
            line: self.line(n),
            path: self.path(n),
            message: message.into(),
        }
    }

    /// An error about a missing child `tag` of element `n`.
    pub fn missing(&self, n: El, tag: &str) -> OsimError {
        OsimError::Invalid {
            source_name: self.source.to_string(),
            line: self.line(n),
            path: format!("{}/{}", self.path(n), tag),
            message: "required element is missing".into(),
        }
    }

    /// The required child element named `tag`.
    pub fn req<'b>(&self, n: El<'b, 'input>, tag: &str) -> Result<El<'b, 'input>, OsimError> {
        child(n, tag).ok_or_else(|| self.missing(n, tag))
    }

    /// The number held by element `n`.
    pub fn f64_of(&self, n: El) -> Result<f64, OsimError> {
        let t = text(n);
        parse_num(t).ok_or_else(|| self.err(n, format!("`{t}` is not a number")))
    }

    /// All numbers held by element `n` (space separated).
    pub fn vec_of(&self, n: El) -> Result<Vec<f64>, OsimError> {
        text(n)
            .split_whitespace()
            .map(|t| parse_num(t).ok_or_else(|| self.err(n, format!("`{t}` is not a number"))))
            .collect()
    }

    /// Exactly `N` numbers held by element `n`.
    pub fn arr_of<const N: usize>(&self, n: El) -> Result<[f64; N], OsimError> {
        let v = self.vec_of(n)?;
        v.as_slice().try_into().map_err(|_| {
            self.err(
                n,
                format!("expected {N} numbers, found {} (`{}`)", v.len(), text(n)),
            )
        })
    }

    /// A boolean (`true`/`false`) held by element `n`.
    pub fn bool_of(&self, n: El) -> Result<bool, OsimError> {
        match text(n) {
            "true" | "1" => Ok(true),
            "false" | "0" => Ok(false),
            t => Err(self.err(n, format!("`{t}` is not a boolean (true/false)"))),
        }
    }

    /// Required number child.
    pub fn req_f64(&self, n: El, tag: &str) -> Result<f64, OsimError> {
        self.f64_of(self.req(n, tag)?)
    }

    /// Optional number child with a default.
    pub fn opt_f64(&self, n: El, tag: &str, default: f64) -> Result<f64, OsimError> {
        match child(n, tag) {
            Some(c) if !text(c).is_empty() => self.f64_of(c),
            _ => Ok(default),
        }
    }

    /// Optional 3-vector child with a default.
    pub fn opt_vec3(&self, n: El, tag: &str, default: [f64; 3]) -> Result<[f64; 3], OsimError> {
        match child(n, tag) {
            Some(c) if !text(c).is_empty() => self.arr_of::<3>(c),
            _ => Ok(default),
        }
    }

    /// Optional boolean child with a default.
    pub fn opt_bool(&self, n: El, tag: &str, default: bool) -> Result<bool, OsimError> {
        match child(n, tag) {
            Some(c) if !text(c).is_empty() => self.bool_of(c),
            _ => Ok(default),
        }
    }
}

/// Parse one number as written in `.osim` files (also `inf`, `-inf`, `nan`).
fn parse_num(t: &str) -> Option<f64> {
    match t.to_ascii_lowercase().as_str() {
        "inf" | "+inf" | "infinity" => Some(f64::INFINITY),
        "-inf" | "-infinity" => Some(f64::NEG_INFINITY),
        "nan" => Some(f64::NAN),
        _ => t.parse().ok(),
    }
}

/// The first child element named `tag`.
pub(crate) fn child<'b, 'input>(n: El<'b, 'input>, tag: &str) -> Option<El<'b, 'input>> {
    n.children()
        .find(|c| c.is_element() && c.tag_name().name() == tag)
}

/// All child elements.
pub(crate) fn elements<'b, 'input>(n: El<'b, 'input>) -> impl Iterator<Item = El<'b, 'input>> {
    n.children().filter(|c| c.is_element())
}

/// Child elements of `n/objects` (OpenSim sets), empty when absent.
pub(crate) fn objects<'b, 'input>(n: El<'b, 'input>) -> Vec<El<'b, 'input>> {
    child(n, "objects")
        .map(|o| elements(o).collect())
        .unwrap_or_default()
}

/// Trimmed text of an element ("" when empty).
pub(crate) fn text<'b>(n: El<'b, '_>) -> &'b str {
    n.text().map(str::trim).unwrap_or("")
}

/// Optional trimmed text of a child element ("" when absent).
pub(crate) fn child_text<'b>(n: El<'b, '_>, tag: &str) -> &'b str {
    child(n, tag).map(text).unwrap_or("")
}

/// Tag name of an element.
pub(crate) fn tag<'b>(n: El<'b, '_>) -> &'b str {
    n.tag_name().name()
}

/// Name attribute ("" when absent).
pub(crate) fn name_of<'b>(n: El<'b, '_>) -> &'b str {
    n.attribute("name").unwrap_or("")
}

/// Last component of an OpenSim component path (`/bodyset/femur_r` → `femur_r`).
pub(crate) fn last_component(path: &str) -> &str {
    path.trim_end_matches('/')
        .rsplit('/')
        .next()
        .unwrap_or(path)
}

/// Rotation matrix of body-fixed X–Y–Z Euler angles (OpenSim orientation convention).
pub(crate) fn rot_xyz(a: [f64; 3]) -> [[f64; 3]; 3] {
    let (s1, c1) = a[0].sin_cos();
    let (s2, c2) = a[1].sin_cos();
    let (s3, c3) = a[2].sin_cos();
    // R = Rx(a0) Ry(a1) Rz(a2)
    [
        [c2 * c3, -c2 * s3, s2],
        [c1 * s3 + s1 * s2 * c3, c1 * c3 - s1 * s2 * s3, -s1 * c2],
        [s1 * s3 - c1 * s2 * c3, s1 * c3 + c1 * s2 * s3, c1 * c2],
    ]
}

/// Matrix–vector product.
pub(crate) fn mul(r: &[[f64; 3]; 3], v: [f64; 3]) -> [f64; 3] {
    [
        r[0][0] * v[0] + r[0][1] * v[1] + r[0][2] * v[2],
        r[1][0] * v[0] + r[1][1] * v[1] + r[1][2] * v[2],
        r[2][0] * v[0] + r[2][1] * v[1] + r[2][2] * v[2],
    ]
}

/// Record an element that was not imported.
pub(crate) fn report(ctx: &Ctx, model: &mut Model, el: El, reason: impl Into<String>) {
    model.unsupported.push(UnsupportedElement {
        element: tag(el).to_string(),
        name: name_of(el).to_string(),
        path: ctx.path(el),
        line: ctx.line(el),
        reason: reason.into(),
    });
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rot_xyz_is_product_of_elementary_rotations() {
        // Rz(-pi/2) maps x to -y.
        let r = rot_xyz([0.0, 0.0, -std::f64::consts::FRAC_PI_2]);
        let v = mul(&r, [1.0, 0.0, 0.0]);
        assert!((v[0]).abs() < 1e-15 && (v[1] + 1.0).abs() < 1e-15 && v[2].abs() < 1e-15);
        // Body-fixed X then Y: Rx(90°) Ry(90°) applied to x gives Rx(90°) (-z)... = (0, 1, 0)
        let h = std::f64::consts::FRAC_PI_2;
        let v = mul(&rot_xyz([h, h, 0.0]), [1.0, 0.0, 0.0]);
        // Ry(90) x = (0,0,-1); Rx(90) (0,0,-1) = (0, 1, 0)
        assert!(v[0].abs() < 1e-15 && (v[1] - 1.0).abs() < 1e-15 && v[2].abs() < 1e-15);
    }

    #[test]
    fn last_component_of_paths() {
        assert_eq!(last_component("/bodyset/femur_r"), "femur_r");
        assert_eq!(last_component("femur_r"), "femur_r");
        assert_eq!(
            last_component("/jointset/knee_r/knee_angle_r"),
            "knee_angle_r"
        );
    }
}
