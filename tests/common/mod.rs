//! Shared test helpers: proptest strategies and independent reference computations.
#![allow(dead_code)] // each test crate uses a different subset

pub mod reference;
pub mod strategies;
