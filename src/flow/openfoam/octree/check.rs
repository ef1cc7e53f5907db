//! The table against the blend: check points over the mesh and next to its walls, and the
//! largest differences there.

use super::*;
use crate::flow::FlowField;

/// Where the table is checked against the blend: points spread over the mesh and points at
/// given fractions of the first cell's height from the wall faces, in from each face's centre.
#[derive(Debug, Clone)]
pub struct CheckPoints {
    /// Points spread over the mesh's bounding box that lie in a mesh cell.
    pub spread: Vec<Vec3>,
    /// (point, patch index, fraction of the first cell's height) next to the wall faces.
    pub near_wall: Vec<(Vec3, usize, f64)>,
}

/// The largest differences of the table from the blend over some points.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Misses {
    /// Points compared.
    pub points: usize,
    /// Largest |u − u_blend| / |u|max.
    pub u: f64,
    /// Largest |∇u − ∇u_blend| / |∇u|max (Frobenius).
    pub gradient: f64,
}

/// SplitMix64 (Steele, Lea & Flood 2014): a fixed sequence of check points for a seed.
fn splitmix(state: &mut u64) -> f64 {
    *state = state.wrapping_add(0x9E37_79B9_7F4A_7C15);
    let mut z = *state;
    z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
    ((z ^ (z >> 31)) >> 11) as f64 / (1u64 << 53) as f64
}

impl OctreeFlow {
    /// `spread` points drawn uniformly in the mesh's bounding box until that many lie in a
    /// cell (at most 100 draws each), and at every `stride`-th wall face one point at each of
    /// `fractions` of its cell's height in from its centre.
    pub fn check_points(&self, spread: usize, stride: usize, fractions: &[f64], seed: u64) -> CheckPoints {
        let cellwise = self.blend.cellwise();
        let mesh = cellwise.mesh();
        let (lo, hi) = mesh.points().iter().fold(
            (Vec3::repeat(f64::INFINITY), Vec3::repeat(f64::NEG_INFINITY)),
            |(lo, hi), p| (lo.inf(p), hi.sup(p)),
        );
        let mut state = seed;
        let mut inside = Vec::with_capacity(spread);
        for _ in 0..100 * spread {
            if inside.len() == spread {
                break;
            }
            let x = lo
                + (hi - lo).component_mul(&Vec3::new(
                    splitmix(&mut state),
                    splitmix(&mut state),
                    splitmix(&mut state),
                ));
            if cellwise.locate(&x, None).is_ok() {
                inside.push(x);
            }
        }
        let layer = cellwise.wall_layer();
        let mut near_wall = Vec::new();
        for (k, &f) in cellwise.walls().iter().enumerate().step_by(stride.max(1)) {
            let f = f as usize;
            let normal = mesh.face_areas()[f].normalize();
            let height = 2.0 * layer.depth(k);
            for &q in fractions {
                let x = mesh.face_centres()[f] - normal * (q * height);
                near_wall.push((x, mesh.patch_of(f).unwrap_or(usize::MAX), q));
            }
        }
        CheckPoints {
            spread: inside,
            near_wall,
        }
    }

    /// The largest differences from the blend at `points` where both answer.
    pub fn misses(&self, points: impl IntoIterator<Item = Vec3>) -> Misses {
        let report = &self.table.report;
        let mut m = Misses::default();
        for x in points {
            if let (Ok(a), Ok(b)) = (self.sample(&x, 0.0), self.blend.sample(&x, 0.0)) {
                m.points += 1;
                m.u = m.u.max((a.u - b.u).norm() / report.u_max);
                m.gradient = m.gradient.max((a.grad_u - b.grad_u).norm() / report.gradient_max);
            }
        }
        m
    }
}
