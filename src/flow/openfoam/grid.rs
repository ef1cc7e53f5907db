//! Which balls contain a point: balls of their own radii binned on a uniform grid, each bin
//! listing the balls that meet it.
//!
//! # Why bins with candidate lists
//! [`super::BlendedFlow`] asks, at every flow sample, for the cells whose support ball holds x,
//! and for the wall faces within their support of x; each ball has its own radius, fixed when
//! the field is built. A tree answers any query, and pays for it: on the airway bifurcation's
//! 37 k cells an `rstar` radius query cost about 23 000 instructions for its ~9 hits. A cell
//! list (Hockney & Eastwood 1988, §8.4) with bins of the largest radius R scans the 3³ bins
//! around x; on the bifurcation 84 % of the centres it measured lay farther than their own
//! radius (R is set by the coarsest cells), about 11 000 instructions per particle step. Here
//! each bin holds the list of the balls that meet it, so a query reads one bin's list: the balls
//! within one bin edge of holding x.
//!
//! # Bin edge and bounded memory
//! The grid covers the balls' bounding box. The bin edge starts at the median radius (a ball of
//! radius r ≈ edge meets about 8–27 bins, so a list holds about as many balls as contain a point
//! of the bin), and doubles while there would be more than 8N + 64 bins or more than 64N + bins
//! entries in the lists (a few huge balls over fine bins). Once the edge exceeds the box there is
//! one bin and N entries, so the loop ends after at most log₂(extent/edge) + 1 doublings, and
//! the memory is bounded by the balls present.
//!
//! # Cost
//! A query of the cells' grid on the airway bifurcation reads about 34 candidates for 9 hits,
//! some 44 instructions a candidate; finer lists (octants) were measured and bought little for
//! much more fill (`paper-figures/openfoam-peer/NOTES.md`, History: The blend's bin lists).

use crate::tensor::Vec3;

/// Bins allowed per ball (plus [`SPARE_BINS`]).
const BINS_PER_BALL: usize = 8;
/// Bins allowed on top of [`BINS_PER_BALL`] N, for tiny sets.
const SPARE_BINS: usize = 64;
/// List entries allowed per ball (plus one per bin).
const ENTRIES_PER_BALL: usize = 64;
/// Doublings of the bin edge allowed: 2¹⁰⁰⁰ exceeds any ratio of f64 lengths.
const MAX_DOUBLINGS: usize = 1000;

/// Balls binned for "which balls contain x" queries (module docs).
#[derive(Debug, Clone)]
pub struct BallGrid {
    origin: Vec3,
    bin: f64,
    dims: [usize; 3],
    /// `entries[starts[b]..starts[b + 1]]` are the balls meeting bin b, in ascending order.
    starts: Vec<u32>,
    entries: Vec<u32>,
    centres: Vec<Vec3>,
    radii: Vec<f64>,
}

impl BallGrid {
    /// Bin the balls (`centres[i]`, `radii[i]`), radii positive and everything finite; `None`
    /// if the lengths differ, there are more than `u32::MAX` balls or list entries, or an input
    /// is not finite or a radius not positive.
    pub fn new(centres: &[Vec3], radii: &[f64]) -> Option<Self> {
        u32::try_from(centres.len()).ok()?;
        if radii.len() != centres.len()
            || radii.iter().any(|r| !(r.is_finite() && *r > 0.0))
            || centres.iter().any(|c| !c.iter().all(|v| v.is_finite()))
        {
            return None;
        }
        let (lo, hi) = centres.iter().zip(radii).fold(
            (Vec3::repeat(f64::INFINITY), Vec3::repeat(f64::NEG_INFINITY)),
            |(lo, hi), (c, r)| (lo.inf(&c.add_scalar(-r)), hi.sup(&c.add_scalar(*r))),
        );
        let (origin, extent) = if centres.is_empty() {
            (Vec3::zeros(), Vec3::zeros())
        } else {
            (lo, hi - lo)
        };
        if !extent.iter().all(|e| e.is_finite()) {
            return None;
        }
        let mut sorted = radii.to_vec();
        sorted.sort_unstable_by(f64::total_cmp);
        let mut grid = Self {
            origin,
            bin: sorted.get(sorted.len() / 2).copied().unwrap_or(1.0),
            dims: [1; 3],
            starts: Vec::new(),
            entries: Vec::new(),
            centres: centres.to_vec(),
            radii: radii.to_vec(),
        };
        let count = |bin: f64| extent.map(|e| ((e / bin).floor() as usize).saturating_add(1));
        let allowed_bins = BINS_PER_BALL * centres.len() + SPARE_BINS;
        for _ in 0..MAX_DOUBLINGS {
            let d = count(grid.bin);
            let bins = d[0].saturating_mul(d[1]).saturating_mul(d[2]);
            if bins <= allowed_bins {
                grid.dims = [d[0], d[1], d[2]];
                let entries: usize = (0..centres.len()).map(|i| grid.boxes_met(i).1).sum();
                if entries <= ENTRIES_PER_BALL * centres.len() + bins {
                    break;
                }
            }
            grid.bin *= 2.0;
        }
        let d = count(grid.bin);
        grid.dims = [d[0], d[1], d[2]];
        grid.fill()?;
        Some(grid)
    }

    /// The bins along each axis that ball i's bounding box meets, and their number (an upper
    /// bound of the bins the ball meets).
    fn boxes_met(&self, i: usize) -> ([(usize, usize); 3], usize) {
        let (c, r) = (self.centres[i], self.radii[i]);
        let mut range = [(0usize, 0usize); 3];
        for (k, span) in range.iter_mut().enumerate() {
            let axis = |v: f64| (((v - self.origin[k]) / self.bin).floor().max(0.0) as usize).min(self.dims[k] - 1);
            *span = (axis(c[k] - r), axis(c[k] + r));
        }
        (range, range.iter().map(|(a, b)| b - a + 1).product())
    }

    /// Whether ball i meets bin `bin`: the distance from its centre to the bin's box is below
    /// its radius.
    fn meets(&self, i: usize, bin: [usize; 3]) -> bool {
        let (c, r) = (self.centres[i], self.radii[i]);
        let d2: f64 = (0..3)
            .map(|k| {
                let lo = self.origin[k] + bin[k] as f64 * self.bin;
                let gap = (lo - c[k]).max(c[k] - (lo + self.bin)).max(0.0);
                gap * gap
            })
            .sum();
        d2 < r * r
    }

    /// `on(bin, ball)` for every ball and bin it meets, ball by ball in index order.
    fn for_each_met(&self, mut on: impl FnMut(usize, usize)) {
        for i in 0..self.centres.len() {
            let (range, _) = self.boxes_met(i);
            for z in range[2].0..=range[2].1 {
                for y in range[1].0..=range[1].1 {
                    for x in range[0].0..=range[0].1 {
                        if self.meets(i, [x, y, z]) {
                            on((z * self.dims[1] + y) * self.dims[0] + x, i);
                        }
                    }
                }
            }
        }
    }

    /// Fill the bins' lists: count, then place (each list in ascending ball order); `None` if
    /// the entries outnumber `u32::MAX`.
    fn fill(&mut self) -> Option<()> {
        let n_bins = self.dims[0] * self.dims[1] * self.dims[2];
        let mut starts = vec![0u32; n_bins + 1];
        let mut overflow = false;
        self.for_each_met(|b, _| match starts[b + 1].checked_add(1) {
            Some(c) => starts[b + 1] = c,
            None => overflow = true,
        });
        for b in 0..n_bins {
            starts[b + 1] = starts[b + 1].checked_add(starts[b])?;
        }
        if overflow {
            return None;
        }
        let mut entries = vec![0u32; starts[n_bins] as usize];
        let mut next: Vec<u32> = starts[..n_bins].to_vec();
        self.for_each_met(|b, i| {
            entries[next[b] as usize] = i as u32;
            next[b] += 1;
        });
        self.starts = starts;
        self.entries = entries;
        Some(())
    }

    /// Ball i's centre.
    pub fn centre(&self, i: usize) -> Vec3 {
        self.centres[i]
    }

    /// Ball i's radius.
    pub fn radius(&self, i: usize) -> f64 {
        self.radii[i]
    }

    /// The largest radius.
    pub fn largest_radius(&self) -> f64 {
        self.radii.iter().copied().fold(0.0, f64::max)
    }

    /// Call `visit(index, centre, distance)` for every ball whose centre is nearer to `x` than
    /// its radius, in ascending index order: the same `x` always visits the same balls in the
    /// same order.
    pub fn for_each_containing(&self, x: &Vec3, mut visit: impl FnMut(usize, &Vec3, f64)) {
        let mut bin = 0;
        for k in (0..3).rev() {
            let v = ((x[k] - self.origin[k]) / self.bin).floor();
            // Outside the bounding box of the balls (or NaN): no ball holds x.
            if !(v >= 0.0 && v < self.dims[k] as f64) {
                return;
            }
            bin = bin * self.dims[k] + v as usize;
        }
        let (first, last) = (self.starts[bin] as usize, self.starts[bin + 1] as usize);
        for &i in &self.entries[first..last] {
            let centre = &self.centres[i as usize];
            let d = (x - centre).norm();
            if d < self.radii[i as usize] {
                visit(i as usize, centre, d);
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A deterministic scatter of 500 balls in a flat box, radii 0.02–0.3 (a graded mesh's
    /// supports span about as much).
    fn balls() -> (Vec<Vec3>, Vec<f64>) {
        (0..500)
            .map(|i| {
                let f = i as f64;
                (
                    Vec3::new(
                        (f * 0.618).fract() * 2.0,
                        (f * 0.414).fract(),
                        (f * 0.732).fract() * 0.1,
                    ),
                    0.02 + 0.28 * (f * 0.137).fract().powi(3),
                )
            })
            .unzip()
    }

    /// The grid visits exactly the balls a brute-force scan finds holding x, in ascending order,
    /// for queries inside, on the edge of and outside the box (where nothing may be found).
    #[test]
    fn finds_what_brute_force_finds() {
        let (centres, radii) = balls();
        let grid = BallGrid::new(&centres, &radii).unwrap();
        let mut hits = 0;
        for q in 0..2000 {
            let f = q as f64;
            let x = Vec3::new(
                (f * 0.377).fract() * 2.8 - 0.4,
                (f * 0.291).fract() * 1.8 - 0.4,
                (f * 0.853).fract() * 0.9 - 0.4,
            );
            let mut found = Vec::new();
            grid.for_each_containing(&x, |i, c, d| {
                assert_eq!(*c, centres[i]);
                assert_eq!(d, (x - c).norm());
                found.push(i);
            });
            let expected: Vec<usize> = (0..centres.len())
                .filter(|&i| (x - centres[i]).norm() < radii[i])
                .collect();
            assert_eq!(found, expected, "query {x:?}");
            hits += found.len();
        }
        assert!(hits > 2000, "the queries must hit balls: {hits}");
    }

    /// Many tiny balls spread over a box set the bins (about 8N of them); thirty balls that
    /// cover the box would then fill every bin's list (1.2·10⁵ entries). The edge grows
    /// instead, bins and entries stay within their bounds, and the queries still find what
    /// brute force finds.
    #[test]
    fn memory_is_bounded_by_the_balls() {
        let (mut centres, mut radii): (Vec<Vec3>, Vec<f64>) = (0..1000)
            .map(|i| {
                let f = i as f64;
                (
                    Vec3::new((f * 0.618).fract(), (f * 0.414).fract(), (f * 0.732).fract()),
                    1e-3,
                )
            })
            .unzip();
        for i in 0..30 {
            centres.push(Vec3::repeat(0.5 + 0.001 * i as f64));
            radii.push(2.0);
        }
        let grid = BallGrid::new(&centres, &radii).unwrap();
        let n = centres.len();
        let bins = grid.starts.len() - 1;
        assert!(bins <= BINS_PER_BALL * n + SPARE_BINS, "{bins} bins");
        assert!(
            grid.entries.len() <= ENTRIES_PER_BALL * n + bins,
            "{} entries",
            grid.entries.len()
        );
        for &q in &[7usize, 123, 999] {
            let x = centres[q] + Vec3::new(5e-4, 0.0, 0.0);
            let mut found = Vec::new();
            grid.for_each_containing(&x, |i, _, _| found.push(i));
            let expected: Vec<usize> = (0..n).filter(|&i| (x - centres[i]).norm() < radii[i]).collect();
            assert_eq!(found, expected);
            assert!(found.contains(&q));
        }
    }

    /// The balls' hits at x by brute force, in ascending order.
    fn brute_force(centres: &[Vec3], radii: &[f64], x: &Vec3) -> Vec<usize> {
        (0..centres.len())
            .filter(|&i| (x - centres[i]).norm() < radii[i])
            .collect()
    }

    /// What the grid visits at x, checking the centre and distance it passes.
    fn visited(grid: &BallGrid, centres: &[Vec3], x: &Vec3) -> Vec<usize> {
        let mut found = Vec::new();
        grid.for_each_containing(x, |i, c, d| {
            assert_eq!(*c, centres[i]);
            assert_eq!(d.to_bits(), (x - c).norm().to_bits());
            found.push(i);
        });
        found
    }

    /// xorshift64: deterministic points in [0, 1).
    fn uniform(state: &mut u64) -> f64 {
        *state ^= *state << 13;
        *state ^= *state >> 7;
        *state ^= *state << 17;
        (*state >> 11) as f64 / (1u64 << 53) as f64
    }

    /// A box meshed as 20 × 20 columns of 0.05 over a wall at z = 0 with 12 prism layers, the
    /// first 2·10⁻⁴ high, each 1.4 × the one below, then cubes of 0.05 up to z = 0.6 (9 600
    /// cells); each cell's ball of radius 1.2 × its half-diagonal, as the blend's supports.
    fn layered() -> (Vec<Vec3>, Vec<f64>) {
        let mut faces = vec![0.0];
        let mut h = 2e-4;
        for _ in 0..12 {
            faces.push(faces.last().unwrap() + h);
            h *= 1.4;
        }
        while *faces.last().unwrap() < 0.6 {
            faces.push(faces.last().unwrap() + 0.05);
        }
        let mut balls = Vec::new();
        for w in faces.windows(2) {
            for i in 0..20 {
                for j in 0..20 {
                    let half = Vec3::new(0.025, 0.025, 0.5 * (w[1] - w[0]));
                    let centre = Vec3::new(0.05 * i as f64 + 0.025, 0.05 * j as f64 + 0.025, w[0] + half[2]);
                    balls.push((centre, 1.2 * half.norm()));
                }
            }
        }
        balls.into_iter().unzip()
    }

    /// Near a prism-layered wall a bin holds every layer's balls (radii 0.042 to the cubes'
    /// 0.052) and a query's hits change from layer to layer: the query
    /// visits exactly what brute force finds, in the same order with the same distances, at
    /// 2·10⁴ points (half within a cube's height of the wall, crowded towards it).
    #[test]
    fn near_a_layered_wall_it_finds_what_brute_force_finds() {
        let (centres, radii) = layered();
        let grid = BallGrid::new(&centres, &radii).unwrap();
        let mut state = 0x2545F4914F6CDD1D;
        let mut hits = 0;
        for q in 0..20_000 {
            let mut x = Vec3::new(
                uniform(&mut state),
                uniform(&mut state),
                0.7 * uniform(&mut state) - 0.05,
            );
            if q % 2 == 1 {
                x[2] = 0.05 * uniform(&mut state).powi(4);
                let found = visited(&grid, &centres, &x);
                hits += found.len();
                assert_eq!(found, brute_force(&centres, &radii, &x), "query {x:?}");
            } else {
                assert_eq!(
                    visited(&grid, &centres, &x),
                    brute_force(&centres, &radii, &x),
                    "query {x:?}"
                );
            }
        }
        assert!(hits > 20_000, "the queries must hit balls: {hits}");
    }

    /// Degenerate sets: 2 000 equal balls at one point, and one ball over the whole box of 2 000
    /// tiny ones: the bins and entries stay within their bounds, and the queries find what
    /// brute force finds.
    #[test]
    fn degenerate_sets_stay_bounded() {
        let point = (vec![Vec3::new(0.3, -0.2, 0.1); 2000], vec![0.5; 2000]);
        let (mut centres, mut radii): (Vec<Vec3>, Vec<f64>) = (0..2000)
            .map(|i| {
                let f = i as f64;
                (
                    Vec3::new((f * 0.618).fract(), (f * 0.414).fract(), (f * 0.732).fract()),
                    1e-3,
                )
            })
            .unzip();
        centres.push(Vec3::repeat(0.5));
        radii.push(10.0);
        let mut state = 7;
        for (centres, radii) in [point, (centres, radii)] {
            let grid = BallGrid::new(&centres, &radii).unwrap();
            let (n, bins) = (centres.len(), grid.dims.iter().product::<usize>());
            assert!(bins <= BINS_PER_BALL * n + SPARE_BINS, "{bins} bins");
            assert!(
                grid.entries.len() <= ENTRIES_PER_BALL * n + bins,
                "{} entries",
                grid.entries.len()
            );
            for q in 0..2000 {
                let x = if q % 2 == 0 {
                    centres[q] + Vec3::new(5e-4, 0.0, -3e-4)
                } else {
                    Vec3::new(uniform(&mut state), uniform(&mut state), uniform(&mut state)) * 2.0 - Vec3::repeat(0.5)
                };
                assert_eq!(
                    visited(&grid, &centres, &x),
                    brute_force(&centres, &radii, &x),
                    "query {x:?}"
                );
            }
        }
    }

    proptest::proptest! {
        #![proptest_config(proptest::prelude::ProptestConfig::with_cases(64))]
        /// Any set of up to 300 balls with radii over four decades, queried at their centres
        /// moved by up to their radius (on and near the spheres) and anywhere in their box:
        /// the grid visits what brute force finds.
        #[test]
        fn any_balls_any_points(
            balls in proptest::collection::vec(((-1.0..1.0f64, -1.0..1.0f64, -1.0..1.0f64), -4.0..0.0f64), 1..300),
            offsets in proptest::collection::vec((-1.0..1.0f64, -1.0..1.0f64, -1.0..1.0f64), 50),
        ) {
            let (centres, radii): (Vec<Vec3>, Vec<f64>) =
                balls.iter().map(|&((x, y, z), e)| (Vec3::new(x, y, z), 10f64.powf(e))).unzip();
            let grid = BallGrid::new(&centres, &radii).unwrap();
            for (k, &(a, b, c)) in offsets.iter().enumerate() {
                let i = k % centres.len();
                for x in [centres[i] + Vec3::new(a, b, c) * radii[i], Vec3::new(a, b, c) * 1.5] {
                    proptest::prop_assert_eq!(visited(&grid, &centres, &x), brute_force(&centres, &radii, &x));
                }
            }
        }
    }

    #[test]
    fn refuses_bad_input() {
        let one = [Vec3::zeros()];
        assert!(BallGrid::new(&one, &[0.0]).is_none());
        assert!(BallGrid::new(&one, &[f64::NAN]).is_none());
        assert!(BallGrid::new(&one, &[1.0, 2.0]).is_none());
        assert!(BallGrid::new(&[Vec3::new(f64::INFINITY, 0.0, 0.0)], &[1.0]).is_none());
        assert!(BallGrid::new(&[Vec3::new(f64::MAX, 0.0, 0.0)], &[f64::MAX]).is_none());
        let empty = BallGrid::new(&[], &[]).unwrap();
        empty.for_each_containing(&Vec3::zeros(), |_, _, _| panic!("no balls"));
        let grid = BallGrid::new(&one, &[1.0]).unwrap();
        grid.for_each_containing(&Vec3::repeat(f64::NAN), |_, _, _| panic!("NaN holds nothing"));
    }
}
