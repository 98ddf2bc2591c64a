//! stride-view: one self-contained HTML page (no server, nothing fetched) that animates a
//! predicted gait in 3D — bodies, contact spheres, muscle paths coloured by activation,
//! ground reaction forces — with joint-angle and force curves, for one result folder or
//! every case of a study folder.
//!
//! - [`folder`]: reading result and study folders (the one place that knows their files);
//! - [`frames`]: the motion resampled to uniform frames over the gait cycle;
//! - [`scene`]: the model's solids and, per frame, body poses and muscle path points in
//!   ground (computed with `stride_geometry`'s kinematics and path points);
//! - [`encode`]: compact array encodings for the page (quantised integers in base64);
//! - [`page`]: the HTML page (three.js, the viewer script and the data embedded).
//!
//! The library does not print; `stride view` (CLI) writes the page.

pub mod encode;
pub mod error;
pub mod folder;
pub mod frames;
pub mod page;
pub mod scene;

pub use error::ViewError;
pub use page::{result_page, study_page, ViewOptions};
