//! Special functions for the exact kernels: the Clausen function Cl2 and Im Li2 of a complex
//! argument (the dilogarithm terms of Narayanaswamy's edge-pair formula, docs/algorithms.md §4.2).

use std::f64::consts::{LN_2, PI, TAU};

/// Numerators and denominators of the Bernoulli numbers |B_2|, |B_4|, ..., |B_32| (exact).
const BERNOULLI_ABS: [(f64, f64); 16] = [
    (1.0, 6.0),
    (1.0, 30.0),
    (1.0, 42.0),
    (1.0, 30.0),
    (5.0, 66.0),
    (691.0, 2730.0),
    (7.0, 6.0),
    (3617.0, 510.0),
    (43867.0, 798.0),
    (174611.0, 330.0),
    (854513.0, 138.0),
    (236364091.0, 2730.0),
    (8553103.0, 6.0),
    (23749461029.0, 870.0),
    (8615841276005.0, 14322.0),
    (7709321041217.0, 510.0),
];

/// Series coefficients a_n = |B_2n| / (2n (2n+1)!), n = 1..16.
const fn small_angle_coeffs() -> [f64; 16] {
    let mut out = [0.0; 16];
    let mut fact = 1.0; // (2n+1)!
    let mut k = 1;
    let mut n = 0;
    while n < 16 {
        // advance fact from (2n-1)! to (2n+1)!
        k += 1;
        fact *= k as f64;
        k += 1;
        fact *= k as f64;
        let (num, den) = BERNOULLI_ABS[n];
        let m = (2 * (n + 1)) as f64;
        out[n] = num / den / (m * fact);
        n += 1;
    }
    out
}

/// b_n = (2^2n - 1) a_n, the coefficients of the expansion about pi.
const fn near_pi_coeffs() -> [f64; 16] {
    let a = small_angle_coeffs();
    let mut out = [0.0; 16];
    let mut p = 1.0;
    let mut n = 0;
    while n < 16 {
        p *= 4.0;
        out[n] = (p - 1.0) * a[n];
        n += 1;
    }
    out
}

const A_COEF: [f64; 16] = small_angle_coeffs();
const B_COEF: [f64; 16] = near_pi_coeffs();

fn horner(c: &[f64; 16], x2: f64) -> f64 {
    let mut acc = 0.0;
    for k in (0..16).rev() {
        acc = acc * x2 + c[k];
    }
    acc
}

/// Clausen function Cl2(theta) = -int_0^theta ln|2 sin(t/2)| dt = sum_k sin(k theta)/k^2,
/// for any real theta (odd, 2 pi-periodic). Absolute accuracy ~1e-16 on the reduced range.
///
/// Reduction to [0, pi] by periodicity and oddness, then one of two Bernoulli series
/// (Abramowitz & Stegun 27.8; derived from ln(sin y / y) and ln cos y):
///   0 <= theta <= 2pi/3:  Cl2 = theta - theta ln theta + sum_n a_n theta^(2n+1),
///                         a_n = |B_2n| / (2n (2n+1)!)
///   x = pi - theta < pi/3: Cl2 = x ln 2 - sum_n (2^2n - 1) a_n x^(2n+1)
/// Both tails shrink like (1/3)^(2n), so 16 terms reach double precision.
pub fn clausen2(theta: f64) -> f64 {
    if !theta.is_finite() {
        return f64::NAN;
    }
    // Oddness first (exact), then periodicity.
    let sign0 = if theta < 0.0 { -1.0 } else { 1.0 };
    let mut t = theta.abs();
    if t > TAU {
        t = t.rem_euclid(TAU);
    }
    let mut sign = sign0;
    if t > PI {
        t = TAU - t;
        sign = -sign;
    }
    let v = if t == 0.0 {
        0.0
    } else if t <= 2.0 * PI / 3.0 {
        t - t * t.ln() + t * t * t * horner(&A_COEF, t * t)
    } else {
        let x = PI - t;
        x * LN_2 - x * x * x * horner(&B_COEF, x * x)
    };
    sign * v
}

/// Im Li2(r e^{i theta}) for r >= 0 and any real theta (the imaginary part of the
/// dilogarithm; on the cut theta = 0, r > 1 it returns the limit from above, pi ln r).
///
/// Kummer's formula via Clausen functions (Lewin 1981, eq. 5.4; docs/algorithms.md §4.2 item 5):
///   Im Li2(r e^{i theta}) = omega ln r + (Cl2(2 theta) + Cl2(2 omega) - Cl2(2 omega + 2 theta)) / 2,
///   omega = atan2(r sin theta, 1 - r cos theta).
/// For r <= 1/4 the power series sum_k r^k sin(k theta)/k^2 is used instead (relative
/// accuracy as r -> 0, where Kummer's terms cancel), and for r >= 4 the inversion formula
///   Im Li2(r e^{i theta}) = Im Li2(r^{-1} e^{i theta}) + (pi - theta) ln r,  0 <= theta <= pi,
/// maps back to that series. Im Li2 grows like ln r as r -> infinity (returns +-inf at r = inf).
pub fn im_li2(r: f64, theta: f64) -> f64 {
    if !(r >= 0.0) || !theta.is_finite() {
        return f64::NAN;
    }
    // Reduce theta to [0, pi] using Im Li2(conj z) = -Im Li2(z) and 2 pi-periodicity.
    let mut sign = if theta < 0.0 { -1.0 } else { 1.0 };
    let mut t = theta.abs();
    if t > TAU {
        t = t.rem_euclid(TAU);
    }
    if t > PI {
        t = TAU - t;
        sign = -sign;
    }
    if r == 0.0 || t == PI && r <= 1.0 {
        return 0.0;
    }
    if r.is_infinite() {
        return if t == PI { 0.0 } else { sign * f64::INFINITY };
    }
    let v = if r <= 0.25 {
        im_li2_series(r, t)
    } else if r >= 4.0 {
        im_li2_series(1.0 / r, t) + (PI - t) * r.ln()
    } else {
        let s = t.sin();
        // 1 - r cos t written to keep accuracy when r ~ 1 and t ~ 0.
        let half = (0.5 * t).sin();
        let omega = (r * s).atan2((1.0 - r) + 2.0 * r * half * half);
        omega * r.ln() + 0.5 * (clausen2(2.0 * t) + clausen2(2.0 * omega) - clausen2(2.0 * omega + 2.0 * t))
    };
    sign * v
}

/// sum_k r^k sin(k t) / k^2 for r <= 1/4 (4^-27 < 1e-16 after 27 terms).
fn im_li2_series(r: f64, t: f64) -> f64 {
    let (s1, c1) = t.sin_cos();
    // sin(k t) by the complex rotation (cos, sin) -> (cos, sin) * e^{it}, stable for any t.
    let (mut sk, mut ck) = (s1, c1);
    let mut rk = r;
    let mut acc = 0.0;
    for k in 1..=40 {
        let kf = k as f64;
        acc += rk * sk / (kf * kf);
        rk *= r;
        if rk < 1e-18 * r {
            break;
        }
        let (ns, nc) = (sk * c1 + ck * s1, ck * c1 - sk * s1);
        sk = ns;
        ck = nc;
    }
    acc
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::quadrature::gauss::gauss_legendre_pm1 as gauss_legendre;

    /// Composite Gauss-Legendre of f on [a, b] with `panels` panels of `n` nodes.
    fn quad(f: impl Fn(f64) -> f64, a: f64, b: f64, panels: usize, n: usize) -> f64 {
        let (x, w) = gauss_legendre(n);
        let h = (b - a) / panels as f64;
        let mut acc = 0.0;
        for p in 0..panels {
            let m = a + (p as f64 + 0.5) * h;
            for k in 0..n {
                acc += w[k] * 0.5 * h * f(m + 0.5 * h * x[k]);
            }
        }
        acc
    }

    #[test]
    fn gauss_legendre_integrates_polynomials() {
        for n in [1, 2, 5, 16, 33] {
            let (x, w) = gauss_legendre(n);
            for deg in 0..2 * n {
                let q: f64 = x.iter().zip(&w).map(|(x, w)| w * x.powi(deg as i32)).sum();
                let exact = if deg % 2 == 1 { 0.0 } else { 2.0 / (deg as f64 + 1.0) };
                assert!((q - exact).abs() < 1e-14, "n={n} deg={deg} {q} {exact}");
            }
        }
    }

    /// Cl2 from its defining integral: -int_0^theta ln|2 sin(t/2)| dt, with the log
    /// singularity at 0 split off exactly (int_0^theta ln t = theta ln theta - theta) and
    /// the smooth rest ln(2 sin(t/2)/t) integrated by Gauss-Legendre. Only for 0 < theta < 2 pi.
    fn cl2_by_quadrature(theta: f64) -> f64 {
        let smooth = |t: f64| {
            if t == 0.0 {
                0.0
            } else {
                (2.0 * (0.5 * t).sin() / t).ln()
            }
        };
        // ln(2 sin(t/2)/t) is singular at t = 2 pi: stay below 5.5.
        -(theta * theta.ln() - theta) - quad(smooth, 0.0, theta, 8, 30)
    }

    #[test]
    fn clausen_matches_defining_integral() {
        let mut worst: f64 = 0.0;
        for i in 1..=110 {
            let th = i as f64 * 0.05;
            let d = (clausen2(th) - cl2_by_quadrature(th)).abs();
            worst = worst.max(d);
        }
        assert!(worst < 2e-15, "worst abs error {worst:e}");
    }

    #[test]
    fn clausen_symmetries_and_constants() {
        // Cl2(pi/2) = Catalan's constant G (Lewin 1981, eq. 4.24).
        let catalan = 0.915_965_594_177_219_015_054_603_514_932_384_110_774;
        assert!((clausen2(PI / 2.0) - catalan).abs() < 1e-16);
        assert_eq!(clausen2(0.0), 0.0);
        assert!(clausen2(PI).abs() < 1e-16);
        for th in [0.1, 1.0, 2.0, 2.5, 3.0] {
            assert!((clausen2(-th) + clausen2(th)).abs() < 1e-16);
            assert!((clausen2(th + TAU) - clausen2(th)).abs() < 5e-15);
            assert!((clausen2(TAU - th) + clausen2(th)).abs() < 2e-15);
            // duplication: Cl2(2t) = 2 Cl2(t) - 2 Cl2(pi - t)
            let dup = 2.0 * clausen2(th) - 2.0 * clausen2(PI - th);
            assert!((clausen2(2.0 * th) - dup).abs() < 3e-15, "{th}");
        }
        // Continuity across the series switch at 2 pi/3.
        let s = 2.0 * PI / 3.0;
        // slope there is -ln(sqrt 3): a step of 4e-15 moves it by 2.2e-15
        assert!((clausen2(s - 2e-15) - clausen2(s + 2e-15)).abs() < 5e-15);
        // maximum at pi/3 (Cl2' = 0 there)
        assert!(clausen2(PI / 3.0) > clausen2(PI / 3.0 - 1e-4));
        assert!(clausen2(PI / 3.0) > clausen2(PI / 3.0 + 1e-4));
        assert!(clausen2(f64::NAN).is_nan());
    }

    /// Power series of Im Li2 for r < 1: sum_k r^k sin(k t)/k^2, summed to full convergence.
    fn im_li2_power_series(r: f64, t: f64) -> f64 {
        let mut acc = 0.0;
        for k in 1..20000 {
            let kf = k as f64;
            let term = r.powi(k) * (kf * t).sin() / (kf * kf);
            acc += term;
            if r.powi(k) < 1e-20 {
                break;
            }
        }
        acc
    }

    #[test]
    #[allow(clippy::approx_constant)] // angles just short of pi/2 and pi, on purpose
    fn im_li2_against_power_series_and_inversion() {
        let mut worst: f64 = 0.0;
        for &r in &[1e-12, 1e-3, 0.1, 0.2499, 0.25, 0.2501, 0.5, 0.8, 0.95] {
            for &t in &[-2.9, -0.7, 1e-6, 0.3, 1.0, 1.5707, 2.2, 3.0, 3.1415, 7.5] {
                let a = im_li2(r, t);
                let b = im_li2_power_series(r, t);
                // relative accuracy, except near the real axis (t ~ 0, pi) where the value
                // is tiny and Kummer's form keeps an absolute error of a few ulps of r
                let e = (a - b).abs() / (b.abs() + 1e-1 * r);
                worst = worst.max(e);
                // inversion: Im Li2(r^-1 e^{it}) = Im Li2(r e^{it}) - (pi - t) ln(1/r) for t in [0, pi]
                let tr = t.rem_euclid(TAU);
                if tr <= PI {
                    let inv = im_li2(1.0 / r, t);
                    let want = b + (PI - tr) * (1.0 / r).ln();
                    assert!((inv - want).abs() <= 2e-15 * (1.0 + want.abs()), "r={r} t={t} {inv} {want}");
                }
            }
        }
        // measured 5.8e-14 (absolute 1.5e-15 at r = 1/4, t = 3.1415)
        assert!(worst < 1e-13, "worst relative error {worst:e}");
    }

    #[test]
    fn im_li2_special_values() {
        // On the unit circle Im Li2(e^{it}) = Cl2(t).
        for t in [0.2, 1.0, 2.0, 3.0] {
            assert!((im_li2(1.0, t) - clausen2(t)).abs() < 1e-15);
        }
        // Small r: Im Li2 ~ r sin t + r^2 sin(2t)/4.
        let (r, t) = (1e-9_f64, 0.7_f64);
        let lead = r * t.sin() + r * r * (2.0 * t).sin() / 4.0;
        assert!((im_li2(r, t) - lead).abs() < 1e-15 * lead);
        // Just above the cut: Im Li2(r + i0) = pi ln r for r > 1.
        assert!((im_li2(3.0, 0.0) - PI * 3f64.ln()).abs() < 1e-14);
        assert!((im_li2(3.0, 1e-12) - PI * 3f64.ln()).abs() < 1e-10);
        assert_eq!(im_li2(0.0, 1.0), 0.0);
        assert!(im_li2(f64::INFINITY, 1.0).is_infinite());
        assert!(im_li2(-1.0, 1.0).is_nan());
        // Continuity across the algorithm switches at r = 1/4 and r = 4.
        for r0 in [0.25, 4.0] {
            for t in [0.3, 2.0] {
                // step 2e-15 r0: the slope is below 1, so a jump shows up above 1e-14
                let d = im_li2(r0 * (1.0 + 1e-15), t) - im_li2(r0 * (1.0 - 1e-15), t);
                assert!(d.abs() < 1e-14, "{r0} {t} {d}");
            }
        }
    }

    #[test]
    fn im_li2_against_mpmath() {
        // Values from: python3 -c "import mpmath as m; m.mp.dps=30;
        //   print([m.im(m.polylog(2, r*m.expj(t))) for r,t in [(0.3,1.1),(3.3,2.1),(1.7,0.4)]])"
        let want = [
            (0.3, 1.1, 0.284_540_958_070_097_463_056_887_190_847),
            (3.3, 2.1, 1.485_567_143_334_095_508_180_935_839_39),
            (1.7, 0.4, 1.777_817_009_186_202_645_045_643_453_57),
        ];
        for (r, t, w) in want {
            assert!((im_li2(r, t) - w).abs() < 2e-15, "{r} {t}");
        }
    }
}
