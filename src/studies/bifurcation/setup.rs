//! The airway and its air (paper §6.4): dimensions, fluid, particle density, the Stokes number
//! and the meshed flow.
//!
//! # Physics
//! Stokes number of a particle of volume-equivalent diameter d_eq in the parent branch (eq. 25
//! with L = D and U the mean inlet velocity):
//! ```math
//! Stk = \frac{\rho_p}{\rho_f}\frac{d_{eq}^2 U}{18\,\nu_f D} = \frac{\rho_p}{\rho_f}\frac{Re\, d_{eq}^2}{18\, D^2},
//! \qquad Re = \frac{U D}{\nu_f},
//! ```
//! so with Re fixed only the density ratio enters. The paper does not state ρ_p; its three
//! pairs (Stk 0.1 ↔ 8.06 µm, 0.4 ↔ 16.12 µm, 0.5 ↔ 18.03 µm) all hold, to the printed
//! digits, for ρ_p/ρ_f ∈ [1993.7, 1994.4]; we take [`DENSITY_RATIO`] = 1994.

use crate::contact::MeshBoundary;
use crate::error::{ParamError, positive};
use crate::flow::openfoam::{BlendedFlow, FoamCase, FoamError, FoamFlow};
use crate::particle::Fluid;
use std::path::{Path, PathBuf};

/// Radius R of the parent and both daughters (D = 6 mm).
pub const RADIUS: f64 = 3e-3;
/// Diameter D of the parent and both daughters.
pub const DIAMETER: f64 = 2.0 * RADIUS;
/// Total length L along the parent axis e₁, inlet plane to outlet plane.
pub const LENGTH: f64 = 0.04;
/// Streamwise position of the carina apex ("bifurcation radius A"), x₁/L.
pub const CARINA_X_OVER_L: f64 = 0.77;
/// Angle between the two daughter axes α.
pub const BIFURCATION_ANGLE_DEG: f64 = 60.0;
/// Reynolds number of the parent branch, U D/ν.
pub const REYNOLDS: f64 = 500.0;
/// Kinematic viscosity of air [m²/s], as in the paper's §6.2.
pub const NU: f64 = 1.491e-5;
/// Density of air [kg/m³], as in the paper's §6.2.
pub const RHO_FLUID: f64 = 1.208;
/// ρ_p/ρ_f implied by the paper's (Stk, d_eq) pairs (module docs).
pub const DENSITY_RATIO: f64 = 1994.0;
/// Diameter of the injection disc at the inlet.
pub const INJECTION_DIAMETER: f64 = 5.5e-3;
/// Streamwise position of the injection disc: 0.2 mm downstream of the inlet plane (half a cell
/// of the shipped mesh), so the flow is sampled inside the first cells and the longest particle
/// studied (λ₁ = 20 at Stk = 0.5, r₁ = 66 µm) is clear of the inlet patch.
pub const INJECTION_X: f64 = 2e-4;
/// Gravitational acceleration along the streamwise direction +e₁ [m/s²] (paper Fig. 17).
pub const GRAVITY: f64 = 9.81;
/// Tracking time in mean residence times of the flow (paper §6.4, after Zhang et al.).
pub const RESIDENCE_TIMES: f64 = 10.0;

/// Mean inlet velocity U = Re ν/D (1.2425 m/s).
pub fn inlet_velocity() -> f64 {
    REYNOLDS * NU / DIAMETER
}

/// Particle density ρ_p = [`DENSITY_RATIO`] ρ_f.
pub fn rho_particle() -> f64 {
    DENSITY_RATIO * RHO_FLUID
}

/// Air: μ_f = ρ_f ν_f, ρ_f.
pub fn fluid() -> Fluid {
    Fluid {
        mu: RHO_FLUID * NU,
        rho: RHO_FLUID,
    }
}

/// Branching angle θ between the parent and a daughter axis, α/2 (rad): the θ of the Zhang et
/// al. correlation, which in its source and in the codes that use it is the angle by which the
/// flow turns into one daughter, not the angle between the daughters.
pub fn branching_angle() -> f64 {
    (0.5 * BIFURCATION_ANGLE_DEG).to_radians()
}

/// Stk of a particle of volume-equivalent diameter `d_eq` (> 0) (module docs).
pub fn stokes_number(d_eq: f64) -> Result<f64, ParamError> {
    let d = positive("d_eq", d_eq)?;
    Ok(DENSITY_RATIO * REYNOLDS * d * d / (18.0 * DIAMETER * DIAMETER))
}

/// The volume-equivalent diameter of Stokes number `stokes` (> 0).
pub fn d_eq_for_stokes(stokes: f64) -> Result<f64, ParamError> {
    let stk = positive("Stokes number", stokes)?;
    Ok(DIAMETER * (18.0 * stk / (DENSITY_RATIO * REYNOLDS)).sqrt())
}

/// The Zhang et al. (1997) deposition efficiency at Stokes number `stokes` for this airway
/// (Re = 500, θ = 30°, [`crate::reference::zhang_deposition_efficiency`]).
pub fn zhang_reference(stokes: f64) -> Result<f64, ParamError> {
    crate::reference::zhang_deposition_efficiency(stokes, REYNOLDS, branching_angle())
}

/// The meshed airway: the steady flow and the particle boundaries (patches `inlet`, `outlet1`,
/// `outlet2`: exits; `wall`: deposition). The flow is the continuous blend of the cells' linear
/// fits ([`BlendedFlow`]): the cellwise field's jumps at faces cost the adaptive integrator most
/// of its steps and trap some particles on faces.
///
/// Any case of this family opens the same way: an `inlet` patch in the plane x₁ = 0 with the
/// uniform inflow [`inlet_velocity`] along e₁ into a parent of diameter [`DIAMETER`], `wall`
/// patches and exits of type patch. The multi-generation tree (`cases/airway-tree`,
/// [`crate::studies::airway_tree`], eight outlets) is one: its G3 tube is this parent, so the
/// Stokes and capillary numbers, the injection and the tracking rule carry over unchanged.
#[derive(Debug, Clone)]
pub struct Airway {
    flow: BlendedFlow,
    boundary: MeshBoundary,
    residence_time: f64,
}

impl Airway {
    /// The field shipped in `reference-data/bifurcation` (made by `cases/bifurcation/Allrun`
    /// with 0.3 mm cells and `Allship`).
    pub fn shipped_dir() -> PathBuf {
        Path::new(env!("CARGO_MANIFEST_DIR")).join("reference-data/bifurcation")
    }

    /// Read the case in `dir` (the last time directory is the steady field).
    pub fn open(dir: impl AsRef<Path>) -> Result<Self, FoamError> {
        let case = FoamCase::open(dir)?;
        let last = *case.times().last().ok_or_else(|| FoamError::Field {
            path: "(time directories)".into(),
            reason: "the case has no time directory with a field".into(),
        })?;
        let flow = FoamFlow::read(&case, &[last])?;
        let boundary = MeshBoundary::new(flow.mesh())?;
        let mesh = flow.mesh();
        let inlet = mesh
            .patches()
            .iter()
            .find(|p| p.name == "inlet")
            .ok_or_else(|| FoamError::Mesh {
                reason: "no patch named `inlet`".into(),
            })?;
        // Q = U A_inlet: the inlet condition is the uniform U along e₁ on faces normal to e₁.
        let inlet_area: f64 = (inlet.start..inlet.start + inlet.size)
            .map(|f| mesh.face_areas()[f].norm())
            .sum();
        let volume: f64 = mesh.cell_volumes().iter().sum();
        let residence_time = volume / (inlet_velocity() * inlet_area);
        if !(residence_time.is_finite() && residence_time > 0.0) {
            return Err(FoamError::Mesh {
                reason: format!(
                    "mean residence time {residence_time} from volume {volume} and inlet area {inlet_area}"
                ),
            });
        }
        Ok(Self {
            flow: BlendedFlow::new(flow)?,
            boundary,
            residence_time,
        })
    }

    /// The steady flow (continuous blend).
    pub fn flow(&self) -> &BlendedFlow {
        &self.flow
    }

    /// Wall (deposition) and inlet/outlet (exit) patches.
    pub fn boundary(&self) -> &MeshBoundary {
        &self.boundary
    }

    /// Mean residence time τ = V/Q of the flow (mesh volume over inlet flow rate).
    pub fn mean_residence_time(&self) -> f64 {
        self.residence_time
    }

    /// Tracking time: [`RESIDENCE_TIMES`] × τ; a particle still inside then is suspended.
    pub fn tracking_time(&self) -> f64 {
        RESIDENCE_TIMES * self.residence_time
    }

    /// Largest cell-centre speed of the field.
    pub fn max_speed(&self) -> f64 {
        let cells = self.flow.cellwise();
        let mesh = cells.mesh();
        (0..mesh.n_cells())
            .map(|c| cells.sample_cell(c, &mesh.cell_centres()[c], 0.0).u.norm())
            .fold(0.0, f64::max)
    }
}
