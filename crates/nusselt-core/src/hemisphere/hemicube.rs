//! Hemicube (Cohen & Greenberg, SIGGRAPH '85), with exact cell integrals.
//!
//! Around each sample point p on the source, a cube of half side 1 is cut by the element
//! plane: a top face z = 1 with R x R cells over [-1, 1]^2 and four side faces with R x R/2
//! cells over [-1, 1] x [0, 1]. Every other polygon is clipped to the element's front
//! half-space and to each face's near plane, projected onto the face and scan-converted with
//! cell-centre sampling into a z-buffer and an item buffer. A cell's delta form factor is the
//! exact integral of the cosine kernel over the cell (docs/algorithms.md §2.2):
//!
//!   top,  [x0, x1]x[y0, y1]: dF = Phi(x1,y1) - Phi(x0,y1) - Phi(x1,y0) + Phi(x0,y0),
//!     Phi(x,y) = (1/2pi)[x/sqrt(1+x^2) atan(y/sqrt(1+x^2)) + y/sqrt(1+y^2) atan(x/sqrt(1+y^2))],
//!   side, [y0, y1]x[z0, z1]: dF = Psi(y1,z1) - Psi(y0,z1) - Psi(y1,z0) + Psi(y0,z0),
//!     Psi(y,z) = (1/2pi)[atan y - atan(y/sqrt(1+z^2)) / sqrt(1+z^2)],
//!
//! so the five faces sum to 1 up to rounding (no normalisation drift as with midpoint deltas).
//!
//! Depth: the inverse ray parameter w = 1/t along the ray through face point (a, b, 1) is
//! affine in (a, b) for a planar polygon (w = (m . (a,b,1)) / h with m the polygon normal in
//! face coordinates and h = m . X0 < 0 for a front face), so it is evaluated exactly at every
//! cell centre; larger w is nearer.
//!
//! Error (docs/algorithms.md §2.4): aliasing of projected polygons (about 1-3 % per pair once a
//! receiver covers 10 x 10 cells), proximity (the centre is not the patch: use several source
//! points), and partial visibility. Random rotation about the normal per sample point turns
//! the structured aliasing into noise that averages out over points and patches.

use super::{check_near, check_row, place_points, row_over_points, Accum, Points, RowResult, SourcePoints};
use crate::error::{Error, Result};
use crate::geometry::{Polygon, Vec3};
use crate::registry::method_options;
use std::cell::RefCell;
use std::f64::consts::PI;

/// Item-buffer value of a cell that sees nothing.
const EMPTY: u32 = u32::MAX;
/// Item-buffer value of a cell that sees a polygon's back side (blocked, received by none).
const BACK: u32 = u32::MAX - 1;

method_options! {
    /// Options of [`hemicube_row`].
    pub struct HemicubeOptions for "hemicube" {
        /// Cells per side of the top face (even, 4..=4096); side faces are R x R/2.
        /// Default 128 (about 49 000 cells per hemicube). With `row_tol`: the finest a row may use.
        resolution: u32,
        /// Target aliasing error per entry, in [0, 0.5]; 0 (default) renders at `resolution`. Else
        /// a row is rendered at 16, 24, 32, 48, 64, 96, ... cells (capped at `resolution`) and stops
        /// at the first where every entry's estimated aliasing error (the standard deviation over
        /// the random rotations, from the cells along its outline) is at most `row_tol` and an entry
        /// no cell saw is below `row_tol` too (docs/algorithms.md §2.5). Needs `random_rotation`.
        row_tol: f64,
        /// Sample points on the source. Default [`SourcePoints::Auto`].
        source: SourcePoints,
        /// Rotate the cube about the normal by a random angle per sample point. Default true.
        random_rotation: bool,
        /// Seed of the rotations and source points (results are reproducible per seed). Default 0.
        seed: u64,
    }
    fixed {
        /// Near-plane distance relative to the source patch radius, in (0, 0.1]. Geometry closer
        /// to the eye than this (a thin band of adjacent patches) is lost. Default 1e-6.
        near: f64 = 1e-6,
    }
    check(o) {
        let r = o.resolution;
        if !r.is_multiple_of(2) {
            return Err(Error::InvalidArgument(format!("method \"hemicube\": option resolution={r} must be even")));
        }
        if o.row_tol > 0.0 && !o.random_rotation {
            return Err(Error::InvalidArgument(format!(
                "method \"hemicube\": option row_tol={} needs random_rotation=true (its error estimate is the spread \
                 over random rotations of the cube)",
                o.row_tol
            )));
        }
        check_near("hemicube", o.near)
    }
}

/// Phi(x, y): form factor from a differential element to the rectangle [0, x]x[0, y] of the
/// plane at height 1 (Howell B-3, odd in x and in y). 4 Phi(1,1) = 0.5541264 (top face).
pub fn phi(x: f64, y: f64) -> f64 {
    let sx = (1.0 + x * x).sqrt();
    let sy = (1.0 + y * y).sqrt();
    (x / sx * (y / sx).atan() + y / sy * (x / sy).atan()) / (2.0 * PI)
}

/// Psi(y, z): form factor from a differential element (normal z) to [0, y]x[0, z] of the side
/// plane x = 1. 2 Psi(1,1) = 0.1114684 (one side face).
pub fn psi(y: f64, z: f64) -> f64 {
    let s = (1.0 + z * z).sqrt();
    (y.atan() - (y / s).atan() / s) / (2.0 * PI)
}

/// Exact delta form factor of the top-face cell [x0, x1]x[y0, y1] (plane z = 1).
pub fn top_cell(x0: f64, x1: f64, y0: f64, y1: f64) -> f64 {
    phi(x1, y1) - phi(x0, y1) - phi(x1, y0) + phi(x0, y0)
}

/// Exact delta form factor of the side-face cell [y0, y1]x[z0, z1] (plane x = 1, z >= 0).
pub fn side_cell(y0: f64, y1: f64, z0: f64, z1: f64) -> f64 {
    psi(y1, z1) - psi(y0, z1) - psi(y1, z0) + psi(y0, z0)
}

/// Face k maps local (x, y, z) to face coordinates (a, b, depth): top, +x, -x, +y, -y.
/// Each map is orthogonal, so the plane offset h and the front/back test are face independent.
#[inline]
fn to_face(k: usize, q: Vec3) -> Vec3 {
    match k {
        0 => q,
        1 => Vec3::new(q.y, q.z, q.x),
        2 => Vec3::new(q.y, q.z, -q.x),
        3 => Vec3::new(q.x, q.z, q.y),
        _ => Vec3::new(q.x, q.z, -q.y),
    }
}

/// Per-thread buffers: delta tables, z-buffer and item buffer of the five faces, clip space.
#[derive(Default)]
struct Scratch {
    res: usize,
    /// dF per cell: top R*R (row-major in b), then the side R/2 x R table (shared by the 4 sides).
    top: Vec<f64>,
    side: Vec<f64>,
    depth: Vec<f64>,
    item: Vec<u32>,
    local: Vec<Vec3>,
    /// Per patch: the aliasing variance of its entry (`row_tol`).
    var: Accum,
    /// Source points of a `row_tol` row (for their weights).
    points: Vec<(Vec3, f64)>,
    clip_a: Vec<Vec3>,
    clip_b: Vec<Vec3>,
    proj: Vec<[f64; 2]>,
    xs: Vec<f64>,
}

impl Scratch {
    /// Cell tables for `res` (computed once per resolution) and cleared buffers; false when
    /// cancelled or over budget while the tables were being computed (they are then left
    /// invalid, to be computed again by the next call).
    fn prepare(&mut self, res: usize) -> bool {
        if self.res != res {
            self.res = 0;
            let h = 2.0 / res as f64;
            // each cell is the difference of Phi (Psi) at its four corners: evaluate the
            // corners once per row of cells (the same values as `top_cell` / `side_cell`)
            let (mut lo, mut hi) = (vec![0.0; res + 1], vec![0.0; res + 1]);
            self.top.clear();
            self.top.reserve(res * res);
            for row in 0..res {
                // [methods] a row of corners at a time, so that Ctrl-C is seen at 4096 cells
                if !crate::work::go_on() {
                    return false;
                }
                let (y0, y1) = (-1.0 + row as f64 * h, -1.0 + (row as f64 + 1.0) * h);
                for (k, (l, u)) in lo.iter_mut().zip(hi.iter_mut()).enumerate() {
                    let x = -1.0 + k as f64 * h;
                    (*l, *u) = (phi(x, y0), phi(x, y1));
                }
                self.top.extend((0..res).map(|c| hi[c + 1] - hi[c] - lo[c + 1] + lo[c]));
            }
            self.side.clear();
            self.side.reserve(res * res / 2);
            for row in 0..res / 2 {
                if !crate::work::go_on() {
                    return false;
                }
                let (z0, z1) = (row as f64 * h, (row as f64 + 1.0) * h);
                for (k, (l, u)) in lo.iter_mut().zip(hi.iter_mut()).enumerate() {
                    let y = -1.0 + k as f64 * h;
                    (*l, *u) = (psi(y, z0), psi(y, z1));
                }
                self.side.extend((0..res).map(|c| hi[c + 1] - hi[c] - lo[c + 1] + lo[c]));
            }
            self.res = res;
        }
        let cells = 3 * res * res;
        self.depth.clear();
        self.depth.resize(cells, 0.0);
        self.item.clear();
        self.item.resize(cells, EMPTY);
        true
    }
}

thread_local! {
    static SCRATCH: RefCell<Scratch> = RefCell::new(Scratch::default());
}

/// Sutherland-Hodgman clip of a polygon to the half-space `f(q) >= c` where f picks one
/// coordinate (after `to_face`), allocation-free.
fn clip_coord(inp: &[Vec3], axis: usize, c: f64, out: &mut Vec<Vec3>) {
    out.clear();
    let n = inp.len();
    for k in 0..n {
        let (p, q) = (inp[k], inp[(k + 1) % n]);
        let (dp, dq) = (p[axis] - c, q[axis] - c);
        if dp >= 0.0 {
            out.push(p);
        }
        if (dp >= 0.0) != (dq >= 0.0) {
            let t = dp / (dp - dq);
            let mut x = p + (q - p) * t;
            x[axis] = c; // exactly on the plane, so the depth divide stays positive
            out.push(x);
        }
    }
}

/// Scan-converts a projected polygon into one face (cell-centre sampling, even-odd rule, so
/// concave outlines are filled correctly). `w` gives the inverse depth w = w0 a + w1 b + w2.
#[allow(clippy::too_many_arguments)]
fn rasterize(
    poly: &[[f64; 2]],
    w: [f64; 3],
    id: u32,
    b0: f64,
    res: usize,
    rows: usize,
    depth: &mut [f64],
    item: &mut [u32],
    xs: &mut Vec<f64>,
) {
    let h = 2.0 / res as f64;
    let (mut bmin, mut bmax) = (f64::INFINITY, f64::NEG_INFINITY);
    for p in poly {
        bmin = bmin.min(p[1]);
        bmax = bmax.max(p[1]);
    }
    // rows whose centre b0 + (r + 1/2) h lies in [bmin, bmax)
    let r_lo = ((bmin - b0) / h - 0.5).ceil().clamp(0.0, rows as f64) as usize;
    let r_hi = ((bmax - b0) / h - 0.5).ceil().clamp(0.0, rows as f64) as usize;
    let n = poly.len();
    for r in r_lo..r_hi {
        let y = b0 + (r as f64 + 0.5) * h;
        xs.clear();
        for k in 0..n {
            let (p, q) = (poly[k], poly[(k + 1) % n]);
            if (p[1] <= y) != (q[1] <= y) {
                xs.push(p[0] + (y - p[1]) * (q[0] - p[0]) / (q[1] - p[1]));
            }
        }
        xs.sort_unstable_by(|a, b| a.total_cmp(b));
        let wy = w[1] * y + w[2];
        for span in xs.chunks_exact(2) {
            // columns whose centre -1 + (c + 1/2) h lies in [x0, x1)
            let c_lo = ((span[0] + 1.0) / h - 0.5).ceil().clamp(0.0, res as f64) as usize;
            let c_hi = ((span[1] + 1.0) / h - 0.5).ceil().clamp(0.0, res as f64) as usize;
            let base = r * res;
            for c in c_lo..c_hi {
                let a = -1.0 + (c as f64 + 0.5) * h;
                let wv = w[0] * a + wy;
                let cell = base + c;
                if wv > depth[cell] {
                    depth[cell] = wv;
                    item[cell] = id;
                }
            }
        }
    }
}

/// Row i of the form-factor matrix by the hemicube.
///
/// `receivers[j]` says whether column j is reported; non-receivers still block. The source
/// itself is skipped. F_ij = sum_k w_k sum_{cells of face sets at point k showing j} dF.
/// With `row_tol` the row's `samples` is the resolution it stopped at.
pub fn hemicube_row(scene: &[Polygon], receivers: &[bool], i: usize, opts: &HemicubeOptions) -> Result<RowResult> {
    opts.check()?;
    SCRATCH.with(|s| {
        let s = &mut *s.borrow_mut();
        if opts.row_tol > 0.0 {
            row_to_tolerance(s, scene, receivers, i, opts)
        } else {
            render_row(s, scene, receivers, i, opts, opts.resolution as usize, false)
        }
    })
}

/// The resolutions a `row_tol` row is rendered at: the first of 16, 24, 32, 48, 64, 96, ...
/// (2^k and 3 x 2^(k-1), each at most 1.5x the one before) that is at least `r`.
fn ladder_at_least(r: f64) -> usize {
    let mut a = 16usize;
    while (a as f64) < r && a < 1 << 20 {
        a = if a.is_power_of_two() { a / 2 * 3 } else { a / 3 * 4 };
    }
    a
}

/// A row rendered at increasing resolutions until its aliasing estimate meets `row_tol`
/// (docs/algorithms.md §2.5). Each rendering is the fixed-resolution row at that resolution.
fn row_to_tolerance(
    s: &mut Scratch,
    scene: &[Polygon],
    receivers: &[bool],
    i: usize,
    opts: &HemicubeOptions,
) -> Result<RowResult> {
    check_row(scene, receivers, i)?;
    let (tol, cap) = (opts.row_tol, opts.resolution as usize);
    // An entry that no cell saw at any source point: F <= min(1, 3 sum w_k^2) x the largest
    // cell's dF at 95 % (`unseen`), so the first rendering is the coarsest where that meets tol.
    let mut pts = std::mem::take(&mut s.points);
    place_points(scene, i, rule_points(opts), &mut pts);
    let unseen = (3.0 * pts.iter().map(|p| p.1 * p.1).sum::<f64>()).min(1.0);
    s.points = pts;
    let brightest = |r: usize| top_cell(0.0, 2.0 / r as f64, 0.0, 2.0 / r as f64);
    let mut res = 16usize;
    while res < cap && unseen * brightest(res) > tol {
        res = ladder_at_least(res as f64 + 1.0);
    }
    loop {
        res = res.min(cap);
        let mut row = render_row(s, scene, receivers, i, opts, res, true)?;
        let err = s.var.max_over(receivers).sqrt();
        if err <= tol || res >= cap || !crate::work::go_on() {
            row.samples = res as u32;
            return Ok(row);
        }
        // the estimate falls like (cell size)^p, p from 1 (edges along the cells) to 3/2 (edges
        // across them): aim at the resolution p = 1.25 says meets tol
        res = ladder_at_least((res as f64 * (err / tol).powf(0.8)).max(res as f64 + 1.0));
    }
}

fn rule_points(opts: &HemicubeOptions) -> Points {
    Points::Rule { source: opts.source, seed: opts.seed, rotation: opts.random_rotation.then_some(0x0420_7A7E) }
}

/// The row at resolution `res`; with `estimate`, `s.var` holds each patch's aliasing variance.
fn render_row(
    s: &mut Scratch,
    scene: &[Polygon],
    receivers: &[bool],
    i: usize,
    opts: &HemicubeOptions,
    res: usize,
    estimate: bool,
) -> Result<RowResult> {
    if estimate {
        s.var.reset(scene.len());
    }
    let mut row = row_over_points(scene, receivers, i, rule_points(opts), |eye, acc, lost| {
        let near = opts.near * scene[i].radius();
        // Eye a hair above the element: nothing of the source plane can be in front.
        let at = eye.p + eye.n * (0.5 * near);
        // one work unit per cell; stop at cancellation or over budget
        if !crate::work::spend(3 * (res * res) as u64) {
            return false;
        }
        if !s.prepare(res) {
            return false;
        }
        for (j, poly) in scene.iter().enumerate() {
            if j == i || (j % 256 == 0 && !crate::work::go_on()) {
                continue;
            }
            project_polygon(s, poly, j as u32, at, eye.u, eye.v, eye.n, near, res);
        }
        *lost += eye.weight * accumulate(s, acc, res, eye.weight);
        if estimate {
            add_outline_variance(s, res, eye.weight * eye.weight);
        }
        true
    })?;
    row.lost = row.lost.max(0.0);
    Ok(row)
}

/// Adds weight^2 x the aliasing variance of this rendering to `s.var` for every patch
/// (docs/algorithms.md §2.5). Two neighbouring cells of one face that show different items
/// mark a cell cut by an outline; its centre sample is off by dF (1 - p) or -dF p, p the
/// covered part, variance p (1 - p) dF^2, 1/6 dF^2 on average. Cuts in a straight run (the same
/// pair of items across consecutive rows or columns, as where an edge lies along the cells:
/// every edge parallel to the normal does on the side faces, whatever the rotation) may all
/// be off the same way, so a run counts as one error of the run's summed dF.
fn add_outline_variance(s: &mut Scratch, res: usize, weight2: f64) {
    let Scratch { top, side, item, var, .. } = s;
    let mut close = |run: &mut (u32, u32, f64)| {
        let v = weight2 * run.2 * run.2 / 6.0;
        for j in [run.0, run.1] {
            if v > 0.0 && j != EMPTY && j != BACK {
                var.add(j, v);
            }
        }
        *run = (EMPTY, EMPTY, 0.0);
    };
    let side_len = res * res / 2;
    for f in 0..5 {
        let (off, rows, table): (usize, usize, &[f64]) =
            if f == 0 { (0, res, top) } else { (res * res + (f - 1) * side_len, res / 2, side) };
        let cells = &item[off..off + rows * res];
        // cuts between columns c and c + 1, run along the rows; then between rows, along columns
        for (n_out, n_in, step_out, step_in, next) in [(res - 1, rows, 1, res, 1), (rows - 1, res, res, 1, res)] {
            for o in 0..n_out {
                let mut run = (EMPTY, EMPTY, 0.0);
                for m in 0..n_in {
                    let k = o * step_out + m * step_in;
                    let (a, b) = (cells[k], cells[k + next]);
                    if a == b {
                        close(&mut run);
                    } else {
                        if (a, b) != (run.0, run.1) {
                            close(&mut run);
                            (run.0, run.1) = (a, b);
                        }
                        run.2 += 0.5 * (table[k] + table[k + next]);
                    }
                }
                close(&mut run);
            }
        }
    }
}

/// Clips `poly` to the element's front half-space, then per face to the near plane, and
/// scan-converts it.
#[allow(clippy::too_many_arguments)]
fn project_polygon(
    s: &mut Scratch,
    poly: &Polygon,
    id: u32,
    eye: Vec3,
    u: Vec3,
    v: Vec3,
    n: Vec3,
    near: f64,
    res: usize,
) {
    let zmax = super::to_local(poly, eye, [u, v, n], &mut s.local);
    if zmax <= near {
        return; // behind the element (or in its plane)
    }
    let nj = poly.normal();
    let hh = nj.dot(poly.centroid() - eye);
    if hh.abs() <= 1e-12 * (poly.radius() + (poly.centroid() - eye).length()) {
        return; // seen edge-on: covers no area
    }
    let id = if hh < 0.0 { id } else { BACK };
    let m = Vec3::new(nj.dot(u), nj.dot(v), nj.dot(n));
    // Element plane (z >= near) first, shared by all faces.
    let mut elem = std::mem::take(&mut s.clip_a);
    clip_coord(&s.local, 2, near, &mut elem);
    if elem.len() < 3 {
        s.clip_a = elem;
        return;
    }
    let mut face_poly = std::mem::take(&mut s.clip_b);
    let mut clipped = std::mem::take(&mut s.local);
    for f in 0..5 {
        // quick frustum rejection in face coordinates
        let (mut all_a_hi, mut all_a_lo, mut all_b_hi, mut all_near) = (true, true, true, true);
        face_poly.clear();
        for q in &elem {
            let t = to_face(f, *q);
            all_a_hi &= t.x > t.z;
            all_a_lo &= t.x < -t.z;
            all_b_hi &= t.y > t.z;
            all_near &= t.z <= near;
            face_poly.push(t);
        }
        let all_b_lo = f == 0 && face_poly.iter().all(|t| t.y < -t.z);
        if all_a_hi || all_a_lo || all_b_hi || all_near || all_b_lo {
            continue;
        }
        clip_coord(&face_poly, 2, near, &mut clipped);
        if clipped.len() < 3 {
            continue;
        }
        s.proj.clear();
        s.proj.extend(clipped.iter().map(|t| [t.x / t.z, t.y / t.z]));
        let mf = to_face(f, m);
        let w = [mf.x / hh, mf.y / hh, mf.z / hh];
        let (b0, rows, off) = if f == 0 { (-1.0, res, 0) } else { (0.0, res / 2, res * res + (f - 1) * res * res / 2) };
        let len = rows * res;
        rasterize(&s.proj, w, id, b0, res, rows, &mut s.depth[off..off + len], &mut s.item[off..off + len], &mut s.xs);
    }
    s.local = clipped;
    s.clip_a = elem;
    s.clip_b = face_poly;
}

/// Adds weight * dF of every covered cell to its patch; returns the lost fraction (cells that
/// see nothing or a back side).
fn accumulate(s: &Scratch, acc: &mut Accum, res: usize, weight: f64) -> f64 {
    let mut lost = 0.0;
    let side_len = res * res / 2;
    for f in 0..5 {
        let (off, table): (usize, &[f64]) =
            if f == 0 { (0, &s.top) } else { (res * res + (f - 1) * side_len, &s.side) };
        for (c, &df) in table.iter().enumerate() {
            match s.item[off + c] {
                EMPTY | BACK => lost += df,
                j => acc.add(j, weight * df),
            }
        }
    }
    lost
}

#[cfg(test)]
mod tests {
    use super::super::testkit::*;
    use super::*;

    #[test]
    fn exact_face_sums() {
        let top = 4.0 * phi(1.0, 1.0);
        let side = 2.0 * psi(1.0, 1.0);
        assert!((top - 0.5541264).abs() < 5e-8, "{top}");
        assert!((side - 0.1114684).abs() < 5e-8, "{side}");
        assert!((top + 4.0 * side - 1.0).abs() < 1e-14, "{}", top + 4.0 * side - 1.0);
        // cell tables sum to the same, at any resolution
        for res in [4usize, 50, 128] {
            let mut s = Scratch::default();
            assert!(s.prepare(res));
            let total: f64 = s.top.iter().sum::<f64>() + 4.0 * s.side.iter().sum::<f64>();
            assert!((total - 1.0).abs() < 1e-13, "res {res}: {total}");
            // the tables from corner rows are the cell formulas, bit for bit
            let h = 2.0 / res as f64;
            for (c, &t) in s.top.iter().enumerate() {
                let (col, row) = ((c % res) as f64, (c / res) as f64);
                let want = top_cell(-1.0 + col * h, -1.0 + (col + 1.0) * h, -1.0 + row * h, -1.0 + (row + 1.0) * h);
                assert_eq!(t.to_bits(), want.to_bits(), "res {res} top cell {c}");
            }
            for (c, &t) in s.side.iter().enumerate() {
                let (col, row) = ((c % res) as f64, (c / res) as f64);
                let want = side_cell(-1.0 + col * h, -1.0 + (col + 1.0) * h, row * h, (row + 1.0) * h);
                assert_eq!(t.to_bits(), want.to_bits(), "res {res} side cell {c}");
            }
        }
        // Phi and Psi against midpoint integration of the kernels over a cell
        let m = 400;
        let (x0, x1, y0, y1) = (0.2, 0.7, -0.3, 0.4);
        let (mut ft, mut fs) = (0.0, 0.0);
        for a in 0..m {
            for b in 0..m {
                let x = x0 + (x1 - x0) * (a as f64 + 0.5) / m as f64;
                let y = y0 + (y1 - y0) * (b as f64 + 0.5) / m as f64;
                let da = (x1 - x0) * (y1 - y0) / (m * m) as f64;
                ft += da / (PI * (x * x + y * y + 1.0).powi(2));
                let (yy, z) = (x, (y - y0) / (y1 - y0) * 0.5 + 0.1); // side cell [0.2,0.7]x[0.1,0.6]
                fs += z * ((x1 - x0) * 0.5 / (m * m) as f64) / (PI * (yy * yy + z * z + 1.0).powi(2));
            }
        }
        assert!((ft - top_cell(x0, x1, y0, y1)).abs() < 1e-7, "{ft}");
        assert!((fs - side_cell(x0, x1, 0.1, 0.6)).abs() < 1e-7, "{fs}");
    }

    fn tiny_source_facing(scene_rest: Vec<Polygon>, centre: Vec3, n: Vec3) -> Vec<Polygon> {
        let (t, b) = crate::geometry::tangent_frame(n);
        let e = 1e-4;
        let src = quad(centre - t * e - b * e, centre + t * e - b * e, centre + t * e + b * e, centre - t * e + b * e);
        assert!((src.normal() - n).length() < 1e-12);
        let mut s = vec![src];
        s.extend(scene_rest);
        s
    }

    #[test]
    fn point_to_square_matches_lambert() {
        let exact = 4.0 * corner_rect(0.5, 0.5); // 0.239456
        let recv = quad(
            Vec3::new(-0.5, -0.5, 1.),
            Vec3::new(-0.5, 0.5, 1.),
            Vec3::new(0.5, 0.5, 1.),
            Vec3::new(0.5, -0.5, 1.),
        );
        let scene = tiny_source_facing(vec![recv], Vec3::ZERO, Vec3::Z);
        let rec = vec![true; 2];
        // res a multiple of 4: the outline x, y = +-0.5 lies on cell boundaries, so the
        // exact cell integrals must reproduce the exact value
        for res in [32u32, 128] {
            let o = HemicubeOptions {
                resolution: res,
                source: SourcePoints::Centre,
                random_rotation: false,
                ..Default::default()
            };
            let r = hemicube_row(&scene, &rec, 0, &o).unwrap();
            let f = r.get(1);
            assert!((f - exact).abs() < 1e-12, "res {res}: {f} vs {exact}");
            assert!((r.lost - (1.0 - f)).abs() < 1e-12);
        }
        // rotated: the outline cuts cells; error bounded by the outline cells' dF (about
        // 2 res cells of dF <= 4/(pi res^2)) and shrinking with resolution
        let mut errs = Vec::new();
        for res in [34u32, 130, 514] {
            let o = HemicubeOptions { resolution: res, source: SourcePoints::Centre, seed: 3, ..Default::default() };
            let f = hemicube_row(&scene, &rec, 0, &o).unwrap().get(1);
            let bound = 8.0 / (PI * res as f64);
            assert!((f - exact).abs() < bound, "res {res}: {f} vs {exact}");
            errs.push((f - exact).abs());
        }
        assert!(errs[2] < errs[0] && errs[2] < 1e-3, "{errs:?}");
    }

    #[test]
    fn occluded_half() {
        // Source at origin facing +z; receiver [-.5,.5]^2 at z = 2; blocker [-.5,0]x[-.5,.5]
        // at z = 1 shadows exactly the receiver's x < 0 half.
        let scene = tiny_source_facing(half_blocked().to_vec(), Vec3::ZERO, Vec3::Z);
        let rec = vec![true; 3];
        let o = HemicubeOptions { resolution: 512, source: SourcePoints::Centre, ..Default::default() };
        let r = hemicube_row(&scene, &rec, 0, &o).unwrap();
        let (fr, fb) = (2.0 * corner_rect(0.25, 0.25), 2.0 * corner_rect(0.5, 0.5));
        assert!((r.get(1) - fr).abs() < 1e-3, "{} vs {fr}", r.get(1));
        assert!((r.get(2) - fb).abs() < 2e-3, "{} vs {fb}", r.get(2));
        // blocker as a non-receiver: still blocks, not reported, not lost
        let r2 = hemicube_row(&scene, &[true, true, false], 0, &o).unwrap();
        assert_eq!(r2.entries.len(), 1);
        assert!((r2.get(1) - r.get(1)).abs() < 1e-15);
        assert!((r2.lost - r.lost).abs() < 1e-15);
        // blocker turned around: its back side blocks the same cells, which are now lost
        let mut flipped = scene.clone();
        let mut v = flipped[2].vertices().to_vec();
        v.reverse();
        flipped[2] = Polygon::new(v).unwrap();
        let r3 = hemicube_row(&flipped, &rec, 0, &o).unwrap();
        assert_eq!(r3.get(2), 0.0);
        assert!((r3.get(1) - r.get(1)).abs() < 1e-15);
        assert!((r3.lost - (r.lost + r.get(2))).abs() < 1e-12);
    }

    #[test]
    fn area_pairs_converge_with_source_points() {
        let par = parallel_squares(1.0);
        let per = perpendicular_squares();
        let (ep, eq) = (parallel_rect(1., 1., 1.), perpendicular_rect(1., 1., 1.));
        let mut errs = Vec::new();
        for n in [4u32, 256] {
            let o = HemicubeOptions { resolution: 128, source: SourcePoints::Points(n), ..Default::default() };
            let fp = hemicube_row(&par, &[true, true], 0, &o).unwrap().get(1);
            let fq = hemicube_row(&per, &[true, true], 0, &o).unwrap().get(1);
            let err = (fp - ep).abs().max((fq - eq).abs());
            errs.push(err);
            eprintln!("hemicube points {n}: parallel {fp} vs {ep}, perpendicular {fq} vs {eq}");
        }
        assert!(errs[0] < 0.03 && errs[1] < 3e-3 && errs[1] < errs[0], "{errs:?}");
        // 3 x 3 Gauss points: the smooth proximity variation is integrated almost exactly,
        // what is left is aliasing at res 256
        let o = HemicubeOptions { resolution: 256, source: SourcePoints::Gauss(3), ..Default::default() };
        let fp = hemicube_row(&par, &[true, true], 0, &o).unwrap().get(1);
        let fq = hemicube_row(&per, &[true, true], 0, &o).unwrap().get(1);
        assert!((fp - ep).abs() < 3e-4 && (fq - eq).abs() < 3e-4, "{fp} {fq}");
        // centre only: the proximity error of docs/algorithms.md §2.4 (+20 % at d = side)
        let o = HemicubeOptions {
            resolution: 256,
            source: SourcePoints::Centre,
            random_rotation: false,
            ..Default::default()
        };
        let fc = hemicube_row(&par, &[true, true], 0, &o).unwrap().get(1);
        assert!((fc - 4.0 * corner_rect(0.5, 0.5)).abs() < 3e-3, "{fc}");
    }

    #[test]
    fn closed_cube_rows_sum_to_one() {
        let scene = closed_box(Vec3::ZERO, Vec3::ONE, 3, true);
        let rec = vec![true; scene.len()];
        let o = HemicubeOptions::default();
        for i in [0usize, 4, 13, 31, 53] {
            let r = hemicube_row(&scene, &rec, i, &o).unwrap();
            // cells are exactly partitioned; only the near-plane band can be lost
            assert!((r.sum() - 1.0).abs() < 1e-6, "row {i}: {}", r.sum());
            assert!(r.lost < 1e-6);
            assert!(r.entries.iter().all(|e| e.0 as usize != i && e.1 > 0.0));
        }
    }

    #[test]
    fn seeded_and_reproducible() {
        let scene = closed_box(Vec3::ZERO, Vec3::ONE, 2, true);
        let rec = vec![true; scene.len()];
        let o = HemicubeOptions { resolution: 32, source: SourcePoints::Points(4), seed: 9, ..Default::default() };
        let a = hemicube_row(&scene, &rec, 5, &o).unwrap();
        let b = hemicube_row(&scene, &rec, 5, &o).unwrap();
        assert_eq!(a, b);
        let c = hemicube_row(&scene, &rec, 5, &HemicubeOptions { seed: 10, ..o }).unwrap();
        assert_ne!(a, c);
    }

    #[test]
    fn scale_invariant() {
        let o = HemicubeOptions { resolution: 64, source: SourcePoints::Points(4), ..Default::default() };
        let base = closed_box(Vec3::ZERO, Vec3::new(1., 2., 3.), 2, true);
        let a = hemicube_row(&base, &[true; 24], 3, &o).unwrap();
        for s in [1e-3, 1e3] {
            let sc: Vec<Polygon> =
                base.iter().map(|p| Polygon::new(p.vertices().iter().map(|v| *v * s).collect()).unwrap()).collect();
            let b = hemicube_row(&sc, &[true; 24], 3, &o).unwrap();
            assert_eq!(a.entries.len(), b.entries.len());
            for (x, y) in a.entries.iter().zip(&b.entries) {
                assert_eq!(x.0, y.0);
                assert!((x.1 - y.1).abs() < 1e-9, "scale {s}: {x:?} {y:?}");
            }
        }
    }

    /// A near-point source (half-width 1e-5 at the origin, facing +z) and receivers with
    /// their exact F from the point: a unit square on axis, a small square off axis, a wall
    /// standing on the horizon (edges along the side faces' cells).
    fn lambert_cases() -> Vec<(Vec<Polygon>, f64)> {
        let small = (Vec3::new(0.3, 0.2, 1.), Vec3::new(0.05, 0., 0.), Vec3::new(0., 0.05, 0.));
        let wall = (Vec3::new(2., -1., 0.), Vec3::new(0., 2., 0.), Vec3::new(0., 0., 1.));
        let sq = |(o, u, v): (Vec3, Vec3, Vec3)| quad(o, o + v, o + u + v, o + u); // facing the origin
        let f = |(o, u, v): (Vec3, Vec3, Vec3)| point_to_polygon_midpoint(Vec3::ZERO, Vec3::Z, o, u, v, 1000);
        let unit = (Vec3::new(-0.5, -0.5, 1.), Vec3::new(1., 0., 0.), Vec3::new(0., 1., 0.));
        [unit, small, wall]
            .into_iter()
            .map(|g| {
                (
                    vec![small_square(Vec3::ZERO, 1e-5), sq(g)],
                    if g == unit { 4.0 * corner_rect(0.5, 0.5) } else { f(g) },
                )
            })
            .collect()
    }

    #[test]
    fn row_tol_meets_its_target_against_lambert() {
        let rec = [true, true];
        for (scene, exact) in lambert_cases() {
            for tol in [1e-3, 1e-4] {
                let (mut e2, mut fixed2, n) = (0.0, 0.0, 24);
                for seed in 0..n {
                    let o = HemicubeOptions {
                        resolution: 4096,
                        row_tol: tol,
                        source: SourcePoints::Centre,
                        seed,
                        ..Default::default()
                    };
                    let r = hemicube_row(&scene, &rec, 0, &o).unwrap();
                    let res = r.samples;
                    assert!(res >= 16 && (res as usize) == ladder_at_least(res as f64), "{res}");
                    // the row is the fixed-resolution row at the resolution it stopped at
                    let fixed = HemicubeOptions { resolution: res, row_tol: 0.0, ..o };
                    assert_eq!(r.entries, hemicube_row(&scene, &rec, 0, &fixed).unwrap().entries);
                    e2 += (r.get(1) - exact).powi(2);
                    let coarse = HemicubeOptions { resolution: 16, row_tol: 0.0, ..o };
                    fixed2 += (hemicube_row(&scene, &rec, 0, &coarse).unwrap().get(1) - exact).powi(2);
                }
                let (rms, rms16) = ((e2 / n as f64).sqrt(), (fixed2 / n as f64).sqrt());
                eprintln!("F {exact:.3e} tol {tol:e}: rms error {rms:.2e} (resolution 16: {rms16:.2e})");
                // the error is a spread over the rotations: its rms meets the target
                assert!(rms <= tol, "F {exact}: rms {rms} for tol {tol}");
                assert!(rms16 > 2.0 * rms, "{rms16} {rms}");
            }
        }
    }

    #[test]
    fn row_tol_estimate_covers_the_spread() {
        // at fixed resolutions: the rms of the real error over rotations is below the rms of the
        // estimate (the estimate is conservative: 0.2-0.6x measured)
        let rec = [true, true];
        for (scene, exact) in lambert_cases() {
            for res in [64usize, 256] {
                let (mut e2, mut s2, n) = (0.0, 0.0, 32);
                for seed in 0..n {
                    let o = HemicubeOptions { source: SourcePoints::Centre, seed, ..Default::default() };
                    SCRATCH.with(|s| {
                        let s = &mut *s.borrow_mut();
                        let r = render_row(s, &scene, &rec, 0, &o, res, true).unwrap();
                        e2 += (r.get(1) - exact).powi(2);
                        s2 += s.var.max_over(&rec);
                    });
                }
                assert!(
                    e2 < s2,
                    "F {exact} res {res}: rms error {} estimate {}",
                    (e2 / n as f64).sqrt(),
                    (s2 / n as f64).sqrt()
                );
            }
        }
    }

    #[test]
    fn row_tol_rows_close_in_a_box() {
        let scene = closed_box(Vec3::ZERO, Vec3::ONE, 3, true);
        let rec = vec![true; scene.len()];
        for i in [0usize, 13, 40] {
            let o = HemicubeOptions { resolution: 512, row_tol: 2e-3, ..Default::default() };
            let r = hemicube_row(&scene, &rec, i, &o).unwrap();
            assert!((r.sum() - 1.0).abs() < 1e-6 && r.lost < 1e-6, "row {i}: {}", r.sum());
            assert!(r.entries.iter().all(|e| e.1 > 0.0) && r.samples <= 512);
        }
        // the cap holds
        let o = HemicubeOptions { resolution: 40, row_tol: 1e-6, ..Default::default() };
        assert_eq!(hemicube_row(&scene, &rec, 0, &o).unwrap().samples, 40);
    }

    #[test]
    fn bad_input() {
        let scene = parallel_squares(1.0);
        assert!(hemicube_row(&scene, &[true], 0, &HemicubeOptions::default()).is_err());
        assert!(hemicube_row(&scene, &[true, true], 2, &HemicubeOptions::default()).is_err());
        for o in [
            HemicubeOptions { resolution: 0, ..Default::default() },
            HemicubeOptions { resolution: 33, ..Default::default() },
            HemicubeOptions { resolution: 1 << 30, ..Default::default() },
            HemicubeOptions { near: f64::NAN, ..Default::default() },
            HemicubeOptions { row_tol: -1e-3, ..Default::default() },
            HemicubeOptions { row_tol: f64::NAN, ..Default::default() },
            HemicubeOptions { row_tol: 0.6, ..Default::default() },
            HemicubeOptions { row_tol: 1e-3, random_rotation: false, ..Default::default() },
            HemicubeOptions { near: 0.0, ..Default::default() },
            HemicubeOptions { source: SourcePoints::Points(0), ..Default::default() },
            HemicubeOptions { source: SourcePoints::Points(1_000_000_000), ..Default::default() },
        ] {
            let e = hemicube_row(&scene, &[true, true], 0, &o).unwrap_err();
            assert!(matches!(e, Error::InvalidArgument(_)), "{e}");
        }
    }
}
