use pseudorigid::flow::unstructured::MeshedFlow;
use pseudorigid::scenes::cavity::{Cavity, Contact, ShapeModel, fig15_fig16_releases, fluid_inertia};
use std::time::Instant;
fn main() -> Result<(), Box<dyn std::error::Error>> {
    let flow = MeshedFlow::load("reference-data/cavity_re470.prf")?;
    let args: Vec<String> = std::env::args().skip(1).collect();
    let idx: usize = args[0].parse()?;
    let t_max: f64 = args[1].parse()?;
    let model = if args.iter().any(|a| a == "inertialess") { ShapeModel::Inertialess } else { ShapeModel::Inertial };
    let r = fig15_fig16_releases()[idx];
    for fi in [false, true] {
        let mut cavity = Cavity::new(&flow)?.with_shape_model(model);
        if fi { cavity = cavity.with_forces(fluid_inertia()?); }
        let start = Instant::now();
        let run = cavity.track(r, Contact::Barycentre, t_max, 1e-6, 0.1)?;
        println!("{:?} fi={fi}: {:?} steps {} rejected {} in {:.2}s; last x {:?}", r, run.outcome, run.stats.steps, run.stats.rejected, start.elapsed().as_secs_f64(), run.path.last().map(|p| p.1.as_slice().to_vec()));
    }
    Ok(())
}
