//! Draws that injection rules share: points on a disc (by area or by pipe flux), rotations uniform on SO(3).

use super::spec::ParticleRng;
use crate::error::{ParamError, positive};
use crate::tensor::{Mat3, Vec3};
use nalgebra::{Quaternion, UnitQuaternion};
use rand::RngExt;
use std::f64::consts::PI;

/// How points are spread over an injection disc.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, serde::Deserialize, serde::Serialize)]
#[serde(rename_all = "snake_case")]
pub enum DiscWeight {
    /// Uniform by area.
    #[default]
    Area,
    /// By the flux of fully developed laminar pipe flow through the disc, u ∝ 1 − r²/R²: the
    /// particles of a uniformly mixed suspension entering a pipe of radius R (Pich 1972's
    /// inlet). Unlike injection through a mesh's patch, which weights each face by that mesh's
    /// own flux, particle k starts at the same point on every mesh of a study.
    Poiseuille,
}

/// A point uniform (by area) on the disc of `radius` (> 0) about `centre` normal to `normal`
/// (non-zero): [`disc_point`] with [`DiscWeight::Area`].
pub fn uniform_disc(rng: &mut ParticleRng, centre: &Vec3, normal: &Vec3, radius: f64) -> Result<Vec3, ParamError> {
    disc_point(rng, centre, normal, radius, DiscWeight::Area)
}

/// A point on the disc of `radius` R (> 0) about `centre` normal to `normal` (non-zero),
/// spread by `weight`: angle φ = 2πw and radius ρ from u, for u, w uniform on [0, 1). By area
/// ρ = R√u, so that the area element ρ dρ dφ has constant density. By Poiseuille flux the
/// density is ∝ ρ(1 − ρ²/R²), whose distribution 2s − s² (s = ρ²/R²) inverts to
/// $\rho = R\sqrt{1 - \sqrt{1 - u}}$. The in-plane angle is measured from the unit vector
/// along the component of e₁ (or e₂, when `normal` is nearer e₁) normal to `normal`.
pub fn disc_point(
    rng: &mut ParticleRng,
    centre: &Vec3,
    normal: &Vec3,
    radius: f64,
    weight: DiscWeight,
) -> Result<Vec3, ParamError> {
    let radius = positive("disc radius", radius)?;
    let n = normal
        .try_normalize(0.0)
        .filter(|n| n.iter().all(|c| c.is_finite()))
        .ok_or(ParamError::NotPositive {
            name: "disc normal length",
            value: normal.norm(),
        })?;
    let seed = if n.x.abs() < 0.9 { Vec3::x() } else { Vec3::y() };
    let e1 = (seed - n * n.dot(&seed)).normalize();
    let e2 = n.cross(&e1);
    let (u, w): (f64, f64) = (rng.random(), rng.random());
    let s = match weight {
        DiscWeight::Area => u,
        DiscWeight::Poiseuille => 1.0 - (1.0 - u).sqrt(),
    };
    let (rho, phi) = (radius * s.sqrt(), 2.0 * PI * w);
    Ok(centre + rho * (phi.cos() * e1 + phi.sin() * e2))
}

/// A rotation uniform on SO(3) (Haar measure), from a unit quaternion uniform on S³ by
/// Shoemake's (1992) construction from three uniform numbers.
pub fn haar_rotation(rng: &mut ParticleRng) -> Mat3 {
    let (u1, u2, u3): (f64, f64, f64) = (rng.random(), rng.random(), rng.random());
    let (a, b) = ((1.0 - u1).sqrt(), u1.sqrt());
    let (t2, t3) = (2.0 * PI * u2, 2.0 * PI * u3);
    let q = Quaternion::new(b * t3.cos(), a * t2.sin(), a * t2.cos(), b * t3.sin());
    UnitQuaternion::from_quaternion(q).to_rotation_matrix().into_inner()
}

/// Points drawn from a set of triangles with given weights: a triangle with probability
/// proportional to its weight (inverse of the cumulative sums, binary search), then a point
/// uniform by area in it (barycentric (1 − √u, √u (1 − w), √u w), Osada et al. 2002).
#[derive(Debug, Clone, PartialEq)]
pub struct WeightedTriangles {
    triangles: Vec<[Vec3; 3]>,
    /// Cumulative weights, ending at the total.
    cumulative: Vec<f64>,
}

impl WeightedTriangles {
    /// The triangles with their weights (finite, ≥ 0, not all zero).
    pub fn new(triangles: Vec<([Vec3; 3], f64)>) -> Result<Self, ParamError> {
        let mut total = 0.0;
        let mut cumulative = Vec::with_capacity(triangles.len());
        for (_, w) in &triangles {
            if !(w.is_finite() && *w >= 0.0) {
                return Err(ParamError::NonFinite {
                    name: "triangle weight (must be finite and >= 0)",
                    value: *w,
                });
            }
            total += w;
            cumulative.push(total);
        }
        positive("total weight of the triangles", total)?;
        Ok(Self {
            triangles: triangles.into_iter().map(|(t, _)| t).collect(),
            cumulative,
        })
    }

    /// One point.
    pub fn draw(&self, rng: &mut ParticleRng) -> Vec3 {
        let total = self.cumulative[self.cumulative.len() - 1];
        let (pick, u, w): (f64, f64, f64) = (rng.random(), rng.random(), rng.random());
        let k = self
            .cumulative
            .partition_point(|&c| c <= pick * total)
            .min(self.triangles.len() - 1);
        let [a, b, c] = self.triangles[k];
        let s = u.sqrt();
        a * (1.0 - s) + b * (s * (1.0 - w)) + c * (s * w)
    }
}
