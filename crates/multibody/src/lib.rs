//! stride-multibody: Multibody dynamics for stride: kinematics, inverse dynamics and smooth foot-ground contact, generic over the scalar.
//!
//! Pinocchio-style split: the immutable [`stride_model::Model`] plus a preallocated
//! workspace [`Data`] reused across calls. Everything is expressed in the ground frame.
//!
//! - [`spatial`]: 3-vectors and rotation matrices generic over the scalar;
//! - [`data`]: the workspace (compiled joint functions, per-body kinematics, loads);
//! - [`kinematics`]: forward kinematics (OpenSim `CustomJoint` semantics), points, COM;
//! - [`dynamics`]: recursive Newton–Euler inverse dynamics with external loads;
//! - [`elements`]: force laws of ligaments, coordinate limit forces and generalised springs;
//! - [`couplers`]: coupled coordinates eliminated by substitution;
//! - [`contact`]: smooth Hunt–Crossley sphere–plane contact (FORMULATION 5.2);
//! - [`skeleton`]: the per-node entry of the optimal control problem.

#![warn(missing_docs)]

pub mod contact;
pub mod couplers;
pub mod data;
pub mod dynamics;
pub mod elements;
pub mod error;
pub mod kinematics;
pub mod skeleton;
pub mod spatial;

pub use contact::{
    contact_forces, contact_forces_with_geometry, sphere_force, SphereForce, SphereGeometry,
};
pub use data::{ContactGroups, Data};
pub use dynamics::{accelerations, inverse_dynamics, inverse_dynamics_from_kinematics};
pub use error::MultibodyError;
pub use kinematics::{
    center_of_mass, forward_kinematics, kinetic_energy, point_position, point_velocity,
    potential_energy,
};
pub use skeleton::{
    center_of_pressure, skeleton_dynamics, skeleton_dynamics_with_geometry, SkeletonOutput,
};
