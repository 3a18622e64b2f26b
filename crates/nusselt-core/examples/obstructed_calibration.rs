//! Calibration of the obstructed error estimate without Python, on any scene read as in
//! `obstructed_scene` (one polygon per line):
//!     cargo run --release -p nusselt-core --example obstructed_calibration -- FILE PAIRS REFS TOL...
//! PAIRS random obstructed pairs (every other polygon a blocker; fixed seed), their references
//! by `clipping` at tol 1e-11 with 2 million evaluations per integral, kept in the file REFS
//! (computed once). For each TOL: `auto` at that `obstructed_tol`, the error relative to
//! tol x the pair's unobstructed G (what tol bounds): quantiles, the share in [1/30, 1], the
//! number above 1 (over the partly hidden pairs; fully hidden ones must come out exactly 0,
//! and the count of those that do not is printed), and the CPU time per pair (this thread). NUSSELT_MAXEVALS=N sets `max_evals`;
//! NUSSELT_WORST=1 lists the pairs above their target.
#[path = "common/pairs.rs"]
mod pairs;
#[path = "common/polygon_file.rs"]
mod polygon_file;
use nusselt_core::obstructed::{self, ClippingOptions, Context, Estimator};
use nusselt_core::unobstructed::method::{self, Method};
use nusselt_core::visibility::{Bvh, Occluders, Visibility};
use pairs::facing_pairs;
use polygon_file::read_polygons;
use std::time::Instant;

/// CPU seconds of this thread so far (Linux), wall seconds elsewhere.
fn cpu_seconds(wall: &Instant) -> f64 {
    std::fs::read_to_string("/proc/thread-self/schedstat")
        .ok()
        .and_then(|t| t.split_whitespace().next().and_then(|x| x.parse::<f64>().ok()))
        .map_or_else(|| wall.elapsed().as_secs_f64(), |ns| ns * 1e-9)
}

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let want: usize = args[2].parse().expect("a number of pairs");
    let refs_file = &args[3];
    let tols: Vec<f64> = args[4..].iter().map(|s| s.parse().expect("a tolerance")).collect();
    let polys = read_polygons(&args[1]);
    let occ = Occluders::new(&polys);
    let bvh = Bvh::new(&occ.polygons).unwrap();
    let ctx = Context { polygons: &polys, occluders: &occ, vis: &bvh, rules: None, exact_tol: 1e-12 };
    let exact = method::Options { tol: 1e-12, ..Default::default() };
    let free = |i: usize, j: usize| method::area_factor(&polys[i], &polys[j], Method::Auto, &exact, None).unwrap();
    // (i, j, reference G)
    let pairs: Vec<(usize, usize, f64)> = match std::fs::read_to_string(refs_file) {
        Ok(t) => t
            .lines()
            .map(|l| {
                let w: Vec<&str> = l.split_whitespace().collect();
                (w[0].parse().unwrap(), w[1].parse().unwrap(), w[2].parse().unwrap())
            })
            .collect(),
        Err(_) => {
            let o = Estimator::Clipping(ClippingOptions { tol: 1e-11, max_evals: 2_000_000, ..Default::default() });
            let (mut out, mut cand) = (Vec::new(), Vec::new());
            let t0 = Instant::now();
            for (i, j) in facing_pairs(&polys) {
                if out.len() >= want {
                    break;
                }
                bvh.candidates_between(&polys[i], &polys[j], &[occ.owner[i], occ.owner[j]], &mut cand);
                if cand.is_empty() {
                    continue;
                }
                let f = free(i, j);
                if f < 1e-6 * polys[i].area() {
                    continue;
                }
                let r = obstructed::pair(&ctx, i, j, &o).unwrap().value;
                if r < f * (1.0 - 1e-6) {
                    out.push((i, j, r));
                }
            }
            let t: String = out.iter().map(|(i, j, r)| format!("{i} {j} {r:e}\n")).collect();
            std::fs::write(refs_file, t).unwrap();
            println!("{} references in {:.1} s", out.len(), t0.elapsed().as_secs_f64());
            out
        }
    };
    let frees: Vec<f64> = pairs.iter().map(|&(i, j, _)| free(i, j)).collect();
    for tol in tols {
        let mut o = ClippingOptions { tol, ..Default::default() };
        if let Some(m) = std::env::var("NUSSELT_MAXEVALS").ok().and_then(|s| s.parse().ok()) {
            o.max_evals = m;
        }
        let wall = Instant::now();
        let t0 = cpu_seconds(&wall);
        let got: Vec<f64> = pairs
            .iter()
            .map(|&(i, j, _)| obstructed::pair(&ctx, i, j, &Estimator::Clipping(o)).unwrap().value)
            .collect();
        let us = (cpu_seconds(&wall) - t0) / pairs.len() as f64 * 1e6;
        // fully hidden pairs (reference 0) come out exactly 0 and are left out of the ratios
        let hidden = pairs.iter().zip(&got).filter(|(p, g)| p.2 == 0.0 && **g != 0.0).count();
        let mut r: Vec<f64> = pairs
            .iter()
            .zip(&got)
            .zip(&frees)
            .filter(|((p, _), _)| p.2 > 0.0)
            .map(|((p, g), f)| (g - p.2).abs() / (tol * f))
            .collect();
        r.sort_by(|a, b| a.total_cmp(b));
        let at = |q: f64| r[((r.len() as f64 * q) as usize).min(r.len() - 1)];
        let inside = r.iter().filter(|&&x| (1.0 / 30.0..=1.0).contains(&x)).count();
        if std::env::var("NUSSELT_WORST").is_ok() {
            for ((p, g), f) in pairs.iter().zip(&got).zip(&frees) {
                let x = (g - p.2).abs() / (tol * f);
                if x > 1.0 {
                    println!("  pair {} {}: ratio {x:.2}, free G {f:.3e}, hidden {:.3}", p.0, p.1, 1.0 - p.2 / f);
                }
            }
        }
        println!(
            "tol {tol:.0e}: {us:8.1} us/pair; error/(tol free) 5/25/50/75/95 % {:.1e} {:.1e} {:.1e} {:.1e} {:.1e} \
             max {:.2e}; in [1/30, 1] {:.1} %; above 1: {} of {} partly hidden; {hidden} fully hidden not 0",
            at(0.05),
            at(0.25),
            at(0.5),
            at(0.75),
            at(0.95),
            r[r.len() - 1],
            100.0 * inside as f64 / r.len() as f64,
            r.iter().filter(|&&x| x > 1.0).count(),
            r.len()
        );
    }
}
