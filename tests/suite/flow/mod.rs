//! Flow fields (src/flow).

#[cfg(feature = "mesh")]
mod openfoam;
