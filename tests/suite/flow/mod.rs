//! Flow fields (src/flow).

mod analytic;

#[cfg(feature = "mesh")]
mod openfoam;
