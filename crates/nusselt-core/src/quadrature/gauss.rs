//! One-dimensional Gauss rules on [0, 1], tabulated on first use: Gauss-Legendre (the one
//! generator of the crate) and Gauss-Jacobi for the weight (1 - u) of the collapsed triangle map.

use crate::error::{Error, Result};
use std::f64::consts::PI;
use std::sync::OnceLock;

/// Largest tabulated Gauss order.
pub const MAX_ORDER: usize = 64;

/// Rules are computed on first use, one order at a time: the high orders (Newton iterations on
/// Jacobi polynomials) cost far more than the low ones that distant pairs need, and a process
/// that never asks for them should not pay for them.
struct Tables {
    legendre: Vec<OnceLock<Vec<(f64, f64)>>>,
    jacobi10: Vec<OnceLock<Vec<(f64, f64)>>>,
}

fn tables() -> &'static Tables {
    static T: OnceLock<Tables> = OnceLock::new();
    T.get_or_init(|| Tables {
        legendre: (0..MAX_ORDER).map(|_| OnceLock::new()).collect(),
        jacobi10: (0..MAX_ORDER).map(|_| OnceLock::new()).collect(),
    })
}

/// Gauss-Legendre nodes and weights on [0, 1], n = 1..=64 (exact for degree 2n - 1).
///
/// Panics if n is outside 1..=64: that is a programming error of the caller; use
/// [`try_gauss_legendre`] for values that come from users.
pub fn gauss_legendre(n: usize) -> &'static [(f64, f64)] {
    assert!((1..=MAX_ORDER).contains(&n), "gauss_legendre: n = {n} is outside 1..={MAX_ORDER}");
    tables().legendre[n - 1].get_or_init(|| legendre_rule(n))
}

/// Checked [`gauss_legendre`].
pub fn try_gauss_legendre(n: usize) -> Result<&'static [(f64, f64)]> {
    check_order(n, "Gauss-Legendre order")?;
    Ok(gauss_legendre(n))
}

pub(crate) fn check_order(n: usize, what: &str) -> Result<()> {
    if (1..=MAX_ORDER).contains(&n) {
        Ok(())
    } else {
        Err(Error::InvalidArgument(format!("{what} must be in 1..={MAX_ORDER}, got {n}")))
    }
}

/// Gauss-Jacobi rule for the weight (1 - u) on [0, 1] (α = 1, β = 0 on [-1, 1]): exact for
/// ∫_0^1 (1 - u) p(u) du with deg p <= 2n - 1. Used in the collapsed triangle rule.
pub(crate) fn gauss_jacobi10(n: usize) -> &'static [(f64, f64)] {
    tables().jacobi10[n - 1].get_or_init(|| jacobi10_rule(n))
}

/// Legendre P_n(x) and P_n'(x) by the three-term recurrence
/// k P_k = (2k - 1) x P_{k-1} - (k - 1) P_{k-2}, differentiated term by term.
fn legendre_p(n: usize, x: f64) -> (f64, f64) {
    let (mut p0, mut p1) = (0.0, 1.0);
    let (mut d0, mut d1) = (0.0, 0.0);
    for k in 1..=n {
        let kf = k as f64;
        let p2 = ((2.0 * kf - 1.0) * x * p1 - (kf - 1.0) * p0) / kf;
        let d2 = ((2.0 * kf - 1.0) * (p1 + x * d1) - (kf - 1.0) * d0) / kf;
        (p0, p1, d0, d1) = (p1, p2, d1, d2);
    }
    (p1, d1)
}

/// Newton on P_n from the guesses cos(π (i + 3/4) / (n + 1/2)); weights 2 / ((1 - x²) P_n'²)
/// (Abramowitz & Stegun 25.4.29), mapped from [-1, 1] to [0, 1].
fn legendre_rule(n: usize) -> Vec<(f64, f64)> {
    let mut out = Vec::with_capacity(n);
    for i in 0..n {
        let mut x = (PI * (i as f64 + 0.75) / (n as f64 + 0.5)).cos();
        for _ in 0..100 {
            let (p, dp) = legendre_p(n, x);
            let dx = p / dp;
            x -= dx;
            if dx.abs() <= 1e-16 {
                break;
            }
        }
        let (_, dp) = legendre_p(n, x);
        let w = 2.0 / ((1.0 - x * x) * dp * dp);
        out.push((0.5 * (1.0 - x), 0.5 * w));
    }
    out.sort_by(|a, b| a.0.total_cmp(&b.0));
    out
}

/// Jacobi P_n^(α,β)(x), α = 1, β = 0, and its derivative, by DLMF 18.9.1 with s = 2k + α + β:
/// 2k(k + α + β)(s - 2) P_k = (s - 1)[s(s - 2)x + α² - β²] P_{k-1} - 2(k + α - 1)(k + β - 1)s P_{k-2}.
fn jacobi10_p(n: usize, x: f64) -> (f64, f64) {
    let (a, b) = (1.0f64, 0.0f64);
    let (mut p0, mut p1) = (0.0, 1.0);
    let (mut d0, mut d1) = (0.0, 0.0);
    for k in 1..=n {
        let k = k as f64;
        let s = 2.0 * k + a + b;
        let c = 2.0 * k * (k + a + b) * (s - 2.0);
        let lin = (s - 1.0) * s * (s - 2.0);
        let con = (s - 1.0) * (a * a - b * b);
        let back = 2.0 * (k + a - 1.0) * (k + b - 1.0) * s;
        let p2 = ((lin * x + con) * p1 - back * p0) / c;
        let d2 = ((lin * x + con) * d1 + lin * p1 - back * d0) / c;
        (p0, p1, d0, d1) = (p1, p2, d1, d2);
    }
    (p1, d1)
}

/// Gauss-Jacobi (α = 1, β = 0): roots bracketed on a fine grid in θ (x = cos θ), polished by
/// safeguarded Newton; weights 4 / ((1 - x²) P_n'(x)²) (Szegő 15.3.5 with α = 1, β = 0, where
/// the gamma-function prefactor is 1). Mapped to [0, 1] with weight (1 - u): w / 4.
fn jacobi10_rule(n: usize) -> Vec<(f64, f64)> {
    let m = 64 * n + 64;
    let mut out = Vec::with_capacity(n);
    let xs: Vec<f64> = (0..=m).map(|i| (PI * i as f64 / m as f64).cos()).collect();
    for i in 0..m {
        let (mut hi, mut lo) = (xs[i], xs[i + 1]); // hi > lo
        let (mut phi, _) = jacobi10_p(n, hi);
        let (plo, _) = jacobi10_p(n, lo);
        if phi == 0.0 {
            // a grid point hit the root exactly: count it once, at the interval's upper end
            if i > 0 {
                out.push(hi);
            }
            continue;
        }
        if phi.signum() == plo.signum() {
            continue;
        }
        let mut x = 0.5 * (hi + lo);
        for _ in 0..200 {
            let (p, dp) = jacobi10_p(n, x);
            if p == 0.0 {
                break;
            }
            if p.signum() == phi.signum() {
                hi = x;
                phi = p;
            } else {
                lo = x;
            }
            let newton = x - p / dp;
            let nx = if newton > lo && newton < hi { newton } else { 0.5 * (hi + lo) };
            if (nx - x).abs() <= 1e-17 * (1.0 + x.abs()) || hi - lo <= 1e-16 {
                x = nx;
                break;
            }
            x = nx;
        }
        out.push(x);
    }
    debug_assert_eq!(out.len(), n);
    let mut rule: Vec<(f64, f64)> = out
        .into_iter()
        .map(|x| {
            let (_, dp) = jacobi10_p(n, x);
            let w = 4.0 / ((1.0 - x * x) * dp * dp);
            (0.5 * (1.0 + x), 0.25 * w)
        })
        .collect();
    rule.sort_by(|a, b| a.0.total_cmp(&b.0));
    rule
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn gauss_legendre_is_exact_to_degree_2n_minus_1() {
        for n in 1..=MAX_ORDER {
            let g = gauss_legendre(n);
            assert_eq!(g.len(), n);
            assert!(g.iter().all(|&(x, w)| x > 0.0 && x < 1.0 && w > 0.0));
            for k in 0..2 * n {
                let q: f64 = g.iter().map(|&(x, w)| w * x.powi(k as i32)).sum();
                let exact = 1.0 / (k as f64 + 1.0);
                assert!(
                    (q - exact).abs() <= 4e-15 * exact.max(1e-3) * (1.0 + k as f64 / 8.0),
                    "n={n} k={k}: {q} vs {exact}"
                );
            }
            // not exact one degree higher (n <= 10 where the defect is above rounding)
            if n <= 10 {
                let k = 2 * n;
                let q: f64 = g.iter().map(|&(x, w)| w * x.powi(k as i32)).sum();
                assert!((q - 1.0 / (k as f64 + 1.0)).abs() > 1e-14);
            }
        }
    }

    #[test]
    fn gauss_jacobi_is_exact_to_degree_2n_minus_1() {
        for n in 1..=MAX_ORDER {
            let g = gauss_jacobi10(n);
            assert_eq!(g.len(), n, "n={n}");
            assert!(g.iter().all(|&(x, w)| x > 0.0 && x < 1.0 && w > 0.0));
            for k in 0..2 * n {
                // ∫_0^1 (1 - u) u^k du = 1 / ((k + 1)(k + 2))
                let q: f64 = g.iter().map(|&(x, w)| w * x.powi(k as i32)).sum();
                let exact = 1.0 / ((k as f64 + 1.0) * (k as f64 + 2.0));
                assert!((q - exact).abs() <= 1e-14 * exact.max(1e-3), "n={n} k={k}: {q} vs {exact}");
            }
        }
    }

    #[test]
    fn bad_orders_are_errors() {
        for n in [0, 65, 1_000_000_000] {
            assert!(matches!(try_gauss_legendre(n), Err(Error::InvalidArgument(_))));
        }
    }
}
