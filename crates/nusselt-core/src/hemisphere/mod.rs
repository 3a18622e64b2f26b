//! Whole rows of the form-factor matrix by sampling the hemisphere above a source patch.
//!
//! Every method here looks out from points on patch i and attributes each piece of the
//! hemisphere to the first patch seen there, so one pass yields F_ij for all j at once
//! (docs/algorithms.md §1.1: F_{dA -> A_j} = projected solid angle of the visible part of A_j / pi,
//! and F_ij is its area average over A_i):
//!
//! * [`hemicube_row`]: five z-buffered faces with exact cell integrals (Cohen & Greenberg 1985),
//! * [`single_plane_row`]: one plane with Warnock area subdivision (Sillion & Puech 1989),
//! * [`raytrace_row`]: cosine-distributed rays, Owen-scrambled Sobol (reverse Nusselt),
//! * [`nusselt_row`]: the Nusselt analogue on an equal-area partition of the unit disk.
//!
//! Only front sides receive: a piece of hemisphere that sees a polygon's back side is blocked
//! but lost, as is any piece that sees nothing (an open scene) and, for the single plane, the
//! horizon band the plane misses. `RowResult::lost` reports that fraction. Hits on
//! polygons that are not receivers are blocked and simply not reported (they are not lost).
//!
//! One loop serves all four (`row_over_points`): it checks the arguments, places the source
//! points with their (randomly rotated) tangent frames, keeps the per-thread accumulator over
//! patch ids and reads the row out; a method supplies only what one eye sees.
//!
//! The functions are pure (no shared mutable state, per-thread scratch buffers), so the
//! caller may run rows in parallel. Memory is O(N) per thread, never N x N.

pub mod hemicube;
pub mod nusselt_analog;
pub mod raytrace;
pub mod single_plane;
mod source_cuts;

pub use hemicube::{hemicube_row, HemicubeOptions};
pub use nusselt_analog::{nusselt_row, NusseltOptions};
pub use raytrace::{raytrace_row, RaytraceOptions};
pub use single_plane::{single_plane_row, SinglePlaneOptions};

use crate::error::{Error, Result};
use crate::geometry::{Polygon, Vec3};
use crate::sampling::{hash_seed, hash_unit, sobol4, PolygonSampler};
use std::cell::RefCell;
use std::f64::consts::PI;

/// One row F_i. of the form-factor matrix.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct RowResult {
    /// (j, F_ij) for every receiver j with F_ij > 0, increasing j.
    pub entries: Vec<(u32, f64)>,
    /// Standard error of each entry (same order), for the sampling methods that have one.
    pub std_err: Option<Vec<f64>>,
    /// Fraction of the source's hemisphere assigned to no patch: back-face hits, directions
    /// that see nothing, and (single plane) the horizon band missed by the plane.
    pub lost: f64,
    /// Rays cast (raytrace, fewer than `rays` where `row_tol` stopped the row), or the
    /// resolution a hemicube row with `row_tol` stopped at; 0 otherwise.
    pub samples: u32,
}

impl RowResult {
    /// Sum of the reported entries.
    pub fn sum(&self) -> f64 {
        self.entries.iter().map(|e| e.1).sum()
    }
    /// F_ij, 0 if absent.
    pub fn get(&self, j: u32) -> f64 {
        self.entries.binary_search_by_key(&j, |e| e.0).map_or(0.0, |k| self.entries[k].1)
    }
}

/// Where on the source patch the hemisphere is sampled. The row is the weighted sum of the
/// point rows (weights sum to 1), i.e. an area quadrature of F_{dA -> A_j} over patch i.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum SourcePoints {
    /// The area centroid only: F_ij ~ F_{dA_centre -> A_j}. Fine for patches small compared
    /// with their distance to others (about 1 % beyond five patch sizes, docs/algorithms.md §2.4).
    Centre,
    /// n area-uniform points, the first n of an Owen-scrambled Sobol (0,2)-sequence mapped
    /// onto the patch (stratified: use a power of two), equal weights 1/n. 1 <= n <= 4096.
    Points(u32),
    /// A k x k Gauss-Legendre product rule on the patch (bilinear map for a convex quad,
    /// collapsed map per triangle otherwise, see [`crate::quadrature::polygon_gauss_points`]):
    /// converges much faster than random points where F_{dA -> A_j} varies smoothly over the
    /// patch. 1 <= k <= [`MAX_GAUSS_ORDER`].
    Gauss(u32),
    /// Chooses by the patch's size relative to the scene, rho = radius_i / (AUTO_REL_SIZE *
    /// scene diameter): the centroid for rho <= 1, else Gauss(min(ceil(rho), AUTO_MAX_ORDER)).
    /// Small patches in a large scene get one point (their proximity errors average out at
    /// surface level, a midpoint rule); patches that are a sizeable part of the scene get up
    /// to 64 points. Gauss is very accurate where the view varies smoothly over the patch
    /// (2 x 2: 1.5e-3 on two unit squares at distance 1, where the centre is 4e-2 off;
    /// 3 x 3: 2e-5); where an obstacle casts a shadow across a large patch the integrand
    /// jumps and only the number of points helps, hence the growth with rho. The cost per
    /// unit scene area stays about constant.
    Auto,
}

/// See [`SourcePoints::Auto`].
pub const AUTO_REL_SIZE: f64 = 0.03;
/// Largest Gauss order [`SourcePoints::Auto`] uses (8 x 8 = 64 points).
pub const AUTO_MAX_ORDER: u32 = 8;
/// Largest number of source points accepted.
pub const MAX_SOURCE_POINTS: u32 = 4096;
/// Largest k of a k x k Gauss rule of source points (also the range of every method's
/// `source` option in the registry).
pub const MAX_GAUSS_ORDER: u32 = 16;

/// Checks a method's near-plane distance (relative to the source radius): in (0, 0.1].
fn check_near(method: &str, near: f64) -> Result<()> {
    if near > 0.0 && near <= 0.1 {
        Ok(())
    } else {
        Err(Error::InvalidArgument(format!("{method} near must be in (0, 0.1], got {near}")))
    }
}

impl SourcePoints {
    /// Checks the points as the `source` option of row method `method`: a Gauss order in
    /// that option's range in the registry (0 there means [`SourcePoints::Centre`]).
    pub(crate) fn check(&self, method: &str) -> Result<()> {
        if let SourcePoints::Gauss(k) = *self {
            if k == 0 {
                return Err(Error::InvalidArgument(format!(
                    "method {method:?}: source points: a Gauss rule needs k >= 1 (use Centre)"
                )));
            }
            crate::registry::check_field(method, "source", crate::registry::Value::Int(k.into()))?;
        }
        if let SourcePoints::Points(n) = *self {
            if n == 0 || n > MAX_SOURCE_POINTS {
                return Err(Error::InvalidArgument(format!(
                    "source points: {n} is out of range 1..={MAX_SOURCE_POINTS}"
                )));
            }
        }
        Ok(())
    }

    /// The points and weights for `poly` (row `i` of a scene whose diameter is
    /// `scene_size`), written to `out`. Deterministic in (seed, i).
    pub(crate) fn generate(&self, poly: &Polygon, scene_size: f64, seed: u64, i: usize, out: &mut Vec<(Vec3, f64)>) {
        out.clear();
        if let SourcePoints::Gauss(k) = *self {
            crate::quadrature::polygon_gauss_points(poly, k as usize, out);
            return;
        }
        let n = match *self {
            SourcePoints::Centre | SourcePoints::Gauss(_) => 0,
            SourcePoints::Points(n) => n,
            SourcePoints::Auto => {
                let rho = poly.radius() / (AUTO_REL_SIZE * scene_size.max(f64::MIN_POSITIVE));
                if rho > 1.0 {
                    crate::quadrature::polygon_gauss_points(poly, rho.ceil().min(AUTO_MAX_ORDER as f64) as usize, out);
                    return;
                }
                0
            }
        };
        if n == 0 {
            out.push((poly.centroid(), 1.0));
            return;
        }
        let sampler = PolygonSampler::new(poly);
        let s = hash_seed(seed, &[i as u64, 0x5EED_0F50_u64]);
        let w = 1.0 / n as f64;
        for k in 0..n {
            let u = sobol4(k, s);
            out.push((sampler.sample([u[0], u[1]]), w));
        }
    }
}

/// Where a row method looks out from.
#[derive(Debug, Clone, Copy)]
pub(crate) enum Points {
    /// The points of `source` (deterministic in `seed` and the row), each with its frame
    /// rotated about the normal by 2 pi hash(seed, row, point, salt) when `rotation` holds the
    /// method's salt, unrotated when it is None.
    Rule { source: SourcePoints, seed: u64, rotation: Option<u64> },
    /// One eye at the centroid with weight 1 and the unrotated frame: for a method that samples
    /// points of the patch itself, jointly with its directions (raytrace).
    WholePatch,
}

/// One source point of a row: position, tangent frame (u, v, n) and quadrature weight.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Eye {
    pub p: Vec3,
    pub u: Vec3,
    pub v: Vec3,
    pub n: Vec3,
    pub weight: f64,
    /// Index of the point in the row (seeds per-point randomness).
    pub k: usize,
}

thread_local! {
    static ROW: RefCell<(Accum, Vec<(Vec3, f64)>)> = RefCell::new(Default::default());
}

/// The source-point loop of every row method. For each eye, `look(eye, acc, lost)` adds
/// weight x F(eye -> j) of what it sees to `acc[j]` and the weight of what it loses to `lost`,
/// and returns false to stop (work budget spent or cancelled: the caller discards the row).
/// Returns the receivers' entries and the summed `lost`; `std_err` is left to the method.
pub(crate) fn row_over_points(
    scene: &[Polygon],
    receivers: &[bool],
    i: usize,
    points: Points,
    mut look: impl FnMut(&Eye, &mut Accum, &mut f64) -> bool,
) -> Result<RowResult> {
    check_row(scene, receivers, i)?;
    let src = &scene[i];
    let n = src.normal();
    ROW.with(|r| {
        let mut r = r.borrow_mut();
        let (acc, pts) = &mut *r;
        acc.reset(scene.len());
        let (seed, rotation) = place_points(scene, i, points, pts);
        let mut lost = 0.0;
        for (k, &(p, weight)) in pts.iter().enumerate() {
            let angle = rotation.map_or(0.0, |salt| 2.0 * PI * hash_unit(seed, &[i as u64, k as u64, salt]));
            let (u, v) = rotated_frame(n, angle);
            if !look(&Eye { p, u, v, n, weight, k }, acc, &mut lost) {
                break;
            }
        }
        Ok(RowResult { entries: acc.entries(receivers), std_err: None, lost, samples: 0 })
    })
}

/// Writes the points and weights of `points` on source `i` to `pts`; returns the seed and the
/// rotation salt of their frames.
pub(crate) fn place_points(
    scene: &[Polygon],
    i: usize,
    points: Points,
    pts: &mut Vec<(Vec3, f64)>,
) -> (u64, Option<u64>) {
    match points {
        Points::Rule { source, seed, rotation } => {
            let size = scene_diameter(scene);
            let cut = matches!(source, SourcePoints::Auto | SourcePoints::Gauss(_))
                && rule_over_pieces(&source_cuts::source_pieces(scene, i), source, size, seed, i, pts);
            if !cut {
                source.generate(&scene[i], size, seed, i, pts);
            }
            (seed, rotation)
        }
        Points::WholePatch => {
            pts.clear();
            pts.push((scene[i].centroid(), 1.0));
            (0, None)
        }
    }
}

/// Replaces the points of a Gauss rule over a whole source by the rule over each of `pieces`
/// (the source cut where other polygons stand on it, [`source_cuts::source_pieces`]), each
/// piece's weights scaled by its share of the area. Returns false (and leaves `pts` alone)
/// when there are no pieces: the caller places the rule on the whole patch.
fn rule_over_pieces(
    pieces: &[Vec<Vec3>],
    source: SourcePoints,
    size: f64,
    seed: u64,
    i: usize,
    pts: &mut Vec<(Vec3, f64)>,
) -> bool {
    let polys: Vec<Polygon> = pieces.iter().filter_map(|p| Polygon::new(p.clone()).ok()).collect();
    let total: f64 = polys.iter().map(Polygon::area).sum();
    if polys.is_empty() || !(total > 0.0) {
        return false;
    }
    pts.clear();
    let mut one = Vec::new();
    for piece in &polys {
        source.generate(piece, size, seed, i, &mut one);
        let share = piece.area() / total;
        pts.extend(one.iter().map(|&(x, w)| (x, w * share)));
    }
    true
}

/// Validates the common arguments of a row computation.
pub(crate) fn check_row(scene: &[Polygon], receivers: &[bool], i: usize) -> Result<()> {
    if receivers.len() != scene.len() {
        return Err(Error::InvalidArgument(format!(
            "receiver mask has {} entries for {} polygons",
            receivers.len(),
            scene.len()
        )));
    }
    if i >= scene.len() {
        return Err(Error::InvalidArgument(format!("source patch {i} out of range for {} polygons", scene.len())));
    }
    if scene.len() > u32::MAX as usize - 2 {
        return Err(Error::InvalidArgument(format!("{} polygons exceed the id range", scene.len())));
    }
    Ok(())
}

/// Diagonal of the scene's bounding box.
pub(crate) fn scene_diameter(scene: &[Polygon]) -> f64 {
    let mut lo = Vec3::splat(f64::INFINITY);
    let mut hi = Vec3::splat(f64::NEG_INFINITY);
    for p in scene {
        for v in p.vertices() {
            lo = lo.min(*v);
            hi = hi.max(*v);
        }
    }
    (hi - lo).length()
}

/// Rotation of the tangent frame about the normal: (u, v, n) right-handed.
pub(crate) fn rotated_frame(n: Vec3, angle: f64) -> (Vec3, Vec3) {
    let (t, b) = crate::geometry::tangent_frame(n);
    let (s, c) = angle.sin_cos();
    (t * c + b * s, b * c - t * s)
}

/// Dense per-thread accumulator over patch ids with a list of touched ids, so that a row
/// costs O(entries) to read out and O(N) memory once per thread.
#[derive(Debug, Default)]
pub(crate) struct Accum {
    acc: Vec<f64>,
    touched: Vec<u32>,
}

impl Accum {
    pub(crate) fn reset(&mut self, n: usize) {
        for &j in &self.touched {
            if let Some(a) = self.acc.get_mut(j as usize) {
                *a = 0.0;
            }
        }
        self.touched.clear();
        if self.acc.len() != n {
            self.acc.clear();
            self.acc.resize(n, 0.0);
        }
    }
    #[inline]
    pub(crate) fn add(&mut self, j: u32, w: f64) {
        let a = &mut self.acc[j as usize];
        if *a == 0.0 {
            self.touched.push(j);
        }
        *a += w;
    }
    /// Largest f(value) over the touched ids (0 when none is touched).
    pub(crate) fn max_value(&self, f: impl Fn(f64) -> f64) -> f64 {
        self.touched.iter().map(|&j| f(self.acc[j as usize])).fold(0.0, f64::max)
    }
    /// Largest value over the touched ids that are receivers (0 when there is none).
    pub(crate) fn max_over(&self, receivers: &[bool]) -> f64 {
        self.touched.iter().filter(|&&j| receivers[j as usize]).map(|&j| self.acc[j as usize]).fold(0.0, f64::max)
    }
    /// Sorted (j, value) for the receivers among the touched ids.
    pub(crate) fn entries(&mut self, receivers: &[bool]) -> Vec<(u32, f64)> {
        self.touched.sort_unstable();
        self.touched
            .iter()
            .filter(|&&j| receivers[j as usize] && self.acc[j as usize] > 0.0)
            .map(|&j| (j, self.acc[j as usize]))
            .collect()
    }
}

/// Brute-force visibility for the tests: every polygon, plane hit + point-in-polygon.
#[cfg(test)]
pub(crate) mod brute {
    use crate::geometry::{tangent_frame, Polygon, Vec3};
    use crate::visibility::{Hit, Visibility};

    pub struct BruteForce<'a> {
        pub scene: &'a [Polygon],
    }

    fn inside(p: &Polygon, x: Vec3) -> bool {
        let (t, b) = tangent_frame(p.normal());
        let q = [(x - p.centroid()).dot(t), (x - p.centroid()).dot(b)];
        let v = p.vertices();
        let mut c = false;
        for k in 0..v.len() {
            let a = v[k] - p.centroid();
            let bb = v[(k + 1) % v.len()] - p.centroid();
            let (a, bb) = ([a.dot(t), a.dot(b)], [bb.dot(t), bb.dot(b)]);
            if (a[1] > q[1]) != (bb[1] > q[1]) && q[0] < a[0] + (q[1] - a[1]) * (bb[0] - a[0]) / (bb[1] - a[1]) {
                c = !c;
            }
        }
        c
    }

    impl Visibility for BruteForce<'_> {
        fn first_hit(&self, origin: Vec3, dir: Vec3, tmin: f64, tmax: f64, ignore: &[u32]) -> Option<Hit> {
            let mut best: Option<Hit> = None;
            for (j, p) in self.scene.iter().enumerate() {
                if ignore.contains(&(j as u32)) {
                    continue;
                }
                let dn = dir.dot(p.normal());
                if dn == 0.0 {
                    continue;
                }
                let t = (p.centroid() - origin).dot(p.normal()) / dn;
                if !(t > tmin && t < tmax) || best.is_some_and(|h| h.t <= t) {
                    continue;
                }
                if inside(p, origin + dir * t) {
                    best = Some(Hit { id: j as u32, t, front: dn < 0.0 });
                }
            }
            best
        }
        fn occluded(&self, a: Vec3, b: Vec3, ignore: &[u32]) -> bool {
            self.first_hit(a, b - a, 1e-9, 1.0 - 1e-9, ignore).is_some()
        }
        fn candidates_between(&self, _a: &Polygon, _b: &Polygon, ignore: &[u32], out: &mut Vec<u32>) {
            out.clear();
            out.extend((0..self.scene.len() as u32).filter(|j| !ignore.contains(j)));
        }
        fn candidates_toward_box(
            &self,
            a: &Polygon,
            _lo: Vec3,
            _hi: Vec3,
            ignore: &[u32],
            among: Option<&[u32]>,
            out: &mut Vec<u32>,
        ) {
            match among {
                Some(among) => self.candidates_among(a, a, ignore, among, out),
                None => self.candidates_between(a, a, ignore, out),
            }
        }
        fn candidates_among(&self, _a: &Polygon, _b: &Polygon, ignore: &[u32], among: &[u32], out: &mut Vec<u32>) {
            out.clear();
            out.extend(among.iter().copied().filter(|j| !ignore.contains(j)));
        }
    }
}

/// `poly`'s vertices in the frame (u, v, n) at `eye`, written to `out`; returns the largest
/// height along n (the hemicube and the single plane clip at a near height).
#[inline]
fn to_local(poly: &Polygon, eye: Vec3, [u, v, n]: [Vec3; 3], out: &mut Vec<Vec3>) -> f64 {
    out.clear();
    let mut zmax = f64::NEG_INFINITY;
    for x in poly.vertices() {
        let d = *x - eye;
        let q = Vec3::new(d.dot(u), d.dot(v), d.dot(n));
        zmax = zmax.max(q.z);
        out.push(q);
    }
    zmax
}

/// Scenes and exact references shared by the method tests.
#[cfg(test)]
pub(crate) mod testkit {
    use crate::geometry::{Polygon, Vec3};
    use std::f64::consts::PI;

    pub fn quad(a: Vec3, b: Vec3, c: Vec3, d: Vec3) -> Polygon {
        Polygon::new(vec![a, b, c, d]).unwrap()
    }

    /// A square of half-width e about `centre` in its z plane, facing +z (a near-point source).
    pub fn small_square(centre: Vec3, e: f64) -> Polygon {
        quad(
            centre + Vec3::new(-e, -e, 0.),
            centre + Vec3::new(e, -e, 0.),
            centre + Vec3::new(e, e, 0.),
            centre + Vec3::new(-e, e, 0.),
        )
    }

    /// The receiver [-1/2, 1/2]^2 at z = 2 and a blocker [-1/2, 0] x [-1/2, 1/2] at z = 1, both
    /// facing -z: seen from the origin the blocker hides exactly the receiver's x < 0 half.
    pub fn half_blocked() -> [Polygon; 2] {
        let recv = quad(
            Vec3::new(-0.5, -0.5, 2.),
            Vec3::new(-0.5, 0.5, 2.),
            Vec3::new(0.5, 0.5, 2.),
            Vec3::new(0.5, -0.5, 2.),
        );
        let block =
            quad(Vec3::new(-0.5, -0.5, 1.), Vec3::new(-0.5, 0.5, 1.), Vec3::new(0., 0.5, 1.), Vec3::new(0., -0.5, 1.));
        [recv, block]
    }

    /// Unit square in z = 0 facing +z and unit square in z = h facing -z (Howell C-11 pair).
    pub fn parallel_squares(h: f64) -> Vec<Polygon> {
        vec![
            quad(Vec3::new(0., 0., 0.), Vec3::new(1., 0., 0.), Vec3::new(1., 1., 0.), Vec3::new(0., 1., 0.)),
            quad(Vec3::new(0., 0., h), Vec3::new(0., 1., h), Vec3::new(1., 1., h), Vec3::new(1., 0., h)),
        ]
    }

    /// Unit square in z = 0 facing +z and unit square in x = 0 facing +x (shared edge on y).
    pub fn perpendicular_squares() -> Vec<Polygon> {
        vec![
            quad(Vec3::new(0., 0., 0.), Vec3::new(1., 0., 0.), Vec3::new(1., 1., 0.), Vec3::new(0., 1., 0.)),
            quad(Vec3::new(0., 0., 0.), Vec3::new(0., 1., 0.), Vec3::new(0., 1., 1.), Vec3::new(0., 0., 1.)),
        ]
    }

    /// Closed box [0,sx]x[0,sy]x[0,sz], faces pointing inward, each split into m x m quads.
    pub fn closed_box(lo: Vec3, hi: Vec3, m: usize, inward: bool) -> Vec<Polygon> {
        let mut out = Vec::new();
        let d = hi - lo;
        let (x, y, z) = (Vec3::new(d.x, 0., 0.), Vec3::new(0., d.y, 0.), Vec3::new(0., 0., d.z));
        // (origin, edge u, edge v) with u x v pointing inward
        let faces = [
            (lo, x, y),                          // z = lo, +z
            (Vec3::new(lo.x, lo.y, hi.z), y, x), // z = hi, -z
            (lo, z, x),                          // y = lo, +y
            (Vec3::new(lo.x, hi.y, lo.z), x, z), // y = hi, -y
            (lo, y, z),                          // x = lo, +x
            (Vec3::new(hi.x, lo.y, lo.z), z, y), // x = hi, -x
        ];
        for (o, u, v) in faces {
            for a in 0..m {
                for b in 0..m {
                    let p = |s: usize, t: usize| o + u * (s as f64 / m as f64) + v * (t as f64 / m as f64);
                    let mut q = vec![p(a, b), p(a + 1, b), p(a + 1, b + 1), p(a, b + 1)];
                    if !inward {
                        q.reverse();
                    }
                    out.push(Polygon::new(q).unwrap());
                }
            }
        }
        out
    }

    /// A room [0,4]x[0,3]x[0,2.5] split m x m per wall plus an outward-facing crate
    /// [1,2.2]x[1,2]x[0.3,1.1] (raised: every face sees the room) split c x c per face, with
    /// the surface id of each polygon (0-5 walls, 6-11 crate faces).
    pub fn room_with_crate(m: usize, c: usize) -> (Vec<Polygon>, Vec<usize>) {
        let mut scene = closed_box(Vec3::ZERO, Vec3::new(4., 3., 2.5), m, true);
        let mut surf: Vec<usize> = (0..scene.len()).map(|k| k / (m * m)).collect();
        let crate_box = closed_box(Vec3::new(1., 1., 0.3), Vec3::new(2.2, 2., 1.1), c, false);
        for (k, p) in crate_box.into_iter().enumerate() {
            scene.push(p);
            surf.push(6 + k / (c * c));
        }
        (scene, surf)
    }

    /// Differential element at a rectangle's corner, normal along the rectangle's axis at
    /// height 1, rectangle a x b: (1/2pi)[A/sqrt(1+A^2) atan(B/sqrt(1+A^2)) + (A<->B)]
    /// (Howell B-3). Checked against a midpoint integration in `lambert_reference_checked`.
    pub fn corner_rect(a: f64, b: f64) -> f64 {
        let f = |x: f64, y: f64| x / (1. + x * x).sqrt() * (y / (1. + x * x).sqrt()).atan();
        (f(a, b) + f(b, a)) / (2. * PI)
    }

    /// Howell C-11: identical parallel directly opposed rectangles a x b at distance c.
    pub fn parallel_rect(a: f64, b: f64, c: f64) -> f64 {
        let (x, y) = (a / c, b / c);
        let (x2, y2) = (1. + x * x, 1. + y * y);
        2. / (PI * x * y)
            * ((x2 * y2 / (x2 + y2 - 1.)).sqrt().ln()
                + x * y2.sqrt() * (x / y2.sqrt()).atan()
                + y * x2.sqrt() * (y / x2.sqrt()).atan()
                - x * x.atan()
                - y * y.atan())
    }

    /// Howell C-14: perpendicular rectangles with a common edge of length l, widths h, w
    /// (from the w-rectangle to the h-rectangle).
    pub fn perpendicular_rect(l: f64, w: f64, h: f64) -> f64 {
        let (hh, ww) = (h / l, w / l);
        let a = (1. + ww * ww) * (1. + hh * hh) / (1. + ww * ww + hh * hh);
        let b = ww * ww * (1. + ww * ww + hh * hh) / ((1. + ww * ww) * (ww * ww + hh * hh));
        let c = hh * hh * (1. + hh * hh + ww * ww) / ((1. + hh * hh) * (hh * hh + ww * ww));
        1. / (PI * ww)
            * (ww * (1. / ww).atan() + hh * (1. / hh).atan()
                - (hh * hh + ww * ww).sqrt() * (1. / (hh * hh + ww * ww).sqrt()).atan()
                + 0.25 * (a.ln() + ww * ww * b.ln() + hh * hh * c.ln()))
    }

    /// F_{dA -> square} by a midpoint rule on an n x n grid (independent of the closed forms).
    pub fn point_to_polygon_midpoint(p: Vec3, n: Vec3, lo: Vec3, u: Vec3, v: Vec3, m: usize) -> f64 {
        let nr = u.cross(v).normalize();
        let da = u.cross(v).length() / (m * m) as f64;
        let mut f = 0.0;
        for a in 0..m {
            for b in 0..m {
                let x = lo + u * ((a as f64 + 0.5) / m as f64) + v * ((b as f64 + 0.5) / m as f64);
                let r = x - p;
                let r2 = r.length_squared();
                let ci = n.dot(r) / r2.sqrt();
                let cj = -nr.dot(r) / r2.sqrt();
                f += (ci * cj.abs()).max(0.0) / (PI * r2) * da;
            }
        }
        f
    }

    #[test]
    fn references_checked() {
        // corner rectangle vs midpoint integration; square on axis = 4 corners = 0.239456
        let mid = point_to_polygon_midpoint(
            Vec3::ZERO,
            Vec3::Z,
            Vec3::new(0., 0., 1.),
            Vec3::new(0.7, 0., 0.),
            Vec3::new(0., 1.3, 0.),
            800,
        );
        assert!((mid - corner_rect(0.7, 1.3)).abs() < 1e-6, "{mid} {}", corner_rect(0.7, 1.3));
        let sq = 4.0 * corner_rect(0.5, 0.5);
        assert!((sq - 0.239456).abs() < 1e-6, "{sq}");
        assert!((parallel_rect(1., 1., 1.) - 0.199824895698387).abs() < 1e-14);
        assert!((perpendicular_rect(1., 1., 1.) - 0.200043776075403).abs() < 1e-14);
        // parallel squares vs a 4-D midpoint rule (smooth integrand, converges ~h^2)
        let m = 24;
        let mut g = 0.0;
        let h = 1.0 / m as f64;
        for a in 0..m * m {
            let x = Vec3::new((a % m) as f64 + 0.5, (a / m) as f64 + 0.5, 0.) * h;
            for b in 0..m * m {
                let y = Vec3::new((b % m) as f64 + 0.5, (b / m) as f64 + 0.5, 1.0 / h) * h;
                let r2 = (y - x).length_squared();
                g += 1.0 / (PI * r2 * r2);
            }
        }
        g *= h.powi(4);
        assert!((g - parallel_rect(1., 1., 1.)).abs() < 2e-4, "{g}");
        // box faces point inward (or outward)
        let c = Vec3::new(0.5, 1.0, 1.5);
        for p in closed_box(Vec3::ZERO, 2.0 * c, 2, true) {
            assert!((c - p.centroid()).dot(p.normal()) > 0.0);
        }
        for p in closed_box(Vec3::ZERO, 2.0 * c, 2, false) {
            assert!((c - p.centroid()).dot(p.normal()) < 0.0);
        }
    }
}

#[cfg(test)]
mod room_tests {
    //! Surface-level checks on rooms; rays go through the scene's BVH (tested against brute
    //! force in visibility::bvh), as they would in use.
    use super::testkit::*;
    use super::*;
    use crate::visibility::bvh::Bvh;

    /// Surface-level matrix: F_IJ = sum_{i in I} A_i sum_{j in J} F_ij / A_I.
    fn surface_matrix(scene: &[Polygon], surf: &[usize], rows: &[RowResult]) -> Vec<Vec<f64>> {
        let ns = surf.iter().max().unwrap() + 1;
        let mut f = vec![vec![0.0; ns]; ns];
        let mut area = vec![0.0; ns];
        for (i, r) in rows.iter().enumerate() {
            area[surf[i]] += scene[i].area();
            for &(j, v) in &r.entries {
                f[surf[i]][surf[j as usize]] += scene[i].area() * v;
            }
        }
        for (i, row) in f.iter_mut().enumerate() {
            for x in row.iter_mut() {
                *x /= area[i];
            }
        }
        f
    }

    fn all_rows(scene: &[Polygon], method: &str) -> Vec<RowResult> {
        let rec = vec![true; scene.len()];
        let vis = Bvh::new(scene).unwrap();
        (0..scene.len())
            .map(|i| match method {
                "hemicube" => hemicube_row(scene, &rec, i, &HemicubeOptions::default()),
                "single_plane" => single_plane_row(scene, &rec, i, &SinglePlaneOptions::default()),
                "raytrace" => raytrace_row(scene, &vis, &rec, i, &RaytraceOptions::default()),
                _ => nusselt_row(scene, &vis, &rec, i, &NusseltOptions::default()),
            })
            .collect::<Result<Vec<_>>>()
            .unwrap()
    }

    #[test]
    #[cfg_attr(debug_assertions, ignore = "heavy: run with --release")]
    fn empty_room_surface_level_defaults() {
        // walls: 0 floor, 1 ceiling, 2 y=0, 3 y=3, 4 x=0, 5 x=4 of [0,4]x[0,3]x[0,2.5]
        let exact = [
            (0, 1, parallel_rect(4., 3., 2.5)),
            (0, 2, perpendicular_rect(4., 3., 2.5)),
            (0, 4, perpendicular_rect(3., 4., 2.5)),
            (2, 3, parallel_rect(4., 2.5, 3.)),
            (4, 5, parallel_rect(3., 2.5, 4.)),
        ];
        for m in [1usize, 4] {
            let scene = closed_box(Vec3::ZERO, Vec3::new(4., 3., 2.5), m, true);
            let surf: Vec<usize> = (0..scene.len()).map(|k| k / (m * m)).collect();
            for method in ["hemicube", "single_plane", "raytrace", "nusselt"] {
                let rows = all_rows(&scene, method);
                let f = surface_matrix(&scene, &surf, &rows);
                let mut worst: f64 = 0.0;
                for &(a, b, e) in &exact {
                    worst = worst.max((f[a][b] - e).abs());
                }
                let sums: Vec<f64> = rows.iter().map(|r| r.sum() + r.lost).collect();
                eprintln!(
                    "m {m} {method}: worst surface error {worst:.2e}, mean lost {:.2e}",
                    rows.iter().map(|r| r.lost).sum::<f64>() / rows.len() as f64
                );
                assert!(worst < 1e-2, "m {m} {method}: {worst}");
                assert!(sums.iter().all(|s| (s - 1.0).abs() < 1e-9));
            }
        }
    }

    #[test]
    #[cfg_attr(debug_assertions, ignore = "heavy: run with --release")]
    fn room_with_crate_surface_level_defaults() {
        // Reference: 2^18 cosine rays per polygon on the unsplit scene (binomial std error
        // <= 1e-3), an estimator independent of the rasterising methods. Surface-level F does
        // not depend on the mesh, so the same reference serves the split scene.
        let (coarse, _) = room_with_crate(1, 1);
        let vis = Bvh::new(&coarse).unwrap();
        let rec = vec![true; coarse.len()];
        let o = RaytraceOptions { rays: 1 << 18, seed: 12345, ..Default::default() };
        let reference: Vec<RowResult> =
            (0..coarse.len()).map(|i| raytrace_row(&coarse, &vis, &rec, i, &o).unwrap()).collect();
        let fref = surface_matrix(&coarse, &(0..12).collect::<Vec<_>>(), &reference);
        for (m, c) in [(1usize, 1usize), (4, 2)] {
            let (scene, surf) = room_with_crate(m, c);
            for method in ["hemicube", "single_plane", "raytrace", "nusselt"] {
                let rows = all_rows(&scene, method);
                let f = surface_matrix(&scene, &surf, &rows);
                let mut worst: f64 = 0.0;
                let mut at = (0, 0);
                for a in 0..12 {
                    for b in 0..12 {
                        if (f[a][b] - fref[a][b]).abs() > worst {
                            worst = (f[a][b] - fref[a][b]).abs();
                            at = (a, b);
                        }
                    }
                }
                eprintln!("  worst at {at:?}: {} vs {}", f[at.0][at.1], fref[at.0][at.1]);
                let worst_sum = rows.iter().map(|r| (r.sum() - 1.0).abs()).fold(0.0, f64::max);
                eprintln!(
                    "room {m}/{c} {method}: worst surface error {worst:.2e}, worst |row sum - 1| {worst_sum:.2e}"
                );
                assert!(worst < 1e-2, "{m}/{c} {method}: {worst}");
                assert!(worst_sum < 1e-2, "{m}/{c} {method}: {worst_sum}");
            }
        }
    }

    /// Rows per second at default options on the room with a crate (20 x 20 per wall,
    /// 10 x 10 per crate face: 3000 patches), single thread. Release build:
    /// cargo test --release -p nusselt-core --lib hemisphere::room_tests::throughput -- --ignored --nocapture
    #[test]
    #[ignore]
    fn throughput() {
        let (scene, _surf) = room_with_crate(20, 10);
        let rec = vec![true; scene.len()];
        let rows: Vec<usize> = (0..scene.len()).step_by(23).collect();
        let time = |name: &str, f: &dyn Fn(usize) -> RowResult| {
            let t = std::time::Instant::now();
            let mut s = 0.0;
            for &i in &rows {
                s += f(i).sum();
            }
            let dt = t.elapsed().as_secs_f64();
            eprintln!(
                "{name}: {:.1} rows/s ({} rows, mean row sum {:.4})",
                rows.len() as f64 / dt,
                rows.len(),
                s / rows.len() as f64
            );
        };
        time("hemicube", &|i| hemicube_row(&scene, &rec, i, &HemicubeOptions::default()).unwrap());
        time("single_plane", &|i| single_plane_row(&scene, &rec, i, &SinglePlaneOptions::default()).unwrap());
        let t = std::time::Instant::now();
        let bvh = crate::visibility::bvh::Bvh::new(&scene).unwrap();
        eprintln!("bvh build {:.3} s", t.elapsed().as_secs_f64());
        time("raytrace", &|i| raytrace_row(&scene, &bvh, &rec, i, &RaytraceOptions::default()).unwrap());
        time("nusselt", &|i| nusselt_row(&scene, &bvh, &rec, i, &NusseltOptions::default()).unwrap());
    }
}
