//! Translational drag f_D = μ_f K̂ · (u − v_c) (paper eq. 14 writes K̂ = π r_min k).
//!
//! # Physics (paper eq. 14; Brenner 1963, Oberbeck 1876)
//! For an ellipsoid with principal frame (r, Q) and integrals χ₀, α_i:
//! $\hat K = 16\pi\\, Q^T \mathrm{diag}\big(1/(\chi_0 + x_i\alpha_i)\big) Q$, i.e. the paper's
//! $k_i = 16 / (r_{min}(\chi_0 + x_i\alpha_i))$. A sphere has k = 6 (f = 6πμa u); prolate values
//! are tabulated by Brenner (1963) and tested. Derivation and the spheroid closed forms:
//! [`crate::theory::drag`].
//!
//! Drag models are selectable by name (`particles.drag` in scene files, the Python package):
//! each registers a builder ([`DragRegistration`]) in its own file, and [`by_name`] builds it.

use crate::ellipsoid::{EllipsoidIntegrals, PrincipalFrame};
use crate::error::ParamError;
use crate::registry::{self, Entry, Parameters, Values};
use crate::tensor::{Mat3, Vec3};
use serde::{Deserialize, Serialize};
use std::f64::consts::PI;
use std::fmt;
use std::sync::Arc;

pub use inventory;

/// A translational resistance model: the tensor K̂ with f_D = μ_f K̂·(u − v_c).
///
/// K̂ has dimensions of length. Implement this trait to plug in another drag law.
pub trait DragModel: Send + Sync {
    /// Resistance tensor K̂ (global components) of the ellipsoid in `frame` with integrals `ints`.
    fn resistance(&self, frame: &PrincipalFrame, ints: &EllipsoidIntegrals) -> Mat3;

    /// Whether K̂ of a sphere is the same whatever the rotation of its principal frame (true
    /// for every model that sees the frame only through the shape). The default, `false`,
    /// is the safe answer for a model with body-fixed data; with `true` a rigid sphere's
    /// orientation may be left out of the step's error test
    /// ([`crate::particle::Particle::orientation_is_passive`]).
    fn isotropic_on_spheres(&self) -> bool {
        false
    }
}

/// Brenner's exact Stokes resistance of an ellipsoid (the paper's model).
#[derive(Debug, Clone, Copy, Default, Serialize, Deserialize)]
pub struct Brenner;

impl Brenner {
    /// Principal coefficients k_i of the paper's normalisation K̂ = π r_min k.
    pub fn k_principal(frame: &PrincipalFrame, ints: &EllipsoidIntegrals) -> Vec3 {
        Vec3::from_fn(|i, _| 16.0 / (frame.r_min() * (ints.chi0 + ints.x[i] * ints.alpha[i])))
    }
}

/// Orientation-averaged translational response time of an ellipsoid with semi-axes `r`,
/// relative to the sphere of the same volume: with K̂ = diag(K_i) in the principal frame,
/// $\bar\tau/\tau_{sphere} = 6\pi a_{eq} \cdot \tfrac13 \sum_i K_i^{-1}
/// = \tfrac{a_{eq}}{8}\big(3\chi_0 + \sum_i x_i\alpha_i\big)$, a_eq the volume-equivalent radius.
/// A randomly oriented particle that does not rotate on the time scale of its response sees
/// the mean mobility $\tfrac13 \mathrm{tr}\\,\hat K^{-1}$; this is the factor by which its
/// Stokes number defined from d_eq (paper eq. 25) over-states its inertia. Exactly 1 for a
/// sphere; about 0.96, 0.80 and 0.50 for prolates λ = 2, 5 and 20.
pub fn mean_response_time_ratio(r: &Vec3) -> Result<f64, ParamError> {
    let ints = EllipsoidIntegrals::try_new(r)?;
    let a_eq = r.product().cbrt();
    Ok(a_eq / 8.0 * (3.0 * ints.chi0 + ints.x.dot(&ints.alpha)))
}

/// A borrowed drag model is the model (a particle's rigid twin borrows its drag,
/// [`crate::particle::Particle::rigid_twin`]).
impl<D: DragModel + ?Sized> DragModel for &D {
    fn resistance(&self, frame: &PrincipalFrame, ints: &EllipsoidIntegrals) -> Mat3 {
        (**self).resistance(frame, ints)
    }

    fn isotropic_on_spheres(&self) -> bool {
        (**self).isotropic_on_spheres()
    }
}

impl DragModel for Brenner {
    fn resistance(&self, frame: &PrincipalFrame, ints: &EllipsoidIntegrals) -> Mat3 {
        let k = Self::k_principal(frame, ints);
        frame.to_global(&Mat3::from_diagonal(&k)) * (PI * frame.r_min())
    }

    /// A sphere's k_i are equal (6 each), so K̂ = 6π a 1.
    fn isotropic_on_spheres(&self) -> bool {
        true
    }
}

/// Stokes drag of the volume-equivalent sphere, K̂ = 6π a_eq 1 (shape-blind reference model).
#[derive(Debug, Clone, Copy, Default, Serialize, Deserialize)]
pub struct StokesSphere;

impl DragModel for StokesSphere {
    fn resistance(&self, frame: &PrincipalFrame, _ints: &EllipsoidIntegrals) -> Mat3 {
        Mat3::identity() * (6.0 * PI * frame.r.product().cbrt())
    }

    fn isotropic_on_spheres(&self) -> bool {
        true
    }
}

/// A drag model selectable by name: its name in scene files and how to build it from its
/// parameters. Submit one with `inventory::submit!` in the model's file.
pub struct DragRegistration {
    /// Name in scene files (`particles.drag`).
    pub name: &'static str,
    /// Build the model; refuse parameters it does not take ([`Parameters::only`]).
    pub build: fn(&Parameters) -> Result<Arc<dyn DragModel>, ParamError>,
}

inventory::collect!(DragRegistration);

impl Entry for DragRegistration {
    const KIND: &'static str = "drag model";
    fn name(&self) -> &'static str {
        self.name
    }
}

/// The registered drag models' names, sorted.
pub fn names() -> Vec<&'static str> {
    registry::names::<DragRegistration>()
}

/// The registry: the drag model called `name` with parameters `values`.
pub fn by_name(name: &str, values: &Values) -> Result<NamedDrag, ParamError> {
    let entry = registry::find::<DragRegistration>(name)?;
    Ok(NamedDrag {
        name: entry.name,
        values: values.clone(),
        model: (entry.build)(&Parameters::new(entry.name, values))?,
    })
}

/// A drag model built by name, with the parameters it was built from.
#[derive(Clone)]
pub struct NamedDrag {
    name: &'static str,
    values: Values,
    model: Arc<dyn DragModel>,
}

impl NamedDrag {
    /// The registered name.
    pub fn name(&self) -> &'static str {
        self.name
    }
}

impl fmt::Debug for NamedDrag {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.debug_struct("NamedDrag")
            .field("name", &self.name)
            .field("values", &self.values)
            .finish()
    }
}

/// Two models are equal when built by the same name from the same parameters.
impl PartialEq for NamedDrag {
    fn eq(&self, other: &Self) -> bool {
        self.name == other.name && self.values == other.values
    }
}

impl DragModel for NamedDrag {
    fn resistance(&self, frame: &PrincipalFrame, ints: &EllipsoidIntegrals) -> Mat3 {
        self.model.resistance(frame, ints)
    }

    fn isotropic_on_spheres(&self) -> bool {
        self.model.isotropic_on_spheres()
    }
}

// Selectable by name: `particles.drag = "brenner"` (the default) and `"stokes_sphere"`.
inventory::submit! {
    DragRegistration {
        name: "brenner",
        build: |p| {
            p.only(&[])?;
            Ok(Arc::new(Brenner))
        },
    }
}
inventory::submit! {
    DragRegistration {
        name: "stokes_sphere",
        build: |p| {
            p.only(&[])?;
            Ok(Arc::new(StokesSphere))
        },
    }
}
