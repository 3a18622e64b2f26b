//! Occluders: the scene as visibility sees it. Whether a segment is blocked depends on where
//! the scene is opaque, not on how its surfaces are meshed, so coplanar polygons of the same
//! orientation that share an edge are joined wherever their union is convex: a crate face of
//! 5 x 5 tiles becomes one quad. Shaft queries, shadow casting and the kink split of the pair
//! methods then see a few large blockers instead of many tiles, and no kink planes along the
//! seams between tiles, which are not edges of anything opaque.
//!
//! Ignoring the occluder of a pair's own polygon is exact: every other member lies in that
//! polygon's plane, and a segment from a point in front of a plane to a point on it (or the
//! other way round) meets the plane only at its end.

use crate::geometry::{join_adjacent, join_convex, Polygon, Vec3};

/// Largest distance of a joined polygon's vertices from the other's plane, relative to the
/// size of the two: meshes of a flat face have their vertices on the plane up to rounding.
const COPLANAR_TOL: f64 = 1e-10;

/// Sine of the angle under which a vertex of a joined outline counts as straight and is
/// dropped: rounding of rotated meshes far from the origin leaves ~1e-13.
const STRAIGHT_TOL: f64 = 1e-10;

/// The scene's polygons joined into occluders.
#[derive(Debug, Clone)]
pub struct Occluders {
    /// The occluders (each a polygon of the scene, or a convex union of coplanar ones).
    pub polygons: Vec<Polygon>,
    /// The occluder of each scene polygon.
    pub owner: Vec<u32>,
    /// One member of each occluder (a scene polygon to name in messages).
    pub member: Vec<u32>,
}

impl Occluders {
    /// Joins `polys` greedily where coplanar, same-facing neighbours have a convex union
    /// (`join_adjacent`).
    pub fn new(polys: &[Polygon]) -> Occluders {
        let n = polys.len();
        let mut outline: Vec<Vec<Vec3>> = polys.iter().map(|p| p.vertices().to_vec()).collect();
        // each group's polygon once it has joined something (validated when joined)
        let mut joined_poly: Vec<Option<Polygon>> = vec![None; n];
        let normal: Vec<Vec3> = polys.iter().map(|p| p.normal()).collect();
        let coplanar = |g: &[Vec3], ng: Vec3, h: &[Vec3], nh: Vec3| {
            if ng.dot(nh) < 1.0 - 1e-12 {
                return false;
            }
            let (mut lo, mut hi) = (Vec3::splat(f64::INFINITY), Vec3::splat(f64::NEG_INFINITY));
            for v in g.iter().chain(h) {
                lo = lo.min(*v);
                hi = hi.max(*v);
            }
            let tol = COPLANAR_TOL * (hi - lo).length();
            h.iter().all(|v| ng.dot(*v - g[0]).abs() <= tol) && g.iter().all(|v| nh.dot(*v - h[0]).abs() <= tol)
        };
        // union-find parent of each group; a group is alive while it is its own root
        let parent = join_adjacent(
            &mut outline,
            |a: Vec3| a.to_array().map(f64::to_bits),
            |g, h, v, w| {
                let ng = normal[g];
                if !coplanar(v, ng, w, normal[h]) {
                    return None;
                }
                let turn = |p: Vec3, q: Vec3, r: Vec3| {
                    let (e, f) = (q - p, r - q);
                    (e.cross(f).dot(ng), e.dot(f), e.length() * f.length())
                };
                let u = join_convex(v, w, turn, STRAIGHT_TOL)?;
                // the union must be a valid polygon in its own right
                joined_poly[g] = Some(Polygon::with_tolerance(u.clone(), 1e-9).ok()?);
                joined_poly[h] = None;
                Some(u)
            },
        );
        let root = |mut g: usize| {
            while parent[g] != g {
                g = parent[g];
            }
            g
        };
        let mut index = vec![u32::MAX; n];
        let (mut out, mut member) = (Vec::new(), Vec::new());
        let mut owner = vec![0u32; n];
        for k in 0..n {
            let r = root(k);
            if index[r] == u32::MAX {
                index[r] = out.len() as u32;
                // a polygon that joined nothing is its own occluder
                out.push(joined_poly[r].take().unwrap_or_else(|| polys[r].clone()));
                member.push(k as u32);
            }
            owner[k] = index[r];
        }
        Occluders { polygons: out, owner, member }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn quad(x0: f64, y0: f64, x1: f64, y1: f64, z: f64) -> Polygon {
        Polygon::new(vec![Vec3::new(x0, y0, z), Vec3::new(x1, y0, z), Vec3::new(x1, y1, z), Vec3::new(x0, y1, z)])
            .unwrap()
    }

    /// n x n unit tiles of [0, n]^2 at height z, facing +z.
    fn tiles(n: usize, z: f64) -> Vec<Polygon> {
        let mut out = Vec::new();
        for i in 0..n {
            for j in 0..n {
                out.push(quad(i as f64, j as f64, i as f64 + 1.0, j as f64 + 1.0, z));
            }
        }
        out
    }

    #[test]
    fn a_tiled_square_becomes_one_occluder() {
        let o = Occluders::new(&tiles(5, 0.3));
        assert_eq!(o.polygons.len(), 1);
        let p = &o.polygons[0];
        assert_eq!(p.vertices().len(), 4, "{:?}", p.vertices());
        assert!((p.area() - 25.0).abs() < 1e-12);
        assert!(p.normal().z > 0.0);
        assert!(o.owner.iter().all(|&k| k == 0));
    }

    #[test]
    fn triangles_of_a_quad_mesh_join_and_members_stay_inside() {
        // a rotated, shifted 4 x 3 grid of quads, each split into two triangles
        let rot = glam::DQuat::from_axis_angle(Vec3::new(1.0, 2.0, 3.0).normalize(), 0.7);
        let map = |x: f64, y: f64| rot * Vec3::new(x * 0.37, y * 0.52, 0.0) + Vec3::new(1e3, -2e3, 5e2);
        let mut polys = Vec::new();
        for i in 0..4 {
            for j in 0..3 {
                let (a, b, c, d) = (
                    map(i as f64, j as f64),
                    map(i as f64 + 1.0, j as f64),
                    map(i as f64 + 1.0, j as f64 + 1.0),
                    map(i as f64, j as f64 + 1.0),
                );
                polys.push(Polygon::new(vec![a, b, c]).unwrap());
                polys.push(Polygon::new(vec![a, c, d]).unwrap());
            }
        }
        let o = Occluders::new(&polys);
        let total: f64 = polys.iter().map(Polygon::area).sum();
        let joined: f64 = o.polygons.iter().map(Polygon::area).sum();
        assert!((total - joined).abs() < 1e-9 * total);
        assert!(o.polygons.len() < 4, "{} occluders", o.polygons.len());
        // every member's centroid lies inside its occluder (same plane, inside every edge)
        for (k, p) in polys.iter().enumerate() {
            let occ = &o.polygons[o.owner[k] as usize];
            let v = occ.vertices();
            let c = p.centroid();
            assert!(occ.normal().dot(c - v[0]).abs() < 1e-9);
            for e in 0..v.len() {
                let (a, b) = (v[e], v[(e + 1) % v.len()]);
                assert!(
                    (b - a).cross(c - a).dot(occ.normal()) > 0.0,
                    "{:?} {:?}",
                    v.iter().map(|x| rot.inverse() * (*x - Vec3::new(1e3, -2e3, 5e2))).collect::<Vec<_>>(),
                    rot.inverse() * (c - Vec3::new(1e3, -2e3, 5e2))
                );
            }
        }
    }

    #[test]
    fn only_convex_unions_of_coplanar_same_facing_neighbours_join() {
        // an L of three tiles: the two arms join, the whole L would not be convex
        let l = [quad(0.0, 0.0, 1.0, 1.0, 0.0), quad(1.0, 0.0, 2.0, 1.0, 0.0), quad(0.0, 1.0, 1.0, 2.0, 0.0)];
        let o = Occluders::new(&l);
        assert_eq!(o.polygons.len(), 2);
        let areas: f64 = o.polygons.iter().map(Polygon::area).sum();
        assert!((areas - 3.0).abs() < 1e-12);
        // neighbours at a kink (a fold of 1e-6) stay apart
        let bent = Polygon::new(vec![
            Vec3::new(1.0, 0.0, 0.0),
            Vec3::new(2.0, 0.0, 1e-6),
            Vec3::new(2.0, 1.0, 1e-6),
            Vec3::new(1.0, 1.0, 0.0),
        ])
        .unwrap();
        assert_eq!(Occluders::new(&[quad(0.0, 0.0, 1.0, 1.0, 0.0), bent]).polygons.len(), 2);
        // the same square seen from behind shares the edge in the same direction: no join
        let back = Polygon::new(quad(1.0, 0.0, 2.0, 1.0, 0.0).vertices().iter().rev().copied().collect()).unwrap();
        assert_eq!(Occluders::new(&[quad(0.0, 0.0, 1.0, 1.0, 0.0), back]).polygons.len(), 2);
        // neighbours sharing only half an edge (a T-junction) stay apart
        assert_eq!(Occluders::new(&[quad(0.0, 0.0, 1.0, 2.0, 0.0), quad(1.0, 0.0, 2.0, 1.0, 0.0)]).polygons.len(), 2);
    }
}
