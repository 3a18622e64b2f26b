//! `auto` pair rows of an unobstructed scene (a convex enclosure or part of one): the hot
//! loop of the biggest runs, so the common pair costs a few dozen flops.
//!
//! Per pair, exactly what [`crate::method::area_factor`] does with `auto`, in the same order:
//! the facing test (bounding spheres first, the vertices only when a sphere straddles a
//! plane), then the rule of the [`FarPlan`] from the squared separation, then that rule. The
//! per-polygon data the loop touches (centroid, normal, radius, second moments) sits in one
//! contiguous array, and the plan is built once per call instead of once per pair.

use crate::error::{Error, Result};
use crate::geometry::{Polygon, Vec3};
use crate::method::{self, Facing, RuleCache};
use crate::moments::{moment_pair, Moments};
use crate::quadrature::{FarPlan, FarRule};
use crate::matrix::PairRow;
use rayon::prelude::*;
use std::sync::atomic::{AtomicBool, Ordering};

/// What the loop needs of one polygon.
struct Patch {
    m: Moments,
    radius: f64,
    /// Largest distance of a vertex from the polygon's own plane (planarity tolerance).
    thickness: f64,
    /// A regular quad ([`crate::quadrature::is_regular_quad`]): tighter rule thresholds.
    regular: bool,
}

/// Whether every vertex of b is within `eps` of a's plane (normal `na`, b's centroid at
/// signed height `hab`), decided from b's thickness: a vertex v is at height
/// hab + (v - c_b)·n_b + (v - c_b)·(na - n_b), bounded by hab ± (thickness + radius |na - n_b|).
/// Same-plane patches of a mesh are a sixth of a cube's pairs; this spares their vertex loops.
#[inline]
fn coplanar(hab: f64, b: &Patch, na: Vec3, eps: f64) -> bool {
    hab.abs() + b.thickness + b.radius * (na - b.m.normal).length() <= eps
}

/// G_ij = A_i F_ij for each row i of `rows` and receiver j > i, by `auto` at relative
/// accuracy `tol`, for a scene in which nothing blocks anything (the caller checks).
pub(crate) fn pair_rows(
    polys: &[Polygon],
    receiver: &[bool],
    rules: &RuleCache,
    rows: &[usize],
    tol: f64,
    cancel: &AtomicBool,
) -> Result<Vec<PairRow>> {
    let n = polys.len();
    if let Some(&bad) = rows.iter().find(|&&i| i >= n) {
        return Err(Error::InvalidArgument(format!("row {bad} out of range for {n} polygons")));
    }
    let plan = FarPlan::new(tol);
    // only the polygons these rows touch (j > min row) need their data
    let lo = rows.iter().copied().min().unwrap_or(n);
    let patches: Vec<Patch> = (lo..n)
        .into_par_iter()
        .map(|k| {
            let p = &polys[k];
            let thickness = p.vertices().iter().map(|v| (*v - p.centroid()).dot(p.normal()).abs()).fold(0.0, f64::max);
            Patch { m: *rules.moments(k, p), radius: p.radius(), thickness, regular: crate::quadrature::is_regular_quad(p) }
        })
        .collect();
    let at = |k: usize| &patches[k - lo];
    rows.par_iter()
        .map(|&i| {
            if cancel.load(Ordering::Relaxed) {
                return Err(Error::Cancelled);
            }
            let mut row = PairRow::default();
            if !receiver[i] {
                return Ok(row);
            }
            // most pairs of an enclosure exchange something: room for all, no regrowth
            row.cols.reserve(n - i - 1);
            row.g.reserve(n - i - 1);
            let a = at(i);
            let (ca, na, ra) = (a.m.centroid, a.m.normal, a.radius);
            for j in i + 1..n {
                if !receiver[j] {
                    continue;
                }
                let b = at(j);
                let d: Vec3 = b.m.centroid - ca;
                let (hab, hba) = (na.dot(d), -b.m.normal.dot(d));
                let rsum = ra + b.radius;
                let eps = 1e-12 * rsum;
                // method::facing's bounding-sphere tests, then its vertex tests when undecided
                let f = if hab - b.radius > eps && hba - ra > eps {
                    Facing::Full
                } else if hab + b.radius < -eps || hba + ra < -eps {
                    Facing::None
                } else if coplanar(hab, b, na, eps) {
                    // b's vertices all within eps of a's plane: facing's vertex test gives None
                    Facing::None
                } else {
                    method::facing(&polys[i], &polys[j])
                };
                let g = match f {
                    Facing::None => continue,
                    Facing::Partial => crate::analytic::polygon_pair(&polys[i], &polys[j]),
                    Facing::Full => match plan.rule_sq(d.dot(d), rsum * rsum, a.regular && b.regular) {
                        FarRule::Moment => moment_pair(&a.m, &b.m),
                        rule => method::full_facing_pair(&polys[i], &polys[j], rule, Some((rules, i, j))),
                    },
                };
                if g != 0.0 {
                    row.cols.push(j as u32);
                    row.g.push(g);
                }
            }
            Ok(row)
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use crate::method::{self, Method, Options, RuleCache};
    use crate::obstructed::VisMethod;
    use crate::scene::{AllOptions, AnyMethod, Scene};
    use crate::{Polygon, Vec3};
    use std::sync::atomic::AtomicBool;

    /// The unit cube's faces split into k x k squares each, facing inwards, and a tilted
    /// triangle strip inside (so that shapes other than squares take part).
    fn cube(k: usize) -> Vec<Polygon> {
        let mut out = Vec::new();
        let faces = [
            (Vec3::ZERO, Vec3::X, Vec3::Y),
            (Vec3::ONE, -Vec3::Y, -Vec3::X),
            (Vec3::ZERO, Vec3::Y, Vec3::Z),
            (Vec3::ONE, -Vec3::Z, -Vec3::Y),
            (Vec3::ZERO, Vec3::Z, Vec3::X),
            (Vec3::ONE, -Vec3::X, -Vec3::Z),
        ];
        let h = 1.0 / k as f64;
        for (o, u, w) in faces {
            for a in 0..k {
                for b in 0..k {
                    let p = o + u * (a as f64 * h) + w * (b as f64 * h);
                    if (a + b) % 3 == 0 {
                        // two triangles instead of the square
                        out.push(Polygon::new(vec![p, p + u * h, p + u * h + w * h]).unwrap());
                        out.push(Polygon::new(vec![p, p + u * h + w * h, p + w * h]).unwrap());
                    } else {
                        out.push(Polygon::new(vec![p, p + u * h, p + u * h + w * h, p + w * h]).unwrap());
                    }
                }
            }
        }
        out
    }

    #[test]
    fn rows_equal_the_pair_kernel_and_close_the_cube() {
        let polys = cube(5);
        let n = polys.len();
        let scene = Scene::new(polys.clone(), vec![true; n]).unwrap();
        assert!(scene.unobstructed());
        let rows: Vec<usize> = (0..n).collect();
        for tol in [0.05, 1e-4, 1e-10] {
            let mut o = AllOptions::default();
            o.exact.tol = tol;
            let out = scene.pair_rows(&rows, AnyMethod::Visible(VisMethod::Auto), &o, &AtomicBool::new(false)).unwrap();
            let cache = RuleCache::new(n);
            let opts = Options { tol, ..Options::default() };
            let mut g = vec![vec![0.0; n]; n];
            for (i, row) in out.iter().enumerate() {
                assert!(row.std.is_none());
                for (j, gij, _) in row.iter() {
                    let j = j as usize;
                    let want = method::area_factor(&polys[i], &polys[j], Method::Auto, &opts, Some((&cache, i, j))).unwrap();
                    assert!((gij - want).abs() <= 1e-13 * want.abs(), "tol {tol:e} ({i},{j}): {gij} vs {want}");
                    g[i][j] = gij;
                    g[j][i] = gij;
                }
            }
            // closure: every row of F sums to 1 within what tol allows
            for (i, p) in polys.iter().enumerate() {
                let sum: f64 = g[i].iter().sum::<f64>() / p.area();
                assert!((sum - 1.0).abs() < tol.max(1e-12), "tol {tol:e}, row {i}: {sum}");
            }
        }
    }

    #[test]
    fn rows_skip_non_receivers_and_reject_bad_rows() {
        let polys = cube(2);
        let n = polys.len();
        let mut recv = vec![true; n];
        recv[3] = false;
        let scene = Scene::new(polys, recv).unwrap();
        let o = AllOptions::default();
        let m = AnyMethod::Visible(VisMethod::Auto);
        let out = scene.pair_rows(&[0, 3], m, &o, &AtomicBool::new(false)).unwrap();
        assert!(!out[0].cols.contains(&3) && out[1].is_empty());
        assert!(scene.pair_rows(&[n], m, &o, &AtomicBool::new(false)).is_err());
        let cancelled = scene.pair_rows(&[0], m, &o, &AtomicBool::new(true));
        assert_eq!(cancelled.unwrap_err(), crate::Error::Cancelled);
    }
}
