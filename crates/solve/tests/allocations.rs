//! Heap allocations of the interior point's iterations, counted by a global allocator: once
//! the workspace is built and the first iterations have sized the buffers that grow, an
//! iteration of an exact-Hessian or limited-memory solve allocates nothing.

use std::alloc::{GlobalAlloc, Layout, System};
use std::ops::ControlFlow;
use std::sync::atomic::{AtomicUsize, Ordering};

use stride_solve::ipm::InteriorPoint;
use stride_solve::problems::PendulumChain;
use stride_solve::solver::{HessianMode, IterationRecord, MuStrategy, Solver, SolverOptions};

/// The system allocator, counting allocations and reallocations.
struct Counting;

static ALLOCATIONS: AtomicUsize = AtomicUsize::new(0);

unsafe impl GlobalAlloc for Counting {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        ALLOCATIONS.fetch_add(1, Ordering::Relaxed);
        System.alloc(layout)
    }
    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        System.dealloc(ptr, layout)
    }
    unsafe fn realloc(&self, ptr: *mut u8, layout: Layout, new_size: usize) -> *mut u8 {
        ALLOCATIONS.fetch_add(1, Ordering::Relaxed);
        System.realloc(ptr, layout, new_size)
    }
}

#[global_allocator]
static GLOBAL: Counting = Counting;

/// Allocations between consecutive iteration records of a solve with `hessian` (entry k:
/// those from record k − 1 to record k), and the iteration where a hybrid solve switched to
/// the exact Hessian.
fn allocations_per_iteration(hessian: HessianMode) -> (Vec<usize>, Option<usize>) {
    let o = SolverOptions {
        hessian,
        mu_strategy: MuStrategy::Adaptive,
        tol: 1e-8,
        ..SolverOptions::default()
    };
    let p = PendulumChain::new(3, 40);
    let mut counts = Vec::with_capacity(10_000);
    let mut last = 0;
    let r = InteriorPoint::new()
        .solve(&p, &o, &mut |_: &IterationRecord| {
            let now = ALLOCATIONS.load(Ordering::Relaxed);
            counts.push(now - last);
            last = now;
            ControlFlow::Continue(())
        })
        .unwrap();
    assert!(r.status.is_success(), "{:?}", r.status);
    (counts, r.exact_hessian_from)
}

#[test]
fn iterations_do_not_allocate_once_the_buffers_are_sized() {
    let history = 6;
    for hessian in [
        HessianMode::Exact,
        HessianMode::LimitedMemory { history },
        HessianMode::Hybrid { history },
    ] {
        let (counts, switch) = allocations_per_iteration(hessian);
        // the first iteration sizes the block-solve buffers; with L-BFGS each of the first
        // `history` updates stores a pair and widens the low-rank correction
        let sized = match hessian {
            HessianMode::Exact => 2,
            _ => history + 2,
        };
        assert!(counts.len() > sized, "{hessian:?}: {counts:?}");
        for (k, &c) in counts.iter().enumerate().skip(sized) {
            // a hybrid solve builds its exact-Hessian KKT pattern once, in the iteration
            // where it switches
            let switching = switch.is_some_and(|s| k == s + 1);
            assert!(c == 0 || switching, "{hessian:?}: {counts:?}");
        }
    }
}
