//! Solver backends other than stride's own interior-point method (ripopt, system IPOPT).
