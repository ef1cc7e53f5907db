//! A transient OpenFOAM field read lazily: of its time levels, only those around the current
//! time window are held.
//!
//! # Memory
//! [`FoamFlow::read`] holds every level asked for: 12 f64 per cell a level (u and ∇u), 0.48 GB
//! a level for a 5 M-cell airway. [`TransientFlow`] builds the mesh, the cell locator, the
//! gradient stencils and the wall geometry once, and holds the levels of one window of time:
//! [`TransientFlow::slide`] to [start, end] keeps the levels from the last one at or before
//! `start` to the first one after `end` (two when the window lies between two levels, three
//! when it spans one), dropping the others before it computes the new ones ([`super::frame`]:
//! u, ∇u and the wall fits, in f64 or f32). Its peak memory is that of the mesh and three
//! levels, whatever the number of levels.
//!
//! Opening reads every level once, one at a time: to refuse a bad level before a run of hours
//! reaches it, to find the no-slip walls (wall patches whose velocity every level prescribes,
//! as [`FoamFlow::new`] decides them) and to hash the levels for
//! [`TransientFlow::fingerprint`]. Its gradients are computed when a window needs it.
//!
//! # Interpolation in time: linear, argued
//! Between two levels $t_a < t < t_b$ u and ∇u are linear in t and ∂u/∂t is the levels'
//! difference over $t_b − t_a$ (what [`FoamFlow`] does, bit for bit: the window holds the same
//! two levels). The error of linear interpolation is
//! ```math
//! |u − I_1 u| \le \tfrac{1}{8} Δt_w^2 \max|\partial_t^2 u|
//! ```
//! with $Δt_w$ the spacing of the written levels: for a flow periodic in T (a breathing cycle)
//! with N levels a period, $\partial_t^2 u \sim (2\pi/T)^2 U$ and the relative error is
//! $\pi^2/(2N^2)$, 1.2·10⁻⁴ for N = 200; ∂u/∂t is accurate to $\pi/N$. The solver's own step
//! $Δt_s$ (Courant-limited, second order in time with `backward` or `CrankNicolson`) is a
//! fraction of $Δt_w$, so the levels are accurate to $O(Δt_s^2)$ and the interpolation's
//! $O(Δt_w^2)$ dominates: it is set by the case's `writeInterval`, which can be chosen for it.
//! Higher order (cubic through four levels) would cut the error to $O(Δt_w^4)$ but hold four
//! levels instead of two, and it overshoots where the flow changes abruptly (a valve opening,
//! the turn from inspiration to expiration), inventing velocities the solver never had. Linear
//! interpolation is bounded by its levels, and its order is measured: in the tests (a flow
//! $u(x) \sin\omega t$ written as time directories: observed order 1.98 at the midpoints), and
//! on icoFoam's cavity with a lid oscillating in T = 0.5 s, written every 2.5 ms step
//! (`cases/oscillating-cavity`, `examples/transient_interpolation`: every k-th level kept, the
//! others compared at the cell centres): relative errors 4.9·10⁻⁴, 2.0·10⁻³, 7.9·10⁻³,
//! 3.1·10⁻², 0.12 for N = 100, 50, 25, 12.5, 6.25 levels a period, order 2.00, on the estimate
//! $\pi^2/(2N^2)$.
//!
//! # Periodic fields
//! [`Cycle::Periodic`] repeats the levels with period P (a breathing cycle solved once): the
//! level at $τ_k$ stands for every $τ_k + cP$, so the window holds levels of the unrolled
//! sequence at those times, and a window across the end of a cycle holds the last levels of
//! one cycle and the first of the next. The levels must cover one period: they span at most
//! P, and the wrap from the last level back to the first ($τ_0 + P − τ_{n−1}$) is no longer
//! than the largest spacing between levels; a level at $τ_0 + P$ itself is the start of the
//! next cycle and is not read (the first level stands for it). Anything else is a
//! [`FoamError::Period`].
//!
//! # Threads
//! [`FlowField::sample`] takes `&self` and is shared by the threads of one window;
//! [`TransientFlow::slide`] takes `&mut self`, between windows, so no sample ever sees a
//! half-slid field and no lock is needed. A time outside the held window is a
//! [`FlowError::OutsideTimeWindow`], never a level held beyond its span.

use super::frame::{self, Frame, Geometry, Precision};
use super::{BlendedFlow, FoamCase, FoamError, FoamFlow, Stencils, WallGeometry, same_time};
use crate::error::FlowError;
use crate::flow::{Crossing, FlowField, FlowSample};
use crate::tensor::Vec3;

/// How a transient field's levels repeat.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub enum Cycle {
    /// Once: before the first level and after the last the field holds that level.
    #[default]
    Once,
    /// Repeated with this period (module docs, Periodic fields).
    Periodic {
        /// The period P.
        period: f64,
    },
}

/// A cellwise field whose levels a [`TransientFlow`] slides: [`FoamFlow`], or the continuous
/// [`BlendedFlow`] over it. The sampling code is theirs; the window only changes the levels
/// the cellwise field holds.
pub trait Windowed: FlowField + Sized {
    /// The field over `cellwise` (its mesh and walls; its levels are replaced by windows).
    fn over(cellwise: FoamFlow) -> Result<Self, FoamError>;

    /// The cellwise field underneath.
    fn cellwise(&self) -> &FoamFlow;

    /// The cellwise field, to replace its levels: a field that remembers samples forgets
    /// them here.
    fn cellwise_mut(&mut self) -> &mut FoamFlow;

    /// The field's fingerprint from its cellwise field's `fingerprint`.
    fn describe(fingerprint: String) -> String;
}

impl Windowed for FoamFlow {
    fn over(cellwise: FoamFlow) -> Result<Self, FoamError> {
        Ok(cellwise)
    }

    fn cellwise(&self) -> &FoamFlow {
        self
    }

    fn cellwise_mut(&mut self) -> &mut FoamFlow {
        self
    }

    fn describe(fingerprint: String) -> String {
        fingerprint
    }
}

impl Windowed for BlendedFlow {
    fn over(cellwise: FoamFlow) -> Result<Self, FoamError> {
        BlendedFlow::new(cellwise)
    }

    fn cellwise(&self) -> &FoamFlow {
        BlendedFlow::cellwise(self)
    }

    fn cellwise_mut(&mut self) -> &mut FoamFlow {
        self.forget_samples();
        self.cellwise_levels()
    }

    fn describe(fingerprint: String) -> String {
        format!("blended {fingerprint}")
    }
}

/// A transient field over a case's time directories, holding one window of levels (module
/// docs).
#[derive(Debug)]
pub struct TransientFlow<F> {
    case: FoamCase,
    /// The case's times of the levels, ascending (one period's, for a periodic field).
    levels: Vec<f64>,
    cycle: Cycle,
    precision: Precision,
    stencils: Stencils,
    flow: F,
    /// The unrolled index of each level `flow` holds (module docs, Periodic fields).
    held: Vec<i64>,
    fingerprint: String,
}

impl<F: Windowed> TransientFlow<F> {
    /// The velocity `U` of `case` at the case's times `times` (any order, distinct), repeated
    /// as `cycle` says, stored in `precision`, holding the window at the first level.
    pub fn open(case: FoamCase, times: &[f64], cycle: Cycle, precision: Precision) -> Result<Self, FoamError> {
        let mut levels = times.to_vec();
        levels.sort_by(f64::total_cmp);
        if levels.is_empty() || levels.iter().any(|t| !t.is_finite()) {
            return Err(FoamError::Field {
                path: "(velocity)".into(),
                reason: format!("time levels must be finite and at least one, got {times:?}"),
            });
        }
        if let Some(w) = levels.windows(2).find(|w| same_time(w[0], w[1])) {
            return Err(FoamError::Field {
                path: "(velocity)".into(),
                reason: format!("time levels must be distinct, got {} and {}", w[0], w[1]),
            });
        }
        if let Cycle::Periodic { period } = cycle {
            one_period(&mut levels, period)?;
        }
        // One pass over every level, one at a time: shapes, walls and the fingerprint.
        let mesh = case.mesh();
        let mut fixed = vec![true; mesh.patches().len()];
        let mut hash = super::level_hash(levels.len());
        for &t in &levels {
            let field = case.read_field(t, "U", 3)?;
            frame::check_shape(mesh, t, &field)?;
            fixed.iter_mut().zip(&field.fixed).for_each(|(a, &b)| *a &= b);
            super::hash_level(&mut hash, t, mesh.n_cells(), field.internal.iter().copied());
        }
        let walls = super::no_slip_walls(mesh, &fixed);
        let mut fingerprint = super::describe(mesh, levels.len(), &walls, hash);
        if let Cycle::Periodic { period } = cycle {
            fingerprint.push_str(&format!(", periodic in {period:e}"));
        }
        if precision == Precision::F32 {
            fingerprint.push_str(", stored in f32");
        }
        let stencils = Stencils::new(mesh)?;
        let wall_layer = WallGeometry::new(mesh, &walls);
        let first = {
            let geometry = Geometry {
                mesh,
                stencils: &stencils,
                walls: &walls,
                wall_layer: &wall_layer,
            };
            Frame::compute(&geometry, levels[0], &case.read_field(levels[0], "U", 3)?, precision)?
        };
        // The strain rate of the first level, as for a field holding every level.
        let strain_rate = first.strain_rate(mesh);
        let cellwise = FoamFlow::assemble(mesh.clone(), walls, wall_layer, vec![first], strain_rate)?;
        let mut flow = Self {
            fingerprint: F::describe(fingerprint),
            flow: F::over(cellwise)?,
            case,
            levels,
            cycle,
            precision,
            stencils,
            held: vec![0],
        };
        let start = flow.levels[0];
        flow.slide(start, start)?;
        Ok(flow)
    }

    /// Hold the levels that answer every time in [start, end] (module docs): those held already
    /// are kept, the others dropped before the new ones are computed. Every level inside the
    /// window is held too, so memory grows with the window's width: slide in steps of about
    /// the levels' spacing. A periodic field refuses a window that would hold more than one
    /// cycle's levels and the two around them. On an error (a level that cannot be read) the
    /// field answers no time until a window is held.
    pub fn slide(&mut self, start: f64, end: f64) -> Result<(), FoamError> {
        let refuse = |reason: String| FoamError::Window { start, end, reason };
        if !(start.is_finite() && end.is_finite() && start <= end) {
            return Err(refuse("the window must be finite with start <= end".into()));
        }
        let (first, last) = match self.cycle {
            Cycle::Once => {
                let n = self.levels.len();
                let first = self.levels.partition_point(|&t| t <= start).saturating_sub(1);
                (
                    first as i64,
                    self.levels.partition_point(|&t| t <= end).min(n - 1) as i64,
                )
            }
            Cycle::Periodic { period } => {
                let m = self.levels.len() as f64;
                // Unrolled indices stay exact in f64 and i64 within 2⁵² levels.
                let cycles = |t: f64| ((t - self.levels[0]) / period).floor();
                let limit = 2f64.powi(52) / m;
                if cycles(start).abs() >= limit || cycles(end).abs() >= limit {
                    return Err(refuse(format!(
                        "more than 2^52 levels from the first level's time {} with period {period}",
                        self.levels[0]
                    )));
                }
                (self.at_or_before(start, period), self.at_or_before(end, period) + 1)
            }
        };
        let (span_start, span_end) = match self.cycle {
            Cycle::Once => (
                if first == 0 {
                    f64::NEG_INFINITY
                } else {
                    self.time_of(first)
                },
                if last as usize == self.levels.len() - 1 {
                    f64::INFINITY
                } else {
                    self.time_of(last)
                },
            ),
            Cycle::Periodic { .. } => (self.time_of(first), self.time_of(last)),
        };
        // A window longer than the period would hold (and compute) levels twice.
        if last - first > self.levels.len() as i64 + 1 {
            return Err(refuse(format!(
                "it would hold {} levels of a cycle of {}: slide by at most a period",
                last - first + 1,
                self.levels.len()
            )));
        }
        // Far from the first level, τ + cP rounds away the spacing of the levels.
        if let Some(j) = (first..last).find(|&j| self.time_of(j + 1) <= self.time_of(j)) {
            return Err(refuse(format!(
                "levels {j} and {} of the unrolled cycle both fall at t = {}: too many periods from the first level for f64",
                j + 1,
                self.time_of(j)
            )));
        }
        let cellwise = self.flow.cellwise_mut();
        let mut kept: Vec<(i64, Frame)> = std::mem::take(&mut cellwise.frames)
            .into_iter()
            .zip(self.held.drain(..))
            .filter(|(_, j)| (first..=last).contains(j))
            .map(|(f, j)| (j, f))
            .collect();
        cellwise.span = (f64::INFINITY, f64::NEG_INFINITY);
        let mut frames = Vec::with_capacity((last - first + 1) as usize);
        let mut held = Vec::with_capacity(frames.capacity());
        for j in first..=last {
            let frame = match kept.iter().position(|(k, _)| *k == j) {
                Some(i) => kept.swap_remove(i).1,
                None => self.level(j)?,
            };
            frames.push(frame);
            held.push(j);
        }
        self.held = held;
        self.flow.cellwise_mut().hold(frames, (span_start, span_end));
        Ok(())
    }

    /// The largest unrolled index whose time is at or before t, for a field periodic in
    /// `period`.
    fn at_or_before(&self, t: f64, period: f64) -> i64 {
        let m = self.levels.len() as i64;
        let c = ((t - self.levels[0]) / period).floor();
        let k = self.levels.partition_point(|&tau| tau + c * period <= t) as i64;
        let mut j = c as i64 * m + k - 1;
        // The guess is off by at most one level where the rounding of τ + cP and of the
        // division disagree; each loop runs at most m times.
        for _ in 0..=m {
            if self.time_of(j + 1) <= t {
                j += 1;
            } else {
                break;
            }
        }
        for _ in 0..=m {
            if self.time_of(j) > t {
                j -= 1;
            } else {
                break;
            }
        }
        j
    }

    /// The time of unrolled level j: the level's own time, plus whole periods for a periodic
    /// field.
    fn time_of(&self, j: i64) -> f64 {
        let m = self.levels.len() as i64;
        match self.cycle {
            Cycle::Once => self.levels[j as usize],
            Cycle::Periodic { period } => self.levels[j.rem_euclid(m) as usize] + j.div_euclid(m) as f64 * period,
        }
    }

    /// Unrolled level j, read and computed.
    fn level(&self, j: i64) -> Result<Frame, FoamError> {
        let m = self.levels.len() as i64;
        let case_time = self.levels[j.rem_euclid(m) as usize];
        let field = self.case.read_field(case_time, "U", 3)?;
        let cellwise = self.flow.cellwise();
        let geometry = Geometry {
            mesh: cellwise.mesh(),
            stencils: &self.stencils,
            walls: cellwise.walls(),
            wall_layer: cellwise.wall_layer(),
        };
        Frame::compute(&geometry, self.time_of(j), &field, self.precision)
    }

    /// The times the held levels answer: the window slid to, widened to its levels (infinite
    /// where a non-periodic field holds its first or last level).
    pub fn window(&self) -> (f64, f64) {
        self.flow.cellwise().span
    }

    /// The times of the levels held, ascending (unrolled for a periodic field).
    pub fn held_times(&self) -> Vec<f64> {
        self.flow.cellwise().times()
    }

    /// The field of the held window (its mesh, walls and levels).
    pub fn field(&self) -> &F {
        &self.flow
    }

    /// The case's times of the levels, ascending (one period's for a periodic field).
    pub fn levels(&self) -> &[f64] {
        &self.levels
    }

    /// How the levels repeat.
    pub fn cycle(&self) -> Cycle {
        self.cycle
    }

    /// The mesh.
    pub fn mesh(&self) -> &super::PolyMesh {
        self.flow.cellwise().mesh()
    }

    /// What identifies this field for a run's configuration hash: for a non-periodic f64
    /// field, the [`FoamFlow::fingerprint`] (or [`BlendedFlow::fingerprint`]) of the same
    /// levels all read; the period and f32 storage are added where they apply.
    pub fn fingerprint(&self) -> &str {
        &self.fingerprint
    }
}

/// The window ends of a run from 0 to `t_end` in windows of length `window` (> 0): every
/// multiple of `window` below `t_end`, then `t_end` (a last window shorter than a thousandth of
/// one is merged into the one before: it would cost every particle a landing step for nothing).
/// The command's schedule on a transient field (a scene's `flow.window`, by default the smallest
/// spacing of the levels); the batch runner (`population::batch`) slides the field to each end.
pub fn window_ends(window: f64, t_end: f64) -> Vec<f64> {
    let n = (t_end / window).floor() as u64;
    let mut ends = vec![0.0];
    ends.extend(
        (1..=n)
            .map(|k| k as f64 * window)
            .filter(|&t| t < t_end - 1e-3 * window),
    );
    ends.push(t_end);
    ends
}

/// Check that `levels` (ascending, distinct) cover one period (module docs) and drop a last
/// level at the first's time plus the period.
fn one_period(levels: &mut Vec<f64>, period: f64) -> Result<(), FoamError> {
    let (first, last) = (levels[0], levels[levels.len() - 1]);
    let refuse = |reason: String| FoamError::Period {
        period,
        first,
        last,
        reason,
    };
    if !(period.is_finite() && period > 0.0) {
        return Err(refuse("the period must be positive and finite".into()));
    }
    if levels.len() > 1 && same_time(last, first + period) {
        let _ = levels.pop();
    }
    if levels.len() < 2 {
        return Err(refuse(
            "at least two levels within one period are needed (one level is a steady field)".into(),
        ));
    }
    let end = levels[levels.len() - 1];
    if end >= first + period {
        return Err(refuse(format!("the levels span {}, more than one period", end - first)));
    }
    let spacing = levels.windows(2).map(|w| w[1] - w[0]).fold(0.0, f64::max);
    let wrap = first + period - end;
    if wrap > spacing * (1.0 + 1e-9) {
        return Err(refuse(format!(
            "the wrap from the last level back to the first spans {wrap}, more than the largest spacing {spacing} between levels: the levels do not cover the period"
        )));
    }
    Ok(())
}

impl<F: Windowed> FlowField for TransientFlow<F> {
    fn sample(&self, x: &Vec3, t: f64) -> Result<FlowSample, FlowError> {
        self.flow.sample(x, t)
    }

    fn image(&self, x: &Vec3, t: f64) -> Option<Crossing> {
        self.flow.image(x, t)
    }

    /// The volume mean of the cells' √(2 D:D) at the first level.
    fn strain_rate(&self) -> Option<f64> {
        self.flow.strain_rate()
    }
}
