//! stride-multibody: Multibody dynamics for stride: kinematics, inverse dynamics and smooth foot-ground contact, generic over the scalar.
