//! Experimental kinematics used for bounds and data-informed initial guesses: an average
//! inverse-kinematics cycle, low-pass filtered (6 Hz, 2nd-order Butterworth, zero lag) and
//! splined (not-a-knot) to obtain positions, speeds and accelerations (FORMULATION 8.7).

use crate::gait::GaitModel;
use stride_model::signal;
use stride_model::storage::Storage;
use stride_model::MotionType;

/// Filtered experimental kinematics in problem coordinate order, SI units (rad, m).
#[derive(Clone, Debug)]
pub struct Kinematics {
    /// Sample times [s].
    pub time: Vec<f64>,
    /// Positions `q[sample][coordinate]` [rad or m].
    pub q: Vec<Vec<f64>>,
    /// Speeds [rad s⁻¹ or m s⁻¹].
    pub v: Vec<Vec<f64>>,
    /// Accelerations [rad s⁻² or m s⁻²].
    pub a: Vec<Vec<f64>>,
    /// Per problem coordinate: whether the source had a column for it (a coordinate
    /// without one is 0 at every sample).
    pub measured: Vec<bool>,
}

/// Why experimental kinematics could not be used.
#[derive(Debug, thiserror::Error)]
pub enum KinematicsError {
    /// A coordinate of the model has no column in the file.
    #[error("{file}: no column for coordinate `{coordinate}`")]
    MissingColumn {
        /// Data source.
        file: String,
        /// Missing coordinate.
        coordinate: String,
    },
    /// Filtering or splining failed.
    #[error("{file}: coordinate `{coordinate}`: {reason}")]
    Signal {
        /// Data source.
        file: String,
        /// Coordinate.
        coordinate: String,
        /// Why.
        reason: String,
    },
    /// Too few samples.
    #[error("{file}: {n} samples; at least 8 are needed for filtering")]
    TooShort {
        /// Data source.
        file: String,
        /// Number of rows.
        n: usize,
    },
}

/// Cut-off of the low-pass filter applied to the experimental kinematics [Hz].
pub const FILTER_CUTOFF_HZ: f64 = 6.0;

impl Kinematics {
    /// Filter and spline the columns of `storage` that match the problem coordinates;
    /// every coordinate needs a column.
    pub fn from_storage(
        storage: &Storage,
        gait: &GaitModel,
        source: &str,
    ) -> Result<Self, KinematicsError> {
        Self::from_storage_filtered(storage, gait, source, FILTER_CUTOFF_HZ)
    }

    /// [`Kinematics::from_storage`] with the low-pass cut-off `cutoff_hz` [Hz]; 0: the
    /// columns are splined as they are (simulated data).
    pub fn from_storage_filtered(
        storage: &Storage,
        gait: &GaitModel,
        source: &str,
        cutoff_hz: f64,
    ) -> Result<Self, KinematicsError> {
        let k = Self::matching_filtered(storage, gait, source, cutoff_hz)?;
        match k.measured.iter().position(|&m| !m) {
            Some(i) => Err(KinematicsError::MissingColumn {
                file: source.into(),
                coordinate: gait.coordinates[i].name.clone(),
            }),
            None => Ok(k),
        }
    }

    /// Filter and spline the columns of `storage` whose names match problem coordinates;
    /// coordinates without a column are 0 (position, speed and acceleration) and marked
    /// in [`Kinematics::measured`].
    pub fn matching(
        storage: &Storage,
        gait: &GaitModel,
        source: &str,
    ) -> Result<Self, KinematicsError> {
        Self::matching_filtered(storage, gait, source, FILTER_CUTOFF_HZ)
    }

    /// [`Kinematics::matching`] with the low-pass cut-off `cutoff_hz` [Hz] (0: none).
    fn matching_filtered(
        storage: &Storage,
        gait: &GaitModel,
        source: &str,
        cutoff_hz: f64,
    ) -> Result<Self, KinematicsError> {
        let time = storage.time();
        let ns = time.len();
        if ns < 8 {
            return Err(KinematicsError::TooShort {
                file: source.into(),
                n: ns,
            });
        }
        let fs = (ns - 1) as f64 / (time[ns - 1] - time[0]);
        let in_degrees = storage.angles_in_degrees();
        let nq = gait.nq();
        let mut q = vec![vec![0.0; nq]; ns];
        let mut v = vec![vec![0.0; nq]; ns];
        let mut a = vec![vec![0.0; nq]; ns];
        let mut measured = vec![false; nq];
        for (i, c) in gait.coordinates.iter().enumerate() {
            let Some(mut col) = storage.coordinate_column(&c.name) else {
                continue;
            };
            measured[i] = true;
            if in_degrees && c.motion_type == MotionType::Rotational {
                col.iter_mut().for_each(|x| *x = x.to_radians());
            }
            let signal_error = |e: signal::SignalError| KinematicsError::Signal {
                file: source.into(),
                coordinate: c.name.clone(),
                reason: e.to_string(),
            };
            let filtered = if cutoff_hz > 0.0 {
                signal::lowpass_filtfilt(&col, cutoff_hz, fs).map_err(signal_error)?
            } else {
                col
            };
            let spline = signal::NotAKnotSpline::new(&time, &filtered).map_err(signal_error)?;
            for s in 0..ns {
                let [p, d1, d2] = spline.eval(time[s]);
                q[s][i] = p;
                v[s][i] = d1;
                a[s][i] = d2;
            }
        }
        Ok(Self {
            time,
            q,
            v,
            a,
            measured,
        })
    }

    /// Number of samples.
    pub fn len(&self) -> usize {
        self.time.len()
    }
    /// Whether there are no samples.
    pub fn is_empty(&self) -> bool {
        self.time.is_empty()
    }

    /// Linear resampling of (q, v, a) at `n` equally spaced times from the first to the last
    /// sample.
    pub fn resample(&self, n: usize) -> Self {
        let t0 = self.time[0];
        let t1 = self.time[self.len() - 1];
        let times: Vec<f64> = (0..n)
            .map(|k| t0 + (t1 - t0) * k as f64 / (n.max(2) - 1) as f64)
            .collect();
        let interp = |data: &Vec<Vec<f64>>| -> Vec<Vec<f64>> {
            times
                .iter()
                .map(|&t| {
                    let s = match self.time.iter().position(|&x| x > t) {
                        Some(0) => 0,
                        Some(p) => p - 1,
                        None => self.len() - 2,
                    }
                    .min(self.len() - 2);
                    let w = (t - self.time[s]) / (self.time[s + 1] - self.time[s]);
                    data[s]
                        .iter()
                        .zip(&data[s + 1])
                        .map(|(a, b)| a + w * (b - a))
                        .collect()
                })
                .collect()
        };
        Self {
            q: interp(&self.q),
            v: interp(&self.v),
            a: interp(&self.a),
            time: times,
            measured: self.measured.clone(),
        }
    }
}
