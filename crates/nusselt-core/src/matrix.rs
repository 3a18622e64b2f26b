//! Scene-wide assembly of form-factor rows, in parallel (rayon), block by block.
//!
//! Pair methods compute the symmetric quantity G_ij = A_i F_ij = A_j F_ji once per unordered
//! pair (j > i): reciprocity then holds exactly by construction, and half the work is saved.
//! The caller asks for a block of rows at a time, which keeps memory bounded, lets it report
//! progress and honour Ctrl-C between blocks, and lets it checkpoint finished blocks.

use crate::error::{Error, Result};
use rayon::prelude::*;
use std::sync::atomic::{AtomicBool, Ordering};

/// For every source row i in `rows`, the value of every receiver pair (i, j), j > i, that
/// `pair(i, j)` returns as `Some` (None: nothing exchanged, not stored). `skip(i, j)` is a
/// cheap test that the pair exchanges nothing (e.g. j behind i), checked first. Stops early
/// with `Error::Cancelled` when `cancel` is set.
pub fn upper_pair_rows<T, P, S>(
    n: usize,
    rows: &[usize],
    receiver: &[bool],
    cancel: &AtomicBool,
    skip: S,
    pair: P,
) -> Result<Vec<Vec<(u32, T)>>>
where
    T: Send,
    P: Fn(usize, usize) -> Result<Option<T>> + Sync,
    S: Fn(usize, usize) -> bool + Sync,
{
    check_rows(n, rows, receiver)?;
    rows.par_iter()
        .map(|&i| {
            if cancel.load(Ordering::Relaxed) {
                return Err(Error::Cancelled);
            }
            let mut row = Vec::new();
            if !receiver[i] {
                return Ok(row);
            }
            for j in i + 1..n {
                if !receiver[j] || skip(i, j) {
                    continue;
                }
                if let Some(g) = pair(i, j)? {
                    row.push((j as u32, g));
                }
            }
            Ok(row)
        })
        .collect()
}

/// Whole rows from a per-row method (hemisphere sampling): `row(i)` returns F_i. directly.
pub fn full_rows<R, T>(n: usize, rows: &[usize], receiver: &[bool], cancel: &AtomicBool, row: R) -> Result<Vec<T>>
where
    R: Fn(usize) -> Result<T> + Sync,
    T: Send,
{
    check_rows(n, rows, receiver)?;
    rows.par_iter()
        .map(|&i| {
            if cancel.load(Ordering::Relaxed) {
                return Err(Error::Cancelled);
            }
            row(i)
        })
        .collect()
}

fn check_rows(n: usize, rows: &[usize], receiver: &[bool]) -> Result<()> {
    if receiver.len() != n {
        return Err(Error::InvalidArgument(format!("receiver mask has {} entries for {n} polygons", receiver.len())));
    }
    if let Some(&bad) = rows.iter().find(|&&i| i >= n) {
        return Err(Error::InvalidArgument(format!("row {bad} out of range for {n} polygons")));
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn upper_rows_compute_each_pair_once() {
        let n = 5;
        let receiver = vec![true, true, false, true, true];
        let rows: Vec<usize> = (0..n).collect();
        let calls = std::sync::atomic::AtomicUsize::new(0);
        let out = upper_pair_rows(n, &rows, &receiver, &AtomicBool::new(false), |_, _| false, |i, j| {
            calls.fetch_add(1, Ordering::Relaxed);
            Ok(Some((10 * i + j) as f64))
        })
        .unwrap();
        // pairs among receivers {0,1,3,4}: 6 unordered pairs
        assert_eq!(calls.load(Ordering::Relaxed), 6);
        assert_eq!(out[0], vec![(1, 1.0), (3, 3.0), (4, 4.0)]);
        assert!(out[2].is_empty());
        assert_eq!(out[3], vec![(4, 34.0)]);
    }

    #[test]
    fn cancel_stops() {
        let r = upper_pair_rows(3, &[0, 1], &[true; 3], &AtomicBool::new(true), |_, _| false, |_, _| Ok(Some(1.0)));
        assert_eq!(r.unwrap_err(), Error::Cancelled);
    }

    #[test]
    fn bad_rows_are_errors() {
        let r = full_rows(3, &[3], &[true; 3], &AtomicBool::new(false), |_| Ok(()));
        assert!(matches!(r, Err(Error::InvalidArgument(_))));
    }
}
