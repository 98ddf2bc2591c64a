//! Bounds and scale factors of the problem variables (FORMULATION 8.7–8.8).
//!
//! Coordinate, speed and acceleration bounds come from experimental kinematics: for each
//! coordinate (left and right pooled), [min − 2 range, max + 2 range] for positions and
//! 3 ranges of margin for speeds and accelerations, then the paper's manual overrides.
//! Coordinates the data do not cover (toes, midtarsal joints, …) get the model-only rule
//! of [`crate::bounds_model`]. With `bounds = "predsim"` ([`CoordinateBounds::predsim`])
//! every coordinate gets that rule. The scale factor of each quantity is
//! max(|lower|, |upper|).

use crate::experimental::Kinematics;
use crate::gait::{side_of, GaitModel};
use crate::range::Range;
use crate::settings::{CycleKind, ProblemSettings};
use stride_model::storage::Storage;

/// Bounds of the coordinate-related variables, in problem coordinate order.
#[derive(Clone, Debug)]
pub struct CoordinateBounds {
    /// Positions [rad or m].
    pub q: Vec<Range>,
    /// Speeds [rad s⁻¹ or m s⁻¹].
    pub v: Vec<Range>,
    /// Accelerations [rad s⁻² or m s⁻²].
    pub a: Vec<Range>,
}

/// A bound setting that names a coordinate the model does not have, or is impossible.
#[derive(Debug, thiserror::Error)]
pub enum BoundsError {
    /// Unknown coordinate name.
    #[error("coordinate_bounds: unknown coordinate `{0}`")]
    UnknownCoordinate(String),
    /// Lower above upper after all overrides.
    #[error("bounds of coordinate `{name}` are empty after overrides: [{lo}, {hi}]")]
    Empty {
        /// Coordinate.
        name: String,
        /// Lower bound.
        lo: f64,
        /// Upper bound.
        hi: f64,
    },
}

/// Pelvis-height bounds of PredSim's rule as factors on the standing pelvis height.
pub const PREDSIM_HEIGHT_FACTORS: [f64; 2] = [0.5, 1.2];

/// Speed above which running is allowed and the bounds are widened [m s⁻¹].
pub const RUNNING_SPEED_THRESHOLD: f64 = 1.33;

impl CoordinateBounds {
    /// Data-driven bounds with the paper's manual overrides and the user's overrides.
    pub fn new(
        gait: &GaitModel,
        data: &Kinematics,
        settings: &ProblemSettings,
    ) -> Result<Self, BoundsError> {
        let nq = gait.nq();
        let pooled = |series: &Vec<Vec<f64>>, i: usize| -> (f64, f64) {
            let mut lo = f64::INFINITY;
            let mut hi = f64::NEG_INFINITY;
            let m = gait.coordinates[i].mirror;
            let cols: &[usize] = if side_of(&gait.coordinates[i].name).1.is_some() {
                &[i, m]
            } else {
                &[i]
            };
            for row in series {
                for &c in cols.iter().filter(|&&c| data.measured[c]) {
                    lo = lo.min(row[c]);
                    hi = hi.max(row[c]);
                }
            }
            (lo, hi)
        };
        let widen = |(lo, hi): (f64, f64), k: f64| Range {
            lo: lo - k * (hi - lo),
            hi: hi + k * (hi - lo),
        };
        let mut q = Vec::with_capacity(nq);
        let mut v = Vec::with_capacity(nq);
        let mut a = Vec::with_capacity(nq);
        let mut raw_q = Vec::with_capacity(nq);
        for i in 0..nq {
            let c = &gait.coordinates[i];
            if !data.measured[i] && !data.measured[c.mirror] {
                let [bq, bv, ba] = crate::bounds_model::model_only(&c.name, c.range);
                raw_q.push((bq.lo, bq.hi));
                q.push(bq);
                v.push(bv);
                a.push(ba);
                continue;
            }
            let pq = pooled(&data.q, i);
            raw_q.push(pq);
            q.push(widen(pq, 2.0));
            v.push(widen(pooled(&data.v, i), 3.0));
            a.push(widen(pooled(&data.a, i), 3.0));
        }
        let mut b = Self { q, v, a };
        b.apply_paper_overrides(gait, &raw_q, settings.speed);
        b.apply_settings(gait, settings)?;
        Ok(b)
    }

    /// PredSim's bounds for every coordinate ([`crate::bounds_model::model_only`]), the
    /// pelvis height within [0.5, 1.2] × `standing_height` [m] (the initial guess's pelvis
    /// height), the forward position within [0, 2] m, then the user's overrides.
    pub fn predsim(
        gait: &GaitModel,
        settings: &ProblemSettings,
        standing_height: f64,
    ) -> Result<Self, BoundsError> {
        let rows = gait
            .coordinates
            .iter()
            .map(|c| crate::bounds_model::model_only(&c.name, c.range));
        let (mut q, mut v, mut a) = (Vec::new(), Vec::new(), Vec::new());
        for [bq, bv, ba] in rows {
            q.push(bq);
            v.push(bv);
            a.push(ba);
        }
        let mut b = Self { q, v, a };
        b.set_forward(gait, settings.speed);
        b.q[gait.vertical_translation] = Range {
            lo: PREDSIM_HEIGHT_FACTORS[0] * standing_height,
            hi: PREDSIM_HEIGHT_FACTORS[1] * standing_height,
        };
        b.apply_settings(gait, settings)?;
        Ok(b)
    }

    /// The user's coordinate bounds of `settings`; an unknown coordinate or an empty range
    /// is an error.
    fn apply_settings(
        &mut self,
        gait: &GaitModel,
        settings: &ProblemSettings,
    ) -> Result<(), BoundsError> {
        let b = self;
        for o in &settings.coordinate_bounds {
            let i = gait
                .index_of(&o.coordinate)
                .ok_or_else(|| BoundsError::UnknownCoordinate(o.coordinate.clone()))?;
            if let Some(lo) = o.lower {
                b.q[i].lo = lo;
            }
            if let Some(hi) = o.upper {
                b.q[i].hi = hi;
            }
        }
        for (i, r) in b.q.iter().enumerate() {
            if r.lo > r.hi {
                return Err(BoundsError::Empty {
                    name: gait.coordinates[i].name.clone(),
                    lo: r.lo,
                    hi: r.hi,
                });
            }
        }
        Ok(())
    }

    /// The manual bounds of the reference implementation (ESM eqs 21–26 and 31–33), applied
    /// to the coordinates of that name when the model has them.
    fn apply_paper_overrides(&mut self, gait: &GaitModel, raw_q: &[(f64, f64)], speed: f64) {
        self.set_forward(gait, speed);
        self.q[gait.vertical_translation] = Range { lo: 0.75, hi: 1.1 };
        let running = speed > RUNNING_SPEED_THRESHOLD;
        for (i, c) in gait.coordinates.iter().enumerate() {
            let (base, _) = side_of(&c.name);
            match base {
                "pelvis_tz" => self.q[i] = Range { lo: -0.1, hi: 0.1 },
                "elbow_flex" => self.q[i].lo = 0.0,
                "arm_add" | "arm_rot" => self.q[i].hi = raw_q[i].1,
                "pelvis_tilt" if running => self.q[i].lo = (-20f64).to_radians(),
                "arm_flex" if running => self.q[i].lo = (-50f64).to_radians(),
                _ => {}
            }
        }
    }

    /// The forward position within [0, 2] m, and above [`RUNNING_SPEED_THRESHOLD`] the
    /// forward speed up to 4 m s⁻¹ (the paper's manual bounds, kept by PredSim's rule).
    fn set_forward(&mut self, gait: &GaitModel, speed: f64) {
        let tx = gait.forward_translation;
        self.q[tx] = Range { lo: 0.0, hi: 2.0 };
        if speed > RUNNING_SPEED_THRESHOLD {
            self.v[tx].hi = 4.0;
        }
    }
}

/// Experimental kinematics that define the bounds of a problem with `settings`: the
/// walking half cycle, or the full cycle for a full-cycle problem.
pub fn bounds_data(settings: &ProblemSettings) -> Storage {
    match settings.cycle {
        CycleKind::HalfSymmetric => crate::data::walking_half_cycle(),
        CycleKind::FullPeriodic => crate::data::walking_full_cycle(),
    }
}
