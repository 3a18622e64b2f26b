//! Ray-casting speed of `raytrace` rows on the urban grid of bench/scenes.py (no Python), on
//! one thread: rays per CPU second (user + sys of this thread, from /proc) and the BVH build.
//!     cargo run --release -p nusselt-core --example raytrace_urban -- [K=12] [ROWS=200] [RAYS=4096]
//! K = 12 is the 23 040-patch scene; ROWS rows spread evenly over the scene are traced.
use nusselt_core::hemisphere::{raytrace_row, RaytraceOptions};
use nusselt_core::visibility::Bvh;
use std::time::Instant;

#[path = "common/urban.rs"]
mod urban;

/// CPU seconds (user + sys) of the calling thread; Linux only (NaN elsewhere).
fn thread_cpu() -> f64 {
    let Ok(s) = std::fs::read_to_string("/proc/thread-self/stat") else { return f64::NAN };
    // fields after the command name (which is in parentheses and may hold spaces)
    let rest = &s[s.rfind(')').map_or(0, |k| k + 2)..];
    let f: Vec<&str> = rest.split_whitespace().collect();
    let ticks: f64 = f[11].parse::<f64>().unwrap_or(f64::NAN) + f[12].parse::<f64>().unwrap_or(f64::NAN);
    ticks / 100.0 // USER_HZ is 100 on Linux
}

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let arg = |k: usize, d: usize| args.get(k).and_then(|s| s.parse().ok()).unwrap_or(d);
    let (k, rows, rays) = (arg(1, 12), arg(2, 200), arg(3, 4096) as u32);
    let scene = urban::urban(k);
    let n = scene.len();
    let rec = vec![true; n];
    let (c0, t0) = (thread_cpu(), Instant::now());
    let bvh = Bvh::new(&scene).unwrap();
    let (c1, t1) = (thread_cpu(), Instant::now());
    println!(
        "urban k={k}: {n} patches, {} triangles; BVH build {:.3} s CPU ({:.3} s wall)",
        bvh.triangle_count(),
        c1 - c0,
        (t1 - t0).as_secs_f64()
    );
    let opts = RaytraceOptions { rays, ..Default::default() };
    let step = (n / rows.max(1)).max(1);
    let (mut traced, mut sum, mut lost) = (0u64, 0.0, 0.0);
    let mut count = 0;
    for i in (0..n).step_by(step) {
        let r = raytrace_row(&scene, &bvh, &rec, i, &opts).unwrap();
        traced += r.samples as u64;
        sum += r.sum();
        lost += r.lost;
        count += 1;
    }
    let (c2, t2) = (thread_cpu(), Instant::now());
    let cpu = c2 - c1;
    println!(
        "raytrace: {count} rows x {rays} rays: {traced} rays in {cpu:.2} s CPU ({:.2} s wall): {:.3} M rays/s per core; \
         mean row sum {:.4}, mean lost {:.4}",
        (t2 - t1).as_secs_f64(),
        traced as f64 / cpu / 1e6,
        sum / count as f64,
        lost / count as f64
    );
}
