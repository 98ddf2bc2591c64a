//! Experimental data shipped with stride (subject1 of Falisse et al. 2019, MIT licence,
//! via 3dpredictsim): average inverse-kinematics cycles for bounds and data-informed
//! guesses, walking means ± SD (and trunk sway) for figures, and the affected-side ankle
//! torque of six transtibial amputees (Quesada et al. 2016, via 3dpredictsim) for the
//! prosthesis figure. Regenerate with
//! `stride data import --reference <shared/reference>`, which reads the reference files
//! with stride's own readers and writes them in stride's formats.

use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;
use std::path::Path;
use stride_files::write_atomic;
use stride_model::storage::{Storage, MAX_STORAGE_BYTES};

const WALKING_HALF: &str = include_str!("../data/ik_walking_half_cycle.mot");
const RUNNING_HALF: &str = include_str!("../data/ik_running_half_cycle.mot");
const WALKING_FULL: &str = include_str!("../data/ik_walking_full_cycle.mot");
const WALKING_MEANS: &str = include_str!("../data/experimental_walking.json");

/// Names of the shipped inverse-kinematics files (same names in the reference folder
/// `experimental/`).
pub const IK_FILES: [&str; 3] = [
    "ik_walking_half_cycle.mot",
    "ik_running_half_cycle.mot",
    "ik_walking_full_cycle.mot",
];

/// Average walking half cycle (50 samples, degrees/m): bounds and the walking guess.
pub fn walking_half_cycle() -> Storage {
    Storage::parse(WALKING_HALF, Path::new(IK_FILES[0])).expect("shipped file parses")
}
/// Average running half cycle: the running guess.
pub fn running_half_cycle() -> Storage {
    Storage::parse(RUNNING_HALF, Path::new(IK_FILES[1])).expect("shipped file parses")
}
/// Average walking full cycle: bounds and guess of full-cycle problems.
pub fn walking_full_cycle() -> Storage {
    Storage::parse(WALKING_FULL, Path::new(IK_FILES[2])).expect("shipped file parses")
}

/// Mean and standard deviation of one channel over a gait cycle (100 samples from right
/// heel strike).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Channel {
    /// Unit tag (`deg`, `Nm`, `W`, `pctBW`, ...).
    pub unit: String,
    /// Mean per sample.
    pub mean: Vec<f64>,
    /// Sample standard deviation per sample.
    pub std: Vec<f64>,
}

/// Walking reference data of the subject (11 trials).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct WalkingReference {
    /// Quantity (`joint_angles`, `joint_torques`, `joint_powers`, `grf`, ...) → channel →
    /// mean ± SD.
    pub quantities: BTreeMap<String, BTreeMap<String, Channel>>,
    /// Step width mean and SD [m].
    pub step_width: [f64; 2],
    /// Stride length mean and SD [m].
    pub stride_length: [f64; 2],
}

/// The shipped walking reference data.
pub fn walking_reference() -> WalkingReference {
    serde_json::from_str(WALKING_MEANS).expect("shipped file parses")
}

/// Why the reference data could not be imported.
#[derive(Debug, thiserror::Error)]
pub enum DataError {
    /// File missing or unreadable.
    #[error("{path}: {reason}")]
    Read {
        /// File.
        path: String,
        /// Why.
        reason: String,
    },
    /// Unexpected content.
    #[error("{path}, line {line}: {reason}")]
    Format {
        /// File.
        path: String,
        /// Line (1-based).
        line: usize,
        /// Why.
        reason: String,
    },
}

fn read(path: &Path) -> Result<String, DataError> {
    stride_model::input_file::read_text_limited(path, MAX_STORAGE_BYTES).map_err(|e| {
        DataError::Read {
            path: path.display().to_string(),
            reason: e.to_string(),
        }
    })
}

/// Parse a `*_mean_std.csv` of the reference into channels.
fn parse_mean_std(path: &Path) -> Result<BTreeMap<String, Channel>, DataError> {
    let text = read(path)?;
    let mut lines = text.lines();
    let header: Vec<&str> = lines.next().unwrap_or("").split(',').collect();
    let mut out: BTreeMap<String, Channel> = BTreeMap::new();
    let mut cols = Vec::new();
    for (c, h) in header.iter().enumerate() {
        for (tag, is_mean) in [("_mean_", true), ("_std_", false)] {
            if let Some(p) = h.find(tag) {
                let name = h[..p].to_string();
                let unit = h[p + tag.len()..].to_string();
                out.entry(name.clone()).or_insert(Channel {
                    unit,
                    mean: Vec::new(),
                    std: Vec::new(),
                });
                cols.push((c, name, is_mean));
            }
        }
    }
    for (ln, line) in lines.enumerate() {
        let fields: Vec<&str> = line.split(',').collect();
        for (c, name, is_mean) in &cols {
            let v: f64 = fields
                .get(*c)
                .and_then(|f| f.trim().parse().ok())
                .ok_or_else(|| DataError::Format {
                    path: path.display().to_string(),
                    line: ln + 2,
                    reason: format!("column {} is not a number", c + 1),
                })?;
            let ch = out.get_mut(name).expect("inserted above");
            if *is_mean {
                ch.mean.push(v);
            } else {
                ch.std.push(v);
            }
        }
    }
    Ok(out)
}

/// Mean and sample SD (N − 1) across the per-subject columns (`subject<k>_<name>_<unit>`)
/// of a table with one row per sample, as one channel named `<name>` with unit `<unit>`.
fn parse_subjects(path: &Path, name: &str) -> Result<Channel, DataError> {
    let text = read(path)?;
    let mut lines = text.lines();
    let header: Vec<&str> = lines.next().unwrap_or("").split(',').collect();
    let tag = format!("_{name}_");
    let cols: Vec<usize> = (0..header.len())
        .filter(|&c| header[c].starts_with("subject") && header[c].contains(&tag))
        .collect();
    let unit = cols
        .first()
        .and_then(|&c| header[c].split_once(&tag))
        .map(|(_, u)| u.to_string())
        .ok_or_else(|| DataError::Format {
            path: path.display().to_string(),
            line: 1,
            reason: format!("no `subject<k>{tag}<unit>` columns"),
        })?;
    let n = cols.len() as f64;
    let mut ch = Channel {
        unit,
        mean: Vec::new(),
        std: Vec::new(),
    };
    for (ln, line) in lines.enumerate().filter(|(_, l)| !l.trim().is_empty()) {
        let fields: Vec<&str> = line.split(',').collect();
        let v: Vec<f64> = cols
            .iter()
            .map(|&c| fields.get(c).and_then(|f| f.trim().parse().ok()))
            .collect::<Option<_>>()
            .ok_or_else(|| DataError::Format {
                path: path.display().to_string(),
                line: ln + 2,
                reason: "a subject column is not a number".into(),
            })?;
        let mean = v.iter().sum::<f64>() / n;
        let var = v.iter().map(|x| (x - mean).powi(2)).sum::<f64>() / (n - 1.0).max(1.0);
        ch.mean.push(mean);
        ch.std.push(var.sqrt());
    }
    Ok(ch)
}

/// Mean and SD rows of `walking_step_width_stride_length.csv`.
fn parse_step_stride(path: &Path) -> Result<([f64; 2], [f64; 2]), DataError> {
    let text = read(path)?;
    let mut lines = text.lines();
    let header: Vec<String> = lines
        .next()
        .unwrap_or("")
        .split(',')
        .map(|s| s.trim().to_lowercase())
        .collect();
    let col = |key: &str| header.iter().position(|h| h.contains(key));
    let (sw, sl) = match (col("step_width"), col("stride_length")) {
        (Some(a), Some(b)) => (a, b),
        _ => {
            return Err(DataError::Format {
                path: path.display().to_string(),
                line: 1,
                reason: "expected step_width and stride_length columns".into(),
            })
        }
    };
    let mut mean = None;
    let mut std = None;
    for line in lines {
        let f: Vec<&str> = line.split(',').collect();
        let key = f
            .first()
            .map(|s| s.trim().to_lowercase())
            .unwrap_or_default();
        let get = |c: usize| f.get(c).and_then(|x| x.trim().parse::<f64>().ok());
        if key == "mean" {
            mean = get(sw).zip(get(sl));
        } else if key == "std" {
            std = get(sw).zip(get(sl));
        }
    }
    match (mean, std) {
        (Some((mw, ml)), Some((sw, sl))) => Ok(([mw, sw], [ml, sl])),
        _ => Err(DataError::Format {
            path: path.display().to_string(),
            line: 0,
            reason: "missing `mean` or `std` row".into(),
        }),
    }
}

/// Import the reference experimental data into `out_dir` (the crate's `data/` folder).
pub fn import_reference(reference: &Path, out_dir: &Path) -> Result<Vec<String>, DataError> {
    let exp = reference.join("experimental");
    let mut written = Vec::new();
    for name in IK_FILES {
        let path = exp.join(name);
        let s = Storage::read(&path).map_err(|e| DataError::Read {
            path: path.display().to_string(),
            reason: e.to_string(),
        })?;
        let out = out_dir.join(name);
        s.write(&out).map_err(|e| DataError::Read {
            path: out.display().to_string(),
            reason: e.to_string(),
        })?;
        written.push(out.display().to_string());
    }
    let mut quantities = BTreeMap::new();
    for q in [
        "joint_angles",
        "joint_velocities",
        "joint_torques",
        "joint_powers",
        "grf",
        "emg",
    ] {
        quantities.insert(
            q.to_string(),
            parse_mean_std(&exp.join(format!("walking_{q}_mean_std.csv")))?,
        );
    }
    // Trunk sway of the same trials (mean ± SD series, deg).
    quantities.insert(
        "trunk_sway".to_string(),
        parse_mean_std(&exp.join("walking_trunk_sway.csv"))?,
    );
    // Affected-side ankle torque of six transtibial amputees (Quesada et al. 2016).
    let mut prosthesis = BTreeMap::new();
    prosthesis.insert(
        "ankle_torque".to_string(),
        parse_subjects(
            &exp.join("quesada2016_prosthesis_ankle_torque.csv"),
            "ankle_torque",
        )?,
    );
    quantities.insert("prosthesis".to_string(), prosthesis);
    let (step_width, stride_length) =
        parse_step_stride(&exp.join("walking_step_width_stride_length.csv"))?;
    let reference = WalkingReference {
        quantities,
        step_width,
        stride_length,
    };
    let out = out_dir.join("experimental_walking.json");
    let json = serde_json::to_string(&reference).expect("serialisable");
    write_atomic(&out, json.as_bytes()).map_err(|e| DataError::Read {
        path: out.display().to_string(),
        reason: e.to_string(),
    })?;
    written.push(out.display().to_string());
    Ok(written)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn subject_columns_give_mean_and_sample_sd() {
        let dir = std::env::temp_dir().join(format!("stride-subjects-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let p = dir.join("t.csv");
        std::fs::write(
            &p,
            "sample,gait_cycle_pct,subject1_ankle_torque_Nm_per_kg,subject2_ankle_torque_Nm_per_kg,subject3_ankle_torque_Nm_per_kg\n\
             1,0,1,2,3\n2,1,-1,-1,-1\n",
        )
        .unwrap();
        let c = parse_subjects(&p, "ankle_torque").unwrap();
        assert_eq!(c.unit, "Nm_per_kg");
        assert_eq!(c.mean, vec![2.0, -1.0]);
        assert_eq!(c.std, vec![1.0, 0.0]);
        assert!(parse_subjects(&p, "knee_torque").is_err());
        std::fs::write(&p, "sample,subject1_ankle_torque_Nm\n1,x\n").unwrap();
        let e = parse_subjects(&p, "ankle_torque").unwrap_err().to_string();
        assert!(e.contains("line 2"), "{e}");
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
