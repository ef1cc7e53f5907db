//! Models chosen by name: one registry per kind of model (laws
//! [`crate::material::registry`], drag models [`crate::hydro::drag`], force terms
//! [`crate::hydro::forces`], integrators [`crate::integrator::registry`]), each filled by the
//! models' own files with `inventory::submit!`, in the manner of OpenFOAM's run-time selection
//! tables. Scene files and the Python package build every model through these registries, so a
//! model added in one file is selectable by name with no dispatch code to edit.
//!
//! A registered model is built from its [`Parameters`]: named [`Value`]s as a scene file gives
//! them. A builder declares the keys it takes ([`Parameters::only`]) and reads each with its
//! type; every refusal is a [`ParamError`] that names the key ([`ParamError::key`]), so the
//! scene parser can point at it.

use crate::error::ParamError;
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;

/// One parameter value, as a scene file or Python writes it.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(untagged)]
pub enum Value {
    /// A number (TOML integers are read as numbers too).
    Number(f64),
    /// `true` or `false`.
    Flag(bool),
    /// Text (an expression law's energy).
    Text(String),
    /// Named numbers (an expression law's constants).
    Table(BTreeMap<String, f64>),
}

impl From<f64> for Value {
    fn from(x: f64) -> Self {
        Value::Number(x)
    }
}

impl From<bool> for Value {
    fn from(b: bool) -> Self {
        Value::Flag(b)
    }
}

impl From<&str> for Value {
    fn from(s: &str) -> Self {
        Value::Text(s.to_string())
    }
}

/// Named parameter values, such as `{ mu = 5.0, lambda = 50.0 }`.
pub type Values = BTreeMap<String, Value>;

/// The values given to one model, read by its builder.
#[derive(Debug, Clone, Copy)]
pub struct Parameters<'a> {
    model: &'static str,
    values: &'a Values,
}

impl<'a> Parameters<'a> {
    /// The `values` given to the model registered as `model`.
    pub fn new(model: &'static str, values: &'a Values) -> Self {
        Self { model, values }
    }

    /// The model's registered name.
    pub fn model(&self) -> &'static str {
        self.model
    }

    /// Refuse every key outside `known`: a misspelt key is an error, not a silent default.
    pub fn only(&self, known: &[&'static str]) -> Result<(), ParamError> {
        match self.values.keys().find(|k| !known.contains(&k.as_str())) {
            Some(key) => Err(ParamError::Unexpected {
                model: self.model,
                key: key.clone(),
                known: known.to_vec(),
            }),
            None => Ok(()),
        }
    }

    fn wrong(key: &str, expected: &'static str) -> ParamError {
        ParamError::WrongType {
            key: key.to_string(),
            expected,
        }
    }

    /// The finite number `key`, if given.
    pub fn optional_number(&self, key: &'static str) -> Result<Option<f64>, ParamError> {
        match self.values.get(key) {
            None => Ok(None),
            Some(Value::Number(x)) => crate::error::finite(key, *x).map(Some),
            Some(_) => Err(Self::wrong(key, "a number")),
        }
    }

    /// The finite number `key`, which the model needs.
    pub fn number(&self, key: &'static str) -> Result<f64, ParamError> {
        self.optional_number(key)?.ok_or_else(|| ParamError::Missing {
            model: self.model,
            key: key.to_string(),
        })
    }

    /// The finite number `key` > 0, which the model needs.
    pub fn positive(&self, key: &'static str) -> Result<f64, ParamError> {
        crate::error::positive(key, self.number(key)?)
    }

    /// The flag `key` (absent: false).
    pub fn flag(&self, key: &'static str) -> Result<bool, ParamError> {
        match self.values.get(key) {
            None => Ok(false),
            Some(Value::Flag(b)) => Ok(*b),
            Some(_) => Err(Self::wrong(key, "true or false")),
        }
    }

    /// The text `key`, which the model needs.
    pub fn text(&self, key: &'static str) -> Result<&'a str, ParamError> {
        match self.values.get(key) {
            None => Err(ParamError::Missing {
                model: self.model,
                key: key.to_string(),
            }),
            Some(Value::Text(s)) => Ok(s),
            Some(_) => Err(Self::wrong(key, "text")),
        }
    }

    /// The text `key` as one of `choices` (its name, its value), the first when `key` is
    /// absent; any other text is [`ParamError::WrongType`] with `expected` (the names, as the
    /// error shows them).
    pub fn choice<T: Copy>(
        &self,
        key: &'static str,
        choices: &[(&str, T)],
        expected: &'static str,
    ) -> Result<T, ParamError> {
        let name = match self.text(key) {
            Err(ParamError::Missing { .. }) => return Ok(choices[0].1),
            other => other?,
        };
        choices
            .iter()
            .find(|(n, _)| *n == name)
            .map(|(_, v)| *v)
            .ok_or_else(|| Self::wrong(key, expected))
    }

    /// The table of numbers `key` (absent: empty).
    pub fn table(&self, key: &'static str) -> Result<BTreeMap<String, f64>, ParamError> {
        match self.values.get(key) {
            None => Ok(BTreeMap::new()),
            Some(Value::Table(t)) => Ok(t.clone()),
            Some(_) => Err(Self::wrong(key, "a table of numbers")),
        }
    }
}

/// An entry of a registry: what the look-up by name needs of it.
pub trait Entry: inventory::Collect {
    /// What the registry holds, for messages (`"law"`, `"drag model"`, ...).
    const KIND: &'static str;

    /// The entry's name.
    fn name(&self) -> &'static str;

    /// Other names the entry answers to (earlier spellings).
    fn aliases(&self) -> &'static [&'static str] {
        &[]
    }
}

/// The entry of registry `E` called `name` (or one of its aliases).
pub fn find<E: Entry>(name: &str) -> Result<&'static E, ParamError> {
    inventory::iter::<E>
        .into_iter()
        .find(|e| e.name() == name || e.aliases().contains(&name))
        .ok_or_else(|| ParamError::Unknown {
            kind: E::KIND,
            name: name.to_string(),
            known: names::<E>(),
        })
}

/// The names registered in `E`, sorted.
pub fn names<E: Entry>() -> Vec<&'static str> {
    let mut names: Vec<&'static str> = inventory::iter::<E>.into_iter().map(Entry::name).collect();
    names.sort_unstable();
    names
}
