//! Planar polygons: validation, derived quantities, half-space clipping, triangulation.
//!
//! Conventions: a polygon is a list of n >= 3 vertices, counter-clockwise seen
//! from its front; the normal follows the right-hand rule. Every tolerance is relative to
//! the polygon's own size, so the same polygon in metres and millimetres behaves the same.

pub use glam::DVec3 as Vec3;

/// Relative planarity tolerance: the largest allowed distance of a vertex from the
/// best-fit plane, as a fraction of the polygon's diameter.
pub const DEFAULT_PLANARITY_TOL: f64 = 1e-6;

/// Relative tolerance below which two points (or a point and a plane) count as coincident.
pub const COINCIDENT_TOL: f64 = 1e-12;

#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum GeometryError {
    #[error("vertex {0} has a NaN or infinite coordinate")]
    NonFinite(usize),
    #[error("needs at least 3 distinct vertices, has {0}")]
    TooFewVertices(usize),
    #[error("has zero area (all vertices collinear or coincident)")]
    ZeroArea,
    #[error("is not planar: vertex {vertex} lies {relative:.2e} (relative to the polygon size) off its plane, tolerance {tol:.1e}")]
    NonPlanar { vertex: usize, relative: f64, tol: f64 },
    #[error("has a self-intersecting outline: edges {0} and {1} cross")]
    SelfIntersecting(usize, usize),
}

impl GeometryError {
    /// A short stable name of the problem, for callers that act on it rather than print it.
    pub fn kind(&self) -> &'static str {
        match self {
            GeometryError::NonFinite(_) => "non_finite",
            GeometryError::TooFewVertices(_) => "too_few_vertices",
            GeometryError::ZeroArea => "zero_area",
            GeometryError::NonPlanar { .. } => "non_planar",
            GeometryError::SelfIntersecting(..) => "self_intersecting",
        }
    }

    /// The polygon has no area to speak of (a `repair` may drop it instead of refusing it).
    pub fn is_degenerate(&self) -> bool {
        matches!(self, GeometryError::TooFewVertices(_) | GeometryError::ZeroArea)
    }
}

/// Validates every outline in turn: outline k becomes a [`Polygon`] or an
/// [`Error::Geometry`](crate::Error::Geometry) with index k, so that the caller, which knows
/// where each outline came from (a file line, a named object), can name the face.
pub fn validate_all(
    outlines: impl IntoIterator<Item = Vec<Vec3>>,
    planarity_tol: f64,
) -> Vec<Result<Polygon, crate::Error>> {
    outlines
        .into_iter()
        .enumerate()
        .map(|(index, v)| {
            Polygon::with_tolerance(v, planarity_tol).map_err(|source| crate::Error::Geometry { index, source })
        })
        .collect()
}

/// A validated planar polygon with its derived quantities.
#[derive(Debug, Clone)]
pub struct Polygon {
    vertices: Vec<Vec3>,
    normal: Vec3,
    area: f64,
    centroid: Vec3,
    radius: f64,
}

impl Polygon {
    /// Validates `vertices` with the default planarity tolerance.
    pub fn new(vertices: Vec<Vec3>) -> Result<Self, GeometryError> {
        Self::with_tolerance(vertices, DEFAULT_PLANARITY_TOL)
    }

    /// Validates `vertices`; `planarity_tol` is relative to the polygon's diameter.
    /// Consecutive repeated vertices (and a closing vertex equal to the first) are dropped.
    pub fn with_tolerance(vertices: Vec<Vec3>, planarity_tol: f64) -> Result<Self, GeometryError> {
        if let Some(i) = vertices.iter().position(|v| !v.is_finite()) {
            return Err(GeometryError::NonFinite(i));
        }
        let scale = bounding_diameter(&vertices);
        let vertices = drop_repeated(vertices, COINCIDENT_TOL * scale);
        if vertices.len() < 3 {
            return Err(GeometryError::TooFewVertices(vertices.len()));
        }
        let nv = newell_normal(&vertices);
        let twice_area = nv.length();
        if !(twice_area > 1e-14 * scale * scale) {
            // A bow-tie has zero net area but is not degenerate: name the real problem.
            if let Some(n) = widest_cross(&vertices).filter(|n| n.length() > 1e-14 * scale * scale) {
                if let Some((a, b)) = self_intersection(&vertices, n.normalize()) {
                    return Err(GeometryError::SelfIntersecting(a, b));
                }
            }
            return Err(GeometryError::ZeroArea);
        }
        let normal = nv / twice_area;
        let centroid = area_centroid(&vertices, normal);
        // Planarity: distance of each vertex from the plane through the centroid.
        for (i, v) in vertices.iter().enumerate() {
            let rel = (v - centroid).dot(normal).abs() / scale;
            if rel > planarity_tol {
                return Err(GeometryError::NonPlanar { vertex: i, relative: rel, tol: planarity_tol });
            }
        }
        if vertices.len() > 3 {
            if let Some((a, b)) = self_intersection(&vertices, normal) {
                return Err(GeometryError::SelfIntersecting(a, b));
            }
        }
        let radius = vertices.iter().map(|v| v.distance(centroid)).fold(0.0, f64::max);
        Ok(Polygon { vertices, normal, area: 0.5 * twice_area, centroid, radius })
    }

    pub fn vertices(&self) -> &[Vec3] {
        &self.vertices
    }
    /// Unit normal (right-hand rule).
    pub fn normal(&self) -> Vec3 {
        self.normal
    }
    pub fn area(&self) -> f64 {
        self.area
    }
    /// Area centroid (lies on the polygon's plane).
    pub fn centroid(&self) -> Vec3 {
        self.centroid
    }
    /// Radius of the smallest centroid-centred sphere containing the polygon.
    pub fn radius(&self) -> f64 {
        self.radius
    }
    /// True if `point` lies strictly in front of the polygon's plane (beyond `tol` * radius).
    pub fn in_front(&self, point: Vec3, tol: f64) -> bool {
        (point - self.centroid).dot(self.normal) > tol * self.radius
    }
    /// Triangulation of the (possibly concave) outline as vertex-index triples.
    pub fn triangulate(&self) -> Vec<[usize; 3]> {
        triangulate(&self.vertices, self.normal)
    }
    /// True when every corner turns left about the normal by a sine of at least 1e-12
    /// (strictly convex: a quadrilateral's bilinear map is then one-to-one), by
    /// `turns_left`. Python's `Scene.refined` and the area rules split such quads bilinearly.
    pub fn is_strictly_convex(&self) -> bool {
        turns_left(&self.vertices, turn_about(self.normal), 1e-12)
    }
}

/// The union of the convex outlines `s` and `t` (the same orientation) when they share an
/// edge (the same two points, in opposite directions, as neighbouring tiles of one mesh have
/// them bit for bit) and the union is convex; vertices left on a straight line at the joint
/// are dropped. `turn(a, b, c)` gives the cross and dot products of a -> b and b -> c (the
/// cross positive for a turn to the left of the outline) and their scale, the product of the
/// two lengths; a turn whose sine is within `straight` of 0 in the forward direction counts
/// as straight. (Outlines that still carry straight vertices can share two edges in a row:
/// the union then doubles back along one, a turn of sine 0 that is not straight.)
pub(crate) fn join_convex<P: Copy + PartialEq>(
    s: &[P],
    t: &[P],
    turn: impl Fn(P, P, P) -> (f64, f64, f64),
    straight: f64,
) -> Option<Vec<P>> {
    let (m, l) = (s.len(), t.len());
    for i in 0..m {
        let (u, v) = (s[i], s[(i + 1) % m]);
        for j in 0..l {
            if t[j] != v || t[(j + 1) % l] != u {
                continue;
            }
            // s from v round to u, then t after u round to before v
            let mut out: Vec<P> = (1..=m).map(|k| s[(i + k) % m]).collect();
            out.extend((2..l).map(|k| t[(j + k) % l]));
            let n = out.len();
            let convex = (0..n).all(|k| {
                let (cross, dot, scale) = turn(out[k], out[(k + 1) % n], out[(k + 2) % n]);
                cross > straight * scale || (cross >= -straight * scale && dot > 0.0)
            });
            if !convex {
                return None;
            }
            // drop straight vertices (the joint's ends, when the union continues an edge)
            let mut k = 0;
            while k < out.len() && out.len() > 3 {
                let n = out.len();
                let (cross, _, scale) = turn(out[(k + n - 1) % n], out[k], out[(k + 1) % n]);
                if cross.abs() <= straight * scale {
                    out.remove(k);
                } else {
                    k += 1;
                }
            }
            return Some(out);
        }
    }
    None
}

/// True when the closed outline `v` turns left at every corner by at least `sine` times the
/// corner's scale: the one convexity test of the crate. `turn(a, b, c)` gives the cross product
/// of a -> b and b -> c (positive for a left turn) and its scale (the product of the two
/// lengths, [`turn_2d`] and [`turn_about`]; a fixed scale makes `sine` an absolute margin).
/// A small positive `sine` asks for strictly convex corners, a small negative one lets
/// corners that are straight within rounding pass (a vertex on an edge, as clipping leaves).
pub(crate) fn turns_left<P: Copy>(v: &[P], turn: impl Fn(P, P, P) -> (f64, f64), sine: f64) -> bool {
    let m = v.len();
    (0..m).all(|i| {
        let (cross, scale) = turn(v[i], v[(i + 1) % m], v[(i + 2) % m]);
        cross >= sine * scale
    })
}

/// The turn at b on the 2-D path a -> b -> c, for [`turns_left`].
#[inline]
pub(crate) fn turn_2d(a: [f64; 2], b: [f64; 2], c: [f64; 2]) -> (f64, f64) {
    let (e, f) = ([b[0] - a[0], b[1] - a[1]], [c[0] - b[0], c[1] - b[1]]);
    (e[0] * f[1] - e[1] * f[0], ((e[0] * e[0] + e[1] * e[1]) * (f[0] * f[0] + f[1] * f[1])).sqrt())
}

/// The turn at b on the path a -> b -> c about the normal `n` (left = counter-clockwise seen
/// from the front), for [`turns_left`].
pub(crate) fn turn_about(n: Vec3) -> impl Fn(Vec3, Vec3, Vec3) -> (f64, f64) {
    move |a, b, c| {
        let (e, f) = (b - a, c - b);
        (e.cross(f).dot(n), (e.length_squared() * f.length_squared()).sqrt())
    }
}

/// Joins edge-adjacent outlines greedily, for occluders (coplanar tiles) and for shadows (of
/// tiles): each live outline in turn takes in neighbours across its edges (an outline that
/// has the edge the other way round, found by the end points' `key`) while
/// `join(g, h, outline g, outline h)` gives their union, in passes until nothing joins (a row
/// of tiles becomes a strip in one pass, neighbouring strips join in the next). Returns each
/// outline's group: itself while alive, else the outline it went into (follow to the root);
/// the outlines that went into another are left empty.
pub(crate) fn join_adjacent<P: Copy + PartialEq, K: std::hash::Hash + Eq>(
    outline: &mut [Vec<P>],
    key: impl Fn(P) -> K,
    mut join: impl FnMut(usize, usize, &[P], &[P]) -> Option<Vec<P>>,
) -> Vec<usize> {
    let n = outline.len();
    let mut parent: Vec<usize> = (0..n).collect();
    // directed edge -> the outline that had it when it was recorded (checked on use)
    let mut edges: std::collections::HashMap<(K, K), usize> = std::collections::HashMap::new();
    let record = |edges: &mut std::collections::HashMap<(K, K), usize>, g: usize, v: &[P]| {
        for k in 0..v.len() {
            edges.insert((key(v[k]), key(v[(k + 1) % v.len()])), g);
        }
    };
    for (g, v) in outline.iter().enumerate() {
        record(&mut edges, g, v);
    }
    let has_edge = |v: &[P], a: P, b: P| (0..v.len()).any(|k| v[k] == a && v[(k + 1) % v.len()] == b);
    loop {
        let mut joined = false;
        for g in 0..n {
            if parent[g] != g {
                continue;
            }
            while let Some((h, u)) = {
                let v = &outline[g];
                (0..v.len()).find_map(|k| {
                    let (a, b) = (v[k], v[(k + 1) % v.len()]);
                    let &h = edges.get(&(key(b), key(a)))?;
                    if h == g || parent[h] != h || !has_edge(&outline[h], b, a) {
                        return None;
                    }
                    Some((h, join(g, h, v, &outline[h])?))
                })
            } {
                parent[h] = g;
                outline[h] = Vec::new();
                record(&mut edges, g, &u);
                outline[g] = u;
                joined = true;
            }
        }
        if !joined {
            return parent;
        }
    }
}

/// Newell's normal: a vector along the polygon normal whose length is twice the area.
/// Exact for planar polygons, convex or concave, and robust for nearly degenerate ones.
pub fn newell_normal(v: &[Vec3]) -> Vec3 {
    let n = v.len();
    let o = v[0]; // shifting the origin improves rounding for far-away polygons
    let mut acc = Vec3::ZERO;
    for i in 1..n.saturating_sub(1) {
        acc += (v[i] - o).cross(v[i + 1] - o);
    }
    acc
}

/// A double-double number hi + lo (|lo| about an ulp of hi at most): the few quantities that
/// must keep more digits than their inputs' rounding leaves (a needle's plane, a vertex's
/// height over a nearly coplanar plane) are summed in it from error-free differences and
/// products (TwoSum, FMA), and rounded once at the end.
#[derive(Clone, Copy, Debug)]
struct Dd(f64, f64);

/// (s, e) with s + e = a + b exactly (Knuth's TwoSum).
fn two_sum(a: f64, b: f64) -> (f64, f64) {
    let s = a + b;
    let bb = s - a;
    (s, (a - (s - bb)) + (b - bb))
}

impl Dd {
    const ZERO: Dd = Dd(0.0, 0.0);
    fn add(self, x: f64) -> Dd {
        let (s, e) = two_sum(self.0, x);
        Dd(s, self.1 + e)
    }
    // += (a.0 + a.1) (b.0 + b.1), dropping a.1 b.1
    fn add_product(self, a: (f64, f64), b: (f64, f64)) -> Dd {
        let p = a.0 * b.0;
        let e = a.0.mul_add(b.0, -p);
        let d = self.add(p);
        Dd(d.0, d.1 + e + a.0 * b.1 + a.1 * b.0)
    }
    fn pair(self) -> (f64, f64) {
        let (s, e) = two_sum(self.0, self.1);
        (s, e)
    }
    fn value(self) -> f64 {
        self.0 + self.1
    }
}

/// Newell's vector of `v` (as [`newell_normal`]) in double-double.
fn newell_dd(v: &[Vec3]) -> [Dd; 3] {
    let o = v[0];
    let diff = |x: Vec3| [two_sum(x.x, -o.x), two_sum(x.y, -o.y), two_sum(x.z, -o.z)];
    let mut acc = [Dd::ZERO; 3];
    for i in 1..v.len().saturating_sub(1) {
        let (a, b) = (diff(v[i]), diff(v[i + 1]));
        for (k, (j, l)) in [(1, 2), (2, 0), (0, 1)].into_iter().enumerate() {
            // (a x b)_k = a_j b_l - a_l b_j
            acc[k] = acc[k].add_product(a[j], b[l]).add_product((-a[l].0, -a[l].1), b[j]);
        }
    }
    acc
}

/// [`newell_normal`] in double-double arithmetic, rounded once at the end: the direction is
/// accurate to a few eps even for a needle, whose plane in plain arithmetic is known only to
/// ~eps / sin(its smallest angle) (8e-13 rad for a triangle 2e-5 wide), which tilts
/// everything measured from that plane.
pub fn accurate_normal(v: &[Vec3]) -> Vec3 {
    let n = newell_dd(v);
    Vec3::new(n[0].value(), n[1].value(), n[2].value())
}

/// The plane of a polygon for signed heights accurate to a few eps of themselves: Newell's
/// vector N and the mean of N . v over the vertices, both in double-double. A height
/// measured in plain arithmetic from a rounded centroid along a rounded normal carries an
/// error of eps times the coordinates: for two triangles whose planes meet at 1e-9 rad that
/// is 1e-7 of the heights that place the cut where they pierce each other, and F moved by
/// 2e-8, differently at each scale of the same pair.
pub struct AccuratePlane {
    n: [(f64, f64); 3],
    offset: (f64, f64),
    inv_len: f64,
}

impl AccuratePlane {
    pub fn of(v: &[Vec3]) -> Self {
        let n = newell_dd(v).map(Dd::pair);
        let mut sum = Dd::ZERO;
        for x in v {
            for (k, c) in [x.x, x.y, x.z].into_iter().enumerate() {
                sum = sum.add_product((c, 0.0), n[k]);
            }
        }
        // the mean, sum / m, in double-double
        let m = v.len() as f64;
        let (s, e) = sum.pair();
        let hi = s / m;
        let lo = ((-hi).mul_add(m, s) + e) / m;
        let len = Vec3::new(n[0].0, n[1].0, n[2].0).length();
        AccuratePlane { n, offset: (hi, lo), inv_len: 1.0 / len }
    }

    /// Signed distance of `x` from the plane (positive on the front side).
    pub fn height(&self, x: Vec3) -> f64 {
        let mut acc = Dd::ZERO;
        for (k, c) in [x.x, x.y, x.z].into_iter().enumerate() {
            acc = acc.add_product((c, 0.0), self.n[k]);
        }
        let acc = acc.add(-self.offset.0);
        (acc.value() - self.offset.1) * self.inv_len
    }
}

/// Largest distance between the bounding-box corners (cheap size measure for tolerances).
pub fn bounding_diameter(v: &[Vec3]) -> f64 {
    let mut lo = Vec3::splat(f64::INFINITY);
    let mut hi = Vec3::splat(f64::NEG_INFINITY);
    for p in v {
        lo = lo.min(*p);
        hi = hi.max(*p);
    }
    if v.is_empty() {
        0.0
    } else {
        (hi - lo).length()
    }
}

/// The largest cross product (v_i - v_0) x (v_{i+1} - v_0): a plane normal even when the
/// signed area cancels.
fn widest_cross(v: &[Vec3]) -> Option<Vec3> {
    (1..v.len() - 1).map(|i| (v[i] - v[0]).cross(v[i + 1] - v[0])).max_by(|a, b| a.length().total_cmp(&b.length()))
}

fn drop_repeated(v: Vec<Vec3>, tol: f64) -> Vec<Vec3> {
    let mut out: Vec<Vec3> = Vec::with_capacity(v.len());
    for p in v {
        if out.last().is_none_or(|q| q.distance(p) > tol) {
            out.push(p);
        }
    }
    while out.len() > 1 && out[0].distance(*out.last().unwrap()) <= tol {
        out.pop();
    }
    out
}

/// Area centroid of a planar polygon (signed fan decomposition, valid for concave outlines).
fn area_centroid(v: &[Vec3], normal: Vec3) -> Vec3 {
    let o = v[0];
    let mut acc = Vec3::ZERO;
    let mut total = 0.0;
    for i in 1..v.len() - 1 {
        let a = (v[i] - o).cross(v[i + 1] - o).dot(normal);
        acc += a * (o + v[i] + v[i + 1]) / 3.0;
        total += a;
    }
    acc / total
}

/// Orthonormal tangent basis (t, b) with t x b = n.
pub fn tangent_frame(n: Vec3) -> (Vec3, Vec3) {
    // Duff et al. 2017, "Building an orthonormal basis, revisited".
    let sign = 1f64.copysign(n.z);
    let a = -1.0 / (sign + n.z);
    let b = n.x * n.y * a;
    let t = Vec3::new(1.0 + sign * n.x * n.x * a, sign * b, -sign * n.x);
    let bb = Vec3::new(b, sign + n.y * n.y * a, -n.y);
    (t, bb)
}

/// Projects onto the plane with normal `n` in 2-D coordinates (right-handed about n).
fn project_2d(v: &[Vec3], n: Vec3) -> Vec<[f64; 2]> {
    let (t, b) = tangent_frame(n);
    let o = v[0];
    v.iter().map(|p| [(p - o).dot(t), (p - o).dot(b)]).collect()
}

fn orient(a: [f64; 2], b: [f64; 2], c: [f64; 2]) -> f64 {
    (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0])
}

/// `eps`: the orientation (twice a triangle's area) below which three points are collinear;
/// `slack`: how far beyond a segment's bounding box a collinear point still touches it (a
/// length relative to the polygon: an absolute 1e-12 made a U-shaped outline of size 1e-12
/// touch itself across its gap).
fn segments_cross(p1: [f64; 2], p2: [f64; 2], q1: [f64; 2], q2: [f64; 2], eps: f64, slack: f64) -> bool {
    let d1 = orient(q1, q2, p1);
    let d2 = orient(q1, q2, p2);
    let d3 = orient(p1, p2, q1);
    let d4 = orient(p1, p2, q2);
    if ((d1 > eps && d2 < -eps) || (d1 < -eps && d2 > eps)) && ((d3 > eps && d4 < -eps) || (d3 < -eps && d4 > eps)) {
        return true;
    }
    // Touching or overlapping (collinear) non-adjacent edges also make the outline invalid.
    let on = |a: [f64; 2], b: [f64; 2], p: [f64; 2], d: f64| {
        d.abs() <= eps
            && p[0] >= a[0].min(b[0]) - slack
            && p[0] <= a[0].max(b[0]) + slack
            && p[1] >= a[1].min(b[1]) - slack
            && p[1] <= a[1].max(b[1]) + slack
    };
    on(q1, q2, p1, d1) || on(q1, q2, p2, d2) || on(p1, p2, q1, d3) || on(p1, p2, q2, d4)
}

/// Returns a pair of non-adjacent edges that cross or touch, if any (O(n^2), n is small).
fn self_intersection(v: &[Vec3], n: Vec3) -> Option<(usize, usize)> {
    let p = project_2d(v, n);
    let m = p.len();
    let scale = bounding_diameter(v);
    let (eps, slack) = (1e-12 * scale * scale, 1e-12 * scale);
    for i in 0..m {
        for j in i + 2..m {
            if i == 0 && j == m - 1 {
                continue; // adjacent through the closing edge
            }
            if segments_cross(p[i], p[(i + 1) % m], p[j], p[(j + 1) % m], eps, slack) {
                return Some((i, j));
            }
        }
    }
    None
}

/// Distance between the segments p→q and r→s (Ericson, Real-Time Collision Detection, 5.1.9),
/// either of which may be a point (p = q: the distance of the point p from r→s).
pub fn segment_distance(p: Vec3, q: Vec3, r: Vec3, s: Vec3) -> f64 {
    let (d1, d2, w) = (q - p, s - r, p - r);
    let (a, e, f) = (d1.dot(d1), d2.dot(d2), d2.dot(w));
    let c = d1.dot(w);
    // (a point: the general case divides 0 by 0 where its foot falls beyond the other's ends)
    if !(a > 0.0) || !(e > 0.0) {
        let sp = if a > 0.0 { (-c / a).clamp(0.0, 1.0) } else { 0.0 };
        let tp = if e > 0.0 { (f / e).clamp(0.0, 1.0) } else { 0.0 };
        return (p + d1 * sp).distance(r + d2 * tp);
    }
    let b = d1.dot(d2);
    let denom = a * e - b * b;
    let mut sp = if denom > 1e-14 * a * e { ((b * f - c * e) / denom).clamp(0.0, 1.0) } else { 0.0 };
    let mut tp = (b * sp + f) / e;
    if tp < 0.0 {
        tp = 0.0;
        sp = (-c / a).clamp(0.0, 1.0);
    } else if tp > 1.0 {
        tp = 1.0;
        sp = ((b - c) / a).clamp(0.0, 1.0);
    }
    (p + d1 * sp).distance(r + d2 * tp)
}

/// Ear-clipping triangulation of a simple planar polygon (convex or concave).
pub fn triangulate(v: &[Vec3], n: Vec3) -> Vec<[usize; 3]> {
    let m = v.len();
    if m == 3 {
        return vec![[0, 1, 2]];
    }
    let p = project_2d(v, n);
    let mut idx: Vec<usize> = (0..m).collect();
    let mut tris = Vec::with_capacity(m - 2);
    let scale = bounding_diameter(v);
    let eps = 1e-14 * scale * scale;
    let mut guard = 0;
    while idx.len() > 3 && guard < 4 * m * m {
        guard += 1;
        let k = idx.len();
        let mut clipped = false;
        for e in 0..k {
            let (ia, ib, ic) = (idx[(e + k - 1) % k], idx[e], idx[(e + 1) % k]);
            if orient(p[ia], p[ib], p[ic]) <= eps {
                continue; // reflex or degenerate corner
            }
            let inside = idx.iter().any(|&q| {
                q != ia
                    && q != ib
                    && q != ic
                    && orient(p[ia], p[ib], p[q]) >= -eps
                    && orient(p[ib], p[ic], p[q]) >= -eps
                    && orient(p[ic], p[ia], p[q]) >= -eps
            });
            if !inside {
                tris.push([ia, ib, ic]);
                idx.remove(e);
                clipped = true;
                break;
            }
        }
        if !clipped {
            // Only collinear remnants are left: fan them, they carry no area.
            break;
        }
    }
    for e in 1..idx.len().saturating_sub(1) {
        tris.push([idx[0], idx[e], idx[e + 1]]);
    }
    tris
}

/// Sutherland-Hodgman clip of a planar polygon to the closed half-space n.(x - p) >= 0.
/// Vertices within `tol` (absolute distance) of the plane count as on it, so a polygon that
/// touches the plane along an edge keeps that edge exactly and grows no slivers.
pub fn clip_to_halfspace(v: &[Vec3], p: Vec3, n: Vec3, tol: f64, out: &mut Vec<Vec3>) {
    clip_by_height(v, |x| (x - p).dot(n), tol, out)
}

/// [`clip_to_halfspace`] for the half-space where `height` (a signed distance) is >= 0.
pub fn clip_by_height(v: &[Vec3], height: impl Fn(Vec3) -> f64, tol: f64, out: &mut Vec<Vec3>) {
    with_snapped(v.len(), |k| height(v[k]), tol, |d| clip_by_distances(v, d, out))
}

/// [`clip_by_height`] with the heights `h` of the vertices `v` given.
fn clip_by_heights(v: &[Vec3], h: &[f64], tol: f64, out: &mut Vec<Vec3>) {
    with_snapped(v.len(), |k| h[k], tol, |d| clip_by_distances(v, d, out))
}

/// `then` of the values f(0..m), those within `tol` of 0 set to 0 (a vertex within rounding
/// of the plane lies on it), on the stack for the usual small polygons.
fn with_snapped<R>(m: usize, f: impl Fn(usize) -> f64, tol: f64, then: impl FnOnce(&[f64]) -> R) -> R {
    let snap = |k: usize| {
        let s = f(k);
        if s.abs() <= tol {
            0.0
        } else {
            s
        }
    };
    let mut small = [0.0f64; 16];
    if m <= small.len() {
        for (k, d) in small[..m].iter_mut().enumerate() {
            *d = snap(k);
        }
        then(&small[..m])
    } else {
        then(&(0..m).map(snap).collect::<Vec<f64>>())
    }
}

/// The part of polygon `v` where the signed distances `d` (one per vertex) are >= 0.
fn clip_by_distances(v: &[Vec3], d: &[f64], out: &mut Vec<Vec3>) {
    out.clear();
    let m = v.len();
    if m == 0 {
        return;
    }
    if d.iter().all(|&s| s >= 0.0) {
        out.extend_from_slice(v);
        return;
    }
    if d.iter().all(|&s| s <= 0.0) {
        return;
    }
    for i in 0..m {
        let j = (i + 1) % m;
        let (a, b, da, db) = (v[i], v[j], d[i], d[j]);
        if da >= 0.0 {
            out.push(a);
        }
        if (da > 0.0 && db < 0.0) || (da < 0.0 && db > 0.0) {
            let t = da / (da - db);
            out.push(a + (b - a) * t);
        }
    }
    // A clipped polygon may carry vertices repeated where a vertex lay on the plane.
    let scale = bounding_diameter(out);
    drop_repeated_in_place(out, COINCIDENT_TOL * scale);
}

/// The triangles of polygon `p` (its own triangulation), for repeated [`within_triangles`] tests.
pub(crate) fn triangles_of(p: &Polygon) -> Vec<[Vec3; 3]> {
    let v = p.vertices();
    p.triangulate().iter().map(|t| [v[t[0]], v[t[1]], v[t[2]]]).collect()
}

/// True if x (in the plane of the triangles, whose polygon has normal n) lies in one of them or
/// within `tol` (absolute) of it. The polygon's normal, not the triangles': a sliver of a fan
/// has none.
pub(crate) fn within_triangles(tris: &[[Vec3; 3]], n: Vec3, x: Vec3, tol: f64) -> bool {
    tris.iter().any(|t| {
        (0..3).all(|k| {
            let (p, q) = (t[k], t[(k + 1) % 3]);
            n.dot((q - p).cross(x - p)) >= -tol * p.distance(q)
        })
    })
}

/// True if the convex `piece` has vertices farther than `tol` (absolute) on both sides of the
/// plane through q with normal n, i.e. [`split_by_plane`] would cut it in two.
pub(crate) fn crosses_plane(piece: &[Vec3], q: Vec3, n: Vec3, tol: f64) -> bool {
    let side = |x: &Vec3| n.dot(*x - q);
    piece.iter().any(|x| side(x) > tol) && piece.iter().any(|x| side(x) < -tol)
}

/// True if [`split_by_plane`] cuts the convex `piece` into two halves that do not overlap: it
/// [`crosses_plane`], and the sides of its vertices (those within `tol` of the plane counting
/// as on it) are those of a line through it, one run on each side with at most one vertex on
/// the plane between them. A plane at a small angle to the piece's own is within `tol` of it
/// along a band as wide as `tol` over that angle, and vertices on both sides of the band, or
/// two in it side by side, then give halves that share a triangle (they both keep every vertex
/// in the band): in the seed-39 replays of tests/test_properties.py a kink plane 4e-8 rad off
/// a face's plane cut a start piece of area 0.0532 into halves of 0.0560 together, and F came
/// out half the truth (3.30e-5 for 6.51e-5).
pub(crate) fn cuts_in_two(piece: &[Vec3], q: Vec3, n: Vec3, tol: f64) -> bool {
    let side = |x: Vec3| {
        let h = n.dot(x - q);
        (h > tol) as i8 - (h < -tol) as i8
    };
    let m = piece.len();
    let (mut above, mut below) = (0, 0);
    for k in 0..m {
        let (s, before) = (side(piece[k]), side(piece[(k + m - 1) % m]));
        if s == before && s == 0 {
            return false;
        }
        above += (s == 1 && before != 1) as usize;
        below += (s == -1 && before != -1) as usize;
    }
    above == 1 && below == 1
}

/// The two sides of the convex `piece` cut by the plane through q with normal n, each pushed to
/// `out` if it keeps 3 vertices. Vertices within `tol` of the plane count as on it in both
/// halves; the decision to cut ([`crosses_plane`]) must take the same `tol`, or a vertex a
/// rounding off the plane is classed by that rounding's sign, and the pieces (and the fans of
/// triangles over them) change with the scene's scale (a kink split 0.08 x obstructed_tol off
/// at scale 1 and 2.84 x at 0.1; tests/test_properties.py).
pub(crate) fn split_by_plane(piece: &[Vec3], q: Vec3, n: Vec3, tol: f64, out: &mut Vec<Vec<Vec3>>) {
    for m in [n, -n] {
        let mut half = Vec::with_capacity(piece.len() + 1);
        clip_to_halfspace(piece, q, m, tol, &mut half);
        if half.len() >= 3 {
            out.push(half);
        }
    }
}

/// The chord (ends of its hull) along which polygon `b` passes through or touches the plane
/// (point q, normal n), if it does.
pub(crate) fn plane_chord(b: &Polygon, q: Vec3, n: Vec3) -> Option<(Vec3, Vec3)> {
    let n = n.normalize_or_zero();
    let v = b.vertices();
    let tol = 1e-9 * b.radius();
    // heights within tol count as 0, whatever their rounding where the scene lies
    let h: Vec<f64> = v.iter().map(|x| n.dot(*x - q)).map(|x| if x.abs() <= tol { 0.0 } else { x }).collect();
    let mut ends: Vec<Vec3> = Vec::new();
    if !(h.iter().any(|&x| x > tol) && h.iter().any(|&x| x < -tol)) {
        // touching the plane (a wall meeting the source along an edge) counts too
        ends.extend(v.iter().zip(&h).filter(|(_, x)| x.abs() <= tol).map(|(p, _)| *p));
        if ends.is_empty() {
            return None;
        }
    }
    for k in 0..v.len() {
        let k1 = (k + 1) % v.len();
        if (h[k] > 0.0) != (h[k1] > 0.0) {
            ends.push(v[k] + (v[k1] - v[k]) * (h[k] / (h[k] - h[k1])));
        }
    }
    let (&a, rest) = ends.split_first()?;
    let far = |from: Vec3| {
        rest.iter().chain([&a]).copied().fold(from, |m, x| if x.distance(from) > m.distance(from) { x } else { m })
    };
    let p = far(a);
    Some((p, far(p)))
}

/// [`drop_repeated`] without a new allocation.
fn drop_repeated_in_place(v: &mut Vec<Vec3>, tol: f64) {
    // squared distances: no square root per vertex on the clipping hot path
    let tol2 = tol * tol;
    let mut kept = 0;
    for k in 0..v.len() {
        if kept == 0 || v[kept - 1].distance_squared(v[k]) > tol2 {
            v[kept] = v[k];
            kept += 1;
        }
    }
    v.truncate(kept);
    while v.len() > 1 && v[0].distance_squared(*v.last().unwrap()) <= tol2 {
        v.pop();
    }
}

/// Clips each polygon of a pair to the other's front half-space (needed before any contour
/// formula: a polygon partly behind the other's plane would otherwise give wrong F, even 0).
/// Returns None when nothing of either polygon is in front of the other.
pub fn clip_pair(a: &Polygon, b: &Polygon) -> Option<(Vec<Vec3>, Vec<Vec3>)> {
    // Each polygon's tolerances are its own: a 1e-8 square under a unit ceiling is a pair
    // (a tolerance of their summed size would call the square coplanar and give F = 0).
    let d = a.centroid.distance(b.centroid);
    let tol_a = plane_tol(a.radius, b.radius + d);
    let tol_b = plane_tol(b.radius, a.radius + d);
    let mut ca = Vec::with_capacity(a.vertices.len() + 2);
    let mut cb = Vec::with_capacity(b.vertices.len() + 2);
    // heights accurate to themselves: nearly coplanar pairs are cut where they truly pierce
    let (plane_a, plane_b) = (AccuratePlane::of(&a.vertices), AccuratePlane::of(&b.vertices));
    // A polygon cut by the other's plane ends on the line where the planes meet; a vertex of the
    // other within its tolerance behind its plane then lies across that line by height /
    // sin(angle) and, kept, overlaps the cut polygon in a sliver that the contour sum counts
    // whole. Such a polygon is cut exactly too, both ending on the line (a face leaning 6.1e-5
    // over another, its vertex 1.1e-16 behind the other's plane: a sliver 9.1e-13 wide, F 9.8e-4
    // off; tests/test_properties.py, seed 33).
    let cut = |h: &[f64], tol: f64| h.iter().any(|&s| s > tol) && h.iter().any(|&s| s < -tol);
    let grazes = |h: &[f64], tol: f64| h.iter().any(|&s| s < 0.0 && s >= -tol);
    let (va, vb) = (&a.vertices, &b.vertices);
    let mut clip = |ha: &[f64], hb: &[f64]| {
        let exact_a = if cut(hb, tol_b) && grazes(ha, tol_a) { 0.0 } else { tol_a };
        let exact_b = if cut(ha, tol_a) && grazes(hb, tol_b) { 0.0 } else { tol_b };
        clip_by_heights(va, ha, exact_a, &mut ca);
        clip_by_heights(vb, hb, exact_b, &mut cb);
    };
    // (the heights on the stack, as with_snapped keeps them: a tolerance of 0 snaps nothing)
    with_snapped(
        va.len(),
        |k| plane_b.height(va[k]),
        0.0,
        |ha| with_snapped(vb.len(), |k| plane_a.height(vb[k]), 0.0, |hb| clip(ha, hb)),
    );
    if ca.len() < 3 || cb.len() < 3 {
        return None;
    }
    // A polygon lying entirely in the other's plane (coplanar pair) exchanges nothing.
    let area_a = 0.5 * newell_normal(&ca).length();
    let area_b = 0.5 * newell_normal(&cb).length();
    if area_a <= 1e-14 * a.radius * a.radius || area_b <= 1e-14 * b.radius * b.radius {
        return None;
    }
    let off_a = ca.iter().map(|x| (x - b.centroid).dot(b.normal)).fold(0.0, f64::max);
    let off_b = cb.iter().map(|x| (x - a.centroid).dot(a.normal)).fold(0.0, f64::max);
    if off_a <= tol_a || off_b <= tol_b {
        return None;
    }
    Some((ca, cb))
}

/// Distance from another polygon's plane within which the vertices of a polygon of radius
/// `own` count as lying on it: 1e-10 of its own size (never of the pair's, so that pairs of
/// very different size keep the small one), and no less than the rounding of a signed
/// distance measured across `reach` (the other's radius plus the centroids' distance).
pub fn plane_tol(own: f64, reach: f64) -> f64 {
    COINCIDENT_TOL * 1e2 * own + 1e-14 * reach
}

#[cfg(test)]
pub(crate) mod tests {
    use super::*;

    /// A point's distance from a segment, the point given as a segment of length 0 on either
    /// side, where its foot falls before, on and beyond the segment (Pythagoras), and two
    /// skew segments (their common perpendicular, a unit apart).
    #[test]
    fn segment_distance_takes_points() {
        let (r, s) = (Vec3::ZERO, Vec3::new(2.0, 0.0, 0.0));
        for (x, want) in [(-3.0, 5.0), (1.0, 4.0), (5.0, 5.0)] {
            let p = Vec3::new(x, 4.0, 0.0);
            assert_eq!(segment_distance(p, p, r, s), want, "{p}");
            assert_eq!(segment_distance(r, s, p, p), want, "{p}");
        }
        assert_eq!(segment_distance(r, r, s, s), 2.0);
        let (p, q) = (Vec3::new(1.0, -1.0, 1.0), Vec3::new(1.0, 1.0, 1.0));
        assert!((segment_distance(p, q, r, s) - 1.0).abs() < 1e-15);
    }

    /// A plane 1e-9 rad off the quad's own, within `tol` of it at two adjacent corners and
    /// beyond it on both sides at the other two: the halves of [`split_by_plane`] both keep
    /// the two corners in the band and overlap, so [`cuts_in_two`] says no (the seed-39 kink
    /// split of obstructed::clipping). A plane across the quad cuts it into two halves
    /// whose areas add up to the quad's.
    #[test]
    fn a_plane_within_tol_of_two_adjacent_corners_cuts_no_overlapping_halves() {
        let quad = [Vec3::ZERO, Vec3::X, Vec3::new(2.0, 1.0, 0.0), Vec3::Y];
        let area = |p: &[Vec3]| 0.5 * newell_normal(p).length();
        let halves = |q: Vec3, n: Vec3| {
            let mut out = Vec::new();
            split_by_plane(&quad, q, n, 1e-9, &mut out);
            out.iter().map(|h| area(h)).sum::<f64>()
        };
        // heights (in 1e-9) 0.8, -0.7, -1.5, 1.5 at the corners
        let (q, n) = (Vec3::new(0.0, 0.0, -0.8e-9), Vec3::new(-1.5e-9, 0.7e-9, 1.0).normalize());
        assert!(crosses_plane(&quad, q, n, 1e-9) && !cuts_in_two(&quad, q, n, 1e-9));
        assert!(halves(q, n) > 1.1 * area(&quad), "{}", halves(q, n));
        let (q, n) = (Vec3::new(0.5, 0.0, 0.0), Vec3::new(1.0, -0.3, 0.0).normalize());
        assert!(cuts_in_two(&quad, q, n, 1e-9));
        assert!((halves(q, n) - area(&quad)).abs() < 1e-15, "{}", halves(q, n));
    }

    /// A needle triangle (smallest angle ~1e-9) with coordinates k 2^-20 (k < 2^32), whose
    /// edge vectors and cross product are exact in i128 (not in f64: the products need 64 bits): accurate_normal is within a few eps
    /// of the exact direction, where plain arithmetic is off by ~eps / 1e-9.
    #[test]
    fn accurate_normal_of_a_needle() {
        let pts: [[i64; 3]; 3] = [
            [1_234_567_891, -2_345_678_912, 3_456_789_123],
            [567_891_234, 3_345_678_912, -456_789_123],
            [901_229_563, 499_999_999, 1_500_000_001],
        ];
        let e = |i: usize, k: usize| (pts[i][k] - pts[0][k]) as i128;
        let exact = [
            e(1, 1) * e(2, 2) - e(1, 2) * e(2, 1),
            e(1, 2) * e(2, 0) - e(1, 0) * e(2, 2),
            e(1, 0) * e(2, 1) - e(1, 1) * e(2, 0),
        ];
        let want = Vec3::new(exact[0] as f64, exact[1] as f64, exact[2] as f64).normalize();
        let scale = (2.0f64).powi(-20);
        let v: Vec<Vec3> = pts.iter().map(|p| Vec3::new(p[0] as f64, p[1] as f64, p[2] as f64) * scale).collect();
        let sin = (v[1] - v[0]).cross(v[2] - v[0]).length() / ((v[1] - v[0]).length() * (v[2] - v[0]).length());
        assert!(sin < 1e-6, "not a needle: {sin}");
        let got = accurate_normal(&v).normalize();
        assert!((got - want).length() < 4.0 * f64::EPSILON, "{got} {want}");
        let plain = newell_normal(&v).normalize();
        assert!(
            (plain - want).length() > 1e3 * f64::EPSILON,
            "plain arithmetic is this exact too: the needle is too easy"
        );
    }

    /// The concave L of three unit squares in z = 0 (area 3, facing +z).
    pub(crate) fn ell() -> Vec<Vec3> {
        vec![
            Vec3::new(0., 0., 0.),
            Vec3::new(2., 0., 0.),
            Vec3::new(2., 1., 0.),
            Vec3::new(1., 1., 0.),
            Vec3::new(1., 2., 0.),
            Vec3::new(0., 2., 0.),
        ]
    }

    fn sq(s: f64) -> Vec<Vec3> {
        vec![Vec3::new(0., 0., 0.), Vec3::new(s, 0., 0.), Vec3::new(s, s, 0.), Vec3::new(0., s, 0.)]
    }

    #[test]
    fn convexity_test_in_two_and_three_dimensions() {
        let square = [[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]];
        assert!(turns_left(&square, turn_2d, 1e-12));
        let clockwise: Vec<[f64; 2]> = square.iter().rev().copied().collect();
        assert!(!turns_left(&clockwise, turn_2d, -1e-12));
        // a vertex on an edge: straight, so convex only when straight corners are allowed
        let on_edge = [[0.0, 0.0], [0.5, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]];
        assert!(turns_left(&on_edge, turn_2d, -1e-12) && !turns_left(&on_edge, turn_2d, 1e-12));
        // the L of three unit squares has one right turn (at (1, 1))
        let ell = [[0.0, 0.0], [2.0, 0.0], [2.0, 1.0], [1.0, 1.0], [1.0, 2.0], [0.0, 2.0]];
        assert!(!turns_left(&ell, turn_2d, -1e-12));
        // the threshold is relative to the edges: a dent of relative depth 1e-9 is seen at any scale
        for scale in [1e-6, 1.0, 1e6] {
            let dent: Vec<[f64; 2]> = [[0.0, 0.0], [0.5, 1e-9], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]]
                .map(|[x, y]| [x * scale, y * scale])
                .into();
            assert!(!turns_left(&dent, turn_2d, -1e-12), "scale {scale}");
        }
        // 3-D: the square tilted out of the xy plane is convex about its own normal only
        let r = glam::DQuat::from_axis_angle(Vec3::new(1.0, 2.0, 3.0).normalize(), 0.7);
        let v: Vec<Vec3> = sq(3.0).into_iter().map(|x| r * x).collect();
        let n = r * Vec3::Z;
        assert!(turns_left(&v, turn_about(n), 1e-12));
        assert!(!turns_left(&v, turn_about(-n), -1e-12));
        // the 3-D turn is the 2-D one of the projection
        let p = project_2d(&v, n);
        let (c3, s3) = turn_about(n)(v[0], v[1], v[2]);
        let (c2, s2) = turn_2d(p[0], p[1], p[2]);
        assert!((c3 - c2).abs() < 1e-13 * s3 && (s3 - s2).abs() < 1e-13 * s3);
    }

    /// A U whose arms end on one line (edges (3,2)-(2,2) and (1,2)-(0,2), a gap of a third of
    /// its size between them) is simple at every scale; and touching across the gap is seen.
    #[test]
    fn self_touching_is_relative_to_the_outline() {
        let u = [[0.0, 0.0], [3.0, 0.0], [3.0, 2.0], [2.0, 2.0], [2.0, 1.0], [1.0, 1.0], [1.0, 2.0], [0.0, 2.0]];
        for scale in [1e-14, 1e-13, 1.0, 1e13] {
            let v: Vec<Vec3> = u.iter().map(|[x, y]| Vec3::new(x * scale, y * scale, 0.0)).collect();
            assert!(Polygon::new(v).is_ok(), "scale {scale}");
        }
        let closed = [[0.0, 0.0], [3.0, 0.0], [3.0, 2.0], [1.0, 2.0], [1.0, 1.0], [2.0, 1.0], [2.0, 2.0], [0.0, 2.0]];
        let v: Vec<Vec3> = closed.iter().map(|[x, y]| Vec3::new(x * 1e-13, y * 1e-13, 0.0)).collect();
        assert!(matches!(Polygon::new(v), Err(GeometryError::SelfIntersecting(..))));
    }

    #[test]
    fn square_quantities() {
        let p = Polygon::new(sq(2.0)).unwrap();
        assert!((p.area() - 4.0).abs() < 1e-15);
        assert!((p.normal() - Vec3::Z).length() < 1e-15);
        assert!((p.centroid() - Vec3::new(1., 1., 0.)).length() < 1e-15);
        assert!((p.radius() - 2f64.sqrt()).abs() < 1e-15);
    }

    #[test]
    fn clockwise_square_faces_down() {
        let mut v = sq(1.0);
        v.reverse();
        assert!((Polygon::new(v).unwrap().normal() + Vec3::Z).length() < 1e-15);
    }

    #[test]
    fn concave_l_shape_area_and_triangulation() {
        let v = ell();
        let p = Polygon::new(v.clone()).unwrap();
        assert!((p.area() - 3.0).abs() < 1e-14);
        let tri_area: f64 =
            p.triangulate().iter().map(|t| 0.5 * (v[t[1]] - v[t[0]]).cross(v[t[2]] - v[t[0]]).dot(Vec3::Z)).sum();
        assert!((tri_area - 3.0).abs() < 1e-14, "{tri_area}");
        // every triangle is positively oriented (no ear across the notch)
        for t in p.triangulate() {
            assert!((v[t[1]] - v[t[0]]).cross(v[t[2]] - v[t[0]]).z > 0.0);
        }
    }

    #[test]
    fn rejects_bad_input() {
        let mut v = sq(1.0);
        v[2].x = f64::NAN;
        assert_eq!(Polygon::new(v).unwrap_err(), GeometryError::NonFinite(2));
        assert_eq!(Polygon::new(vec![Vec3::ZERO, Vec3::X, Vec3::X]).unwrap_err(), GeometryError::TooFewVertices(2));
        assert_eq!(Polygon::new(vec![Vec3::ZERO, Vec3::X, 2.0 * Vec3::X]).unwrap_err(), GeometryError::ZeroArea);
        let mut v = sq(1.0);
        v[2].z = 1e-3;
        assert!(matches!(Polygon::new(v).unwrap_err(), GeometryError::NonPlanar { .. }));
        let bow = vec![Vec3::new(0., 0., 0.), Vec3::new(1., 1., 0.), Vec3::new(1., 0., 0.), Vec3::new(0., 1., 0.)];
        assert!(matches!(Polygon::new(bow).unwrap_err(), GeometryError::SelfIntersecting(..)));
    }

    #[test]
    fn every_outline_is_validated_with_its_index() {
        let outlines = vec![sq(1.0), vec![Vec3::ZERO, Vec3::X, 2.0 * Vec3::X], sq(2.0), vec![Vec3::ZERO, Vec3::X]];
        let r = validate_all(outlines, 1e-6);
        assert!(r[0].is_ok() && r[2].is_ok());
        let err = r[1].as_ref().unwrap_err();
        assert_eq!(err, &crate::Error::Geometry { index: 1, source: GeometryError::ZeroArea });
        assert_eq!(err.to_string(), "polygon 1 has zero area (all vertices collinear or coincident)");
        match &r[3] {
            Err(crate::Error::Geometry { index: 3, source }) => {
                assert_eq!(source.kind(), "too_few_vertices");
                assert!(source.is_degenerate());
            }
            other => panic!("{other:?}"),
        }
        let bow = vec![Vec3::ZERO, Vec3::new(1., 1., 0.), Vec3::X, Vec3::Y];
        let e = Polygon::new(bow).unwrap_err();
        assert_eq!(e.kind(), "self_intersecting");
        assert!(!e.is_degenerate());
    }

    #[test]
    fn planarity_is_scale_relative() {
        for s in [1e-3, 1.0, 1e3, 1e6] {
            let mut v = sq(s);
            v[2].z = 1e-8 * s;
            assert!(Polygon::new(v).is_ok());
        }
    }

    #[test]
    fn clip_half_square() {
        let mut out = Vec::new();
        clip_to_halfspace(&sq(1.0), Vec3::new(0.5, 0., 0.), Vec3::X, 0.0, &mut out);
        let a = 0.5 * newell_normal(&out).length();
        assert!((a - 0.5).abs() < 1e-15);
        assert!(out.iter().all(|p| p.x >= 0.5));
    }

    #[test]
    fn clip_pair_piercing() {
        // docs/algorithms.md §1.4: A2 in x = 0.5 cuts A1's plane; after clipping A2 keeps z >= 0,
        // A1 keeps x <= 0.5 (the side A2 faces).
        let a = Polygon::new(sq(1.0)).unwrap();
        let b = Polygon::new(vec![
            Vec3::new(0.5, 0., -0.5),
            Vec3::new(0.5, 0., 0.5),
            Vec3::new(0.5, 1., 0.5),
            Vec3::new(0.5, 1., -0.5),
        ])
        .unwrap();
        assert!((b.normal() + Vec3::X).length() < 1e-15);
        let (ca, cb) = clip_pair(&a, &b).unwrap();
        assert!(ca.iter().all(|p| p.x <= 0.5 + 1e-15));
        assert!(cb.iter().all(|p| p.z >= -1e-15));
        assert!((0.5 * newell_normal(&ca).length() - 0.5).abs() < 1e-15);
        assert!((0.5 * newell_normal(&cb).length() - 0.5).abs() < 1e-15);
    }

    /// A face leaning 6.1e-5 over another, both facing +z and seeing each other across the line
    /// from (0, -0.5, 0) to (-1, 0, 0) (tests/test_properties.py, seed 33). A vertex of the
    /// lower face 2.2e-16 above z = 0 puts the leaning face's vertex (0, -0.5, 0) 1.1e-16
    /// behind the lower face's plane, and the lower face is cut where it crosses the leaning
    /// face's plane, 9.1e-13 off that vertex. Kept whole (1.1e-16 is within the tolerance),
    /// the leaning face overlapped the cut face by a sliver that the contour sum counted:
    /// both now end on the one line, and F is the 30-digit value.
    #[test]
    fn clip_pair_cuts_a_vertex_behind_the_plane_of_a_cut_face() {
        let tri = |v: [[f64; 3]; 3]| Polygon::new(v.iter().map(|p| Vec3::from_array(*p)).collect()).unwrap();
        let a = tri([[0.0, -0.5, 0.0], [0.0, 0.0, 6.103515625e-05], [-1.0, 0.0, 0.0]]);
        let b = tri([[-1.0, 0.0, 0.0], [0.0, -1.0, 2.220446049250313e-16], [0.0, 0.0, 0.0]]);
        let (ca, cb) = clip_pair(&a, &b).unwrap();
        let cut = |c: &[Vec3]| *c.iter().find(|x| x.x == 0.0 && (-0.75..-0.25).contains(&x.y)).unwrap();
        assert!(cut(&cb).y > -0.5 + 9e-13, "{:?}", cut(&cb));
        assert!(cut(&ca).distance(cut(&cb)) <= 4.0 * f64::EPSILON, "{:?} {:?}", cut(&ca), cut(&cb));
        let f = crate::unobstructed::analytic::polygon_pair::polygon_pair(&a, &b) / a.area();
        assert!((f / 1.85986384288e-9 - 1.0).abs() < 1e-8, "{f:e}");
    }

    /// Two triangles whose planes meet at ~1e-9 rad, piercing each other: the cut on the edges
    /// in x = 0 lies exactly at (0, e/2, 1/2) (the edges' lines y = e z and y = e (1 - z)
    /// cross there). Heights from a rounded centroid and normal put it 1e-7 of the edge off,
    /// by a different amount at each scale.
    #[test]
    fn clip_pair_of_nearly_coplanar_piercing_triangles() {
        let e = 1e-9;
        for s in [1.0, 0.1, 3.0, 1e-6, 1e3, 1e6] {
            let tri = |v: [[f64; 3]; 3]| Polygon::new(v.iter().map(|p| Vec3::from_array(*p) * s).collect()).unwrap();
            let a = tri([[0., 0., 0.], [0., e, 1.], [1., 1., 0.]]);
            let b = tri([[0., 0., 1.], [0., e, 0.], [1., 1., 0.]]);
            let want = Vec3::new(0.0, (s * e) / 2.0, s / 2.0);
            let (ca, cb) = clip_pair(&a, &b).unwrap();
            for (name, c) in [("a", &ca), ("b", &cb)] {
                let off = c.iter().map(|x| x.distance(want)).fold(f64::INFINITY, f64::min);
                assert!(off <= 4.0 * f64::EPSILON * s, "{name} at scale {s}: cut {:e} of the size off", off / s);
                assert_eq!(c.len(), 3, "{name} at scale {s}: {c:?}");
            }
        }
    }

    /// Heights over an accurate plane against exact integer arithmetic, for points 1e-9 of
    /// their coordinates off the plane of a triangle: plain arithmetic keeps ~7 digits.
    #[test]
    fn accurate_plane_heights_are_exact_to_rounding() {
        let t: [[i64; 3]; 3] = [[3, -7, 11], [1_000_000_003, 5, -2], [7, 999_999_937, 1_000_013]];
        let v: Vec<Vec3> = t.iter().map(|p| Vec3::new(p[0] as f64, p[1] as f64, p[2] as f64)).collect();
        let e = |i: usize, k: usize| (t[i][k] - t[0][k]) as i128;
        let n = [
            e(1, 1) * e(2, 2) - e(1, 2) * e(2, 1),
            e(1, 2) * e(2, 0) - e(1, 0) * e(2, 2),
            e(1, 0) * e(2, 1) - e(1, 1) * e(2, 0),
        ];
        let len = ((n[0] * n[0] + n[1] * n[1] + n[2] * n[2]) as f64).sqrt();
        let plane = AccuratePlane::of(&v);
        let tri = Polygon::new(v.clone()).unwrap();
        let mut plain_worst: f64 = 0.0;
        // points of the plane (integer combinations of the edges) moved by a unit or two
        for (k1, k2, d) in [(1, 1, [0, 0, 1]), (2, -1, [1, -2, 0]), (-1, 3, [0, 1, 1]), (1, 0, [-1, 0, 2])] {
            let x: [i64; 3] =
                std::array::from_fn(|k| t[0][k] + k1 * (t[1][k] - t[0][k]) + k2 * (t[2][k] - t[0][k]) + d[k]);
            let h = (0..3).map(|k| (x[k] - t[0][k]) as i128 * n[k]).sum::<i128>();
            let want = h as f64 / len;
            let p = Vec3::new(x[0] as f64, x[1] as f64, x[2] as f64);
            let got = plane.height(p);
            assert!((got - want).abs() <= 4.0 * f64::EPSILON * want.abs(), "{got:e} {want:e}");
            plain_worst = plain_worst.max(((p - tri.centroid()).dot(tri.normal()) - want).abs() / want.abs());
        }
        assert!(plain_worst > 1e3 * f64::EPSILON, "plain arithmetic is this exact too: {plain_worst:e}");
    }

    #[test]
    fn coplanar_pair_exchanges_nothing() {
        let a = Polygon::new(sq(1.0)).unwrap();
        let b = Polygon::new(sq(1.0).into_iter().map(|p| p + Vec3::X).collect()).unwrap();
        assert!(clip_pair(&a, &b).is_none());
    }
}
