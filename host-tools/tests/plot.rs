//! Plots render to PNG and SVG with labelled axes, on a synthetic data set.
use mre_host::fit::{run_fit, FitOptions};
use mre_host::plot::{run_plot, PlotOptions};
use std::path::Path;

/// A data set with loops at 0 and 1 A (fit) and 0.5 A (validate), from the
/// paper table's forces with known offsets.
fn synthetic_dataset(dir: &Path) {
    let table = mre_core::table::Table::paper().unwrap();
    let mut toml = String::from("name = \"synthetic\"\n");
    for (c, role) in [(0.0, "fit"), (0.5, "validate"), (1.0, "fit")] {
        let file = format!("i{c}.csv");
        toml.push_str(&format!(
            "[[recording]]\nfile = \"{file}\"\ncurrent_a = {c}\nrole = \"{role}\"\n"
        ));
        let mut csv = String::from("time_s,displacement_mm,velocity_m_s,force_n\n");
        for i in 0..400 {
            let phase = i as f64 / 400.0;
            let (x, v) = if phase < 0.5 {
                (1.8 * phase, 0.5)
            } else {
                (1.8 * (1.0 - phase), -0.5)
            };
            let f = table.force(x as f32, v as f32, c as f32).force_n as f64 + 20.0 * (i as f64).sin();
            csv.push_str(&format!("{},{x},{v},{f}\n", i as f64 * 1e-3));
        }
        std::fs::write(dir.join(file), csv).unwrap();
    }
    std::fs::write(dir.join("dataset.toml"), toml).unwrap();
}

/// A short GSA (20 agents × 20 iterations): the tests check outputs, not GSA.
fn quick_fit() -> FitOptions {
    FitOptions {
        gsa: mre_host::fit::gsa::GsaParams {
            agents: 20,
            iters: 20,
            ..Default::default()
        },
        ..Default::default()
    }
}

#[test]
fn fit_then_plot_writes_every_figure() {
    let data = tempfile::tempdir().unwrap();
    synthetic_dataset(data.path());
    let out = tempfile::tempdir().unwrap();
    let model = out.path().join("model.toml");
    let options = quick_fit();
    let run = run_fit(data.path(), &options, &[], &model).unwrap();
    assert_eq!(run.fits.len(), 4, "0 A and 1 A, two branches each; 0.5 A is not fitted");
    let files = run_plot(
        data.path(),
        &model,
        &[],
        &PlotOptions { interpolated_a: vec![] },
        out.path(),
    )
    .unwrap();
    let names: Vec<String> = files
        .iter()
        .map(|f| f.file_name().unwrap().to_string_lossy().into_owned())
        .collect();
    assert_eq!(
        names,
        [
            "fig08_loop_0A",
            "fig08_loop_1A",
            "fig09_all_currents",
            "fig11_interpolated",
            "fig12_bracket_0p5A",
            "gsa_convergence"
        ]
    );
    for f in &files {
        let png = std::fs::read(format!("{}.png", f.display())).unwrap();
        assert_eq!(&png[..8], b"\x89PNG\r\n\x1a\n");
        let svg = std::fs::read_to_string(format!("{}.svg", f.display())).unwrap();
        assert!(svg.contains("<svg"));
    }
    let svg = std::fs::read_to_string(out.path().join("fig08_loop_1A.svg")).unwrap();
    assert!(svg.contains("displacement x (mm)") && svg.contains("force F (N)") && svg.contains("measured, 1 A"));
}

#[test]
fn a_plot_failing_part_way_writes_nothing() {
    let data = tempfile::tempdir().unwrap();
    synthetic_dataset(data.path());
    let out = tempfile::tempdir().unwrap();
    // The paper's table fits these data; the third figure file fails to write.
    let model = Path::new(env!("CARGO_MANIFEST_DIR")).join("../data/paper/table4.toml");
    let options = PlotOptions { interpolated_a: vec![] };
    let err = mre_host::atomic_write::command_failing_after(2, || {
        run_plot(data.path(), &model, &[], &options, &out.path().join("figs"))
    })
    .unwrap_err();
    assert!(format!("{err:#}").contains("injected write failure"), "{err:#}");
    assert_eq!(std::fs::read_dir(out.path()).unwrap().count(), 0);
}

#[test]
fn whole_pipeline_on_a_synthetic_data_set() {
    let data = tempfile::tempdir().unwrap();
    synthetic_dataset(data.path());
    let out = tempfile::tempdir().unwrap();
    let model = out.path().join("model.toml");
    let options = quick_fit();
    mre_host::fit::run_fit(data.path(), &options, &[], &model).unwrap();
    // The data follow the paper's 0 and 1 A quartics plus a ±20 N sine, so
    // the fitted loops reproduce the recordings to about that (RMSE ≤ 20 N)…
    let report =
        mre_host::validate::run_validate(data.path(), model.to_str().unwrap(), &[], &out.path().join("report"))
            .unwrap();
    for r in report.recordings.iter().filter(|r| !r.interpolated) {
        assert!(r.rmse_n < 20.0, "{}: {}", r.file, r.rmse_n);
    }
    // …and the 0.5 A recording is predicted by interpolation, not fitted.
    let half = report.recordings.iter().find(|r| r.current_a == 0.5).unwrap();
    assert!(half.interpolated && half.bracket.is_some());
    assert!(out.path().join("report/report.md").is_file() && out.path().join("report/report.json").is_file());
    let table = mre_host::tables::run_tables(&model, &out.path().join("generated_table.rs")).unwrap();
    let src = std::fs::read_to_string(out.path().join("generated_table.rs")).unwrap();
    assert!(src.contains(&format!("crc32: {:#010x},", table.crc32())));
    let sweep_dir = out.path().join("sweep");
    let problems =
        mre_host::fit::problems::branch_problems(&mre_host::dataset::Dataset::load(data.path()).unwrap()).unwrap();
    let s = mre_host::fit::sweep::sweep(&problems, &options, &[5, 10], &[5, 10]).unwrap();
    mre_host::plot::sweep::render_sweep(&s, &options, &sweep_dir).unwrap();
    assert!(sweep_dir.join("fig13_index_vs_iterations.png").is_file());
    assert!(sweep_dir.join("fig14_index_vs_agents.svg").is_file());
}
