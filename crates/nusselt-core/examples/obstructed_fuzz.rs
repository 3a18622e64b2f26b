//! How often `clipping` misses its target on random obstructed pairs in general position
//! (no Python):
//!     cargo run --release -p nusselt-core --example obstructed_fuzz -- CASES [SEED]
//! (with FUZZ_DUMP set, the polygons of each pair over its target go to stderr, one per line:
//! the pair first, then its blockers)
//! A tilted convex 3- to 6-gon source at z = 0 and receiver at z = 1 (facing down), and 1 to 4
//! blockers: tilted n-gons between them, some crossing the source's plane or nearly touching
//! the receiver's (as furniture stands on a floor). Reference: the same method at tol 1e-9 with
//! a budget of 2 million evaluations per integral. Pairs the blockers do not touch are skipped.
//! Errors are relative to each pair's unobstructed G = A_i F_ij (what `tol` bounds). A pair
//! over its target is "silent" when the error it reports (its std_err: the integral's estimate
//! where it ran out of evaluations short of the goal, else 0) does not cover the miss either.
use nusselt_core::obstructed::{self, ClippingOptions, Context, Estimator};
use nusselt_core::unobstructed::method::{self, Method};
use nusselt_core::visibility::{Bvh, Occluders};
use nusselt_core::{Polygon, Vec3};
use std::time::Instant;

/// xorshift64 with uniform and normal draws
struct Rng(u64);

impl Rng {
    fn f(&mut self) -> f64 {
        self.0 ^= self.0 << 13;
        self.0 ^= self.0 >> 7;
        self.0 ^= self.0 << 17;
        (self.0 >> 11) as f64 / (1u64 << 53) as f64
    }
    fn u(&mut self, (a, b): (f64, f64)) -> f64 {
        a + (b - a) * self.f()
    }
    fn normal(&mut self) -> f64 {
        let (a, b) = (self.f().max(1e-300), self.f());
        (-2.0 * a.ln()).sqrt() * (std::f64::consts::TAU * b).cos()
    }
}

/// A convex polygon on a circle of radius `size` around a random point at height `z`, its
/// normal +z tilted by `tilt` times a random vector, reversed with probability `flip`.
fn polygon(r: &mut Rng, z: (f64, f64), size: (f64, f64), tilt: (f64, f64), flip: f64) -> Option<Polygon> {
    let (z, size, tilt, flip) = (r.u(z), r.u(size), r.u(tilt), r.f() < flip);
    let n = (Vec3::Z + tilt * Vec3::new(r.normal(), r.normal(), r.normal())).normalize();
    let (t, b) = nusselt_core::geometry::tangent_frame(n);
    let c = Vec3::new(r.u((-0.5, 0.5)), r.u((-0.5, 0.5)), z);
    let mut angles: Vec<f64> = (0..3 + (r.f() * 4.0) as usize).map(|_| r.u((0.0, std::f64::consts::TAU))).collect();
    angles.sort_by(f64::total_cmp);
    let mut v: Vec<Vec3> = angles.iter().map(|a| c + size * (a.cos() * t + a.sin() * b)).collect();
    if flip {
        v.reverse();
    }
    Polygon::new(v).ok()
}

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let cases: usize = args.get(1).and_then(|s| s.parse().ok()).unwrap_or(200);
    let seed: u64 = args.get(2).and_then(|s| s.parse().ok()).unwrap_or(0x1234_5678_9abc_def1);
    let mut r = Rng(seed.max(1));
    let tols = [1e-2, 1e-3, 1e-4, 1e-5, 1e-6];
    let (mut over, mut silent, mut reported, mut worst, mut time) =
        ([0usize; 5], [0usize; 5], [0usize; 5], [0f64; 5], [0f64; 5]);
    // error / target of every pair, per tol (the calibration: how much of the target is used)
    let mut ratios: [Vec<f64>; 5] = Default::default();
    let mut done = 0;
    while done < cases {
        let (Some(a), Some(b)) = (
            polygon(&mut r, (0.0, 0.0), (0.2, 1.0), (0.3, 0.3), 0.0),
            polygon(&mut r, (1.0, 1.0), (0.2, 1.0), (0.3, 0.3), 1.0),
        ) else {
            continue;
        };
        let mut polys = vec![a, b];
        for _ in 0..1 + (r.f() * 4.0) as usize {
            let kind = r.f();
            let p = if kind < 0.15 {
                polygon(&mut r, (-0.1, 0.1), (0.1, 0.6), (2.0, 2.0), 0.0) // through the source's plane
            } else if kind < 0.3 {
                polygon(&mut r, (0.95, 1.0), (0.1, 0.6), (1.5, 1.5), 0.0) // up to the receiver's
            } else {
                polygon(&mut r, (0.1, 0.9), (0.05, 0.8), (0.0, 1.5), 0.5)
            };
            polys.extend(p);
        }
        let occ = Occluders::new(&polys);
        let bvh = Bvh::new(&occ.polygons).unwrap();
        let ctx = Context { polygons: &polys, occluders: &occ, vis: &bvh, rules: None, exact_tol: 1e-12 };
        let free = method::area_factor(&polys[0], &polys[1], Method::Analytic, &Default::default(), None).unwrap();
        let reference = Estimator::Clipping(ClippingOptions { tol: 1e-9, max_evals: 2_000_000, ..Default::default() });
        let reference = obstructed::pair(&ctx, 0, 1, &reference).unwrap().value;
        if !(free > 0.0) || (free - reference).abs() < 1e-9 * free {
            continue;
        }
        done += 1;
        for (k, &tol) in tols.iter().enumerate() {
            let t0 = Instant::now();
            let o = Estimator::Clipping(ClippingOptions { tol, ..Default::default() });
            let v = obstructed::pair(&ctx, 0, 1, &o).unwrap();
            time[k] += t0.elapsed().as_secs_f64();
            let e = (v.value - reference).abs() / free;
            over[k] += (e > tol) as usize;
            silent[k] += (e > tol && e * free > v.std_err) as usize;
            if e > tol && std::env::var_os("FUZZ_DUMP").is_some() {
                // the pair (first two lines) and its blockers, one polygon per line, to replay it
                eprintln!("# tol {tol:e}: {:.2} x target", e / tol);
                for p in &polys {
                    let c: Vec<String> =
                        p.vertices().iter().flat_map(|x| x.to_array()).map(|x| format!("{x:e}")).collect();
                    eprintln!("{}", c.join(" "));
                }
            }
            reported[k] += (v.std_err > 0.0) as usize;
            worst[k] = worst[k].max(e / tol);
            ratios[k].push(e / tol);
        }
    }
    for (k, tol) in tols.iter().enumerate() {
        println!(
            "tol {tol:e}: {:3} of {cases} pairs over target ({:3} silent), {:3} report an error, worst {:7.2} x target, {:6.0} us per pair",
            over[k],
            silent[k],
            reported[k],
            worst[k],
            time[k] / cases as f64 * 1e6
        );
    }
    println!("error / target: quantiles 5 % / 50 % / 95 %, share within [1/30, 1]");
    for (k, tol) in tols.iter().enumerate() {
        let r = &mut ratios[k];
        r.sort_by(f64::total_cmp);
        let q = |p: f64| r[((p * (r.len() - 1) as f64).round() as usize).min(r.len() - 1)];
        let within = r.iter().filter(|&&x| (1.0 / 30.0..=1.0).contains(&x)).count();
        println!(
            "tol {tol:e}: {:9.2e} {:9.2e} {:9.2e}, {:5.1} %",
            q(0.05),
            q(0.5),
            q(0.95),
            100.0 * within as f64 / r.len() as f64
        );
    }
}
