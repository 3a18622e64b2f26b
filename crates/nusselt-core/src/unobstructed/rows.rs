//! `auto` pair rows of an unobstructed scene (a convex enclosure or part of one): the hot
//! loop of the biggest runs, so the common pair costs a few dozen flops.
//!
//! Per pair, exactly what [`crate::unobstructed::method::area_factor`] does with `auto`, in the same order:
//! the facing test (bounding spheres first, the vertices only when a sphere straddles a
//! plane), then the rule of the [`FarPlan`] from the squared separation, then that rule. The
//! per-polygon data the loop touches (centroid, normal, radius, second moments) sits in one
//! contiguous array, and the plan is built once per call instead of once per pair.

use crate::error::{try_filled, Error, Result};
use crate::geometry::{Polygon, Vec3};
use crate::matrix::{split_lengths, PairBlock};
use crate::unobstructed::far_field::FarPlan;
use crate::unobstructed::method::{self, Facing, Options, RuleCache};
use crate::unobstructed::moments::{moment_rule_formula, Moments};
use rayon::prelude::*;
use std::sync::atomic::{AtomicBool, Ordering};

/// What the loop needs of the polygons, as structure of arrays (index k - lo) so that the
/// first pass over a row vectorises.
struct Patches {
    c: [Vec<f64>; 3],
    n: [Vec<f64>; 3],
    radius: Vec<f64>,
    area: Vec<f64>,
    /// Central second moments per unit area: xx, xy, xz, yy, yz, zz.
    m: [Vec<f64>; 6],
    /// Edge vectors of a quad (x, y, z of the first, then of the second), for the
    /// fourth-order moment rule on regular quads.
    e: [Vec<f64>; 6],
    /// Largest distance of a vertex from the polygon's own plane (planarity tolerance).
    thickness: Vec<f64>,
    /// A regular quad ([`crate::unobstructed::far_field::is_regular_quad`]): tighter rule thresholds.
    regular: Vec<bool>,
    receiver: Vec<bool>,
}

impl Patches {
    fn new(polys: &[Polygon], receiver: &[bool], rules: &RuleCache, lo: usize) -> Patches {
        let per: Vec<(Moments, f64, f64, bool)> = (lo..polys.len())
            .into_par_iter()
            .map(|k| {
                let p = &polys[k];
                let thickness =
                    p.vertices().iter().map(|v| (*v - p.centroid()).dot(p.normal()).abs()).fold(0.0, f64::max);
                (*rules.moments(k, p), p.radius(), thickness, crate::unobstructed::far_field::is_regular_quad(p))
            })
            .collect();
        let col = |f: &dyn Fn(&(Moments, f64, f64, bool)) -> f64| per.iter().map(f).collect::<Vec<f64>>();
        Patches {
            c: [col(&|q| q.0.centroid.x), col(&|q| q.0.centroid.y), col(&|q| q.0.centroid.z)],
            n: [col(&|q| q.0.normal.x), col(&|q| q.0.normal.y), col(&|q| q.0.normal.z)],
            radius: col(&|q| q.1),
            area: col(&|q| q.0.area),
            m: std::array::from_fn(|e| col(&|q| q.0.m[e])),
            e: std::array::from_fn(|e| col(&|q| q.0.edges[e / 3][e % 3])),
            thickness: col(&|q| q.2),
            regular: per.iter().map(|q| q.3).collect(),
            receiver: receiver[lo..].to_vec(),
        }
    }

    fn centroid(&self, k: usize) -> Vec3 {
        Vec3::new(self.c[0][k], self.c[1][k], self.c[2][k])
    }

    fn normal(&self, k: usize) -> Vec3 {
        Vec3::new(self.n[0][k], self.n[1][k], self.n[2][k])
    }

    fn moments(&self, k: usize) -> [f64; 6] {
        std::array::from_fn(|e| self.m[e][k])
    }

    fn edges(&self, k: usize) -> [Vec3; 2] {
        [Vec3::new(self.e[0][k], self.e[1][k], self.e[2][k]), Vec3::new(self.e[3][k], self.e[4][k], self.e[5][k])]
    }
}

/// Whether every vertex of b is within `eps` of a's plane (normal `na`, b's centroid at
/// signed height `hab`), decided from b's thickness: a vertex v is at height
/// hab + (v - c_b)·n_b + (v - c_b)·(na - n_b), bounded by hab ± (thickness + radius |na - n_b|).
/// Same-plane patches of a mesh are a sixth of a cube's pairs; this spares their vertex loops.
#[inline]
fn coplanar(hab: f64, thickness: f64, radius: f64, na: Vec3, nb: Vec3, eps: f64) -> bool {
    hab.abs() + thickness + radius * (na - nb).length() <= eps
}

/// Pair classes of the first pass.
const SKIP: u8 = 0;
const MOMENT: u8 = 1;
/// The fourth-order moment rule, left by a pass that did not evaluate it.
const MOMENT4: u8 = 2;
const OTHER: u8 = 3;

/// Columns per first-pass chunk (stack buffers).
const CHUNK: usize = 256;

/// G_ij = A_i F_ij for each row i of `rows` and receiver j > i, by `auto` at relative
/// accuracy `opts.tol`, for a scene in which nothing blocks anything (the caller checks).
///
/// Each row runs in two passes per chunk of columns: a branch-free pass over all of them
/// classifies each pair (nothing exchanged / moment rule / anything else) and evaluates the
/// moment rule everywhere (it vectorises, and the moment rule is what most pairs of a large
/// scene use), then a scalar pass keeps the moment values and computes the other pairs
/// exactly as [`crate::unobstructed::method::area_factor`] would.
pub(crate) fn pair_block(
    polys: &[Polygon],
    receiver: &[bool],
    rules: &RuleCache,
    rows: &[usize],
    opts: &Options,
    cancel: &AtomicBool,
) -> Result<PairBlock> {
    let n = polys.len();
    if receiver.len() != n {
        return Err(Error::InvalidArgument(format!("receiver mask has {} entries for {n} polygons", receiver.len())));
    }
    if let Some(&bad) = rows.iter().find(|&&i| i >= n) {
        return Err(Error::InvalidArgument(format!("row {bad} out of range for {n} polygons")));
    }
    let plan = FarPlan::new(opts.tol);
    let windows = [plan.moment_from_sq(false), plan.moment_from_sq(true), plan.moment4_from_sq()];
    // only the polygons these rows touch (j > min row) need their data
    let lo = rows.iter().copied().min().unwrap_or(n);
    let pt = Patches::new(polys, receiver, rules, lo);
    // Each row writes straight into the block's arrays, into room for all its pairs; the rows
    // are then moved together in place. No per-row buffers and no second copy of the block.
    let room: Vec<usize> = rows.iter().map(|&i| if receiver[i] { n - i - 1 } else { 0 }).collect();
    let total: usize = room.iter().sum();
    // refused as an error, not a process abort, when the block cannot fit in memory
    let mut cols = try_filled("a block's column indices", total, 0i32)?;
    let mut vals = try_filled("a block's entries", total, 0.0f64)?;
    let jobs: Vec<_> = rows
        .iter()
        .zip(split_lengths(&mut cols, room.iter().copied()))
        .zip(split_lengths(&mut vals, room.iter().copied()))
        .collect();
    let counts: Vec<usize> = jobs
        .into_par_iter()
        .map(|((&i, out_c), out_g)| {
            if cancel.load(Ordering::Relaxed) {
                return Err(Error::Cancelled);
            }
            if !receiver[i] {
                return Ok(0);
            }
            let mut len = 0;
            let ia = i - lo;
            let (ca, na, ra, area_a, reg_a) =
                (pt.centroid(ia), pt.normal(ia), pt.radius[ia], pt.area[ia], pt.regular[ia]);
            let (ma, ea) = (pt.moments(ia), pt.edges(ia));
            let (mut class, mut value) = ([SKIP; CHUNK], [0.0f64; CHUNK]);
            let mut start = ia + 1;
            // whether the previous chunk had enough fourth-order pairs to evaluate the rule
            // for all columns (it costs about as much again as the rest of the pass)
            let mut fourth = false;
            while start < n - lo {
                let chunk = (n - lo - start).min(CHUNK);
                let end = start + chunk;
                let fourths = first_pass(
                    &pt,
                    start..end,
                    (ca, na, ra, area_a, reg_a, &ma, &ea),
                    &windows,
                    fourth,
                    &mut class[..chunk],
                    &mut value[..chunk],
                );
                fourth = 8 * fourths > chunk;
                for (e, (&cl, &g)) in class[..chunk].iter().zip(&value[..chunk]).enumerate() {
                    let j = start + e + lo;
                    let g = match cl {
                        SKIP => continue,
                        MOMENT => g,
                        MOMENT4 => {
                            let jb = j - lo;
                            let (d, mb, eb) = (pt.centroid(jb) - ca, pt.moments(jb), pt.edges(jb));
                            moment_rule_formula(d, na, pt.normal(jb), &ma, &mb, &ea, &eb, area_a * pt.area[jb], true)
                        }
                        _ => other_pair(polys, rules, &plan, &pt, i, j, lo),
                    };
                    if g != 0.0 {
                        out_c[len] = j as i32;
                        out_g[len] = g;
                        len += 1;
                    }
                }
                start = end;
            }
            Ok(len)
        })
        .collect::<Result<_>>()?;
    let mut indptr = Vec::with_capacity(rows.len() + 1);
    indptr.push(0i64);
    let (mut from, mut to) = (0usize, 0usize);
    for (&len, &r) in counts.iter().zip(&room) {
        cols.copy_within(from..from + len, to);
        vals.copy_within(from..from + len, to);
        from += r;
        to += len;
        indptr.push(to as i64);
    }
    cols.truncate(to);
    vals.truncate(to);
    Ok(PairBlock { indptr, cols, g: vals, std: None })
}

type Source<'a> = (Vec3, Vec3, f64, f64, bool, &'a [f64; 6], &'a [Vec3; 2]);

/// The branch-free pass: class and moment-rule value of the pairs (a, k), k in `ks`. With
/// `fourth`, pairs for the fourth-order rule get its value and class MOMENT; without, they get
/// class MOMENT4 for the caller to evaluate. Returns the number of such pairs. Uses AVX2
/// when the CPU has it (checked once); without FMA, so both paths round alike.
fn first_pass(
    pt: &Patches,
    ks: std::ops::Range<usize>,
    a: Source,
    windows: &[f64; 3],
    fourth: bool,
    class: &mut [u8],
    value: &mut [f64],
) -> usize {
    #[cfg(target_arch = "x86_64")]
    {
        if std::arch::is_x86_feature_detected!("avx2") {
            // SAFETY: the CPU supports AVX2, checked just above.
            return unsafe {
                if fourth {
                    first_pass_avx2::<true>(pt, ks, a, windows, class, value)
                } else {
                    first_pass_avx2::<false>(pt, ks, a, windows, class, value)
                }
            };
        }
    }
    if fourth {
        first_pass_body::<true>(pt, ks, a, windows, class, value)
    } else {
        first_pass_body::<false>(pt, ks, a, windows, class, value)
    }
}

#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
unsafe fn first_pass_avx2<const FOURTH: bool>(
    pt: &Patches,
    ks: std::ops::Range<usize>,
    a: Source,
    windows: &[f64; 3],
    class: &mut [u8],
    value: &mut [f64],
) -> usize {
    first_pass_body::<FOURTH>(pt, ks, a, windows, class, value)
}

#[inline(always)]
fn first_pass_body<const FOURTH: bool>(
    pt: &Patches,
    ks: std::ops::Range<usize>,
    a: Source,
    windows: &[f64; 3],
    class: &mut [u8],
    value: &mut [f64],
) -> usize {
    let (ca, na, ra, area_a, reg_a, ma, ea) = a;
    let (cx, cy, cz) = (&pt.c[0][ks.clone()], &pt.c[1][ks.clone()], &pt.c[2][ks.clone()]);
    let (nx, ny, nz) = (&pt.n[0][ks.clone()], &pt.n[1][ks.clone()], &pt.n[2][ks.clone()]);
    let (rb, ab) = (&pt.radius[ks.clone()], &pt.area[ks.clone()]);
    let m: [&[f64]; 6] = std::array::from_fn(|e| &pt.m[e][ks.clone()]);
    let edge: [&[f64]; 6] = std::array::from_fn(|e| &pt.e[e][ks.clone()]);
    let (reg, recv) = (&pt.regular[ks.clone()], &pt.receiver[ks.clone()]);
    let mut fourths = 0;
    for k in 0..class.len() {
        let (dx, dy, dz) = (cx[k] - ca.x, cy[k] - ca.y, cz[k] - ca.z);
        let hab = na.x * dx + na.y * dy + na.z * dz;
        let hba = -(nx[k] * dx + ny[k] * dy + nz[k] * dz);
        let rs = ra + rb[k];
        let (s, rs2) = (dx * dx + dy * dy + dz * dz, rs * rs);
        // each polygon's own tolerance, as method::facing has them (bounding-sphere tests)
        let reach = rs + s.sqrt();
        let (eps_b, eps_a) = (1e-12 * rb[k] + 1e-16 * reach, 1e-12 * ra + 1e-16 * reach);
        let full = (hab - rb[k] > eps_b) & (hba - ra > eps_a);
        let none = (hab + rb[k] < -eps_b) | (hba + ra < -eps_a) | !recv[k];
        let regular = reg_a & reg[k];
        let from = if regular { windows[1] } else { windows[0] };
        let moment2 = full & (s >= from * rs2);
        let moment4 = full & regular & (s >= windows[2] * rs2) & !moment2;
        let mb = [m[0][k], m[1][k], m[2][k], m[3][k], m[4][k], m[5][k]];
        let nb = Vec3::new(nx[k], ny[k], nz[k]);
        let eb = [Vec3::new(edge[0][k], edge[1][k], edge[2][k]), Vec3::new(edge[3][k], edge[4][k], edge[5][k])];
        value[k] =
            moment_rule_formula(Vec3::new(dx, dy, dz), na, nb, ma, &mb, ea, &eb, area_a * ab[k], FOURTH & moment4);
        fourths += (!none & moment4) as usize;
        class[k] = if none {
            SKIP
        } else if moment2 | (FOURTH & moment4) {
            MOMENT
        } else if moment4 {
            MOMENT4
        } else {
            OTHER
        };
    }
    fourths
}

/// A pair the first pass left to the general path: [`method::auto_pair`], with the facing
/// test spared its vertex loops for same-plane pairs.
fn other_pair(
    polys: &[Polygon],
    rules: &RuleCache,
    plan: &FarPlan,
    pt: &Patches,
    i: usize,
    j: usize,
    lo: usize,
) -> f64 {
    let (ia, ib) = (i - lo, j - lo);
    let (na, nb, rb) = (pt.normal(ia), pt.normal(ib), pt.radius[ib]);
    let hab = na.dot(pt.centroid(ib) - pt.centroid(ia));
    let f = if coplanar(hab, pt.thickness[ib], rb, na, nb, 1e-12 * rb) {
        Facing::None
    } else {
        method::facing(&polys[i], &polys[j])
    };
    method::auto_pair(&polys[i], &polys[j], f, plan, pt.regular[ia] && pt.regular[ib], Some((rules, i, j)))
}

#[cfg(test)]
mod tests {
    use crate::scene::{AnyMethod, Scene};
    use crate::unobstructed::method::AutoOptions;
    use crate::unobstructed::method::{self, Method, Options, RuleCache};
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
            let m = AnyMethod::Auto(AutoOptions { tol, ..Default::default() });
            let out = scene.pair_rows(&rows, &m, &AtomicBool::new(false)).unwrap();
            let cache = RuleCache::new(n);
            let opts = Options { tol, ..Options::default() };
            let mut g = vec![vec![0.0; n]; n];
            for (i, row) in out.iter().enumerate() {
                assert!(row.std.is_none());
                for (j, gij, _) in row.iter() {
                    let j = j as usize;
                    let want =
                        method::area_factor(&polys[i], &polys[j], Method::Auto, &opts, Some((&cache, i, j))).unwrap();
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
    fn fourth_order_pairs_equal_the_pair_kernel_in_both_paths() {
        // a cube fine enough that many pairs take the fourth-order moment rule: chunks rich in
        // them evaluate it in the vectorised pass, the others in the scalar one; either way
        // each entry equals the pair kernel's
        let polys = cube(10);
        let n = polys.len();
        let scene = Scene::new(polys.clone(), vec![true; n]).unwrap();
        let rows: Vec<usize> = (0..n).collect();
        for tol in [0.03, 1e-3] {
            let plan = crate::unobstructed::far_field::FarPlan::new(tol);
            let m = AnyMethod::Auto(AutoOptions { tol, ..Default::default() });
            let out = scene.pair_rows(&rows, &m, &AtomicBool::new(false)).unwrap();
            let cache = RuleCache::new(n);
            let opts = Options { tol, ..Options::default() };
            let mut fourth = 0;
            for (i, row) in out.iter().enumerate() {
                for (j, gij, _) in row.iter() {
                    let j = j as usize;
                    let want =
                        method::area_factor(&polys[i], &polys[j], Method::Auto, &opts, Some((&cache, i, j))).unwrap();
                    assert!((gij - want).abs() <= 1e-13 * want.abs(), "tol {tol:e} ({i},{j}): {gij} vs {want}");
                    let (a, b) = (&polys[i], &polys[j]);
                    let (d, r) = (b.centroid() - a.centroid(), a.radius() + b.radius());
                    if method::facing(a, b) == method::Facing::Full
                        && plan.rule_sq(d.dot(d), r * r, true) == crate::unobstructed::far_field::FarRule::Moment4
                    {
                        fourth += 1;
                    }
                }
            }
            assert!(fourth > 5000, "tol {tol:e}: {fourth} fourth-order pairs");
        }
    }

    #[test]
    fn scenes_with_something_in_between_are_recognised() {
        // the closed cube: nothing can block; a patch inside it or outside behind a wall can
        let inner = Polygon::new(vec![
            Vec3::new(0.4, 0.4, 0.5),
            Vec3::new(0.6, 0.4, 0.5),
            Vec3::new(0.6, 0.6, 0.5),
            Vec3::new(0.4, 0.6, 0.5),
        ])
        .unwrap();
        let below = Polygon::new(inner.vertices().iter().map(|v| Vec3::new(v.x, v.y, -0.5)).collect()).unwrap();
        // coplanar with the floor patches but slightly lower than their plane's tolerance
        let sunk = Polygon::new(inner.vertices().iter().map(|v| Vec3::new(v.x + 2.0, v.y, -1e-6)).collect()).unwrap();
        let flush = Polygon::new(inner.vertices().iter().map(|v| Vec3::new(v.x, v.y, 0.0)).collect()).unwrap();
        let base = cube(3);
        let scene = |extra: Option<&Polygon>| {
            let mut p = base.clone();
            p.extend(extra.cloned());
            let n = p.len();
            Scene::new(p, vec![true; n]).unwrap().unobstructed()
        };
        assert!(scene(None));
        assert!(scene(Some(&flush)), "a patch lying in the floor blocks nothing");
        assert!(!scene(Some(&inner)));
        assert!(!scene(Some(&below)));
        assert!(!scene(Some(&sunk)));
    }

    #[test]
    fn rows_skip_non_receivers_and_reject_bad_rows() {
        let polys = cube(2);
        let n = polys.len();
        let mut recv = vec![true; n];
        recv[3] = false;
        let scene = Scene::new(polys, recv).unwrap();
        let m = &AnyMethod::Auto(Default::default());
        let out = scene.pair_rows(&[0, 3], m, &AtomicBool::new(false)).unwrap();
        assert!(!out[0].cols.contains(&3) && out[1].is_empty());
        // a block of rows in any order holds each row's entries where its indptr says
        let block = scene.pair_block(&[5, 0, 3, 1], m, &AtomicBool::new(false)).unwrap();
        let single = |i: usize| scene.pair_rows(&[i], m, &AtomicBool::new(false)).unwrap().remove(0);
        for (k, &i) in [5usize, 0, 3, 1].iter().enumerate() {
            let (s, e) = (block.indptr[k] as usize, block.indptr[k + 1] as usize);
            let row = single(i);
            assert_eq!(block.cols[s..e].iter().map(|&j| j as u32).collect::<Vec<_>>(), row.cols, "row {i}");
            assert_eq!(&block.g[s..e], &row.g[..], "row {i}");
        }
        assert_eq!(*block.indptr.last().unwrap() as usize, block.g.len());
        assert!(scene.pair_rows(&[n], m, &AtomicBool::new(false)).is_err());
        let cancelled = scene.pair_rows(&[0], m, &AtomicBool::new(true));
        assert_eq!(cancelled.unwrap_err(), crate::Error::Cancelled);
    }
}
