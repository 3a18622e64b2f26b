//! Rows from points: F from differential areas (sensor points, each with a unit normal) to
//! every receiver of a scene, obstructed by the scene's polygons; the sky view factor of
//! points and patches; and rays to infinity (for sky patches). One call per batch, rayon
//! over the points.
//!
//! Per point, Lambert's closed form gives the unobstructed F to every target (the targets in
//! Morton order of their centroids); clusters of neighbouring targets ask the BVH once for
//! the blockers that may meet the hull of the point and the cluster's box, halved while
//! something may block (as the scene's pair rows do), and only pairs left with candidates of
//! their own pay for visibility: the exact visible region from the point
//! ([`point_visible_view_factor`]), or the per-point estimator of the method asked for.

use super::{blocked_clusters, bounding_box, morton_ranks, AnyMethod, Scene};
use crate::error::{Error, Result};
use crate::geometry::{turns_left, Polygon, Vec3};
use crate::matrix::PairBlock;
use crate::obstructed::{self, Context, Estimator};
use crate::quadrature::AreaRule;
use crate::unobstructed::analytic;
use crate::visibility::shadow::{hides_whole, point_visible_view_factor, visible_part};
use rayon::prelude::*;
use std::sync::atomic::{AtomicBool, Ordering};

/// The targets of a batch of points: polygons, the occluder each may not be blocked by (its
/// own), and their Morton order.
struct Targets<'a> {
    polygons: &'a [Polygon],
    own: Vec<u32>,
    order: Vec<u32>,
}

/// What to do with a pair (point, target k) that has candidate blockers left.
type Hard<'a> = dyn Fn(Vec3, Vec3, usize, &[&Polygon]) -> Result<f64> + Sync + 'a;

/// The sky view factor at a point: `sky(p, unit n, skip)` (see `Scene::with_sky`).
type SkyAt<'a> = dyn Fn(Vec3, Vec3, Option<u32>) -> Result<f64> + Sync + 'a;

impl Scene {
    /// Largest distance of a vertex from the centre of the scene's box (the scale of the
    /// tiny source triangle standing for a point in shaft queries).
    fn extent(&self) -> (Vec3, f64) {
        let (mut lo, mut hi) = (Vec3::splat(f64::INFINITY), Vec3::splat(f64::NEG_INFINITY));
        for v in self.polygons.iter().flat_map(|p| p.vertices()) {
            lo = lo.min(*v);
            hi = hi.max(*v);
        }
        let c = 0.5 * (lo + hi);
        (c, 0.5 * (hi - lo).length())
    }

    /// The scene's receivers as targets of points, in Morton order of their centroids.
    fn targets(&self, ctx: Option<&Context>) -> Targets<'_> {
        let ranks = self.ranks.get_or_init(|| morton_ranks(&self.polygons));
        let mut order: Vec<u32> = (0..self.polygons.len() as u32).filter(|&j| self.receiver[j as usize]).collect();
        order.sort_unstable_by_key(|&j| ranks[j as usize]);
        let own = match ctx {
            Some(c) => c.occluders.owner.clone(),
            None => vec![u32::MAX; self.polygons.len()],
        };
        Targets { polygons: &self.polygons, own, order }
    }

    /// F from each point (unit normal) to every receiver of the scene, as CSR parts (indptr,
    /// receiver polygon ids, F, standard error or None). `obstructed`: every polygon of the
    /// scene blocks (a receiver never blocks its own view); else Lambert's closed form alone.
    /// Methods: `auto`, `clipping`, `analytic` and `contour` (Lambert's form on the exact
    /// visible region), the other pair methods with visibility (their per-point estimators).
    pub fn point_rows(
        &self,
        points: &[Vec3],
        normals: &[Vec3],
        m: &AnyMethod,
        obstructed: bool,
        cancel: &AtomicBool,
    ) -> Result<PairBlock> {
        m.check()?;
        check_points(points, normals)?;
        let Some(est) = m.estimator() else {
            return Err(Error::InvalidArgument(
                "a row method has no point rows; use a pair method (auto, clipping, ...)".into(),
            ));
        };
        let ctx = if obstructed && !self.polygons.is_empty() { Some(self.pair_context(m)?) } else { None };
        let targets = self.targets(ctx.as_ref());
        // `auto`, `clipping`, `analytic`, `contour`: Lambert's form on the exact visible region
        let lambert = matches!(est, Estimator::Clipping(_));
        let sampled = matches!(m, AnyMethod::MonteCarlo(_));
        let hard = |p: Vec3, n: Vec3, j: usize, blockers: &[&Polygon]| -> Result<f64> {
            if lambert {
                Ok(point_visible_view_factor(p, n, &self.polygons[j], blockers))
            } else {
                Ok(obstructed::point(ctx.as_ref().unwrap(), p, n, j, &est)?.value)
            }
        };
        // Monte Carlo carries a standard error: such pairs go through the per-point estimator.
        if sampled {
            let c = ctx.as_ref().unwrap();
            let rows: Vec<Result<Vec<(u32, f64, f64)>>> = per_point(points, normals, cancel, |p, n| {
                let mut row = Vec::new();
                for &j in &targets.order {
                    let e = obstructed::point(c, p, n, j as usize, &est)?;
                    if e.value != 0.0 || e.std_err != 0.0 {
                        row.push((j, e.value, e.std_err));
                    }
                }
                row.sort_unstable_by_key(|e| e.0);
                Ok(row)
            });
            return csr(rows, true);
        }
        let (centre, radius) = self.extent();
        let rows: Vec<Result<Vec<(u32, f64, f64)>>> = per_point(points, normals, cancel, |p, n| {
            let row = point_row(ctx.as_ref(), p, n, &targets, None, &hard, radius + p.distance(centre))?;
            Ok(row.into_iter().map(|(j, f)| (j, f, 0.0)).collect())
        });
        csr(rows, false)
    }

    /// F from a small sphere at each point to every receiver's front: the solid angle of
    /// the receiver's part visible from the point over 4 pi (the mean of the plane element's
    /// F over all directions of its normal), as CSR parts like [`Scene::point_rows`]; exact
    /// (Van Oosterom and Strackee's triangle formula on the visible region's contours).
    pub fn point_sphere_rows(&self, points: &[Vec3], obstructed: bool, cancel: &AtomicBool) -> Result<PairBlock> {
        let up = vec![Vec3::new(0.0, 0.0, 1.0); points.len()];
        check_points(points, &up)?;
        let ctx = if obstructed && !self.polygons.is_empty() { Some(self.context()?) } else { None };
        let targets = self.targets(ctx.as_ref());
        let free = |p: Vec3, _n: Vec3, b: &Polygon| sphere_fraction(p, b, &[b.vertices().to_vec()]);
        let hard = |p: Vec3, _n: Vec3, j: usize, blockers: &[&Polygon]| {
            let b = &self.polygons[j];
            // every point of b is in the half-space -n_b . (x - p) >= 0 when p is in front of b
            Ok(sphere_fraction(p, b, &visible_part(p, -b.normal(), b, blockers)))
        };
        let (centre, radius) = self.extent();
        let rows: Vec<Result<Vec<(u32, f64, f64)>>> = per_point(points, &up, cancel, |p, n| {
            let row = point_row_with(ctx.as_ref(), p, n, &targets, None, &free, &hard, radius + p.distance(centre))?;
            Ok(row.into_iter().map(|(j, f)| (j, f, 0.0)).collect())
        });
        csr(rows, false)
    }

    /// The sky view factor of each point (unit normal): the fraction of the radiation leaving
    /// it that no polygon of the scene intercepts, 1 - sum_k F(p -> visible part of occluder
    /// k), every occluder seen from whichever side faces p (polygons block from both sides).
    /// Each direction meets exactly one first polygon, so the sum is the covered fraction,
    /// exact up to rounding (~1e-15 per term) and the exact visible regions' accuracy.
    pub fn point_sky(&self, points: &[Vec3], normals: &[Vec3], cancel: &AtomicBool) -> Result<Vec<f64>> {
        check_points(points, normals)?;
        if self.polygons.is_empty() {
            return Ok(vec![1.0; points.len()]);
        }
        self.with_sky(|sky, _| per_point(points, normals, cancel, |p, n| sky(p, n, None)).into_iter().collect())
    }

    /// The sky view factor of each receiver patch in `rows`: the point sky view factor
    /// integrated over the patch by its Gauss rule of `order` (per triangle or quad; points on
    /// the patch, which does not block them), divided by the area. Accurate to the rule's
    /// error: the point value is smooth inside a patch but its derivative has a logarithmic
    /// singularity along edges shared with other polygons and kinks at shadow edges.
    pub fn patch_sky(&self, rows: &[usize], order: usize, cancel: &AtomicBool) -> Result<Vec<f64>> {
        if let Some(&i) = rows.iter().find(|&&i| i >= self.polygons.len()) {
            return Err(Error::InvalidArgument(format!("no polygon {i} (the scene has {})", self.polygons.len())));
        }
        self.with_sky(|sky, ctx| {
            rows.par_iter()
                .map(|&i| {
                    if cancel.load(Ordering::Relaxed) {
                        return Err(Error::Cancelled);
                    }
                    let poly = &self.polygons[i];
                    let rule = AreaRule::try_new(poly, order)?;
                    let own = ctx.occluders.owner[i];
                    let mut sum = 0.0;
                    for (&p, &w) in rule.points.iter().zip(&rule.weights) {
                        sum += w * sky(p, poly.normal(), Some(own))?;
                    }
                    Ok((sum / poly.area()).clamp(0.0, 1.0))
                })
                .collect()
        })
    }

    /// Runs `f` with the sky view factor at a point, `sky(p, unit n, skip)` (`skip`: an
    /// occluder that blocks nothing for p, the patch it lies on), and the scene's context:
    /// the setup [`Scene::point_sky`] and [`Scene::patch_sky`] share.
    fn with_sky<T>(&self, f: impl FnOnce(&SkyAt, &Context) -> Result<T>) -> Result<T> {
        let ctx = self.context()?;
        let both = sky_polygons(&ctx)?;
        let targets = sky_targets(&both);
        let (centre, radius) = self.extent();
        let hard =
            |p: Vec3, n: Vec3, k: usize, blockers: &[&Polygon]| Ok(point_visible_view_factor(p, n, &both[k], blockers));
        let sky = |p: Vec3, n: Vec3, skip: Option<u32>| -> Result<f64> {
            let row = point_row(Some(&ctx), p, n, &targets, skip, &hard, radius + p.distance(centre))?;
            Ok(sky_from(&row))
        };
        f(&sky, &ctx)
    }

    /// Whether each ray origin + t dir, t > 1e-9 of the scene's size, meets any polygon of
    /// the scene (either side): the rays to the sky.
    pub fn rays_blocked(&self, origins: &[Vec3], dirs: &[Vec3], cancel: &AtomicBool) -> Result<Vec<bool>> {
        if origins.len() != dirs.len() {
            return Err(Error::InvalidArgument(format!("{} origins but {} directions", origins.len(), dirs.len())));
        }
        if let Some(k) =
            (0..origins.len()).find(|&k| !origins[k].is_finite() || !dirs[k].is_finite() || dirs[k] == Vec3::ZERO)
        {
            return Err(Error::InvalidArgument(format!(
                "ray {k}: origin and direction must be finite, direction nonzero"
            )));
        }
        if self.polygons.is_empty() {
            return Ok(vec![false; origins.len()]);
        }
        let ctx = self.context()?;
        let (centre, radius) = self.extent();
        origins
            .par_iter()
            .zip(dirs)
            .with_min_len(256)
            .map(|(&o, &d)| {
                if cancel.load(Ordering::Relaxed) {
                    return Err(Error::Cancelled);
                }
                let d = d.normalize();
                let tmin = 1e-9 * (radius + o.distance(centre));
                Ok(ctx.vis.first_hit(o, d, tmin, f64::INFINITY, &[]).is_some())
            })
            .collect()
    }
}

/// Solid angle of the region bounded by `contours` (on b's plane; outer counter-clockwise
/// about b's normal, holes clockwise) seen from p, over 4 pi; 0 unless p is strictly in front
/// of b. Per triangle of a fan, tan(omega / 2) = a . (b x c) / (abc + (a . b) c + (a . c) b
/// + (b . c) a) (Van Oosterom and Strackee 1983), with atan2 for the whole range.
fn sphere_fraction(p: Vec3, b: &Polygon, contours: &[Vec<Vec3>]) -> f64 {
    let v = b.vertices();
    let h = b.normal().dot(p - b.centroid());
    if !(h > 1e-12 * (b.radius() + p.distance(b.centroid()))) || v.is_empty() {
        return 0.0;
    }
    let mut omega = 0.0;
    for c in contours {
        if c.len() < 3 {
            continue;
        }
        let a = c[0] - p;
        let la = a.length();
        for k in 1..c.len() - 1 {
            let (x, y) = (c[k] - p, c[k + 1] - p);
            let (lx, ly) = (x.length(), y.length());
            let num = a.dot(x.cross(y));
            let den = la * lx * ly + a.dot(x) * ly + a.dot(y) * lx + x.dot(y) * la;
            omega += 2.0 * num.atan2(den);
        }
    }
    // a contour counter-clockwise about a normal facing p winds clockwise seen from p
    (-omega / (4.0 * std::f64::consts::PI)).max(0.0)
}

fn sky_from(row: &[(u32, f64)]) -> f64 {
    (1.0 - row.iter().map(|e| e.1).sum::<f64>()).clamp(0.0, 1.0)
}

fn check_points(points: &[Vec3], normals: &[Vec3]) -> Result<()> {
    if points.len() != normals.len() {
        return Err(Error::InvalidArgument(format!("{} points but {} normals", points.len(), normals.len())));
    }
    for (k, (p, n)) in points.iter().zip(normals).enumerate() {
        if !p.is_finite() || !n.is_finite() {
            return Err(Error::InvalidArgument(format!("point {k}: point and normal must be finite")));
        }
        if (n.length() - 1.0).abs() > 1e-6 {
            return Err(Error::InvalidArgument(format!(
                "point {k}: the normal must be a unit vector (length {})",
                n.length()
            )));
        }
    }
    Ok(())
}

/// `f(point, normal)` for every point, in parallel; each point first checks for Ctrl-C.
fn per_point<T: Send>(
    points: &[Vec3],
    normals: &[Vec3],
    cancel: &AtomicBool,
    f: impl Fn(Vec3, Vec3) -> Result<T> + Sync + Send,
) -> Vec<Result<T>> {
    points
        .par_iter()
        .zip(normals)
        .map(|(&p, &n)| {
            if cancel.load(Ordering::Relaxed) {
                return Err(Error::Cancelled);
            }
            f(p, n)
        })
        .collect()
}

fn csr(rows: Vec<Result<Vec<(u32, f64, f64)>>>, with_std: bool) -> Result<PairBlock> {
    let mut b = PairBlock { indptr: vec![0], cols: Vec::new(), g: Vec::new(), std: with_std.then(Vec::new) };
    for r in rows {
        for (j, f, s) in r? {
            b.cols.push(j as i32);
            b.g.push(f);
            if let Some(std) = &mut b.std {
                std.push(s);
            }
        }
        b.indptr.push(b.cols.len() as i64);
    }
    Ok(b)
}

/// The polygons of `among` (not in `ignore`) that may meet the cone from p over the convex
/// polygon b, closed by b's plane: a polygon is dropped when all its vertices lie outside one
/// of the cone's planes (through p and an edge of b) or beyond b's plane, or when p and b lie
/// strictly on one side of its plane (tolerance 1e-10 of the pair's size, so polygons merely
/// touching the cone are dropped, as in the shaft test). The same answer as the shaft test's
/// superset for a point source, without building a shaft. False (nothing done) when b is not
/// convex.
fn cone_candidates(p: Vec3, b: &Polygon, ignore: &[u32], among: &[u32], occ: &[Polygon], out: &mut Vec<u32>) -> bool {
    out.clear();
    let v = b.vertices();
    let m = v.len();
    let nb = b.normal();
    let c = b.centroid();
    let size = b.radius() + p.distance(c);
    let tol = 1e-10 * size;
    // convex: every turn to the left about b's normal (straight within rounding passes)
    if !turns_left(v, |a, b, c| ((b - a).cross(c - b).dot(nb), size), -1e-12 * size) {
        return false;
    }
    let h = nb.dot(p - c);
    if !(h > tol) {
        return false;
    }
    // inward unit normals of the cone's side planes (through p): b's centroid is inside
    let mut planes: [(Vec3, f64); 9] = [(Vec3::ZERO, 0.0); 9];
    if m + 1 > planes.len() {
        return false;
    }
    for k in 0..m {
        let mut n = (v[k] - p).cross(v[(k + 1) % m] - p);
        let len = n.length();
        if !(len > 0.0) {
            return false;
        }
        n /= len;
        if n.dot(c - p) < 0.0 {
            n = -n;
        }
        planes[k] = (n, n.dot(p));
    }
    // b's plane: the inside is p's side
    planes[m] = (nb, nb.dot(c));
    for &k in among {
        if ignore.contains(&k) {
            continue;
        }
        let q = &occ[k as usize];
        let w = q.vertices();
        let outside = planes[..m].iter().any(|&(n, d)| w.iter().all(|x| n.dot(*x) - d < -tol))
            || w.iter().all(|x| nb.dot(*x) - planes[m].1 < -tol);
        if outside {
            continue;
        }
        // the blocker's plane separates nothing: p and b on one side
        let (nq, dq) = (q.normal(), q.normal().dot(q.centroid()));
        let sp = nq.dot(p) - dq;
        let side = |x: &Vec3| nq.dot(*x) - dq;
        if (sp > tol && v.iter().all(|x| side(x) > tol)) || (sp < -tol && v.iter().all(|x| side(x) < -tol)) {
            continue;
        }
        out.push(k);
    }
    true
}

/// Every occluder in both orientations (target 2k faces like occluder k, 2k + 1 the other way).
fn sky_polygons(ctx: &Context) -> Result<Vec<Polygon>> {
    let mut both = Vec::with_capacity(2 * ctx.occluders.polygons.len());
    for q in &ctx.occluders.polygons {
        let mut rev = q.vertices().to_vec();
        rev.reverse();
        let back = Polygon::new(rev).map_err(|e| Error::InvalidArgument(format!("reversed occluder: {e}")))?;
        both.push(q.clone());
        both.push(back);
    }
    Ok(both)
}

/// [`sky_polygons`] as targets, each unblocked by its own occluder.
fn sky_targets(both: &[Polygon]) -> Targets<'_> {
    let ranks = morton_ranks(both);
    let mut order: Vec<u32> = (0..both.len() as u32).collect();
    order.sort_unstable_by_key(|&k| ranks[k as usize]);
    Targets { polygons: both, own: (0..both.len() as u32).map(|k| k / 2).collect(), order }
}

/// (target id, F) from the point p (unit normal n) to every target it sees, sorted by id.
/// `skip`: an occluder that blocks nothing for this point (the patch it lies on). `scale`
/// sets the size of the tiny triangle standing for p in shaft queries.
fn point_row(
    ctx: Option<&Context>,
    p: Vec3,
    n: Vec3,
    t: &Targets,
    skip: Option<u32>,
    hard: &Hard,
    scale: f64,
) -> Result<Vec<(u32, f64)>> {
    point_row_with(ctx, p, n, t, skip, &|p, n, b| analytic::point_polygon(p, n, b.vertices()), hard, scale)
}

/// [`point_row`] with the unobstructed value of a target given by `free` (Lambert's F for a
/// plane element, the solid-angle fraction for a sphere).
#[allow(clippy::too_many_arguments)]
fn point_row_with(
    ctx: Option<&Context>,
    p: Vec3,
    n: Vec3,
    t: &Targets,
    skip: Option<u32>,
    free_of: &(dyn Fn(Vec3, Vec3, &Polygon) -> f64 + Sync),
    hard: &Hard,
    scale: f64,
) -> Result<Vec<(u32, f64)>> {
    let polys = t.polygons;
    // unobstructed F of every target, in Morton order
    let free: Vec<(u32, f64)> = t
        .order
        .iter()
        .filter_map(|&k| {
            let f = free_of(p, n, &polys[k as usize]);
            (f > 0.0).then_some((k, f))
        })
        .collect();
    let Some(ctx) = ctx else {
        let mut row = free;
        row.sort_unstable_by_key(|e| e.0);
        return Ok(row);
    };
    let src = obstructed::point_source(p, n, scale)?;
    let skip_ids: Vec<u32> = skip.into_iter().collect();
    let mut f: Vec<f64> = free.iter().map(|e| e.1).collect();
    let idx: Vec<u32> = (0..free.len() as u32).collect();
    let (mut cand, mut ignore) = (Vec::new(), Vec::with_capacity(2));
    blocked_clusters(
        &idx,
        |cluster, parent, among| {
            let (lo, hi) = bounding_box(cluster.iter().map(|&q| &polys[free[q as usize].0 as usize]));
            // A cluster of targets with one occluder (tiles of one wall) cannot be blocked
            // by it: each pair ignores its own occluder anyway.
            let first = t.own[free[cluster[0] as usize].0 as usize];
            let one = cluster.iter().all(|&q| t.own[free[q as usize].0 as usize] == first);
            let mut ids = skip_ids.clone();
            if one {
                ids.push(first);
            }
            ctx.vis.candidates_toward_box(&src, lo, hi, &ids, parent, among);
        },
        |cluster, among| {
            for &q in cluster {
                let k = free[q as usize].0 as usize;
                let b = &polys[k];
                ignore.clear();
                ignore.push(t.own[k]);
                ignore.extend(skip);
                if !cone_candidates(p, b, &ignore, among, &ctx.occluders.polygons, &mut cand) {
                    ctx.vis.candidates_among(&src, b, &ignore, among, &mut cand);
                }
                if cand.is_empty() {
                    continue;
                }
                let blockers: Vec<&Polygon> = cand.iter().map(|&c| &ctx.occluders.polygons[c as usize]).collect();
                f[q as usize] = if blockers.iter().any(|bl| hides_whole(&[p], b.vertices(), bl)) {
                    0.0
                } else {
                    hard(p, n, k, &blockers)?
                };
            }
            Ok(())
        },
    )?;
    let mut row: Vec<(u32, f64)> = free.iter().zip(&f).filter(|(_, &v)| v != 0.0).map(|(e, &v)| (e.0, v)).collect();
    row.sort_unstable_by_key(|e| e.0);
    Ok(row)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::hemisphere::testkit::room_with_crate;

    fn lcg(state: &mut u64) -> f64 {
        *state = state.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
        (*state >> 11) as f64 / (1u64 << 53) as f64
    }

    #[test]
    fn point_rows_equal_the_per_point_estimates_and_close() {
        // The batch path (clusters, cone tests) against obstructed::point pair by pair, and
        // closure inside the room.
        let (polys, _) = room_with_crate(3, 1);
        let n = polys.len();
        let scene = Scene::new(polys, vec![true; n]).unwrap();
        let ctx = scene.context().unwrap();
        let mut s = 7u64;
        let (mut pts, mut nrm) = (Vec::new(), Vec::new());
        while pts.len() < 12 {
            let p = Vec3::new(4.0 * lcg(&mut s), 3.0 * lcg(&mut s), 2.5 * lcg(&mut s));
            let inside_crate = p.x > 1.0 && p.x < 2.2 && p.y > 1.0 && p.y < 2.0 && p.z > 0.3 && p.z < 1.1;
            if !inside_crate {
                pts.push(p);
                nrm.push(Vec3::new(lcg(&mut s) - 0.5, lcg(&mut s) - 0.5, lcg(&mut s) - 0.5).normalize());
            }
        }
        let m = AnyMethod::Auto(Default::default());
        let b = scene.point_rows(&pts, &nrm, &m, true, &AtomicBool::new(false)).unwrap();
        let mut hidden = 0;
        for (k, (&p, &nv)) in pts.iter().zip(&nrm).enumerate() {
            let (lo, hi) = (b.indptr[k] as usize, b.indptr[k + 1] as usize);
            let row: std::collections::HashMap<i32, f64> =
                b.cols[lo..hi].iter().copied().zip(b.g[lo..hi].iter().copied()).collect();
            let sum: f64 = b.g[lo..hi].iter().sum();
            assert!((sum - 1.0).abs() < 1e-12, "point {k}: row sum {sum}");
            for j in 0..n {
                let want = obstructed::point(&ctx, p, nv, j, &m.estimator().unwrap()).unwrap().value;
                let got = row.get(&(j as i32)).copied().unwrap_or(0.0);
                assert!((got - want).abs() <= 1e-13, "point {k} polygon {j}: {got} against {want}");
                hidden += (want < analytic::point_polygon(p, nv, scene.polygons[j].vertices()) * (1.0 - 1e-9)) as usize;
            }
        }
        assert!(hidden > 20, "{hidden} hidden pairs");
        // spheres close too
        let sph = scene.point_sphere_rows(&pts, true, &AtomicBool::new(false)).unwrap();
        for k in 0..pts.len() {
            let sum: f64 = sph.g[sph.indptr[k] as usize..sph.indptr[k + 1] as usize].iter().sum();
            assert!((sum - 1.0).abs() < 1e-12, "sphere {k}: {sum}");
        }
        // and nothing of the sky is seen from inside
        for v in scene.point_sky(&pts, &nrm, &AtomicBool::new(false)).unwrap() {
            assert!(v < 1e-12, "{v}");
        }
    }
}
