//! Loaders for the reference tables of the paper (contact spheres, passive torques, polynomials, metabolic parameters).
