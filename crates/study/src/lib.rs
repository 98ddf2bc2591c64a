//! stride-study: Study files, parameter sweeps and result stores for stride.
