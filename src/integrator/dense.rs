//! Dense output over one step: cubic Hermite interpolation of the barycentre x and the
//! deformation gradient F from their values and rates at both ends of the step.
//!
//! # Physics
//! None of its own: the paper's scheme has no dense output. The interpolant serves the driver's
//! output times and events (wall contact, [`crate::contact`]) between the accepted states of
//! eqs. 17, 18.
//!
//! # Accuracy
//! With exact end rates the cubic Hermite interpolant has local error O(h⁴), the same order as
//! the collocation polynomial of Radau IIA(5) and higher than the local error O(h³) of a
//! second-order step, so it never limits the accuracy of the schemes here. For the paper's
//! IMEX step the end rate A^{n+1} = (F^{n+1} − Fⁿ)/Δt is itself first order, and so is the
//! interpolant, like the scheme. The interpolant passes through both end states exactly, so an
//! event located on it is consistent with the states the driver accepted.

use crate::particle::State;
use crate::tensor::{Mat3, Vec3};

/// Values and rates at one end of a step.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Knot {
    /// Barycentre x.
    pub x: Vec3,
    /// Barycentre rate ẋ.
    pub x_dot: Vec3,
    /// Deformation gradient F.
    pub f: Mat3,
    /// Its rate Ḟ.
    pub f_dot: Mat3,
}

impl Knot {
    /// Values and rates of a state whose `v` is ẋ and whose `a` is Ḟ.
    pub fn of_state(s: &State) -> Self {
        Self {
            x: s.x,
            x_dot: s.v,
            f: s.f,
            f_dot: s.a,
        }
    }
}

/// Cubic Hermite interpolant over [t₀, t₀ + h].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Dense {
    t0: f64,
    h: f64,
    start: Knot,
    end: Knot,
}

impl Dense {
    /// Interpolant between `start` at `t0` and `end` at `t0 + h`.
    pub fn new(t0: f64, h: f64, start: Knot, end: Knot) -> Self {
        Self { t0, h, start, end }
    }

    /// Start time t₀.
    pub fn t_start(&self) -> f64 {
        self.t0
    }

    /// End time t₀ + h.
    pub fn t_end(&self) -> f64 {
        self.t0 + self.h
    }

    /// The interpolated state at `t` ∈ [t₀, t₀ + h] (clamped): x and F from the Hermite
    /// cubic, v = ẋ and A = Ḟ from its derivative.
    pub fn state_at(&self, t: f64) -> State {
        let s = ((t - self.t0) / self.h).clamp(0.0, 1.0);
        let (s2, s3) = (s * s, s * s * s);
        // Hermite basis and its derivative (per unit s).
        let (h00, h10, h01, h11) = (
            2.0 * s3 - 3.0 * s2 + 1.0,
            s3 - 2.0 * s2 + s,
            -2.0 * s3 + 3.0 * s2,
            s3 - s2,
        );
        // (The derivative of h01 is −d00.)
        let (d00, d10, d11) = (6.0 * s2 - 6.0 * s, 3.0 * s2 - 4.0 * s + 1.0, 3.0 * s2 - 2.0 * s);
        let (a, b, h) = (&self.start, &self.end, self.h);
        let x = a.x * h00 + a.x_dot * (h * h10) + b.x * h01 + b.x_dot * (h * h11);
        let f = a.f * h00 + a.f_dot * (h * h10) + b.f * h01 + b.f_dot * (h * h11);
        let v = (a.x - b.x) * (d00 / h) + a.x_dot * d10 + b.x_dot * d11;
        let fa = (a.f - b.f) * (d00 / h) + a.f_dot * d10 + b.f_dot * d11;
        State {
            t: self.t0 + s * h,
            x,
            v,
            f,
            a: fa,
        }
    }
}
