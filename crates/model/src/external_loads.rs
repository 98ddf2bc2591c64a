//! OpenSim ExternalLoads files (`.xml`, versions 20302 to 4.x): the measured forces of a
//! trial, each with the body it acts on, the frames its force and point are expressed in,
//! the column identifiers of its force, point and torque in the data file, and that data
//! file (`<datafile>`, a `.mot`/`.sto` beside the `.xml`).
//!
//! The columns of one force are `{identifier}x`, `{identifier}y` and `{identifier}z` for
//! each of its three identifiers (e.g. `ground_force_vx` for `ground_force_v`).

use crate::storage::{read_limited, Storage};
use std::path::{Path, PathBuf};

/// Largest ExternalLoads file read [bytes] (OpenSim's own are below 30 kB).
pub const MAX_EXTERNAL_LOADS_BYTES: u64 = 4 << 20;

/// One `ExternalForce` of an ExternalLoads file.
#[derive(Clone, Debug, PartialEq)]
pub struct ExternalForce {
    /// Its `name` attribute.
    pub name: String,
    /// Line of its element in the file (1-based), for messages.
    pub line: usize,
    /// Body the force acts on (`applied_to_body`; a component path is reduced to its
    /// last part, `/bodyset/calcn_r` → `calcn_r`).
    pub applied_to_body: String,
    /// Frame of the force and torque vectors (`force_expressed_in_body`, default ground).
    pub force_expressed_in_body: String,
    /// Frame of the point of application (`point_expressed_in_body`, default ground).
    pub point_expressed_in_body: String,
    /// Column prefix of the force [N] (`force_identifier`).
    pub force_identifier: String,
    /// Column prefix of the point of application [m] (`point_identifier`).
    pub point_identifier: String,
    /// Column prefix of the free torque [N m] (`torque_identifier`).
    pub torque_identifier: String,
    /// Whether the force is applied (`isDisabled` false in OpenSim 3, `appliesForce` true
    /// in OpenSim 4; applied when neither is given).
    pub enabled: bool,
}

impl ExternalForce {
    /// The data columns of this force: force x y z [N], point x y z [m], torque x y z
    /// [N m].
    pub fn columns(&self) -> [String; 9] {
        let ids = [
            &self.force_identifier,
            &self.point_identifier,
            &self.torque_identifier,
        ];
        std::array::from_fn(|i| format!("{}{}", ids[i / 3], ["x", "y", "z"][i % 3]))
    }
}

/// The content of an ExternalLoads file.
#[derive(Clone, Debug, PartialEq)]
pub struct ExternalLoads {
    /// The file, as given (for messages).
    pub path: PathBuf,
    /// The forces, in file order (disabled ones included, marked).
    pub forces: Vec<ExternalForce>,
    /// The data file (`<datafile>`), relative paths resolved against the folder of the
    /// `.xml`.
    pub datafile: PathBuf,
}

/// Why an ExternalLoads file cannot be used; every message names the file and the
/// element (and the force).
#[derive(Debug, thiserror::Error)]
pub enum ExternalLoadsError {
    /// The file (or its data file) could not be read.
    #[error("{path}: {reason}")]
    Read {
        /// The file.
        path: String,
        /// Why.
        reason: String,
    },
    /// The file is not well-formed XML or not an ExternalLoads document.
    #[error("{path}:{line}: {reason}")]
    Format {
        /// The file.
        path: String,
        /// Line (1-based).
        line: usize,
        /// Why.
        reason: String,
    },
    /// A force lacks an element or has an invalid value in one.
    #[error("{path}:{line}: ExternalForce `{force}`: <{element}> {reason}")]
    Force {
        /// The file.
        path: String,
        /// Line of the force (1-based).
        line: usize,
        /// The force's name.
        force: String,
        /// The element.
        element: String,
        /// Why.
        reason: String,
    },
    /// The forces do not suit their use (e.g. no force on one foot).
    #[error("{path}: {reason}")]
    Unusable {
        /// The file.
        path: String,
        /// Why.
        reason: String,
    },
    /// The data file named by `<datafile>` cannot be read.
    #[error("{path}: <datafile> `{datafile}`: {reason}")]
    DataFile {
        /// The `.xml` file.
        path: String,
        /// The data file, resolved.
        datafile: String,
        /// Why.
        reason: String,
    },
}

/// Trimmed text of the child element `tag` of `n`, if present.
fn child_text<'a>(n: roxmltree::Node<'a, '_>, tag: &str) -> Option<&'a str> {
    n.children()
        .find(|c| c.is_element() && c.tag_name().name() == tag)
        .map(|c| c.text().map(str::trim).unwrap_or(""))
}

/// Line (1-based) of node `n` in `doc`.
fn line_of(doc: &roxmltree::Document, n: roxmltree::Node) -> usize {
    doc.text_pos_at(n.range().start).row as usize
}

/// Last part of an OpenSim component path (`/bodyset/calcn_r` → `calcn_r`; `ground` and
/// `/ground` → `ground`).
fn last_part(path: &str) -> String {
    path.trim_end_matches('/')
        .rsplit('/')
        .next()
        .unwrap_or(path)
        .to_string()
}

impl ExternalLoads {
    /// Reads an ExternalLoads file (at most [`MAX_EXTERNAL_LOADS_BYTES`]).
    pub fn read(path: &Path) -> Result<Self, ExternalLoadsError> {
        let name = path.display().to_string();
        let bytes =
            read_limited(path, MAX_EXTERNAL_LOADS_BYTES).map_err(|e| ExternalLoadsError::Read {
                path: name.clone(),
                reason: e.to_string(),
            })?;
        let text = String::from_utf8(bytes).map_err(|_| ExternalLoadsError::Read {
            path: name.clone(),
            reason: "not UTF-8 text".into(),
        })?;
        Self::parse(&text, path)
    }

    /// Parses the text of an ExternalLoads file; `path` names it in messages and its folder
    /// resolves a relative `<datafile>`.
    pub fn parse(text: &str, path: &Path) -> Result<Self, ExternalLoadsError> {
        let name = path.display().to_string();
        let format = |line: usize, reason: String| ExternalLoadsError::Format {
            path: name.clone(),
            line,
            reason,
        };
        crate::osim::input::check_depth(text, 64, &name).map_err(|e| format(0, e.to_string()))?;
        let doc = roxmltree::Document::parse(text)
            .map_err(|e| format(e.pos().row as usize, format!("malformed XML: {e}")))?;
        let loads = doc
            .descendants()
            .find(|n| n.has_tag_name("ExternalLoads"))
            .ok_or_else(|| format(1, "no <ExternalLoads> element".into()))?;
        let forces = loads
            .descendants()
            .filter(|n| n.has_tag_name("ExternalForce"))
            .map(|n| force(&doc, n, &name))
            .collect::<Result<Vec<_>, _>>()?;
        if forces.is_empty() {
            return Err(format(line_of(&doc, loads), "no <ExternalForce>".into()));
        }
        let datafile = child_text(loads, "datafile").unwrap_or("");
        if datafile.is_empty() {
            return Err(format(
                line_of(&doc, loads),
                "<ExternalLoads> has no <datafile> (the .mot/.sto file of the forces)".into(),
            ));
        }
        let folder = path.parent().unwrap_or(Path::new(""));
        Ok(Self {
            path: path.to_path_buf(),
            forces,
            datafile: folder.join(datafile),
        })
    }

    /// The forces that are applied (not disabled).
    pub fn enabled(&self) -> impl Iterator<Item = &ExternalForce> {
        self.forces.iter().filter(|f| f.enabled)
    }

    /// Reads the data file and checks that it has the columns of every applied force.
    pub fn read_data(&self) -> Result<Storage, ExternalLoadsError> {
        let data_error = |reason: String| ExternalLoadsError::DataFile {
            path: self.path.display().to_string(),
            datafile: self.datafile.display().to_string(),
            reason,
        };
        if !self.datafile.is_file() {
            return Err(data_error("no such file".into()));
        }
        let data = Storage::read(&self.datafile).map_err(|e| data_error(e.to_string()))?;
        for f in self.enabled() {
            if let Some(c) = f.columns().into_iter().find(|c| data.column(c).is_none()) {
                return Err(data_error(format!(
                    "no column `{c}` (of ExternalForce `{}`)",
                    f.name
                )));
            }
        }
        Ok(data)
    }
}

/// One `<ExternalForce>` element.
fn force(
    doc: &roxmltree::Document,
    n: roxmltree::Node,
    path: &str,
) -> Result<ExternalForce, ExternalLoadsError> {
    let name = n.attribute("name").unwrap_or("").to_string();
    let line = line_of(doc, n);
    let bad = |element: &str, reason: &str| ExternalLoadsError::Force {
        path: path.into(),
        line,
        force: name.clone(),
        element: element.into(),
        reason: reason.into(),
    };
    let required = |element: &str| match child_text(n, element) {
        Some(t) if !t.is_empty() => Ok(t.to_string()),
        _ => Err(bad(element, "is missing or empty")),
    };
    let frame = |element: &str| match child_text(n, element) {
        Some(t) if !t.is_empty() => last_part(t),
        _ => "ground".to_string(),
    };
    let flag = |element: &str| -> Result<Option<bool>, ExternalLoadsError> {
        match child_text(n, element)
            .map(str::to_ascii_lowercase)
            .as_deref()
        {
            None => Ok(None),
            Some("true" | "1") => Ok(Some(true)),
            Some("false" | "0") => Ok(Some(false)),
            Some(_) => Err(bad(element, "is neither true nor false")),
        }
    };
    let disabled = flag("isDisabled")?.unwrap_or(false);
    let applies = flag("appliesForce")?.unwrap_or(true);
    Ok(ExternalForce {
        applied_to_body: last_part(&required("applied_to_body")?),
        force_expressed_in_body: frame("force_expressed_in_body"),
        point_expressed_in_body: frame("point_expressed_in_body"),
        force_identifier: required("force_identifier")?,
        point_identifier: required("point_identifier")?,
        torque_identifier: required("torque_identifier")?,
        enabled: applies && !disabled,
        name: name.clone(),
        line,
    })
}

#[cfg(test)]
mod tests;
