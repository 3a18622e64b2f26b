//! Work accounting and cancellation, shared by every method's inner loops.
//!
//! Two reasons stop a computation early:
//! - **cancellation**: the process-wide flag [`CANCEL`] (the Python binding sets it on
//!   Ctrl-C and clears it once the interrupted call has returned). Ctrl-C means "stop what
//!   this process computes", so one flag for all calls is the intended scope.
//! - **the work budget** of one pair (pair methods) or one row (row methods): the number of
//!   work units it may spend, one unit being one visibility evaluation — a point-to-point
//!   ray test, a hemicube or single-plane cell, a Nusselt disk cell, a traced ray, a shadow
//!   evaluation per blocker, a visible piece a shadow is cut from, a kink plane compared — or
//!   one point pair of `quadrature` / `montecarlo` that needs
//!   no ray test (so every sample counts, an unobstructed pair's too). A pair or row that
//!   needs more fails with [`Error::Budget`] instead of running for minutes.
//!
//! The meter is thread-local: one pair or row is computed on one thread (no nested parallel
//! loops inside an estimator), so [`begin`] and [`end`] bracket it on that thread. Inner loops
//! call [`spend`] and leave early when it returns false; whatever they return then is
//! discarded, because [`end`] reports the reason and the caller propagates it as an error.

use crate::error::{Error, Result};
use std::cell::Cell;
use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};

/// Set to stop every running computation of the process (Ctrl-C).
pub static CANCEL: AtomicBool = AtomicBool::new(false);

/// Units spent by every metered pair or row this process has ended (see [`units_done`]).
static DONE: AtomicU64 = AtomicU64::new(0);

/// The work units spent by every metered pair or row this process has ended (finished,
/// cancelled or over budget), on any thread:
/// a measure of cost that, unlike CPU time, does not depend on what else the machine runs
/// (benchmarks print its difference around a run).
pub fn units_done() -> u64 {
    DONE.load(Ordering::Relaxed)
}

/// Default budget per pair or row: 2^27 units (about 13-95 s of one core: 1.4e6-1.0e7 units/s measured by
/// `bench/methods.py budget`, docs/guide.md; every method at its default options stays far below it).
pub const DEFAULT_BUDGET: u64 = 1 << 27;

thread_local! {
    /// (units spent, budget) of the pair or row being computed on this thread.
    static METER: Cell<(u64, u64)> = const { Cell::new((0, u64::MAX)) };
}

/// True once cancellation was requested.
#[inline]
pub fn cancelled() -> bool {
    CANCEL.load(Ordering::Relaxed)
}

/// Starts metering one pair or row on this thread with `budget` units.
#[inline]
pub fn begin(budget: u64) {
    METER.with(|m| m.set((0, budget)));
}

/// Spends `n` units; false when the caller should stop (cancelled or over budget).
#[inline]
pub fn spend(n: u64) -> bool {
    METER.with(|m| {
        let (s, b) = m.get();
        let s = s.saturating_add(n);
        m.set((s, b));
        s <= b && !cancelled()
    })
}

/// True while the current pair or row may go on (no cancellation, within budget).
#[inline]
pub fn go_on() -> bool {
    spend(0)
}

/// Ends metering: `Err(Cancelled)` or `Err(Budget)` when the computation was cut short (its
/// result must then be discarded); resets the meter to unlimited.
pub fn end(what: impl FnOnce() -> String) -> Result<()> {
    let (spent, budget) = METER.with(|m| m.replace((0, u64::MAX)));
    DONE.fetch_add(spent, Ordering::Relaxed);
    if cancelled() {
        return Err(Error::Cancelled);
    }
    if spent > budget {
        return Err(Error::Budget { what: what(), budget });
    }
    Ok(())
}

/// Runs `f` as one metered pair or row: [`begin`], `f`, [`end`].
pub fn metered<T>(budget: u64, what: impl FnOnce() -> String, f: impl FnOnce() -> Result<T>) -> Result<T> {
    begin(budget);
    let r = f();
    end(what)?;
    r
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn over_budget_is_an_error_naming_the_budget() {
        let r = metered(
            10,
            || "pair (0, 1)".into(),
            || {
                let mut n = 0;
                while spend(3) {
                    n += 1;
                }
                Ok(n)
            },
        );
        match r {
            Err(Error::Budget { what, budget }) => {
                assert_eq!(budget, 10);
                assert_eq!(what, "pair (0, 1)");
            }
            other => panic!("{other:?}"),
        }
        // the meter is reset: unmetered work goes on
        assert!(spend(1 << 40));
    }

    #[test]
    fn within_budget_returns_the_value() {
        assert!(metered(10, String::new, || Ok(spend(10))).unwrap());
    }

    #[test]
    fn finished_work_is_counted() {
        // (other tests run metered work on other threads: the count only grows)
        let before = units_done();
        metered(100, String::new, || Ok(spend(7) && spend(5))).unwrap();
        assert!(units_done() >= before + 12);
    }
}
