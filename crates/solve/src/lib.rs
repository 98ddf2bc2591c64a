//! stride-solve: Nonlinear-program abstraction and interior-point solver backends for stride.
