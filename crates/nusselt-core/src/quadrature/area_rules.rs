//! Area rules on polygons: Σ w_k f(x_k) ≈ ∫_P f dA, from the 1-D rules of [`super::gauss`].

use super::gauss::{check_order, gauss_jacobi10, gauss_legendre, MAX_ORDER};
use crate::error::Result;
use crate::geometry::{Polygon, Vec3};

/// Quadrature points and weights on a polygon: Σ w_k f(x_k) ≈ ∫_P f dA, Σ w_k = area.
///
/// * Convex quadrilateral: order x order tensor Gauss-Legendre through the bilinear map
///   x(u,v) with Jacobian n·(x_u × x_v) (linear in u and v for a planar quad). Exact for
///   polynomials of degree 2·order - 1 on parallelograms, 2·order - 2 on general convex quads
///   (order 1 is the area centroid with the area as weight: exact for degree 1).
/// * Triangle: collapsed (Duffy / Stroud conical product) map x = p0 + u e1 + (1 - u) v e2,
///   Jacobian 2A(1 - u), with Gauss-Jacobi(1,0) in u and Gauss-Legendre in v: order² points,
///   all inside, all weights positive, exact for total degree 2·order - 1.
/// * Any other polygon (and concave quads): the triangle rule on each triangle of
///   [`Polygon::triangulate`].
#[derive(Debug, Clone, PartialEq)]
pub struct AreaRule {
    pub points: Vec<Vec3>,
    pub weights: Vec<f64>,
}

impl AreaRule {
    /// Panics if `order` is outside 1..=64 (a caller error); see [`AreaRule::try_new`].
    pub fn new(poly: &Polygon, order: usize) -> AreaRule {
        assert!((1..=MAX_ORDER).contains(&order), "AreaRule: order {order} is outside 1..={MAX_ORDER}");
        let v = poly.vertices();
        let n = poly.normal();
        let mut rule = AreaRule { points: Vec::new(), weights: Vec::new() };
        if v.len() == 4 && poly.is_strictly_convex() {
            // strictly convex: the bilinear map is one-to-one
            rule.push_quad(v, n, order);
        } else if v.len() == 3 {
            rule.push_triangle(v[0], v[1], v[2], n, order);
        } else {
            for [i, j, k] in poly.triangulate() {
                rule.push_triangle(v[i], v[j], v[k], n, order);
            }
        }
        rule
    }

    /// Checked [`AreaRule::new`].
    pub fn try_new(poly: &Polygon, order: usize) -> Result<AreaRule> {
        check_order(order, "area rule order")?;
        Ok(AreaRule::new(poly, order))
    }

    pub fn len(&self) -> usize {
        self.points.len()
    }

    pub fn is_empty(&self) -> bool {
        self.points.is_empty()
    }

    fn push_quad(&mut self, v: &[Vec3], n: Vec3, order: usize) {
        if order == 1 {
            // The bilinear map's centre is the vertex mean, not the area centroid, so the
            // one-point tensor rule would be exact for constants only: use the centroid.
            let (a1, a2) = ((v[1] - v[0]).cross(v[2] - v[0]).dot(n), (v[2] - v[0]).cross(v[3] - v[0]).dot(n));
            let c = ((v[0] + v[1] + v[2]) * a1 + (v[0] + v[2] + v[3]) * a2) / (3.0 * (a1 + a2));
            self.points.push(c);
            self.weights.push(0.5 * (a1 + a2));
            return;
        }
        let g = gauss_legendre(order);
        self.points.reserve(order * order);
        self.weights.reserve(order * order);
        for &(u, wu) in g {
            for &(t, wt) in g {
                let x =
                    v[0] * ((1.0 - u) * (1.0 - t)) + v[1] * (u * (1.0 - t)) + v[2] * (u * t) + v[3] * ((1.0 - u) * t);
                let xu = (v[1] - v[0]) * (1.0 - t) + (v[2] - v[3]) * t;
                let xt = (v[3] - v[0]) * (1.0 - u) + (v[2] - v[1]) * u;
                self.points.push(x);
                self.weights.push(wu * wt * xu.cross(xt).dot(n));
            }
        }
    }

    fn push_triangle(&mut self, p0: Vec3, p1: Vec3, p2: Vec3, n: Vec3, order: usize) {
        let twice_area = (p1 - p0).cross(p2 - p0).dot(n);
        if !(twice_area > 0.0) {
            return; // collinear remnant of a triangulation: no area
        }
        for (x, w) in triangle_rule(p0, p1, p2, twice_area, order) {
            self.points.push(x);
            self.weights.push(w);
        }
    }
}

/// The triangle rule of [`AreaRule`] (collapsed Gauss-Jacobi(1,0) x Gauss-Legendre, order^2
/// points) on the triangle p0 p1 p2 whose twice area the caller gives (signed for signed fans;
/// exact quarters for midpoint children, where recomputing it would add rounding).
pub(crate) fn triangle_rule(
    p0: Vec3,
    p1: Vec3,
    p2: Vec3,
    twice_area: f64,
    order: usize,
) -> impl Iterator<Item = (Vec3, f64)> {
    let (gj, gl) = (gauss_jacobi10(order), gauss_legendre(order));
    let (e1, e2) = (p1 - p0, p2 - p0);
    gj.iter().flat_map(move |&(u, wu)| {
        gl.iter().map(move |&(t, wt)| (p0 + e1 * u + e2 * ((1.0 - u) * t), twice_area * wu * wt))
    })
}

/// The Gauss area rule of [`AreaRule`] of order k (clamped to 1..=64) on `poly` with weights
/// summing to 1: source points for the row methods.
pub fn polygon_gauss_points(poly: &Polygon, k: usize, out: &mut Vec<(Vec3, f64)>) {
    out.clear();
    let rule = AreaRule::new(poly, k.clamp(1, MAX_ORDER));
    let total = poly.area();
    out.extend(rule.points.iter().zip(&rule.weights).map(|(&x, &w)| (x, w / total)));
}

#[cfg(test)]
pub(crate) mod tests {
    use super::*;
    use crate::error::Error;
    use crate::geometry::tangent_frame;

    /// Small deterministic generator (splitmix64) for the random geometries of the tests.
    pub(crate) struct Rng(pub u64);
    impl Rng {
        pub fn next_u64(&mut self) -> u64 {
            self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
            let mut z = self.0;
            z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
            z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
            z ^ (z >> 31)
        }
        pub fn unit(&mut self) -> f64 {
            (self.next_u64() >> 11) as f64 / (1u64 << 53) as f64
        }
        pub fn range(&mut self, lo: f64, hi: f64) -> f64 {
            lo + (hi - lo) * self.unit()
        }
        pub fn dir(&mut self) -> Vec3 {
            loop {
                let v = Vec3::new(self.range(-1., 1.), self.range(-1., 1.), self.range(-1., 1.));
                let l = v.length();
                if l > 0.1 && l <= 1.0 {
                    return v / l;
                }
            }
        }
    }

    #[test]
    fn bad_orders_are_errors() {
        for n in [0, 65, 1_000_000_000] {
            let p = Polygon::new(vec![Vec3::ZERO, Vec3::X, Vec3::Y]).unwrap();
            assert!(matches!(AreaRule::try_new(&p, n), Err(Error::InvalidArgument(_))));
        }
    }

    /// ∫_P x^a y^b dA in the polygon's own plane coordinates, by Green's theorem
    /// ∫_P x^a y^b dA = ∮ x^(a+1) y^b / (a + 1) dy, each edge integrated exactly by 1-D Gauss.
    fn green_moment(p: &Polygon, a: i32, b: i32) -> f64 {
        let (t, s) = tangent_frame(p.normal());
        let o = p.centroid();
        let v = p.vertices();
        let g = gauss_legendre(((a + b) as usize / 2 + 2).min(MAX_ORDER));
        let mut sum = 0.0;
        for i in 0..v.len() {
            let (p0, p1) = (v[i] - o, v[(i + 1) % v.len()] - o);
            let (x0, y0, x1, y1) = (p0.dot(t), p0.dot(s), p1.dot(t), p1.dot(s));
            for &(u, w) in g {
                let (x, y) = (x0 + u * (x1 - x0), y0 + u * (y1 - y0));
                sum += w * x.powi(a + 1) * y.powi(b) / (a + 1) as f64 * (y1 - y0);
            }
        }
        sum
    }

    fn rule_moment(p: &Polygon, r: &AreaRule, a: i32, b: i32) -> f64 {
        let (t, s) = tangent_frame(p.normal());
        let o = p.centroid();
        r.points.iter().zip(&r.weights).map(|(x, w)| w * (*x - o).dot(t).powi(a) * (*x - o).dot(s).powi(b)).sum()
    }

    fn placed(v2: &[[f64; 2]], rng: &mut Rng) -> Polygon {
        let n = rng.dir();
        let (t, s) = tangent_frame(n);
        let o = Vec3::new(rng.range(-3., 3.), rng.range(-3., 3.), rng.range(-3., 3.));
        Polygon::new(v2.iter().map(|q| o + t * q[0] + s * q[1]).collect()).unwrap()
    }

    #[test]
    fn area_rules_integrate_polynomials_exactly() {
        let mut rng = Rng(7);
        let shapes: Vec<(Vec<[f64; 2]>, usize)> = vec![
            // (outline, exact total degree = 2 order - d) with d = 1 (triangles, parallelograms),
            // 2 (general convex quads and triangulated polygons: same as triangles, d = 1)
            (vec![[0., 0.], [1.3, 0.2], [0.4, 0.9]], 1),
            (vec![[0., 0.], [2., 0.], [2.5, 1.], [0.5, 1.]], 1),
            (vec![[0., 0.], [2., 0.3], [1.7, 1.4], [-0.2, 0.8]], 2), // (order 1: degree 1, below)
            (vec![[0., 0.], [2., 0.], [1., 0.4], [0.9, 2.]], 1),     // concave quad: triangulated
            (vec![[0., 0.], [2., 0.], [2., 1.], [1., 1.], [1., 2.], [0., 2.]], 1), // L shape
            (vec![[0., 0.], [1., -0.3], [1.8, 0.4], [1.2, 1.3], [0.1, 1.0]], 1),
        ];
        for (v2, defect) in &shapes {
            let p = placed(v2, &mut rng);
            for order in [1usize, 2, 3, 5, 8] {
                let r = AreaRule::new(&p, order);
                let wsum: f64 = r.weights.iter().sum();
                assert!((wsum - p.area()).abs() <= 1e-13 * p.area(), "weights sum {wsum} vs area {}", p.area());
                assert!(r.weights.iter().all(|&w| w > 0.0));
                assert!(r
                    .points
                    .iter()
                    .all(|x| ((*x - p.centroid()).dot(p.normal())).abs() < 1e-12 * (1.0 + x.length())));
                let deg = if order == 1 { 1 } else { 2 * order as i32 - *defect as i32 };
                for a in 0..=deg {
                    for b in 0..=deg - a {
                        let exact = green_moment(&p, a, b);
                        let q = rule_moment(&p, &r, a, b);
                        let scale = rule_moment(&p, &r, 0, 0) * (p.radius()).powi(a + b);
                        assert!((q - exact).abs() <= 1e-12 * scale, "order {order} x^{a} y^{b}: {q} vs {exact}");
                    }
                }
            }
        }
    }

    #[test]
    fn gauss_points_have_unit_weight_and_polygon_moments() {
        // skewed convex quad and concave L: weights sum to 1, first moments give the centroid,
        // and the L's mean of x^2 is that of its three unit squares
        let quad = Polygon::new(vec![
            Vec3::new(0., 0., 0.),
            Vec3::new(2., 0.2, 0.),
            Vec3::new(1.7, 1.5, 0.),
            Vec3::new(0.1, 1., 0.),
        ])
        .unwrap();
        let l = Polygon::new(crate::geometry::tests::ell()).unwrap();
        let mut pts = Vec::new();
        for p in [&quad, &l] {
            for k in 1..=5 {
                polygon_gauss_points(p, k, &mut pts);
                let ws: f64 = pts.iter().map(|x| x.1).sum();
                assert!((ws - 1.0).abs() < 1e-14, "{ws}");
                let c: Vec3 = pts.iter().map(|x| x.0 * x.1).sum();
                if k >= 2 {
                    assert!((c - p.centroid()).length() < 1e-13, "k {k}: {c} vs {}", p.centroid());
                }
            }
        }
        polygon_gauss_points(&l, 3, &mut pts);
        let m2: f64 = pts.iter().map(|x| x.0.x * x.0.x * x.1).sum();
        let exact = (1.0 / 3.0 + 7.0 / 3.0 + 1.0 / 3.0) / 3.0; // int x^2 over the 3 unit squares / 3
        assert!((m2 - exact).abs() < 1e-14, "{m2} vs {exact}");
    }
}
