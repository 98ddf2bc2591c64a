//! OpenSim storage files (.mot/.sto): reading and writing.
//!
//! A storage file is a header (lines up to `endheader`, e.g. `version=1`, `nRows=`,
//! `nColumns=`, `inDegrees=yes|no`, or the older `name`/`datacolumns`/`datarows`/`range`
//! style), one line of column labels, and numeric rows separated by tabs or spaces.
//! Values may be `nan`/`NaN`/`inf`.

use std::path::{Path, PathBuf};
use stride_files::write_atomic;

/// Errors reading or writing a storage file; every variant names the file (and line).
#[derive(Debug, thiserror::Error)]
pub enum StorageError {
    /// The file could not be read or written.
    #[error("{path}: {source}")]
    Io {
        /// File concerned.
        path: PathBuf,
        /// Underlying I/O error.
        #[source]
        source: std::io::Error,
    },
    /// The file has no `endheader` line.
    #[error("{path}: no `endheader` line found")]
    NoEndHeader {
        /// File concerned.
        path: PathBuf,
    },
    /// The file ends right after the header, without a label line.
    #[error("{path}: no column label line after `endheader`")]
    NoLabels {
        /// File concerned.
        path: PathBuf,
    },
    /// A data entry is not a number.
    #[error("{path}:{line}: column {column} (`{label}`): `{text}` is not a number")]
    BadNumber {
        /// File concerned.
        path: PathBuf,
        /// Line number (1-based).
        line: usize,
        /// Column index (0-based).
        column: usize,
        /// Column label.
        label: String,
        /// The offending text.
        text: String,
    },
    /// A data row has a different number of entries than there are labels.
    #[error("{path}:{line}: row has {found} values but there are {expected} column labels")]
    RowLength {
        /// File concerned.
        path: PathBuf,
        /// Line number (1-based).
        line: usize,
        /// Number of labels.
        expected: usize,
        /// Number of values on the row.
        found: usize,
    },
    /// A storage to be written is inconsistent (row length differs from label count).
    #[error("storage `{name}`: row {row} has {found} values but there are {expected} labels")]
    Inconsistent {
        /// Storage name.
        name: String,
        /// Row index (0-based).
        row: usize,
        /// Number of labels.
        expected: usize,
        /// Number of values on the row.
        found: usize,
    },
}

/// The content of an OpenSim storage file: named columns of numbers (time first, usually).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Storage {
    /// Name (first header line, or the `name` key of the older format).
    pub name: String,
    /// Whether angles are in degrees (`inDegrees=yes`), if the header says.
    pub in_degrees: Option<bool>,
    /// Column labels (e.g. `time`, coordinate names).
    pub labels: Vec<String>,
    /// Numeric rows, each with `labels.len()` values.
    pub rows: Vec<Vec<f64>>,
}

fn parse_value(s: &str) -> Option<f64> {
    match s.to_ascii_lowercase().as_str() {
        "nan" | "-nan" | "+nan" => Some(f64::NAN),
        "inf" | "+inf" | "infinity" => Some(f64::INFINITY),
        "-inf" | "-infinity" => Some(f64::NEG_INFINITY),
        _ => s.parse::<f64>().ok(),
    }
}

impl Storage {
    /// Read a storage file (`.mot`, `.sto`) from disk.
    pub fn read(path: &Path) -> Result<Storage, StorageError> {
        let io = |source| StorageError::Io {
            path: path.to_path_buf(),
            source,
        };
        let bytes = read_limited(path, MAX_STORAGE_BYTES).map_err(io)?;
        let text = String::from_utf8(bytes).map_err(|e| {
            let at = e.utf8_error().valid_up_to();
            let line = 1 + e.as_bytes()[..at].iter().filter(|&&b| b == b'\n').count();
            io(std::io::Error::new(
                std::io::ErrorKind::InvalidData,
                format!("line {line}: not UTF-8 text"),
            ))
        })?;
        Self::parse(&text, path)
    }

    /// Parse the text of a storage file; `path` is used only in error messages.
    pub fn parse(text: &str, path: &Path) -> Result<Storage, StorageError> {
        let mut lines = text.lines().enumerate();
        let mut name = String::new();
        let mut in_degrees = None;
        let mut found_end = false;
        let mut first = true;
        for (_, raw) in lines.by_ref() {
            let line = raw.trim();
            if line.eq_ignore_ascii_case("endheader") {
                found_end = true;
                break;
            }
            if let Some((key, value)) = line.split_once('=') {
                let (key, value) = (key.trim(), value.trim());
                if key.eq_ignore_ascii_case("inDegrees") {
                    in_degrees = Some(value.eq_ignore_ascii_case("yes"));
                }
            } else if let Some(rest) = line.strip_prefix("name ") {
                name = rest.trim().to_string();
            } else if first && !line.is_empty() {
                name = line.to_string();
            }
            if !line.is_empty() {
                first = false;
            }
        }
        if !found_end {
            return Err(StorageError::NoEndHeader {
                path: path.to_path_buf(),
            });
        }
        let labels: Vec<String> = loop {
            match lines.next() {
                Some((_, l)) if l.trim().is_empty() => continue,
                Some((_, l)) => break l.split_whitespace().map(str::to_string).collect(),
                None => {
                    return Err(StorageError::NoLabels {
                        path: path.to_path_buf(),
                    })
                }
            }
        };
        let mut rows = Vec::new();
        for (i, raw) in lines {
            if raw.trim().is_empty() {
                continue;
            }
            let mut row = Vec::with_capacity(labels.len());
            for (column, tok) in raw.split_whitespace().enumerate() {
                let v = parse_value(tok).ok_or_else(|| StorageError::BadNumber {
                    path: path.to_path_buf(),
                    line: i + 1,
                    column,
                    label: labels.get(column).cloned().unwrap_or_default(),
                    text: tok.to_string(),
                })?;
                row.push(v);
            }
            if row.len() != labels.len() {
                return Err(StorageError::RowLength {
                    path: path.to_path_buf(),
                    line: i + 1,
                    expected: labels.len(),
                    found: row.len(),
                });
            }
            rows.push(row);
        }
        Ok(Storage {
            name,
            in_degrees,
            labels,
            rows,
        })
    }

    /// Index of the column with this label.
    pub fn column_index(&self, label: &str) -> Option<usize> {
        self.labels.iter().position(|l| l == label)
    }

    /// The values of the column with this label (one per row), if present.
    pub fn column(&self, label: &str) -> Option<Vec<f64>> {
        let j = self.column_index(label)?;
        Some(self.rows.iter().map(|r| r[j]).collect())
    }

    /// The values of the column holding coordinate `name`'s value, named after it or by
    /// its OpenSim 4 state path (see [`coordinate_of_label`]), if present.
    pub fn coordinate_column(&self, name: &str) -> Option<Vec<f64>> {
        let j = self
            .labels
            .iter()
            .position(|l| coordinate_of_label(l) == Some(name))?;
        Some(self.rows.iter().map(|r| r[j]).collect())
    }

    /// Whether rotational coordinates are in degrees: as the header's `inDegrees` says;
    /// without it, degrees unless the columns are OpenSim 4 state paths (states are in
    /// radians).
    pub fn angles_in_degrees(&self) -> bool {
        self.in_degrees
            .unwrap_or_else(|| !self.labels.iter().any(|l| l.starts_with('/')))
    }

    /// The `time` column [s] (or the first column when no column is labelled `time`).
    pub fn time(&self) -> Vec<f64> {
        self.column("time")
            .unwrap_or_else(|| self.rows.iter().map(|r| r[0]).collect())
    }

    /// Number of data rows.
    pub fn n_rows(&self) -> usize {
        self.rows.len()
    }

    /// Render the storage in the OpenSim `version=1` text format.
    pub fn to_text(&self) -> Result<String, StorageError> {
        for (row, r) in self.rows.iter().enumerate() {
            if r.len() != self.labels.len() {
                return Err(StorageError::Inconsistent {
                    name: self.name.clone(),
                    row,
                    expected: self.labels.len(),
                    found: r.len(),
                });
            }
        }
        // The name is the first header line: one that would read back as something else
        // (the end of the header, a key, the older `name` key, several lines) is replaced.
        let n = self.name.trim();
        let unsafe_name = n.is_empty()
            || n.eq_ignore_ascii_case("endheader")
            || n.contains(['=', '\n', '\r'])
            || n.starts_with("name ");
        let name = if unsafe_name { "stride" } else { n };
        let mut s = String::new();
        s.push_str(name);
        s.push('\n');
        s.push_str("version=1\n");
        s.push_str(&format!("nRows={}\n", self.rows.len()));
        s.push_str(&format!("nColumns={}\n", self.labels.len()));
        let deg = if self.in_degrees == Some(true) {
            "yes"
        } else {
            "no"
        };
        s.push_str(&format!("inDegrees={deg}\n"));
        s.push_str("endheader\n");
        s.push_str(&self.labels.join("\t"));
        s.push('\n');
        for r in &self.rows {
            let mut firstv = true;
            for v in r {
                if !firstv {
                    s.push('\t');
                }
                firstv = false;
                if v.is_nan() {
                    s.push_str("nan");
                } else {
                    // `{:?}` prints the shortest representation that round-trips exactly.
                    s.push_str(&format!("{v:?}"));
                }
            }
            s.push('\n');
        }
        Ok(s)
    }

    /// Write the storage to `path` (atomically) in the OpenSim `version=1` format.
    pub fn write(&self, path: &Path) -> Result<(), StorageError> {
        let text = self.to_text()?;
        write_atomic(path, text.as_bytes()).map_err(|source| StorageError::Io {
            path: path.to_path_buf(),
            source,
        })
    }
}

/// The coordinate whose value a column holds: the label itself for a plain label
/// (`knee_angle_r`), the coordinate of an OpenSim 4 state path
/// (`/jointset/walker_knee_r/knee_angle_r/value`), `None` for any other state path
/// (speeds, muscle states).
pub fn coordinate_of_label(label: &str) -> Option<&str> {
    if !label.starts_with('/') {
        return Some(label);
    }
    let rest = label.strip_suffix("/value")?;
    rest.rsplit('/').next().filter(|c| !c.is_empty())
}

/// Largest `.mot`/`.sto` file read [bytes].
pub const MAX_STORAGE_BYTES: u64 = 256 << 20;

pub use crate::input_file::read_limited;

#[cfg(test)]
mod tests;
