//! stride-geometry: Muscle-tendon path geometry from OpenSim path points and its polynomial approximation for stride.
