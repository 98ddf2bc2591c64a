//! The Solver trait, its options and its result type.
