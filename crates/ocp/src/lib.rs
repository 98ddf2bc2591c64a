//! stride-ocp: Optimal control problems of gait: goals, Radau transcription, initial guesses, trajectories.
