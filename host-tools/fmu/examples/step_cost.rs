//! The damper FMU's cost per evaluation next to the core's, in one run:
//! rust-fmi's importer (`fmi` crate) setting the three inputs and getting
//! the force of `damper.fmu` (Co-Simulation), against `Table::force` on the
//! table read from the same FMU's page. Prints ns per evaluation (median of
//! 9 repeats over a sweep of 100 000 inputs) and the ratio.
//!
//! `cargo run --release -p mre-fmu --example step_cost -- path/to/damper.fmu`
use fmi::fmi3::import::Fmi3Import;
use fmi::fmi3::{Common, Fmi3Model, GetSet};
use fmi::traits::FmiImport;
use std::hint::black_box;
use std::time::Instant;

const N: usize = 100_000;

fn median(mut v: Vec<f64>) -> f64 {
    v.sort_by(f64::total_cmp);
    v[v.len() / 2]
}

fn main() {
    let path = std::env::args().nth(1).expect("usage: step_cost DAMPER.fmu");
    let import: Fmi3Import = fmi::import::from_path(&path).expect("import damper.fmu");
    let (table, _) = mre_fmu::page::load(&import.archive_path().join("resources")).expect("the FMU's page");
    let vr = |name: &str| {
        import
            .model_description()
            .model_variables
            .iter_abstract()
            .find(|v| v.name() == name)
            .expect("variable")
            .value_reference()
    };
    let (x, v, i, f) = (vr("displacement_m"), vr("velocity_m_s"), vr("current_a"), vr("force_n"));
    let mut cs = import
        .instantiate_cs("bench", false, false, false, false, &[])
        .expect("instance");
    cs.enter_initialization_mode(None, 0.0, None).expect("init");
    cs.exit_initialization_mode().expect("init");
    // A compression–extension sweep over 0–12 mm and 0–2 A.
    let inputs: Vec<[f64; 3]> = (0..N)
        .map(|k| {
            let s = k as f64 / N as f64;
            [12e-3 * (std::f64::consts::PI * s).sin(), 2.0 * (0.5 - s), 2.0 * s]
        })
        .collect();
    let (mut fmu_ns, mut core_ns) = (Vec::new(), Vec::new());
    for _ in 0..9 {
        let start = Instant::now();
        let mut out = [0.0];
        for input in &inputs {
            cs.set_float64(&[x, v, i], black_box(input)).expect("set");
            cs.get_float64(&[f], &mut out).expect("get");
            black_box(out[0]);
        }
        fmu_ns.push(start.elapsed().as_nanos() as f64 / N as f64);
        let start = Instant::now();
        for input in &inputs {
            let [xm, vm, ia] = *black_box(input);
            black_box(mre_fmu::Damper::force_at(&table, xm, vm, ia));
        }
        core_ns.push(start.elapsed().as_nanos() as f64 / N as f64);
    }
    let (fmu, core) = (median(fmu_ns), median(core_ns));
    println!("damper.fmu via fmi (set 3 inputs, get force): {fmu:.1} ns per evaluation");
    println!("mre_algorithm Table::force, same inputs:          {core:.1} ns per evaluation");
    println!("ratio FMU / core: {:.1}", fmu / core);
}
