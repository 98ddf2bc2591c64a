//! stride-muscle: muscle models for stride, generic over the scalar type
//! ([`stride_ad::Scalar`]): De Groote 2016 Hill-type contraction dynamics ([`hill`],
//! [`curves`]), Raasch activation dynamics and arm actuators ([`activation`]), passive joint
//! torques ([`passive`]), ligament force laws ([`ligament`]), metabolic energy models ([`metabolic`]) and polynomial
//! muscle–tendon geometry ([`polynomial`]). Equations follow `FORMULATION.md` sections 2–4, 6, 7.

pub mod activation;
pub mod curves;
pub mod error;
pub mod hill;
pub mod ligament;
pub mod metabolic;
pub mod passive;
pub mod polynomial;

pub use error::MuscleError;
pub use hill::{hill_equilibrium, hill_params_from_model, HillOutput, HillParams};
pub use metabolic::{basal_metabolic_rate, MetabolicModel, MetabolicRate};
pub use polynomial::{MusclePaths, PathPolynomialEval, PathWorkspace};
