//! Source pieces of a row. Where another polygon stands on the source patch or passes through
//! it (a wall standing on a ground cell, a partition through a floor patch), what a point of
//! the patch sees jumps across that line: on one side the wall's face, on the other its back
//! or the inside of a solid. A Gauss rule over the whole patch does not converge across such a
//! jump (a 2 x 2 rule with two points under a building sees nothing for half the patch). The
//! patch is cut along every such chord and the rule runs on each piece, weighted by its area
//! (docs/algorithms.md §2.4).

use crate::geometry::{plane_chord, split_by_plane, Polygon, Vec3};

/// Most pieces a source is cut into; further chords are left uncut.
pub(crate) const MAX_SOURCE_PIECES: usize = 32;

/// The convex pieces of `scene[i]` cut along the chords that other polygons of the scene make
/// through its interior, or an empty vector when there is none (then the rule runs on the
/// patch unchanged). Polygons in the source's own plane (its mesh neighbours) cut nothing;
/// a chord along the patch's boundary or touching it in a point cuts nothing either.
pub(crate) fn source_pieces(scene: &[Polygon], i: usize) -> Vec<Vec<Vec3>> {
    let src = &scene[i];
    let (c, n, r) = (src.centroid(), src.normal(), src.radius());
    let tol = 1e-9 * r;
    let mut pieces: Vec<Vec<Vec3>> = Vec::new();
    let mut cut = false;
    for (j, b) in scene.iter().enumerate() {
        let h = n.dot(b.centroid() - c);
        if j == i || h.abs() > b.radius() || b.centroid().distance(c) > r + b.radius() {
            continue; // cannot reach the patch's plane within the patch's sphere
        }
        let btol = 1e-9 * b.radius();
        if b.vertices().iter().all(|x| n.dot(*x - c).abs() <= btol) {
            continue; // coplanar
        }
        let Some((p, q)) = plane_chord(b, c, n) else { continue };
        let len = p.distance(q);
        if !(len > tol) {
            continue;
        }
        let u = (q - p) / len;
        let m = n.cross(u); // normal of the cutting plane through the chord
        if pieces.is_empty() {
            let v = src.vertices();
            pieces = src.triangulate().iter().map(|t| vec![v[t[0]], v[t[1]], v[t[2]]]).collect();
        }
        let mut next = Vec::with_capacity(pieces.len() + 2);
        for (k, piece) in pieces.iter().enumerate() {
            if next.len() + (pieces.len() - k) >= MAX_SOURCE_PIECES || !chord_cuts(piece, p, u, m, len, tol) {
                next.push(piece.clone());
                continue;
            }
            cut = true;
            split_by_plane(piece, p, m, tol, &mut next);
        }
        pieces = next;
    }
    if !cut {
        pieces.clear();
    }
    pieces
}

/// True if the chord from p along u (length len), on the plane with normal m, passes through
/// the convex piece's interior: the piece has vertices on both sides of the plane and the
/// chord overlaps the piece's section of the line.
fn chord_cuts(piece: &[Vec3], p: Vec3, u: Vec3, m: Vec3, len: f64, tol: f64) -> bool {
    let side: Vec<f64> = piece.iter().map(|x| m.dot(*x - p)).collect();
    if !(side.iter().any(|&s| s > tol) && side.iter().any(|&s| s < -tol)) {
        return false;
    }
    let (mut slo, mut shi) = (f64::INFINITY, f64::NEG_INFINITY);
    for k in 0..piece.len() {
        let k1 = (k + 1) % piece.len();
        let (a, b) = (side[k], side[k1]);
        if (a <= 0.0) != (b <= 0.0) {
            let x = piece[k] + (piece[k1] - piece[k]) * (a / (a - b));
            let s = u.dot(x - p);
            slo = slo.min(s);
            shi = shi.max(s);
        }
    }
    shi.min(len) - slo.max(0.0) > tol
}

#[cfg(test)]
mod tests {
    use super::*;

    fn quad(v: [[f64; 3]; 4]) -> Polygon {
        Polygon::new(v.iter().map(|&x| Vec3::from(x)).collect()).unwrap()
    }

    fn area(piece: &[Vec3]) -> f64 {
        (1..piece.len() - 1).map(|k| 0.5 * (piece[k] - piece[0]).cross(piece[k + 1] - piece[0]).length()).sum()
    }

    #[test]
    fn a_standing_wall_cuts_the_cell_and_neighbours_do_not() {
        let cell = quad([[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [1.0, 1.0, 0.0], [0.0, 1.0, 0.0]]);
        let neighbour = quad([[1.0, 0.0, 0.0], [2.0, 0.0, 0.0], [2.0, 1.0, 0.0], [1.0, 1.0, 0.0]]);
        let on_edge = quad([[1.0, 0.0, 0.0], [1.0, 1.0, 0.0], [1.0, 1.0, 1.0], [1.0, 0.0, 1.0]]);
        let touching = quad([[1.0, 1.0, 0.0], [2.0, 2.0, 0.0], [2.0, 2.0, 1.0], [1.5, 1.5, 1.0]]);
        assert!(source_pieces(&[cell.clone(), neighbour, on_edge, touching], 0).is_empty());
        // a wall standing at x = 0.25 over the whole cell, and one passing through at y = 0.5
        // that ends half way across
        let wall = quad([[0.25, -1.0, 0.0], [0.25, 2.0, 0.0], [0.25, 2.0, 1.0], [0.25, -1.0, 1.0]]);
        let through = quad([[0.5, 0.5, -1.0], [2.0, 0.5, -1.0], [2.0, 0.5, 1.0], [0.5, 0.5, 1.0]]);
        let pieces = source_pieces(&[cell.clone(), wall, through], 0);
        let total: f64 = pieces.iter().map(|p| area(p)).sum();
        assert!((total - 1.0).abs() < 1e-12);
        // no piece straddles either chord
        for p in &pieces {
            assert!(p.iter().all(|x| x.x >= 0.25 - 1e-12) || p.iter().all(|x| x.x <= 0.25 + 1e-12));
            let right = p.iter().all(|x| x.x >= 0.5 - 1e-12);
            assert!(!right || p.iter().all(|x| x.y >= 0.5 - 1e-12) || p.iter().all(|x| x.y <= 0.5 + 1e-12));
        }
        let left: f64 = pieces.iter().filter(|p| p.iter().all(|x| x.x <= 0.25 + 1e-12)).map(|p| area(p)).sum();
        assert!((left - 0.25).abs() < 1e-12);
    }
}
