//! Second-moment far-field rule: A_a F_ab from each polygon's area, centroid and second
//! moments, one division per pair.
//!
//! For an unobstructed pair that lies wholly in each other's front half-space,
//!
//!   A_a F_ab = ∫_a ∫_b K(y - x) dy dx,   K(d) = p q / (π s²),  p = n_a·d, q = -n_b·d, s = d·d.
//!
//! Taylor-expanding K about d₀ = c_b - c_a to second order, the first moments vanish (the
//! expansion is about the centroids) and the second-order terms need only the central second
//! moments per unit area M_a, M_b (symmetric 3x3; K depends on y - x only, so ∇²_x = ∇²_y):
//!
//!   A_a F_ab ≈ A_a A_b [K(d₀) + ½ (M_a + M_b) : ∇²K(d₀)].
//!
//! With ∇p = n_a, ∇q = -n_b, ∇s = 2d,
//!
//!   π ∇²K = -(n_a n_bᵀ + n_b n_aᵀ)/s² - 4 (q n_a - p n_b) dᵀ/s³ - 4 d (q n_a - p n_b)ᵀ/s³
//!           - 4 p q I/s³ + 24 p q d dᵀ/s⁴,
//!
//! and because each polygon lies in its plane, M_a n_a = 0 and M_b n_b = 0, so n_aᵀ M n_b = 0 and
//!
//!   A_a F_ab ≈ A_a A_b/(π s²) [p q - 4 (q n_a·M_b d - p n_b·M_a d)/s - 2 p q tr(M)/s
//!                              + 12 p q d·M d/s²],   M = M_a + M_b.
//!
//! The neglected terms are of third order in size/distance (zero third moments, e.g. for
//! parallelograms, leave fourth order). The relative error is calibrated per separation like
//! the Gauss rules (`calibrate_moment_rule`, ignored test) in [`crate::unobstructed::far_field`]; the rule
//! costs about as much as one point pair of a Gauss rule.
//!
//! # Fourth order, for parallelograms
//!
//! A parallelogram is point-symmetric about its centroid, so all its odd central moments
//! vanish and the next terms are of fourth order; adding them leaves an error of sixth order.
//! Write x = c_a + x', y = c_b + y', u = y' - x', and (because x' lies in a's plane and y' in
//! b's) p(d₀ + u) = p + α with α = n_a·y', q(d₀ + u) = q + β with β = n_b·x',
//! s(d₀ + u) = s (1 + ε), ε = t (2δ + w), t = 1/s, δ = d₀·u, w = u·u. Then
//! π K = (p + α)(q + β) t² (1 + ε)⁻², and with (1 + ε)⁻² = 1 - 2ε + 3ε² - 4ε³ + 5ε⁴ - ...
//! sorted by order in u,
//!
//!   S₁ = -4tδ,  S₂ = -2tw + 12t²δ²,  S₃ = 12t²δw - 32t³δ³,  S₄ = 3t²w² - 48t³δ²w + 80t⁴δ⁴.
//!
//! Odd orders average to zero, E\[α\] = E\[β\] = E\[αβ\] = 0, and the fourth-order part of the
//! bracket is
//!
//!   pq E\[S₄\] + p E\[β S₃\] + q E\[α S₃\] + E\[αβ S₂\].
//!
//! The expectations over the two independent, centred points follow from the moments of each
//! polygon: for a parallelogram with edge vectors E₁, E₂, x' = σ₁E₁ + σ₂E₂ with σ uniform on
//! [-½, ½]², so E\[σ²\] = 1/12, E\[σ⁴\] = 1/80, and every moment is a polynomial in the edge
//! projections v_k = v·E_k (see `fourth_order_term`). The second-order part is the rule
//! above (M = (E₁E₁ᵀ + E₂E₂ᵀ)/12 for a parallelogram). Cost: about four times the
//! second-order rule, against 81 point pairs of the Gauss rule of order 3 that it replaces.

use crate::geometry::{Polygon, Vec3};
use crate::quadrature::AreaRule;
use std::f64::consts::PI;

/// What the moment rule needs of one polygon.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Moments {
    pub area: f64,
    pub centroid: Vec3,
    pub normal: Vec3,
    /// Central second moments per unit area: xx, xy, xz, yy, yz, zz.
    pub m: [f64; 6],
    /// For a quad, its edge vectors v1 - v0 and v3 - v0 (which span it when it is a
    /// parallelogram, the only case [`moment4_pair`] is for); zero otherwise.
    pub edges: [Vec3; 2],
}

impl Moments {
    pub fn new(poly: &Polygon) -> Moments {
        // order 2 integrates the quadratic x xᵀ exactly on triangles and planar quads (the
        // quad map's Jacobian is affine): order 3 leaves a margin for the triangulated case too
        let rule = AreaRule::new(poly, 3);
        let c = poly.centroid();
        let mut m = [0.0f64; 6];
        let mut area = 0.0;
        for (x, &w) in rule.points.iter().zip(&rule.weights) {
            let d = *x - c;
            m[0] += w * d.x * d.x;
            m[1] += w * d.x * d.y;
            m[2] += w * d.x * d.z;
            m[3] += w * d.y * d.y;
            m[4] += w * d.y * d.z;
            m[5] += w * d.z * d.z;
            area += w;
        }
        for v in &mut m {
            *v /= area;
        }
        let v = poly.vertices();
        let edges = if v.len() == 4 { [v[1] - v[0], v[3] - v[0]] } else { [Vec3::ZERO; 2] };
        Moments { area: poly.area(), centroid: c, normal: poly.normal(), m, edges }
    }
}

/// M d for the packed symmetric moments m (xx, xy, xz, yy, yz, zz).
#[inline(always)]
fn times(m: &[f64; 6], d: Vec3) -> Vec3 {
    Vec3::new(
        m[0] * d.x + m[1] * d.y + m[2] * d.z,
        m[1] * d.x + m[3] * d.y + m[4] * d.z,
        m[2] * d.x + m[4] * d.y + m[5] * d.z,
    )
}

/// pq plus the second-order terms: the bracket of the module docs (t = 1/(d·d)).
#[inline(always)]
pub(crate) fn second_order_bracket(d: Vec3, na: Vec3, nb: Vec3, ma: &[f64; 6], mb: &[f64; 6], t: f64) -> f64 {
    let (p, q) = (na.dot(d), -nb.dot(d));
    let (mad, mbd) = (times(ma, d), times(mb, d));
    let dmd = d.dot(mad) + d.dot(mbd);
    let trace = (ma[0] + ma[3] + ma[5]) + (mb[0] + mb[3] + mb[5]);
    let pq = p * q;
    pq - t * (4.0 * (q * na.dot(mbd) - p * nb.dot(mad)) + 2.0 * pq * trace) + 12.0 * t * t * pq * dmd
}

/// E\[σ²\], E\[σ⁴\] and E\[σ²\]² for σ uniform on [-½, ½].
const MU2: f64 = 1.0 / 12.0;
const MU4: f64 = 1.0 / 80.0;
const MU22: f64 = 1.0 / 144.0;

/// The fourth-order part of the bracket for two parallelograms with edge vectors `ea`, `eb`
/// (module docs; t = 1/(d·d)). Each expectation is written out in the edge projections:
/// with v_k = v·E_k of one polygon and L_k = E_k·E_k, C = E₁·E₂,
///
///   M(v, w) = μ₂ (v₁w₁ + v₂w₂),   (M_a v)·(M_b w) = μ₂² Σ_kl v_k w_l (E_ak·E_bl),
///   Q(w, w, w, w) = μ₄ (w₁⁴ + w₂⁴) + 6 μ₂² w₁²w₂²,
///   Q(v, w, w, w) = μ₄ (v₁w₁³ + v₂w₂³) + 3 μ₂² (v₁w₁w₂² + v₂w₂w₁²),
///   E\[(v·x')(w·x')|x'|²\] = v₁w₁ (μ₄L₁ + μ₂²L₂) + v₂w₂ (μ₂²L₁ + μ₄L₂) + 2μ₂² C (v₁w₂ + v₂w₁),
///   E|x'|⁴ = μ₄ (L₁² + L₂²) + 2μ₂² L₁L₂ + 4μ₂² C²,
///
/// and for u = y' - x' the fourth moments add the two polygons' own and the six products of
/// second moments, e.g. E\[δ⁴\] = Q_a(d⁴) + Q_b(d⁴) + 6 M_a(d, d) M_b(d, d).
#[inline(always)]
pub(crate) fn fourth_order_term(d: Vec3, na: Vec3, nb: Vec3, ea: &[Vec3; 2], eb: &[Vec3; 2], t: f64) -> f64 {
    let (p, q) = (na.dot(d), -nb.dot(d));
    // projections on the edges: d and n_b on a's, d and n_a on b's
    let (da1, da2, va1, va2) = (d.dot(ea[0]), d.dot(ea[1]), nb.dot(ea[0]), nb.dot(ea[1]));
    let (db1, db2, vb1, vb2) = (d.dot(eb[0]), d.dot(eb[1]), na.dot(eb[0]), na.dot(eb[1]));
    let (g11, g12, g21, g22) = (ea[0].dot(eb[0]), ea[0].dot(eb[1]), ea[1].dot(eb[0]), ea[1].dot(eb[1]));
    let (la1, la2, ca) = (ea[0].dot(ea[0]), ea[1].dot(ea[1]), ea[0].dot(ea[1]));
    let (lb1, lb2, cb) = (eb[0].dot(eb[0]), eb[1].dot(eb[1]), eb[0].dot(eb[1]));
    // second moments
    let (tra, trb) = (MU2 * (la1 + la2), MU2 * (lb1 + lb2));
    let ma_dd = MU2 * (da1 * da1 + da2 * da2);
    let mb_dd = MU2 * (db1 * db1 + db2 * db2);
    let ma_nd = MU2 * (va1 * da1 + va2 * da2); // M_a(n_b, d)
    let mb_nd = MU2 * (vb1 * db1 + vb2 * db2); // M_b(n_a, d)
    let cross = |v1: f64, v2: f64, w1: f64, w2: f64| MU22 * (v1 * (w1 * g11 + w2 * g12) + v2 * (w1 * g21 + w2 * g22));
    let mad_mbd = cross(da1, da2, db1, db2);
    let mad_mbn = cross(da1, da2, vb1, vb2);
    let man_mbd = cross(va1, va2, db1, db2);
    let man_mbn = cross(va1, va2, vb1, vb2);
    let ma_mb = MU22 * (g11 * g11 + g12 * g12 + g21 * g21 + g22 * g22);
    // fourth moments of each polygon
    let q4 = |w1: f64, w2: f64| MU4 * (w1 * w1 * w1 * w1 + w2 * w2 * w2 * w2) + 6.0 * MU22 * (w1 * w1) * (w2 * w2);
    let q31 = |v1: f64, v2: f64, w1: f64, w2: f64| {
        MU4 * (v1 * w1 * w1 * w1 + v2 * w2 * w2 * w2) + 3.0 * MU22 * (v1 * w1 * w2 * w2 + v2 * w2 * w1 * w1)
    };
    let qtr = |v1: f64, v2: f64, w1: f64, w2: f64, l1: f64, l2: f64, c: f64| {
        v1 * w1 * (MU4 * l1 + MU22 * l2) + v2 * w2 * (MU22 * l1 + MU4 * l2) + 2.0 * MU22 * c * (v1 * w2 + v2 * w1)
    };
    let x4 = |l1: f64, l2: f64, c: f64| MU4 * (l1 * l1 + l2 * l2) + 2.0 * MU22 * (l1 * l2 + 2.0 * c * c);
    // the expectations of the module docs
    let e_d4 = q4(da1, da2) + q4(db1, db2) + 6.0 * ma_dd * mb_dd;
    let e_d2w = qtr(da1, da2, da1, da2, la1, la2, ca)
        + qtr(db1, db2, db1, db2, lb1, lb2, cb)
        + mb_dd * tra
        + ma_dd * trb
        + 4.0 * mad_mbd;
    let e_w2 = x4(la1, la2, ca) + x4(lb1, lb2, cb) + 2.0 * tra * trb + 4.0 * ma_mb;
    let e_ad3 = q31(vb1, vb2, db1, db2) + 3.0 * mb_nd * ma_dd;
    let e_adw = qtr(vb1, vb2, db1, db2, lb1, lb2, cb) + mb_nd * tra + 2.0 * mad_mbn;
    let e_bd3 = -(q31(va1, va2, da1, da2) + 3.0 * ma_nd * mb_dd);
    let e_bdw = -(qtr(va1, va2, da1, da2, la1, la2, ca) + ma_nd * trb + 2.0 * man_mbd);
    let e_abw = -2.0 * man_mbn;
    let e_abd2 = -2.0 * mb_nd * ma_nd;
    let t2 = t * t;
    p * q * (3.0 * t2 * e_w2 - 48.0 * t2 * t * e_d2w + 80.0 * t2 * t2 * e_d4)
        + p * (12.0 * t2 * e_bdw - 32.0 * t2 * t * e_bd3)
        + q * (12.0 * t2 * e_adw - 32.0 * t2 * t * e_ad3)
        + (-2.0 * t * e_abw + 12.0 * t2 * e_abd2)
}

/// The rule on plain numbers: d = c_b - c_a, the unit normals, the second moments of a and b,
/// the edges of a and b, A_a A_b; to second order, or with `fourth` to fourth order (two
/// parallelograms, module docs). Branch-free, so that the scene loop's pass over a row
/// vectorises with a mix of both; with a constant `false` the fourth-order terms are dead code
/// after inlining. Shared by [`moment_pair`], [`moment4_pair`] and the scene loop
/// (`unobstructed::rows`), which gathers b's numbers from arrays.
#[inline(always)]
#[allow(clippy::too_many_arguments)]
pub(crate) fn moment_rule_formula(
    d: Vec3,
    na: Vec3,
    nb: Vec3,
    ma: &[f64; 6],
    mb: &[f64; 6],
    ea: &[Vec3; 2],
    eb: &[Vec3; 2],
    area_product: f64,
    fourth: bool,
) -> f64 {
    let t = 1.0 / d.dot(d);
    let t4 = fourth_order_term(d, na, nb, ea, eb, t);
    let bracket = second_order_bracket(d, na, nb, ma, mb, t) + if fourth { t4 } else { 0.0 };
    (area_product / PI) * t * t * bracket.max(0.0)
}

/// [`moment_rule_formula`] on two polygons' [`Moments`].
#[inline(always)]
fn on_moments(a: &Moments, b: &Moments, fourth: bool) -> f64 {
    let (d, ab) = (b.centroid - a.centroid, a.area * b.area);
    moment_rule_formula(d, a.normal, b.normal, &a.m, &b.m, &a.edges, &b.edges, ab, fourth)
}

/// A_a F_ab by the second-moment rule (see the module docs); valid for a pair in which each
/// polygon lies in the other's closed front half-space and far apart compared with its size.
/// Symmetric in a and b up to rounding.
#[inline(always)]
pub fn moment_pair(a: &Moments, b: &Moments) -> f64 {
    on_moments(a, b, false)
}

/// A_a F_ab by the fourth-order moment rule (module docs); for two parallelograms (e.g.
/// [`crate::unobstructed::far_field::is_regular_quad`]) each in the other's closed front half-space, far
/// apart compared with their size. Symmetric in a and b up to rounding.
#[inline(always)]
pub fn moment4_pair(a: &Moments, b: &Moments) -> f64 {
    on_moments(a, b, true)
}

/// The centroid (one-point) rule: A_a A_b K(c_b - c_a), for comparison and for pairs so far
/// apart that the moment terms are below the accuracy asked for.
#[inline]
pub fn centroid_pair(a: &Moments, b: &Moments) -> f64 {
    let d = b.centroid - a.centroid;
    let t = 1.0 / d.dot(d);
    let (p, q) = (a.normal.dot(d), -b.normal.dot(d));
    (a.area * b.area / PI) * t * t * (p.max(0.0) * q.max(0.0))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::quadrature::area_rules::tests::Rng;
    use crate::unobstructed::far_field::tests::{random_far_pair, reference_aff};

    fn square(c: Vec3, u: Vec3, w: Vec3, h: f64) -> Polygon {
        let (u, w) = (u * (0.5 * h), w * (0.5 * h));
        Polygon::new(vec![c - u - w, c + u - w, c + u + w, c - u + w]).unwrap()
    }

    #[test]
    fn moments_of_a_square_and_a_triangle() {
        // square of side h in the xy-plane: M = diag(h²/12, h²/12, 0)
        let s = Moments::new(&square(Vec3::new(1.0, 2.0, 3.0), Vec3::X, Vec3::Y, 0.3));
        let e = 0.09 / 12.0;
        for (k, want) in [e, 0.0, 0.0, e, 0.0, 0.0].iter().enumerate() {
            assert!((s.m[k] - want).abs() < 1e-15, "square m[{k}] = {}", s.m[k]);
        }
        // right triangle (0,0),(1,0),(0,1): Ixx about the centroid = 1/36 · 1/... per unit area 1/18
        let t = Moments::new(&Polygon::new(vec![Vec3::ZERO, Vec3::X, Vec3::Y]).unwrap());
        assert!((t.m[0] - 1.0 / 18.0).abs() < 1e-15 && (t.m[3] - 1.0 / 18.0).abs() < 1e-15);
        assert!((t.m[1] + 1.0 / 36.0).abs() < 1e-15, "xy = {}", t.m[1]);
    }

    type Rule = fn(&Moments, &Moments) -> f64;

    /// The relative error of `rule` on the pairs `pair(h)` for the shrinking sizes `hs`
    /// (fixed centres; reference: Gauss order 24) falls by a factor in `drop` per halving, is
    /// below the `coarser` rule's by more than `margin`, and the rule is symmetric.
    fn assert_converges(
        hs: [f64; 3],
        pair: impl Fn(f64) -> (Polygon, Polygon),
        rule: Rule,
        coarser: Rule,
        margin: f64,
        drop: (f64, f64),
    ) {
        let mut prev: Option<f64> = None;
        for h in hs {
            let (a, b) = pair(h);
            let (ma, mb) = (Moments::new(&a), Moments::new(&b));
            let r = reference_aff(&a, &b, 24);
            let e = (rule(&ma, &mb) - r).abs() / r;
            let e_coarse = (coarser(&ma, &mb) - r).abs() / r;
            assert!(e < e_coarse / margin, "h {h}: {e:.1e} vs the coarser rule's {e_coarse:.1e}");
            if let Some(p) = prev {
                assert!(p / e > drop.0 && p / e < drop.1, "h {h}: ratio {}", p / e);
            }
            prev = Some(e);
            assert!((rule(&ma, &mb) - rule(&mb, &ma)).abs() <= 1e-14 * r);
        }
    }

    #[test]
    fn moment_rule_converges_at_fourth_order_for_squares() {
        // squares: the error of a parallelogram pair falls as h⁴ (a 16-fold drop per
        // halving), the centroid rule's as h²
        let pair = |h| {
            let a = square(Vec3::ZERO, Vec3::X, Vec3::Y, h);
            (a, square(Vec3::new(0.3, 0.2, 0.5), (Vec3::Y + Vec3::Z).normalize(), Vec3::X, h))
        };
        assert_converges([0.05, 0.025, 0.0125], pair, moment_pair, centroid_pair, 50.0, (12.0, 20.0));
    }

    fn parallelogram(c: Vec3, e1: Vec3, e2: Vec3) -> Polygon {
        let o = c - (e1 + e2) * 0.5;
        Polygon::new(vec![o, o + e1, o + e1 + e2, o + e2]).unwrap()
    }

    #[test]
    fn fourth_order_rule_converges_at_sixth_order_for_parallelograms() {
        // parallelograms in general position (skewed, unequal sides, oblique planes): the
        // fourth-order rule's error falls as h⁶ (64-fold per halving), far below the
        // second-order rule's
        let (u, v) = (Vec3::new(1.0, 0.3, -0.2).normalize(), Vec3::new(-0.1, 0.8, 0.5).normalize());
        let w = Vec3::new(0.4, -0.3, 1.0).normalize();
        let w1 = w.cross(Vec3::new(0.2, 1.0, 0.1)).normalize();
        let w2 = w.cross(w1);
        let pair = |h| {
            let a = parallelogram(Vec3::ZERO, u * h, (u * 0.4 + v * 0.8) * h);
            let mut b = parallelogram(Vec3::new(0.2, -0.1, 0.6), w1 * (1.3 * h), (w2 * 0.9 - w1 * 0.3) * h);
            if b.normal().dot(a.centroid() - b.centroid()) < 0.0 {
                b = Polygon::new(b.vertices().iter().rev().copied().collect()).unwrap();
            }
            assert_eq!(crate::unobstructed::method::facing(&a, &b), crate::unobstructed::method::Facing::Full);
            (a, b)
        };
        assert_converges([0.08, 0.04, 0.02], pair, moment4_pair, moment_pair, 30.0, (45.0, 90.0));
    }

    #[test]
    fn fourth_order_rule_on_random_far_regular_quads() {
        // random parallelogram pairs (both orientations, size ratio up to 20, resting on each
        // other's plane half the time) at relative separation 16: the fourth-order rule beats
        // the second-order one on every pair by a wide margin
        let mut rng = Rng(99);
        let mut worst = 0.0f64;
        for _ in 0..40 {
            let (a, b) = crate::unobstructed::far_field::tests::random_far_pair_of(
                &mut rng,
                16.0,
                crate::unobstructed::far_field::tests::random_regular_outline,
            );
            let r = reference_aff(&a, &b, 20);
            let (ma, mb) = (Moments::new(&a), Moments::new(&b));
            let e4 = (moment4_pair(&ma, &mb) - r).abs() / r;
            let e2 = (moment_pair(&ma, &mb) - r).abs() / r;
            assert!(e4 <= e2 / 5.0 + 1e-13, "fourth order {e4:.1e} vs second {e2:.1e}");
            worst = worst.max(e4);
        }
        assert!(worst < 1e-5, "worst {worst:.1e}");
    }

    #[test]
    fn moment_rule_on_random_far_pairs() {
        // general polygons (triangles, concave, slivers, size ratio up to 20) at relative
        // separation 64: within 1e-4 of the reference, always better than the centroid rule
        // on average
        let mut rng = Rng(7);
        let (mut sum_m, mut sum_c) = (0.0, 0.0);
        for _ in 0..40 {
            let (a, b) = random_far_pair(&mut rng, 64.0);
            let r = reference_aff(&a, &b, 16);
            let (ma, mb) = (Moments::new(&a), Moments::new(&b));
            let e = (moment_pair(&ma, &mb) - r).abs() / r;
            assert!(e < 1e-4, "moment error {e:.1e}");
            sum_m += e;
            sum_c += (centroid_pair(&ma, &mb) - r).abs() / r;
        }
        assert!(sum_m < 0.2 * sum_c, "moment {sum_m:.1e} centroid {sum_c:.1e}");
    }

    /// Worst relative error of `rule` per row of `pairs` (one row per FAR_SEPS entry) against
    /// a compensated Gauss reference of orders `refs(s)` = (high, low), the difference of the
    /// two (the reference's uncertainty) added to each error, printed as the Rust table `name`.
    /// Rows in parallel.
    fn print_calibration(
        name: &str,
        pairs: &[Vec<(Polygon, Polygon)>],
        refs: fn(f64) -> (usize, usize),
        rule: fn(&Moments, &Moments) -> f64,
    ) {
        use rayon::prelude::*;
        let seps = crate::unobstructed::far_field::FAR_SEPS;
        let rows: Vec<(f64, f64)> = seps
            .par_iter()
            .zip(pairs)
            .map(|(&s, pairs)| {
                let (hi, lo) = refs(s);
                let (mut worst, mut unc_max) = (0.0f64, 0.0f64);
                for (a, b) in pairs {
                    let r = reference_aff(a, b, hi);
                    let unc = (r - reference_aff(a, b, lo)).abs() / r;
                    unc_max = unc_max.max(unc);
                    worst = worst.max((rule(&Moments::new(a), &Moments::new(b)) - r).abs() / r + unc);
                }
                (worst, unc_max)
            })
            .collect();
        println!("const {name}: &[f64] = &[");
        for (s, (worst, unc)) in seps.iter().zip(rows) {
            println!("    {worst:.1e}, // s = {s}, reference uncertainty {unc:.1e}");
        }
        println!("];");
    }

    /// NUSSELT_CAL_SAMPLES random pairs (default 300) per FAR_SEPS entry from `pair`.
    fn calibration_pairs(
        seed: u64,
        pair: impl Fn(&mut Rng, f64) -> (Polygon, Polygon),
    ) -> Vec<Vec<(Polygon, Polygon)>> {
        let samples: usize = std::env::var("NUSSELT_CAL_SAMPLES").ok().and_then(|s| s.parse().ok()).unwrap_or(300);
        let mut rng = Rng(seed);
        crate::unobstructed::far_field::FAR_SEPS
            .iter()
            .map(|&s| (0..samples).map(|_| pair(&mut rng, s)).collect())
            .collect()
    }

    /// Prints `far_field::REGULAR_MOMENT4_ERRS`: the fourth-order rule on the same random
    /// pairs of regular quads (same seed and generator) as `calibrate_regular_quads`; the
    /// reference orders are higher than `calibrate_moment_rule`'s (the errors are smaller).
    /// Run: cargo test --release -p nusselt-core calibrate_moment4_rule -- --ignored --nocapture
    #[test]
    #[ignore]
    fn calibrate_moment4_rule() {
        use crate::unobstructed::far_field::tests::{random_far_pair_of, random_regular_outline};
        let pairs = calibration_pairs(4048, |rng, s| random_far_pair_of(rng, s, random_regular_outline));
        print_calibration("REGULAR_MOMENT4_ERRS", &pairs, |s| if s < 2.0 { (32, 24) } else { (24, 20) }, moment4_pair);
    }

    /// Prints the moment rule's calibration rows for `far_field::MOMENT_ERRS`: the same
    /// random pairs (same seed and generator) as `calibrate_far_field`. The reference is a
    /// compensated Gauss rule of lower order than there (the moment rule's errors are far
    /// larger than the Gauss rules'), and its uncertainty (difference to a lower order) is
    /// added to each error.
    /// Run: cargo test --release -p nusselt-core calibrate_moment_rule -- --ignored --nocapture
    #[test]
    #[ignore]
    fn calibrate_moment_rule() {
        let pairs = calibration_pairs(2024, random_far_pair);
        print_calibration("MOMENT_ERRS", &pairs, |s| if s < 2.0 { (24, 20) } else { (20, 16) }, moment_pair);
    }
}
