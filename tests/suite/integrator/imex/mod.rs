//! The paper's IMEX scheme (src/integrator/imex).

mod stability;
