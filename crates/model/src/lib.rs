//! stride-model: musculoskeletal models.
//!
//! - [`model`]: the immutable model description (bodies, joints, coordinates, muscles,
//!   contact spheres, actuators, passive elements, polynomial geometry).
//! - [`osim`]: OpenSim `.osim` import.
//! - [`storage`]: OpenSim `.mot`/`.sto` files, bounded reads.
//! - [`signal`]: filtering and splines for experimental data.
//! - [`function`]: coordinate functions (linear, splines, ...) generic over the scalar.
//! - [`expression`]: arithmetic expressions in OpenSim's syntax, compiled once, generic over
//!   the scalar.
//! - [`reference`]: loaders of the paper's reference tables.
//! - [`default_model`]: the built-in model.
//! - [`model_settings`]: a model's own settings file (`<model>.toml`).
//! - [`inspect`]: human-readable tables of a model.
//! - [`shipped`]: the models shipped with stride, usable by name.

pub mod contact_check;
pub mod default_model;
pub mod expression;
pub mod external_loads;
pub mod function;
pub mod input_file;
pub mod inspect;
pub mod model;
pub mod model_settings;
pub mod osim;
pub mod reference;
pub mod shipped;
pub mod signal;
pub mod storage;

pub use model::*;
