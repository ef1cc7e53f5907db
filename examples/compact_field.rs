//! Convert an exported OpenFOAM field (legacy VTK with point arrays U and grad(U)) into the
//! compact shipped form (`reference-data/*.prf`).
//!
//! ```text
//! cargo run --release --example compact_field -- IN.vtk OUT.prf [MANTISSA_BITS]
//! ```
//! MANTISSA_BITS (default 12, at most 23 = lossless f32) sets the rounding of the stored values.
//! Prints the size and the largest difference between the two forms at the cell centres.

use pseudorigid::flow::FlowField;
use pseudorigid::flow::unstructured::{MeshedFlow, compact};
use std::path::PathBuf;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let (input, output, bits) = match args.as_slice() {
        [i, o] => (i, o, 12),
        [i, o, b] => (i, o, b.parse()?),
        _ => return Err("usage: compact_field IN.vtk OUT.prf [MANTISSA_BITS]".into()),
    };
    let flow = MeshedFlow::load(input)?;
    let output = PathBuf::from(output);
    let bytes = compact::write(&flow, &output, bits)?;
    let back = MeshedFlow::load(&output)?;
    let (mut du, mut dg) = (0.0f64, 0.0f64);
    for x in flow.mesh().centres() {
        let (a, b) = (flow.sample(x, 0.0)?, back.sample(x, 0.0)?);
        du = du.max((a.u - b.u).amax());
        dg = dg.max((a.grad_u - b.grad_u).amax());
    }
    println!(
        "{}: {} points, {} cells, {bits} mantissa bits, {bytes} bytes; \
         max |Δu| = {du:.2e}, max |Δ∇u| = {dg:.2e}",
        output.display(),
        flow.mesh().points().len(),
        flow.mesh().cells().len()
    );
    Ok(())
}
