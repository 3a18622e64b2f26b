//! One entry point for every method: a scene of polygons (some obstruction-only), method
//! selection by name, and the computations the Python layer asks for (blocks of rows, one
//! pair, one point).
//!
//! Visibility is decided once per scene: when every polygon has the whole scene on or in
//! front of its plane (a convex enclosure or a subset of one), no polygon can come between
//! two others, so no pair needs a visibility query at all. Otherwise every pair first gets
//! its unobstructed value from the vectorised rows of the exact kernel, clusters of a row's
//! receivers ask the BVH for candidate blockers once (a shaft test), and only pairs whose own
//! shaft keeps a candidate pay for visibility.

use crate::error::{Error, Result};
use crate::geometry::{Polygon, Vec3};
use crate::hemisphere::{
    hemicube_row, nusselt_row, raytrace_row, single_plane_row, HemicubeOptions, NusseltOptions, RaytraceOptions,
    RowResult, SinglePlaneOptions, SourcePoints,
};
pub use crate::matrix::PairRow;
use crate::matrix::{clamp_g, flatten_pair_rows, full_rows, upper_pair_rows, PairBlock};
use crate::obstructed::{
    self, AdaptiveOptions, ClippingOptions, Context, Estimate, Estimator, MonteCarloOptions, QuadratureOptions,
    SubdivisionOptions,
};
use crate::unobstructed::method::{self, AnalyticOptions, AutoOptions, ContourOptions, Method, Options, RuleCache};
use crate::unobstructed::rows as unobstructed_rows;
use crate::visibility::{Bvh, Occluders};
use crate::work;
use rayon::prelude::*;
use std::sync::atomic::AtomicBool;
use std::sync::OnceLock;

mod points;

/// Every method with its options (the options type of each is named as the method);
/// [`crate::registry::configure`] builds one from the name and options a user gives.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum AnyMethod {
    /// Unobstructed pairs by the cheapest rule that meets `tol`; pairs something may block by
    /// `clipping` to `obstructed_tol`.
    Auto(AutoOptions),
    /// Unobstructed pair kernels (closed form, double contour integral); pairs something may
    /// block by `clipping` from the kernel's value.
    Analytic(AnalyticOptions),
    Contour(ContourOptions),
    /// Pair methods with visibility.
    Quadrature(QuadratureOptions),
    MonteCarlo(MonteCarloOptions),
    Subdivision(SubdivisionOptions),
    Adaptive(AdaptiveOptions),
    Clipping(ClippingOptions),
    /// Whole rows by hemisphere sampling.
    Hemicube(HemicubeOptions),
    SinglePlane(SinglePlaneOptions),
    Raytrace(RaytraceOptions),
    Nusselt(NusseltOptions),
}

/// `$e` with `$o` bound to the options of any variant of `$m`.
macro_rules! with_options {
    ($m:expr, $o:ident => $e:expr) => {
        match $m {
            AnyMethod::Auto($o) => $e,
            AnyMethod::Analytic($o) => $e,
            AnyMethod::Contour($o) => $e,
            AnyMethod::Quadrature($o) => $e,
            AnyMethod::MonteCarlo($o) => $e,
            AnyMethod::Subdivision($o) => $e,
            AnyMethod::Adaptive($o) => $e,
            AnyMethod::Clipping($o) => $e,
            AnyMethod::Hemicube($o) => $e,
            AnyMethod::SinglePlane($o) => $e,
            AnyMethod::Raytrace($o) => $e,
            AnyMethod::Nusselt($o) => $e,
        }
    };
}

impl AnyMethod {
    /// The method named `name` at its defaults (None: no such method).
    pub fn from_name(name: &str) -> Option<AnyMethod> {
        use std::default::Default as D;
        [
            AnyMethod::Auto(D::default()),
            AnyMethod::Analytic(D::default()),
            AnyMethod::Contour(D::default()),
            AnyMethod::Quadrature(D::default()),
            AnyMethod::MonteCarlo(D::default()),
            AnyMethod::Subdivision(D::default()),
            AnyMethod::Adaptive(D::default()),
            AnyMethod::Clipping(D::default()),
            AnyMethod::Hemicube(D::default()),
            AnyMethod::SinglePlane(D::default()),
            AnyMethod::Raytrace(D::default()),
            AnyMethod::Nusselt(D::default()),
        ]
        .into_iter()
        .find(|m| m.name() == name)
    }

    /// The user-facing name.
    pub fn name(&self) -> &'static str {
        with_options!(self, o => o.name())
    }

    pub fn check(&self) -> Result<()> {
        with_options!(self, o => o.check())
    }

    /// Work units one pair or row may take (see [`crate::work`]).
    pub fn budget(&self) -> u64 {
        with_options!(self, o => o.budget)
    }

    /// Sets option `key` from `v` (checked against the registry); false when the method has
    /// no such option.
    pub(crate) fn set(&mut self, key: &str, v: &crate::registry::Value) -> bool {
        with_options!(self, o => o.set(key, v))
    }

    /// The unobstructed kernel of `analytic` and `contour` (None for the others).
    pub(crate) fn kernel(&self) -> Option<Method> {
        match self {
            AnyMethod::Analytic(_) => Some(Method::Analytic),
            AnyMethod::Contour(_) => Some(Method::Contour),
            _ => None,
        }
    }

    /// What the unobstructed kernels read: `auto`'s tol, `contour`'s nodes (defaults for
    /// the others).
    pub(crate) fn exact(&self) -> Options {
        match self {
            AnyMethod::Auto(o) => Options { tol: o.tol, ..Options::default() },
            AnyMethod::Contour(o) => Options { nodes: o.nodes, ..Options::default() },
            _ => Options::default(),
        }
    }

    /// The estimator of the pairs something may block: the method's own, `clipping` to
    /// `obstructed_tol` for `auto`, `analytic` and `contour`; None for a row method.
    pub fn estimator(&self) -> Option<Estimator> {
        let clip = |tol| Estimator::Clipping(ClippingOptions { tol, ..ClippingOptions::default() });
        Some(match *self {
            AnyMethod::Auto(o) => clip(o.obstructed_tol),
            AnyMethod::Analytic(o) => clip(o.obstructed_tol),
            AnyMethod::Contour(o) => clip(o.obstructed_tol),
            AnyMethod::Quadrature(o) => Estimator::Quadrature(o),
            AnyMethod::MonteCarlo(o) => Estimator::MonteCarlo(o),
            AnyMethod::Subdivision(o) => Estimator::Subdivision(o),
            AnyMethod::Adaptive(o) => Estimator::Adaptive(o),
            AnyMethod::Clipping(o) => Estimator::Clipping(o),
            AnyMethod::Hemicube(_) | AnyMethod::SinglePlane(_) | AnyMethod::Raytrace(_) | AnyMethod::Nusselt(_) => {
                return None
            }
        })
    }

    /// Whether this is a row method (whole rows by hemisphere sampling).
    pub fn is_row(&self) -> bool {
        self.estimator().is_none()
    }

    /// The pair estimator, or the error a row method gets where a pair method is needed.
    fn pair_estimator(&self) -> Result<Estimator> {
        self.estimator().ok_or_else(|| Error::InvalidArgument("a row method has no pair rows".into()))
    }
}

/// A scene: validated polygons, which of them get rows/columns, and lazily built helpers.
pub struct Scene {
    polygons: Vec<Polygon>,
    receiver: Vec<bool>,
    rules: RuleCache,
    /// for the row methods, which need to know which polygon a ray hits
    bvh: OnceLock<Result<Bvh>>,
    /// for the pair methods, which only ask whether something blocks
    occluders: OnceLock<Result<(Occluders, Bvh)>>,
    convex: OnceLock<bool>,
    /// Each polygon's position in the Morton order of the centroids (see [`morton_ranks`]).
    ranks: OnceLock<Vec<u32>>,
}

/// Receivers of a row that share one tree query for candidate blockers ([`Scene::visible_rows`]):
/// 32 neighbours in Morton order, halved while something may block. On the room of
/// bench/obstructed.py (1500 patches) anything from 8 to the whole row took the same time
/// within the host's noise.
const CLUSTER: usize = 32;

/// The receivers `items` (indices, in Morton order) in clusters of [`CLUSTER`], each halved
/// while something may block it: `candidates(cluster, parent, out)` writes the candidate
/// blockers of the cluster's box (searching only `parent`, the enclosing cluster's answer,
/// when there is one); a cluster with none is unobstructed as a whole and skipped. Clusters
/// of two or fewer get `leaf(cluster, among)` with their parent's answer, for each pair to
/// test its own shaft against.
fn blocked_clusters<'a>(
    items: &'a [u32],
    mut candidates: impl FnMut(&'a [u32], Option<&[u32]>, &mut Vec<u32>),
    mut leaf: impl FnMut(&'a [u32], &[u32]) -> Result<()>,
) -> Result<()> {
    let mut stack: Vec<(&[u32], Option<Vec<u32>>)> = items.chunks(CLUSTER).rev().map(|c| (c, None)).collect();
    while let Some((cluster, parent)) = stack.pop() {
        let among = match parent {
            Some(parent) if cluster.len() <= 2 => parent,
            parent => {
                let mut among = Vec::new();
                candidates(cluster, parent.as_deref(), &mut among);
                if among.is_empty() {
                    continue;
                }
                if cluster.len() > 2 {
                    let (x, y) = cluster.split_at(cluster.len() / 2);
                    stack.push((y, Some(among.clone())));
                    stack.push((x, Some(among)));
                    continue;
                }
                among
            }
        };
        leaf(cluster, &among)?;
    }
    Ok(())
}

/// The bounding box of the vertices of `polys`.
fn bounding_box<'a>(polys: impl Iterator<Item = &'a Polygon>) -> (Vec3, Vec3) {
    let (mut lo, mut hi) = (Vec3::splat(f64::INFINITY), Vec3::splat(f64::NEG_INFINITY));
    for v in polys.flat_map(|q| q.vertices()) {
        lo = lo.min(*v);
        hi = hi.max(*v);
    }
    (lo, hi)
}

/// Each polygon's rank in the Morton (Z-order) sequence of the centroids, 21 bits per axis of
/// the scene's box: polygons close in rank are close in space.
fn morton_ranks(polys: &[Polygon]) -> Vec<u32> {
    let (mut lo, mut hi) = (Vec3::splat(f64::INFINITY), Vec3::splat(f64::NEG_INFINITY));
    for p in polys {
        lo = lo.min(p.centroid());
        hi = hi.max(p.centroid());
    }
    let ext = (hi - lo).max(Vec3::splat(f64::MIN_POSITIVE));
    let spread = |v: u64| {
        // the 21 bits of v spaced out to every third bit
        let mut x = v & 0x1f_ffff;
        x = (x | x << 32) & 0x1f00000000ffff;
        x = (x | x << 16) & 0x1f0000ff0000ff;
        x = (x | x << 8) & 0x100f00f00f00f00f;
        x = (x | x << 4) & 0x10c30c30c30c30c3;
        (x | x << 2) & 0x1249249249249249
    };
    let key = |p: &Polygon| {
        let u = (p.centroid() - lo) / ext * 2_097_151.0;
        spread(u.x as u64) | spread(u.y as u64) << 1 | spread(u.z as u64) << 2
    };
    let mut order: Vec<(u64, u32)> = polys.iter().enumerate().map(|(k, p)| (key(p), k as u32)).collect();
    order.sort_unstable();
    let mut rank = vec![0u32; polys.len()];
    for (r, &(_, k)) in order.iter().enumerate() {
        rank[k as usize] = r as u32;
    }
    rank
}

impl Scene {
    pub fn new(polygons: Vec<Polygon>, receiver: Vec<bool>) -> Result<Self> {
        if receiver.len() != polygons.len() {
            return Err(Error::InvalidArgument("receiver mask length differs from polygon count".into()));
        }
        if polygons.len() > i32::MAX as usize {
            return Err(Error::InvalidArgument(format!("{} polygons: at most 2^31 - 1 are supported", polygons.len())));
        }
        let rules = RuleCache::new(polygons.len());
        Ok(Scene {
            polygons,
            receiver,
            rules,
            bvh: OnceLock::new(),
            occluders: OnceLock::new(),
            convex: OnceLock::new(),
            ranks: OnceLock::new(),
        })
    }

    pub fn polygons(&self) -> &[Polygon] {
        &self.polygons
    }

    fn bvh(&self) -> Result<&Bvh> {
        self.bvh.get_or_init(|| Bvh::new(&self.polygons)).as_ref().map_err(|e| e.clone())
    }

    /// True when no polygon can block any pair: every vertex of the scene lies on or in
    /// front of every polygon's plane (relative tolerance).
    pub fn unobstructed(&self) -> bool {
        *self.convex.get_or_init(|| {
            let size: f64 = self.polygons.iter().map(|p| p.radius()).fold(0.0, f64::max);
            let tol = 1e-9 * size.max(f64::MIN_POSITIVE);
            // Polygons sharing a plane (the same normal bit for bit, offsets within tol/4) need
            // one test, against the group's largest offset (the strictest): meshes of flat
            // walls have few planes. Offsets too large for the buckets are not grouped.
            let quantum = tol / 4.0;
            let mut groups: std::collections::HashMap<([u64; 3], i64), f64> = std::collections::HashMap::new();
            let mut planes: Vec<(Vec3, f64)> = Vec::new();
            for p in &self.polygons {
                let (n, d) = (p.normal(), p.normal().dot(p.centroid()));
                let bucket = (d / quantum).floor();
                if bucket.abs() < 4.5e15 {
                    let e = groups.entry(([n.x.to_bits(), n.y.to_bits(), n.z.to_bits()], bucket as i64)).or_insert(d);
                    *e = e.max(d);
                } else {
                    planes.push((n, d));
                }
            }
            planes.extend(
                groups.into_iter().map(|((n, _), d)| {
                    (Vec3::new(f64::from_bits(n[0]), f64::from_bits(n[1]), f64::from_bits(n[2])), d)
                }),
            );
            // O(planes x N) vertex tests: in parallel, stopping at the first polygon behind a plane
            planes.par_iter().all(|&(n, d)| {
                self.polygons.iter().all(|q| {
                    // bounding sphere wholly in front: no need to look at the vertices
                    n.dot(q.centroid()) - d - q.radius() >= -tol || q.vertices().iter().all(|v| n.dot(*v) - d >= -tol)
                })
            })
        })
    }

    fn context(&self) -> Result<Context<'_>> {
        let occ = self.occluders.get_or_init(|| {
            let occ = Occluders::new(&self.polygons);
            Bvh::new(&occ.polygons).map(|bvh| (occ, bvh))
        });
        let (occluders, vis) = occ.as_ref().map_err(|e| e.clone())?;
        let exact_tol = Options::default().tol;
        Ok(Context { polygons: &self.polygons, occluders, vis, rules: Some(&self.rules), exact_tol })
    }

    /// [`Scene::context`] for the pair estimators of method `m` (the unobstructed G they
    /// compute is `auto`'s at `m`'s kernel tol).
    fn pair_context(&self, m: &AnyMethod) -> Result<Context<'_>> {
        Ok(Context { exact_tol: m.exact().tol, ..self.context()? })
    }

    /// G_ij = A_i F_ij for every row i in `rows` and receiver j > i (pair methods).
    pub fn pair_rows(&self, rows: &[usize], m: &AnyMethod, cancel: &AtomicBool) -> Result<Vec<PairRow>> {
        m.check()?;
        let n = self.polygons.len();
        let p = &self.polygons;
        let skip = |i: usize, j: usize| method::facing(&p[i], &p[j]) == method::Facing::None;
        let free = self.unobstructed();
        let (est, exact) = (m.pair_estimator()?, m.exact());
        let est: Box<dyn Fn(usize, usize) -> Result<Estimate> + Sync> = match m.kernel() {
            Some(mm) if free => Box::new(move |i, j| Ok(Estimate::exact(self.exact_g(i, j, mm, &exact)?))),
            Some(_) => return self.visible_rows(rows, m, cancel),
            None if free && matches!(m, AnyMethod::Auto(_)) => {
                return Ok(unobstructed_rows::pair_block(p, &self.receiver, &self.rules, rows, &exact, cancel)?.rows());
            }
            None if obstructed::exact_when_unobstructed(&est) => return self.visible_rows(rows, m, cancel),
            None => {
                let ctx = self.pair_context(m)?;
                let budget = m.budget();
                Box::new(move |i, j| {
                    work::metered(budget, || pair_what(m, i, j), || obstructed::pair(&ctx, i, j, &est))
                })
            }
        };
        upper_pair_rows(n, rows, &self.receiver, cancel, skip, |i, j| {
            let e = est(i, j)?;
            Ok((e.value != 0.0 || e.std_err != 0.0).then_some((e.value, e.std_err)))
        })
        .map(|rows| {
            rows.into_iter()
                .map(|r| PairRow {
                    cols: r.iter().map(|e| e.0).collect(),
                    g: r.iter().map(|e| e.1 .0).collect(),
                    std: Some(r.iter().map(|e| e.1 .1).collect()),
                })
                .collect()
        })
    }

    /// The unobstructed G_ij of an exact kernel (`analytic`, `contour`).
    fn exact_g(&self, i: usize, j: usize, mm: Method, exact: &Options) -> Result<f64> {
        method::area_factor(&self.polygons[i], &self.polygons[j], mm, exact, Some((&self.rules, i, j)))
    }

    /// Pair rows of a method that computes unobstructed pairs exactly, on a scene where
    /// something may block: the unobstructed G of every pair first (the vectorised rows of
    /// an enclosure for the methods with visibility, the method's own kernel for `analytic`
    /// and `contour`), then per row one shaft query per cluster of receivers (see
    /// [`CLUSTER`]); only the pairs of a cluster something may block test their own shaft
    /// against that query's answer, and only pairs with candidates left pay for visibility
    /// (`analytic` and `contour`: the exact visible region, `clipping` to `vis.tol`). The
    /// same values as asking [`obstructed::pair_with`] pair by pair, at a fraction of the cost.
    fn visible_rows(&self, rows: &[usize], m: &AnyMethod, cancel: &AtomicBool) -> Result<Vec<PairRow>> {
        let p = &self.polygons;
        let ctx = self.pair_context(m)?;
        let (estimator, exact) = (m.pair_estimator()?, m.exact());
        let free = match m.kernel() {
            None => unobstructed_rows::pair_block(p, &self.receiver, &self.rules, rows, &exact, cancel)?,
            Some(mm) => {
                let skip = |i: usize, j: usize| method::facing(&p[i], &p[j]) == method::Facing::None;
                let g = upper_pair_rows(p.len(), rows, &self.receiver, cancel, skip, |i, j| {
                    let g = self.exact_g(i, j, mm, &exact)?;
                    Ok((g != 0.0).then_some(g))
                })?;
                let g: Vec<PairRow> = g
                    .into_iter()
                    .map(|r| PairRow {
                        cols: r.iter().map(|e| e.0).collect(),
                        g: r.iter().map(|e| e.1).collect(),
                        std: None,
                    })
                    .collect();
                flatten_pair_rows(&g)?
            }
        };
        let ranks = self.ranks.get_or_init(|| morton_ranks(p));
        rows.par_iter()
            .enumerate()
            .map(|(r, &i)| {
                if cancel.load(std::sync::atomic::Ordering::Relaxed) {
                    return Err(Error::Cancelled);
                }
                let (s, e) = (free.indptr[r] as usize, free.indptr[r + 1] as usize);
                let (cols, g0) = (&free.cols[s..e], &free.g[s..e]);
                let mut g = g0.to_vec();
                let mut std = vec![0.0; g.len()];
                let mut order: Vec<u32> = (0..cols.len() as u32).collect();
                order.sort_unstable_by_key(|&k| ranks[cols[k as usize] as usize]);
                // Clusters of receivers, halved while something may block; pairs of two or
                // fewer test their own shafts against the parent's answer.
                let own = [ctx.occluders.owner[i]];
                blocked_clusters(
                    &order,
                    |cluster, parent, among| {
                        let (lo, hi) = bounding_box(cluster.iter().map(|&k| &p[cols[k as usize] as usize]));
                        ctx.vis.candidates_toward_box(&p[i], lo, hi, &own, parent, among);
                    },
                    |cluster, among| {
                        for &k in cluster {
                            let (k, j) = (k as usize, cols[k as usize] as usize);
                            let known = obstructed::Known { free: Some(g0[k]), among: Some(among) };
                            let est = work::metered(
                                m.budget(),
                                || pair_what(m, i, j),
                                || obstructed::pair_with(&ctx, i, j, &estimator, known),
                            )?;
                            (g[k], std[k]) = (est.value, est.std_err);
                        }
                        Ok(())
                    },
                )?;
                let keep: Vec<usize> = (0..g.len()).filter(|&k| g[k] != 0.0 || std[k] != 0.0).collect();
                Ok(PairRow {
                    cols: keep.iter().map(|&k| cols[k] as u32).collect(),
                    g: keep.iter().map(|&k| g[k]).collect(),
                    std: Some(keep.iter().map(|&k| std[k]).collect()),
                })
            })
            .collect()
    }

    /// [`Scene::pair_rows`] as one block of CSR parts (what the Python layer stores); an
    /// unobstructed scene with `auto` writes its rows straight into the block.
    pub fn pair_block(&self, rows: &[usize], m: &AnyMethod, cancel: &AtomicBool) -> Result<PairBlock> {
        let mut block = if matches!(m, AnyMethod::Auto(_)) && self.unobstructed() {
            m.check()?;
            unobstructed_rows::pair_block(&self.polygons, &self.receiver, &self.rules, rows, &m.exact(), cancel)?
        } else {
            flatten_pair_rows(&self.pair_rows(rows, m, cancel)?)?
        };
        let areas: Vec<f64> = self.polygons.iter().map(|p| p.area()).collect();
        block.clamp_to_areas(rows, &areas);
        Ok(block)
    }

    /// Whole rows F_i. by hemisphere sampling (row methods).
    pub fn full_rows(&self, rows: &[usize], m: &AnyMethod, cancel: &AtomicBool) -> Result<Vec<RowResult>> {
        if !m.is_row() {
            return Err(Error::InvalidArgument(format!("method {:?} is a pair method: it has no full rows", m.name())));
        }
        let vis = match m {
            AnyMethod::Raytrace(_) | AnyMethod::Nusselt(_) => Some(self.bvh()?),
            _ => None,
        };
        full_rows(self.polygons.len(), rows, &self.receiver, cancel, |i| {
            if !self.receiver[i] {
                return Ok(RowResult::default());
            }
            let what = || format!("method {:?}: row {i}", m.name());
            let (p, r) = (&self.polygons, &self.receiver);
            work::metered(m.budget(), what, || match m {
                AnyMethod::Hemicube(o) => hemicube_row(p, r, i, o),
                AnyMethod::SinglePlane(o) => single_plane_row(p, r, i, o),
                AnyMethod::Raytrace(o) => raytrace_row(p, vis.unwrap(), r, i, o),
                AnyMethod::Nusselt(o) => nusselt_row(p, vis.unwrap(), r, i, o),
                _ => unreachable!("checked above: a row method"),
            })
        })
    }
}

/// What a budget error names: the method and the pair.
fn pair_what(m: &AnyMethod, i: usize, j: usize) -> String {
    format!("method {:?}: pair ({i}, {j})", m.name())
}

/// A scene of `polys` followed by `obstacles`; the first `receivers` polygons get rows and
/// columns (all of them when None).
fn scene_of(mut polys: Vec<Polygon>, obstacles: Vec<Polygon>, receivers: Option<usize>) -> Result<Scene> {
    let k = receivers.unwrap_or(polys.len() + obstacles.len());
    polys.extend(obstacles);
    let receiver = (0..polys.len()).map(|q| q < k).collect();
    Scene::new(polys, receiver)
}

/// F from `source` to `b` (with `obstacles`) by a row method: the source's row on a scene
/// where only the two receive.
fn row_entry_of(source: Polygon, b: Polygon, obstacles: Vec<Polygon>, m: &AnyMethod) -> Result<Estimate> {
    let scene = scene_of(vec![source, b], obstacles, Some(2))?;
    let row = scene.full_rows(&[0], m, &AtomicBool::new(false))?.pop().unwrap_or_default();
    Ok(row_entry(&row, 1))
}

/// F_ab for a single pair with optional obstacles (opaque from both sides). `analytic` and
/// `contour` keep their kernel where nothing may block; where something may, the pair is
/// the exact visible region integrated over the source (`clipping` to `vis.tol`) from that
/// kernel's unobstructed G.
pub fn pair_view_factor(a: Polygon, b: Polygon, obstacles: Vec<Polygon>, m: &AnyMethod) -> Result<Estimate> {
    m.check()?;
    let area = a.area();
    let Some(est) = m.estimator() else {
        let e = row_entry_of(a, b, obstacles, m)?;
        return Ok(Estimate { value: e.value.clamp(0.0, 1.0), ..e });
    };
    let free = match m.kernel() {
        Some(mm) => {
            let g = method::area_factor(&a, &b, mm, &m.exact(), None)?;
            if obstacles.is_empty() {
                return Ok(Estimate::exact(clamp_g(g, area, b.area()) / area));
            }
            Some(g)
        }
        None => None,
    };
    let scene = scene_of(vec![a, b], obstacles, None)?;
    let ctx = scene.pair_context(m)?;
    let known = obstructed::Known { free, among: None };
    let e = work::metered(m.budget(), || pair_what(m, 0, 1), || obstructed::pair_with(&ctx, 0, 1, &est, known))?;
    let area_b = scene.polygons[1].area();
    Ok(Estimate { value: clamp_g(e.value, area, area_b) / area, std_err: e.std_err / area })
}

/// F from a differential area (p, unit n) to polygon b, with optional obstacles; in [0, 1]
/// (rounding of cancelling sums can leave a method's value just outside). `analytic` and
/// `contour` with obstacles: Lambert's form on the exact visible region (as `clipping`).
pub fn point_view_factor(p: Vec3, n: Vec3, b: Polygon, obstacles: Vec<Polygon>, m: &AnyMethod) -> Result<Estimate> {
    m.check()?;
    if !p.is_finite() || !n.is_finite() || !((n.length() - 1.0).abs() < 1e-6) {
        return Err(Error::InvalidArgument("point and unit normal must be finite".into()));
    }
    let e = match (m.kernel(), m.estimator()) {
        (Some(mm), _) if obstacles.is_empty() => Estimate::exact(method::point_factor(p, n, &b, mm, &m.exact())?),
        (_, Some(est)) => {
            let scene = scene_of(vec![b], obstacles, None)?;
            let ctx = scene.pair_context(m)?;
            let what = || format!("method {:?}: the point", m.name());
            work::metered(m.budget(), what, || obstructed::point(&ctx, p, n, 0, &est))?
        }
        (_, None) => {
            // The point becomes a tiny source patch sampled at its centroid (= p).
            let size = b.radius().max(p.distance(b.centroid()));
            let (t, s) = crate::geometry::tangent_frame(n);
            // (and resolved in p's coordinates, as for the candidate test of obstructed::point)
            let e = (1e-7 * size).max(1e-9 * p.abs().max_element());
            let tri = Polygon::new(vec![
                p + e * (2.0 * t),
                p + e * (-t + 1.7320508075688772 * s),
                p + e * (-t - 1.7320508075688772 * s),
            ])
            .map_err(|err| Error::InvalidArgument(format!("point source: {err}")))?;
            let mut m = *m;
            match &mut m {
                AnyMethod::Hemicube(o) => o.source = SourcePoints::Centre,
                AnyMethod::SinglePlane(o) => o.source = SourcePoints::Centre,
                AnyMethod::Nusselt(o) => o.source = SourcePoints::Centre,
                _ => {}
            }
            row_entry_of(tri, b, obstacles, &m)?
        }
    };
    Ok(Estimate { value: e.value.clamp(0.0, 1.0), ..e })
}

fn row_entry(row: &RowResult, j: u32) -> Estimate {
    let k = row.entries.binary_search_by_key(&j, |e| e.0).ok();
    Estimate {
        value: k.map_or(0.0, |k| row.entries[k].1),
        std_err: match (&row.std_err, k) {
            (Some(s), Some(k)) => s[k],
            _ => 0.0,
        },
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::hemisphere::testkit::room_with_crate;
    use crate::visibility::Visibility;

    #[test]
    fn visible_rows_equal_the_pair_by_pair_estimates() {
        // The row path (unobstructed G from the vectorised rows, shaft queries per cluster of
        // receivers) against obstructed::pair asked for each pair on its own.
        let (polys, _) = room_with_crate(3, 1);
        let n = polys.len();
        let scene = Scene::new(polys, vec![true; n]).unwrap();
        assert!(!scene.unobstructed());
        let rows: Vec<usize> = (0..n).collect();
        let auto = AnyMethod::Auto(AutoOptions { obstructed_tol: 1e-4, ..Default::default() });
        let ctx = scene.pair_context(&auto).unwrap();
        for m in [
            auto,
            AnyMethod::Clipping(ClippingOptions { tol: 1e-4, source: Some(1), ..Default::default() }),
            AnyMethod::Subdivision(SubdivisionOptions { divisions: 6, source: Some(2), ..Default::default() }),
            AnyMethod::Quadrature(QuadratureOptions { tol: 1e-4, order: 4, ..Default::default() }),
            AnyMethod::MonteCarlo(MonteCarloOptions { samples: 256, ..Default::default() }),
        ] {
            let est = m.estimator().unwrap();
            let out = scene.pair_rows(&rows, &m, &AtomicBool::new(false)).unwrap();
            let (mut pairs, mut hidden) = (0, 0);
            for (i, row) in rows.iter().zip(&out) {
                let mut k = 0;
                for j in i + 1..n {
                    let want = obstructed::pair(&ctx, *i, j, &est).unwrap();
                    let free =
                        method::area_factor(&scene.polygons[*i], &scene.polygons[j], Method::Auto, &m.exact(), None)
                            .unwrap();
                    let got = if row.cols.get(k) == Some(&(j as u32)) {
                        k += 1;
                        (row.g[k - 1], row.std.as_ref().unwrap()[k - 1])
                    } else {
                        (0.0, 0.0)
                    };
                    pairs += (want.value != 0.0) as usize;
                    hidden += (want.value < (1.0 - 1e-3) * free) as usize;
                    let err = (got.0 - want.value).abs();
                    assert!(err <= 1e-12 * free, "{m:?} pair {i} {j}: {} against {} (free {free})", got.0, want.value);
                    assert_eq!(got.1, want.std_err, "{m:?} pair {i} {j}");
                }
                assert_eq!(k, row.cols.len());
            }
            assert!(pairs > 1000 && hidden > 100, "{m:?}: {pairs} pairs, {hidden} hidden");
        }
    }

    #[test]
    fn exact_kernels_keep_their_values_where_nothing_blocks_and_clip_elsewhere() {
        // `analytic` and `contour` on a room with a crate: a pair whose shaft holds no
        // blocker is the kernel's value bit for bit; the others are the exact visible region
        // from that value, as `clipping` gives it pair by pair.
        let (polys, _) = room_with_crate(3, 1);
        let n = polys.len();
        let scene = Scene::new(polys, vec![true; n]).unwrap();
        let rows: Vec<usize> = (0..n).collect();
        let ctx = Context { exact_tol: 1e-12, ..scene.context().unwrap() };
        let tight = Estimator::Clipping(ClippingOptions { tol: 1e-9, ..Default::default() });
        for m in [
            AnyMethod::Analytic(AnalyticOptions { obstructed_tol: 1e-6, ..Default::default() }),
            AnyMethod::Contour(ContourOptions { obstructed_tol: 1e-6, ..Default::default() }),
        ] {
            let mm = m.kernel().unwrap();
            let out = scene.pair_rows(&rows, &m, &AtomicBool::new(false)).unwrap();
            let (mut free_pairs, mut blocked) = (0, 0);
            for (&i, row) in rows.iter().zip(&out) {
                for (j, g, std) in row.iter() {
                    let j = j as usize;
                    assert_eq!(std, 0.0);
                    let free = scene.exact_g(i, j, mm, &m.exact()).unwrap();
                    let mut cand = Vec::new();
                    let owner = &ctx.occluders.owner;
                    ctx.vis.candidates_between(
                        &scene.polygons[i],
                        &scene.polygons[j],
                        &[owner[i], owner[j]],
                        &mut cand,
                    );
                    if cand.is_empty() {
                        assert_eq!(g.to_bits(), free.to_bits(), "{mm:?} pair {i} {j}");
                        free_pairs += 1;
                        continue;
                    }
                    let want = obstructed::pair(&ctx, i, j, &tight).unwrap().value;
                    assert!((g - want).abs() <= 2e-6 * free, "{mm:?} pair {i} {j}: {g} against {want} (free {free})");
                    assert!(g <= free, "{mm:?} pair {i} {j}");
                    blocked += (g < (1.0 - 1e-3) * free) as usize;
                }
            }
            assert!(free_pairs > 500 && blocked > 200, "{mm:?}: {free_pairs} free, {blocked} blocked");
        }
    }

    #[test]
    fn joined_occluders_give_the_values_of_the_tiles() {
        // Walls of 3 x 3 tiles and a crate of 3 x 3 tiles per face join into 12 occluders;
        // obstructed pairs get the values that the tiles as separate blockers give.
        let (polys, _) = room_with_crate(3, 3);
        let n = polys.len();
        let scene = Scene::new(polys.clone(), vec![true; n]).unwrap();
        let ctx = Context { exact_tol: 1e-12, ..scene.context().unwrap() };
        assert_eq!(ctx.occluders.polygons.len(), 12);
        let ids: Vec<u32> = (0..n as u32).collect();
        let tiles = Occluders { polygons: polys.clone(), owner: ids.clone(), member: ids };
        let bvh = Bvh::new(&polys).unwrap();
        let tile_ctx = Context { polygons: &polys, occluders: &tiles, vis: &bvh, rules: None, exact_tol: 1e-12 };
        let clip2 = Estimator::Clipping(ClippingOptions { source: Some(2), ..Default::default() });
        // `auto` on an obstructed pair is `clipping` at its obstructed_tol
        let auto = Estimator::Clipping(ClippingOptions { tol: 1e-6, ..Default::default() });
        let (mut checked, mut cand) = (0, Vec::new());
        for i in (0..n).step_by(3) {
            for j in (i + 1..n).step_by(5) {
                bvh.candidates_between(&polys[i], &polys[j], &[i as u32, j as u32], &mut cand);
                let free = method::area_factor(
                    &polys[i],
                    &polys[j],
                    Method::Auto,
                    &Options { tol: 1e-12, ..Default::default() },
                    None,
                )
                .unwrap();
                if cand.is_empty() || free == 0.0 {
                    continue;
                }
                for (m, tol) in [(&clip2, 1e-12), (&auto, 2e-6)] {
                    let (a, b) = (
                        obstructed::pair(&ctx, i, j, m).unwrap().value,
                        obstructed::pair(&tile_ctx, i, j, m).unwrap().value,
                    );
                    assert!((a - b).abs() <= tol * free, "{m:?} pair {i} {j}: joined {a}, tiles {b}, free {free}");
                }
                checked += 1;
            }
        }
        assert!(checked > 40, "{checked} obstructed pairs");
    }
}
