//! The worker pool, fork-safe: a child process created by fork() does not inherit the
//! parent's threads, so it must not use the parent's pool; it builds its own on first use.
use std::sync::{Arc, Mutex};

static POOL: Mutex<Option<(u32, Arc<rayon::ThreadPool>)>> = Mutex::new(None);

fn threads() -> usize {
    std::env::var("NUSSELT_NUM_THREADS")
        .ok()
        .and_then(|s| s.parse().ok())
        .filter(|&n| n > 0)
        .unwrap_or_else(|| std::thread::available_parallelism().map_or(1, |n| n.get()))
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
