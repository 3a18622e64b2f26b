//! The worker pool, fork-safe: a child process created by fork() does not inherit the
//! parent's threads, so it must not use the parent's pool; it builds its own on first use.
use pyo3::prelude::*;
use std::sync::{Arc, Mutex};

static POOL: Mutex<Option<(u32, Arc<rayon::ThreadPool>)>> = Mutex::new(None);

/// The pool's size: `NUSSELT_NUM_THREADS`, else `RAYON_NUM_THREADS` (what rayon users set,
/// and what our benchmarks and docs use), else the CPUs this process may run on.
fn threads() -> usize {
    ["NUSSELT_NUM_THREADS", "RAYON_NUM_THREADS"]
        .iter()
        .find_map(|v| std::env::var(v).ok().and_then(|s| s.trim().parse().ok()).filter(|&n: &usize| n > 0))
        .unwrap_or_else(|| std::thread::available_parallelism().map_or(1, |n| n.get()))
}

/// How many worker threads the core computes with (starts the pool if need be).
#[pyfunction]
pub fn num_threads() -> usize {
    pool().current_num_threads()
}

/// Work units spent by every pair or row this process has computed (see
/// `nusselt_core::work::units_done`): benchmarks print its difference around a run.
#[pyfunction]
pub fn work_units() -> u64 {
    nusselt_core::work::units_done()
}

/// The pool of this process (rebuilt after a fork, detected by the process id).
pub fn pool() -> Arc<rayon::ThreadPool> {
    let pid = std::process::id();
    let mut guard = POOL.lock().unwrap_or_else(|e| e.into_inner());
    match &*guard {
        Some((p, pool)) if *p == pid => pool.clone(),
        _ => {
            let pool = Arc::new(
                rayon::ThreadPoolBuilder::new()
                    .num_threads(threads())
                    .thread_name(|i| format!("nusselt-{i}"))
                    .build()
                    .expect("cannot start worker threads"),
            );
            *guard = Some((pid, pool.clone()));
            pool
        }
    }
}
