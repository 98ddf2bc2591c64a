//! stride-geometry: muscle–tendon path geometry from OpenSim path points and its
//! polynomial approximation (FORMULATION section 4).
//!
//! - [`basis`]: the monomial basis and its coefficient order (4.2).
//! - [`fit`]: stacked length + moment-arm least squares and order selection (4.4).
//! - [`function`], [`kinematics`], [`path`]: path-point geometry (length, moment arms,
//!   lengthening speed) generic over the scalar.
//! - [`samples`]: fitting poses from a motion file or drawn at random.
//! - [`model_fit`]: fitting every muscle of a model and the accuracy report.

pub mod basis;
pub mod error;
pub mod fit;
pub mod function;
pub mod kinematics;
pub mod lsq;
pub mod model_fit;
pub mod path;
pub mod samples;

pub use basis::{basis_size, MonomialBasis};
pub use error::GeometryError;
pub use fit::{fit_order, fit_polynomial, FitOptions, MuscleSamples, PolynomialFit};
pub use model_fit::{fit_model, sample_geometry, FitModelOptions, FitReport, MuscleFitRow};
pub use path::{lengthening_speed, MusclePaths, PathGeometry};
pub use samples::{poses_from_motion, random_poses, PoseSamples};
