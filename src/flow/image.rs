//! Isometries of a flow: the maps by which a particle that crosses a cyclic patch, a symmetry
//! plane or a wedge continues inside the domain ([`crate::flow::openfoam::images`]).
//!
//! # Physics
//! An isometry $T(x) = Q(x − o) + o + s$ (Q orthogonal, o a point, s a shift) is a symmetry of
//! the flow u when $u(T x) = Q\\,u(x)$; then $\nabla u(Tx) = Q\\,\nabla u(x)\\,Q^T$. Periodic
//! pairs (Q = 1 or a rotation), symmetry planes (Q a reflection) and the wedges of an
//! axisymmetric case (Q a rotation about the axis) are such symmetries, and a particle's motion
//! maps with them: its image is a solution of the same equations (the model is objective and,
//! for a reflection, its laws are isotropic). A material point $x = x_c + F X$ of the image is
//! $Q x_c + Q F X$; for a reflection (det Q = −1) the image's reference configuration is relabelled
//! by $X^\prime = P X$ with $P = \mathrm{diag}(1, 1, −1)$, which maps the rest ellipsoid (semi-axes along
//! the reference axes) and its inertia onto themselves and keeps det F > 0. The state's map
//! ([`crate::particle::State::mapped`]) is
//! ```math
//! x_c' = T(x_c),\quad v_c' = Q v_c,\quad F' = Q F P,\quad \dot F' = Q \dot F P,
//! \qquad P = \begin{cases} 1 & \det Q = 1 \\ \mathrm{diag}(1,1,−1) & \det Q = −1. \end{cases}
//! ```
//! An isotropic law has W(QFP) = W(F), so the image's stress is the mapped stress. A law with a
//! preferred material direction is mapped by a reflection to its mirror image, which is another
//! material unless the direction lies along a reference axis.

use crate::tensor::{Mat3, Vec3};

use super::FlowSample;

/// $T(x) = Q(x − o) + o + s$, Q orthogonal (module docs).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Isometry {
    /// The orthogonal part Q.
    pub q: Mat3,
    /// The fixed point o of Q.
    pub origin: Vec3,
    /// The shift s.
    pub shift: Vec3,
}

impl Isometry {
    /// The translation by `s`.
    pub fn translation(s: Vec3) -> Self {
        Self {
            q: Mat3::identity(),
            origin: Vec3::zeros(),
            shift: s,
        }
    }

    /// The rotation by `angle` (rad, right-handed) about the line through `origin` along the
    /// unit vector `axis`.
    pub fn rotation(axis: &Vec3, origin: Vec3, angle: f64) -> Self {
        let axis = nalgebra::Unit::new_normalize(*axis);
        Self {
            q: *nalgebra::Rotation3::from_axis_angle(&axis, angle).matrix(),
            origin,
            shift: Vec3::zeros(),
        }
    }

    /// The reflection about the plane through `point` with unit normal `normal`.
    pub fn reflection(point: Vec3, normal: &Vec3) -> Self {
        Self {
            q: Mat3::identity() - 2.0 * normal * normal.transpose(),
            origin: point,
            shift: Vec3::zeros(),
        }
    }

    /// T(x).
    pub fn point(&self, x: &Vec3) -> Vec3 {
        self.q * (x - self.origin) + self.origin + self.shift
    }

    /// Q v: a velocity, a normal.
    pub fn vector(&self, v: &Vec3) -> Vec3 {
        self.q * v
    }

    /// The inverse map $T^{-1}(y) = Q^T(y − o − s) + o$.
    pub fn inverse(&self) -> Self {
        let q = self.q.transpose();
        Self {
            q,
            origin: self.origin + self.shift,
            shift: -self.shift,
        }
    }

    /// The flow at x from its sample at T(x): $u(x) = Q^T u(Tx)$, $\nabla u(x) = Q^T \nabla
    /// u(Tx)\\,Q$, the accelerations as u.
    pub fn pull(&self, s: &FlowSample) -> FlowSample {
        let qt = self.q.transpose();
        FlowSample {
            u: qt * s.u,
            grad_u: qt * s.grad_u * self.q,
            du_dt: qt * s.du_dt,
            convective: qt * s.convective,
        }
    }
}

/// Where a particle's barycentre crossed a patch it passes through: the patch's plane (of its
/// nearest face, for a patch that is not planar) and the map that brings it back inside.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Crossing {
    /// The map back inside.
    pub map: Isometry,
    /// A point of the crossed plane.
    pub point: Vec3,
    /// The plane's outward unit normal.
    pub normal: Vec3,
}

impl Crossing {
    /// The signed distance of x from the crossed plane, positive on the domain's side: the
    /// gap whose root the driver locates to map the particle where it crossed.
    pub fn gap(&self, x: &Vec3) -> f64 {
        (self.point - x).dot(&self.normal)
    }
}
