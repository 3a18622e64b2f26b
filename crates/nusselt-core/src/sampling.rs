//! Low-discrepancy points and the maps that carry them onto disks, hemispheres and polygons.
//!
//! * Owen-scrambled Sobol points (Burley, "Practical Hash-based Owen Scrambling", JCGT 9(4)
//!   2020) from the `sobol_burley` crate, extended past its 2^16-point limit by giving each
//!   block of 2^16 indices its own seed (Burley's padding/decorrelation by seed).
//! * The Shirley-Chiu concentric map square -> disk, which preserves area ratios up to the
//!   constant pi/4 and keeps strata compact; lifted to the hemisphere it gives Malley's
//!   cosine-weighted directions (pbrt `ConcentricSampleDisk`, `CosineSampleHemisphere`).
//! * Area-uniform points on triangles and (possibly concave) polygons.
//!
//! Everything is a pure function of its inputs and a seed, so results are reproducible and
//! the functions can run on any number of threads.

use crate::geometry::{Polygon, Vec3};
use std::f64::consts::FRAC_PI_4;

/// Largest index `sobol_burley` accepts in one scrambled sequence.
const SOBOL_BLOCK: u32 = 1 << 16;

/// SplitMix64 finaliser: a bijective 64-bit mixer (Steele et al. 2014).
#[inline]
pub fn mix64(mut z: u64) -> u64 {
    z = z.wrapping_add(0x9E37_79B9_7F4A_7C15);
    z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
    z ^ (z >> 31)
}

/// Hashes a seed with a list of integers (row index, sample index, ...) into 64 bits.
#[inline]
pub fn hash_seed(seed: u64, parts: &[u64]) -> u64 {
    parts.iter().fold(mix64(seed), |h, &p| mix64(h ^ p.wrapping_mul(0xD6E8_FEB8_6659_FD93)))
}

/// A uniform number in [0, 1) from a hash (53 random bits).
#[inline]
pub fn hash_unit(seed: u64, parts: &[u64]) -> f64 {
    (hash_seed(seed, parts) >> 11) as f64 * (1.0 / (1u64 << 53) as f64)
}

/// Point `index` of the 4-D Owen-scrambled Sobol sequence with the given seed, in [0,1)^4.
///
/// Dimensions 0 and 1 form a (0,2)-sequence: every aligned block of 2^k points is stratified
/// in every elementary interval of area 2^-k of the unit square. Indices past 2^16 start a
/// new, independently scrambled block (seed hashed with the block number), so any u32 index
/// is valid; each block of 2^16 keeps its own stratification.
#[inline]
pub fn sobol4(index: u32, seed: u64) -> [f64; 4] {
    let block = index / SOBOL_BLOCK;
    let s = hash_seed(seed, &[block as u64]) as u32;
    let u = sobol_burley::sample_4d(index % SOBOL_BLOCK, 0, s);
    [u[0] as f64, u[1] as f64, u[2] as f64, u[3] as f64]
}

/// Shirley-Chiu concentric map of the unit square onto the unit disk.
///
/// a = 2u1 - 1, b = 2u2 - 1; if |a| > |b|: r = a, phi = (pi/4)(b/a), else r = b,
/// phi = pi/2 - (pi/4)(a/b). The square ring max(|a|,|b|) = r maps to the circle of radius
/// r, and areas are scaled by exactly pi/4, so equal-area squares map to equal-area cells.
/// Source: Shirley & Chiu, "A low distortion map between disk and square", JGT 2(3) 1997;
/// pbrt-v3 `ConcentricSampleDisk`.
#[inline]
pub fn concentric_disk(u: [f64; 2]) -> [f64; 2] {
    let a = 2.0 * u[0] - 1.0;
    let b = 2.0 * u[1] - 1.0;
    if a == 0.0 && b == 0.0 {
        return [0.0, 0.0];
    }
    let (r, phi) =
        if a.abs() > b.abs() { (a, FRAC_PI_4 * (b / a)) } else { (b, 2.0 * FRAC_PI_4 - FRAC_PI_4 * (a / b)) };
    [r * phi.cos(), r * phi.sin()]
}

/// Malley's method: a disk point lifted to the hemisphere, z = sqrt(1 - x^2 - y^2).
/// If the disk point is uniform, the direction has density cos(theta)/pi (Nusselt analogue).
#[inline]
pub fn lift_to_hemisphere(d: [f64; 2]) -> Vec3 {
    let z = (1.0 - d[0] * d[0] - d[1] * d[1]).max(0.0).sqrt();
    Vec3::new(d[0], d[1], z)
}

/// Cosine-weighted direction about +z (pdf cos(theta)/pi) from a point of the unit square.
#[inline]
pub fn cosine_hemisphere(u: [f64; 2]) -> Vec3 {
    lift_to_hemisphere(concentric_disk(u))
}

/// Area-uniform point of triangle (a, b, c) from a point of the unit square:
/// x = (1 - sqrt(u1)) a + sqrt(u1)(1 - u2) b + sqrt(u1) u2 c (pbrt / Turk 1990).
#[inline]
pub fn uniform_triangle(u: [f64; 2], a: Vec3, b: Vec3, c: Vec3) -> Vec3 {
    let s = u[0].sqrt();
    a * (1.0 - s) + b * (s * (1.0 - u[1])) + c * (s * u[1])
}

/// Area-uniform points on a planar polygon (convex or concave): the polygon is triangulated
/// once; u1 picks a triangle through the cumulative area table and is rescaled to [0,1)
/// inside it, so strata of the input square stay compact on the polygon.
#[derive(Debug, Clone)]
pub struct PolygonSampler {
    tris: Vec<[Vec3; 3]>,
    /// Cumulative area fractions, last entry 1.
    cdf: Vec<f64>,
}

impl PolygonSampler {
    pub fn new(poly: &Polygon) -> Self {
        let v = poly.vertices();
        let n = poly.normal();
        let mut tris = Vec::new();
        let mut cdf = Vec::new();
        let mut total = 0.0;
        for t in poly.triangulate() {
            let (a, b, c) = (v[t[0]], v[t[1]], v[t[2]]);
            let area = 0.5 * (b - a).cross(c - a).dot(n);
            if area > 0.0 {
                total += area;
                tris.push([a, b, c]);
                cdf.push(total);
            }
        }
        if tris.is_empty() {
            // Cannot happen for a validated polygon (positive area); keep a usable sampler.
            tris.push([v[0], v[1], v[2]]);
            cdf.push(1.0);
            total = 1.0;
        }
        for c in &mut cdf {
            *c /= total;
        }
        PolygonSampler { tris, cdf }
    }

    /// Maps a point of the unit square to an area-uniform point of the polygon.
    pub fn sample(&self, u: [f64; 2]) -> Vec3 {
        let k = self.cdf.partition_point(|&c| c <= u[0]).min(self.tris.len() - 1);
        let lo = if k == 0 { 0.0 } else { self.cdf[k - 1] };
        let width = self.cdf[k] - lo;
        let u0 = if width > 0.0 { ((u[0] - lo) / width).clamp(0.0, 1.0) } else { 0.5 };
        let [a, b, c] = self.tris[k];
        uniform_triangle([u0, u[1]], a, b, c)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn concentric_map_is_area_preserving_and_inside() {
        // Equal squares -> equal disk areas: each image of an s x s grid cell, its boundary
        // mapped at 64 points, has area pi/s^2 by the shoelace formula.
        let s = 64;
        let mut total = 0.0;
        let mut max_dev: f64 = 0.0;
        let target = std::f64::consts::PI / (s * s) as f64;
        for i in 0..s {
            for j in 0..s {
                // subdivide each cell boundary finely so curved edges are resolved
                let m = 16;
                let mut pts = Vec::new();
                let (x0, y0, h) = (i as f64 / s as f64, j as f64 / s as f64, 1.0 / s as f64);
                for k in 0..m {
                    pts.push([x0 + h * k as f64 / m as f64, y0]);
                }
                for k in 0..m {
                    pts.push([x0 + h, y0 + h * k as f64 / m as f64]);
                }
                for k in 0..m {
                    pts.push([x0 + h - h * k as f64 / m as f64, y0 + h]);
                }
                for k in 0..m {
                    pts.push([x0, y0 + h - h * k as f64 / m as f64]);
                }
                let d: Vec<[f64; 2]> = pts.iter().map(|&p| concentric_disk(p)).collect();
                let mut a = 0.0;
                for k in 0..d.len() {
                    let (p, q) = (d[k], d[(k + 1) % d.len()]);
                    a += p[0] * q[1] - p[1] * q[0];
                }
                let a = 0.5 * a.abs();
                total += a;
                max_dev = max_dev.max((a / target - 1.0).abs());
            }
        }
        // polygonal approximation of arcs under-estimates slightly (chords, 16 per side)
        assert!((total - std::f64::consts::PI).abs() < 1e-3, "{total}");
        assert!(max_dev < 2e-3, "cell area deviation {max_dev}");
        for k in 0..1000 {
            let u = [hash_unit(1, &[k]), hash_unit(2, &[k])];
            let d = concentric_disk(u);
            assert!(d[0] * d[0] + d[1] * d[1] <= 1.0 + 1e-15);
        }
    }

    #[test]
    fn cosine_directions_have_cosine_density() {
        // E[cos theta] = 2/3 and E[cos^2 theta] = 1/2 under pdf cos/pi; P(theta < 45 deg) = 1/2.
        let n = 1 << 14;
        let (mut m1, mut m2, mut inside) = (0.0, 0.0, 0usize);
        for k in 0..n {
            let u = sobol4(k, 7);
            let d = cosine_hemisphere([u[0], u[1]]);
            assert!((d.length() - 1.0).abs() < 1e-12 && d.z >= 0.0);
            m1 += d.z;
            m2 += d.z * d.z;
            if d.z > std::f64::consts::FRAC_1_SQRT_2 {
                inside += 1;
            }
        }
        let nf = n as f64;
        assert!((m1 / nf - 2.0 / 3.0).abs() < 1e-4, "{}", m1 / nf);
        assert!((m2 / nf - 0.5).abs() < 1e-4, "{}", m2 / nf);
        assert!((inside as f64 / nf - 0.5).abs() < 1e-3);
    }

    #[test]
    fn sobol_prefixes_are_stratified_and_seeded() {
        // First 16 points of any seed: one point in each 4x4 cell of dims (0,1).
        for seed in [0u64, 1, 99] {
            let mut seen = [false; 16];
            for k in 0..16 {
                let u = sobol4(k, seed);
                let c = (u[0] * 4.0) as usize + 4 * (u[1] * 4.0) as usize;
                assert!(!seen[c], "seed {seed}: cell {c} twice");
                seen[c] = true;
            }
        }
        assert_eq!(sobol4(5, 3), sobol4(5, 3));
        assert_ne!(sobol4(5, 3), sobol4(5, 4));
        // beyond the 2^16 block: still valid and in range
        let u = sobol4((1 << 16) + 3, 3);
        assert!(u.iter().all(|&x| (0.0..1.0).contains(&x)));
        assert_ne!(u, sobol4(3, 3));
    }

    #[test]
    fn polygon_sampler_is_area_uniform_on_concave_outline() {
        // L-shape of area 3: mean of the points equals the area centroid, and each unit
        // square of the L gets one third of the points.
        let p = Polygon::new(crate::geometry::tests::ell()).unwrap();
        let s = PolygonSampler::new(&p);
        let n = 1 << 14;
        let mut mean = Vec3::ZERO;
        let mut counts = [0usize; 3];
        for k in 0..n {
            let u = sobol4(k, 11);
            let x = s.sample([u[0], u[1]]);
            assert!(x.z.abs() < 1e-15 && x.x >= -1e-15 && x.y >= -1e-15);
            assert!(!(x.x > 1.0 + 1e-12 && x.y > 1.0 + 1e-12), "outside the L: {x}");
            mean += x;
            let c = if x.y >= 1.0 {
                2
            } else if x.x >= 1.0 {
                1
            } else {
                0
            };
            counts[c] += 1;
        }
        mean /= n as f64;
        assert!((mean - p.centroid()).length() < 2e-3, "{mean} vs {}", p.centroid());
        for c in counts {
            assert!((c as f64 / n as f64 - 1.0 / 3.0).abs() < 5e-3, "{counts:?}");
        }
    }
}
