//! Cavity validation at Re = 1000 (src/flow/unstructured/cavity) on the shipped 60³ OpenFOAM
//! field against Albensoeder & Kuhlmann (2005).
use pseudorigid::flow::unstructured::MeshedFlow;
use pseudorigid::scenes::cavity_benchmark::{CavityCase, ReferenceTable, compare_extrema};

const CASE: CavityCase = CavityCase {
    edge: 0.1,
    lid_speed: 0.173,
};

/// The centreline extrema lie within 5 % of the spectral reference: a uniform 60³ finite-volume
/// grid is expected 2–5 % shallow (Ben Beya & Lili: 1–2 % at 48³–64³ with a finer scheme, 5 %
/// at 32³), so 5 % is the acceptance bound, not a fitted one.
/// Values rounded to 3 decimals are snapshotted (the compact field stores 12 mantissa bits,
/// relative error ≤ 1.2e-4).
#[test]
fn re1000_extrema_within_five_percent_of_albensoeder_kuhlmann() {
    let root = env!("CARGO_MANIFEST_DIR");
    let flow = MeshedFlow::load(format!("{root}/reference-data/cavity_re1000.prf")).unwrap();
    let table =
        ReferenceTable::read_csv(format!("{root}/reference-data/cavity_re1000_albensoeder_kuhlmann.csv").as_ref())
            .unwrap();
    let rows = compare_extrema(&CASE, &flow, &table).unwrap();
    assert_eq!(rows.len(), 3);
    let mut text = String::from("extremum,simulated,position,reference,error_percent\n");
    for r in &rows {
        assert!(
            r.relative_error().abs() <= 0.05,
            "{}: {:+.2} %",
            r.which.name(),
            100.0 * r.relative_error()
        );
        text.push_str(&format!(
            "{},{:.3},{:.3},{:.3},{:.1}\n",
            r.which.name(),
            r.simulated.value,
            r.simulated.position,
            r.reference.value,
            100.0 * r.relative_error()
        ));
    }
    insta::assert_snapshot!(text);
}
