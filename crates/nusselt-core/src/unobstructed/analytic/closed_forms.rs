//! Named closed-form view factors (docs/algorithms.md §8.2; Howell, *A Catalog of Radiation Heat
//! Transfer Configuration Factors*, 3rd ed.). Each is checked in the tests against a
//! numerical integration written there. Every length must be finite and positive (offsets and
//! coordinates finite); otherwise the result is `Err(Error::InvalidArgument)`.

use crate::error::{Error, Result};
use std::f64::consts::PI;

fn positive(name: &str, v: f64) -> Result<f64> {
    if v.is_finite() && v > 0.0 {
        Ok(v)
    } else {
        Err(Error::InvalidArgument(format!("{name} must be a finite positive length, got {v}")))
    }
}

fn finite(name: &str, v: f64) -> Result<f64> {
    if v.is_finite() {
        Ok(v)
    } else {
        Err(Error::InvalidArgument(format!("{name} must be finite, got {v}")))
    }
}

/// Checks the coordinate interval `name` = [lo, hi]: finite, lo < hi.
fn interval(name: &str, [lo, hi]: [f64; 2]) -> Result<()> {
    finite(name, lo)?;
    finite(name, hi)?;
    if hi > lo {
        Ok(())
    } else {
        Err(Error::InvalidArgument(format!("need {name} = [lo, hi] with lo < hi, got [{lo}, {hi}]")))
    }
}

/// Differential area parallel to a coaxial disc of radius `r` at distance `h` (facing it):
/// F = r^2 / (h^2 + r^2). (docs/algorithms.md §1.3 and 8.2 row 1.)
pub fn disk_coaxial(h: f64, r: f64) -> Result<f64> {
    let (h, r) = (positive("h", h)?, positive("r", r)?);
    Ok(r * r / (h * h + r * r))
}

/// Differential area parallel to a disc of radius `r` at distance `h`, its normal passing a
/// distance `a >= 0` from the disc's centre (8.2 row 2): with H = h/a, R = r/a, Z = 1 + H^2 + R^2,
/// F = (1/2)[1 - (Z - 2R^2)/sqrt(Z^2 - 4R^2)], evaluated in the equivalent dimensional form
/// F = (1/2)[1 - (a^2 + h^2 - r^2)/sqrt((a^2 + h^2 + r^2)^2 - 4 a^2 r^2)], which is also valid at
/// a = 0 (the coaxial case).
pub fn disk_offset(h: f64, r: f64, a: f64) -> Result<f64> {
    let (h, r) = (positive("h", h)?, positive("r", r)?);
    let a = finite("a", a)?;
    if a < 0.0 {
        return Err(Error::InvalidArgument(format!("offset a must be >= 0, got {a}")));
    }
    let (a2, h2, r2) = (a * a, h * h, r * r);
    // (z^2 - 4 a^2 r^2) = (a^2 + h^2 - r^2)^2 + 4 h^2 r^2 (> 0, no cancellation)
    let m = a2 + h2 - r2;
    let root = (m * m + 4.0 * h2 * r2).sqrt();
    // 1 - m/root written without cancellation when m ~ root
    let f = if m > 0.0 { 0.5 * (4.0 * h2 * r2) / (root * (root + m)) } else { 0.5 * (1.0 - m / root) };
    Ok(f)
}

/// Coaxial parallel discs, radius `r1` (emitter) to radius `r2`, separation `a` (Howell C-40/41;
/// 8.2 row 10): R1 = r1/a, R2 = r2/a, X = 1 + (1 + R2^2)/R1^2,
/// F12 = (1/2)[X - sqrt(X^2 - 4 (r2/r1)^2)] = 2 (r2/r1)^2 / (X + sqrt(X^2 - 4 (r2/r1)^2)).
pub fn coaxial_disks(r1: f64, r2: f64, a: f64) -> Result<f64> {
    let (r1, r2, a) = (positive("r1", r1)?, positive("r2", r2)?, positive("a", a)?);
    let (big_r1, big_r2) = (r1 / a, r2 / a);
    let x = 1.0 + (1.0 + big_r2 * big_r2) / (big_r1 * big_r1);
    let q = r2 / r1;
    Ok(2.0 * q * q / (x + (x * x - 4.0 * q * q).max(0.0).sqrt()))
}

/// Identical, parallel, directly opposed rectangles `a` x `b` at separation `c` (Howell C-11;
/// 8.2 row 6): X = a/c, Y = b/c,
/// F = 2/(pi X Y) [ ln sqrt((1+X^2)(1+Y^2)/(1+X^2+Y^2)) + X sqrt(1+Y^2) atan(X/sqrt(1+Y^2))
///                  + Y sqrt(1+X^2) atan(Y/sqrt(1+X^2)) - X atan X - Y atan Y ].
pub fn parallel_rectangles(a: f64, b: f64, c: f64) -> Result<f64> {
    let (a, b, c) = (positive("a", a)?, positive("b", b)?, positive("c", c)?);
    let (x, y) = (a / c, b / c);
    let (x2, y2) = (x * x, y * y);
    let sx = (1.0 + x2).sqrt();
    let sy = (1.0 + y2).sqrt();
    let t = 0.5 * (x2.ln_1p() + y2.ln_1p() - (x2 + y2).ln_1p()) + x * sy * (x / sy).atan() + y * sx * (y / sx).atan()
        - x * x.atan()
        - y * y.atan();
    Ok(2.0 / (PI * x * y) * t)
}

/// Perpendicular rectangles with a common edge of length `l`; emitter A1 = l x `w`, receiver
/// A2 = l x `h` (Howell C-14; 8.2 row 7): W = w/l, H = h/l,
/// F12 = 1/(pi W) [ W atan(1/W) + H atan(1/H) - sqrt(H^2+W^2) atan(1/sqrt(H^2+W^2))
///        + (1/4) ln{ (1+W^2)(1+H^2)/(1+W^2+H^2) [W^2(1+W^2+H^2)/((1+W^2)(W^2+H^2))]^(W^2)
///                    [H^2(1+H^2+W^2)/((1+H^2)(H^2+W^2))]^(H^2) } ].
/// The logarithm is expanded into a sum of logs (no overflow of the powers).
pub fn perpendicular_rectangles(l: f64, w: f64, h: f64) -> Result<f64> {
    let (l, w, h) = (positive("l", l)?, positive("w", w)?, positive("h", h)?);
    let (bw, bh) = (w / l, h / l);
    let (w2, h2) = (bw * bw, bh * bh);
    let s = (w2 + h2).sqrt();
    let ln_a = w2.ln_1p() + h2.ln_1p() - (w2 + h2).ln_1p();
    let ln_b = w2.ln() + (w2 + h2).ln_1p() - w2.ln_1p() - (w2 + h2).ln();
    let ln_c = h2.ln() + (w2 + h2).ln_1p() - h2.ln_1p() - (w2 + h2).ln();
    let t =
        bw * (1.0 / bw).atan() + bh * (1.0 / bh).atan() - s * (1.0 / s).atan() + 0.25 * (ln_a + w2 * ln_b + h2 * ln_c);
    Ok(t / (PI * bw))
}

/// Parallel, aligned rectangles in arbitrary position (Howell section C; Gross, Spindler &
/// Hahne 1981; 8.2 row 8). A1 = [x1, x2] x [y1, y2] in the plane z = 0 (facing +z), A2 =
/// [xi1, xi2] x [eta1, eta2] in the plane at height `z` > 0 (facing -z). F12 =
/// 1/((x2-x1)(y2-y1)) sum_{i,j,k,l} (-1)^(i+j+k+l) G(x_i, y_j, eta_k, xi_l) with
/// G = (1/2pi)[ (y-eta) sqrt((x-xi)^2+z^2) atan((y-eta)/sqrt((x-xi)^2+z^2))
///            + (x-xi) sqrt((y-eta)^2+z^2) atan((x-xi)/sqrt((y-eta)^2+z^2))
///            - (z^2/2) ln((x-xi)^2 + (y-eta)^2 + z^2) ].
pub fn parallel_rectangles_general(x: [f64; 2], y: [f64; 2], xi: [f64; 2], eta: [f64; 2], z: f64) -> Result<f64> {
    for (name, iv) in [("x", x), ("y", y), ("xi", xi), ("eta", eta)] {
        interval(name, iv)?;
    }
    let z = positive("z", z)?;
    let g = |x: f64, y: f64, eta: f64, xi: f64| {
        let (u, v) = (x - xi, y - eta);
        let su = (u * u + z * z).sqrt();
        let sv = (v * v + z * z).sqrt();
        (v * su * (v / su).atan() + u * sv * (u / sv).atan() - 0.5 * z * z * (u * u + v * v + z * z).ln()) / (2.0 * PI)
    };
    Ok(corner_sum(x, y, eta, xi, g) / ((x[1] - x[0]) * (y[1] - y[0])))
}

/// Σ (-1)^(i+j+k+l) g(x_i, y_j, eta_k, xi_l) over the 16 corners of two aligned rectangles'
/// coordinate intervals: the general rectangle formulas are this sum of a corner function.
fn corner_sum(x: [f64; 2], y: [f64; 2], eta: [f64; 2], xi: [f64; 2], g: impl Fn(f64, f64, f64, f64) -> f64) -> f64 {
    let mut sum = 0.0;
    for (i, x) in x.into_iter().enumerate() {
        for (j, y) in y.into_iter().enumerate() {
            for (k, eta) in eta.into_iter().enumerate() {
                for (m, xi) in xi.into_iter().enumerate() {
                    let sign = if (i + j + k + m) % 2 == 0 { 1.0 } else { -1.0 };
                    sum += sign * g(x, y, eta, xi);
                }
            }
        }
    }
    sum
}

/// Perpendicular rectangles in arbitrary aligned position with the common axis y (Howell
/// section C; 8.2 row 9). A1 = {(x, y, 0)}, x in [x1, x2], y in [y1, y2] (facing +z); A2 =
/// {(0, eta, xi)}, eta in [eta1, eta2], xi in [xi1, xi2] (facing +x); x1 >= 0 and xi1 >= 0.
/// F12 = 1/((x2-x1)(y2-y1)) sum (-1)^(i+j+k+l) G(x_i, y_j, eta_k, xi_l) with
/// G = (1/2pi)[ (y-eta) sqrt(x^2+xi^2) atan((y-eta)/sqrt(x^2+xi^2))
///            - (1/4)(x^2 + xi^2 - (y-eta)^2) ln(x^2 + xi^2 + (y-eta)^2) ],
/// terms with a zero argument taken as their limit 0.
pub fn perpendicular_rectangles_general(x: [f64; 2], y: [f64; 2], eta: [f64; 2], xi: [f64; 2]) -> Result<f64> {
    for (name, iv) in [("x", x), ("y", y), ("eta", eta), ("xi", xi)] {
        interval(name, iv)?;
    }
    if x[0] < 0.0 || xi[0] < 0.0 {
        return Err(Error::InvalidArgument(format!(
            "both rectangles must lie on the front side of the other (x1 >= 0 and xi1 >= 0), got {} and {}",
            x[0], xi[0]
        )));
    }
    let g = |x: f64, y: f64, eta: f64, xi: f64| {
        let v = y - eta;
        let s2 = x * x + xi * xi;
        let s = s2.sqrt();
        let a = if s > 0.0 { v * s * (v / s).atan() } else { 0.0 };
        let r2 = s2 + v * v;
        let b = if r2 > 0.0 { 0.25 * (s2 - v * v) * r2.ln() } else { 0.0 };
        (a - b) / (2.0 * PI)
    };
    Ok(corner_sum(x, y, eta, xi, g) / ((x[1] - x[0]) * (y[1] - y[0])))
}

/// Differential area parallel to a rectangle `a` x `b` whose corner lies on the element's
/// normal at distance `c` (8.2 row 3): A = a/c, B = b/c,
/// F = (1/2pi)[ A/sqrt(1+A^2) atan(B/sqrt(1+A^2)) + B/sqrt(1+B^2) atan(A/sqrt(1+B^2)) ].
pub fn point_rectangle_corner_parallel(a: f64, b: f64, c: f64) -> Result<f64> {
    let (a, b, c) = (positive("a", a)?, positive("b", b)?, positive("c", c)?);
    let (ba, bb) = (a / c, b / c);
    let sa = (1.0 + ba * ba).sqrt();
    let sb = (1.0 + bb * bb).sqrt();
    Ok((ba / sa * (bb / sa).atan() + bb / sb * (ba / sb).atan()) / (2.0 * PI))
}

/// Differential area perpendicular to a rectangle (8.2 row 4). The element lies in a plane
/// perpendicular to the rectangle that contains the rectangle's base edge (width `b`); the
/// element sits opposite one end of that edge at distance `c` from it; the rectangle's height
/// is `a`. In coordinates: element at the origin with normal +z; rectangle x in [0, b],
/// z in [0, a] in the plane y = c, facing -y. X = a/b, Y = c/b,
/// F = (1/2pi)[ atan(1/Y) - Y/sqrt(X^2+Y^2) atan(1/sqrt(X^2+Y^2)) ].
pub fn point_rectangle_corner_perpendicular(a: f64, b: f64, c: f64) -> Result<f64> {
    let (a, b, c) = (positive("a", a)?, positive("b", b)?, positive("c", c)?);
    let (x, y) = (a / b, c / b);
    let s = (x * x + y * y).sqrt();
    Ok(((1.0 / y).atan() - y / s * (1.0 / s).atan()) / (2.0 * PI))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::Vec3;
    use crate::quadrature::gauss::gauss_legendre_pm1 as gauss_legendre;
    use crate::unobstructed::analytic::lambert::point_polygon;

    /// Breakpoints on [a, b], graded geometrically (ratio 1/4, `levels` times) toward a and/or b.
    fn graded(a: f64, b: f64, toward_a: bool, toward_b: bool, levels: usize) -> Vec<f64> {
        let mut pts = vec![a, b];
        let half = 0.5 * (b - a);
        if toward_a || toward_b {
            pts.push(a + half);
        }
        let mut len = half;
        for _ in 0..levels {
            len *= 0.25;
            if toward_a {
                pts.push(a + len);
            }
            if toward_b {
                pts.push(b - len);
            }
        }
        pts.sort_by(f64::total_cmp);
        pts
    }

    /// Tensor Gauss-Legendre of f(u, v) over [u0, u1] x [v0, v1]. With `split` > 0 the panels are
    /// graded toward u = u0 and toward both ends of v (for the weak singularities of a point
    /// factor near a shared edge and its corners).
    fn quad2(f: &dyn Fn(f64, f64) -> f64, u: (f64, f64), v: (f64, f64), n: usize, split: usize) -> f64 {
        let (x, w) = gauss_legendre(n);
        let bu = graded(u.0, u.1, split > 0, false, split);
        let bv = graded(v.0, v.1, split > 0, split > 0, split);
        let mut acc = 0.0;
        for p in 0..bu.len() - 1 {
            let (a, b) = (bu[p], bu[p + 1]);
            for q in 0..bv.len() - 1 {
                let (c, d) = (bv[q], bv[q + 1]);
                for i in 0..n {
                    let uu = 0.5 * (a + b) + 0.5 * (b - a) * x[i];
                    for j in 0..n {
                        let vv = 0.5 * (c + d) + 0.5 * (d - c) * x[j];
                        acc += w[i] * w[j] * 0.25 * (b - a) * (d - c) * f(uu, vv);
                    }
                }
            }
        }
        acc
    }

    fn rect_xy(x: (f64, f64), y: (f64, f64), z: f64, up: bool) -> Vec<Vec3> {
        let mut v =
            vec![Vec3::new(x.0, y.0, z), Vec3::new(x.1, y.0, z), Vec3::new(x.1, y.1, z), Vec3::new(x.0, y.1, z)];
        if !up {
            v.reverse();
        }
        v
    }

    #[test]
    fn discs_against_quadrature() {
        // Point kernel h^2 / (pi (rho^2 + h^2)^2) over the disc in polar coordinates
        // (Gauss in rho, Gauss on two half-turns in phi), element offset a from the axis.
        let point_disc = |h: f64, r: f64, a: f64| {
            let f = |rho: f64, phi: f64| {
                let (x, y) = (rho * phi.cos() - a, rho * phi.sin());
                let d2 = x * x + y * y + h * h;
                rho * h * h / (PI * d2 * d2)
            };
            quad2(&f, (0.0, r), (0.0, PI), 40, 0) * 2.0
        };
        let f = disk_coaxial(2.0, 1.0).unwrap();
        assert!((f - 0.2).abs() < 1e-15);
        assert!((f - point_disc(2.0, 1.0, 0.0)).abs() < 1e-13);
        for (h, r, a) in [(1.2, 0.7, 0.9), (0.5, 1.0, 0.3), (1.0, 0.5, 3.0), (2.0, 1.0, 0.0)] {
            let g = disk_offset(h, r, a).unwrap();
            let q = point_disc(h, r, a);
            assert!((g - q).abs() < 1e-12 * q, "{h} {r} {a}: {g} {q}");
        }
        assert!((disk_offset(1.2, 0.7, 0.9).unwrap() - 0.138322227928).abs() < 1e-12);
        // C-40: F12 = (1/A1) int_{A1} F_{dA -> disc 2} dA, the inner factor by the offset formula
        // (itself checked above), the outer integral by Gauss in the radius.
        for (r1, r2, a) in [(1.0, 1.0, 3.0), (0.5, 0.8, 1.1), (0.2, 10.0, 1.0), (10.0, 2.0, 1.0)] {
            let (x, w) = gauss_legendre(60);
            let mut acc = 0.0;
            for k in 0..60 {
                let rho = 0.5 * r1 * (1.0 + x[k]);
                acc += 0.5 * r1 * w[k] * 2.0 * PI * rho * disk_offset(a, r2, rho).unwrap();
            }
            let q = acc / (PI * r1 * r1);
            let f = coaxial_disks(r1, r2, a).unwrap();
            assert!((f - q).abs() < 1e-12 * q, "{r1} {r2} {a}: {f} {q}");
        }
        assert!((coaxial_disks(1.0, 1.0, 3.0).unwrap() - (11.0 - 117f64.sqrt()) / 2.0).abs() < 1e-15);
    }

    /// F12 by integrating Lambert's point factor over the emitter rectangle in z = 0 (x range,
    /// y range), with optional grading toward x = x0.
    fn lambert_integral(x: (f64, f64), y: (f64, f64), receiver: &[Vec3], n: usize, split: usize) -> f64 {
        let f = |u: f64, v: f64| point_polygon(Vec3::new(u, v, 0.0), Vec3::Z, receiver);
        quad2(&f, x, y, n, split) / ((x.1 - x.0) * (y.1 - y.0))
    }

    #[test]
    fn parallel_rectangles_against_quadrature() {
        for (a, b, c) in [(1.0, 1.0, 1.0), (2.0, 4.0, 1.0), (0.3, 0.5, 2.0), (1.0, 3.0, 0.5)] {
            let f = parallel_rectangles(a, b, c).unwrap();
            let recv = rect_xy((0.0, a), (0.0, b), c, false);
            let q = lambert_integral((0.0, a), (0.0, b), &recv, 40, 0);
            assert!((f - q).abs() < 1e-12 * q, "{a} {b} {c}: {f} {q}");
        }
        // Fully independent: 4-D Gauss of the double area integral for the unit cube case.
        let (x, w) = gauss_legendre(24);
        let mut acc = 0.0;
        for i in 0..24 {
            for j in 0..24 {
                for k in 0..24 {
                    for l in 0..24 {
                        let (dx, dy) = (0.5 * (x[i] - x[k]), 0.5 * (x[j] - x[l]));
                        let r2 = dx * dx + dy * dy + 1.0;
                        acc += w[i] * w[j] * w[k] * w[l] / (16.0 * PI * r2 * r2);
                    }
                }
            }
        }
        assert!((parallel_rectangles(1.0, 1.0, 1.0).unwrap() - acc).abs() < 1e-12);
        assert!((parallel_rectangles(1.0, 1.0, 1.0).unwrap() - 0.199824895698387).abs() < 1e-14);
    }

    #[test]
    fn perpendicular_rectangles_against_quadrature() {
        // Shared edge along y at x = 0: emitter x in [0, w] (z = 0, +z), receiver z in [0, h]
        // in the plane x = 0 facing +x. The point factor is singular-ish at x -> 0: grade.
        for (l, w, h) in [(1.0, 1.0, 1.0), (1.0, 2.0, 0.5), (2.0, 0.3, 1.7)] {
            let f = perpendicular_rectangles(l, w, h).unwrap();
            let recv = vec![Vec3::new(0., 0., 0.), Vec3::new(0., l, 0.), Vec3::new(0., l, h), Vec3::new(0., 0., h)];
            // point_polygon returns 0 within 1e-12 (relative) of the receiver's plane, so the
            // strip x < x0 = 1e-10 w is added as x0 times the line integral at x0 (O(x0^2) error).
            let x0 = 1e-10 * w;
            let inner = |u: f64, v: f64| point_polygon(Vec3::new(u, v, 0.0), Vec3::Z, &recv);
            let body = quad2(&inner, (x0, w), (0.0, l), 20, 16);
            let strip = x0 * quad2(&|_u: f64, v: f64| inner(x0, v), (0.0, 1.0), (0.0, l), 20, 16);
            let q = (body + strip) / (w * l);
            assert!((f - q).abs() < 1e-12 * q, "{l} {w} {h}: {f} {q}");
        }
        assert!((perpendicular_rectangles(1.0, 1.0, 1.0).unwrap() - 0.200043776075403).abs() < 1e-14);
        assert!((perpendicular_rectangles(1.0, 2.0, 0.5).unwrap() - 0.078650270506).abs() < 1e-12);
    }

    #[test]
    fn general_rectangles_against_quadrature() {
        let f = parallel_rectangles_general([0.0, 1.0], [0.0, 2.0], [0.5, 2.0], [-0.5, 1.0], 0.7).unwrap();
        let recv = rect_xy((0.5, 2.0), (-0.5, 1.0), 0.7, false);
        let q = lambert_integral((0.0, 1.0), (0.0, 2.0), &recv, 60, 0);
        assert!((f - q).abs() < 1e-12 * q, "{f} {q}");
        assert!((f - 0.201845405433).abs() < 1e-12);

        let f = perpendicular_rectangles_general([0.3, 1.3], [0.0, 2.0], [0.5, 1.5], [0.2, 1.0]).unwrap();
        let recv =
            vec![Vec3::new(0., 0.5, 0.2), Vec3::new(0., 1.5, 0.2), Vec3::new(0., 1.5, 1.0), Vec3::new(0., 0.5, 1.0)];
        let q = lambert_integral((0.3, 1.3), (0.0, 2.0), &recv, 60, 0);
        assert!((f - q).abs() < 1e-12 * q, "{f} {q}");
        assert!((f - 0.072571586221).abs() < 1e-12);
        // touching (x1 = xi1 = 0, overlapping y): the zero-argument limits are exercised
        let f = perpendicular_rectangles_general([0.0, 1.0], [0.0, 1.0], [0.0, 1.0], [0.0, 1.0]).unwrap();
        assert!((f - perpendicular_rectangles(1.0, 1.0, 1.0).unwrap()).abs() < 1e-14);
    }

    #[test]
    fn point_rectangle_forms_against_quadrature() {
        // Row 3: element at the origin facing +z, rectangle [0,a] x [0,b] at height c.
        for (a, b, c) in [(1.0, 2.0, 1.0), (0.3, 0.7, 2.0), (5.0, 1.0, 0.2)] {
            let f = point_rectangle_corner_parallel(a, b, c).unwrap();
            let kern = |x: f64, y: f64| {
                let d2 = x * x + y * y + c * c;
                c * c / (PI * d2 * d2)
            };
            let q = quad2(&kern, (0.0, a), (0.0, b), 60, 0);
            assert!((f - q).abs() < 1e-12 * q, "{a} {b} {c}: {f} {q}");
            let l = point_polygon(Vec3::ZERO, Vec3::Z, &rect_xy((0.0, a), (0.0, b), c, false));
            assert!((f - l).abs() < 1e-13 * l);
        }
        assert!((point_rectangle_corner_parallel(1.0, 2.0, 1.0).unwrap() - 0.167375009914).abs() < 1e-12);
        // Row 4: element at the origin facing +z; rectangle x in [0,b], z in [0,a] at y = c.
        for (a, b, c) in [(2.0, 1.0, 0.5), (0.4, 1.3, 0.9), (3.0, 3.0, 0.1)] {
            let f = point_rectangle_corner_perpendicular(a, b, c).unwrap();
            // cos at the element = z/r, cos at the rectangle = c/r
            let kern = |x: f64, z: f64| {
                let d2 = x * x + c * c + z * z;
                z * c / (PI * d2 * d2)
            };
            let q = quad2(&kern, (0.0, b), (0.0, a), 60, 0);
            assert!((f - q).abs() < 1e-12 * q, "{a} {b} {c}: {f} {q}");
        }
        assert!((point_rectangle_corner_perpendicular(2.0, 1.0, 0.5).unwrap() - 0.158774804514).abs() < 1e-12);
    }

    #[test]
    fn invalid_arguments() {
        assert!(matches!(disk_coaxial(0.0, 1.0), Err(Error::InvalidArgument(_))));
        assert!(disk_coaxial(1.0, f64::NAN).is_err());
        assert!(disk_offset(1.0, 1.0, -0.1).is_err());
        assert!(coaxial_disks(1.0, -1.0, 1.0).is_err());
        assert!(parallel_rectangles(1.0, 1.0, f64::INFINITY).is_err());
        assert!(perpendicular_rectangles(0.0, 1.0, 1.0).is_err());
        assert!(parallel_rectangles_general([1.0, 0.0], [0.0, 1.0], [0.0, 1.0], [0.0, 1.0], 1.0).is_err());
        assert!(parallel_rectangles_general([0.0, 1.0], [0.0, 1.0], [0.0, 1.0], [0.0, 1.0], 0.0).is_err());
        assert!(perpendicular_rectangles_general([-1.0, 1.0], [0.0, 1.0], [0.0, 1.0], [0.0, 1.0]).is_err());
        assert!(perpendicular_rectangles_general([0.0, 1.0], [0.0, f64::NAN], [0.0, 1.0], [0.0, 1.0]).is_err());
        assert!(point_rectangle_corner_parallel(1.0, 1.0, -1.0).is_err());
        assert!(point_rectangle_corner_perpendicular(1.0, 0.0, 1.0).is_err());
    }
}
