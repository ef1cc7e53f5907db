//! Cavity validation at Re = 1000 (src/scenes/cavity_benchmark) on the shipped 60³ OpenFOAM
//! field against Albensoeder & Kuhlmann (2005).
mod common;

use pseudorigid::flow::unstructured::MeshedFlow;

/// The centreline extrema lie within 5 % of the spectral reference (the acceptance
/// bound, argued in `common::cavity_re1000_extrema`). Values rounded to 3 decimals are
/// snapshotted (the compact field stores 12 mantissa bits, relative error ≤ 1.2e-4).
#[test]
fn re1000_extrema_within_five_percent_of_albensoeder_kuhlmann() {
    let flow = MeshedFlow::load(concat!(env!("CARGO_MANIFEST_DIR"), "/reference-data/cavity_re1000.prf")).unwrap();
    let text = common::cavity_re1000_extrema(&flow);
    insta::assert_snapshot!(text);
}
