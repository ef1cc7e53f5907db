//! Sampling the table: the descent to the leaf holding a point, the leaf's interpolant and
//! its join to the blend next to the wall leaves.

use super::*;
use crate::error::FlowError;
use crate::flow::FlowField;
use crate::flow::openfoam::memo;
use crate::tensor::Mat3;

impl OctreeFlow {
    /// What the build found: leaves, nodes, memory and the misses at the leaves' midpoints.
    pub fn report(&self) -> &BuildReport {
        &self.table.report
    }

    /// The blended field underneath (the reference, and the field next to the walls).
    pub fn blended(&self) -> &BlendedFlow {
        &self.blend
    }

    /// The tabulated leaf holding x, x's coordinates ξ in it and its edge, `None` in a wall
    /// leaf or outside the root cubes.
    fn leaf(&self, x: &Vec3) -> Option<(usize, [f64; 3], f64)> {
        let t = &self.table;
        let rel = (x - t.origin) / t.edge;
        let mut entry = 0usize;
        let mut xi = [0.0; 3];
        let mut edge = t.edge;
        for a in (0..3).rev() {
            let f = rel[a].floor();
            if !(f >= 0.0 && f < t.dims[a] as f64) {
                return None;
            }
            entry = entry * t.dims[a] + f as usize;
            xi[a] = rel[a] - f;
        }
        // Doubling ξ and taking off the child's half is exact in binary floating point.
        for _ in 0..=MAX_LEVEL {
            let e = t.tree[entry];
            match e & TAG {
                BRANCH => {
                    let mut child = 0;
                    for (a, v) in xi.iter_mut().enumerate() {
                        *v *= 2.0;
                        if *v >= 1.0 {
                            *v -= 1.0;
                            child |= 1 << a;
                        }
                    }
                    entry = (e & !TAG) as usize + child;
                    edge *= 0.5;
                }
                TABLE => return Some(((e & !TAG) as usize, xi, edge)),
                _ => return None,
            }
        }
        None
    }

    /// Every leaf of the octree, root cube by root cube, depth first.
    pub fn leaves(&self) -> Vec<LeafBox> {
        let t = &self.table;
        let mut out = Vec::new();
        let mut stack: Vec<(usize, Vec3, f64)> = (0..t.dims.iter().product::<usize>())
            .map(|r| {
                let ijk = Vec3::new(
                    (r % t.dims[0]) as f64,
                    (r / t.dims[0] % t.dims[1]) as f64,
                    (r / (t.dims[0] * t.dims[1])) as f64,
                );
                (r, t.origin + ijk * t.edge, t.edge)
            })
            .rev()
            .collect();
        // Each entry is pushed once (a tree has no cycles), so the loop ends.
        while let Some((entry, lower, edge)) = stack.pop() {
            let e = t.tree[entry];
            if e & TAG == BRANCH {
                for c in (0..8).rev() {
                    let bit = |a: usize| ((c >> a) & 1) as f64 * edge / 2.0;
                    stack.push((
                        (e & !TAG) as usize + c,
                        lower + Vec3::new(bit(0), bit(1), bit(2)),
                        edge / 2.0,
                    ));
                }
            } else {
                out.push(LeafBox {
                    lower,
                    edge,
                    tabulated: e & TAG == TABLE,
                });
            }
        }
        out
    }

    /// Whether x lies where a sample is the table alone (a tabulated leaf, χ = 0 there).
    pub fn is_tabulated(&self, x: &Vec3) -> bool {
        self.leaf(x).is_some_and(|(leaf, xi, _)| self.chi(leaf, &xi) <= 0.0)
    }

    /// Node n's data.
    fn node(&self, n: u32) -> &[f64] {
        let stride = self.table.stride;
        &self.table.nodes[n as usize * stride..(n as usize + 1) * stride]
    }

    /// The join's weight χ at ξ in tabulated leaf `leaf` (trilinear in the corners' χ).
    fn chi(&self, leaf: usize, xi: &[f64; 3]) -> f64 {
        let w = weights(xi);
        let last = self.table.stride - 1;
        (0..8)
            .map(|k| w[k] * self.node(self.table.corners[leaf][k])[last])
            .sum()
    }

    /// The tabulated leaf's interpolant at ξ (leaf edge `edge`) and χ there.
    fn tabulated(&self, leaf: usize, xi: &[f64; 3], edge: f64) -> (FlowSample, f64) {
        let ids = &self.table.corners[leaf];
        match self.table.interpolant {
            Interpolant::Trilinear => {
                let w = weights(xi);
                let mut d = [0.0; DATA];
                for (k, &n) in ids.iter().enumerate() {
                    for (dc, v) in d.iter_mut().zip(self.node(n)) {
                        *dc += w[k] * v;
                    }
                }
                let sample = FlowSample {
                    u: Vec3::from_column_slice(&d[..3]),
                    grad_u: Mat3::from_column_slice(&d[3..12]),
                    du_dt: Vec3::zeros(),
                    convective: Vec3::from_column_slice(&d[12..15]),
                };
                (sample, d[DATA - 1])
            }
            Interpolant::Hermite => {
                let (u, grad_u) = hermite::value_and_gradient(|k| &self.node(ids[k])[..HERMITE - 1], xi, edge);
                let sample = FlowSample {
                    u,
                    grad_u,
                    du_dt: Vec3::zeros(),
                    convective: grad_u * u,
                };
                (sample, self.chi(leaf, xi))
            }
        }
    }
}

impl FlowField for OctreeFlow {
    fn sample(&self, x: &Vec3, t: f64) -> Result<FlowSample, FlowError> {
        crate::flow::check_query(x, t)?;
        self.blend.cellwise().check_time(t)?;
        memo::remembered(self.id, x, t, || self.evaluate(x, t))
    }

    fn strain_rate(&self) -> Option<f64> {
        self.blend.strain_rate()
    }
}

impl OctreeFlow {
    /// The table at (x, t): a tabulated leaf's interpolant, joined to the blend by χ next to
    /// the wall leaves; the blend in a wall leaf (module docs).
    fn evaluate(&self, x: &Vec3, t: f64) -> Result<FlowSample, FlowError> {
        let Some((leaf, xi, edge)) = self.leaf(x) else {
            return self.blend.sample(x, t);
        };
        let (table, chi) = self.tabulated(leaf, &xi, edge);
        if chi <= 0.0 {
            return Ok(table);
        }
        let b = self.blend.sample(x, t)?;
        let mix = |a: f64, b: f64| (1.0 - chi) * a + chi * b;
        Ok(FlowSample {
            u: table.u.zip_map(&b.u, mix),
            grad_u: table.grad_u.zip_map(&b.grad_u, mix),
            du_dt: Vec3::zeros(),
            convective: table.convective.zip_map(&b.convective, mix),
        })
    }
}

/// A leaf of the table: its lower corner, edge, and whether it is tabulated (else a wall leaf,
/// where a sample is the blend).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LeafBox {
    /// Lower corner.
    pub lower: Vec3,
    /// Edge length.
    pub edge: f64,
    /// Tabulated (trilinear), or a wall leaf.
    pub tabulated: bool,
}
