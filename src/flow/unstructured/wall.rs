//! Domain walls and particle–wall contact for deposition.
//!
//! # Physics
//! The domain is the intersection of half-spaces $\{x : (x − p_w)·n_w ≤ 0\}$, one per wall w
//! with outward unit normal $n_w$. A particle is an ellipsoid with barycentre $x_c$, semi-axes
//! $r_a$ and rotation Q whose rows are the principal directions $n_a$. Its extent along n is
//! the support distance $h(n) = \sqrt{\sum_a r_a^2 (n·n_a)^2}$, so it touches wall w when the
//! gap $g_w = (p_w − x_c)·n_w − h(n_w) ≤ 0$. Each wall carries a rule: the particle leaves
//! the domain ([`WallRule::Exit`], the cavity lid in paper §6.3) or deposits
//! ([`WallRule::Stick`], every other wall).

pub use crate::ellipsoid::frame::support_distance;
use crate::error::ParamError;
use crate::tensor::{Mat3, Vec3};
use serde::{Deserialize, Serialize};

/// What happens to a particle that touches a wall.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
pub enum WallRule {
    /// The particle leaves the domain through this wall.
    Exit,
    /// The particle deposits (sticks) on this wall.
    Stick,
}

/// One planar wall.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Wall {
    /// Name (for reports), e.g. the OpenFOAM patch.
    pub name: String,
    /// A point on the wall plane.
    pub point: Vec3,
    /// Outward unit normal.
    pub normal: Vec3,
    /// Contact rule.
    pub rule: WallRule,
}

/// A particle touching a wall.
#[derive(Debug, Clone, PartialEq)]
pub struct WallContact {
    /// Index of the wall in [`Boundary::walls`].
    pub wall: usize,
    /// The wall's rule.
    pub rule: WallRule,
    /// Gap $g_w ≤ 0$ (negative: overlap depth).
    pub gap: f64,
}

/// The boundary of a convex domain bounded by planar walls.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Boundary {
    walls: Vec<Wall>,
}

impl Boundary {
    /// Boundary from walls; normals are normalised and must be finite and non-zero.
    pub fn new(walls: Vec<Wall>) -> Result<Self, ParamError> {
        let walls = walls
            .into_iter()
            .map(|mut w| {
                let len = w.normal.norm();
                if !len.is_finite() || len <= 0.0 {
                    return Err(ParamError::NotPositive {
                        name: "wall normal length",
                        value: len,
                    });
                }
                if !w.point.iter().all(|c| c.is_finite()) {
                    return Err(ParamError::NonFinite {
                        name: "wall point",
                        value: w.point.amax(),
                    });
                }
                w.normal /= len;
                Ok(w)
            })
            .collect::<Result<_, _>>()?;
        Ok(Self { walls })
    }

    /// The cube [0, L]³ of paper §6.3: lid z = L ([`WallRule::Exit`]), the five other walls
    /// [`WallRule::Stick`].
    pub fn cavity(edge: f64) -> Result<Self, ParamError> {
        let l = crate::error::positive("cavity edge", edge)?;
        let wall = |name: &str, point: Vec3, normal: Vec3, rule| Wall {
            name: name.to_string(),
            point,
            normal,
            rule,
        };
        let (o, top) = (Vec3::zeros(), Vec3::repeat(l));
        Self::new(vec![
            wall("lid", top, Vec3::z(), WallRule::Exit),
            wall("bottom", o, -Vec3::z(), WallRule::Stick),
            wall("x0", o, -Vec3::x(), WallRule::Stick),
            wall("x1", top, Vec3::x(), WallRule::Stick),
            wall("y0", o, -Vec3::y(), WallRule::Stick),
            wall("y1", top, Vec3::y(), WallRule::Stick),
        ])
    }

    /// The walls.
    pub fn walls(&self) -> &[Wall] {
        &self.walls
    }

    /// Gap $g_w$ between the particle and each wall (negative: overlap).
    pub fn gaps<'a>(&'a self, centre: &'a Vec3, semi_axes: &'a Vec3, q: &'a Mat3) -> impl Iterator<Item = f64> + 'a {
        self.walls
            .iter()
            .map(move |w| (w.point - centre).dot(&w.normal) - support_distance(semi_axes, q, &w.normal))
    }

    /// The wall the particle touches most deeply (gap ≤ 0), if any.
    pub fn contact(&self, centre: &Vec3, semi_axes: &Vec3, q: &Mat3) -> Option<WallContact> {
        self.gaps(centre, semi_axes, q)
            .enumerate()
            .filter(|&(_, gap)| gap <= 0.0)
            .min_by(|a, b| a.1.total_cmp(&b.1))
            .map(|(wall, gap)| WallContact {
                wall,
                rule: self.walls[wall].rule,
                gap,
            })
    }
}
