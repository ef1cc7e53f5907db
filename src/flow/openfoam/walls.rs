//! Distances from a point to the no-slip wall faces near it, for the wall terms of
//! [`super::BlendedFlow`].
//!
//! A face is the fan of triangles from its centre to its edges, the same decomposition the
//! particle boundaries and the cell location use, so the distance is zero exactly on the faces
//! a particle touches. The distance to a triangle is that to its closest point (Ericson 2005,
//! *Real-Time Collision Detection*, §5.1.5: the Voronoi regions of the vertices, edges and
//! face). Each face is binned as the ball around its centre of radius its support plus its
//! circumradius (the largest centre-to-vertex distance), which holds every point nearer to the
//! face than its support: a query scans the faces whose ball holds x, so none is missed.

use super::grid::BallGrid;
use super::mesh::PolyMesh;
use crate::tensor::Vec3;

/// The wall faces of a mesh, as triangle fans, binned by centre.
#[derive(Debug, Clone)]
pub struct WallFaces {
    /// Face k's ball: its centre, radius its support plus its circumradius (module docs).
    balls: BallGrid,
    /// Vertices of wall face k: `vertices[offsets[k]..offsets[k + 1]]`.
    offsets: Vec<usize>,
    vertices: Vec<Vec3>,
    /// Distance within which wall face k's term acts.
    supports: Vec<f64>,
    /// Largest distance from wall face k's centre to its vertices.
    circumradii: Vec<f64>,
}

impl WallFaces {
    /// Wall faces `faces` of `mesh`, face k acting within `supports[k]` (> 0, finite) of it;
    /// `None` if a coordinate or support is not finite, or the lengths differ.
    pub fn new(mesh: &PolyMesh, faces: &[u32], supports: &[f64]) -> Option<Self> {
        if supports.len() != faces.len() || supports.iter().any(|s| !s.is_finite()) {
            return None;
        }
        let mut offsets = Vec::with_capacity(faces.len() + 1);
        offsets.push(0);
        let mut vertices = Vec::new();
        let mut circumradii = Vec::with_capacity(faces.len());
        let centres: Vec<Vec3> = faces.iter().map(|&f| mesh.face_centres()[f as usize]).collect();
        for (&f, c) in faces.iter().zip(&centres) {
            let mut circumradius: f64 = 0.0;
            for &v in mesh.face(f as usize) {
                let p = mesh.points()[v as usize];
                circumradius = circumradius.max((p - c).norm());
                vertices.push(p);
            }
            circumradii.push(circumradius);
            offsets.push(vertices.len());
        }
        // A margin of 10⁻⁹ for round-off; a face with no support gets a ball of the smallest
        // radius, whose test below still refuses every point.
        let radii: Vec<f64> = supports
            .iter()
            .zip(&circumradii)
            .map(|(s, c)| ((s + c) * (1.0 + 1e-9)).max(f64::MIN_POSITIVE))
            .collect();
        Some(Self {
            balls: BallGrid::new(&centres, &radii)?,
            circumradii,
            offsets,
            vertices,
            supports: supports.to_vec(),
        })
    }

    /// Calls `visit(k, away, support)` for every wall face k whose distance d = |away| from x is
    /// below its support, in a fixed order; `away` = x − q, q the face's point nearest to x, so
    /// away/d is the gradient of the distance.
    pub fn for_each_within(&self, x: &Vec3, mut visit: impl FnMut(usize, Vec3, f64)) {
        self.balls.for_each_containing(x, |k, centre, to_centre| {
            let support = self.supports[k];
            // The face lies within its circumradius of its centre: no point of it is nearer.
            if to_centre - self.circumradii[k] >= support {
                return;
            }
            let fan = &self.vertices[self.offsets[k]..self.offsets[k + 1]];
            let away = (0..fan.len())
                .map(|i| triangle_offset(x, centre, &fan[i], &fan[(i + 1) % fan.len()]))
                .min_by(|a, b| a.norm_squared().total_cmp(&b.norm_squared()));
            if let Some(away) = away.filter(|a| a.norm() < support) {
                visit(k, away, support);
            }
        });
    }
}

impl WallFaces {
    /// The farthest a face's term reaches from its centre: its support plus its circumradius,
    /// the largest of the faces'.
    pub fn reach(&self) -> f64 {
        self.balls.largest_radius()
    }

    /// The number of faces.
    pub fn len(&self) -> usize {
        self.supports.len()
    }

    /// Whether there are no faces.
    pub fn is_empty(&self) -> bool {
        self.supports.is_empty()
    }

    /// Distance within which face k's term acts.
    pub fn support(&self, k: usize) -> f64 {
        self.supports[k]
    }

    /// Face k's vertices (its fan's rim; the fan's hub is the face centre).
    pub fn vertices(&self, k: usize) -> &[Vec3] {
        &self.vertices[self.offsets[k]..self.offsets[k + 1]]
    }

    /// Face k's centre (the hub of its triangle fan).
    pub fn centre(&self, k: usize) -> Vec3 {
        self.balls.centre(k)
    }

    /// Distance from x to face k (its triangle fan).
    pub fn distance(&self, k: usize, x: &Vec3) -> f64 {
        let (fan, centre) = (self.vertices(k), self.centre(k));
        (0..fan.len())
            .map(|i| triangle_offset(x, &centre, &fan[i], &fan[(i + 1) % fan.len()]).norm())
            .fold(f64::INFINITY, f64::min)
    }
}

/// p − q for q the point of the triangle (a, b, c) nearest to p: the closest point of the
/// vertex, edge or interior region p projects into (Ericson 2005, §5.1.5). A degenerate
/// triangle falls through to its edges and vertices.
pub(super) fn triangle_offset(p: &Vec3, a: &Vec3, b: &Vec3, c: &Vec3) -> Vec3 {
    let (ab, ac, ap) = (b - a, c - a, p - a);
    let (d1, d2) = (ab.dot(&ap), ac.dot(&ap));
    if d1 <= 0.0 && d2 <= 0.0 {
        return ap;
    }
    let bp = p - b;
    let (d3, d4) = (ab.dot(&bp), ac.dot(&bp));
    if d3 >= 0.0 && d4 <= d3 {
        return bp;
    }
    let vc = d1 * d4 - d3 * d2;
    if vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0 {
        return ap - ab * (d1 / (d1 - d3));
    }
    let cp = p - c;
    let (d5, d6) = (ab.dot(&cp), ac.dot(&cp));
    if d6 >= 0.0 && d5 <= d6 {
        return cp;
    }
    let vb = d5 * d2 - d1 * d6;
    if vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0 {
        return ap - ac * (d2 / (d2 - d6));
    }
    let va = d3 * d6 - d5 * d4;
    if va <= 0.0 && (d4 - d3) >= 0.0 && (d5 - d6) >= 0.0 {
        return bp - (c - b) * ((d4 - d3) / ((d4 - d3) + (d5 - d6)));
    }
    let denom = va + vb + vc;
    if denom.abs() > 0.0 {
        let (v, w) = (vb / denom, vc / denom);
        ap - ab * v - ac * w
    } else {
        // Collinear vertices: the nearest of the three edges.
        [(a, b), (b, c), (c, a)]
            .iter()
            .map(|(s, e)| segment_offset(p, s, e))
            .min_by(|x, y| x.norm_squared().total_cmp(&y.norm_squared()))
            .unwrap_or(*p - *a)
    }
}

/// p − q for q the point of the segment [s, e] nearest to p.
fn segment_offset(p: &Vec3, s: &Vec3, e: &Vec3) -> Vec3 {
    let d = e - s;
    let len2 = d.norm_squared();
    let t = if len2 > 0.0 {
        ((p - s).dot(&d) / len2).clamp(0.0, 1.0)
    } else {
        0.0
    };
    p - s - d * t
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    /// The closest-point distance equals the minimum over a fine sampling of the triangle, to
    /// the sampling's resolution: with n subdivisions a point of the triangle lies within
    /// (longest edge)/n of a sample, here 3/400 < 0.01.
    fn sampled(p: &Vec3, a: &Vec3, b: &Vec3, c: &Vec3) -> f64 {
        let n = 400;
        let mut best = f64::INFINITY;
        for i in 0..=n {
            for j in 0..=n - i {
                let (u, v) = (i as f64 / n as f64, j as f64 / n as f64);
                best = best.min((a + (b - a) * u + (c - a) * v - p).norm());
            }
        }
        best
    }

    fn point() -> impl Strategy<Value = Vec3> {
        prop::array::uniform3(-1.0..1.0f64).prop_map(Vec3::from)
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(64))]
        #[test]
        fn triangle_distance_is_the_nearest_point(p in point(), a in point(), b in point(), c in point()) {
            let exact = triangle_offset(&p, &a, &b, &c).norm();
            let approx = sampled(&p, &a, &b, &c);
            // The sampled minimum is never below the exact one (round-off aside) and above it by
            // at most the sampling resolution.
            prop_assert!(approx >= exact - 1e-12 && approx <= exact + 0.01, "{exact} vs {approx}");
        }

        /// The nearest point q = p − offset lies on the triangle: its own offset is zero.
        #[test]
        fn nearest_point_is_on_the_triangle(p in point(), a in point(), b in point(), c in point()) {
            let q = p - triangle_offset(&p, &a, &b, &c);
            prop_assert!(triangle_offset(&q, &a, &b, &c).norm() < 1e-12);
        }
    }

    /// Collinear triangles reduce to their longest edge.
    #[test]
    fn degenerate_triangle_is_a_segment() {
        let (a, b, c) = (Vec3::zeros(), Vec3::new(1.0, 0.0, 0.0), Vec3::new(2.0, 0.0, 0.0));
        let p = Vec3::new(1.5, 1.0, 0.0);
        assert!((triangle_offset(&p, &a, &b, &c).norm() - 1.0).abs() < 1e-15);
        let beyond = Vec3::new(3.0, 0.0, 4.0);
        assert!((triangle_offset(&beyond, &a, &b, &c).norm() - 17f64.sqrt()).abs() < 1e-15);
    }
}
