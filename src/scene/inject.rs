//! The particles of a scene as a population [`Injector`]: an explicit list (particle k is
//! entry k) or injection groups, each drawing its particles from their own generators
//! (particle k of the scene, in whichever group, draws from stream k).

use crate::ellipsoid::Ellipsoid;
use crate::error::{FlowError, ParamError, StepError};
use crate::flow::FlowField;
use crate::hydro::drag::NamedDrag;
use crate::material::NamedLaw;
use crate::material::Softness;
use crate::particle::Particle;
use crate::population::sampling::{DiscWeight, WeightedTriangles, disc_point, haar_rotation};
use crate::population::{Injector, ParticleRng, ParticleSpec, ParticleTemplate};
use crate::scene::models::SceneFlow;
use crate::tensor::{Mat3, Vec3};

/// Initial velocity of a particle.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Velocity {
    /// This velocity.
    Given(Vec3),
    /// The fluid's at the injection point (at t = 0).
    Fluid,
}

/// One particle's shape, response, density, start point and velocity rule.
#[derive(Debug, Clone, PartialEq)]
pub struct Placement {
    /// Stress-free ellipsoid (with its orientation).
    pub shape: Ellipsoid,
    /// Shape response.
    pub softness: Softness<NamedLaw>,
    /// Solid density ρ_s.
    pub density: f64,
    /// Start point (ignored for injection, which draws it).
    pub position: Vec3,
    /// Start velocity.
    pub velocity: Velocity,
}

impl Placement {
    /// The specification with velocity `velocity`.
    pub fn spec(&self, velocity: Vec3) -> ParticleSpec<NamedLaw> {
        ParticleSpec {
            shape: self.shape,
            softness: self.softness.clone(),
            density: self.density,
            position: self.position,
            velocity,
        }
    }
}

/// Where injected particles start.
#[derive(Debug, Clone, PartialEq)]
pub enum Region {
    /// All at one point.
    Point(Vec3),
    /// On a disc, uniform by area or by pipe flux. A drawn point outside the flow's mesh
    /// fails its particle (possible only for the pipe-flux weight, whose rim the scene does not
    /// require inside a faceted wall: on a mesh of a pipe the wall's facets cut the disc's rim).
    Disc {
        /// Centre.
        centre: Vec3,
        /// Normal.
        normal: Vec3,
        /// Radius.
        radius: f64,
        /// How the points spread over it.
        weight: DiscWeight,
    },
    /// On a patch, weighted by the inflow (the triangles already moved inside the mesh).
    Patch(WeightedTriangles),
}

/// One injection group: `count` particles drawn from their own generators.
#[derive(Debug, Clone, PartialEq)]
pub struct Group {
    /// Number of particles.
    pub count: u64,
    /// Start region.
    pub region: Region,
    /// Orientation uniform on SO(3) (else the placement's).
    pub random_orientation: bool,
    /// Shape (rest semi-axes and fixed orientation), response, density and velocity rule.
    pub placement: Placement,
}

/// The particles of a scene.
#[derive(Debug, Clone, PartialEq)]
pub enum ParticleSource {
    /// Particle k is entry k.
    List(Vec<Placement>),
    /// Groups in order: group g holds the particles after those of groups 0..g.
    Inject(Vec<Group>),
}

impl ParticleSource {
    /// Number of particles (saturating: a sum beyond u64 is refused by the scene's cap).
    pub fn count(&self) -> u64 {
        match self {
            ParticleSource::List(l) => l.len() as u64,
            ParticleSource::Inject(groups) => groups.iter().fold(0, |n, g| n.saturating_add(g.count)),
        }
    }
}

/// The group particle `index` belongs to: the first whose cumulative count exceeds it.
fn group_of(groups: &[Group], index: u64) -> Option<&Group> {
    let mut end = 0u64;
    groups.iter().find(|g| {
        end = end.saturating_add(g.count);
        index < end
    })
}

/// A scene's particles over its flow, as the population runner draws them.
#[derive(Debug, Clone, Copy)]
pub struct SceneInjector<'a> {
    template: &'a ParticleTemplate<NamedDrag>,
    source: &'a ParticleSource,
    flow: &'a SceneFlow,
}

impl<'a> SceneInjector<'a> {
    /// Particles of `source` built with `template`, starting in `flow`.
    pub fn new(template: &'a ParticleTemplate<NamedDrag>, source: &'a ParticleSource, flow: &'a SceneFlow) -> Self {
        Self { template, source, flow }
    }

    fn start(&self, placement: &Placement, position: Vec3) -> Result<ParticleSpec<NamedLaw>, StepError> {
        let velocity = match placement.velocity {
            Velocity::Given(v) => v,
            Velocity::Fluid => self.flow.sample(&position, 0.0)?.u,
        };
        Ok(ParticleSpec {
            position,
            ..placement.spec(velocity)
        })
    }
}

impl Injector for SceneInjector<'_> {
    type Law = NamedLaw;
    type Drag = NamedDrag;

    fn draw(&self, index: u64, rng: &mut ParticleRng) -> Result<ParticleSpec<NamedLaw>, StepError> {
        match self.source {
            ParticleSource::List(list) => {
                let placement =
                    usize::try_from(index)
                        .ok()
                        .and_then(|i| list.get(i))
                        .ok_or(ParamError::OutOfRange {
                            name: "particle index",
                            value: index as f64,
                            min: 0.0,
                            max: list.len() as f64 - 1.0,
                        })?;
                self.start(placement, placement.position)
            }
            ParticleSource::Inject(groups) => {
                let Group {
                    region,
                    random_orientation,
                    placement,
                    ..
                } = group_of(groups, index).ok_or(ParamError::OutOfRange {
                    name: "particle index",
                    value: index as f64,
                    min: 0.0,
                    max: self.source.count() as f64 - 1.0,
                })?;
                // Fixed draw order (position, then orientation): particle k's numbers depend
                // on its stream alone.
                let position = match region {
                    Region::Point(p) => *p,
                    Region::Disc {
                        centre,
                        normal,
                        radius,
                        weight,
                    } => {
                        let p = disc_point(rng, centre, normal, *radius, *weight)?;
                        self.flow.with_cellwise(|cells| match cells {
                            Some(cells) if cells.locate(&p, None).is_err() => Err(FlowError::outside(&p)),
                            _ => Ok(p),
                        })?
                    }
                    Region::Patch(triangles) => triangles.draw(rng),
                };
                let mut placement = placement.clone();
                if *random_orientation {
                    let turn: Mat3 = haar_rotation(rng);
                    placement.shape =
                        Ellipsoid::new(placement.shape.semi_axes().into(), turn * placement.shape.axes())?;
                }
                self.start(&placement, position)
            }
        }
    }

    fn particle(&self, spec: &ParticleSpec<NamedLaw>) -> Result<Particle<Softness<NamedLaw>, NamedDrag>, ParamError> {
        self.template.build(spec)
    }
}
