//! stride's own pure-Rust primal-dual interior-point method.
