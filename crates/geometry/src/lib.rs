//! stride-geometry: muscle–tendon path geometry from OpenSim path points and its
//! polynomial approximation (FORMULATION section 4).
//!
//! - [`basis`]: the monomial basis and its coefficient order (4.2).
//! - [`couplers`]: coupled coordinates computed from their independent coordinates.
//! - [`fit`]: stacked length + moment-arm least squares and order selection (4.4).
//! - [`function`], [`kinematics`], [`path`], [`wrap`]: path geometry (length, moment
//!   arms, lengthening speed) with OpenSim's path points and wrapping over cylinders,
//!   spheres, ellipsoids and tori, generic over the scalar.
//! - [`samples`]: fitting poses from a motion file or drawn at random.
//! - [`model_fit`]: fitting every muscle of a model and the accuracy report.
//! - [`geometry_file`]: the fitted-geometry file and its per-model-content cache.

mod atan;
pub mod basis;
pub mod couplers;
mod cylinder_spiral;
mod ellipsoid_closest;
pub mod error;
pub mod fit;
pub mod function;
pub mod geometry_check;
pub mod geometry_file;
pub mod kinematics;
pub mod lsq;
pub mod model_fit;
pub mod path;
pub mod poly;
mod ring_closest;
pub mod samples;
mod vec3;
pub mod wrap;
mod wrap_ellipsoid;
mod wrap_shapes;
mod wrap_torus;

pub use basis::{basis_size, MonomialBasis};
pub use couplers::Couplers;
pub use error::GeometryError;
pub use fit::{fit_order, fit_polynomial, FitOptions, MuscleSamples, PolynomialFit};
pub use geometry_file::{cached_geometry, content_hash, FitSettings, GeometryFile, GeometrySource};
pub use model_fit::{
    fit_ligaments, fit_model, sample_geometry, FitModelOptions, FitReport, MuscleFitRow,
    LIGAMENT_TOLERANCE,
};
pub use path::{lengthening_speed, MusclePaths, PathGeometry};
pub use poly::{polynomial_length, polynomial_moment_arm};
pub use samples::{poses_from_motion, random_poses, MissingCoordinates, PoseSamples};
