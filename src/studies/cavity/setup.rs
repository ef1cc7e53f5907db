//! The cavity's set-up choices: what touches a wall, which particle is released, the field
//! variant and the shape model.

use super::*;

/// What touches a wall.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
pub enum Contact {
    /// The particle's surface (support distance of the current ellipsoid): physical.
    Extent,
    /// The barycentre (a point particle, as a point-particle tracker does), touching at a fixed
    /// distance of [`BARYCENTRE_CONTACT_DISTANCE`] from a wall. The distance is fixed, not a
    /// fraction of the current shape: a soft particle thinning in the corner flow would
    /// otherwise shrink its own margin to nothing and park against the wall.
    Barycentre,
}

impl Contact {
    /// The contact rule this choice is ([`ContactModel`]).
    pub fn model(self) -> ContactModel {
        match self {
            Contact::Extent => ContactModel::Extent,
            Contact::Barycentre => ContactModel::Barycentre {
                radius: BARYCENTRE_CONTACT_DISTANCE,
            },
        }
    }

    /// Label for datasets.
    pub fn label(self) -> &'static str {
        match self {
            Contact::Extent => "extent",
            Contact::Barycentre => "barycentre",
        }
    }
}

/// One release: shape and softness (Ca at the release shear rate γ̇₀).
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Launch {
    /// Initial shape.
    pub shape: Shape,
    /// Deformability.
    pub softness: Deformability,
}

impl Launch {
    /// Capillary number, or `None` for the rigid limit.
    pub fn ca(&self) -> Option<f64> {
        match self.softness {
            Deformability::Rigid => None,
            Deformability::Elastic { ca } => Some(ca),
        }
    }
}

/// How the shape responds (the barycentre is inertial in both).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
pub enum ShapeModel {
    /// Inertialess shape (ρ* → 0): [`Stokesian`] at rtol = atol = tol, Radau IIA unless
    /// [`Cavity::with_scheme`] says otherwise.
    Inertialess,
    /// Solid inertia as in the paper: [`ImexAdaptive`] with local tolerance tol.
    Inertial,
}

impl ShapeModel {
    /// Label for datasets.
    pub fn label(self) -> &'static str {
        match self {
            ShapeModel::Inertialess => "inertialess",
            ShapeModel::Inertial => "inertial",
        }
    }
}

/// A variant of the shipped field within the set-up's uncertainty.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Variant {
    /// Mirror about x = L/2: the lid moves along −x (the release point stays where it is).
    pub mirrored: bool,
    /// Factor on u and ∇u (the field's grid error is ≈ 4 %).
    pub scale: f64,
}

impl Default for Variant {
    fn default() -> Self {
        Self {
            mirrored: false,
            scale: 1.0,
        }
    }
}

/// The shipped field seen through a [`Variant`]: with J = diag(−1, 1, 1) and the mirror
/// x ↦ Jx + L e_x, u′(x) = s J u(Jx + L e_x) and ∇u′(x) = s J ∇u(Jx + L e_x) J.
#[derive(Clone, Copy)]
pub(super) struct VariantFlow<'a> {
    pub(super) mesh: &'a BlendedFlow,
    pub(super) variant: Variant,
}

impl FlowField for VariantFlow<'_> {
    fn sample(&self, x: &Vec3, t: f64) -> Result<crate::flow::FlowSample, crate::error::FlowError> {
        let s = self.variant.scale;
        if !self.variant.mirrored {
            let mut sample = self.mesh.sample(x, t)?;
            sample.u *= s;
            sample.grad_u *= s;
            return Ok(sample);
        }
        let j = Mat3::from_diagonal(&Vec3::new(-1.0, 1.0, 1.0));
        let mut sample = self.mesh.sample(&Vec3::new(EDGE - x[0], x[1], x[2]), t)?;
        sample.u = j * sample.u * s;
        sample.grad_u = j * sample.grad_u * j * s;
        Ok(sample)
    }

    fn strain_rate(&self) -> Option<f64> {
        self.mesh.strain_rate().map(|r| r * self.variant.scale.abs())
    }
}

/// The fluid-inertia force terms a particle of nearly the fluid's density needs (the cavity's
/// ρ_p/ρ_f = 1 − ρ* = 0.9995): the undisturbed-flow force and added mass
/// ([`crate::hydro::forces`]).
pub fn fluid_inertia() -> Result<ForceTerms, ParamError> {
    ForceTerms::new(vec![Arc::new(UndisturbedFlow), Arc::new(AddedMass)])
}
