//! Model-only bounds of a coordinate that no experimental data cover (PREDSIM.md §7.4):
//! PredSim's default coordinate-bounds table by name (left and right alike), else the
//! coordinate's range in the model file for the position, ±10 ranges per second for the
//! speed and ±155 ranges per second² for the acceleration.

use crate::gait::side_of;
use crate::range::Range;

/// One row of PredSim's `Default_Coordinate_Bounds.csv`: base name, then (lower, upper)
/// of position [rad or m], speed [rad s⁻¹ or m s⁻¹] and acceleration [rad s⁻² or m s⁻²].
type Row = (&'static str, [f64; 6]);

/// PredSim's default coordinate bounds (commit 04a892a; PREDSIM.md §7.4).
const DEFAULT_BOUNDS: [Row; 20] = [
    (
        "pelvis_tilt",
        [
            -0.349065850398866,
            0.0672853815966567,
            -1.17661021014571,
            1.23301647140312,
            -18.9606634063809,
            19.7868467414337,
        ],
    ),
    (
        "pelvis_list",
        [
            -0.416176698891006,
            0.416176698891006,
            -6.20777751508605,
            6.20777751508605,
            -92.0322640837515,
            92.0322640837515,
        ],
    ),
    (
        "pelvis_rotation",
        [
            -0.259769033215136,
            0.259769033215136,
            -2.99626777308132,
            2.99626777308132,
            -61.5491912530299,
            61.5491912530299,
        ],
    ),
    (
        "pelvis_tx",
        [
            0.0,
            4.0,
            0.0277777478510077,
            2.73042182851602,
            -61.3654839686098,
            51.2810856526254,
        ],
    ),
    (
        "pelvis_ty",
        [
            0.469888297089066,
            1.12773191301376,
            -1.36140613050148,
            1.37488356845919,
            -16.8717040926935,
            16.6025220893694,
        ],
    ),
    (
        "pelvis_tz",
        [
            -0.1,
            0.1,
            -0.482392334446795,
            0.478769572481235,
            -5.91181614451626,
            5.53552928730173,
        ],
    ),
    (
        "hip_flexion",
        [
            -1.91811668705238,
            2.11902321356129,
            -20.602433630207,
            21.8538877946295,
            -192.948963697409,
            201.444953217385,
        ],
    ),
    (
        "hip_adduction",
        [
            -0.638811890374141,
            0.718717426177655,
            -10.218650823043,
            10.2485691751461,
            -141.245441049244,
            145.547403290364,
        ],
    ),
    (
        "hip_rotation",
        [
            -0.507448251989306,
            0.471590337211414,
            -6.66936686209078,
            6.95586801186067,
            -135.270786246774,
            136.868089242219,
        ],
    ),
    (
        "knee_angle",
        [
            -3.05478772880409,
            1.69794152173642,
            -38.8846957065914,
            39.5051541565237,
            -435.367703797436,
            441.781759234749,
        ],
    ),
    (
        "ankle_angle",
        [
            -1.41741948253318,
            1.35480884656812,
            -25.9805180688803,
            24.1560084145248,
            -396.4473478646,
            430.342899579853,
        ],
    ),
    (
        "subtalar_angle",
        [
            -0.820228847927354,
            0.904224761190195,
            -14.8908126981949,
            14.6701996427156,
            -231.206373976965,
            232.898661432864,
        ],
    ),
    ("mtp_angle", [-0.5, 1.05, -13.0, 13.0, -500.0, 500.0]),
    (
        "lumbar_extension",
        [
            -0.279630627332122,
            0.0662674076360778,
            -3.21683161481279,
            3.47245815941314,
            -52.8353944368335,
            50.1717554529689,
        ],
    ),
    (
        "lumbar_bending",
        [
            -0.530838053030837,
            0.530838053030837,
            -7.72383789474667,
            7.72383789474667,
            -109.744952455678,
            109.744952455678,
        ],
    ),
    (
        "lumbar_rotation",
        [
            -0.665432069883924,
            0.665432069883924,
            -3.60092697535602,
            3.60092697535602,
            -38.7491413742998,
            38.7491413742998,
        ],
    ),
    (
        "arm_flex",
        [
            -0.605174316256392,
            0.550257358709403,
            -5.40369812464309,
            5.23819521163105,
            -65.5162052654476,
            66.7384551990015,
        ],
    ),
    (
        "arm_add",
        [
            -0.743894308431628,
            -0.23474166819783,
            -4.09015441771715,
            4.17281078290233,
            -39.4371938024175,
            39.2956913610813,
        ],
    ),
    (
        "arm_rot",
        [
            -0.229648726171374,
            0.338379488110166,
            -5.57904842207819,
            6.04191841348758,
            -114.880165221124,
            114.025121975772,
        ],
    ),
    (
        "elbow_flex",
        [
            0.0,
            2.0063530656144,
            -12.3175244287771,
            12.9033775787822,
            -93.3112613500639,
            94.2769275856337,
        ],
    ),
];

/// Speed bound of a coordinate outside the table, in ranges per second.
pub const SPEED_RANGES: f64 = 10.0;
/// Acceleration bound of a coordinate outside the table, in ranges per second².
pub const ACCELERATION_RANGES: f64 = 155.0;

/// Position, speed and acceleration bounds of coordinate `name` whose model range is
/// `range` [rad or m]: PredSim's table row of its base name (`_l`/`_r` removed), else
/// the model range, ±10 and ±155 times its width.
pub fn model_only(name: &str, range: [f64; 2]) -> [Range; 3] {
    let (base, _) = side_of(name);
    let r = |lo: f64, hi: f64| Range { lo, hi };
    if let Some((_, b)) = DEFAULT_BOUNDS.iter().find(|(n, _)| *n == base) {
        return [r(b[0], b[1]), r(b[2], b[3]), r(b[4], b[5])];
    }
    let w = range[1] - range[0];
    [
        r(range[0], range[1]),
        r(-SPEED_RANGES * w, SPEED_RANGES * w),
        r(-ACCELERATION_RANGES * w, ACCELERATION_RANGES * w),
    ]
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn toes_use_the_table_and_unknown_coordinates_their_model_range() {
        let [q, v, a] = model_only("mtp_angle_l", [-1.0, 1.0]);
        assert_eq!((q.lo, q.hi, v.hi, a.lo), (-0.5, 1.05, 13.0, -500.0));
        let [q, v, a] = model_only("mtj_angle_r", [-0.5, 0.3]);
        assert_eq!((q.lo, q.hi), (-0.5, 0.3));
        assert!((v.hi - 8.0).abs() < 1e-12 && (a.lo + 124.0).abs() < 1e-12);
    }
}
