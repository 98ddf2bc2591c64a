//! Edge coverage from LLVM SanitizerCoverage (`-sanitizer-coverage-trace-pc-guard`): every
//! instrumented edge has a guard; its callback counts hits in a shared map that the fuzzing
//! loop reads after each input.

use std::sync::atomic::{AtomicU32, AtomicU8, Ordering::Relaxed};

/// Size of the hit map (edges beyond it share slots).
const MAP: usize = 1 << 20;

static HITS: [AtomicU8; MAP] = [const { AtomicU8::new(0) }; MAP];
static GUARDS: AtomicU32 = AtomicU32::new(0);

/// Number the guards of one instrumented module (called by its constructor).
///
/// # Safety
/// Called by the SanitizerCoverage runtime protocol with a valid `[start, stop)` range.
#[no_mangle]
pub unsafe extern "C" fn __sanitizer_cov_trace_pc_guard_init(start: *mut u32, stop: *mut u32) {
    if start == stop || unsafe { *start } != 0 {
        return;
    }
    let mut p = start;
    while p < stop {
        unsafe {
            *p = GUARDS.fetch_add(1, Relaxed) + 1;
            p = p.add(1);
        }
    }
}

/// Count one pass over an instrumented edge.
///
/// # Safety
/// Called by instrumented code with a guard numbered by the function above.
#[no_mangle]
pub unsafe extern "C" fn __sanitizer_cov_trace_pc_guard(guard: *mut u32) {
    let slot = &HITS[unsafe { *guard } as usize % MAP];
    let v = slot.load(Relaxed);
    slot.store(v.saturating_add(1), Relaxed);
}

/// Number of instrumented edges (0 in an uninstrumented build).
pub fn edges() -> usize {
    (GUARDS.load(Relaxed) as usize + 1).min(MAP)
}

/// Clear the hit counts before running an input.
pub fn reset() {
    for h in &HITS[..edges()] {
        h.store(0, Relaxed);
    }
}

/// Hit-count bucket (AFL style: 1, 2, 3, 4–7, 8–15, 16–31, 32–127, 128+) as one bit.
fn bucket(n: u8) -> u8 {
    match n {
        0 => 0,
        1 => 1,
        2 => 2,
        3 => 4,
        4..=7 => 8,
        8..=15 => 16,
        16..=31 => 32,
        32..=127 => 64,
        _ => 128,
    }
}

/// Merge the hits of the last input into `seen` (one bucket bitmask per edge); returns how
/// many (edge, bucket) pairs are new.
pub fn merge_new(seen: &mut Vec<u8>) -> usize {
    let n = edges();
    if seen.len() < n {
        seen.resize(n, 0);
    }
    let mut new = 0;
    for (s, h) in seen.iter_mut().zip(&HITS[..n]) {
        let b = bucket(h.load(Relaxed));
        if b & !*s != 0 {
            *s |= b;
            new += 1;
        }
    }
    new
}

/// Merge the edges hit by the last input into `seen` (hit counts ignored); returns how
/// many edges are new.
pub fn merge_new_edges(seen: &mut Vec<u8>) -> usize {
    let n = edges();
    if seen.len() < n {
        seen.resize(n, 0);
    }
    let mut new = 0;
    for (s, h) in seen.iter_mut().zip(&HITS[..n]) {
        if *s == 0 && h.load(Relaxed) != 0 {
            *s = 1;
            new += 1;
        }
    }
    new
}

/// Number of edges ever hit according to `seen`.
pub fn covered(seen: &[u8]) -> usize {
    seen.iter().filter(|&&s| s != 0).count()
}
