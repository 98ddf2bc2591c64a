//! OpenSim storage files (.mot/.sto): reading and writing.
