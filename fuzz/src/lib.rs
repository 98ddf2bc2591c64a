//! stride-fuzz: coverage-guided fuzzing of stride's input readers on the stable toolchain.
//!
//! - [`targets`]: what is fuzzed (the `.osim` reader, the `.mot`/`.sto` reader, the study
//!   file parser) and the properties checked beyond "does not crash".
//! - [`coverage`]: SanitizerCoverage edge-guard callbacks filling a hit map (the fuzz build
//!   instruments the reader crates through `rustc-sancov.sh`; without it the map stays
//!   empty and fuzzing is blind random mutation).
//! - [`mutate`]: byte-level mutations, dictionary tokens and splices.
//! - [`engine`]: the fuzzing loop (corpus, novelty, crash files, statistics).

pub mod coverage;
pub mod engine;
pub mod mutate;
pub mod targets;
