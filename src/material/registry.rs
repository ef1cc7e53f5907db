//! Laws by name: each law registers a builder in its own file ([`LawRegistration`], with
//! `inventory::submit!`), and scene files (`material = { law = "neo_hooke", mu, lambda }`) and
//! the Python package build laws through [`by_name`] and [`response`]. A law added in one file
//! is then selectable by name with no other edit ([guide](crate::guide)).

use super::{Softness, StressLaw};
use crate::error::ParamError;
use crate::registry::{self, Entry, Parameters, Values};
use crate::tensor::{Mat3, Mat9};
use serde::{Deserialize, Serialize};
use std::fmt;
use std::sync::Arc;

pub use inventory;

/// A law selectable by name: its name in scene files and how to build it from its parameters.
pub struct LawRegistration {
    /// Name in scene files (`material.law`).
    pub name: &'static str,
    /// Build the law; refuse parameters it does not take ([`Parameters::only`]).
    pub build: fn(&Parameters) -> Result<Arc<dyn StressLaw>, ParamError>,
}

inventory::collect!(LawRegistration);

impl Entry for LawRegistration {
    const KIND: &'static str = "law";
    fn name(&self) -> &'static str {
        self.name
    }
}

/// The name of the rigid response (Ca → 0, [`Rigid`](super::Rigid)) in scene files: not a law, so it takes
/// no parameters.
pub const RIGID: &str = "rigid";

/// The registered law names and [`RIGID`], sorted.
pub fn names() -> Vec<&'static str> {
    let mut names = registry::names::<LawRegistration>();
    names.push(RIGID);
    names.sort_unstable();
    names
}

/// The registry: the law called `name` with parameters `values`.
pub fn by_name(name: &str, values: &Values) -> Result<NamedLaw, ParamError> {
    let entry = registry::find::<LawRegistration>(name).map_err(|_| ParamError::Unknown {
        kind: LawRegistration::KIND,
        name: name.to_string(),
        known: names(),
    })?;
    Ok(NamedLaw {
        name: entry.name,
        values: values.clone(),
        law: (entry.build)(&Parameters::new(entry.name, values))?,
    })
}

/// A particle's response by name: [`RIGID`] without parameters, else the registered law.
pub fn response(name: &str, values: &Values) -> Result<Softness<NamedLaw>, ParamError> {
    if name != RIGID {
        return by_name(name, values).map(Softness::Elastic);
    }
    Parameters::new(RIGID, values).only(&[])?;
    Ok(Softness::Rigid)
}

/// A law built by name: the registered law with the parameters it was built from, which are
/// what it serialises to (a checkpoint rebuilds it through the registry).
#[derive(Clone, Serialize)]
#[serde(into = "LawSpec")]
pub struct NamedLaw {
    name: &'static str,
    values: Values,
    law: Arc<dyn StressLaw>,
}

impl NamedLaw {
    /// The registered name.
    pub fn name(&self) -> &'static str {
        self.name
    }

    /// The parameters it was built from.
    pub fn values(&self) -> &Values {
        &self.values
    }
}

impl fmt::Debug for NamedLaw {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.debug_struct("NamedLaw")
            .field("name", &self.name)
            .field("values", &self.values)
            .finish()
    }
}

/// Two laws are equal when built by the same name from the same parameters.
impl PartialEq for NamedLaw {
    fn eq(&self, other: &Self) -> bool {
        self.name == other.name && self.values == other.values
    }
}

impl StressLaw for NamedLaw {
    fn energy_at(&self, f: &Mat3) -> f64 {
        self.law.energy_at(f)
    }
    fn piola(&self, f: &Mat3) -> Mat3 {
        self.law.piola(f)
    }
    fn tangent(&self, f: &Mat3) -> Mat9 {
        self.law.tangent(f)
    }
    fn cauchy(&self, f: &Mat3) -> Mat3 {
        self.law.cauchy(f)
    }
    fn shear_modulus(&self) -> f64 {
        self.law.shear_modulus()
    }
    fn lame_lambda(&self) -> f64 {
        self.law.lame_lambda()
    }
    fn is_isotropic(&self) -> bool {
        self.law.is_isotropic()
    }
}

/// The serialised form of a [`NamedLaw`]: `{ "law": name, parameters... }`, as in a scene.
#[derive(Serialize, Deserialize)]
struct LawSpec {
    law: String,
    #[serde(flatten)]
    values: Values,
}

impl From<NamedLaw> for LawSpec {
    fn from(l: NamedLaw) -> Self {
        Self {
            law: l.name.to_string(),
            values: l.values,
        }
    }
}

impl<'de> Deserialize<'de> for NamedLaw {
    fn deserialize<D: serde::Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        let spec = LawSpec::deserialize(d)?;
        by_name(&spec.law, &spec.values).map_err(serde::de::Error::custom)
    }
}
