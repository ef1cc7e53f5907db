//! Building the table: the root cubes over the mesh, the split test level by level, the
//! balance next to the wall leaves and the corner data with the hanging corners constrained
//! (module docs of [`crate::flow::openfoam::octree`]).

use super::budget::{ENTRY_BYTES, SAMPLE_BYTES, default_max_bytes};
use super::*;
use crate::flow::FlowField;
use crate::flow::openfoam::FoamError;
use crate::flow::openfoam::memo;
use crate::tensor::Mat3;
use rstar::{AABB, RTree, RTreeObject};
use std::collections::HashMap;

/// A wall face's bounding box grown by its support, for the search of the faces a leaf meets.
struct FaceBox {
    face: usize,
    envelope: AABB<[f64; 3]>,
}

impl RTreeObject for FaceBox {
    type Envelope = AABB<[f64; 3]>;
    fn envelope(&self) -> Self::Envelope {
        self.envelope
    }
}

struct Builder<'a> {
    blend: &'a BlendedFlow,
    time: f64,
    origin: Vec3,
    edge: f64,
    dims: [usize; 3],
    faces: RTree<FaceBox>,
    samples: HashMap<Lattice, Datum>,
    tree: Vec<u32>,
    levels: Vec<u32>,
    corners_of: Vec<Lattice>,
    u_tol: f64,
    gradient_tol: f64,
    budget: usize,
    max_bytes: usize,
    wall_leaf: f64,
    interpolant: Interpolant,
    report: BuildReport,
}

/// A trilinear datum's ∂u_i/∂x_j (∇u column-major after u).
fn gradient_entry(d: &[f64; DATA], i: usize, j: usize) -> f64 {
    d[3 + i + 3 * j]
}

/// Hermite corner data of a cube of edge `edge` from its corners' blended u and ∇u alone, the
/// mixed derivatives the cube's one-sided differences of ∇u, f_xyz zero: what the split test
/// of a Hermite leaf uses (the table's nodes take centred differences, [`Builder::finish`]).
fn hermite_corners(data: &[[f64; DATA]], edge: f64) -> Vec<[f64; HERMITE]> {
    (0..8)
        .map(|k| {
            let mut h = [0.0; HERMITE];
            // ∂(∂u_c/∂x_j)/∂x_a from the corner across axis a.
            let along = |c: usize, j: usize, a: usize| {
                let sign = if (k >> a) & 1 == 0 { 1.0 } else { -1.0 };
                sign * (gradient_entry(&data[k ^ (1 << a)], c, j) - gradient_entry(&data[k], c, j)) / edge
            };
            for c in 0..3 {
                let q = c * hermite::QUANTITIES;
                h[q] = data[k][c];
                for a in 0..3 {
                    h[q + (1 << a)] = gradient_entry(&data[k], c, a);
                }
                for (a, b) in [(0, 1), (0, 2), (1, 2)] {
                    h[q + (1 << a) + (1 << b)] = 0.5 * (along(c, a, b) + along(c, b, a));
                }
            }
            h
        })
        .collect()
}

impl Builder<'_> {
    fn position(&self, p: &Lattice) -> Vec3 {
        let unit = self.edge / f64::from(1u32 << MAX_LEVEL);
        self.origin + Vec3::new(f64::from(p[0]), f64::from(p[1]), f64::from(p[2])) * unit
    }

    fn centre_and_radius(&self, cube: &Cube) -> (Vec3, f64) {
        let unit = self.edge / f64::from(1u32 << MAX_LEVEL);
        let e = f64::from(cube.span()) * unit;
        (
            self.position(&cube.corner) + Vec3::repeat(0.5 * e),
            0.5 * 3f64.sqrt() * e,
        )
    }

    /// The smallest support of the wall faces whose support the cube may meet, `None` if it
    /// meets none.
    fn wall_support(&self, cube: &Cube) -> Option<f64> {
        let (centre, radius) = self.centre_and_radius(cube);
        let walls = self.blend.wall_faces();
        let lo = centre.add_scalar(-radius);
        let hi = centre.add_scalar(radius);
        let query = AABB::from_corners([lo[0], lo[1], lo[2]], [hi[0], hi[1], hi[2]]);
        self.faces
            .locate_in_envelope_intersecting(query)
            .filter(|b| walls.distance(b.face, &centre) - radius < walls.support(b.face))
            .map(|b| walls.support(b.face))
            .reduce(f64::min)
    }

    /// Evaluate the blend at every lattice point not yet sampled (in parallel where the crate
    /// has its thread pool).
    fn sample_all(&mut self, points: Vec<Lattice>) -> Result<(), FoamError> {
        let mut fresh: Vec<Lattice> = points.into_iter().filter(|p| !self.samples.contains_key(p)).collect();
        fresh.sort_unstable();
        fresh.dedup();
        let samples = self.samples.len() + fresh.len();
        let bytes = samples * SAMPLE_BYTES + self.tree.len() * ENTRY_BYTES;
        if bytes > self.max_bytes {
            return Err(FoamError::TableTooLarge {
                bytes,
                limit: self.max_bytes,
                samples,
                leaves: self.leaves(),
                budget: self.budget,
                cells: self.report.cells,
            });
        }
        let evaluate = |p: &Lattice| {
            self.blend
                .sample(&self.position(p), self.time)
                .ok()
                .map(|s| datum(&s))
                .filter(|d| d.iter().all(|v| v.is_finite()))
        };
        #[cfg(feature = "parallel")]
        let values: Vec<Datum> = {
            use rayon::prelude::*;
            fresh.par_iter().map(evaluate).collect()
        };
        #[cfg(not(feature = "parallel"))]
        let values: Vec<Datum> = fresh.iter().map(evaluate).collect();
        self.samples.extend(fresh.into_iter().zip(values));
        Ok(())
    }

    /// The 27 points of a cube (corners, edge and face midpoints, centre).
    fn lattice_points(cube: &Cube) -> impl Iterator<Item = Lattice> + '_ {
        (0..27u32).map(move |n| cube.point(n % 3, n / 3 % 3, n / 9))
    }

    /// Corner k's lattice point (k's bits: the x, y, z ends).
    fn corner(cube: &Cube, k: usize) -> Lattice {
        let end = |b: usize| 2 * ((k >> b) & 1) as u32;
        cube.point(end(0), end(1), end(2))
    }

    /// Largest misses of the cube's interpolant at its 19 midpoints (|Δu| and the
    /// Frobenius norm of Δ∇u); `None` where a point is outside every support.
    fn misses(&self, cube: &Cube) -> Option<(f64, f64)> {
        let data: Vec<[f64; DATA]> = (0..8)
            .map(|k| self.samples[&Self::corner(cube, k)])
            .collect::<Option<_>>()?;
        let edge = f64::from(cube.span()) * self.edge / f64::from(1u32 << MAX_LEVEL);
        let hermite = (self.interpolant == Interpolant::Hermite).then(|| hermite_corners(&data, edge));
        let (mut u_miss, mut g_miss) = (0.0f64, 0.0f64);
        for n in 0..27u32 {
            let (i, j, k) = (n % 3, n / 3 % 3, n / 9);
            if i % 2 == 0 && j % 2 == 0 && k % 2 == 0 {
                continue;
            }
            let exact = self.samples[&cube.point(i, j, k)]?;
            let xi = [f64::from(i) / 2.0, f64::from(j) / 2.0, f64::from(k) / 2.0];
            let mut d = [0.0; 12];
            if let Some(h) = &hermite {
                let (u, g) = hermite::value_and_gradient(|k| &h[k][..HERMITE - 1], &xi, edge);
                d[..3].copy_from_slice(u.as_slice());
                d[3..].copy_from_slice(g.as_slice());
            } else {
                let w = weights(&xi);
                for (c, v) in d.iter_mut().enumerate() {
                    *v = (0..8).map(|q| w[q] * data[q][c]).sum::<f64>();
                }
            }
            let du = (0..3).map(|c| (d[c] - exact[c]).powi(2)).sum::<f64>().sqrt();
            let dg = (3..12).map(|c| (d[c] - exact[c]).powi(2)).sum::<f64>().sqrt();
            u_miss = u_miss.max(du);
            g_miss = g_miss.max(dg);
        }
        Some((u_miss, g_miss))
    }

    /// Split entry `cube` into 8 children appended to the tree.
    fn split(&mut self, cube: &Cube) -> [Cube; 8] {
        let first = self.tree.len();
        self.tree[cube.entry] = BRANCH | first as u32;
        for c in 0..8 {
            let child = cube.child(c, first + c);
            self.tree.push(WALL);
            self.levels.push(child.level);
            self.corners_of.push(child.corner);
        }
        std::array::from_fn(|c| cube.child(c, first + c))
    }

    fn leaves(&self) -> usize {
        // Every split turns one leaf into eight.
        self.tree.len() - (self.tree.len() - self.dims.iter().product::<usize>()) / 8
    }

    /// Decide each cube of one level: split (the children are returned), a wall leaf or a
    /// tabulated leaf (module docs).
    fn settle(&mut self, level: Vec<Cube>) -> Result<Vec<Cube>, FoamError> {
        let walls: Vec<Option<f64>> = level.iter().map(|c| self.wall_support(c)).collect();
        let points: Vec<Lattice> = level
            .iter()
            .zip(&walls)
            .filter(|(_, w)| w.is_none())
            .flat_map(|(c, _)| Self::lattice_points(c).collect::<Vec<_>>())
            .collect();
        self.sample_all(points)?;
        let unit = self.edge / f64::from(1u32 << MAX_LEVEL);
        let mut next = Vec::new();
        for (cube, wall) in level.iter().zip(walls) {
            let e = f64::from(cube.span()) * unit;
            let can_split = cube.level < MAX_LEVEL && self.leaves() + 7 <= self.budget;
            let split = match wall {
                Some(support) => e > self.wall_leaf * support,
                None => {
                    let inside: Vec<Vec3> = Self::lattice_points(cube)
                        .filter(|p| self.samples[p].is_some())
                        .map(|p| self.position(&p))
                        .collect();
                    let finest = inside
                        .iter()
                        .filter_map(|x| self.blend.finest_support(x))
                        .reduce(f64::min);
                    match self.misses(cube) {
                        // Inside the supports: split while coarser than a support or missing.
                        Some((u, g)) => {
                            let missing = u > CHECK_SHARE * self.u_tol || g > CHECK_SHARE * self.gradient_tol;
                            if (missing || finest.is_some_and(|r| e > r)) && can_split {
                                true
                            } else if missing {
                                // Out of depth or budget: the blend itself.
                                self.report.unconverged += 1;
                                false
                            } else {
                                self.tree[cube.entry] = TABLE;
                                self.note_miss(u, g);
                                continue;
                            }
                        }
                        // Across the edge of the supports (an inlet or outlet): down to the
                        // supports' size, then the blend; wholly outside: the blend.
                        None => finest.is_some_and(|r| e > r),
                    }
                }
            };
            if split && can_split {
                next.extend(self.split(cube));
            } else {
                self.tree[cube.entry] = WALL;
            }
        }
        Ok(next)
    }

    fn note_miss(&mut self, u: f64, g: f64) {
        self.report.u_miss = self.report.u_miss.max(u / self.report.u_max);
        self.report.gradient_miss = self.report.gradient_miss.max(g / self.report.gradient_max);
    }

    /// The leaf holding the point `q` of the doubled lattice (twice the lattice coordinates,
    /// so the points half a unit off the lattice have integer coordinates): its entry, level
    /// and lower corner; `None` outside the root cubes.
    fn leaf_at(&self, q: [i64; 3]) -> Option<Cube> {
        let span = 2i64 << MAX_LEVEL;
        let mut root = 0usize;
        for a in (0..3).rev() {
            let r = q[a].div_euclid(span);
            if r < 0 || r >= self.dims[a] as i64 {
                return None;
            }
            root = root * self.dims[a] + r as usize;
        }
        let mut entry = root;
        for _ in 0..=MAX_LEVEL {
            if self.tree[entry] & TAG != BRANCH {
                return Some(Cube {
                    entry,
                    level: self.levels[entry],
                    corner: self.corners_of[entry],
                });
            }
            let cube = Cube {
                entry,
                level: self.levels[entry],
                corner: self.corners_of[entry],
            };
            let h = i64::from(cube.span());
            let c: usize = (0..3)
                .map(|a| usize::from(q[a] >= 2 * i64::from(cube.corner[a]) + h) << a)
                .sum();
            entry = (self.tree[entry] & !TAG) as usize + c;
        }
        None
    }

    /// Split tabulated leaves larger than a wall leaf they touch, until none is (module docs).
    fn balance(&mut self) -> Result<(), FoamError> {
        for _ in 0..4 * MAX_LEVEL {
            let mut coarse: Vec<usize> = Vec::new();
            for entry in 0..self.tree.len() {
                if self.tree[entry] & TAG != WALL {
                    continue;
                }
                let cube = Cube {
                    entry,
                    level: self.levels[entry],
                    corner: self.corners_of[entry],
                };
                let s = 2 * i64::from(cube.span());
                for n in 0..27i64 {
                    let d = [n % 3 - 1, n / 3 % 3 - 1, n / 9 - 1];
                    if d == [0, 0, 0] {
                        continue;
                    }
                    let q: [i64; 3] = std::array::from_fn(|a| {
                        let lo = 2 * i64::from(cube.corner[a]);
                        match d[a] {
                            -1 => lo - 1,
                            0 => lo + s / 2,
                            _ => lo + s + 1,
                        }
                    });
                    if let Some(n) = self.leaf_at(q)
                        && self.tree[n.entry] & TAG == TABLE
                        && n.level < cube.level
                    {
                        coarse.push(n.entry);
                    }
                }
            }
            coarse.sort_unstable();
            coarse.dedup();
            if coarse.is_empty() {
                return Ok(());
            }
            let mut children = Vec::new();
            for entry in coarse {
                let cube = Cube {
                    entry,
                    level: self.levels[entry],
                    corner: self.corners_of[entry],
                };
                children.extend(self.split(&cube));
            }
            let points: Vec<Lattice> = children
                .iter()
                .flat_map(|c| Self::lattice_points(c).collect::<Vec<_>>())
                .collect();
            let walls: Vec<Option<f64>> = children.iter().map(|c| self.wall_support(c)).collect();
            self.sample_all(points)?;
            for (child, wall) in children.iter().zip(walls) {
                let corners_inside = (0..8).all(|k| self.samples[&Self::corner(child, k)].is_some());
                self.tree[child.entry] = if wall.is_none() && corners_inside { TABLE } else { WALL };
            }
        }
        Ok(())
    }
}

impl Builder<'_> {
    /// The corner nodes of the tabulated leaves, their data (χ included) with the hanging
    /// corners constrained (module docs), and the final tree.
    fn finish(mut self) -> Table {
        let leaves: Vec<Cube> = (0..self.tree.len())
            .filter(|&e| self.tree[e] & TAG == TABLE)
            .map(|entry| Cube {
                entry,
                level: self.levels[entry],
                corner: self.corners_of[entry],
            })
            .collect();
        let mut index: HashMap<Lattice, u32> = HashMap::new();
        let mut points: Vec<Lattice> = Vec::new();
        let mut corners: Vec<[u32; 8]> = Vec::with_capacity(leaves.len());
        for (n, leaf) in leaves.iter().enumerate() {
            self.tree[leaf.entry] = TABLE | n as u32;
            corners.push(std::array::from_fn(|k| {
                let p = Self::corner(leaf, k);
                *index.entry(p).or_insert_with(|| {
                    points.push(p);
                    (points.len() - 1) as u32
                })
            }));
        }
        // Each node's data, the deepest leaf it is a point of, and the coarsest tabulated
        // leaf it hangs on (if any).
        let stride = match self.interpolant {
            Interpolant::Trilinear => DATA,
            Interpolant::Hermite => HERMITE,
        };
        let mut nodes = vec![0.0; points.len() * stride];
        let mut deepest = vec![0u32; points.len()];
        let mut hanging: Vec<(u32, usize, Cube)> = Vec::new();
        for (n, p) in points.iter().enumerate() {
            let d = &mut nodes[n * stride..(n + 1) * stride];
            if let Some(s) = self.samples[p] {
                match self.interpolant {
                    Interpolant::Trilinear => d[..DATA - 1].copy_from_slice(&s[..DATA - 1]),
                    Interpolant::Hermite => {
                        for c in 0..3 {
                            d[c * hermite::QUANTITIES] = s[c];
                            for a in 0..3 {
                                d[c * hermite::QUANTITIES + (1 << a)] = gradient_entry(&s, c, a);
                            }
                        }
                    }
                }
            }
            let mut host: Option<Cube> = None;
            for o in 0..8 {
                let q: [i64; 3] = std::array::from_fn(|a| 2 * i64::from(p[a]) + if (o >> a) & 1 == 1 { 1 } else { -1 });
                let Some(leaf) = self.leaf_at(q) else { continue };
                deepest[n] = deepest[n].max(leaf.level);
                match self.tree[leaf.entry] & TAG {
                    WALL => d[stride - 1] = 1.0,
                    TABLE
                        if (0..8).all(|k| Self::corner(&leaf, k) != *p)
                            && host.is_none_or(|h| leaf.level < h.level) =>
                    {
                        host = Some(leaf);
                    }
                    _ => {}
                }
            }
            if let Some(h) = host {
                hanging.push((h.level, n, h));
            }
        }
        if self.interpolant == Interpolant::Hermite {
            let free: Vec<usize> = {
                let mut is_hanging = vec![false; points.len()];
                for &(_, n, _) in &hanging {
                    is_hanging[n] = true;
                }
                (0..points.len())
                    .filter(|&n| !is_hanging[n] && self.samples[&points[n]].is_some())
                    .collect()
            };
            let mixed = self.mixed_derivatives(&free, &points, &deepest);
            for (&n, m) in free.iter().zip(mixed) {
                for c in 0..3 {
                    for (pair, &(a, b)) in [(0, 1), (0, 2), (1, 2)].iter().enumerate() {
                        nodes[n * stride + c * hermite::QUANTITIES + (1 << a) + (1 << b)] = m[3 * c + pair];
                    }
                }
            }
        }
        hanging.sort_by_key(|&(level, n, _)| (level, n));
        self.report.hanging = hanging.len();
        let unit = self.edge / f64::from(1u32 << MAX_LEVEL);
        for (_, n, host) in hanging {
            let span = f64::from(host.span());
            let xi: [f64; 3] = std::array::from_fn(|a| f64::from(points[n][a] - host.corner[a]) / span);
            let w = weights(&xi);
            let ids = corners[(self.tree[host.entry] & !TAG) as usize];
            let node = |k: usize| &nodes[ids[k] as usize * stride..(ids[k] as usize + 1) * stride];
            let mut d = vec![0.0; stride];
            match self.interpolant {
                Interpolant::Trilinear => {
                    for (c, v) in d.iter_mut().enumerate() {
                        *v = (0..8).map(|k| w[k] * node(k)[c]).sum();
                    }
                }
                Interpolant::Hermite => {
                    for q in 0..hermite::QUANTITIES {
                        let v = hermite::derivative(|k| &node(k)[..stride - 1], &xi, span * unit, q);
                        for c in 0..3 {
                            d[c * hermite::QUANTITIES + q] = v[c];
                        }
                    }
                    d[stride - 1] = (0..8).map(|k| w[k] * node(k)[stride - 1]).sum();
                }
            }
            nodes[n * stride..(n + 1) * stride].copy_from_slice(&d);
        }
        let wall_leaves = (0..self.tree.len()).filter(|&e| self.tree[e] & TAG == WALL).count();
        let bytes =
            self.tree.len() * size_of::<u32>() + corners.len() * size_of::<[u32; 8]>() + nodes.len() * size_of::<f64>();
        Table {
            origin: self.origin,
            edge: self.edge,
            dims: self.dims,
            tree: self.tree,
            report: BuildReport {
                table_leaves: corners.len(),
                wall_leaves,
                nodes: points.len(),
                bytes,
                ..self.report
            },
            corners,
            nodes,
            stride,
            interpolant: self.interpolant,
        }
    }

    /// The mixed second derivatives ∂²u_c/∂x_a∂x_b (a < b: xy, xz, yz; 3 per component) at
    /// nodes `which`: centred differences of the blend's ∇u over ±ε along each axis, ε half the
    /// edge of the smallest leaf the node is a corner of (one-sided where a side is outside
    /// every support, zero where both are), symmetrised over the two orders.
    fn mixed_derivatives(&self, which: &[usize], points: &[Lattice], deepest: &[u32]) -> Vec<[f64; 9]> {
        let compute = |&n: &usize| -> [f64; 9] {
            let x = self.position(&points[n]);
            let eps = 0.5 * self.edge / f64::from(1u32 << deepest[n]);
            let at = |y: Vec3| {
                self.blend
                    .sample(&y, self.time)
                    .ok()
                    .map(|s| s.grad_u)
                    .filter(|g| g.iter().all(|v| v.is_finite()))
            };
            let centre = self.samples[&points[n]].map(|s| Mat3::from_column_slice(&s[3..12]));
            // ∂(∇u)/∂x_a.
            let slope: [Mat3; 3] = std::array::from_fn(|a| {
                let step = Vec3::ith(a, eps);
                match (at(x - step), centre, at(x + step)) {
                    (Some(lo), _, Some(hi)) => (hi - lo) / (2.0 * eps),
                    (None, Some(c), Some(hi)) => (hi - c) / eps,
                    (Some(lo), Some(c), None) => (c - lo) / eps,
                    _ => Mat3::zeros(),
                }
            });
            let mut m = [0.0; 9];
            for c in 0..3 {
                for (pair, &(a, b)) in [(0, 1), (0, 2), (1, 2)].iter().enumerate() {
                    m[3 * c + pair] = 0.5 * (slope[b][(c, a)] + slope[a][(c, b)]);
                }
            }
            m
        };
        #[cfg(feature = "parallel")]
        {
            use rayon::prelude::*;
            which.par_iter().map(compute).collect()
        }
        #[cfg(not(feature = "parallel"))]
        which.iter().map(compute).collect()
    }
}

impl OctreeFlow {
    /// Tabulate the steady field `blend` (module docs); an error for a field with more than
    /// one time level or a mesh whose extent is not finite.
    pub fn new(blend: BlendedFlow) -> Result<Self, FoamError> {
        Self::with_options(blend, Options::default())
    }

    /// [`OctreeFlow::new`] with other tolerances or leaf budget; an error for tolerances not
    /// positive, a wall leaf not finite and positive or a budget below one leaf per cell.
    pub fn with_options(blend: BlendedFlow, options: Options) -> Result<Self, FoamError> {
        let Options {
            u_tolerance,
            gradient_tolerance,
            leaves_per_cell,
            wall_leaf,
            interpolant,
            max_bytes,
        } = options;
        // A tolerance may be infinite: leaves sized by the mesh alone (the fates measured in
        // `paper-figures/fig18/NOTES.md`, History).
        if !([u_tolerance, gradient_tolerance].iter().all(|t| *t > 0.0)
            && wall_leaf.is_finite()
            && wall_leaf > 0.0
            && leaves_per_cell >= 1)
        {
            return Err(FoamError::Field {
                path: "(octree)".into(),
                reason: format!(
                    "tolerances {u_tolerance:e} (u) and {gradient_tolerance:e} (∇u) and the wall leaf {wall_leaf:e} \
                     must be positive (the wall leaf finite), and the budget {leaves_per_cell} leaves per cell at least 1"
                ),
            });
        }
        let cellwise = blend.cellwise();
        let times = cellwise.times();
        if times.len() != 1 {
            return Err(FoamError::Field {
                path: "(time directories)".into(),
                reason: format!(
                    "the octree tabulates a steady field (one time level), this one has {}; use the blend",
                    times.len()
                ),
            });
        }
        let mesh = cellwise.mesh();
        let max_bytes = max_bytes.unwrap_or_else(|| default_max_bytes(mesh));
        let (lo, hi) = mesh.points().iter().fold(
            (Vec3::repeat(f64::INFINITY), Vec3::repeat(f64::NEG_INFINITY)),
            |(lo, hi), p| (lo.inf(p), hi.sup(p)),
        );
        let n_cells = mesh.n_cells().max(1);
        let mut edge = blend.radius();
        let extent = hi - lo;
        if !(extent.iter().all(|e| e.is_finite()) && edge.is_finite() && edge > 0.0) {
            return Err(FoamError::Mesh {
                reason: format!("cannot tabulate a field on a mesh of extent {extent:?} and support {edge:e}"),
            });
        }
        // The root cubes cover the mesh with a margin of a tenth of a cube; at most one per
        // cell and 2¹⁹ along an axis (lattice coordinates fit u32).
        let origin = lo.add_scalar(-0.1 * edge);
        let dims = loop {
            let dims: [usize; 3] = std::array::from_fn(|a| ((extent[a] + 0.2 * edge) / edge).ceil().max(1.0) as usize);
            if dims.iter().product::<usize>() <= n_cells && dims.iter().all(|&d| d <= 1 << 19) {
                break dims;
            }
            edge *= 2.0;
        };
        let (mut u_max, mut gradient_max) = (0.0f64, 0.0f64);
        for c in 0..mesh.n_cells() {
            let s = cellwise.sample_cell(c, &mesh.cell_centres()[c], times[0]);
            u_max = u_max.max(s.u.norm());
            gradient_max = gradient_max.max(s.grad_u.norm());
        }
        let (u_max, gradient_max) = (u_max.max(f64::MIN_POSITIVE), gradient_max.max(f64::MIN_POSITIVE));
        let walls = blend.wall_faces();
        let faces = RTree::bulk_load(
            (0..walls.len())
                .map(|k| {
                    let grow = walls.support(k);
                    let (lo, hi) = walls
                        .vertices(k)
                        .iter()
                        .fold((walls.centre(k), walls.centre(k)), |(lo, hi), p| (lo.inf(p), hi.sup(p)));
                    let (lo, hi) = (lo.add_scalar(-grow), hi.add_scalar(grow));
                    FaceBox {
                        face: k,
                        envelope: AABB::from_corners([lo[0], lo[1], lo[2]], [hi[0], hi[1], hi[2]]),
                    }
                })
                .collect(),
        );
        let roots = dims.iter().product::<usize>();
        let mut builder = Builder {
            blend: &blend,
            time: times[0],
            origin,
            edge,
            dims,
            faces,
            samples: HashMap::new(),
            tree: vec![WALL; roots],
            levels: vec![0; roots],
            corners_of: (0..roots)
                .map(|r| {
                    let (x, y, z) = (r % dims[0], r / dims[0] % dims[1], r / (dims[0] * dims[1]));
                    [x as u32, y as u32, z as u32].map(|v| v << MAX_LEVEL)
                })
                .collect(),
            u_tol: u_tolerance * u_max,
            gradient_tol: gradient_tolerance * gradient_max,
            budget: leaves_per_cell.saturating_mul(n_cells),
            max_bytes,
            wall_leaf,
            interpolant,
            report: BuildReport {
                u_max,
                gradient_max,
                cells: mesh.n_cells(),
                ..BuildReport::default()
            },
        };
        let mut level: Vec<Cube> = (0..roots)
            .map(|entry| Cube {
                entry,
                level: 0,
                corner: builder.corners_of[entry],
            })
            .collect();
        for _ in 0..=MAX_LEVEL {
            if level.is_empty() {
                break;
            }
            level = builder.settle(level)?;
        }
        builder.balance()?;
        let table = builder.finish();
        Ok(Self {
            blend,
            table,
            id: memo::new_id(),
        })
    }
}
