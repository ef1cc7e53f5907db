//! Wall contact as a terminal driver event.
//!
//! [`ContactEvent`] turns a [`Boundary`] into a terminal [`Event`] of the driver: g is the gap to
//! the nearest patch, located on the dense output to |g| ≤ 10⁻⁹ of the particle's equivalent
//! diameter. It caps every step so that the gap to the nearest patch can close by at most
//! g + δ_s, with δ_s half the particle's smallest rest semi-axis, at the current rates: the
//! barycentre approaches at |v·n| and a tip at distance ≤ r₁ sweeps at ≤ r₁|∇u| (rotation and
//! stretching by the flow), so $(|v·n| + r_1 |\nabla u|)\\,\Delta t \le g + \delta_s$. A tumbling tip
//! then cannot touch and leave the wall within one step.
//!
//! Only the nearest patch is watched, so the cap must also keep the particle off every other
//! patch. How it does depends on the boundary's [`Approach`]: along one smooth wall (a pipe)
//! only the normal velocity closes the gap, $|v·n|$ above. At corners and ridges (mesh walls)
//! the particle may reach another patch while moving along the nearest one; there the cap uses
//! the full speed |v|, $(|v| + r_1 |\nabla u|)\\,\Delta t \le g + \delta_s$, which keeps the
//! particle within the gap of where it was in every direction. The gap to the nearest face is a
//! lower bound of the distance to every other face: exactly so on a plane, and at a convex
//! ridge because each face's plane supports the wall. Planar walls keep the normal cap; in
//! their corners a scene caps the step by its flow speed ([`crate::driver::Plan::with_dt_max`]),
//! as the cavity does.
//!
//! # Room along smooth walls
//! Along most of a duct's wall the full speed is far too cautious: a sphere gliding parallel to
//! the wall a diameter away takes steps of about its own size, and on the 90° bend 89 % of the
//! steps are taken within about 0.4 mm of a wall. Where a mesh boundary knows that within a distance ρ of the barycentre
//! (its [`Gap::room`](super::Gap::room)) every face lies beyond the plane where the gap is
//! measured, or the faces bound a convex fluid side ([`crate::contact::mesh`], Room), the normal
//! velocity is again all that closes the gap, as long as the particle stays inside that
//! distance:
//! ```math
//! \Delta t \le \max\Big(\frac{g + \delta_s}{|v| + r_1|\nabla u|},\ \min\Big(\frac{g + \delta_s}{|v·n| + r_1|\nabla u|},\ \frac{\rho − r_1}{|v| + r_1|\nabla u|}\Big)\Big).
//! ```
//! Beyond the plane nothing can be touched in the first case. In the second a straight move
//! between two points of the convex fluid side stays in it, so a move that meets a wall ends
//! beyond it, where the gap at the step's end is negative and the event is located as any
//! other. (Both are statements about straight moves at the current rates, as the cap always
//! was.) On the bend race's 1 000 rigid spheres (`openfoam_race --integrator auto --tol 1e-2`)
//! the steps fell from 182 to 112 per particle with every fate the same; on the airway
//! bifurcation, where few steps are spent near the walls, by under 1 %.
//!
//! # Grazing contact
//! The full-speed cap lets the particle move at most g + δ_s in a step, so a contact is seen at
//! the step's end as long as the particle's overlap with the wall lasts a path longer than the
//! slack: a particle aimed at a wall ends the step at most δ_s deep in it. A particle grazing a
//! convex edge at a distance d just below its extent overlaps the wall only along a chord of
//! about $2\sqrt{2a(a − d)}$ (a the extent), which a step of slack δ_s = a/2 steps over: spheres
//! aimed 5° past a step's edge at d = 0.8a–0.95a passed through it at 1–10 m/s. In any
//! direction the slack is therefore the gap itself, between $10^{-3}δ_s$ and δ_s:
//! ```math
//! \Delta t \le \frac{g + \min(δ_s, \max(g, 10^{-3} δ_s))}{|v| + r_1|\nabla u|},
//! ```
//! so that the steps shrink geometrically as a grazing particle nears the wall and a pass
//! whose overlap chord exceeds $10^{-3}δ_s$ ends a step inside it. A particle approaching
//! head-on needs a step or two more; one gliding along a ridge at a small positive gap takes
//! steps of about twice the gap. The gap at the step's end must then be the distance to the
//! walls, not to a face's plane beyond its edge: [`crate::contact::mesh`] measures it to the
//! face polygons.
//!
//! # Queries skipped far from the walls
//! The nearest-face query of mesh walls costs as much as a third of a Radau step. Where the
//! boundary knows a lower bound c of the distance from the barycentre to its faces without a
//! query ([`Boundary::clearance`]: [`crate::contact::MeshBoundary`]'s grid of bin-centre
//! distances), the particle, reaching at most $r_1 ≤ \lVert F S\rVert_F$ from its barycentre (the
//! largest singular value is at most the Frobenius norm), is at least
//! ```math
//! d_{lb} = c − \|F S\|_F
//! ```
//! from every face. On mesh walls ([`Approach::AnyDirection`]) the event uses $d_{lb}$ where it
//! is positive and queries otherwise. The step cap takes $d_{lb}$: moving less than its
//! distance to the walls, the particle cannot reach any. The event's gap is $\tfrac12 d_{lb}$:
//! its sign is what the event needs, and near the walls every gap is a query's.
//!
//! A bound carried from the last query, $g_0 + r_{3,0} − |x − x_0| − \lVert F S\rVert_F$ with $g_0$ the
//! gap found there, is not one: $g_0$ is measured to the plane of the face the support point
//! covers, and on a non-planar patch (an outlet cap whose faces were snapped to a curved
//! surface) another face can lie nearer than that plane. Particles leaving through such a cap
//! crossed it between two queries and were integrated outside the mesh until the step failed
//! (6 of 1.2·10⁵ in the airway tree). The grid's bound holds for every face.
//!
//! Pipes and planes (their queries cost a few flops) always query.

use super::{Approach, Boundary, Extent, Gap};
use crate::driver::Event;
use crate::ellipsoid::PrincipalFrame;
use crate::flow::FlowField;
use crate::hydro::DragModel;
use crate::material::Response;
use crate::particle::{Particle, State};
use crate::tensor::{Mat3, Vec3};
use std::cell::Cell;

/// The smallest slack of a step capped by the full speed, in units of δ_s (module docs, Grazing
/// contact): a grazing pass whose overlap lasts a path shorter than this is not seen.
const GRAZE: f64 = 1e-3;

/// Which extent a [`ContactEvent`] uses.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum ContactModel {
    /// The current ellipsoid.
    Extent,
    /// The barycentre with a fixed contact distance δ (not tied to the current shape, so it
    /// cannot collapse as a soft particle thins).
    Barycentre {
        /// Contact distance δ.
        radius: f64,
    },
}

/// Wall contact of one particle with a boundary, as a terminal driver event.
pub struct ContactEvent<'a, B: ?Sized, M, D, F: ?Sized> {
    boundary: &'a B,
    particle: &'a Particle<M, D>,
    flow: &'a F,
    model: ContactModel,
    slack: f64,
    scale: f64,
    /// The last state asked about and what was found there. The driver asks for the gap at a
    /// step's end and then for the cap of the next step from that same state: one boundary
    /// query and one principal frame per step instead of two of each.
    seen: Cell<Option<Seen>>,
    /// The last state whose clearance bound was computed, and the bound: the driver asks for
    /// it at a step's end (the gap) and again for the next step's cap from that same state.
    bounded: Cell<Option<Bounded>>,
}

/// A state's barycentre and F, with [`ContactEvent::bound`] there.
#[derive(Debug, Clone, Copy)]
struct Bounded {
    x: Vec3,
    f: Mat3,
    bound: Option<(f64, f64)>,
}

/// A state's barycentre and F, with its nearest patch and longest semi-axis.
#[derive(Debug, Clone, Copy)]
struct Seen {
    x: Vec3,
    f: Mat3,
    near: Gap,
    r1: f64,
}

impl<'a, B, M, D, F> ContactEvent<'a, B, M, D, F>
where
    B: Boundary + ?Sized,
    M: Response,
    D: DragModel,
    F: FlowField + ?Sized,
{
    /// Contact of `particle` in `flow` with `boundary` under `model`.
    pub fn new(boundary: &'a B, particle: &'a Particle<M, D>, flow: &'a F, model: ContactModel) -> Self {
        let rest = particle.shape().semi_axes();
        Self {
            boundary,
            particle,
            flow,
            model,
            slack: 0.5 * rest.min(),
            scale: 2.0 * rest.product().cbrt(),
            seen: Cell::new(None),
            bounded: Cell::new(None),
        }
    }

    /// The extent of the particle in `state`.
    pub fn extent(&self, state: &State) -> Extent {
        self.extent_in(self.frame(state))
    }

    /// The nearest patch and its gap in `state`.
    pub fn nearest(&self, state: &State) -> Gap {
        self.seen(state).near
    }

    fn frame(&self, state: &State) -> PrincipalFrame {
        self.particle.frame(&state.f)
    }

    fn extent_in(&self, frame: PrincipalFrame) -> Extent {
        match self.model {
            ContactModel::Extent => Extent::Ellipsoid(frame),
            ContactModel::Barycentre { radius } => Extent::Point { radius },
        }
    }

    fn seen(&self, state: &State) -> Seen {
        if let Some(seen) = self.seen.get()
            && seen.x == state.x
            && seen.f == state.f
        {
            return seen;
        }
        let frame = self.frame(state);
        let seen = Seen {
            x: state.x,
            f: state.f,
            near: self.boundary.nearest(&state.x, &self.extent_in(frame)),
            r1: frame.r[0],
        };
        self.seen.set(Some(seen));
        seen
    }

    /// A lower bound of the distance from the particle to the walls in `state` (module docs:
    /// the boundary's clearance less the reach), with the upper bound ‖F S‖_F on the
    /// particle's r₁, on mesh walls; `None` where a query must answer. Half of it bounds the gap.
    fn bound(&self, state: &State) -> Option<(f64, f64)> {
        if self.boundary.approach() != Approach::AnyDirection {
            return None;
        }
        if self.seen.get().is_some_and(|s| s.x == state.x && s.f == state.f) {
            return None;
        }
        if let Some(b) = self.bounded.get()
            && b.x == state.x
            && b.f == state.f
        {
            return b.bound;
        }
        let bound = self.clearance_bound(state);
        self.bounded.set(Some(Bounded {
            x: state.x,
            f: state.f,
            bound,
        }));
        bound
    }

    /// [`Self::bound`] computed: the clearance less the reach, where positive.
    fn clearance_bound(&self, state: &State) -> Option<(f64, f64)> {
        let r1 = self.particle.total_distortion(&state.f).norm();
        let reach = match self.model {
            ContactModel::Extent => r1,
            ContactModel::Barycentre { radius } => radius,
        };
        let bound = self
            .boundary
            .clearance(&state.x)
            .map(|c| c - reach)
            .filter(|b| *b > 0.0)?;
        Some((bound, r1))
    }
}

impl<B, M, D, F> Event for ContactEvent<'_, B, M, D, F>
where
    B: Boundary + ?Sized,
    M: Response,
    D: DragModel,
    F: FlowField + ?Sized,
{
    fn gap(&self, state: &State) -> f64 {
        match self.bound(state) {
            Some((bound, _)) => 0.5 * bound,
            None => self.nearest(state).gap,
        }
    }

    fn scale(&self, _state: &State) -> f64 {
        self.scale
    }

    fn max_step(&self, state: &State) -> f64 {
        let sweep = match self.flow.sample(&state.x, state.t) {
            Ok(s) => s.grad_u.norm(),
            // Outside the flow the step fails anyway; do not cap.
            Err(_) => return f64::INFINITY,
        };
        // The step within which the gap can close by at most g + slack at the rate `approach`.
        let cap = |gap: f64, r1: f64, approach: f64, slack: f64| {
            (gap.max(0.0) + slack) / (approach + r1 * sweep).max(f64::MIN_POSITIVE)
        };
        // In any direction the slack shrinks with the gap (module docs, Grazing contact).
        let graze = |gap: f64| gap.clamp(GRAZE * self.slack, self.slack);
        match self.bound(state) {
            // Only on mesh walls, whose approach is the full speed.
            Some((bound, r1)) => cap(bound, r1, state.v.norm(), graze(bound)),
            None => {
                let Seen { near, r1, .. } = self.seen(state);
                let normal = cap(near.gap, r1, state.v.dot(&near.normal).abs(), self.slack);
                match self.boundary.approach() {
                    Approach::Normal => normal,
                    // Within its room only the normal velocity closes the gap (module docs):
                    // the step may be as long as the particle stays inside the room.
                    Approach::AnyDirection => {
                        let speed = (state.v.norm() + r1 * sweep).max(f64::MIN_POSITIVE);
                        let inside = (near.room - r1).max(0.0) / speed;
                        cap(near.gap, r1, state.v.norm(), graze(near.gap)).max(normal.min(inside))
                    }
                }
            }
        }
    }
}
