//! stride-plot: small scientific line figures.
//!
//! A [`Figure`] is a grid of [`Panel`]s; each panel has a title, axis labels, automatic
//! "nice" ticks (or fixed limits), line [`Series`], shaded [`Band`]s drawn under the lines,
//! an optional legend and an optional horizontal zero line.
//!
//! - [`Figure::to_svg`] writes the SVG text directly;
//! - [`Figure::to_png`] renders that SVG with `resvg` (pure Rust) using DejaVu Sans embedded in
//!   the binary, so the output does not depend on the fonts installed on the machine.
//!
//! Nothing is written to disk here: callers get a `String` or bytes and write them
//! atomically themselves.

pub mod color;
pub mod error;
pub mod figure;
pub mod layout;
pub mod png;
pub mod svg;
pub mod ticks;

pub use color::Color;
pub use error::PlotError;
pub use figure::{Axis, Band, Figure, LegendEntry, LegendKey, Panel, Series};
pub use layout::PlotArea;
pub use ticks::{format_tick, nice_ticks, Ticks};
