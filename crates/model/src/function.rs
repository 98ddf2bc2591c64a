//! Evaluation of OpenSim coordinate functions generic over the scalar.
