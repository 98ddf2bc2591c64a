//! The gait cycle of a result folder resampled to uniformly spaced frames: coordinates in
//! model units, muscle activations and per-foot ground reaction forces, linearly
//! interpolated in time between the rows of the result files.

use crate::error::ViewError;
use crate::folder::{self, ResultFiles};
use stride_model::storage::Storage;
use stride_model::{Model, MotionType};

/// Ground reaction force of one foot at one frame: force [N] and application point [m],
/// both in ground.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct FootForce {
    /// Force on the foot, in ground [N].
    pub force: [f64; 3],
    /// Point of application (centre of pressure), in ground [m].
    pub point: [f64; 3],
}

/// The gait cycle at uniformly spaced frames.
#[derive(Clone, Debug)]
pub struct Frames {
    /// Time of each frame [s], from the first to the last row of the motion.
    pub time: Vec<f64>,
    /// Coordinates of each frame in model order [rad or m].
    pub q: Vec<Vec<f64>>,
    /// Activation (0–1) of each model muscle at each frame; `None` for a muscle without an
    /// activation column.
    pub activation: Vec<Vec<Option<f64>>>,
    /// Right and left foot forces at each frame, when the folder has a force file.
    pub grf: Option<Vec<[FootForce; 2]>>,
}

/// Resample the motion (and forces) of `files` to `n_frames` uniform frames (at least 2,
/// at most the number of motion rows) for `model`; every model coordinate must have a
/// column.
pub fn resample(model: &Model, files: &ResultFiles, n_frames: usize) -> Result<Frames, ViewError> {
    let path = files.motion_path();
    let motion = &files.motion;
    let times = checked_time(motion, &path)?;
    let n = n_frames.min(times.len()).max(2);
    let (t0, t1) = (times[0], times[times.len() - 1]);
    let time: Vec<f64> = (0..n)
        .map(|i| t0 + (t1 - t0) * i as f64 / (n - 1) as f64)
        .collect();
    let degrees = folder::motion_in_degrees(motion);
    let mut coord_cols = Vec::with_capacity(model.coordinates.len());
    for c in &model.coordinates {
        let col = folder::coordinate_column(motion, &c.name).ok_or_else(|| {
            ViewError::content(
                &path,
                format!("no column for coordinate `{}` of the model", c.name),
            )
        })?;
        let to_model = if degrees && c.motion_type == MotionType::Rotational {
            std::f64::consts::PI / 180.0
        } else {
            1.0
        };
        coord_cols.push((col, to_model));
    }
    let act_cols: Vec<Option<usize>> = model
        .muscles
        .iter()
        .map(|m| folder::activation_column(motion, &m.name))
        .collect();
    let mut q = Vec::with_capacity(n);
    let mut activation = Vec::with_capacity(n);
    for &t in &time {
        let (row, w) = bracket(&times, t);
        let at = |col: usize| lerp(motion, row, w, col);
        q.push(coord_cols.iter().map(|&(c, s)| at(c) * s).collect());
        activation.push(act_cols.iter().map(|c| c.map(at)).collect());
    }
    let grf = match &files.grf {
        Some(g) => Some(resample_grf(g, &files.grf_path(), &time)?),
        None => None,
    };
    Ok(Frames {
        time,
        q,
        activation,
        grf,
    })
}

/// Forces of both feet at times `time` from a force file.
fn resample_grf(
    grf: &Storage,
    path: &std::path::Path,
    time: &[f64],
) -> Result<Vec<[FootForce; 2]>, ViewError> {
    let times = checked_time(grf, path)?;
    let cols = [
        folder::grf_columns(grf, path, "r")?,
        folder::grf_columns(grf, path, "l")?,
    ];
    Ok(time
        .iter()
        .map(|&t| {
            let (row, w) = bracket(&times, t);
            cols.map(|c| {
                let v = |k: usize| lerp(grf, row, w, c[k]);
                FootForce {
                    force: [v(0), v(1), v(2)],
                    point: [v(3), v(4), v(5)],
                }
            })
        })
        .collect())
}

/// The `time` column of a storage, checked non-decreasing with at least two rows spanning
/// a positive duration.
fn checked_time(s: &Storage, path: &std::path::Path) -> Result<Vec<f64>, ViewError> {
    let col = s
        .column_index("time")
        .ok_or_else(|| ViewError::content(path, "no `time` column"))?;
    let t: Vec<f64> = s.rows.iter().map(|r| r[col]).collect();
    if t.len() < 2 {
        return Err(ViewError::content(
            path,
            format!("{} rows: need at least 2", t.len()),
        ));
    }
    if let Some(i) = t.iter().position(|x| !x.is_finite()) {
        return Err(ViewError::content(
            path,
            format!("time is not a finite number at data row {}", i + 1),
        ));
    }
    if let Some(i) = (1..t.len()).find(|&i| t[i] < t[i - 1]) {
        return Err(ViewError::content(
            path,
            format!(
                "time decreases at data row {} ({} after {})",
                i + 1,
                t[i],
                t[i - 1]
            ),
        ));
    }
    if t[t.len() - 1] <= t[0] {
        return Err(ViewError::content(path, "time does not advance"));
    }
    Ok(t)
}

/// Row `i` and weight `w` such that time `t` lies at `(1 − w) t_i + w t_{i+1}` (clamped to
/// the first and last rows).
fn bracket(times: &[f64], t: f64) -> (usize, f64) {
    let last = times.len() - 1;
    let i = times.partition_point(|&x| x <= t).clamp(1, last) - 1;
    let span = times[i + 1] - times[i];
    let w = if span > 0.0 {
        ((t - times[i]) / span).clamp(0.0, 1.0)
    } else {
        0.0
    };
    (i, w)
}

/// Column `col` of `s` interpolated between rows `row` and `row + 1` with weight `w`.
fn lerp(s: &Storage, row: usize, w: f64, col: usize) -> f64 {
    let a = s.rows[row][col];
    if w == 0.0 {
        return a;
    }
    a + (s.rows[row + 1][col] - a) * w
}

#[cfg(test)]
mod tests {
    use super::bracket;

    #[test]
    fn bracket_finds_the_interval_and_weight() {
        let t = [0.0, 1.0, 3.0];
        assert_eq!(bracket(&t, 0.0), (0, 0.0));
        assert_eq!(bracket(&t, 0.5), (0, 0.5));
        assert_eq!(bracket(&t, 2.0), (1, 0.5));
        assert_eq!(bracket(&t, 3.0), (1, 1.0));
        assert_eq!(bracket(&t, 9.0), (1, 1.0));
        assert_eq!(bracket(&t, -1.0), (0, 0.0));
    }
}
