//! The far-field double area integral A_a F_ab = ∫_a ∫_b cos θ_a cos θ_b / (π r²) dA_b dA_a
//! by Gauss area rules, and `auto`'s plan of which rule to use ([`FarPlan`]).
//!
//! Tensor Gauss rules converge exponentially for separated pairs and only algebraically for
//! touching ones (docs/algorithms.md §7.2), so [`far_field_order`] picks an order from the relative
//! separation and returns `None` when the pair is too close: the caller then uses an exact
//! kernel (contour or analytic).

use crate::geometry::{Polygon, Vec3};
use crate::quadrature::AreaRule;
use std::f64::consts::PI;
use std::sync::OnceLock;

/// Far-field double area integral:
///
///   A_a F_ab ≈ Σ_k Σ_l w_k w_l max(0, n_a·d) max(0, -n_b·d) / (π |d|⁴),   d = y_l - x_k,
///
/// i.e. cos θ_a cos θ_b / (π r²) with both cosines clipped at zero. Equal to A_a F_ab within
/// the rule's error only for unobstructed pairs that lie in each other's front half-space
/// (otherwise the clipped integrand has kinks and convergence is slow; clip first).
/// Symmetric: area_area(a, na, b, nb) = area_area(b, nb, a, na) up to rounding.
///
/// The inner loop runs over b's points in stack chunks stored as structure of arrays, so it
/// auto-vectorises; no allocation.
pub fn area_area(a: &AreaRule, na: Vec3, b: &AreaRule, nb: Vec3) -> f64 {
    const C: usize = 32;
    let nbp = b.points.len();
    let mut total = 0.0;
    if nbp <= 4 {
        // tiny rules (low orders on quads): the chunk set-up would cost more than the loop
        for (x, &wx) in a.points.iter().zip(&a.weights) {
            let mut s = 0.0;
            for (y, &wy) in b.points.iter().zip(&b.weights) {
                let d = *y - *x;
                let r2 = d.dot(d);
                let ca = na.dot(d).max(0.0);
                let cb = (-nb.dot(d)).max(0.0);
                s += wy * ca * cb / (r2 * r2).max(f64::MIN_POSITIVE);
            }
            total += wx * s;
        }
        return total / PI;
    }
    let (mut bx, mut by, mut bz) = ([0.0f64; C], [0.0f64; C], [0.0f64; C]);
    let (mut bw, mut bna, mut bnb) = ([0.0f64; C], [0.0f64; C], [0.0f64; C]);
    let mut start = 0;
    while start < nbp {
        let m = (nbp - start).min(C);
        for l in 0..C {
            // padding lanes repeat the chunk's first point with zero weight
            let src = if l < m { start + l } else { start };
            let y = b.points[src];
            bx[l] = y.x;
            by[l] = y.y;
            bz[l] = y.z;
            bw[l] = if l < m { b.weights[src] } else { 0.0 };
            bna[l] = na.dot(y);
            bnb[l] = nb.dot(y);
        }
        // lanes in use, rounded up to a multiple of 4 (the padding lanes carry zero weight)
        let lanes = ((m + 3) & !3).min(C);
        for (x, &wx) in a.points.iter().zip(&a.weights) {
            let (nax, nbx) = (na.dot(*x), nb.dot(*x));
            let mut s = 0.0;
            for l in 0..lanes {
                let (dx, dy, dz) = (bx[l] - x.x, by[l] - x.y, bz[l] - x.z);
                let r2 = dx * dx + dy * dy + dz * dz;
                let ca = (bna[l] - nax).max(0.0);
                let cb = (nbx - bnb[l]).max(0.0);
                s += bw[l] * ca * cb / (r2 * r2).max(f64::MIN_POSITIVE);
            }
            total += wx * s;
        }
        start += m;
    }
    total / PI
}

/// SIMD width the packed far-field kernel is written for (AVX2: 4 doubles).
const LANES: usize = 4;

/// An [`AreaRule`] packed for [`far_pair`]: structure of arrays, padded to a multiple of
/// `LANES` with zero-weight copies of the first point, plus the plane offset n·c of the
/// polygon (the rule's points lie on that plane).
#[derive(Debug, Clone, PartialEq)]
pub struct PackedRule {
    x: Vec<f64>,
    y: Vec<f64>,
    z: Vec<f64>,
    w: Vec<f64>,
    len: usize,
    offset: f64,
}

impl PackedRule {
    pub fn new(rule: &AreaRule, poly: &Polygon) -> PackedRule {
        let len = rule.len();
        let padded = len.div_ceil(LANES) * LANES;
        let pick = |k: usize| if k < len { k } else { 0 };
        PackedRule {
            x: (0..padded).map(|k| rule.points[pick(k)].x).collect(),
            y: (0..padded).map(|k| rule.points[pick(k)].y).collect(),
            z: (0..padded).map(|k| rule.points[pick(k)].z).collect(),
            w: (0..padded).map(|k| if k < len { rule.weights[k] } else { 0.0 }).collect(),
            len,
            offset: poly.normal().dot(poly.centroid()),
        }
    }

    pub fn len(&self) -> usize {
        self.len
    }

    pub fn is_empty(&self) -> bool {
        self.len == 0
    }
}

/// The far-field double area integral of [`area_area`] for a pair that lies wholly in each
/// other's front half-space (`method::Facing::Full`), from packed rules:
///
///   A_a F_ab ≈ (1/π) Σ_k w_k cb_k Σ_l w_l ca_l / |y_l - x_k|⁴,
///   ca_l = n_a·y_l - n_a·c_a,   cb_k = n_b·x_k - n_b·c_b,
///
/// i.e. cos θ_a cos θ_b / (π r²) with each cosine factor depending on one point only
/// (the points lie on their planes), so the inner loop is 3 differences, r², one division
/// and an add per point pair. Both factors are clipped at zero, which matters only for
/// rounding. Uses AVX2 when the CPU has it (checked once); the same operations in the same
/// order otherwise, so results do not depend on the path.
pub fn far_pair(a: &PackedRule, na: Vec3, b: &PackedRule, nb: Vec3) -> f64 {
    #[cfg(target_arch = "x86_64")]
    {
        if std::arch::is_x86_feature_detected!("avx2") {
            // SAFETY: the CPU supports AVX2, checked just above.
            return unsafe { far_pair_avx2(a, na, b, nb) };
        }
    }
    far_pair_body(a, na, b, nb)
}

/// Lane groups of b per chunk of [`far_pair`] (a Gauss rule of order 8 on a quad is 16).
const FAR_CHUNK: usize = 16;

#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
unsafe fn far_pair_avx2(a: &PackedRule, na: Vec3, b: &PackedRule, nb: Vec3) -> f64 {
    // SAFETY: this function only runs where the CPU supports AVX2.
    far_pair_with(a, na, b, nb, |cx, cy, cz, bw, x, s, tot| unsafe { lane_sums_avx2(cx, cy, cz, bw, x, s, tot) })
}

fn far_pair_body(a: &PackedRule, na: Vec3, b: &PackedRule, nb: Vec3) -> f64 {
    far_pair_with(a, na, b, nb, lane_sums)
}

/// The lane groups of one chunk of b: x, y, z and w_l ca_l per lane.
type Groups<'g> = &'g [[f64; LANES]];

/// [`far_pair`] with `sums(x, y, z, w ca, point, s, tot)` adding, per lane, s times the sum
/// over the chunk's lane groups of w_l ca_l / |y_l - point|⁴ to `tot` (one sum per lane until
/// the end: a horizontal sum per point of a was the loop's longest dependency chain).
#[inline(always)]
fn far_pair_with(
    a: &PackedRule,
    na: Vec3,
    b: &PackedRule,
    nb: Vec3,
    sums: impl Fn(Groups, Groups, Groups, Groups, Vec3, f64, &mut [f64; LANES]),
) -> f64 {
    // b's points in chunks of FAR_CHUNK lane groups: w_l * ca_l on the stack per chunk
    let (bx, by, bz, bwt) = (
        b.x.as_chunks::<LANES>().0,
        b.y.as_chunks::<LANES>().0,
        b.z.as_chunks::<LANES>().0,
        b.w.as_chunks::<LANES>().0,
    );
    let mut tot = [0.0f64; LANES];
    let mut bw = [[0.0f64; LANES]; FAR_CHUNK];
    for start in (0..bx.len()).step_by(FAR_CHUNK) {
        let m = (bx.len() - start).min(FAR_CHUNK);
        let (cx, cy, cz) = (&bx[start..start + m], &by[start..start + m], &bz[start..start + m]);
        for (g, out) in bw[..m].iter_mut().enumerate() {
            for l in 0..LANES {
                let ca = na.x * cx[g][l] + na.y * cy[g][l] + na.z * cz[g][l] - a.offset;
                out[l] = bwt[start + g][l] * ca.max(0.0);
            }
        }
        for k in 0..a.len {
            let x = Vec3::new(a.x[k], a.y[k], a.z[k]);
            let cb = (nb.x * x.x + nb.y * x.y + nb.z * x.z - b.offset).max(0.0);
            sums(cx, cy, cz, &bw[..m], x, a.w[k] * cb, &mut tot);
        }
    }
    ((tot[0] + tot[1]) + (tot[2] + tot[3])) / PI
}

#[inline(always)]
fn lane_sums(cx: Groups, cy: Groups, cz: Groups, bw: Groups, x: Vec3, s: f64, tot: &mut [f64; LANES]) {
    let mut acc = [0.0f64; LANES];
    for (((px, py), pz), pw) in cx.iter().zip(cy).zip(cz).zip(bw) {
        for l in 0..LANES {
            let (dx, dy, dz) = (px[l] - x.x, py[l] - x.y, pz[l] - x.z);
            let r2 = dx * dx + dy * dy + dz * dz;
            acc[l] += pw[l] / (r2 * r2);
        }
    }
    for l in 0..LANES {
        tot[l] += s * acc[l];
    }
}

/// [`lane_sums`] in AVX2 intrinsics: the compiler's own vectorisation of it uses half-width
/// registers and a dependency chain per pair of lanes (twice the time). Lane for lane the
/// same operations in the same order (no FMA), so the results are identical.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
#[inline]
unsafe fn lane_sums_avx2(cx: Groups, cy: Groups, cz: Groups, bw: Groups, x: Vec3, s: f64, tot: &mut [f64; LANES]) {
    use std::arch::x86_64::*;
    let (vx, vy, vz) = (_mm256_set1_pd(x.x), _mm256_set1_pd(x.y), _mm256_set1_pd(x.z));
    let mut acc = _mm256_setzero_pd();
    for (((px, py), pz), pw) in cx.iter().zip(cy).zip(cz).zip(bw) {
        // SAFETY: each load reads one whole [f64; 4].
        let (px, py, pz, pw) = unsafe {
            (
                _mm256_loadu_pd(px.as_ptr()),
                _mm256_loadu_pd(py.as_ptr()),
                _mm256_loadu_pd(pz.as_ptr()),
                _mm256_loadu_pd(pw.as_ptr()),
            )
        };
        let (dx, dy, dz) = (_mm256_sub_pd(px, vx), _mm256_sub_pd(py, vy), _mm256_sub_pd(pz, vz));
        let r2 = _mm256_add_pd(_mm256_add_pd(_mm256_mul_pd(dx, dx), _mm256_mul_pd(dy, dy)), _mm256_mul_pd(dz, dz));
        acc = _mm256_add_pd(acc, _mm256_div_pd(pw, _mm256_mul_pd(r2, r2)));
    }
    // SAFETY: tot is one whole [f64; 4].
    unsafe {
        let t = _mm256_add_pd(_mm256_loadu_pd(tot.as_ptr()), _mm256_mul_pd(_mm256_set1_pd(s), acc));
        _mm256_storeu_pd(tot.as_mut_ptr(), t);
    }
}

/// Calibrated worst-case relative errors (rows: FAR_SEPS; columns: orders 1..=MAX_FAR_ORDER),
/// printed by `calibrate_far_field`.
pub(crate) const FAR_SEPS: &[f64] = &[
    1.05, 1.1, 1.2, 1.3, 1.4, 1.5, 1.75, 2.0, 2.5, 3.0, 4.0, 5.0, 6.0, 8.0, 10.0, 12.0, 16.0, 24.0, 32.0, 48.0, 64.0,
    96.0, 128.0, 256.0, 512.0, 1024.0,
];
#[rustfmt::skip]
const FAR_ERRS: &[[f64; MAX_FAR_ORDER]] = &[
    [8.9e-01, 6.4e-01, 4.4e-01, 2.8e-01, 1.7e-01, 9.4e-02, 5.1e-02, 2.7e-02, 1.4e-02, 6.9e-03, 3.4e-03, 1.7e-03, 8.2e-04, 4.0e-04, 1.9e-04, 9.2e-05], // 1.05
    [9.2e-01, 5.1e-01, 2.8e-01, 1.3e-01, 5.3e-02, 2.0e-02, 7.0e-03, 2.3e-03, 7.1e-04, 2.1e-04, 5.7e-05, 1.5e-05, 3.5e-06, 7.4e-07, 1.3e-07, 3.0e-08], // 1.1
    [6.8e-01, 2.7e-01, 7.4e-02, 1.8e-02, 4.2e-03, 8.6e-04, 1.7e-04, 3.3e-05, 7.3e-06, 1.3e-06, 1.8e-07, 9.1e-09, 5.2e-09, 2.4e-09, 7.1e-10, 1.7e-10], // 1.2
    [6.3e-01, 1.3e-01, 2.2e-02, 3.6e-03, 5.6e-04, 1.1e-04, 3.8e-05, 1.0e-05, 2.3e-06, 4.9e-07, 9.6e-08, 1.8e-08, 3.1e-09, 4.9e-10, 7.2e-11, 9.0e-12], // 1.3
    [6.4e-01, 1.5e-01, 3.0e-02, 5.6e-03, 9.4e-04, 1.4e-04, 2.4e-05, 4.4e-06, 7.3e-07, 1.1e-07, 1.7e-08, 2.3e-09, 3.0e-10, 3.6e-11, 3.8e-12, 3.0e-13], // 1.4
    [5.0e-01, 1.2e-01, 1.4e-02, 1.5e-03, 1.4e-04, 2.8e-05, 3.1e-06, 1.3e-07, 2.4e-08, 5.9e-09, 6.6e-10, 2.7e-11, 4.9e-12, 1.2e-12, 1.4e-13, 1.3e-14], // 1.5
    [6.2e-01, 9.7e-02, 1.1e-02, 1.1e-03, 9.7e-05, 7.9e-06, 6.1e-07, 4.5e-08, 3.3e-09, 2.3e-10, 1.6e-11, 1.1e-12, 7.5e-14, 1.3e-14, 8.9e-15, 1.0e-14], // 1.75
    [2.9e-01, 4.5e-02, 2.0e-03, 1.1e-04, 6.1e-06, 3.0e-07, 1.4e-08, 6.5e-10, 2.9e-11, 1.6e-12, 8.9e-14, 7.4e-15, 6.2e-15, 9.2e-15, 9.8e-15, 1.2e-14], // 2
    [2.8e-01, 2.3e-02, 9.6e-04, 4.5e-05, 2.3e-06, 1.1e-07, 4.5e-09, 1.8e-10, 7.0e-12, 2.6e-13, 1.0e-14, 6.8e-15, 9.0e-15, 7.9e-15, 9.2e-15, 1.5e-14], // 2.5
    [2.7e-01, 3.9e-02, 1.8e-03, 5.1e-05, 1.0e-06, 1.4e-08, 1.0e-10, 1.4e-12, 7.2e-14, 4.5e-15, 7.2e-15, 8.0e-15, 6.5e-15, 7.6e-15, 1.3e-14, 8.9e-15], // 3
    [2.0e-01, 2.9e-03, 4.2e-05, 5.6e-07, 6.4e-09, 6.9e-11, 7.1e-13, 8.5e-15, 3.3e-15, 3.9e-15, 5.6e-15, 5.4e-15, 7.3e-15, 8.8e-15, 9.4e-15, 7.5e-15], // 4
    [1.6e-01, 5.8e-03, 3.8e-05, 1.9e-07, 2.0e-09, 1.9e-11, 1.8e-13, 3.1e-15, 5.4e-15, 5.1e-15, 6.6e-15, 6.1e-15, 5.5e-15, 1.0e-14, 1.1e-14, 8.1e-15], // 5
    [1.2e-01, 1.5e-03, 8.3e-06, 2.5e-08, 1.1e-10, 6.0e-13, 3.8e-15, 3.1e-15, 4.9e-15, 6.5e-15, 5.2e-15, 1.2e-14, 7.0e-15, 7.1e-15, 9.2e-15, 1.5e-14], // 6
    [8.3e-02, 1.8e-03, 6.4e-06, 9.3e-09, 2.2e-11, 1.3e-13, 4.1e-15, 3.7e-15, 4.3e-15, 6.7e-15, 5.2e-15, 4.3e-15, 7.1e-15, 8.8e-15, 1.3e-14, 1.7e-14], // 8
    [5.6e-02, 6.4e-04, 4.9e-07, 6.5e-10, 1.3e-12, 2.8e-15, 2.9e-15, 4.9e-15, 4.8e-15, 5.4e-15, 7.1e-15, 6.1e-15, 9.7e-15, 7.4e-15, 1.2e-14, 1.0e-14], // 10
    [5.5e-02, 3.0e-04, 3.8e-07, 4.5e-10, 6.1e-13, 3.5e-15, 3.3e-15, 2.7e-15, 2.9e-15, 5.1e-15, 3.7e-15, 6.5e-15, 7.9e-15, 1.1e-14, 9.3e-15, 9.6e-15], // 12
    [2.8e-02, 1.5e-04, 1.0e-07, 3.0e-11, 4.5e-14, 2.2e-15, 3.9e-15, 2.8e-15, 3.0e-15, 3.9e-15, 4.9e-15, 6.2e-15, 8.2e-15, 7.7e-15, 9.0e-15, 9.3e-15], // 16
    [2.2e-02, 2.1e-04, 1.7e-07, 9.3e-11, 4.0e-14, 2.2e-15, 4.1e-15, 3.2e-15, 5.0e-15, 8.9e-15, 6.0e-15, 9.3e-15, 8.4e-15, 1.0e-14, 7.6e-15, 1.9e-14], // 24
    [2.0e-02, 8.9e-05, 2.4e-08, 7.2e-12, 4.9e-15, 5.7e-15, 4.7e-15, 3.4e-15, 3.8e-15, 5.9e-15, 7.1e-15, 5.2e-15, 5.9e-15, 1.2e-14, 9.9e-15, 8.9e-15], // 32
    [1.2e-02, 5.6e-05, 4.2e-09, 1.4e-13, 2.7e-15, 2.4e-15, 3.1e-15, 3.0e-15, 3.4e-15, 6.7e-15, 6.1e-15, 8.9e-15, 5.7e-15, 1.0e-14, 1.4e-14, 1.8e-14], // 48
    [9.4e-03, 1.7e-05, 1.2e-09, 6.2e-14, 9.9e-15, 1.0e-14, 9.3e-15, 8.4e-15, 7.2e-15, 6.9e-15, 5.4e-15, 5.2e-15, 7.7e-15, 9.1e-15, 1.0e-14, 1.1e-14], // 64
    [8.8e-03, 9.7e-06, 2.0e-10, 5.1e-15, 2.4e-15, 2.9e-15, 3.5e-15, 4.4e-15, 3.1e-15, 3.6e-15, 7.9e-15, 4.8e-15, 9.5e-15, 9.4e-15, 6.9e-15, 1.2e-14], // 96
    [4.2e-03, 2.0e-06, 1.2e-11, 2.4e-15, 2.3e-15, 2.6e-15, 4.6e-15, 3.5e-15, 5.9e-15, 4.3e-15, 4.9e-15, 5.5e-15, 1.1e-14, 9.2e-15, 8.5e-15, 8.2e-15], // 128
    [2.3e-03, 7.8e-07, 9.5e-13, 3.6e-15, 2.6e-15, 2.9e-15, 4.3e-15, 3.8e-15, 3.4e-15, 6.6e-15, 6.4e-15, 7.1e-15, 6.1e-15, 1.0e-14, 9.2e-15, 1.7e-14], // 256
    [1.7e-03, 3.5e-07, 1.9e-13, 8.7e-15, 7.2e-15, 4.3e-15, 7.1e-15, 4.3e-15, 6.0e-15, 5.9e-15, 6.8e-15, 9.3e-15, 1.1e-14, 1.0e-14, 1.1e-14, 1.5e-14], // 512
    [6.9e-04, 1.5e-07, 5.6e-14, 1.8e-15, 2.6e-15, 2.8e-15, 2.7e-15, 3.4e-15, 3.7e-15, 5.4e-15, 9.2e-15, 6.4e-15, 4.9e-15, 6.2e-15, 9.2e-15, 1.1e-14], // 1024
];

/// Calibrated worst-case relative errors of the second-moment rule
/// ([`crate::unobstructed::moments::moment_pair`]) per FAR_SEPS row, printed by `calibrate_moment_rule`
/// (the same random pairs as FAR_ERRS; reference: compensated Gauss order 24/20 below s = 2,
/// 20/16 above, its uncertainty added). Worst cases decay about as s^-2: third-order terms
/// (triangles, concave shapes) and pairs resting on each other's plane.
#[rustfmt::skip]
const MOMENT_ERRS: &[f64] = &[
    7.6e-1, // 1.05
    7.6e-1, // 1.1
    4.4e-1, // 1.2
    3.7e-1, // 1.3
    3.5e-1, // 1.4
    2.4e-1, // 1.5
    2.6e-1, // 1.75
    8.0e-2, // 2
    6.0e-2, // 2.5
    6.2e-2, // 3
    1.7e-2, // 4
    1.7e-2, // 5
    9.4e-3, // 6
    3.7e-3, // 8
    2.9e-3, // 10
    1.2e-3, // 12
    6.7e-4, // 16
    5.1e-4, // 24
    3.6e-4, // 32
    9.0e-5, // 48
    5.9e-5, // 64
    2.2e-5, // 96
    1.4e-5, // 128
    3.5e-6, // 256
    1.5e-6, // 512
    2.9e-7, // 1024
];
const _: () = assert!(MOMENT_ERRS.len() == FAR_SEPS.len());

/// FAR_ERRS and MOMENT_ERRS for pairs of regular quads ([`is_regular_quad`]), printed by
/// `calibrate_regular_quads`: the same generator with parallelogram outlines (side ratio
/// 1/4..1, corner angles 45°..135°); references as for FAR_ERRS (reference uncertainty at
/// most 2.4e-15). The worst cases are the pairs resting on each other's plane and the large
/// size ratios, so the gain over the general tables is modest at moderate separations.
#[rustfmt::skip]
const REGULAR_FAR_ERRS: &[[f64; MAX_FAR_ORDER]] = &[
    [8.4e-1, 4.5e-1, 2.0e-1, 8.2e-2, 3.0e-2, 9.8e-3, 3.0e-3, 8.3e-4, 2.1e-4, 4.9e-5, 1.2e-5, 4.2e-6, 1.2e-6, 4.0e-7, 1.3e-7, 2.6e-8], // 1.05
    [8.4e-1, 4.8e-1, 1.9e-1, 6.2e-2, 1.8e-2, 5.0e-3, 1.2e-3, 2.7e-4, 4.8e-5, 8.5e-6, 2.7e-6, 1.5e-6, 6.8e-7, 2.6e-7, 9.3e-8, 3.1e-8], // 1.1
    [8.6e-1, 4.3e-1, 1.7e-1, 5.4e-2, 1.6e-2, 4.8e-3, 1.4e-3, 3.9e-4, 1.1e-4, 2.9e-5, 7.9e-6, 2.1e-6, 5.7e-7, 1.5e-7, 4.0e-8, 1.0e-8], // 1.2
    [6.1e-1, 1.7e-1, 4.0e-2, 8.9e-3, 1.4e-3, 1.8e-4, 1.9e-5, 2.5e-6, 3.3e-7, 4.3e-8, 7.7e-9, 1.0e-9, 1.6e-10, 3.7e-11, 2.6e-12, 1.2e-12], // 1.3
    [8.1e-1, 3.6e-1, 9.7e-2, 2.1e-2, 4.2e-3, 7.8e-4, 1.4e-4, 2.4e-5, 4.0e-6, 6.6e-7, 1.1e-7, 1.7e-8, 2.7e-9, 4.2e-10, 6.4e-11, 9.9e-12], // 1.4
    [6.5e-1, 1.7e-1, 3.0e-2, 4.2e-3, 4.9e-4, 5.1e-5, 4.8e-6, 3.9e-7, 2.6e-8, 2.6e-9, 2.4e-10, 2.0e-11, 4.4e-12, 3.2e-13, 3.6e-14, 2.0e-14], // 1.5
    [6.9e-1, 1.9e-1, 3.0e-2, 3.8e-3, 4.1e-4, 4.0e-5, 3.7e-6, 3.1e-7, 2.6e-8, 2.0e-9, 1.6e-10, 1.2e-11, 9.0e-13, 6.9e-14, 2.0e-14, 2.0e-14], // 1.75
    [4.6e-1, 4.7e-2, 3.9e-3, 2.8e-4, 1.9e-5, 1.1e-6, 6.0e-8, 3.1e-9, 1.4e-10, 6.7e-12, 5.0e-13, 2.0e-14, 2.0e-14, 2.0e-14, 2.0e-14, 2.0e-14], // 2
    [4.3e-1, 3.7e-2, 1.7e-3, 5.7e-5, 1.4e-6, 4.3e-8, 2.1e-9, 4.3e-11, 1.6e-12, 8.3e-14, 2.0e-14, 2.0e-14, 2.0e-14, 2.0e-14, 2.0e-14, 2.0e-14], // 2.5
    [2.6e-1, 9.9e-3, 2.3e-4, 4.7e-6, 1.7e-7, 5.0e-9, 6.0e-11, 2.0e-12, 8.5e-14, 2.0e-14, 2.0e-14, 2.0e-14, 2.0e-14, 2.0e-14, 2.0e-14, 2.0e-14], // 3
    [1.6e-1, 2.8e-3, 3.5e-5, 6.9e-7, 6.9e-9, 1.1e-10, 2.1e-12, 2.0e-14, 2.0e-14, 2.0e-14, 2.0e-14, 2.0e-14, 2.0e-14, 2.0e-14, 2.0e-14, 2.0e-14], // 4
    [1.6e-1, 3.7e-3, 5.1e-5, 5.0e-7, 3.9e-9, 2.4e-11, 1.3e-13, 2.0e-14, 2.0e-14, 2.0e-14, 2.0e-14, 2.0e-14, 2.0e-14, 2.0e-14, 2.0e-14, 2.0e-14], // 5
    [1.3e-1, 1.4e-3, 5.4e-6, 3.3e-8, 2.1e-10, 1.3e-12, 2.0e-14, 2.0e-14, 2.0e-14, 2.0e-14, 2.0e-14, 2.0e-14, 2.0e-14, 2.0e-14, 2.0e-14, 2.0e-14], // 6
    [1.2e-1, 9.9e-4, 3.1e-6, 1.1e-8, 6.3e-11, 1.1e-13, 2.0e-14, 2.0e-14, 2.0e-14, 2.0e-14, 2.0e-14, 2.0e-14, 2.0e-14, 2.0e-14, 2.0e-14, 2.0e-14], // 8
    [6.8e-2, 3.4e-4, 7.4e-7, 1.8e-9, 4.1e-12, 2.0e-14, 2.0e-14, 2.0e-14, 2.0e-14, 2.0e-14, 2.0e-14, 2.0e-14, 2.0e-14, 2.0e-14, 2.0e-14, 2.0e-14], // 10
    [4.9e-2, 1.3e-4, 1.4e-7, 3.0e-10, 4.7e-13, 2.0e-14, 2.0e-14, 2.0e-14, 2.0e-14, 2.0e-14, 2.0e-14, 2.0e-14, 2.0e-14, 2.0e-14, 2.0e-14, 2.0e-14], // 12
    [5.8e-2, 1.5e-4, 1.9e-7, 1.6e-10, 8.0e-14, 2.0e-14, 2.0e-14, 2.0e-14, 2.0e-14, 2.0e-14, 2.0e-14, 2.0e-14, 2.0e-14, 2.0e-14, 2.0e-14, 2.0e-14], // 16
    [3.6e-2, 2.9e-5, 8.7e-9, 3.7e-12, 2.0e-14, 2.0e-14, 2.0e-14, 2.0e-14, 2.0e-14, 2.0e-14, 2.0e-14, 2.0e-14, 2.0e-14, 2.0e-14, 2.0e-14, 2.0e-14], // 24
    [2.8e-2, 1.9e-5, 6.9e-9, 1.8e-12, 2.0e-14, 2.0e-14, 2.0e-14, 2.0e-14, 2.0e-14, 2.0e-14, 2.0e-14, 2.0e-14, 2.0e-14, 2.0e-14, 2.0e-14, 2.0e-14], // 32
    [1.2e-2, 2.7e-6, 4.7e-10, 5.2e-14, 2.0e-14, 2.0e-14, 2.0e-14, 2.0e-14, 2.0e-14, 2.0e-14, 2.0e-14, 2.0e-14, 2.0e-14, 2.0e-14, 2.0e-14, 2.0e-14], // 48
    [1.3e-2, 2.0e-6, 1.4e-10, 2.0e-14, 2.0e-14, 2.0e-14, 2.0e-14, 2.0e-14, 2.0e-14, 2.0e-14, 2.0e-14, 2.0e-14, 2.0e-14, 2.0e-14, 2.0e-14, 2.0e-14], // 64
    [5.6e-3, 3.5e-7, 1.2e-11, 2.0e-14, 2.0e-14, 2.0e-14, 2.0e-14, 2.0e-14, 2.0e-14, 2.0e-14, 2.0e-14, 2.0e-14, 2.0e-14, 2.0e-14, 2.0e-14, 2.0e-14], // 96
    [6.0e-3, 2.2e-7, 4.1e-12, 2.0e-14, 2.0e-14, 2.0e-14, 2.0e-14, 2.0e-14, 2.0e-14, 2.0e-14, 2.0e-14, 2.0e-14, 2.0e-14, 2.0e-14, 2.0e-14, 2.0e-14], // 128
    [2.8e-3, 2.6e-8, 1.4e-13, 2.0e-14, 2.0e-14, 2.0e-14, 2.0e-14, 2.0e-14, 2.0e-14, 2.0e-14, 2.0e-14, 2.0e-14, 2.0e-14, 2.0e-14, 2.0e-14, 2.0e-14], // 256
    [1.6e-3, 4.9e-9, 2.0e-14, 2.0e-14, 2.0e-14, 2.0e-14, 2.0e-14, 2.0e-14, 2.0e-14, 2.0e-14, 2.0e-14, 2.0e-14, 2.0e-14, 2.0e-14, 2.0e-14, 2.0e-14], // 512
    [7.2e-4, 3.4e-10, 2.0e-14, 2.0e-14, 2.0e-14, 2.0e-14, 2.0e-14, 2.0e-14, 2.0e-14, 2.0e-14, 2.0e-14, 2.0e-14, 2.0e-14, 2.0e-14, 2.0e-14, 2.0e-14], // 1024
];
#[rustfmt::skip]
const REGULAR_MOMENT_ERRS: &[f64] = &[
    6.6e-1, // 1.05
    6.2e-1, // 1.1
    6.3e-1, // 1.2
    3.3e-1, // 1.3
    5.1e-1, // 1.4
    3.0e-1, // 1.5
    3.2e-1, // 1.75
    1.3e-1, // 2
    8.1e-2, // 2.5
    3.0e-2, // 3
    8.8e-3, // 4
    9.4e-3, // 5
    4.4e-3, // 6
    2.5e-3, // 8
    9.2e-4, // 10
    3.7e-4, // 12
    3.4e-4, // 16
    6.2e-5, // 24
    4.7e-5, // 32
    5.6e-6, // 48
    4.4e-6, // 64
    8.6e-7, // 96
    4.8e-7, // 128
    4.1e-8, // 256
    1.0e-8, // 512
    1.0e-9, // 1024
];
const _: () = assert!(REGULAR_FAR_ERRS.len() == FAR_SEPS.len() && REGULAR_MOMENT_ERRS.len() == FAR_SEPS.len());

/// Worst relative error of the fourth-order moment rule ([`crate::unobstructed::moments::moment4_pair`]) on
/// pairs of regular quads, printed by `calibrate_moment4_rule`: the same pairs as
/// REGULAR_MOMENT_ERRS, reference compensated Gauss order 32/24 below s = 2 and 24/20 above
/// (uncertainty at most 7e-12, added). It decays about as s^-6 (s^-4 from 4 to 16, where the
/// pairs resting on each other's plane dominate); between Gauss orders 2 and 3 in accuracy at
/// a small fraction of order 3's cost.
#[rustfmt::skip]
const REGULAR_MOMENT4_ERRS: &[f64] = &[
    5.3e-1, // 1.05
    4.1e-1, // 1.1
    4.4e-1, // 1.2
    1.7e-1, // 1.3
    2.7e-1, // 1.4
    1.3e-1, // 1.5
    1.2e-1, // 1.75
    2.7e-2, // 2
    1.1e-2, // 2.5
    2.5e-3, // 3
    3.9e-4, // 4
    4.4e-4, // 5
    1.5e-4, // 6
    3.9e-5, // 8
    1.0e-5, // 10
    1.8e-6, // 12
    1.5e-6, // 16
    5.5e-8, // 24
    5.4e-8, // 32
    1.9e-9, // 48
    1.1e-9, // 64
    9.5e-11, // 96
    2.1e-11, // 128
    7.6e-13, // 256
    3.4e-14, // 512
    3.1e-15, // 1024
];
const _: () = assert!(REGULAR_MOMENT4_ERRS.len() == FAR_SEPS.len());

/// Largest order [`far_field_order`] returns.
pub const MAX_FAR_ORDER: usize = 16;

/// Safety factor applied to the measured worst-case errors.
const FAR_SAFETY: f64 = 10.0;

/// Relative rounding floor of the far-field sum, as measured (errors never count below it).
const FLOOR: f64 = 2e-14;

/// Smallest Gauss order (per direction, for [`AreaRule::new`] on both polygons) whose relative
/// error for A_a F_ab stays below `rel_tol` for any pair of polygons at relative separation
/// `rel_sep` = |c_a - c_b| / (r_a + r_b) (centroid distance over the sum of bounding radii),
/// or None when no order up to [`MAX_FAR_ORDER`] is known to be safe (the pair is too close,
/// or rel_tol is below the rounding floor): the caller then uses an exact kernel.
///
/// Valid only for unobstructed pairs in which each polygon lies in the other's closed front
/// half-space: this function sees only rel_sep, so the caller must check (e.g.
/// `method::facing`) or clip first; a pair that straddles a plane has a kinked integrand and
/// the table does not apply.
///
/// Calibration (`calibrate_far_field`, ignored test): per separation, 300 random pairs
/// (triangles, convex and concave quads, convex 5-6-gons, slivers, size ratio 1/20..20, half of
/// them resting on the other's plane, perpendicular and opposed ones included) against a
/// compensated order-40/32 reference. Measured worst relative error (rows: rel_sep, columns:
/// order 1..16; values at the rounding floor shown as ~):
///
/// | rel_sep | 1 | 2 | 3 | 4 | 5 | 6 | 7 | 8 | 9 | 10 | 11 | 12 | 13 | 14 | 15 | 16 |
/// |---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|
/// | 1.05 | 9e-1 | 6e-1 | 4e-1 | 3e-1 | 2e-1 | 9e-2 | 5e-2 | 3e-2 | 1e-2 | 7e-3 | 3e-3 | 2e-3 | 8e-4 | 4e-4 | 2e-4 | 9e-5 |
/// | 1.1 | 9e-1 | 5e-1 | 3e-1 | 1e-1 | 5e-2 | 2e-2 | 7e-3 | 2e-3 | 7e-4 | 2e-4 | 6e-5 | 2e-5 | 3e-6 | 7e-7 | 1e-7 | 3e-8 |
/// | 1.2 | 7e-1 | 3e-1 | 7e-2 | 2e-2 | 4e-3 | 9e-4 | 2e-4 | 3e-5 | 7e-6 | 1e-6 | 2e-7 | 9e-9 | 5e-9 | 2e-9 | 7e-10 | 2e-10 |
/// | 1.3 | 6e-1 | 1e-1 | 2e-2 | 4e-3 | 6e-4 | 1e-4 | 4e-5 | 1e-5 | 2e-6 | 5e-7 | 1e-7 | 2e-8 | 3e-9 | 5e-10 | 7e-11 | 9e-12 |
/// | 1.4 | 6e-1 | 1e-1 | 3e-2 | 6e-3 | 9e-4 | 1e-4 | 2e-5 | 4e-6 | 7e-7 | 1e-7 | 2e-8 | 2e-9 | 3e-10 | 4e-11 | 4e-12 | 3e-13 |
/// | 1.5 | 5e-1 | 1e-1 | 1e-2 | 2e-3 | 1e-4 | 3e-5 | 3e-6 | 1e-7 | 2e-8 | 6e-9 | 7e-10 | 3e-11 | 5e-12 | 1e-12 | 1e-13 | ~ |
/// | 1.75 | 6e-1 | 1e-1 | 1e-2 | 1e-3 | 1e-4 | 8e-6 | 6e-7 | 4e-8 | 3e-9 | 2e-10 | 2e-11 | 1e-12 | 7e-14 | ~ | ~ | ~ |
/// | 2 | 3e-1 | 4e-2 | 2e-3 | 1e-4 | 6e-6 | 3e-7 | 1e-8 | 7e-10 | 3e-11 | 2e-12 | 9e-14 | ~ | ~ | ~ | ~ | ~ |
/// | 2.5 | 3e-1 | 2e-2 | 1e-3 | 5e-5 | 2e-6 | 1e-7 | 4e-9 | 2e-10 | 7e-12 | 3e-13 | ~ | ~ | ~ | ~ | ~ | ~ |
/// | 3 | 3e-1 | 4e-2 | 2e-3 | 5e-5 | 1e-6 | 1e-8 | 1e-10 | 1e-12 | 7e-14 | ~ | ~ | ~ | ~ | ~ | ~ | ~ |
/// | 4 | 2e-1 | 3e-3 | 4e-5 | 6e-7 | 6e-9 | 7e-11 | 7e-13 | ~ | ~ | ~ | ~ | ~ | ~ | ~ | ~ | ~ |
/// | 5 | 2e-1 | 6e-3 | 4e-5 | 2e-7 | 2e-9 | 2e-11 | 2e-13 | ~ | ~ | ~ | ~ | ~ | ~ | ~ | ~ | ~ |
/// | 6 | 1e-1 | 2e-3 | 8e-6 | 2e-8 | 1e-10 | 6e-13 | ~ | ~ | ~ | ~ | ~ | ~ | ~ | ~ | ~ | ~ |
/// | 8 | 8e-2 | 2e-3 | 6e-6 | 9e-9 | 2e-11 | 1e-13 | ~ | ~ | ~ | ~ | ~ | ~ | ~ | ~ | ~ | ~ |
/// | 10 | 6e-2 | 6e-4 | 5e-7 | 7e-10 | 1e-12 | ~ | ~ | ~ | ~ | ~ | ~ | ~ | ~ | ~ | ~ | ~ |
/// | 12 | 6e-2 | 3e-4 | 4e-7 | 4e-10 | 6e-13 | ~ | ~ | ~ | ~ | ~ | ~ | ~ | ~ | ~ | ~ | ~ |
/// | 16 | 3e-2 | 1e-4 | 1e-7 | 3e-11 | 4e-14 | ~ | ~ | ~ | ~ | ~ | ~ | ~ | ~ | ~ | ~ | ~ |
/// | 24 | 2e-2 | 2e-4 | 2e-7 | 9e-11 | 4e-14 | ~ | ~ | ~ | ~ | ~ | ~ | ~ | ~ | ~ | ~ | ~ |
/// | 32 | 2e-2 | 9e-5 | 2e-8 | 7e-12 | ~ | ~ | ~ | ~ | ~ | ~ | ~ | ~ | ~ | ~ | ~ | ~ |
/// | 48 | 1e-2 | 6e-5 | 4e-9 | 1e-13 | ~ | ~ | ~ | ~ | ~ | ~ | ~ | ~ | ~ | ~ | ~ | ~ |
/// | 64 | 9e-3 | 2e-5 | 1e-9 | 6e-14 | ~ | ~ | ~ | ~ | ~ | ~ | ~ | ~ | ~ | ~ | ~ | ~ |
/// | 96 | 9e-3 | 1e-5 | 2e-10 | ~ | ~ | ~ | ~ | ~ | ~ | ~ | ~ | ~ | ~ | ~ | ~ | ~ |
/// | 128 | 4e-3 | 2e-6 | 1e-11 | ~ | ~ | ~ | ~ | ~ | ~ | ~ | ~ | ~ | ~ | ~ | ~ | ~ |
/// | 256 | 2e-3 | 8e-7 | 9e-13 | ~ | ~ | ~ | ~ | ~ | ~ | ~ | ~ | ~ | ~ | ~ | ~ | ~ |
/// | 512 | 2e-3 | 3e-7 | 2e-13 | ~ | ~ | ~ | ~ | ~ | ~ | ~ | ~ | ~ | ~ | ~ | ~ | ~ |
/// | 1024 | 7e-4 | 1e-7 | 6e-14 | ~ | ~ | ~ | ~ | ~ | ~ | ~ | ~ | ~ | ~ | ~ | ~ | ~ |
///
/// The order chosen is the smallest with FAR_SAFETY (10) x max(worst error over this and all
/// larger tabulated separations, FLOOR) <= rel_tol, using the largest tabulated separation <=
/// rel_sep; beyond the last row the error is extrapolated as (s_last / s)^max(2n - 3, 1), below
/// the decay seen in the table (about s^-1 at order 1, s^-(2n-2) above: the two cosine factors
/// are linear, so the rule of degree 2n - 1 leaves the (2n - 2)-th term of 1/r⁴).
pub fn far_field_order(rel_sep: f64, rel_tol: f64) -> Option<usize> {
    if !(rel_sep.is_finite() && rel_tol.is_finite() && rel_tol > 0.0) {
        return None;
    }
    // worst error over this and all larger tabulated separations, per row and order
    static SUFFIX_MAX: OnceLock<Vec<[f64; MAX_FAR_ORDER]>> = OnceLock::new();
    let suffix = SUFFIX_MAX.get_or_init(|| {
        let mut t = FAR_ERRS.to_vec();
        for r in (0..t.len() - 1).rev() {
            for n in 0..MAX_FAR_ORDER {
                t[r][n] = t[r][n].max(t[r + 1][n]);
            }
        }
        t
    });
    let row = FAR_SEPS.partition_point(|&s| s <= rel_sep).checked_sub(1)?;
    let last = FAR_SEPS.len() - 1;
    let order_for = |n_ok: &dyn Fn(usize) -> bool| (1..=MAX_FAR_ORDER).find(|&n| n_ok(n));
    if row == last {
        return order_for(&|n| {
            let e = suffix[last][n - 1] * (FAR_SEPS[last] / rel_sep).powi((2 * n as i32 - 3).max(1));
            e.max(FLOOR) * FAR_SAFETY <= rel_tol
        });
    }
    order_for(&|n| suffix[row][n - 1].max(FLOOR) * FAR_SAFETY <= rel_tol)
}

/// Whether `poly` belongs to the regular-quad class of the calibration tables: a
/// parallelogram (v0 + v2 = v1 + v3 within 1e-9 of its size) with side ratio at most 4 and
/// corner angles in [45°, 135°]. Meshes of squares and rectangles are in it. The Gauss and
/// moment rules are much more accurate on such pairs than on general polygons (triangles,
/// concave shapes, slivers), so [`FarPlan`] has separate, calibrated thresholds for pairs of
/// two regular quads.
pub fn is_regular_quad(poly: &Polygon) -> bool {
    let v = poly.vertices();
    if v.len() != 4 {
        return false;
    }
    let (e1, e2) = (v[1] - v[0], v[3] - v[0]);
    if (v[2] - v[1] - e2).length() > 1e-9 * poly.radius() {
        return false;
    }
    let (l1, l2) = (e1.length(), e2.length());
    let cos = e1.dot(e2) / (l1 * l2);
    l1.min(l2) >= 0.25 * l1.max(l2) && cos.abs() <= std::f64::consts::FRAC_1_SQRT_2 + 1e-12
}

/// How `auto` integrates one unobstructed, fully facing pair (see [`FarPlan`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum FarRule {
    /// Tensor Gauss rule of this order on both polygons ([`far_pair`]).
    Gauss(usize),
    /// The second-moment rule ([`crate::unobstructed::moments::moment_pair`]): one division per pair.
    Moment,
    /// The fourth-order moment rule ([`crate::unobstructed::moments::moment4_pair`]), pairs of regular quads
    /// only: a few times the second-order rule's cost, against Gauss order 3's 81 point pairs.
    Moment4,
    /// Too close for any calibrated rule: an exact kernel.
    Exact,
}

/// The rule choice of `auto` for one accuracy target, as separation thresholds: every rule is
/// admissible from a relative separation on (the calibrated worst-case errors times
/// FAR_SAFETY, over this and all larger separations, are below the target), and the cheapest
/// admissible one is used: the moment rule (about 50 ns a pair, 4x less than even the Gauss
/// order 1 kernel, and calibrated more accurate than it at every separation), then Gauss
/// orders 1, 2, 3, ...
/// Two sets of thresholds: pairs of regular quads ([`is_regular_quad`]) from their own
/// tables, all other pairs from the general ones (whose Gauss choice equals
/// [`far_field_order`]'s). Built once per tolerance; choosing is a few comparisons on squared
/// distances, no square root.
#[derive(Debug, Clone, PartialEq)]
pub struct FarPlan {
    tol: f64,
    general: Thresholds,
    regular: Thresholds,
}

/// Squared relative separations from which each rule is admissible (inf: never).
#[derive(Debug, Clone, PartialEq)]
struct Thresholds {
    gauss_sq: [f64; MAX_FAR_ORDER],
    moment_sq: f64,
    moment4_sq: f64,
}

impl Thresholds {
    fn new(
        rel_tol: f64,
        gauss_errs: &[[f64; MAX_FAR_ORDER]],
        moment_errs: &[f64],
        moment4_errs: Option<&[f64]>,
    ) -> Thresholds {
        let mut t = Thresholds {
            gauss_sq: [f64::INFINITY; MAX_FAR_ORDER],
            moment_sq: f64::INFINITY,
            moment4_sq: f64::INFINITY,
        };
        if !(rel_tol.is_finite() && rel_tol > 0.0 && FLOOR * FAR_SAFETY <= rel_tol) {
            return t;
        }
        let last = FAR_SEPS.len() - 1;
        // the first row from which every larger one is admissible; beyond the table, the
        // extrapolation of far_field_order solved for the separation
        let threshold = |errs: &dyn Fn(usize) -> f64, decay: i32| -> f64 {
            let mut from = None;
            for r in (0..=last).rev() {
                if errs(r) * FAR_SAFETY > rel_tol {
                    break;
                }
                from = Some(r);
            }
            let s = match from {
                Some(r) => FAR_SEPS[r],
                None => FAR_SEPS[last] * (errs(last) * FAR_SAFETY / rel_tol).powf(1.0 / decay as f64),
            };
            s * s
        };
        for n in 1..=MAX_FAR_ORDER {
            t.gauss_sq[n - 1] = threshold(&|r| gauss_errs[r][n - 1].max(FLOOR), (2 * n as i32 - 3).max(1));
        }
        t.moment_sq = threshold(&|r| moment_errs[r].max(FLOOR), 1);
        if let Some(errs) = moment4_errs {
            t.moment4_sq = threshold(&|r| errs[r].max(FLOOR), 2);
        }
        t
    }

    #[inline]
    fn rule(&self, dist_sq: f64, radii_sq: f64) -> FarRule {
        if dist_sq >= self.moment_sq * radii_sq {
            return FarRule::Moment;
        }
        if dist_sq >= self.moment4_sq * radii_sq {
            return FarRule::Moment4;
        }
        (0..MAX_FAR_ORDER)
            .find(|&n| dist_sq >= self.gauss_sq[n] * radii_sq)
            .map_or(FarRule::Exact, |n| FarRule::Gauss(n + 1))
    }
}

impl FarPlan {
    pub fn new(rel_tol: f64) -> FarPlan {
        FarPlan {
            tol: rel_tol,
            general: Thresholds::new(rel_tol, FAR_ERRS, MOMENT_ERRS, None),
            regular: Thresholds::new(rel_tol, REGULAR_FAR_ERRS, REGULAR_MOMENT_ERRS, Some(REGULAR_MOMENT4_ERRS)),
        }
    }

    /// The plan for `rel_tol`, built once per thread and tolerance.
    pub fn cached(rel_tol: f64) -> std::rc::Rc<FarPlan> {
        thread_local! {
            static PLAN: std::cell::RefCell<Option<std::rc::Rc<FarPlan>>> = const { std::cell::RefCell::new(None) };
        }
        PLAN.with(|p| {
            let mut p = p.borrow_mut();
            match &*p {
                Some(plan) if plan.tol.to_bits() == rel_tol.to_bits() => plan.clone(),
                _ => {
                    let plan = std::rc::Rc::new(FarPlan::new(rel_tol));
                    *p = Some(plan.clone());
                    plan
                }
            }
        })
    }

    /// The rule for relative separation `rel_sep` = |c_a - c_b| / (r_a + r_b); `regular`:
    /// both polygons are regular quads.
    pub fn rule(&self, rel_sep: f64, regular: bool) -> FarRule {
        if !rel_sep.is_finite() {
            return FarRule::Exact;
        }
        self.rule_sq(rel_sep * rel_sep, 1.0, regular)
    }

    /// The squared relative separation from which the moment rule is chosen, for pairs of
    /// regular quads or others.
    pub fn moment_from_sq(&self, regular: bool) -> f64 {
        if regular {
            self.regular.moment_sq
        } else {
            self.general.moment_sq
        }
    }

    /// The squared relative separation from which the fourth-order moment rule is chosen for
    /// pairs of regular quads (below [`FarPlan::moment_from_sq`]; never for other pairs).
    pub fn moment4_from_sq(&self) -> f64 {
        self.regular.moment4_sq
    }

    /// The relative accuracy target the plan was made for.
    pub fn tol(&self) -> f64 {
        self.tol
    }

    /// [`FarPlan::rule`] from the squared centroid distance and the squared radius sum (no
    /// square root: scene loops call this for every pair).
    #[inline]
    pub fn rule_sq(&self, dist_sq: f64, radii_sq: f64, regular: bool) -> FarRule {
        if regular {
            self.regular.rule(dist_sq, radii_sq)
        } else {
            self.general.rule(dist_sq, radii_sq)
        }
    }
}

#[cfg(test)]
pub(crate) mod tests {
    use super::*;
    use crate::geometry::tangent_frame;
    use crate::quadrature::area_rules::tests::Rng;

    /// A random outline in the plane (triangles, convex and concave quads, convex 5-6-gons),
    /// including slivers; not normalised.
    pub(crate) fn random_outline(rng: &mut Rng) -> Vec<[f64; 2]> {
        let kind = rng.unit();
        loop {
            let v: Vec<[f64; 2]> = if kind < 0.4 {
                (0..3).map(|_| [rng.range(-1., 1.), rng.range(-1., 1.)]).collect()
            } else if kind < 0.85 {
                // star-shaped quad about the origin: convex or concave
                let mut ang: Vec<f64> = (0..4).map(|_| rng.range(0., 2. * PI)).collect();
                ang.sort_by(f64::total_cmp);
                let stretch = rng.range(0.05, 1.0);
                ang.iter()
                    .map(|t| {
                        let r = rng.range(0.3, 1.0);
                        [r * t.cos(), stretch * r * t.sin()]
                    })
                    .collect()
            } else {
                let k = 5 + (rng.unit() * 2.0) as usize;
                let mut ang: Vec<f64> = (0..k).map(|_| rng.range(0., 2. * PI)).collect();
                ang.sort_by(f64::total_cmp);
                let stretch = rng.range(0.1, 1.0);
                ang.iter().map(|t| [t.cos(), stretch * t.sin()]).collect()
            };
            let a2 = (0..v.len())
                .map(|i| {
                    let (p, q) = (v[i], v[(i + 1) % v.len()]);
                    p[0] * q[1] - p[1] * q[0]
                })
                .sum::<f64>();
            if a2.abs() > 1e-3 {
                return if a2 > 0.0 { v } else { v.into_iter().rev().collect() };
            }
        }
    }

    /// Polygon with the given outline, front normal n, bounding radius `radius`, centroid c.
    pub(crate) fn make_polygon(v2: &[[f64; 2]], n: Vec3, radius: f64, c: Vec3) -> Option<Polygon> {
        let (t, s) = tangent_frame(n);
        let p = Polygon::new(v2.iter().map(|q| t * q[0] + s * q[1]).collect()).ok()?;
        let k = radius / p.radius();
        Polygon::new(p.vertices().iter().map(|x| c + (*x - p.centroid()) * k).collect()).ok()
    }

    /// A random pair at relative separation `sep` in which each polygon lies in the other's
    /// closed front half-space. Half of the pairs have b resting on a's plane (touching it
    /// at a vertex or edge), a third of the rest are perpendicular or opposed-parallel.
    pub(crate) fn random_far_pair(rng: &mut Rng, sep: f64) -> (Polygon, Polygon) {
        random_far_pair_of(rng, sep, random_outline)
    }

    /// A random regular quad (see [`is_regular_quad`]): a parallelogram with side ratio in
    /// [1/4, 1] and corner angles in [45°, 135°], counter-clockwise.
    pub(crate) fn random_regular_outline(rng: &mut Rng) -> Vec<[f64; 2]> {
        let ratio = rng.range(0.25, 1.0);
        let ang = rng.range(0.25 * PI, 0.75 * PI);
        let (e1, e2) = ([1.0, 0.0], [ratio * ang.cos(), ratio * ang.sin()]);
        let o = [-(e1[0] + e2[0]) / 2.0, -(e1[1] + e2[1]) / 2.0];
        vec![
            o,
            [o[0] + e1[0], o[1] + e1[1]],
            [o[0] + e1[0] + e2[0], o[1] + e1[1] + e2[1]],
            [o[0] + e2[0], o[1] + e2[1]],
        ]
    }

    /// A pair at relative separation `sep` as in the calibration: b of size ratio 1/20..20,
    /// oriented at random (a fifth perpendicular, a tenth nearly opposed), half of the pairs
    /// with b resting on a's plane, each wholly in front of the other.
    pub(crate) fn random_far_pair_of(
        rng: &mut Rng,
        sep: f64,
        outline: fn(&mut Rng) -> Vec<[f64; 2]>,
    ) -> (Polygon, Polygon) {
        loop {
            let Some(a) = make_polygon(&outline(rng), Vec3::Z, 1.0, Vec3::ZERO) else { continue };
            let rb = (rng.range(-1., 1.) * 20f64.ln()).exp();
            let mode = rng.unit();
            let nb = if mode < 0.2 {
                let t = rng.range(0., 2. * PI);
                Vec3::new(t.cos(), t.sin(), 0.0)
            } else if mode < 0.3 {
                (Vec3::new(rng.range(-0.05, 0.05), rng.range(-0.05, 0.05), -1.0)).normalize()
            } else {
                rng.dir()
            };
            let Some(b0) = make_polygon(&outline(rng), nb, rb, Vec3::ZERO) else { continue };
            let dist = sep * (1.0 + rb);
            let zmin = b0.vertices().iter().map(|v| v.z).fold(f64::INFINITY, f64::min);
            let dz = if rng.unit() < 0.5 {
                (-zmin / dist).min(1.0) // resting on a's plane
            } else {
                rng.range((-zmin / dist).clamp(0.0, 1.0), 1.0)
            };
            let phi = rng.range(0., 2. * PI);
            let h = (1.0 - dz * dz).max(0.0).sqrt();
            let c = Vec3::new(h * phi.cos(), h * phi.sin(), dz) * dist;
            let Some(b) = Polygon::new(b0.vertices().iter().map(|v| *v + c).collect()).ok() else { continue };
            let tol = 1e-12;
            let b_front = b.vertices().iter().all(|v| v.z >= -tol);
            let a_front = a.vertices().iter().all(|v| (*v - b.centroid()).dot(b.normal()) >= -tol);
            let b_strict = b.vertices().iter().any(|v| v.z > 1e-6);
            let a_strict = a.vertices().iter().any(|v| (*v - b.centroid()).dot(b.normal()) > 1e-6);
            if b_front && a_front && b_strict && a_strict {
                return (a, b);
            }
        }
    }

    fn aff(a: &Polygon, b: &Polygon, n: usize) -> f64 {
        area_area(&AreaRule::new(a, n), a.normal(), &AreaRule::new(b, n), b.normal())
    }

    /// Reference double area integral with its own loop and Neumaier-compensated summation
    /// (so that millions of terms add without a 1e-13 rounding floor).
    pub(crate) fn reference_aff(a: &Polygon, b: &Polygon, n: usize) -> f64 {
        let (ra, rb) = (AreaRule::new(a, n), AreaRule::new(b, n));
        let (na, nb) = (a.normal(), b.normal());
        let (mut sum, mut comp) = (0.0f64, 0.0f64);
        for (x, wx) in ra.points.iter().zip(&ra.weights) {
            for (y, wy) in rb.points.iter().zip(&rb.weights) {
                let d = *y - *x;
                let r2 = d.length_squared();
                let term = wx * wy * na.dot(d).max(0.0) * (-nb.dot(d)).max(0.0) / (PI * r2 * r2);
                let t = sum + term;
                comp += if sum.abs() >= term.abs() { (sum - t) + term } else { (term - t) + sum };
                sum = t;
            }
        }
        sum + comp
    }

    /// Prints REGULAR_FAR_ERRS and REGULAR_MOMENT_ERRS: `calibrate_far_field` and
    /// `calibrate_moment_rule` on pairs of regular quads ([`is_regular_quad`]; size ratio
    /// 1/20..20, half of them resting on the other's plane, as there). Rows in parallel.
    /// Run: cargo test --release -p nusselt-core calibrate_regular_quads -- --ignored --nocapture
    #[test]
    #[ignore]
    fn calibrate_regular_quads() {
        use crate::unobstructed::moments::{moment_pair, Moments};
        use rayon::prelude::*;
        let samples: usize = std::env::var("NUSSELT_CAL_SAMPLES").ok().and_then(|s| s.parse().ok()).unwrap_or(300);
        let mut rng = Rng(4048);
        let pairs: Vec<Vec<(Polygon, Polygon)>> = FAR_SEPS
            .iter()
            .map(|&s| (0..samples).map(|_| random_far_pair_of(&mut rng, s, random_regular_outline)).collect())
            .collect();
        assert!(pairs.iter().flatten().all(|(a, b)| is_regular_quad(a) && is_regular_quad(b)));
        let rows: Vec<([f64; MAX_FAR_ORDER], f64, f64)> = FAR_SEPS
            .par_iter()
            .zip(&pairs)
            .map(|(&s, pairs)| {
                let (hi, lo) = if s < 2.0 { (40, 32) } else { (32, 24) };
                let (mut worst, mut moment, mut unc_max) = ([0.0f64; MAX_FAR_ORDER], 0.0f64, 0.0f64);
                for (a, b) in pairs {
                    let r = reference_aff(a, b, hi);
                    let unc = (r - reference_aff(a, b, lo)).abs() / r;
                    unc_max = unc_max.max(unc);
                    for n in 1..=MAX_FAR_ORDER {
                        worst[n - 1] = worst[n - 1].max((aff(a, b, n) - r).abs() / r + unc);
                    }
                    moment = moment.max((moment_pair(&Moments::new(a), &Moments::new(b)) - r).abs() / r + unc);
                }
                (worst, moment, unc_max)
            })
            .collect();
        println!("const REGULAR_FAR_ERRS: &[[f64; MAX_FAR_ORDER]] = &[");
        for (s, (worst, _, unc)) in FAR_SEPS.iter().zip(&rows) {
            let row: Vec<String> = worst.iter().map(|e| format!("{:.1e}", e.max(FLOOR))).collect();
            println!("    [{}], // s = {s}, reference uncertainty {unc:.1e}", row.join(", "));
        }
        println!("];");
        println!("const REGULAR_MOMENT_ERRS: &[f64] = &[");
        for (s, (_, m, _)) in FAR_SEPS.iter().zip(&rows) {
            println!("    {m:.1e}, // s = {s}");
        }
        println!("];");
    }

    /// Calibration of [`far_field_order`]: worst relative error of orders 1..=MAX_FAR_ORDER
    /// over random pairs per separation, against a compensated order-40 (s < 2) or order-32
    /// reference; the difference to the next lower reference order (32 or 24) is added to every
    /// error, so an unconverged reference can only over-estimate.
    /// Run: cargo test -p nusselt-core --release --lib calibrate_far_field -- --ignored --nocapture
    /// (NUSSELT_CAL_SAMPLES pairs per row, default 300).
    #[test]
    #[ignore]
    fn calibrate_far_field() {
        let seps = [
            1.05, 1.1, 1.2, 1.3, 1.4, 1.5, 1.75, 2.0, 2.5, 3.0, 4.0, 5.0, 6.0, 8.0, 10.0, 12.0, 16.0, 24.0, 32.0, 48.0,
            64.0, 96.0, 128.0, 256.0, 512.0, 1024.0,
        ];
        let samples: usize = std::env::var("NUSSELT_CAL_SAMPLES").ok().and_then(|s| s.parse().ok()).unwrap_or(300);
        let mut rng = Rng(2024);
        println!("const FAR_SEPS: &[f64] = &{seps:?};");
        println!("const FAR_ERRS: &[[f64; MAX_FAR_ORDER]] = &[");
        for &s in &seps {
            let (hi, lo) = if s < 2.0 { (40, 32) } else { (32, 24) };
            let mut worst = [0.0f64; MAX_FAR_ORDER];
            let mut ref_unc: f64 = 0.0;
            for _ in 0..samples {
                let (a, b) = random_far_pair(&mut rng, s);
                let r = reference_aff(&a, &b, hi);
                let unc = (r - reference_aff(&a, &b, lo)).abs() / r;
                ref_unc = ref_unc.max(unc);
                for n in 1..=MAX_FAR_ORDER {
                    let e = (aff(&a, &b, n) - r).abs() / r + unc;
                    worst[n - 1] = worst[n - 1].max(e);
                }
            }
            let row: Vec<String> = worst.iter().map(|e| format!("{:.1e}", e.max(FLOOR))).collect();
            println!("    [{}], // s = {s}, reference uncertainty {ref_unc:.1e}", row.join(", "));
        }
        println!("];");
    }

    /// The order chosen by far_field_order meets the tolerance on random pairs (other seed
    /// than the calibration), against a compensated high-order reference.
    #[test]
    fn moment_rule_is_calibrated_no_worse_than_gauss_order_one() {
        // FarPlan prefers the moment rule to Gauss order 1 everywhere: check it is so
        for r in 0..FAR_SEPS.len() {
            assert!(MOMENT_ERRS[r] <= FAR_ERRS[r][0], "general, s = {}", FAR_SEPS[r]);
            assert!(REGULAR_MOMENT_ERRS[r] <= REGULAR_FAR_ERRS[r][0], "regular, s = {}", FAR_SEPS[r]);
            // and the fourth-order rule, tried next, is the more accurate of the two
            assert!(REGULAR_MOMENT4_ERRS[r] <= REGULAR_MOMENT_ERRS[r], "fourth order, s = {}", FAR_SEPS[r]);
        }
    }

    #[test]
    fn regular_quads_are_recognised() {
        let quad = |v: [[f64; 2]; 4]| Polygon::new(v.iter().map(|p| Vec3::new(p[0], p[1], 0.0)).collect()).unwrap();
        assert!(is_regular_quad(&quad([[0., 0.], [1., 0.], [1., 1.], [0., 1.]])));
        assert!(is_regular_quad(&quad([[0., 0.], [4., 0.], [4., 1.], [0., 1.]]))); // side ratio 4
        assert!(!is_regular_quad(&quad([[0., 0.], [5., 0.], [5., 1.], [0., 1.]]))); // 5
        assert!(is_regular_quad(&quad([[0., 0.], [1., 0.], [2., 1.], [1., 1.]]))); // 45° rhombus-like
        assert!(!is_regular_quad(&quad([[0., 0.], [1., 0.], [2.8, 1.], [1.8, 1.]]))); // about 29°
        assert!(!is_regular_quad(&quad([[0., 0.], [2., 0.], [1.5, 1.], [0.5, 1.]]))); // trapezoid
        assert!(!is_regular_quad(&Polygon::new(vec![Vec3::ZERO, Vec3::X, Vec3::Y]).unwrap()));
        // scale and position do not matter
        let far = Polygon::new(vec![
            Vec3::new(1e6, 0., 0.),
            Vec3::new(1e6 + 1e-3, 0., 0.),
            Vec3::new(1e6 + 1e-3, 1e-3, 0.),
            Vec3::new(1e6, 1e-3, 0.),
        ])
        .unwrap();
        assert!(is_regular_quad(&far));
    }

    #[test]
    fn far_plan_meets_tolerance_on_regular_quads() {
        // random regular-quad pairs (other seed than the calibration): whatever rule the
        // plan picks for the pair meets the target
        let mut rng = Rng(31337);
        let mut checked = 0;
        for k in 0..80 {
            let s = (1.05f64.ln() + (2000f64.ln() - 1.05f64.ln()) * (k as f64 + rng.unit()) / 80.0).exp();
            let (a, b) = random_far_pair_of(&mut rng, s, random_regular_outline);
            let sep = a.centroid().distance(b.centroid()) / (a.radius() + b.radius());
            let r = reference_aff(&a, &b, 32);
            let unc = (r - reference_aff(&a, &b, 24)).abs() / r;
            for &tol in &[0.1, 1e-2, 1e-4, 1e-6, 1e-9, 1e-12] {
                if unc > 0.1 * tol {
                    continue;
                }
                let g = match FarPlan::new(tol).rule(sep, true) {
                    FarRule::Gauss(n) => aff(&a, &b, n),
                    FarRule::Moment => crate::unobstructed::moments::moment_pair(
                        &crate::unobstructed::moments::Moments::new(&a),
                        &crate::unobstructed::moments::Moments::new(&b),
                    ),
                    FarRule::Moment4 => crate::unobstructed::moments::moment4_pair(
                        &crate::unobstructed::moments::Moments::new(&a),
                        &crate::unobstructed::moments::Moments::new(&b),
                    ),
                    FarRule::Exact => continue,
                };
                let e = (g - r).abs() / r;
                assert!(e <= tol, "s {sep:.3}, tol {tol:e}: error {e:.2e}");
                checked += 1;
            }
        }
        assert!(checked >= 200, "checked {checked}");
    }

    #[test]
    fn far_plan_agrees_with_far_field_order_and_meets_tolerance() {
        // the Gauss choice is far_field_order's wherever the moment rule is not cheaper
        for &tol in &[0.1, 0.03, 1e-3, 1e-6, 1e-10, 1e-13] {
            let plan = FarPlan::new(tol);
            for k in 0..400 {
                let s = (1.0f64.ln() + (5000f64.ln() - 1.0f64.ln()) * k as f64 / 400.0).exp();
                let rule = plan.rule(s, false);
                let want = far_field_order(s, tol);
                match rule {
                    FarRule::Gauss(n) => assert_eq!(Some(n), want, "tol {tol:e}, s {s}"),
                    FarRule::Exact => assert_eq!(want, None, "tol {tol:e}, s {s}"),
                    // the moment rule replaces a Gauss order only where one is admissible
                    FarRule::Moment => assert!(want.is_some(), "tol {tol:e}, s {s}: {want:?}"),
                    FarRule::Moment4 => panic!("fourth-order rule for general polygons (tol {tol:e}, s {s})"),
                }
                // the squared form decides the same
                assert_eq!(plan.rule_sq(s * s * 4.0, 4.0, false), rule);
            }
        }
        assert_eq!(FarPlan::new(1e-16).rule(1e6, false), FarRule::Exact);
        assert_eq!(FarPlan::new(1e-16).rule(1e6, true), FarRule::Exact);
        assert_eq!(FarPlan::new(1e-6).rule(f64::NAN, true), FarRule::Exact);
        // where the plan picks the moment rule, it meets the target on random pairs
        let mut rng = Rng(99);
        let mut checked = 0;
        for k in 0..60 {
            let s = (2f64.ln() + (2000f64.ln() - 2f64.ln()) * (k as f64 + rng.unit()) / 60.0).exp();
            let (a, b) = random_far_pair(&mut rng, s);
            let r = reference_aff(&a, &b, 20);
            for &tol in &[0.1, 0.03, 1e-2, 1e-3, 1e-4] {
                if FarPlan::new(tol).rule(s, false) == FarRule::Moment {
                    let (ma, mb) = (
                        crate::unobstructed::moments::Moments::new(&a),
                        crate::unobstructed::moments::Moments::new(&b),
                    );
                    let e = (crate::unobstructed::moments::moment_pair(&ma, &mb) - r).abs() / r;
                    assert!(e <= tol, "s {s}, tol {tol:e}: moment rule error {e:.2e}");
                    checked += 1;
                }
            }
        }
        assert!(checked >= 20, "only {checked} moment-rule cases");
    }

    #[test]
    fn far_field_order_meets_tolerance() {
        let mut rng = Rng(77);
        let (mut checked, mut skipped) = (0, 0);
        assert_eq!(far_field_order(1.0, 1e-6), None);
        assert_eq!(far_field_order(f64::NAN, 1e-6), None);
        assert_eq!(far_field_order(5.0, 0.0), None);
        assert_eq!(far_field_order(5.0, 1e-16), None);
        for k in 0..40 {
            let s = (1.05f64.ln() + (300f64.ln() - 1.05f64.ln()) * (k as f64 + rng.unit()) / 40.0).exp();
            let (a, b) = random_far_pair(&mut rng, s);
            let sep = a.centroid().distance(b.centroid()) / (a.radius() + b.radius());
            assert!((sep - s).abs() < 1e-9 * s);
            let orders: Vec<(f64, usize)> =
                [1e-6, 1e-10, 1e-12].iter().filter_map(|&t| far_field_order(sep, t).map(|n| (t, n))).collect();
            if orders.is_empty() {
                continue;
            }
            let r = reference_aff(&a, &b, 32);
            let unc = (r - reference_aff(&a, &b, 24)).abs() / r;
            for (tol, n) in orders {
                if unc > 0.1 * tol {
                    skipped += 1;
                    continue;
                }
                let e = (aff(&a, &b, n) - r).abs() / r;
                assert!(e <= tol, "s = {sep:.3}, tol {tol:e}, order {n}: error {e:.2e}");
                checked += 1;
            }
        }
        assert!(checked >= 60 && skipped <= 10, "checked {checked}, skipped {skipped}");
        // more accuracy or less separation never asks for a lower order
        for &s in &[1.2, 1.5, 2.0, 3.0, 10.0, 100.0, 1e4] {
            let o: Vec<Option<usize>> = [1e-3, 1e-6, 1e-9, 1e-12].iter().map(|&t| far_field_order(s, t)).collect();
            assert!(o.windows(2).all(|w| w[1].is_none_or(|b| w[0].is_some_and(|a| a <= b))), "{s}: {o:?}");
            if let Some(n1) = far_field_order(s, 1e-8) {
                assert!(far_field_order(2.0 * s, 1e-8).is_some_and(|n2| n2 <= n1), "{s}");
            }
        }
    }

    /// The packed kernel (what `auto` uses) computes the same sum as area_area on pairs in
    /// each other's front half-space, for every rule size (chunking, padding) and polygon kind.
    #[test]
    fn far_pair_matches_area_area() {
        let mut rng = Rng(2026);
        for k in 0..200 {
            let sep = 1.1 + 30.0 * rng.unit();
            let (a, b) = random_far_pair(&mut rng, sep);
            let n = 1 + k % 12;
            let (ra, rb) = (AreaRule::new(&a, n), AreaRule::new(&b, n));
            let want = area_area(&ra, a.normal(), &rb, b.normal());
            let got = far_pair(&PackedRule::new(&ra, &a), a.normal(), &PackedRule::new(&rb, &b), b.normal());
            assert!((got - want).abs() <= 1e-12 * want.abs(), "pair {k}, order {n}: {got} vs {want}");
            // symmetric in the pair
            let back = far_pair(&PackedRule::new(&rb, &b), b.normal(), &PackedRule::new(&ra, &a), a.normal());
            assert!((back - want).abs() <= 1e-12 * want.abs(), "pair {k} reversed: {back} vs {want}");
        }
    }

    /// The AVX2 path gives the portable body's results bit for bit, for rules of one lane
    /// group up to several chunks (orders 1 to 16, triangles and quads).
    #[test]
    fn far_pair_paths_agree_bitwise() {
        let mut rng = Rng(77);
        let mut compared = 0;
        for k in 0..120 {
            let sep = 1.2 + 10.0 * rng.unit();
            let (a, b) = random_far_pair(&mut rng, sep);
            let (pa, pb) = (
                PackedRule::new(&AreaRule::new(&a, 1 + k % 16), &a),
                PackedRule::new(&AreaRule::new(&b, 1 + (k * 7) % 16), &b),
            );
            let body = far_pair_body(&pa, a.normal(), &pb, b.normal());
            #[cfg(target_arch = "x86_64")]
            if std::arch::is_x86_feature_detected!("avx2") {
                // SAFETY: the CPU supports AVX2, checked just above.
                let simd = unsafe { far_pair_avx2(&pa, a.normal(), &pb, b.normal()) };
                assert_eq!(simd.to_bits(), body.to_bits(), "pair {k}: {simd} vs {body}");
                compared += 1;
            }
            assert_eq!(far_pair(&pa, a.normal(), &pb, b.normal()).to_bits(), body.to_bits());
        }
        #[cfg(target_arch = "x86_64")]
        if std::arch::is_x86_feature_detected!("avx2") {
            assert_eq!(compared, 120);
        }
    }

    pub(crate) fn square(x0: f64, y0: f64, s: f64, z: f64, up: bool) -> Polygon {
        let mut v = vec![
            Vec3::new(x0, y0, z),
            Vec3::new(x0 + s, y0, z),
            Vec3::new(x0 + s, y0 + s, z),
            Vec3::new(x0, y0 + s, z),
        ];
        if !up {
            v.reverse();
        }
        Polygon::new(v).unwrap()
    }

    /// Howell C-11, parallel directly opposed unit squares at distance 1 (docs/algorithms.md §8).
    #[test]
    fn area_area_matches_c11() {
        let exact = 0.199824895698387;
        let (a, b) = (square(0., 0., 1., 0., true), square(0., 0., 1., 1., false));
        let f = |n| area_area(&AreaRule::new(&a, n), a.normal(), &AreaRule::new(&b, n), b.normal());
        assert!((f(8) - exact).abs() < 1e-9 * exact, "{}", f(8));
        assert!((f(16) - exact).abs() < 1e-14 * exact, "{}", f(16));
        // symmetric in the pair (reciprocity of the estimator)
        let g = area_area(&AreaRule::new(&b, 6), b.normal(), &AreaRule::new(&a, 6), a.normal());
        assert!((g - f(6)).abs() < 1e-15);
        // error decreases with order (until it oscillates about 1e-11)
        let errs: Vec<f64> = (1..=7).map(|n| (f(n) - exact).abs()).collect();
        assert!(errs.windows(2).all(|w| w[1] < w[0]), "{errs:?}");
    }

    /// The chunked structure-of-arrays loop equals a plain double loop (any chunk remainder).
    #[test]
    fn area_area_chunking_matches_plain_sum() {
        let a = Polygon::new(vec![Vec3::new(0., 0., 0.), Vec3::new(1., 0., 0.), Vec3::new(0.2, 0.9, 0.)]).unwrap();
        let b = Polygon::new(vec![Vec3::new(0., 0., 2.), Vec3::new(0.3, 1., 2.4), Vec3::new(1.1, 0.1, 2.2)]).unwrap();
        let nb =
            if b.normal().z > 0.0 { Polygon::new(b.vertices().iter().rev().copied().collect()).unwrap() } else { b };
        for n in 1..=9 {
            let (ra, rb) = (AreaRule::new(&a, n), AreaRule::new(&nb, n));
            let mut plain = 0.0;
            for (x, wx) in ra.points.iter().zip(&ra.weights) {
                for (y, wy) in rb.points.iter().zip(&rb.weights) {
                    let d = *y - *x;
                    let r = d.length();
                    let (ca, cb) = (a.normal().dot(d) / r, -nb.normal().dot(d) / r);
                    plain += wx * wy * ca.max(0.0) * cb.max(0.0) / (PI * r * r);
                }
            }
            let fast = area_area(&ra, a.normal(), &rb, nb.normal());
            assert!((fast - plain).abs() <= 1e-14 * plain, "n={n}: {fast} vs {plain}");
        }
    }
}
