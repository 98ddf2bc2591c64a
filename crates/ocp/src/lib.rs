//! stride-ocp: the optimal control problem of gait.
//!
//! - [`settings`]: every option of a prediction (study-file schema), paper defaults.
//! - [`size`]: NLP size and peak memory of a solve, estimated before building it.
//! - [`gait`]: the gait view of a model (coordinate roles, mirror maps).
//! - [`bounds_model`], [`passive_rules`]: bounds and passive torques of a model from the
//!   model alone (PredSim's rules).
//! - [`radau`]: Radau collocation coefficients.
//! - [`layout`]: the NLP variable layout.
//! - [`contact_geometry`]: contact-sphere geometry files (calibrated spheres).
//! - [`adapt`]: settings that make an OpenSim model without foot contact (or with
//!   undriven coordinates) predict walking (`stride model adapt`, decision 0008).
//! - [`standing`]: the standing pelvis height of a model (quasi-random guess).
//! - [`statics`]: static parameters (constant over time) appended to the NLP vector.
//! - [`outcomes`]: outcome measures of a predicted gait cycle.
//! - [`measures`]: trunk sway and stance measures compared between conditions.
//! - [`threads`]: the worker threads of a solve.

pub mod adapt;
pub mod bounds;
pub mod bounds_model;
pub mod contact_geometry;
pub mod data;
pub mod experimental;
pub mod gait;
pub mod guess;
mod jacobian_fill;
pub mod layout;
pub mod ligaments;
mod linear_rows;
pub mod measures;
pub mod model_defaults;
pub mod node;
pub mod outcomes;
pub mod passive_rules;
pub mod problem;
pub mod radau;
pub mod range;
pub mod settings;
pub mod size;
pub mod standing;
pub mod statics;
pub mod tape_node;
pub mod threads;
pub mod tracking;
pub mod tracking_terms;
pub mod trajectory;
pub mod transcription;
