//! Profiling driver for obstructed `auto` on the box room with an inner box of
//! bench/obstructed.py (6 n^2 wall quads, 6 (n/3)^2 inner-box quads).
//!
//!   cargo run --release --example obstructed_room -- rows N [TOL] [STRIDE] [SOURCE]
//!       time pair_rows over every STRIDE-th row (all receivers j > i), obstructed pairs by
//!       `auto` to TOL or, with SOURCE = k, by `clipping` with a k x k source rule; with
//!       DUMP=path, write "i j G_ij A_i" lines there
//!   cargo run --release --example obstructed_room -- cands N
//!       time the candidate-blocker query of every facing pair
//!   cargo run --release --example obstructed_room -- points N
//!       time single evaluations of the shadowed point F on obstructed pairs
use nusselt_core::obstructed::ClippingOptions;
use nusselt_core::scene::{AnyMethod, Scene};
use nusselt_core::unobstructed::method::AutoOptions;
use nusselt_core::visibility::shadow::point_shadowed_view_factor;
use nusselt_core::visibility::{Bvh, Visibility};
use nusselt_core::Polygon;
use std::sync::atomic::AtomicBool;
use std::time::Instant;

#[path = "common/room.rs"]
mod room;
use room::room;

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let mode = args.get(1).map(String::as_str).unwrap_or("rows");
    let n: usize = args.get(2).and_then(|s| s.parse().ok()).unwrap_or(6);
    let polys = room(n);
    match mode {
        "rows" => {
            let tol: f64 = args.get(3).and_then(|s| s.parse().ok()).unwrap_or(1e-6);
            let stride: usize = args.get(4).and_then(|s| s.parse().ok()).unwrap_or(1);
            let np = polys.len();
            let scene = Scene::new(polys, vec![true; np]).unwrap();
            let source: Option<usize> = args.get(5).and_then(|s| s.parse().ok());
            let m = match source {
                Some(_) => AnyMethod::Clipping(ClippingOptions { tol, source, ..Default::default() }),
                None => AnyMethod::Auto(AutoOptions { obstructed_tol: tol, ..Default::default() }),
            };
            let rows: Vec<usize> = (0..np).step_by(stride).collect();
            let t0 = Instant::now();
            let r = scene.pair_rows(&rows, &m, &AtomicBool::new(false)).unwrap();
            let dt = t0.elapsed().as_secs_f64();
            let pairs: usize = r.iter().map(|x| x.len()).sum();
            if let Ok(path) = std::env::var("DUMP") {
                use std::io::Write;
                let mut w = std::io::BufWriter::new(std::fs::File::create(path).unwrap());
                for (i, row) in rows.iter().zip(&r) {
                    for (j, g, _) in row.iter() {
                        writeln!(w, "{i} {j} {g:.17e} {:.17e}", scene.polygons()[*i].area()).unwrap();
                    }
                }
            }
            println!("{np} patches, {} rows, {pairs} nonzero pairs, tol {tol:e}: {dt:.3} s", rows.len());
        }
        "points" => {
            let bvh = Bvh::new(&polys).unwrap();
            let mut evals = 0usize;
            let mut nonzero = 0usize;
            let mut total = 0.0f64;
            let t0 = Instant::now();
            let mut cand = Vec::new();
            let mut s = 0x1234_5678u64;
            let mut rnd = || {
                s ^= s << 13;
                s ^= s >> 7;
                s ^= s << 17;
                (s >> 11) as f64 / (1u64 << 53) as f64
            };
            'outer: for i in (0..polys.len()).step_by(7) {
                for j in (i + 1..polys.len()).step_by(3) {
                    cand.clear();
                    bvh.candidates_between(&polys[i], &polys[j], &[i as u32, j as u32], &mut cand);
                    if cand.is_empty() {
                        continue;
                    }
                    let bl: Vec<&Polygon> = cand.iter().map(|&k| &polys[k as usize]).collect();
                    let v = polys[i].vertices();
                    for _ in 0..20 {
                        let (a, b) = (rnd(), rnd());
                        let x = v[0] + a * (v[1] - v[0]) + b * (v[3] - v[0]);
                        let f = point_shadowed_view_factor(x, polys[i].normal(), &polys[j], &bl);
                        evals += 1;
                        if f > 0.0 {
                            nonzero += 1;
                        }
                        total += f;
                    }
                    if evals >= 200_000 {
                        break 'outer;
                    }
                }
            }
            let dt = t0.elapsed().as_secs_f64();
            println!(
                "{evals} evals ({nonzero} shadowed), {:.2} us/eval (incl. candidate queries), checksum {total:.12e}",
                dt / evals as f64 * 1e6
            );
        }
        "cands" => {
            // the candidate-blocker query of every facing pair (what every obstructed scene pays)
            let bvh = Bvh::new(&polys).unwrap();
            let t0 = Instant::now();
            let (mut pairs, mut blocked, mut cand, mut check) = (0usize, 0usize, Vec::new(), 0u64);
            for i in 0..polys.len() {
                for j in i + 1..polys.len() {
                    if nusselt_core::unobstructed::method::facing(&polys[i], &polys[j])
                        == nusselt_core::unobstructed::method::Facing::None
                    {
                        continue;
                    }
                    pairs += 1;
                    bvh.candidates_between(&polys[i], &polys[j], &[i as u32, j as u32], &mut cand);
                    blocked += !cand.is_empty() as usize;
                    for &c in &cand {
                        check = check.wrapping_mul(31).wrapping_add(c as u64 + 1);
                    }
                }
            }
            let dt = t0.elapsed().as_secs_f64();
            println!("{pairs} facing pairs, {blocked} with candidates (checksum {check:x}): {dt:.2} s one thread ({:.2} us/pair)", dt / pairs as f64 * 1e6);
        }
        "pair" => {
            let i: usize = args[3].parse().unwrap();
            let j: usize = args[4].parse().unwrap();
            let tol: f64 = args.get(5).and_then(|s| s.parse().ok()).unwrap_or(1e-6);
            let obs: Vec<Polygon> = (0..polys.len()).filter(|&k| k != i && k != j).map(|k| polys[k].clone()).collect();
            let m = AnyMethod::Auto(AutoOptions { obstructed_tol: tol, ..Default::default() });
            let t0 = Instant::now();
            let e = nusselt_core::scene::pair_view_factor(polys[i].clone(), polys[j].clone(), obs, &m).unwrap();
            println!("F {:.15e} in {:.3} s", e.value, t0.elapsed().as_secs_f64());
        }
        _ => panic!("mode rows|cands|points|pair"),
    }
}
