//! Single-plane method (Sillion & Puech, SIGGRAPH '89) with Warnock area subdivision.
//!
//! One plane parallel to the element at height 1 over the sample point, restricted to the
//! window [-a, a]^2, replaces the hemicube (docs/algorithms.md §3). Polygons are clipped to z >= near
//! and projected through the eye onto the plane; projection preserves the projected solid
//! angle, so the form factor of any region of the plane is that of its preimage. A region's
//! form factor is exact: for a rectangle the Phi four-term difference (see
//! [`super::hemicube::top_cell`]), for a polygon P of the plane Lambert's formula
//! (docs/algorithms.md §1.3) with vertices R_k = (x_k, y_k, 1):
//!
//!   F = (1/2pi) |sum_k atan2(|R_k x R_k+1|, R_k . R_k+1) (z . (R_k x R_k+1)) / |R_k x R_k+1||.
//!
//! Visibility by Warnock's recursion on windows (quadtree over the plane):
//! 0. no polygon overlaps the window: nothing there (lost if the scene is open);
//! 1. the overlapping polygons all lie in one plane (e.g. one polygon, or several patches of
//!    one wall, which cannot hide each other): each gets the Lambert value of its part
//!    clipped to the window;
//! 2. the polygons of one plane cover the window and every other overlapping polygon is behind
//!    that plane at the four window corners (inverse depth is affine over the window): that
//!    plane's polygons get their clipped Lambert values;
//! 3. else split into four, until the window carries at most min_cell^2/pi of form factor
//!    (a window of side min_cell at the centre, larger towards the rim where the kernel
//!    1/(pi(1+r^2)^2) is small); such a leaf goes whole to the nearest polygon at its centre.
//!
//! Polygons of one plane are assumed not to overlap (a valid mesh); if their clipped areas
//! add up to more than the window, rules 1-2 are skipped and the window is subdivided.
//!
//! Directions below elevation atan(1/a) (edge midpoints) to atan(1/(a sqrt 2)) (corners) miss
//! the plane: the captured part is 4 Phi(a, a) = (4/pi) s atan(s), s = a/sqrt(1+a^2)
//! (0.99584 for the default a = 14); the missed horizon band is reported in `RowResult::lost`.

use super::hemicube::{phi, top_cell};
use super::{check_near, row_over_points, Accum, Points, RowResult, SourcePoints};
use crate::error::Result;
use crate::geometry::{Polygon, Vec3};
use crate::registry::method_options;
use std::cell::RefCell;
use std::f64::consts::PI;

/// Id of a polygon seen from its back side: blocks, received by none.
const BACK: u32 = u32::MAX - 1;

method_options! {
    /// Options of [`single_plane_row`].
    pub struct SinglePlaneOptions for "single-plane" {
        /// Half-width a of the plane (height 1), in [0.5, 1e4]. Default 14: 0.42 % horizon loss.
        half_width: f64,
        /// Warnock leaf size: side of the smallest window at the plane centre (height 1), in
        /// [1e-4, 1]; leaves carry at most min_cell^2/pi of form factor. Default 1/128.
        min_cell: f64,
        /// Sample points on the source. Default [`SourcePoints::Auto`].
        source: SourcePoints,
        /// Random rotation of the plane about the normal per sample point. Default true.
        random_rotation: bool,
        /// Seed of rotations and source points. Default 0.
        seed: u64,
    }
    fixed {
        /// Near distance relative to the source radius, in (0, 0.1]. Default 1e-6.
        near: f64 = 1e-6,
    }
    check(o) {
        check_near("single-plane", o.near)
    }
}

impl SinglePlaneOptions {
    /// Fraction of the hemisphere the plane captures: 4 Phi(a, a).
    pub fn captured(&self) -> f64 {
        4.0 * phi(self.half_width, self.half_width)
    }
}

/// A polygon projected onto the plane and clipped to [-a, a]^2.
#[derive(Debug, Clone, Copy)]
struct Proj {
    start: usize,
    len: usize,
    id: u32,
    /// Inverse depth w = w0 x + w1 y + w2 along the ray through (x, y, 1).
    w: [f64; 3],
    bbox: [f64; 4],
}

#[derive(Default)]
struct Scratch {
    verts: Vec<[f64; 2]>,
    polys: Vec<Proj>,
    stack: Vec<u32>,
    /// clipped area of each stack entry (parallel to `stack`)
    areas: Vec<f64>,
    buf_a: Vec<[f64; 2]>,
    buf_b: Vec<[f64; 2]>,
    local: Vec<Vec3>,
    clip3: Vec<Vec3>,
    planes: Vec<u32>,
    /// form factor given to ids (receivers or not) at the current point
    assigned: f64,
    weight: f64,
    leaf_ff: f64,
}

thread_local! {
    static SCRATCH: RefCell<Scratch> = RefCell::new(Scratch::default());
}

/// Sutherland-Hodgman clip of a 2-D polygon to the axis-aligned rectangle.
fn clip_rect(inp: &[[f64; 2]], r: [f64; 4], tmp: &mut Vec<[f64; 2]>, out: &mut Vec<[f64; 2]>) {
    out.clear();
    out.extend_from_slice(inp);
    // (axis, bound, keep >= bound?)
    for (axis, c, ge) in [(0usize, r[0], true), (0, r[2], false), (1, r[1], true), (1, r[3], false)] {
        std::mem::swap(tmp, out);
        out.clear();
        let n = tmp.len();
        if n == 0 {
            return;
        }
        for k in 0..n {
            let (p, q) = (tmp[k], tmp[(k + 1) % n]);
            let (dp, dq) = if ge { (p[axis] - c, q[axis] - c) } else { (c - p[axis], c - q[axis]) };
            if dp >= 0.0 {
                out.push(p);
            }
            if (dp >= 0.0) != (dq >= 0.0) {
                let t = dp / (dp - dq);
                let mut x = [p[0] + (q[0] - p[0]) * t, p[1] + (q[1] - p[1]) * t];
                x[axis] = c;
                out.push(x);
            }
        }
    }
}

fn area2(p: &[[f64; 2]]) -> f64 {
    let n = p.len();
    let mut a = 0.0;
    for k in 0..n {
        let (u, v) = (p[k], p[(k + 1) % n]);
        a += u[0] * v[1] - u[1] * v[0];
    }
    0.5 * a
}

/// Lambert's formula for the polygon `p` of the plane z = 1 seen from the origin, normal z.
pub fn lambert_on_plane(p: &[[f64; 2]]) -> f64 {
    let n = p.len();
    let mut f = 0.0;
    for k in 0..n {
        let a = Vec3::new(p[k][0], p[k][1], 1.0);
        let b = Vec3::new(p[(k + 1) % n][0], p[(k + 1) % n][1], 1.0);
        let c = a.cross(b);
        let cl = c.length();
        if cl > 0.0 {
            f += cl.atan2(a.dot(b)) * c.z / cl;
        }
    }
    (f / (2.0 * PI)).abs()
}

fn inside(p: &[[f64; 2]], x: [f64; 2]) -> bool {
    let n = p.len();
    let mut c = false;
    for k in 0..n {
        let (a, b) = (p[k], p[(k + 1) % n]);
        if (a[1] > x[1]) != (b[1] > x[1]) && x[0] < a[0] + (x[1] - a[1]) * (b[0] - a[0]) / (b[1] - a[1]) {
            c = !c;
        }
    }
    c
}

#[inline]
fn weval(w: [f64; 3], x: f64, y: f64) -> f64 {
    w[0] * x + w[1] * y + w[2]
}

fn same_plane(a: [f64; 3], b: [f64; 3]) -> bool {
    let s = a[0].abs().max(a[1].abs()).max(a[2].abs()).max(b[0].abs()).max(b[1].abs()).max(b[2].abs());
    (0..3).all(|k| (a[k] - b[k]).abs() <= 1e-9 * s)
}

impl Scratch {
    fn assign(&mut self, acc: &mut Accum, id: u32, f: f64) {
        if id != BACK {
            acc.add(id, self.weight * f);
            self.assigned += f;
        }
    }

    /// Clips polygon `c` to window `r` into buf_b, returns its area.
    fn clip_to(&mut self, c: usize, r: [f64; 4]) -> f64 {
        let p = self.polys[c];
        let (mut tmp, mut out) = (std::mem::take(&mut self.buf_a), std::mem::take(&mut self.buf_b));
        clip_rect(&self.verts[p.start..p.start + p.len], r, &mut tmp, &mut out);
        let a = if out.len() >= 3 { area2(&out).abs() } else { 0.0 };
        self.buf_a = tmp;
        self.buf_b = out;
        a
    }

    /// Gives every listed polygon the Lambert value of its part inside the window.
    fn assign_clipped(
        &mut self,
        acc: &mut Accum,
        list: std::ops::Range<usize>,
        r: [f64; 4],
        plane_of: Option<[f64; 3]>,
    ) {
        for k in list {
            let c = self.stack[k] as usize;
            if let Some(w) = plane_of {
                if !same_plane(self.polys[c].w, w) {
                    continue;
                }
            }
            self.clip_to(c, r);
            if self.buf_b.len() >= 3 {
                let f = lambert_on_plane(&self.buf_b);
                let id = self.polys[c].id;
                self.assign(acc, id, f);
            }
        }
    }

    /// Warnock recursion on window r = [x0, y0, x1, y1] with candidates stack[cand].
    fn window(&mut self, acc: &mut Accum, r: [f64; 4], cand: std::ops::Range<usize>) {
        // one work unit per window and candidate; stop at cancellation or over budget
        if !crate::work::spend(cand.len() as u64 + 1) {
            return;
        }
        let start = self.stack.len();
        let wa = (r[2] - r[0]) * (r[3] - r[1]);
        for k in cand {
            let c = self.stack[k] as usize;
            let b = self.polys[c].bbox;
            if b[0] >= r[2] || b[2] <= r[0] || b[1] >= r[3] || b[3] <= r[1] {
                continue;
            }
            let a = self.clip_to(c, r);
            if a > 1e-14 * wa {
                self.stack.push(c as u32);
                self.areas.push(a);
            }
        }
        let end = self.stack.len();
        let list = start..end;
        if list.is_empty() {
            return;
        }
        // Rules 1 and 2: a plane group that is alone, or covers the window in front of the rest.
        self.planes.clear();
        for k in list.clone() {
            let w = self.polys[self.stack[k] as usize].w;
            if !self.planes.iter().any(|&q| same_plane(self.polys[self.stack[q as usize] as usize].w, w)) {
                self.planes.push(k as u32);
            }
        }
        let corners = [[r[0], r[1]], [r[2], r[1]], [r[0], r[3]], [r[2], r[3]]];
        for g in 0..self.planes.len() {
            let wg = self.polys[self.stack[self.planes[g] as usize] as usize].w;
            let mut cover = 0.0;
            let mut others_behind = true;
            for k in list.clone() {
                let w = self.polys[self.stack[k] as usize].w;
                if same_plane(w, wg) {
                    cover += self.areas[k];
                } else if others_behind {
                    others_behind =
                        corners.iter().all(|c| weval(w, c[0], c[1]) <= weval(wg, c[0], c[1]) * (1.0 + 1e-12));
                }
            }
            let alone = self.planes.len() == 1;
            let covers = cover >= wa * (1.0 - 1e-9);
            if cover <= wa * (1.0 + 1e-9) && (alone || (covers && others_behind)) {
                self.assign_clipped(acc, list.clone(), r, if alone { None } else { Some(wg) });
                self.stack.truncate(start);
                self.areas.truncate(start);
                return;
            }
        }
        let ff = top_cell(r[0], r[2], r[1], r[3]);
        if ff <= self.leaf_ff {
            // Leaf: nearest polygon at the centre takes the whole window.
            let (cx, cy) = (0.5 * (r[0] + r[2]), 0.5 * (r[1] + r[3]));
            let mut best: Option<(f64, u32)> = None;
            for k in list.clone() {
                let p = self.polys[self.stack[k] as usize];
                if inside(&self.verts[p.start..p.start + p.len], [cx, cy]) {
                    let w = weval(p.w, cx, cy);
                    let better = match best {
                        None => true,
                        Some((bw, bid)) => w > bw || (w == bw && bid == BACK),
                    };
                    if better {
                        best = Some((w, p.id));
                    }
                }
            }
            if let Some((_, id)) = best {
                self.assign(acc, id, ff);
            }
        } else {
            let (mx, my) = (0.5 * (r[0] + r[2]), 0.5 * (r[1] + r[3]));
            for q in [[r[0], r[1], mx, my], [mx, r[1], r[2], my], [r[0], my, mx, r[3]], [mx, my, r[2], r[3]]] {
                self.window(acc, q, list.clone());
            }
        }
        self.stack.truncate(start);
        self.areas.truncate(start);
    }
}

/// Row i of the form-factor matrix by the single-plane method; see the module notes.
/// `lost` includes the horizon band 1 - 4 Phi(a, a) the plane cannot see.
pub fn single_plane_row(
    scene: &[Polygon],
    receivers: &[bool],
    i: usize,
    opts: &SinglePlaneOptions,
) -> Result<RowResult> {
    opts.check()?;
    let a = opts.half_width;
    let root = [-a, -a, a, a];
    let rotation = opts.random_rotation.then_some(0x51_9A7E);
    let points = Points::Rule { source: opts.source, seed: opts.seed, rotation };
    SCRATCH.with(|s| {
        let mut s = s.borrow_mut();
        let s = &mut *s;
        s.leaf_ff = opts.min_cell * opts.min_cell / PI;
        row_over_points(scene, receivers, i, points, |eye, acc, lost| {
            let near = opts.near * scene[i].radius();
            let at = eye.p + eye.n * (0.5 * near);
            s.verts.clear();
            s.polys.clear();
            for (j, poly) in scene.iter().enumerate() {
                if j != i {
                    project(s, poly, j as u32, at, eye.u, eye.v, eye.n, near, root);
                }
            }
            s.stack.clear();
            s.areas.clear();
            s.stack.extend(0..s.polys.len() as u32);
            s.areas.resize(s.stack.len(), 0.0); // parallel to stack; root entries unused
            s.weight = eye.weight;
            s.assigned = 0.0;
            let all = 0..s.stack.len();
            s.window(acc, root, all);
            *lost += eye.weight * (1.0 - s.assigned).max(0.0);
            true
        })
    })
}

/// Clips `poly` to z >= near in the local frame, projects it onto z = 1 and clips it to the
/// plane window; stores it with its inverse-depth plane.
#[allow(clippy::too_many_arguments)]
fn project(s: &mut Scratch, poly: &Polygon, id: u32, eye: Vec3, u: Vec3, v: Vec3, n: Vec3, near: f64, root: [f64; 4]) {
    let zmax = super::to_local(poly, eye, [u, v, n], &mut s.local);
    if zmax <= near {
        return;
    }
    let nj = poly.normal();
    let h = nj.dot(poly.centroid() - eye);
    if h.abs() <= 1e-12 * (poly.radius() + (poly.centroid() - eye).length()) {
        return;
    }
    let id = if h < 0.0 { id } else { BACK };
    let m = Vec3::new(nj.dot(u), nj.dot(v), nj.dot(n));
    s.clip3.clear();
    let nl = s.local.len();
    for k in 0..nl {
        let (p, q) = (s.local[k], s.local[(k + 1) % nl]);
        let (dp, dq) = (p.z - near, q.z - near);
        if dp >= 0.0 {
            s.clip3.push(p);
        }
        if (dp >= 0.0) != (dq >= 0.0) {
            let mut x = p + (q - p) * (dp / (dp - dq));
            x.z = near;
            s.clip3.push(x);
        }
    }
    if s.clip3.len() < 3 {
        return;
    }
    let mut proj = std::mem::take(&mut s.buf_a);
    proj.clear();
    proj.extend(s.clip3.iter().map(|q| [q.x / q.z, q.y / q.z]));
    let mut tmp = std::mem::take(&mut s.buf_b);
    let mut out = Vec::new();
    clip_rect(&proj, root, &mut tmp, &mut out);
    s.buf_a = proj;
    s.buf_b = tmp;
    if out.len() < 3 || area2(&out).abs() <= 0.0 {
        return;
    }
    let mut bbox = [f64::INFINITY, f64::INFINITY, f64::NEG_INFINITY, f64::NEG_INFINITY];
    for p in &out {
        bbox = [bbox[0].min(p[0]), bbox[1].min(p[1]), bbox[2].max(p[0]), bbox[3].max(p[1])];
    }
    let start = s.verts.len();
    s.verts.extend_from_slice(&out);
    s.polys.push(Proj { start, len: out.len(), id, w: [m.x / h, m.y / h, m.z / h], bbox });
}

#[cfg(test)]
mod tests {
    use super::super::testkit::*;
    use super::*;
    use crate::error::Error;

    #[test]
    fn lambert_on_plane_matches_phi() {
        for (x0, x1, y0, y1) in [(0.1, 0.6, -0.2, 0.9), (-3.0, 2.0, 1.0, 7.0), (-1.0, 1.0, -1.0, 1.0)] {
            let rect = [[x0, y0], [x1, y0], [x1, y1], [x0, y1]];
            let l = lambert_on_plane(&rect);
            assert!((l - top_cell(x0, x1, y0, y1)).abs() < 1e-14, "{l}");
            // orientation does not matter
            let mut rev = rect;
            rev.reverse();
            assert!((lambert_on_plane(&rev) - l).abs() < 1e-15);
        }
        // captured fraction table of docs/algorithms.md §3.1
        for (a, f) in [(1.0, 0.5541), (5.0, 0.9683), (10.0, 0.99189), (14.0, 0.99584)] {
            let o = SinglePlaneOptions { half_width: a, ..Default::default() };
            let s = a / (1.0 + a * a).sqrt();
            assert!((o.captured() - 4.0 / PI * s * s.atan()).abs() < 1e-14);
            assert!((o.captured() - f).abs() < 6e-5, "{a}: {}", o.captured());
        }
    }

    #[test]
    fn point_cases_exact_without_overlap() {
        // One receiver only: rule 1 everywhere, so the value is exact (Lambert).
        let recv = quad(
            Vec3::new(-0.5, -0.5, 1.),
            Vec3::new(-0.5, 0.5, 1.),
            Vec3::new(0.5, 0.5, 1.),
            Vec3::new(0.5, -0.5, 1.),
        );
        let scene = vec![small_square(Vec3::ZERO, 1e-4), recv];
        let o = SinglePlaneOptions { source: SourcePoints::Centre, ..Default::default() };
        let r = single_plane_row(&scene, &[true, true], 0, &o).unwrap();
        let exact = 4.0 * corner_rect(0.5, 0.5);
        // exact up to the eye's lift of 0.5 near r_i above the source (~1e-10 here)
        assert!((r.get(1) - exact).abs() < 1e-9, "{}", r.get(1));
        assert!((r.lost - (1.0 - r.get(1))).abs() < 1e-12);
    }

    #[test]
    fn occluded_half() {
        let [recv, block] = half_blocked();
        let scene = vec![small_square(Vec3::ZERO, 1e-4), recv, block];
        let o = SinglePlaneOptions { source: SourcePoints::Centre, ..Default::default() };
        let r = single_plane_row(&scene, &[true; 3], 0, &o).unwrap();
        let (fr, fb) = (2.0 * corner_rect(0.25, 0.25), 2.0 * corner_rect(0.5, 0.5));
        // only leaves along the shared shadow line x = 0 (length 1 on the plane) are sampled:
        // at most ~ (1/min_cell) leaves of form factor <= min_cell^2/pi each
        let bound = o.min_cell / PI;
        assert!((r.get(1) - fr).abs() < bound, "{} vs {fr}", r.get(1));
        assert!((r.get(2) - fb).abs() < bound, "{} vs {fb}", r.get(2));
        assert!((r.sum() + r.lost - 1.0).abs() < 1e-12);
        // finer leaves: closer
        let o2 = SinglePlaneOptions { min_cell: 1.0 / 1024.0, ..o };
        let r2 = single_plane_row(&scene, &[true; 3], 0, &o2).unwrap();
        assert!((r2.get(1) - fr).abs() < o2.min_cell / PI, "{}", r2.get(1));
    }

    #[test]
    fn closed_cube_row_sum_is_one_minus_lost() {
        let scene = closed_box(Vec3::ZERO, Vec3::ONE, 3, true);
        let rec = vec![true; scene.len()];
        let o = SinglePlaneOptions::default();
        for i in [0usize, 4, 13, 31, 53] {
            let r = single_plane_row(&scene, &rec, i, &o).unwrap();
            assert!((r.sum() + r.lost - 1.0).abs() < 1e-12, "row {i}");
            // lost is (almost only) the horizon band: nothing escapes a closed cube
            let horizon = 1.0 - o.captured();
            assert!((r.lost - horizon).abs() < 1e-9, "row {i}: lost {} vs {horizon}", r.lost);
        }
    }

    #[test]
    fn area_pairs() {
        // Parallel squares: the plane holds the whole receiver, rule 1 -> exact per point.
        let o = SinglePlaneOptions { source: SourcePoints::Points(256), ..Default::default() };
        let f = single_plane_row(&parallel_squares(1.0), &[true, true], 0, &o).unwrap().get(1);
        assert!((f - parallel_rect(1., 1., 1.)).abs() < 2e-3, "{f}");
        // Perpendicular: part of the wall lies in the horizon band (missed by design);
        // with a = 100 the band is 0.02 % wide
        let o = SinglePlaneOptions { half_width: 100.0, ..o };
        let f = single_plane_row(&perpendicular_squares(), &[true, true], 0, &o).unwrap().get(1);
        assert!((f - perpendicular_rect(1., 1., 1.)).abs() < 3e-3, "{f}");
    }

    #[test]
    fn seeded_reproducible_and_bad_input() {
        let scene = closed_box(Vec3::ZERO, Vec3::ONE, 2, true);
        let rec = vec![true; scene.len()];
        let o = SinglePlaneOptions { source: SourcePoints::Points(4), seed: 2, ..Default::default() };
        let a = single_plane_row(&scene, &rec, 1, &o).unwrap();
        assert_eq!(a, single_plane_row(&scene, &rec, 1, &o).unwrap());
        assert_ne!(a, single_plane_row(&scene, &rec, 1, &SinglePlaneOptions { seed: 3, ..o }).unwrap());
        for o in [
            SinglePlaneOptions { half_width: f64::NAN, ..Default::default() },
            SinglePlaneOptions { half_width: 0.0, ..Default::default() },
            SinglePlaneOptions { min_cell: 0.0, ..Default::default() },
            SinglePlaneOptions { min_cell: 1e-9, ..Default::default() },
            SinglePlaneOptions { near: -1.0, ..Default::default() },
        ] {
            assert!(matches!(single_plane_row(&scene, &rec, 0, &o).unwrap_err(), Error::InvalidArgument(_)));
        }
    }
}
