//! Cosine-distributed ray casting (the reverse Nusselt analogy, docs/algorithms.md §5.1).
//!
//! With x uniform on A_i (pdf 1/A_i) and a direction of pdf cos(theta)/pi about n_i, the
//! indicator that the first hit is the front of A_j has expectation F_ij. So with N rays
//! F_ij ~ N_ij / N, and all j come out of the same rays.
//!
//! Points: the 4-D Owen-scrambled Sobol sequence (Burley 2020), dims 0-1 -> direction by the
//! concentric map and Malley's lift, dims 2-3 -> point on the patch; the seed is hashed with
//! the row index so rows are decorrelated. Scrambled QMC keeps the estimator unbiased and
//! converges like about N^-0.7 for visibility-type integrands (docs/algorithms.md §5.3).
//!
//! Standard error: sqrt(F(1 - F)/N) is the binomial (independent-ray) value. For scrambled
//! Sobol points the true error is usually smaller, so this is a conservative bound, not an
//! estimate of the actual QMC error.

use super::{row_over_points, Points, RowResult};
use crate::error::Result;
use crate::geometry::Polygon;
use crate::registry::method_options;
use crate::sampling::{cosine_hemisphere, hash_seed, sobol4, PolygonSampler};
use crate::visibility::Visibility;

/// Largest ray count per row accepted.
pub const MAX_RAYS: u32 = 1 << 26;
/// Rays cast before `row_tol` is first checked (then after each doubling).
pub const ROW_TOL_FIRST_CHECK: u32 = 256;

method_options! {
    /// Options of [`raytrace_row`].
    pub struct RaytraceOptions for "raytrace" {
        /// Rays per row (1..=2^26); with `row_tol` the most a row may cast. A power of two keeps
        /// the Sobol points stratified. Default 4096 (binomial std error <= 0.0078 per entry,
        /// about 0.006 at F = 0.2).
        rays: u32,
        /// Seed; the same seed gives the same row. Default 0.
        seed: u64,
        /// Target standard error per entry, in [0, 0.5]; 0 (default) casts exactly `rays`. Else
        /// the row stops at the first ray count N = 256, 512, 1024, ... (capped at `rays`) where
        /// every entry's binomial error sqrt(F(1 - F)/N) is at most `row_tol` and N >= 3/row_tol
        /// (so an entry no ray hit has F <= row_tol at 95 %): F(1 - F) <= 1/4 bounds N by about
        /// 1/(4 row_tol^2). A row at N rays is the fixed-count row of `rays = N`
        /// (docs/algorithms.md §5.1).
        row_tol: f64,
    }
}

/// Row i of the form-factor matrix by cosine-weighted rays from area-uniform points of patch
/// i, first hits through `vis` (built over the same `scene`, ids = indices). Rays that hit a
/// back side or nothing count as lost. `std_err` holds sqrt(F(1-F)/N) per entry, N the rays
/// cast (`rays`, or fewer where `row_tol` was met first).
pub fn raytrace_row(
    scene: &[Polygon],
    vis: &dyn Visibility,
    receivers: &[bool],
    i: usize,
    opts: &RaytraceOptions,
) -> Result<RowResult> {
    opts.check()?;
    let mut cast = 0u32;
    let mut row = row_over_points(scene, receivers, i, Points::WholePatch, |eye, acc, lost| {
        let src = &scene[i];
        // the 4-D Sobol points place origin and direction jointly, so the eye gives only the frame
        let sampler = PolygonSampler::new(src);
        let seed = hash_seed(opts.seed, &[i as u64, 0x7A4_7ACE]);
        // tmin relative to the patch: skips nothing real, avoids re-hitting the source plane.
        let tmin = 1e-9 * src.radius();
        let ignore = [i as u32];
        let nr = opts.rays;
        let mut check_at = if opts.row_tol > 0.0 { ROW_TOL_FIRST_CHECK.min(nr) } else { nr };
        let tol2 = opts.row_tol * opts.row_tol;
        for k in 0..nr {
            // one work unit per ray; stop at cancellation or over budget
            if k % 1024 == 0 && !crate::work::spend(1024) {
                return false;
            }
            if k == check_at {
                // hit counts c: F(1 - F)/N <= tol^2 with F = c/N, i.e. c (N - c) <= tol^2 N^3
                // and N >= 3/tol: an entry no ray has hit has F <= 3/N at 95 % (rule of three)
                let nf = k as f64;
                if nf * opts.row_tol >= 3.0 && acc.max_value(|c| c * (nf - c)) <= tol2 * nf * nf * nf {
                    break;
                }
                check_at = check_at.saturating_mul(2).min(nr);
            }
            let q = sobol4(k, seed);
            let d = cosine_hemisphere([q[0], q[1]]);
            let dir = eye.u * d.x + eye.v * d.y + eye.n * d.z;
            let origin = sampler.sample([q[2], q[3]]);
            match vis.first_hit(origin, dir, tmin, f64::INFINITY, &ignore) {
                Some(h) if h.front && (h.id as usize) < scene.len() => acc.add(h.id, 1.0),
                _ => *lost += 1.0,
            }
            cast = k + 1;
        }
        true
    })?;
    let nf = cast.max(1) as f64;
    for e in &mut row.entries {
        e.1 /= nf;
    }
    row.std_err = Some(row.entries.iter().map(|e| (e.1 * (1.0 - e.1) / nf).sqrt()).collect());
    row.lost /= nf;
    row.samples = cast;
    Ok(row)
}

#[cfg(test)]
mod tests {
    use super::super::brute::BruteForce;
    use super::super::testkit::*;
    use super::*;
    use crate::error::Error;
    use crate::geometry::Vec3;

    fn row(scene: &[Polygon], i: usize, o: &RaytraceOptions) -> RowResult {
        raytrace_row(scene, &BruteForce { scene }, &vec![true; scene.len()], i, o).unwrap()
    }

    /// |F - exact| within 5 reported sigmas (the binomial bound).
    fn within(r: &RowResult, j: u32, exact: f64) -> bool {
        let k = r.entries.iter().position(|e| e.0 == j).unwrap();
        let se = r.std_err.as_ref().unwrap()[k];
        (r.entries[k].1 - exact).abs() <= 5.0 * se
    }

    #[test]
    fn pairs_within_reported_error_and_converging() {
        let par = parallel_squares(1.0);
        let per = perpendicular_squares();
        let (ep, eq) = (parallel_rect(1., 1., 1.), perpendicular_rect(1., 1., 1.));
        let mut err = Vec::new();
        for rays in [1u32 << 10, 1 << 14] {
            let mut e2 = 0.0;
            for seed in 0..8 {
                let o = RaytraceOptions { rays, seed, ..Default::default() };
                let (a, b) = (row(&par, 0, &o), row(&per, 0, &o));
                assert!(within(&a, 1, ep), "{a:?}");
                assert!(within(&b, 1, eq), "{b:?}");
                assert!((a.lost - (1.0 - a.get(1))).abs() < 1e-12);
                e2 += (a.get(1) - ep).powi(2) + (b.get(1) - eq).powi(2);
            }
            err.push((e2 / 16.0).sqrt());
        }
        // 16x the rays: error down by at least 4 (the N^-1/2 rate); QMC does better
        assert!(err[1] < err[0] / 4.0, "{err:?}");
        assert!(err[1] < 1.5e-3, "{err:?}");
    }

    #[test]
    fn closed_cube_and_occlusion() {
        let scene = closed_box(Vec3::ZERO, Vec3::ONE, 2, true);
        for i in [0usize, 7, 22] {
            let r = row(&scene, i, &RaytraceOptions::default());
            assert!(r.lost == 0.0, "row {i} lost {}", r.lost);
            assert!((r.sum() - 1.0).abs() < 1e-12);
        }
        // blocker halves the receiver (see hemicube::occluded_half); source is a small patch
        let [recv, block] = half_blocked();
        let scene = vec![small_square(Vec3::ZERO, 1e-3), recv, block];
        let r = row(&scene, 0, &RaytraceOptions { rays: 1 << 16, seed: 1, ..Default::default() });
        assert!(within(&r, 1, 2.0 * corner_rect(0.25, 0.25)), "{r:?}");
        assert!(within(&r, 2, 2.0 * corner_rect(0.5, 0.5)), "{r:?}");
        // non-receiver blocker: same hits on the receiver, blocker not reported
        let r2 = raytrace_row(
            &scene,
            &BruteForce { scene: &scene },
            &[true, true, false],
            0,
            &RaytraceOptions { rays: 1 << 16, seed: 1, ..Default::default() },
        )
        .unwrap();
        assert_eq!(r2.entries, vec![r.entries[0]]);
    }

    #[test]
    fn row_tol_stops_when_every_entry_meets_it() {
        // closed box: entries 0.02-0.2, so 1/(4 tol^2) bounds the rays and the check is real
        let scene = closed_box(Vec3::ZERO, Vec3::ONE, 2, true);
        for tol in [0.02, 0.005] {
            let o = RaytraceOptions { rays: 1 << 16, row_tol: tol, ..Default::default() };
            let r = row(&scene, 5, &o);
            let n = r.samples;
            assert!(n.is_power_of_two() && n >= ROW_TOL_FIRST_CHECK && n as f64 * tol >= 3.0, "{n}");
            assert!((n as f64) <= 1.0 / (4.0 * tol * tol) * 2.0, "{n} rays for tol {tol}");
            let se = r.std_err.as_ref().unwrap();
            assert!(se.iter().all(|&s| s <= tol), "{se:?}");
            // at half the rays the target was not met (else it would have stopped there)
            if n > ROW_TOL_FIRST_CHECK {
                let half = row(&scene, 5, &RaytraceOptions { rays: n / 2, ..o });
                assert!(half.std_err.unwrap().iter().any(|&s| s > tol));
            }
            // the row is the fixed-count row at that many rays, bit for bit
            assert_eq!(r.entries, row(&scene, 5, &RaytraceOptions { rays: n, row_tol: 0.0, ..o }).entries);
            // and it agrees with a much longer run within its reported errors
            let long = row(&scene, 5, &RaytraceOptions { rays: 1 << 18, ..Default::default() });
            for (k, e) in r.entries.iter().enumerate() {
                assert!((e.1 - long.get(e.0)).abs() <= 5.0 * se[k] + 1e-3, "{e:?} vs {}", long.get(e.0));
            }
        }
        // the cap holds; row_tol out of range is refused
        let capped = row(&scene, 5, &RaytraceOptions { rays: 300, row_tol: 1e-4, ..Default::default() });
        assert_eq!(capped.samples, 300);
        let vis = BruteForce { scene: &scene };
        let rec = vec![true; scene.len()];
        for t in [-0.1, 0.6, f64::NAN] {
            let o = RaytraceOptions { row_tol: t, ..Default::default() };
            assert!(matches!(raytrace_row(&scene, &vis, &rec, 0, &o).unwrap_err(), Error::InvalidArgument(_)));
        }
    }

    #[test]
    fn seeded_and_reproducible() {
        let scene = closed_box(Vec3::ZERO, Vec3::ONE, 2, true);
        let o = RaytraceOptions { rays: 256, seed: 5, ..Default::default() };
        assert_eq!(row(&scene, 3, &o), row(&scene, 3, &o));
        assert_ne!(row(&scene, 3, &o), row(&scene, 3, &RaytraceOptions { seed: 6, ..o }));
    }

    #[test]
    fn bad_input() {
        let scene = parallel_squares(1.0);
        let vis = BruteForce { scene: &scene };
        for rays in [0u32, u32::MAX] {
            let e =
                raytrace_row(&scene, &vis, &[true, true], 0, &RaytraceOptions { rays, seed: 0, ..Default::default() })
                    .unwrap_err();
            assert!(matches!(e, Error::InvalidArgument(_)));
        }
        assert!(raytrace_row(&scene, &vis, &[true], 0, &RaytraceOptions::default()).is_err());
        assert!(raytrace_row(&scene, &vis, &[true, true], 5, &RaytraceOptions::default()).is_err());
    }
}
