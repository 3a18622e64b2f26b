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
///
/// The pairs of all the rows are one parallel loop, so rayon balances pairs, not rows: the
/// cost of a pair varies a thousandfold (an obstructed pair of a sampled method against a
/// free one), and rows split among threads leave a core idle while the other finishes a few
/// expensive rows at the end of each block. Each pair is computed on its own, so the values
/// do not depend on how the pairs are split.
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
    // first[r]: flat index of the pair (rows[r], rows[r] + 1); a non-receiver row has none
    let mut first = Vec::with_capacity(rows.len() + 1);
    first.push(0usize);
    for &i in rows {
        let len = if receiver[i] { n - i - 1 } else { 0 };
        first.push(first[first.len() - 1] + len);
    }
    let row_of = |k: usize| first.partition_point(|&s| s <= k) - 1;
    let found: Vec<(usize, u32, T)> = (0..first[rows.len()])
        .into_par_iter()
        .filter_map(|k| {
            if cancel.load(Ordering::Relaxed) {
                return Some(Err(Error::Cancelled));
            }
            let r = row_of(k);
            let (i, j) = (rows[r], rows[r] + 1 + (k - first[r]));
            if !receiver[j] || skip(i, j) {
                return None;
            }
            pair(i, j).map(|g| g.map(|g| (r, j as u32, g))).transpose()
        })
        .collect::<Result<_>>()?;
    // in flat order, so each row's columns come out ascending
    let mut out: Vec<Vec<(u32, T)>> = rows.iter().map(|_| Vec::new()).collect();
    for (r, j, g) in found {
        out[r].push((j, g));
    }
    Ok(out)
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

/// A square sparse matrix in compressed sparse row form, columns ascending within each row.
/// One finished pair row: columns j, G_ij and, for sampled methods, the standard errors of
/// G_ij (None: the method is exact up to its tolerance).
#[derive(Debug, Clone, Default, PartialEq)]
pub struct PairRow {
    pub cols: Vec<u32>,
    pub g: Vec<f64>,
    pub std: Option<Vec<f64>>,
}

impl PairRow {
    pub fn len(&self) -> usize {
        self.cols.len()
    }

    pub fn is_empty(&self) -> bool {
        self.cols.is_empty()
    }

    /// (j, G_ij, standard error or 0).
    pub fn iter(&self) -> impl Iterator<Item = (u32, f64, f64)> + '_ {
        (0..self.len()).map(|k| (self.cols[k], self.g[k], self.std.as_ref().map_or(0.0, |s| s[k])))
    }
}

/// Finished pair rows as CSR parts over those rows: what the Python layer stores per block.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct PairBlock {
    pub indptr: Vec<i64>,
    pub cols: Vec<i32>,
    pub g: Vec<f64>,
    /// Standard errors of G when some row has them (zeros for the rows that have none).
    pub std: Option<Vec<f64>>,
}

impl PairBlock {
    /// Clamps every G_ij = A_i F_ij of the block (row k is polygon `rows[k]`) to
    /// [0, min(A_i, A_j)] ([`clamp_g`]) and drops the entries that become 0 with no
    /// standard error. Clamping the symmetric G, not F per direction, keeps reciprocity exact.
    pub fn clamp_to_areas(&mut self, rows: &[usize], areas: &[f64]) {
        let mut kept = 0usize;
        let mut start = 0usize;
        for (k, &i) in rows.iter().enumerate() {
            let end = self.indptr[k + 1] as usize;
            for e in start..end {
                let j = self.cols[e] as usize;
                let g = clamp_g(self.g[e], areas[i], areas[j]);
                let sd = self.std.as_ref().map_or(0.0, |s| s[e]);
                if g != 0.0 || sd != 0.0 {
                    self.cols[kept] = self.cols[e];
                    self.g[kept] = g;
                    if let Some(s) = self.std.as_mut() {
                        s[kept] = sd;
                    }
                    kept += 1;
                }
            }
            start = end;
            self.indptr[k + 1] = kept as i64;
        }
        self.cols.truncate(kept);
        self.g.truncate(kept);
        if let Some(s) = self.std.as_mut() {
            s.truncate(kept);
        }
    }

    /// The block's rows one by one (row k of the rows it was computed for).
    pub fn rows(&self) -> Vec<PairRow> {
        self.indptr
            .windows(2)
            .map(|w| {
                let (s, e) = (w[0] as usize, w[1] as usize);
                PairRow {
                    cols: self.cols[s..e].iter().map(|&j| j as u32).collect(),
                    g: self.g[s..e].to_vec(),
                    std: self.std.as_ref().map(|sd| sd[s..e].to_vec()),
                }
            })
            .collect()
    }
}

/// G = A_i F_ij = A_j F_ji brought into its range [0, min(A_i, A_j)] (F_ij <= 1 both ways):
/// rounding of a sum that cancels can leave it slightly outside (-1e-9 A for nearly coplanar
/// triangles sharing a vertex, where the true F is ~1e-15); the clamp is within that error.
#[inline]
pub fn clamp_g(g: f64, area_i: f64, area_j: f64) -> f64 {
    g.max(0.0).min(area_i.min(area_j))
}

/// `s` cut front to back into consecutive pieces of the given lengths (each owned by one
/// parallel job). An empty `s` gives empty pieces (optional arrays that are not kept).
pub(crate) fn split_lengths<T>(mut s: &mut [T], lens: impl IntoIterator<Item = usize>) -> Vec<&mut [T]> {
    lens.into_iter()
        .map(|len| {
            debug_assert!(s.is_empty() || len <= s.len(), "pieces longer than the slice");
            let at = len.min(s.len());
            let (piece, rest) = std::mem::take(&mut s).split_at_mut(at);
            s = rest;
            piece
        })
        .collect()
}

/// The rows' entries laid end to end, copied in parallel (the copy of a big block is
/// dominated by first touches of fresh memory, which then happen on every thread).
pub fn flatten_pair_rows(rows: &[PairRow]) -> Result<PairBlock> {
    let mut indptr = Vec::with_capacity(rows.len() + 1);
    indptr.push(0i64);
    for r in rows {
        indptr.push(indptr.last().unwrap() + r.len() as i64);
    }
    let nnz = *indptr.last().unwrap() as usize;
    let with_std = rows.iter().any(|r| r.std.is_some());
    let mut cols = try_zeroed::<i32>("a block's column indices", nnz)?;
    let mut g = try_zeroed::<f64>("a block's entries", nnz)?;
    let mut std = if with_std { try_zeroed::<f64>("a block's standard errors", nnz)? } else { Vec::new() };
    let lens = || rows.iter().map(|r| r.len());
    let jobs: Vec<_> = rows
        .iter()
        .zip(split_lengths(&mut cols, lens()))
        .zip(split_lengths(&mut g, lens()))
        .zip(split_lengths(&mut std, lens()))
        .collect();
    jobs.into_par_iter().with_min_len(64).for_each(|(((r, c), gg), sd)| {
        for (dst, &j) in c.iter_mut().zip(&r.cols) {
            *dst = j as i32;
        }
        gg.copy_from_slice(&r.g);
        if let Some(s) = &r.std {
            sd.copy_from_slice(s);
        }
    });
    Ok(PairBlock { indptr, cols, g, std: with_std.then_some(std) })
}

#[derive(Debug, Clone, PartialEq, Default)]
pub struct Csr<V = f64> {
    pub indptr: Vec<i64>,
    /// Column indices: i32 like scipy's default, half the memory of i64 (n < 2^31 always).
    pub indices: Vec<i32>,
    pub data: Vec<V>,
}

/// A type F is stored as: f64, or f32 (a third less memory), each entry rounded once from
/// the f64 quotient G / A, so a float32 result holds the float64 result's values rounded.
pub trait Stored: Copy + Send + Sync + 'static {
    fn from_f64(x: f64) -> Self;
}

impl Stored for f64 {
    #[inline]
    fn from_f64(x: f64) -> Self {
        x
    }
}

impl Stored for f32 {
    #[inline]
    fn from_f64(x: f64) -> Self {
        x as f32
    }
}

/// Number types whose all-zero bytes are the value 0.
pub trait Zeroed: Copy {}
impl Zeroed for i32 {}
impl Zeroed for f32 {}
impl Zeroed for f64 {}

/// `count` zeros, or an error when the memory cannot be had. The zeros come from the
/// allocator's zeroed memory (fresh pages of a big allocation are zero already: no serial
/// fill, whose first touches of 377 MB were most of the cost; the parallel writes then
/// touch each page once).
pub fn try_zeroed<T: Zeroed>(what: &'static str, count: usize) -> Result<Vec<T>> {
    let bytes = count.saturating_mul(std::mem::size_of::<T>());
    let oom = || Error::OutOfMemory { what, count, bytes };
    if count == 0 || std::mem::size_of::<T>() == 0 {
        return Ok(Vec::new());
    }
    let layout = std::alloc::Layout::array::<T>(count).map_err(|_| oom())?;
    // SAFETY: the layout has a nonzero size; a non-null pointer is `count` zeroed, aligned
    // slots of T, for which zero bytes are a valid value (Zeroed), owned by the Vec from here
    unsafe {
        let ptr = std::alloc::alloc_zeroed(layout).cast::<T>();
        if ptr.is_null() {
            return Err(oom());
        }
        Ok(Vec::from_raw_parts(ptr, count, count))
    }
}

/// dst = src / a, entry by entry (G over the row's area: F), stored as V.
#[inline]
fn put_divided<V: Stored>(dst: &mut [V], src: &[f64], a: f64) {
    for (d, &v) in dst.iter_mut().zip(src) {
        *d = V::from_f64(v / a);
    }
}

/// One row of the upper triangle of the symmetric G = A_i F_ij: source row `row` and its
/// entries (column j > row, ascending; G_ij; optionally the standard error of G_ij).
pub struct UpperRow<'a> {
    pub row: usize,
    pub cols: &'a [i32],
    pub g: &'a [f64],
    pub std: Option<&'a [f64]>,
}

/// Where the entries of F go: for each output row, where it starts (`count`, with the total
/// last) and how many entries come from rows above it (`lower`, the transposed ones).
pub struct MirrorLayout {
    by_row: Vec<Option<usize>>,
    count: Vec<i64>,
    lower: Vec<i64>,
}

impl MirrorLayout {
    /// The entries of F (both triangles).
    pub fn nnz(&self) -> usize {
        *self.count.last().unwrap_or(&0) as usize
    }

    /// Row starts of F (CSR indptr).
    pub fn indptr(&self) -> &[i64] {
        &self.count
    }
}

/// The layout of the F that [`mirror_into`] builds from these upper rows over `n` rows;
/// checks the rows (each at most once, columns ascending above the diagonal and < n).
pub fn mirror_layout(n: usize, rows: &[UpperRow<'_>]) -> Result<MirrorLayout> {
    let bad = |what: String| Err(Error::InvalidArgument(what));
    if n > i32::MAX as usize {
        return bad(format!("{n} rows: more than a CSR with i32 indices holds"));
    }
    let mut by_row: Vec<Option<usize>> = vec![None; n];
    let mut count = vec![0i64; n + 1];
    let mut lower = vec![0i64; n];
    for (k, r) in rows.iter().enumerate() {
        if r.row >= n || by_row[r.row].is_some() {
            return bad(format!("row {} is out of range or given twice", r.row));
        }
        if r.cols.len() != r.g.len() || r.std.is_some_and(|s| s.len() != r.g.len()) {
            return bad(format!("row {}: column and value counts differ", r.row));
        }
        by_row[r.row] = Some(k);
        let mut prev = r.row as i64;
        for &j in r.cols {
            let j = j as i64;
            if j <= prev || j >= n as i64 {
                return bad(format!("row {}: columns must ascend above the diagonal and be < {n}", r.row));
            }
            prev = j;
            lower[j as usize] += 1;
        }
        count[r.row + 1] += r.cols.len() as i64;
    }
    for i in 0..n {
        count[i + 1] += lower[i] + count[i];
    }
    Ok(MirrorLayout { by_row, count, lower })
}

/// The full F (and its standard errors when given) from the upper triangle of G: F_ij =
/// G_ij / A_i and F_ji = G_ij / A_j, in one pass over the entries, stored as V (f64 or f32:
/// the division in f64, then rounded). Each row is given at most once, in any order; the
/// result has ascending columns (lower entries, then upper).
pub fn mirror_upper<V: Stored + Zeroed>(
    areas: &[f64],
    rows: &[UpperRow<'_>],
    with_std: bool,
) -> Result<(Csr<V>, Option<Csr<V>>)> {
    let layout = mirror_layout(areas.len(), rows)?;
    let nnz = layout.nnz();
    let mut indices = try_zeroed::<i32>("the column indices of F", nnz)?;
    let mut data = try_zeroed::<V>("the entries of F", nnz)?;
    let mut sdata = if with_std { try_zeroed::<V>("the standard errors of F", nnz)? } else { Vec::new() };
    mirror_into(areas, rows, &layout, &mut indices, &mut data, &mut sdata)?;
    let count = layout.count;
    let std = with_std.then(|| Csr { indptr: count.clone(), indices: indices.clone(), data: sdata });
    Ok((Csr { indptr: count, indices, data }, std))
}

/// [`mirror_upper`] into arrays the caller provides (`layout.nnz()` long; `sdata` empty
/// for no standard errors), e.g. memory of the caller's choosing.
pub fn mirror_into<V: Stored>(
    areas: &[f64],
    rows: &[UpperRow<'_>],
    layout: &MirrorLayout,
    indices: &mut [i32],
    data: &mut [V],
    sdata: &mut [V],
) -> Result<()> {
    let n = areas.len();
    let nnz = layout.nnz();
    let with_std = !sdata.is_empty();
    if layout.by_row.len() != n || indices.len() != nnz || data.len() != nnz || (with_std && sdata.len() != nnz) {
        return Err(Error::InvalidArgument(format!("mirror: arrays of {nnz} entries over {n} rows expected")));
    }
    let (by_row, count, lower) = (&layout.by_row, &layout.count, &layout.lower);
    // In parallel over ranges of output rows, each owning its slice of the output: rows
    // [lo, hi) get their lower entries (column k < row, from source rows k ascending: the
    // run of k's columns inside [lo, hi), found by bisection) and then their upper entries.
    let parts = 4 * rayon::current_num_threads().max(1);
    let mut bounds = vec![0usize];
    for p in 1..parts {
        let target = (nnz * p / parts) as i64;
        let b = count.partition_point(|&c| c < target).min(n);
        if b > *bounds.last().unwrap() {
            bounds.push(b);
        }
    }
    bounds.push(n);
    let lens = || bounds.windows(2).map(|w| (count[w[1]] - count[w[0]]) as usize);
    let jobs: Vec<_> = bounds
        .windows(2)
        .zip(split_lengths(indices, lens()))
        .zip(split_lengths(data, lens()))
        .zip(split_lengths(sdata, lens()))
        .map(|(((w, ind), dat), sd)| (w[0], w[1], ind, dat, sd))
        .collect();
    jobs.into_par_iter().for_each(|(lo, hi, ind, dat, sd)| {
        let base = count[lo] as usize;
        // upper entries of rows lo..hi, after their lower ones: contiguous, so plain copies
        for k in lo..hi {
            let Some(b) = by_row[k] else { continue };
            let r = &rows[b];
            let (up, m, a) = ((count[k] + lower[k]) as usize - base, r.cols.len(), areas[k]);
            ind[up..up + m].copy_from_slice(r.cols);
            put_divided(&mut dat[up..up + m], r.g, a);
            if with_std {
                match r.std {
                    Some(s) => put_divided(&mut sd[up..up + m], s, a),
                    None => sd[up..up + m].fill(V::from_f64(0.0)),
                }
            }
        }
        // Lower entries (column k < row j, from source rows k ascending): a transpose. Writing
        // them one by one into their rows thrashes the cache (rows of equal length, as in a
        // meshed enclosure, start at addresses a multiple of 4 KiB apart: every write lands in
        // the same cache sets; 15.7 M entries took 0.5 s). Instead, by tiles of TILE output
        // rows x TILE source rows gathered in a small buffer, then copied out per output row
        // as one contiguous run.
        const TILE: usize = 64;
        let mut next: Vec<usize> = (lo..hi).map(|r| count[r] as usize - base).collect();
        // where source row k's columns inside the current output tile start
        let mut cursor: Vec<usize> =
            (0..hi).map(|k| by_row[k].map_or(0, |b| rows[b].cols.partition_point(|&j| (j as usize) < lo))).collect();
        let mut cnt = [0usize; TILE];
        let mut buf_k = vec![0i32; TILE * TILE];
        let mut buf_g = vec![0.0f64; TILE * TILE];
        let mut buf_s = if with_std { vec![0.0f64; TILE * TILE] } else { Vec::new() };
        for t0 in (lo..hi).step_by(TILE) {
            let t1 = (t0 + TILE).min(hi);
            for k0 in (0..t1).step_by(TILE) {
                cnt.fill(0);
                for k in k0..(k0 + TILE).min(t1) {
                    let Some(b) = by_row[k] else { continue };
                    let r = &rows[b];
                    let mut e = cursor[k];
                    while e < r.cols.len() && (r.cols[e] as usize) < t1 {
                        let j = r.cols[e] as usize - t0;
                        let at = j * TILE + cnt[j];
                        cnt[j] += 1;
                        buf_k[at] = k as i32;
                        buf_g[at] = r.g[e];
                        if with_std {
                            buf_s[at] = r.std.map_or(0.0, |s| s[e]);
                        }
                        e += 1;
                    }
                    cursor[k] = e;
                }
                for j in 0..t1 - t0 {
                    let (m, at, a) = (cnt[j], next[t0 + j - lo], areas[t0 + j]);
                    if m == 0 {
                        continue;
                    }
                    let run = j * TILE..j * TILE + m;
                    ind[at..at + m].copy_from_slice(&buf_k[run.clone()]);
                    put_divided(&mut dat[at..at + m], &buf_g[run.clone()], a);
                    if with_std {
                        put_divided(&mut sd[at..at + m], &buf_s[run], a);
                    }
                    next[t0 + j - lo] += m;
                }
            }
        }
    });
    Ok(())
}

/// The reciprocity error max |A_i F_ij - A_j F_ji| / max(|A_i F_ij|, |A_j F_ji|) of the F
/// that [`mirror_upper`] builds from these rows (F_ij = G_ij / A_i, F_ji = G_ij / A_j, each
/// rounded to f32 first when `as_f32`, as a float32 result stores them), from the upper
/// triangle itself: no transpose of the result. Pairs where both are 0 count as 0.
pub fn upper_reciprocity(areas: &[f64], rows: &[UpperRow<'_>], as_f32: bool) -> Result<f64> {
    let n = areas.len();
    for r in rows {
        if r.row >= n || r.cols.len() != r.g.len() || r.cols.iter().any(|&j| j < 0 || j as usize >= n) {
            return Err(Error::InvalidArgument(format!("row {}: an index out of range, or counts differ", r.row)));
        }
    }
    let worst = |r: &UpperRow<'_>| {
        let ai = areas[r.row];
        let mut w = 0.0f64;
        for (&j, &g) in r.cols.iter().zip(r.g) {
            let aj = areas[j as usize];
            let (mut fi, mut fj) = (g / ai, g / aj);
            if as_f32 {
                (fi, fj) = (fi as f32 as f64, fj as f32 as f64);
            }
            let (x, y) = (fi * ai, fj * aj);
            let den = x.abs().max(y.abs());
            if den > 0.0 {
                w = w.max((x - y).abs() / den);
            }
        }
        w
    };
    Ok(rows.par_iter().map(worst).reduce(|| 0.0, f64::max))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn clamp_keeps_g_in_range_and_drops_zeros() {
        // rows 0 and 2 of polygons with areas 1, 2, 0.5
        let mut b = PairBlock { indptr: vec![0, 2, 3], cols: vec![1, 2, 1], g: vec![-1e-9, 0.7, 2.5], std: None };
        b.clamp_to_areas(&[0, 2], &[1.0, 2.0, 0.5]);
        assert_eq!(b.indptr, vec![0, 1, 2]);
        assert_eq!(b.cols, vec![2, 1]);
        assert_eq!(b.g, vec![0.5, 0.5]);
        // an entry clamped to 0 that has a standard error is kept
        let mut b = PairBlock { indptr: vec![0, 1], cols: vec![1], g: vec![-1e-9], std: Some(vec![1e-3]) };
        b.clamp_to_areas(&[0], &[1.0, 1.0]);
        assert_eq!((b.g, b.std), (vec![0.0], Some(vec![1e-3])));
    }

    #[test]
    fn upper_rows_compute_each_pair_once() {
        let n = 5;
        let receiver = vec![true, true, false, true, true];
        let rows: Vec<usize> = (0..n).collect();
        let calls = std::sync::atomic::AtomicUsize::new(0);
        let out = upper_pair_rows(
            n,
            &rows,
            &receiver,
            &AtomicBool::new(false),
            |_, _| false,
            |i, j| {
                calls.fetch_add(1, Ordering::Relaxed);
                Ok(Some((10 * i + j) as f64))
            },
        )
        .unwrap();
        // pairs among receivers {0,1,3,4}: 6 unordered pairs
        assert_eq!(calls.load(Ordering::Relaxed), 6);
        assert_eq!(out[0], vec![(1, 1.0), (3, 3.0), (4, 4.0)]);
        assert!(out[2].is_empty());
        assert_eq!(out[3], vec![(4, 34.0)]);
    }

    #[test]
    fn upper_rows_do_not_depend_on_thread_count_or_row_order() {
        // rows of unequal length and pairs of unequal cost, in any order, skipped pairs
        // and a non-receiver: the same rows on 1 and 3 threads, in the order asked
        let n = 40;
        let receiver: Vec<bool> = (0..n).map(|i| i != 7).collect();
        let rows: Vec<usize> = vec![5, 0, 39, 7, 12, 30, 1];
        let run = |threads| {
            let pool = rayon::ThreadPoolBuilder::new().num_threads(threads).build().unwrap();
            pool.install(|| {
                upper_pair_rows(
                    n,
                    &rows,
                    &receiver,
                    &AtomicBool::new(false),
                    |i, j| (i + j) % 5 == 0,
                    |i, j| {
                        let spin: f64 = (0..(i * j) % 97 * 100).map(|k| (k as f64).sqrt()).sum();
                        Ok(((i * j) % 3 != 0).then_some(i as f64 + j as f64 / 100.0 + spin * 0.0))
                    },
                )
                .unwrap()
            })
        };
        let one = run(1);
        assert_eq!(one, run(3));
        for (r, &i) in rows.iter().enumerate() {
            let want: Vec<(u32, f64)> = (i + 1..n)
                .filter(|&j| receiver[i] && receiver[j] && (i + j) % 5 != 0 && (i * j) % 3 != 0)
                .map(|j| (j as u32, i as f64 + j as f64 / 100.0))
                .collect();
            assert_eq!(one[r], want, "row {i}");
        }
    }

    #[test]
    fn mirror_upper_builds_symmetric_g_over_areas() {
        // G upper: (0,1)=2, (0,3)=6, (1,2)=4, (2,3)=8; row 2 given before row 0
        let areas = [1.0, 2.0, 4.0, 8.0];
        let (c0, g0, s0) = ([1i32, 3], [2.0, 6.0], [0.1, 0.3]);
        let (c1, g1, s1) = ([2i32], [4.0], [0.2]);
        let (c2, g2, s2) = ([3i32], [8.0], [0.4]);
        let rows = [
            UpperRow { row: 2, cols: &c2, g: &g2, std: Some(&s2) },
            UpperRow { row: 0, cols: &c0, g: &g0, std: Some(&s0) },
            UpperRow { row: 1, cols: &c1, g: &g1, std: Some(&s1) },
        ];
        let (f, s) = mirror_upper::<f64>(&areas, &rows, true).unwrap();
        let mut dense = [[0.0; 4]; 4];
        for i in 0..4 {
            let (a, b) = (f.indptr[i] as usize, f.indptr[i + 1] as usize);
            assert!(f.indices[a..b].windows(2).all(|w| w[0] < w[1]), "row {i} not sorted");
            for k in a..b {
                dense[i][f.indices[k] as usize] = f.data[k];
            }
        }
        let g = [[0.0, 2.0, 0.0, 6.0], [2.0, 0.0, 4.0, 0.0], [0.0, 4.0, 0.0, 8.0], [6.0, 0.0, 8.0, 0.0]];
        for i in 0..4 {
            for j in 0..4 {
                assert_eq!(dense[i][j], g[i][j] / areas[i], "({i},{j})");
            }
        }
        let s = s.unwrap();
        assert_eq!(s.indices, f.indices);
        assert_eq!(s.data[0], 0.1 / 1.0); // row 0, column 1
                                          // malformed input is an error, not a panic
        let bad = [UpperRow { row: 1, cols: &[0i32], g: &[1.0], std: None }];
        assert!(mirror_upper::<f64>(&areas, &bad, false).is_err());
        let twice =
            [UpperRow { row: 0, cols: &[], g: &[], std: None }, UpperRow { row: 0, cols: &[], g: &[], std: None }];
        assert!(mirror_upper::<f64>(&areas, &twice, false).is_err());
    }

    #[test]
    fn upper_reciprocity_is_the_largest_relative_difference_of_a_i_f_ij_and_a_j_f_ji() {
        // by the definition, entry by entry: A_i (G / A_i) against A_j (G / A_j)
        let areas = [0.1, 3.0, 7.0, 1e-3];
        let (c0, g0) = ([1i32, 2, 3], [0.3, 0.7, 1e-5]);
        let (c1, g1) = ([2i32], [2.2]);
        let rows =
            [UpperRow { row: 0, cols: &c0, g: &g0, std: None }, UpperRow { row: 1, cols: &c1, g: &g1, std: None }];
        for as_f32 in [false, true] {
            let mut want = 0.0f64;
            for r in &rows {
                for (&j, &g) in r.cols.iter().zip(r.g) {
                    let (ai, aj) = (areas[r.row], areas[j as usize]);
                    let round = |f: f64| if as_f32 { f as f32 as f64 } else { f };
                    let (x, y) = (round(g / ai) * ai, round(g / aj) * aj);
                    want = want.max((x - y).abs() / x.abs().max(y.abs()));
                }
            }
            assert_eq!(upper_reciprocity(&areas, &rows, as_f32).unwrap(), want);
        }
        assert!(upper_reciprocity(&areas, &rows, true).unwrap() > 1e-9); // float32 rounding shows
        let bad = [UpperRow { row: 0, cols: &[9i32], g: &[1.0], std: None }];
        assert!(upper_reciprocity(&areas, &bad, false).is_err());
    }

    #[test]
    fn mirror_upper_matches_a_dense_transpose_across_tiles() {
        // 300 rows (several tiles and parallel parts), random sparse upper triangle, some rows
        // not given at all; against the dense G / A built entry by entry
        let n = 300;
        let areas: Vec<f64> = (0..n).map(|i| 1.0 + (i % 7) as f64).collect();
        let mut s = 0x2545_f491_4f6c_dd1du64;
        let mut rand = move || {
            s ^= s << 13;
            s ^= s >> 7;
            s ^= s << 17;
            s
        };
        let mut data: Vec<(usize, Vec<i32>, Vec<f64>, Vec<f64>)> = Vec::new();
        for i in (0..n).rev() {
            if rand() % 10 == 0 {
                continue;
            }
            let cols: Vec<i32> = (i + 1..n).filter(|_| rand() % 3 != 0).map(|j| j as i32).collect();
            let g: Vec<f64> = cols.iter().map(|&j| (i * n + j as usize) as f64).collect();
            let sd: Vec<f64> = g.iter().map(|v| 0.5 * v).collect();
            data.push((i, cols, g, sd));
        }
        let rows: Vec<UpperRow> =
            data.iter().map(|(i, c, g, sd)| UpperRow { row: *i, cols: c, g, std: Some(sd) }).collect();
        let (f, sd) = mirror_upper::<f64>(&areas, &rows, true).unwrap();
        let sd = sd.unwrap();
        // float32: the same pattern, every value the float64 one rounded once
        let (f32s, sd32) = mirror_upper::<f32>(&areas, &rows, true).unwrap();
        assert_eq!((&f32s.indptr, &f32s.indices), (&f.indptr, &f.indices));
        assert!(f32s.data.iter().zip(&f.data).all(|(&x, &y)| x == y as f32));
        assert!(sd32.unwrap().data.iter().zip(&sd.data).all(|(&x, &y)| x == y as f32));
        let mut want = vec![vec![0.0; n]; n];
        for (i, c, g, _) in &data {
            for (&j, &v) in c.iter().zip(g) {
                want[*i][j as usize] = v / areas[*i];
                want[j as usize][*i] = v / areas[j as usize];
            }
        }
        for i in 0..n {
            let (a, b) = (f.indptr[i] as usize, f.indptr[i + 1] as usize);
            assert!(f.indices[a..b].windows(2).all(|w| w[0] < w[1]), "row {i} not sorted");
            let mut got = vec![0.0; n];
            for k in a..b {
                got[f.indices[k] as usize] = f.data[k];
                assert_eq!(sd.data[k], 0.5 * f.data[k]);
            }
            assert_eq!(got, want[i], "row {i}");
            assert_eq!(b - a, want[i].iter().filter(|&&v| v != 0.0).count(), "row {i}: entries (all G > 0 here)");
        }
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
