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
//! the Gauss rules (`calibrate_moment_rule`, ignored test) in [`crate::quadrature`]; the rule
//! costs about as much as one point pair of a Gauss rule.

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
        Moments { area: poly.area(), centroid: c, normal: poly.normal(), m }
    }
}

/// M d for the packed symmetric moments m (xx, xy, xz, yy, yz, zz).
#[inline(always)]
fn times(m: &[f64; 6], d: Vec3) -> Vec3 {
    Vec3::new(m[0] * d.x + m[1] * d.y + m[2] * d.z, m[1] * d.x + m[3] * d.y + m[4] * d.z, m[2] * d.x + m[4] * d.y + m[5] * d.z)
}

/// The rule's formula on plain numbers: d = c_b - c_a, the unit normals, the moments of a and b
/// and A_a A_b. Shared by [`moment_pair`] and the vectorised scene loop
/// (`unobstructed_rows`), which gathers b's numbers from arrays.
#[inline(always)]
pub(crate) fn moment_formula(d: Vec3, na: Vec3, nb: Vec3, ma: &[f64; 6], mb: &[f64; 6], area_product: f64) -> f64 {
    let t = 1.0 / d.dot(d);
    let (p, q) = (na.dot(d), -nb.dot(d));
    let (mad, mbd) = (times(ma, d), times(mb, d));
    let dmd = d.dot(mad) + d.dot(mbd);
    let trace = (ma[0] + ma[3] + ma[5]) + (mb[0] + mb[3] + mb[5]);
    let pq = p * q;
    let bracket = pq - t * (4.0 * (q * na.dot(mbd) - p * nb.dot(mad)) + 2.0 * pq * trace) + 12.0 * t * t * pq * dmd;
    (area_product / PI) * t * t * bracket.max(0.0)
}

/// A_a F_ab by the second-moment rule (see the module docs); valid for a pair in which each
/// polygon lies in the other's closed front half-space and far apart compared with its size.
/// Symmetric in a and b up to rounding.
#[inline(always)]
pub fn moment_pair(a: &Moments, b: &Moments) -> f64 {
    moment_formula(b.centroid - a.centroid, a.normal, b.normal, &a.m, &b.m, a.area * b.area)
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
    use crate::quadrature::tests::{random_far_pair, reference_aff, Rng};

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

    #[test]
    fn moment_rule_converges_at_fourth_order_for_squares() {
        // fixed centres, shrinking squares: the error of a parallelogram pair falls as h⁴
        // (a 16-fold drop per halving), the centroid rule's as h²; reference: Gauss order 24
        let mut prev: Option<f64> = None;
        for h in [0.05, 0.025, 0.0125] {
            let a = square(Vec3::ZERO, Vec3::X, Vec3::Y, h);
            let b = square(Vec3::new(0.3, 0.2, 0.5), (Vec3::Y + Vec3::Z).normalize(), Vec3::X, h);
            let (ma, mb) = (Moments::new(&a), Moments::new(&b));
            let r = reference_aff(&a, &b, 24);
            let e = (moment_pair(&ma, &mb) - r).abs() / r;
            let e1 = (centroid_pair(&ma, &mb) - r).abs() / r;
            assert!(e < e1 / 50.0, "h {h}: moment {e:.1e} vs centroid {e1:.1e}");
            if let Some(p) = prev {
                assert!(p / e > 12.0 && p / e < 20.0, "h {h}: ratio {}", p / e);
            }
            prev = Some(e);
            // symmetric in its arguments
            assert!((moment_pair(&ma, &mb) - moment_pair(&mb, &ma)).abs() <= 1e-14 * r);
        }
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

    /// Prints the moment rule's calibration rows for `quadrature::MOMENT_ERRS`: the same
    /// random pairs (same seed and generator) as `calibrate_far_field`. The reference is a
    /// compensated Gauss rule of lower order than there (the moment rule's errors are far
    /// larger than the Gauss rules'), and its uncertainty (difference to a lower order) is
    /// added to each error. Rows in parallel.
    /// Run: cargo test --release -p nusselt-core calibrate_moment_rule -- --ignored --nocapture
    #[test]
    #[ignore]
    fn calibrate_moment_rule() {
        use rayon::prelude::*;
        let seps = crate::quadrature::FAR_SEPS;
        let samples: usize = std::env::var("NUSSELT_CAL_SAMPLES").ok().and_then(|s| s.parse().ok()).unwrap_or(300);
        let mut rng = Rng(2024);
        let pairs: Vec<Vec<(Polygon, Polygon)>> =
            seps.iter().map(|&s| (0..samples).map(|_| random_far_pair(&mut rng, s)).collect()).collect();
        let rows: Vec<(f64, f64)> = seps
            .par_iter()
            .zip(&pairs)
            .map(|(&s, pairs)| {
                let (hi, lo) = if s < 2.0 { (24, 20) } else { (20, 16) };
                let (mut worst, mut unc_max) = (0.0f64, 0.0f64);
                for (a, b) in pairs {
                    let r = reference_aff(a, b, hi);
                    let unc = (r - reference_aff(a, b, lo)).abs() / r;
                    unc_max = unc_max.max(unc);
                    worst = worst.max((moment_pair(&Moments::new(a), &Moments::new(b)) - r).abs() / r + unc);
                }
                (worst, unc_max)
            })
            .collect();
        println!("const MOMENT_ERRS: &[f64] = &[");
        for (s, (worst, unc)) in seps.iter().zip(rows) {
            println!("    {worst:.1e}, // s = {s}, reference uncertainty {unc:.1e}");
        }
        println!("];");
    }
}
