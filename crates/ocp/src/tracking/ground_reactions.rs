//! The measured ground reactions of a trial: per foot the force, its centre of pressure
//! and the free torque, sampled at any time as the force and its moment about the ground
//! origin.

use super::series::interp;

/// Ground reaction samples of both feet.
#[derive(Clone, Debug)]
pub struct GroundReactions {
    /// Sample times [s] (at least two, increasing).
    time: Vec<f64>,
    /// Per sample: right then left foot, each force x y z [N], centre of pressure x y z
    /// [m], free torque x y z [N m], in ground.
    rows: Vec<[f64; 18]>,
}

impl GroundReactions {
    /// The samples at `time` [s] of the 18 columns `columns` (right then left foot, each
    /// force x y z [N], centre of pressure x y z [m], free torque x y z [N m]).
    pub fn new(time: Vec<f64>, columns: &[Vec<f64>; 18]) -> Self {
        let rows = (0..time.len())
            .map(|s| std::array::from_fn(|i| columns[i][s]))
            .collect();
        Self { time, rows }
    }

    /// Force [N] and its moment about the ground origin [N m] (force at the centre of
    /// pressure plus the free torque), right x y z then left x y z, at time `t` [s], with
    /// the centres of pressure moved back by `tx_offset` [m] along ground x.
    pub fn at(&self, t: f64, tx_offset: f64) -> ([f64; 6], [f64; 6]) {
        let g = interp::<18>(&self.time, t, |s| self.rows[s]);
        let (mut grf, mut grt) = ([0.0; 6], [0.0; 6]);
        for foot in 0..2 {
            let c = &g[9 * foot..9 * foot + 9];
            let f = [c[0], c[1], c[2]];
            let p = [c[3] - tx_offset, c[4], c[5]];
            let m = [
                p[1] * f[2] - p[2] * f[1] + c[6],
                p[2] * f[0] - p[0] * f[2] + c[7],
                p[0] * f[1] - p[1] * f[0] + c[8],
            ];
            grf[3 * foot..3 * foot + 3].copy_from_slice(&f);
            grt[3 * foot..3 * foot + 3].copy_from_slice(&m);
        }
        (grf, grt)
    }
}
