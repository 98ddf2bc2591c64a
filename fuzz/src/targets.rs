//! The fuzz targets: each takes arbitrary bytes, runs a reader on them and panics only when
//! a property the reader promises is broken (a reader's error is a normal outcome).

use std::path::Path;
use stride_model::storage::Storage;

/// A fuzzed reader.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Target {
    /// The OpenSim model reader (`stride_model::osim`).
    Osim,
    /// The storage reader (`.mot`/`.sto`), with a write/read round trip of what it accepts.
    Storage,
    /// The study file parser (`stride_study::spec`), expansion and validation included.
    Study,
}

impl Target {
    /// Every target.
    pub const ALL: [Target; 3] = [Target::Osim, Target::Storage, Target::Study];

    /// The target named `name` (`osim`, `storage`, `study`).
    pub fn from_name(name: &str) -> Option<Target> {
        Self::ALL.into_iter().find(|t| t.name() == name)
    }

    /// Name used on the command line and as the corpus folder.
    pub fn name(self) -> &'static str {
        match self {
            Target::Osim => "osim",
            Target::Storage => "storage",
            Target::Study => "study",
        }
    }

    /// Tokens worth inserting into this target's inputs.
    pub fn dictionary(self) -> &'static [&'static str] {
        match self {
            Target::Osim => &[
                "<",
                ">",
                "</",
                "/>",
                "<!--",
                "-->",
                "<![CDATA[",
                "]]>",
                "<?xml version=\"1.0\" encoding=\"ISO-8859-1\"?>",
                "<!DOCTYPE a [<!ENTITY e \"<b>x</b>\">]>",
                "&e;",
                "&amp;",
                "&#x41;",
                "\"",
                "'",
                "=",
                "<OpenSimDocument Version=\"40000\">",
                "<Model name=\"m\">",
                "<objects>",
                "</objects>",
                "<Body name=\"b\">",
                "<mass>",
                "</mass>",
                "nan",
                "inf",
                "-1e308",
                "0 0 0",
                "1e-320",
            ],
            Target::Storage => &[
                "endheader",
                "\n",
                "\t",
                " ",
                "nan",
                "-inf",
                "inf",
                "1e308",
                "-0",
                "nRows=",
                "nColumns=",
                "inDegrees=yes",
                "name ",
                "version=1",
                "time",
                "=",
                "1e-320",
                "0x1",
                "+",
                "-",
            ],
            Target::Study => &[
                "[study]",
                "[base]",
                "[grid]",
                "[[grid.conditions]]",
                "[study.solver]",
                "=",
                "\"",
                "[",
                "]",
                "{",
                "}",
                ",",
                "\n",
                "nan",
                "inf",
                "-1",
                "0",
                "1e9",
                "speed",
                "mesh_intervals",
                "guesses",
                "jobs",
                "threads_per_case",
                "max_iter",
                "tol",
                "name",
                "output",
                "continuation",
                "coordinate_bounds",
                "strength",
                "weights.metabolic",
                "1.33",
                "18446744073709551615",
            ],
        }
    }

    /// Run the reader on `data`; panics when a promised property fails.
    pub fn run(self, data: &[u8]) {
        match self {
            Target::Osim => {
                let _ = stride_model::osim::parse_osim_bytes(data, "fuzz.osim");
            }
            Target::Storage => storage_round_trip(data),
            Target::Study => {
                let text = String::from_utf8_lossy(data);
                let _ = stride_study::spec::parse(&text, Path::new("fuzz.toml"));
            }
        }
    }
}

/// A storage the reader accepts is written and read back to the same labels and values.
fn storage_round_trip(data: &[u8]) {
    let text = String::from_utf8_lossy(data);
    let Ok(s) = Storage::parse(&text, Path::new("fuzz.mot")) else {
        return;
    };
    let written = s.to_text().expect("an accepted storage can be written");
    let back = Storage::parse(&written, Path::new("fuzz.mot"))
        .unwrap_or_else(|e| panic!("a written storage does not read back: {e}"));
    assert_eq!(back.labels, s.labels, "labels changed in a round trip");
    assert_eq!(
        back.rows.len(),
        s.rows.len(),
        "rows changed in a round trip"
    );
    for (a, b) in s.rows.iter().zip(&back.rows) {
        for (x, y) in a.iter().zip(b) {
            assert!(
                x.to_bits() == y.to_bits() || (x.is_nan() && y.is_nan()),
                "value {x:?} read back as {y:?}"
            );
        }
    }
}
