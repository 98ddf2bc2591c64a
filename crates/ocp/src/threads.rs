//! The worker threads of a solve.

/// Runs `f` (a solve) with `threads` worker threads for the node-function evaluations (a
/// rayon pool of that size; 0: rayon's global pool, one thread per core). The error names
/// the pool that could not be built.
pub fn with_threads<R: Send>(threads: usize, f: impl FnOnce() -> R + Send) -> Result<R, String> {
    if threads == 0 {
        return Ok(f());
    }
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .map_err(|e| format!("thread pool of {threads} threads: {e}"))?;
    Ok(pool.install(f))
}

#[cfg(test)]
mod tests {
    use super::with_threads;

    #[test]
    fn a_solve_runs_with_the_threads_asked_for() {
        for n in [1, 3] {
            let seen = with_threads(n, rayon::current_num_threads).unwrap();
            assert_eq!(seen, n);
        }
        // 0: the global pool, one thread per core
        let global = rayon::current_num_threads();
        assert_eq!(with_threads(0, rayon::current_num_threads).unwrap(), global);
    }
}
