//! Profiling driver for obstructed `auto` on any scene, read from a text file with one
//! polygon per line (x y z of each vertex, whitespace separated):
//!
//!   cargo run --release -p nusselt-core --example obstructed_scene -- FILE [TOL] [SLOWEST]
//!       time every pair (i < j) one by one on this thread and list the SLOWEST pairs
//!       (default 10) with their time; the total is the one-core time of the scene, followed
//!       by the largest |row sum - 1| (the accuracy figure of a closed scene)
//!   ... FILE TOL SLOWEST I J
//!       time the pair (I, J) alone
//!   ... FILE TOL SLOWEST A..B
//!       only rows A to B - 1 (pairs i < j): a piece of a large scene small enough for
//!       `valgrind --tool=callgrind`, whose instruction counts compare two builds on a busy
//!       machine
#[path = "common/polygon_file.rs"]
mod polygon_file;
use nusselt_core::scene::{AnyMethod, Scene};
use nusselt_core::unobstructed::method::AutoOptions;
use nusselt_core::Polygon;
use polygon_file::read_polygons;
use std::sync::atomic::AtomicBool;
use std::time::Instant;

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let tol: f64 = args.get(2).and_then(|s| s.parse().ok()).unwrap_or(1e-6);
    let slowest: usize = args.get(3).and_then(|s| s.parse().ok()).unwrap_or(10);
    let polys = read_polygons(&args[1]);
    let n = polys.len();
    let scene = Scene::new(polys, vec![true; n]).unwrap();
    let m = AnyMethod::Auto(AutoOptions { obstructed_tol: tol, ..Default::default() });
    let never = AtomicBool::new(false);
    if let (Some(i), Some(j)) =
        (args.get(4).and_then(|s| s.parse::<usize>().ok()), args.get(5).and_then(|s| s.parse::<usize>().ok()))
    {
        // one pair (i, j), every other polygon a blocker
        let p = scene.polygons();
        let obs: Vec<Polygon> = (0..n).filter(|&k| k != i && k != j).map(|k| p[k].clone()).collect();
        let t = Instant::now();
        let e = nusselt_core::scene::pair_view_factor(p[i].clone(), p[j].clone(), obs, &m).unwrap();
        println!("pair ({i}, {j}): F {:.15e} in {:.4} s", e.value, t.elapsed().as_secs_f64());
        return;
    }
    let rows = match args.get(4).and_then(|s| s.split_once("..")) {
        Some((a, b)) => a.parse().expect("row range A..B")..b.parse::<usize>().expect("row range A..B").min(n),
        None => 0..n,
    };
    let mut times = Vec::new();
    // sum of G over each row (pairs i < j count for both rows: G is symmetric)
    let mut g_rows = vec![0.0; n];
    let t0 = Instant::now();
    for i in rows.clone() {
        // one row at a time: the per-row time locates the expensive pairs
        let t = Instant::now();
        let r = scene.pair_rows(&[i], &m, &never).unwrap();
        times.push((t.elapsed().as_secs_f64(), i, r[0].len()));
        for (&j, &g) in r[0].cols.iter().zip(&r[0].g) {
            g_rows[i] += g;
            g_rows[j as usize] += g;
        }
    }
    let total = t0.elapsed().as_secs_f64();
    times.sort_by(|a, b| b.0.total_cmp(&a.0));
    let p = scene.polygons();
    let row_err = (0..n).map(|i| (g_rows[i] / p[i].area() - 1.0).abs()).fold(0.0, f64::max);
    if rows == (0..n) {
        println!("{n} polygons, tol {tol:e}: {total:.3} s, max |row sum - 1| {row_err:.2e}");
    } else {
        println!("{n} polygons, tol {tol:e}: {total:.3} s for rows {rows:?}");
    }
    for (t, i, len) in times.iter().take(slowest) {
        println!("row {i}: {t:.3} s ({len} nonzero pairs)");
    }
}
