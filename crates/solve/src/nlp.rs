//! The nonlinear-program abstraction.
