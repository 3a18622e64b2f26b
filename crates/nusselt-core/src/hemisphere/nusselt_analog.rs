//! The Nusselt analogue as a method (docs/algorithms.md §1.1).
//!
//! Project the scene onto the unit hemisphere over a source point, then orthographically onto
//! the base disk: F_{dA -> A_j} is the disk area covered by A_j's visible part divided by pi.
//! The disk is partitioned into s x s cells of equal area pi/s^2: the images of an s x s grid
//! of the unit square under the Shirley-Chiu concentric map, which scales every area by
//! exactly pi/4 and maps the square rings max(|a|,|b|) = r to circles. Ring k of the grid
//! (odd s: a centre cell, then rings of 8, 16, 24 ... cells) becomes an annulus of equal-area
//! cells whose radial and tangential sizes are within a factor pi/4 (near-square cells).
//!
//! Each cell is resolved by one direction: its centre (or, with `jitter`, a uniform point of
//! the cell: stratified sampling, unbiased), lifted to the hemisphere, traced to the first
//! visible patch. F_ij = sum over source points k of w_k (cells of k that see j) / s^2.
//! The partition is rotated about the normal by a random angle per source point.

use super::{row_over_points, Points, RowResult, SourcePoints};
use crate::error::Result;
use crate::geometry::Polygon;
use crate::registry::method_options;
use crate::sampling::{concentric_disk, hash_unit, lift_to_hemisphere};
use crate::visibility::Visibility;

/// Largest total cell count per source point (4096^2).
pub const MAX_CELLS: u32 = 1 << 24;

method_options! {
    /// Options of [`nusselt_row`].
    pub struct NusseltOptions for "nusselt" {
        /// Number of equal-area disk cells per source point, rounded to the nearest square s^2
        /// (1..=2^24). Default 4096 (s = 64, cells of area pi/4096).
        cells: u32,
        /// Sample points on the source. Default [`SourcePoints::Auto`].
        source: SourcePoints,
        /// Uniform random point in each cell instead of its centre. Default true.
        jitter: bool,
        /// Random rotation of the partition about the normal per source point. Default true.
        random_rotation: bool,
        /// Seed of the jitter, rotations and source points. Default 0.
        seed: u64,
    }
}

impl NusseltOptions {
    /// Cells per side of the square grid: s = round(sqrt(cells)), at least 1.
    pub fn side(&self) -> u32 {
        ((self.cells as f64).sqrt().round() as u32).max(1)
    }
}

/// Row i of the form-factor matrix by the Nusselt analogue; first hits through `vis` (built
/// over the same `scene`). Cells that see a back side or nothing are lost.
pub fn nusselt_row(
    scene: &[Polygon],
    vis: &dyn Visibility,
    receivers: &[bool],
    i: usize,
    opts: &NusseltOptions,
) -> Result<RowResult> {
    opts.check()?;
    let s = opts.side() as usize;
    let cell_w = 1.0 / (s * s) as f64;
    let ignore = [i as u32];
    let rotation = opts.random_rotation.then_some(0x4E55_5E17);
    let points = Points::Rule { source: opts.source, seed: opts.seed, rotation };
    row_over_points(scene, receivers, i, points, |eye, acc, lost| {
        let tmin = 1e-9 * scene[i].radius();
        let w = eye.weight * cell_w;
        for c in 0..s * s {
            // one work unit per cell; stop at cancellation or over budget
            if c % 1024 == 0 && !crate::work::spend(1024) {
                break;
            }
            let (cx, cy) = (c % s, c / s);
            let (jx, jy) = if opts.jitter {
                let base = [i as u64, eye.k as u64, c as u64];
                (hash_unit(opts.seed ^ 0x1A, &base), hash_unit(opts.seed ^ 0x2B, &base))
            } else {
                (0.5, 0.5)
            };
            let d = lift_to_hemisphere(concentric_disk([(cx as f64 + jx) / s as f64, (cy as f64 + jy) / s as f64]));
            let dir = eye.u * d.x + eye.v * d.y + eye.n * d.z;
            match vis.first_hit(eye.p, dir, tmin, f64::INFINITY, &ignore) {
                Some(h) if h.front && (h.id as usize) < scene.len() => acc.add(h.id, w),
                _ => *lost += w,
            }
        }
        true
    })
}

#[cfg(test)]
mod tests {
    use super::super::brute::BruteForce;
    use super::super::testkit::*;
    use super::*;
    use crate::error::Error;
    use crate::geometry::Vec3;

    fn row(scene: &[Polygon], i: usize, o: &NusseltOptions) -> RowResult {
        nusselt_row(scene, &BruteForce { scene }, &vec![true; scene.len()], i, o).unwrap()
    }

    #[test]
    fn point_to_square_converges() {
        // dA at the origin (tiny source) under the square [-.5,.5]^2 at height 1.
        let e = 1e-4;
        let scene = vec![
            quad(Vec3::new(-e, -e, 0.), Vec3::new(e, -e, 0.), Vec3::new(e, e, 0.), Vec3::new(-e, e, 0.)),
            quad(
                Vec3::new(-0.5, -0.5, 1.),
                Vec3::new(-0.5, 0.5, 1.),
                Vec3::new(0.5, 0.5, 1.),
                Vec3::new(0.5, -0.5, 1.),
            ),
        ];
        let exact = 4.0 * corner_rect(0.5, 0.5);
        let mut errs = Vec::new();
        for cells in [256u32, 4096, 65536] {
            let o = NusseltOptions { cells, source: SourcePoints::Centre, jitter: false, ..Default::default() };
            let r = row(&scene, 0, &o);
            // only cells cut by the outline can be wrong: about 4 * 2 * (covered radius) * s
            // cells of area pi/s^2, i.e. |error| <= 8 * 0.5 / s (generous)
            let s = o.side() as f64;
            assert!((r.get(1) - exact).abs() < 4.0 / s, "cells {cells}: {} vs {exact}", r.get(1));
            assert!((r.lost + r.get(1) - 1.0).abs() < 1e-12);
            errs.push((r.get(1) - exact).abs());
        }
        assert!(errs[2] < 1e-3 && errs[2] < errs[0], "{errs:?}");
        // jittered: unbiased; the mean over seeds agrees within 4 standard errors of the mean
        let runs: Vec<f64> = (0..64)
            .map(|seed| {
                row(
                    &scene,
                    0,
                    &NusseltOptions { cells: 1024, source: SourcePoints::Centre, seed, ..Default::default() },
                )
                .get(1)
            })
            .collect();
        let m = runs.iter().sum::<f64>() / 64.0;
        let sd = (runs.iter().map(|x| (x - m).powi(2)).sum::<f64>() / 63.0).sqrt();
        assert!(sd > 0.0 && sd < 1e-2, "{sd}");
        assert!((m - exact).abs() < 4.0 * sd / 8.0, "{m} vs {exact}, sd {sd}");
    }

    #[test]
    fn area_pairs_and_closure() {
        let o = NusseltOptions { cells: 1024, source: SourcePoints::Points(64), ..Default::default() };
        let fp = row(&parallel_squares(1.0), 0, &o).get(1);
        let fq = row(&perpendicular_squares(), 0, &o).get(1);
        assert!((fp - parallel_rect(1., 1., 1.)).abs() < 3e-3, "{fp}");
        assert!((fq - perpendicular_rect(1., 1., 1.)).abs() < 3e-3, "{fq}");
        let scene = closed_box(Vec3::ZERO, Vec3::ONE, 2, true);
        for i in [0usize, 9, 23] {
            let r = row(&scene, i, &NusseltOptions::default());
            assert!(r.lost == 0.0 && (r.sum() - 1.0).abs() < 1e-12, "row {i}: {} {}", r.sum(), r.lost);
        }
    }

    #[test]
    fn occluded_half() {
        let [recv, block] = half_blocked();
        let scene = vec![small_square(Vec3::ZERO, 1e-4), recv, block];
        let r = row(&scene, 0, &NusseltOptions { cells: 1 << 16, source: SourcePoints::Centre, ..Default::default() });
        assert!((r.get(1) - 2.0 * corner_rect(0.25, 0.25)).abs() < 1e-3, "{r:?}");
        assert!((r.get(2) - 2.0 * corner_rect(0.5, 0.5)).abs() < 1e-3, "{r:?}");
    }

    #[test]
    fn seeded_reproducible_and_bad_input() {
        let scene = closed_box(Vec3::ZERO, Vec3::ONE, 2, true);
        let o = NusseltOptions { cells: 64, source: SourcePoints::Points(2), seed: 4, ..Default::default() };
        assert_eq!(row(&scene, 3, &o), row(&scene, 3, &o));
        assert_ne!(row(&scene, 3, &o), row(&scene, 3, &NusseltOptions { seed: 5, ..o }));
        let vis = BruteForce { scene: &scene };
        let rec = vec![true; scene.len()];
        for o in [
            NusseltOptions { cells: 0, ..Default::default() },
            NusseltOptions { cells: u32::MAX, ..Default::default() },
            NusseltOptions { source: SourcePoints::Points(0), ..Default::default() },
        ] {
            assert!(matches!(nusselt_row(&scene, &vis, &rec, 0, &o).unwrap_err(), Error::InvalidArgument(_)));
        }
    }
}
