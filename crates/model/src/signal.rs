//! Signal processing of experimental data: zero-lag Butterworth filtering and not-a-knot cubic splines.
