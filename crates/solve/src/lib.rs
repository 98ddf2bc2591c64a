//! stride-solve: nonlinear programs and the solvers that solve them.
//!
//! - [`nlp`]: the nonlinear-program abstraction (bounds, functions, sparse derivatives).
//! - [`solver`]: the `Solver` trait, its options and its result type.
//! - [`observer`]: what a solve reports while it runs (iteration records, diagnostics).
//! - [`ipm`]: stride's own pure-Rust interior-point method.
//! - [`problems`]: test problems with known solutions.
//! - [`backends`]: other solver backends (ripopt, system IPOPT behind the `ipopt` feature).
//! - [`pivots`]: the inertia of a factorised symmetric matrix.
//! - [`bench`]: solver benchmarks on the pendulum-chain collocation problem (markdown tables).

pub mod backends;
pub mod bench;
pub mod ipm;
pub mod nlp;
pub mod observer;
pub mod pivots;
pub mod problems;
pub mod solver;
