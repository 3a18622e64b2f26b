//! Heavy calls that Ctrl-C can stop: the work runs on a helper thread with the GIL released
//! while the calling thread waits in short slices and lets Python run its signal handlers
//! between them. On KeyboardInterrupt (or any exception a handler raises) it sets the core's
//! cancellation flag, which every method's inner loop polls, waits for the work to wind down
//! (well under a second) and re-raises.
use crate::errors::guard;
use nusselt_core::work::CANCEL;
use nusselt_core::Error;
use pyo3::prelude::*;
use std::sync::atomic::Ordering;
use std::sync::{Condvar, Mutex};
use std::time::Duration;

/// How long the calling thread waits between two looks at pending signals.
const SLICE: Duration = Duration::from_millis(50);

/// Runs `f` (no Python inside) so that Ctrl-C stops it; panics become RuntimeError.
pub fn run<T: Send>(py: Python<'_>, f: impl FnOnce() -> Result<T, Error> + Send) -> PyResult<T> {
    let done = (Mutex::new(false), Condvar::new());
    let done = &done;
    std::thread::scope(|s| {
        let worker = s.spawn(move || {
            let r = guard(f);
            *done.0.lock().unwrap_or_else(|e| e.into_inner()) = true;
            done.1.notify_all();
            r
        });
        loop {
            let finished = py.detach(|| {
                let g = done.0.lock().unwrap_or_else(|e| e.into_inner());
                *done.1.wait_timeout_while(g, SLICE, |d| !*d).unwrap_or_else(|e| e.into_inner()).0
            });
            if finished {
                break;
            }
            if let Err(signal) = py.check_signals() {
                CANCEL.store(true, Ordering::SeqCst);
                let _ = py.detach(|| worker.join());
                CANCEL.store(false, Ordering::SeqCst);
                return Err(signal);
            }
        }
        py.detach(|| worker.join()).unwrap_or_else(|_| {
            Err(pyo3::exceptions::PyRuntimeError::new_err("internal error in nusselt core: worker thread panicked"))
        })
    })
}
