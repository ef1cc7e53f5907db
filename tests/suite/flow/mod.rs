//! Flow fields (src/flow).

mod analytic;
mod bend_poiseuille;

#[cfg(feature = "mesh")]
mod openfoam;
