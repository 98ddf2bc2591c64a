//! stride-model: musculoskeletal models.
//!
//! - [`model`]: the immutable model description (bodies, joints, coordinates, muscles,
//!   contact spheres, actuators, passive elements).

pub mod model;

pub use model::*;
