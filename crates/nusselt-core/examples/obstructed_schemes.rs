//! Accuracy against time of the obstructed-pair source rules of `clipping` on random obstructed
//! pairs of the box room of bench/obstructed.py (no Python):
//!     cargo run --release -p nusselt-core --example obstructed_schemes -- N PAIRS
//! Reference: the adaptive rule at tol 1e-10. Errors are relative to each pair's unobstructed
//! G = A_i F_ij (what `tol` bounds).
use nusselt_core::obstructed::{self, ClippingOptions, Context, Estimator};
use nusselt_core::unobstructed::method::{self, Method};
use nusselt_core::visibility::{Bvh, Occluders, Visibility};
use std::time::Instant;

#[path = "common/pairs.rs"]
mod pairs;
#[path = "common/room.rs"]
mod room;

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let n: usize = args.get(1).and_then(|s| s.parse().ok()).unwrap_or(9);
    let want: usize = args.get(2).and_then(|s| s.parse().ok()).unwrap_or(300);
    let polys = room::room(n);
    let bvh = Bvh::new(&polys).unwrap(); // picks the pairs (the same ones as before occluders)
    let occ = Occluders::new(&polys);
    let occ_bvh = Bvh::new(&occ.polygons).unwrap();
    let ctx = Context { polygons: &polys, occluders: &occ, vis: &occ_bvh, rules: None, exact_tol: 1e-12 };
    // random pairs with a candidate blocker in between (xorshift, fixed seed)
    let mut cand = Vec::new();
    let pairs: Vec<(usize, usize)> = pairs::facing_pairs(&polys)
        .filter(|&(i, j)| {
            bvh.candidates_between(&polys[i], &polys[j], &[i as u32, j as u32], &mut cand);
            !cand.is_empty()
        })
        .take(want)
        .collect();
    let o = ClippingOptions { tol: 1e-10, ..Default::default() };
    let t0 = Instant::now();
    let refs: Vec<f64> =
        pairs.iter().map(|&(i, j)| obstructed::pair(&ctx, i, j, &Estimator::Clipping(o)).unwrap().value).collect();
    let free: Vec<f64> = pairs
        .iter()
        .map(|&(i, j)| method::area_factor(&polys[i], &polys[j], Method::Analytic, &Default::default(), None).unwrap())
        .collect();
    let hidden = refs.iter().zip(&free).map(|(r, f)| 1.0 - r / f).sum::<f64>() / pairs.len() as f64;
    println!(
        "{} patches, {} obstructed pairs (mean hidden fraction {hidden:.3}), reference in {:.1} s",
        polys.len(),
        pairs.len(),
        t0.elapsed().as_secs_f64()
    );
    let mut schemes: Vec<(String, ClippingOptions)> = Vec::new();
    for k in 1..=4 {
        schemes.push((format!("source {k}x{k}"), ClippingOptions { source: Some(k), ..o }));
    }
    for t in [1e-2, 1e-3, 1e-4, 1e-5, 1e-6, 1e-8] {
        schemes.push((format!("adaptive tol {t:e}"), ClippingOptions { tol: t, ..o }));
    }
    for (name, q) in schemes {
        let t0 = Instant::now();
        let mut errs: Vec<f64> = pairs
            .iter()
            .zip(refs.iter().zip(&free))
            .map(|(&(i, j), (r, f))| {
                (obstructed::pair(&ctx, i, j, &Estimator::Clipping(q)).unwrap().value - r).abs() / f
            })
            .collect();
        let us = t0.elapsed().as_secs_f64() / pairs.len() as f64 * 1e6;
        errs.sort_by(|a, b| a.total_cmp(b));
        let at = |p: usize| errs[(errs.len() * p / 100).min(errs.len() - 1)];
        println!(
            "{name:22} {us:9.1} us/pair   error/free: median {:.1e} p90 {:.1e} p99 {:.1e} max {:.1e}",
            at(50),
            at(90),
            at(99),
            at(100)
        );
    }
}
