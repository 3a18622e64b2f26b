//! Exact polygon-to-polygon view factor by the double contour integral (algorithms.md 1.2),
//! each edge pair in closed form (Narayanaswamy 2015, algorithms.md 4.2).
//!
//!   A_a F_ab = (1/4 pi) sum_{edges i of a, j of b} (d_i . d_j) int_i int_j ln |x - y|^2
//!
//! Valid when each polygon lies in the other's front half-space (clip first) and nothing is
//! in between.

use crate::geometry::{clip_pair, Polygon, Vec3};
use crate::special::{gauss_legendre, im_li2};
use std::f64::consts::PI;
use std::sync::OnceLock;

/// Below this relative distance between the edge lines, D is treated as exactly 0
/// (intersecting or touching lines; the dilogarithm term then vanishes).
const D_ZERO_REL: f64 = 1e-12;
/// Below this sin(angle) the edges are treated as parallel.
const PARALLEL_SIN: f64 = 1e-14;
/// When the closest-approach points of the two lines lie farther than this many edge lengths
/// from the edges, the closed form (written about those points) cancels catastrophically
/// (error ~ eps (X/L)^2); the edge pair then goes through the single-line form instead.
const FAR_ORIGIN: f64 = 4.0;
/// Gauss-Legendre nodes per panel of the single-line form.
const LINE_NODES: usize = 16;

fn line_rule() -> &'static (Vec<f64>, Vec<f64>) {
    static RULE: OnceLock<(Vec<f64>, Vec<f64>)> = OnceLock::new();
    RULE.get_or_init(|| gauss_legendre(LINE_NODES))
}

/// (u . v) int_0^{|p1-p0|} int_0^{|q1-q0|} ln |x(t) - y(tau)|^2 dtau dt for the segments
/// x(t) = p0 + t u and y(tau) = q0 + tau v (u, v unit): one edge pair's share of the double
/// contour integral. Exact in every configuration: skew, parallel, intersecting or touching
/// lines (D = 0: edges sharing a vertex, crossing edges), collinear or overlapping edges, shared
/// edges; 0 for perpendicular edges. No vertex nudging. NaN for non-finite input; 0 when a
/// segment has zero length.
///
/// Method, with s, l measured along the edges from the closest points O_s, O_l of the two
/// lines, D their distance and alpha the angle between the edges:
///   Q(s, l) = s^2 + l^2 - 2 s l cos(alpha) + D^2 = |x - y|^2,
/// and with an antiderivative F (d^2F/ds dl = ln Q) the integral is the four-corner sum
/// cos(alpha) [F]_{s_i..s_j, l_p..l_q}. Narayanaswamy's f (algorithms.md 4.2) satisfies
/// d^2 f/ds dl = -(ln Q + 2) (checked numerically), so here F = -f - 2 s l:
///   F = (s l - cos(alpha)(s^2+l^2)/2) ln Q - s h_s atan2(h_s, l - s cos) - l h_l atan2(h_l, s - l cos)
///       - 3 s l - (D^2 / (2 sin)) [ImLi2(w_s/p_l, alpha) + ImLi2(p_l/w_s, alpha)
///                                   - 2 ImLi2((w_s - 2s)/p_l, pi - alpha)],
///   h_s = sqrt(s^2 sin^2 + D^2), w_s = s + sqrt(s^2 + D^2/sin^2), p_l = l + sqrt(l^2 + D^2/sin^2).
/// (The constant offset is irrelevant for closed polygons, where sum (d_i.d_j)|E_i||E_j| = 0,
/// but this function returns the true integral.) D = 0 drops the dilog term. Parallel edges use
/// the parallel antiderivative -f_par - 2 s l with
///   f_par = ((s-l)^2 - D^2)/2 ln((s-l)^2 + D^2) - 2 (s-l) D acos((s-l)/sqrt((s-l)^2+D^2)) + s l.
/// When O_s, O_l are far from the edges (nearly parallel lines, or far-apart edges), the corner
/// terms grow like X^2 and cancel; those pairs use the single-line form instead: the inner
/// integral in closed form (Mitalas & Stephenson; View3D `V1LIpart`, algorithms.md 4.3),
///   int ln |x - y|^2 dtau = [m ln(m^2 + g^2) - 2m + 2g atan(m/g)]_{m0}^{m1},
/// m_k = (q_k - x).v, g = |(x - q0) x v|, and the outer integral by Gauss-Legendre panels
/// bisected until every complex singularity of the integrand (x(t) meeting an endpoint of the
/// other edge, or g = 0) is at least a panel length away: smooth there, so 16 nodes per panel
/// reach double precision.
pub fn edge_pair_log_integral(p0: Vec3, p1: Vec3, q0: Vec3, q1: Vec3) -> f64 {
    if !(p0.is_finite() && p1.is_finite() && q0.is_finite() && q1.is_finite()) {
        return f64::NAN;
    }
    let (ea, eb) = (p1 - p0, q1 - q0);
    let (la, lb) = (ea.length(), eb.length());
    if la == 0.0 || lb == 0.0 {
        return 0.0;
    }
    let (u, v) = (ea / la, eb / lb);
    let b = u.dot(v);
    if b == 0.0 {
        return 0.0;
    }
    let lmax = la.max(lb);
    let cr = u.cross(v);
    let sin = cr.length();
    let w = p0 - q0;
    if sin <= PARALLEL_SIN {
        return parallel_pair(p0, la, u, q0, q1, lmax);
    }
    // Closest points of the two lines: p0 + s* u and q0 + l* v.
    let den = sin * sin;
    let (dd, e) = (u.dot(w), v.dot(w));
    let s_star = (b * e - dd) / den;
    let l_star = (e - b * dd) / den;
    let far = s_star.abs().max((la - s_star).abs()).max(l_star.abs()).max((lb - l_star).abs());
    if far > FAR_ORIGIN * lmax {
        b * single_line(p0, la, u, q0, q1, v, s_star, sin, w)
    } else {
        closed_form(la, lb, b, sin, s_star, l_star, (w.dot(cr) / sin).abs(), lmax)
    }
}

/// The closed-form four-corner sum for skew lines (see [`edge_pair_log_integral`]).
#[allow(clippy::too_many_arguments)]
fn closed_form(la: f64, lb: f64, b: f64, sin: f64, s_star: f64, l_star: f64, d: f64, lmax: f64) -> f64 {
    // d: distance between the lines, from the projection on the common normal (no cancellation).
    let d = if d < D_ZERO_REL * lmax { 0.0 } else { d };
    // Orient s-hat and l-hat toward the farther endpoint (as in the reference implementation).
    let sa = if s_star.abs() < (la - s_star).abs() { 1.0 } else { -1.0 };
    let sb = if l_star.abs() < (lb - l_star).abs() { 1.0 } else { -1.0 };
    let (si, sj) = (-s_star * sa, (la - s_star) * sa);
    let (lp, lq) = (-l_star * sb, (lb - l_star) * sb);
    let cos = sa * sb * b;
    let alpha = sin.atan2(cos);
    let f = |s: f64, l: f64| skew_antiderivative(s, l, cos, sin, alpha, d);
    cos * (f(sj, lq) - f(si, lq) - f(sj, lp) + f(si, lp))
}

/// F(s, l) of [`edge_pair_log_integral`] for skew (or intersecting, d = 0) lines.
fn skew_antiderivative(s: f64, l: f64, cos: f64, sin: f64, alpha: f64, d: f64) -> f64 {
    // Q = (l - s cos)^2 + s^2 sin^2 + D^2: a sum of squares, no cancellation.
    let m = l - s * cos;
    let q = m * m + s * s * sin * sin + d * d;
    let poly = s * l - 0.5 * cos * (s * s + l * l);
    let mut f = if q > 0.0 { poly * q.ln() } else { 0.0 };
    let hs = (s * sin).hypot(d);
    let hl = (l * sin).hypot(d);
    if hs > 0.0 {
        f -= s * hs * hs.atan2(m);
    }
    if hl > 0.0 {
        f -= l * hl * hl.atan2(s - l * cos);
    }
    f -= 3.0 * s * l;
    if d > 0.0 {
        let k = d / sin; // D / sin(alpha)
        let k2 = k * k;
        let os = s.hypot(k);
        let ol = l.hypot(k);
        // s + sqrt(s^2 + k^2) and sqrt(s^2 + k^2) - s without cancellation
        let ws = if s >= 0.0 { s + os } else { k2 / (os - s) };
        let ws2 = if s <= 0.0 { os - s } else { k2 / (os + s) };
        let pl = if l >= 0.0 { l + ol } else { k2 / (ol - l) };
        let bracket = im_li2(ws / pl, alpha) + im_li2(pl / ws, alpha) - 2.0 * im_li2(ws2 / pl, PI - alpha);
        f -= 0.5 * d * k * bracket;
    }
    f
}

/// Parallel (or antiparallel, collinear, overlapping) edges: both parameterised along u from
/// the foot of p0 on line b; the orientation of edge b is carried by the order of its limits.
fn parallel_pair(p0: Vec3, la: f64, u: Vec3, q0: Vec3, q1: Vec3, lmax: f64) -> f64 {
    let lp = (q0 - p0).dot(u);
    let lq = (q1 - p0).dot(u);
    // Distance between the lines: mean perpendicular offset of edge b's endpoints from line a.
    let d0 = (q0 - p0) - lp * u;
    let d1 = (q1 - p0) - lq * u;
    let mut d = 0.5 * (d0.length() + d1.length());
    if d < D_ZERO_REL * lmax {
        d = 0.0;
    }
    let f = |s: f64, l: f64| {
        let x = s - l;
        let r2 = x * x + d * d;
        let mut g = if r2 > 0.0 { 0.5 * (x * x - d * d) * r2.ln() } else { 0.0 };
        if d > 0.0 {
            // acos(x / r) = atan2(D, x) for D > 0
            g -= 2.0 * x * d * d.atan2(x);
        }
        -g - 3.0 * s * l
    };
    f(la, lq) - f(0.0, lq) - f(la, lp) + f(0.0, lp)
}

/// int_0^la Phi(t) dt with Phi(t) = int_0^lb ln|p0 + t u - q0 - tau v|^2 dtau (closed form), by
/// Gauss-Legendre panels refined around the integrand's complex singularities.
#[allow(clippy::too_many_arguments)]
fn single_line(p0: Vec3, la: f64, u: Vec3, q0: Vec3, q1: Vec3, v: Vec3, s_star: f64, sin: f64, w: Vec3) -> f64 {
    // Singularities (real part along edge a, distance from the real axis).
    let mut sing = [(0.0, 0.0); 3];
    let mut ns = 0;
    for q in [q0, q1] {
        let r = q - p0;
        let t = r.dot(u);
        sing[ns] = (t, (r - t * u).length());
        ns += 1;
    }
    if sin > 0.0 {
        let d = (w.dot(u.cross(v)) / sin).abs();
        sing[ns] = (s_star, d / sin);
        ns += 1;
    }
    let sing = &sing[..ns];
    let phi = |t: f64| {
        let x = p0 + t * u;
        let r0 = q0 - x;
        let g = r0.cross(v).length();
        let mut acc = 0.0;
        for (k, q) in [q0, q1].into_iter().enumerate() {
            let r = q - x;
            let m = r.dot(v);
            let d2 = r.length_squared();
            let mut psi = -2.0 * m;
            if d2 > 0.0 {
                psi += m * d2.ln();
            }
            if g > 0.0 {
                psi += 2.0 * g * m.atan2(g);
            }
            acc += if k == 0 { -psi } else { psi };
        }
        acc
    };
    let (x, wts) = line_rule();
    let mut total = 0.0;
    // Explicit stack of panels (a, b, depth).
    let mut stack: Vec<(f64, f64, u32)> = vec![(0.0, la, 0)];
    while let Some((a, b, depth)) = stack.pop() {
        let len = b - a;
        let near = sing.iter().any(|&(t, e)| {
            let dx = if t < a { a - t } else if t > b { t - b } else { 0.0 };
            dx.hypot(e) < len
        });
        if near && depth < 60 {
            let m = 0.5 * (a + b);
            stack.push((a, m, depth + 1));
            stack.push((m, b, depth + 1));
            continue;
        }
        let (c, h) = (0.5 * (a + b), 0.5 * len);
        let mut acc = 0.0;
        for k in 0..x.len() {
            acc += wts[k] * phi(c + h * x[k]);
        }
        total += h * acc;
    }
    total
}

/// A_a F_ab (= A_b F_ba) for two polygons with nothing in between, exact: the double contour
/// integral (algorithms.md 1.2) over the parts of each polygon in front of the other
/// (`geometry::clip_pair`; 0 when they exchange nothing), summed over all edge pairs with
/// [`edge_pair_log_integral`]. Coordinates are shifted to a's centroid and divided by the pair's
/// size before summing (limits cancellation; exact scale invariance), and the result is
/// multiplied back by size^2. With both polygons counter-clockwise about normals facing each
/// other the contour sum is positive (checked against Howell C-11 in the tests), so
/// A_a F_ab = sum / (4 pi). Roundoff-level negatives are clamped to 0.
pub fn polygon_pair(a: &Polygon, b: &Polygon) -> f64 {
    let Some((ca, cb)) = clip_pair(a, b) else {
        return 0.0;
    };
    let o = a.centroid();
    let size = (a.radius() + b.radius()).max(a.centroid().distance(b.centroid()));
    let inv = 1.0 / size;
    let pa: Vec<Vec3> = ca.iter().map(|p| (*p - o) * inv).collect();
    let pb: Vec<Vec3> = cb.iter().map(|p| (*p - o) * inv).collect();
    let (na, nb) = (pa.len(), pb.len());
    let mut sum = 0.0;
    let mut mag = 0.0;
    for i in 0..na {
        let (a0, a1) = (pa[i], pa[(i + 1) % na]);
        for j in 0..nb {
            let t = edge_pair_log_integral(a0, a1, pb[j], pb[(j + 1) % nb]);
            sum += t;
            mag += t.abs();
        }
    }
    let v = sum / (4.0 * PI);
    let v = if v < 0.0 && v > -1e-13 * mag { 0.0 } else { v };
    v * size * size
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::analytic::closed_forms as cf;

    /// Both evaluation routes of a skew edge pair, forced (closed form, single-line form).
    fn routes(p0: Vec3, p1: Vec3, q0: Vec3, q1: Vec3) -> (f64, f64) {
        let (ea, eb) = (p1 - p0, q1 - q0);
        let (la, lb) = (ea.length(), eb.length());
        let (u, v) = (ea / la, eb / lb);
        let b = u.dot(v);
        let cr = u.cross(v);
        let sin = cr.length();
        let w = p0 - q0;
        let den = sin * sin;
        let (dd, e) = (u.dot(w), v.dot(w));
        let s_star = (b * e - dd) / den;
        let l_star = (e - b * dd) / den;
        let closed = closed_form(la, lb, b, sin, s_star, l_star, (w.dot(cr) / sin).abs(), la.max(lb));
        let line = b * single_line(p0, la, u, q0, q1, v, s_star, sin, w);
        (closed, line)
    }

    /// (u.v) int int ln|x-y|^2 by a tensor Gauss-Legendre rule (separated segments only).
    fn brute_edge(p0: Vec3, p1: Vec3, q0: Vec3, q1: Vec3, n: usize) -> f64 {
        let (x, w) = gauss_legendre(n);
        let (la, lb) = ((p1 - p0).length(), (q1 - q0).length());
        let b = (p1 - p0).dot(q1 - q0) / (la * lb);
        let mut acc = 0.0;
        for i in 0..n {
            let xa = p0 + (p1 - p0) * (0.5 * (1.0 + x[i]));
            for j in 0..n {
                let yb = q0 + (q1 - q0) * (0.5 * (1.0 + x[j]));
                acc += w[i] * w[j] * (xa - yb).length_squared().ln();
            }
        }
        b * 0.25 * la * lb * acc
    }

    fn poly(v: &[[f64; 3]]) -> Polygon {
        Polygon::new(v.iter().map(|p| Vec3::from_array(*p)).collect()).unwrap()
    }

    /// Rectangle o, o+e1, o+e1+e2, o+e2 (front normal e1 x e2).
    fn rect(o: Vec3, e1: Vec3, e2: Vec3) -> Polygon {
        Polygon::new(vec![o, o + e1, o + e1 + e2, o + e2]).unwrap()
    }

    fn f_ab(a: &Polygon, b: &Polygon) -> f64 {
        polygon_pair(a, b) / a.area()
    }

    #[test]
    fn smoke_sign_c11() {
        let a = rect(Vec3::ZERO, Vec3::X, Vec3::Y);
        let b = rect(Vec3::Z, Vec3::Y, Vec3::X);
        let f = f_ab(&a, &b);
        let want = cf::parallel_rectangles(1.0, 1.0, 1.0).unwrap();
        assert!((f - want).abs() < 1e-13, "{f} {want}");
        let _ = (routes, brute_edge, poly);
    }
}
