//! Plots render to PNG and SVG with labelled axes, on a synthetic data set,
//! and draw what they claim to: the Fig. 8 loop's dots sit at the recorded
//! samples and its line on the model file's quartics, branch by branch.
use mre_host::fit::{run_fit, FitOptions};
use mre_host::plot::{run_plot, PlotOptions};
use std::path::Path;

/// A data set with loops at 0 and 1 A (fit) and 0.5 A (validate), from the
/// paper table's forces with known offsets.
fn synthetic_dataset(dir: &Path) {
    let table = mre_algorithm::table::Table::paper().unwrap();
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

/// The value of attribute `name` in one SVG tag's text.
fn attr<'a>(tag: &'a str, name: &str) -> Option<&'a str> {
    let start = tag.find(&format!(" {name}=\""))? + name.len() + 3;
    Some(&tag[start..start + tag[start..].find('"')?])
}

/// Least-squares line `pixel = a·value + b` and its largest residual (px).
fn affine(values: &[f64], pixels: &[f64]) -> (f64, f64, f64) {
    let n = values.len() as f64;
    let (mv, mp) = (values.iter().sum::<f64>() / n, pixels.iter().sum::<f64>() / n);
    let cov: f64 = values.iter().zip(pixels).map(|(v, p)| (v - mv) * (p - mp)).sum();
    let var: f64 = values.iter().map(|v| (v - mv) * (v - mv)).sum();
    let a = cov / var;
    let b = mp - a * mv;
    let worst = values
        .iter()
        .zip(pixels)
        .map(|(v, p)| (a * v + b - p).abs())
        .fold(0.0, f64::max);
    (a, b, worst)
}

#[test]
fn the_loop_figure_draws_the_recorded_samples_and_the_model_quartics() {
    let data = tempfile::tempdir().unwrap();
    synthetic_dataset(data.path());
    let out = tempfile::tempdir().unwrap();
    let model = out.path().join("model.toml");
    run_fit(data.path(), &quick_fit(), &[], &model).unwrap();
    run_plot(
        data.path(),
        &model,
        &[],
        &PlotOptions { interpolated_a: vec![] },
        out.path(),
    )
    .unwrap();
    let svg = std::fs::read_to_string(out.path().join("fig08_loop_1A.svg")).unwrap();
    let tags: Vec<&str> = svg.split('<').collect();

    // Dots: one per recorded 1 A sample, in order. Their pixel positions must
    // be an affine image of the recorded (x, F): x to the right, F upwards.
    // (The legend shows three larger dots, r = 3, as its sample of the series.)
    let dots: Vec<(f64, f64)> = tags
        .iter()
        .filter(|t| t.starts_with("circle") && attr(t, "r") == Some("2"))
        .map(|t| {
            (
                attr(t, "cx").unwrap().parse().unwrap(),
                attr(t, "cy").unwrap().parse().unwrap(),
            )
        })
        .collect();
    let csv = std::fs::read_to_string(data.path().join("i1.csv")).unwrap();
    let samples: Vec<(f64, f64)> = csv
        .lines()
        .skip(1)
        .map(|l| {
            let v: Vec<f64> = l.split(',').map(|c| c.parse().unwrap()).collect();
            (v[1], v[3])
        })
        .collect();
    assert_eq!(dots.len(), samples.len());
    let xs: Vec<f64> = samples.iter().map(|s| s.0).collect();
    let fs: Vec<f64> = samples.iter().map(|s| s.1).collect();
    let (ax, bx, worst_x) = affine(&xs, &dots.iter().map(|d| d.0).collect::<Vec<_>>());
    let (af, bf, worst_f) = affine(&fs, &dots.iter().map(|d| d.1).collect::<Vec<_>>());
    // Pixel coordinates are whole numbers: residuals up to one pixel.
    assert!(ax > 0.0 && af < 0.0, "x → right, F → up: {ax}, {af}");
    assert!(
        worst_x <= 1.0 && worst_f <= 1.0,
        "dots off the samples by {worst_x}, {worst_f} px"
    );

    // The model line (palette colour 1, width 3): compression out to the
    // stroke's end, then extension back. Each vertex, mapped back through the
    // dots' scale, must lie on the model file's quartic for its branch, to
    // within 2 px plus the curve's own change over ±1 px of x (rounding).
    let line = tags
        .iter()
        .find(|t| {
            t.starts_with("polyline") && attr(t, "stroke") == Some("#D55E00") && attr(t, "stroke-width") == Some("3")
        })
        .expect("the model line");
    let vertices: Vec<(f64, f64)> = attr(line, "points")
        .unwrap()
        .split_whitespace()
        .map(|p| {
            let (x, y) = p.split_once(',').unwrap();
            (x.parse().unwrap(), y.parse().unwrap())
        })
        .collect();
    assert!(vertices.len() > 100, "{} vertices", vertices.len());
    let table = mre_host::table_file::read_table_file(&model).unwrap();
    // The last compression vertex: the first at the stroke's end.
    let x_end = vertices.iter().map(|v| v.0).fold(f64::NEG_INFINITY, f64::max);
    let turn = vertices.iter().position(|v| v.0 == x_end).unwrap();
    let model_py = |px: f64, v_m_s: f64| {
        let x_mm = (px - bx) / ax;
        af * table.force(x_mm as f32, v_m_s as f32, 1.0).force_n as f64 + bf
    };
    let mut far_apart = 0;
    for (i, &(px, py)) in vertices.iter().enumerate() {
        let v_m_s = if i <= turn { 0.5 } else { -0.5 };
        let slope = (model_py(px + 1.0, v_m_s) - model_py(px - 1.0, v_m_s)).abs() / 2.0;
        let want = model_py(px, v_m_s);
        assert!(
            (py - want).abs() <= 2.0 + slope,
            "vertex {i} at ({px}, {py}) px: the {} quartic is at {want:.1} px",
            if i <= turn { "compression" } else { "extension" }
        );
        far_apart += usize::from((model_py(px, 0.5) - model_py(px, -0.5)).abs() > 10.0 + 2.0 * slope);
    }
    // The branches differ by more than the tolerance on much of the stroke,
    // so the check tells them apart.
    assert!(
        far_apart > vertices.len() / 4,
        "branches apart at only {far_apart} vertices"
    );

    // The PNG is the same drawing: the line's colour at its vertices.
    let decoder = png::Decoder::new(std::io::Cursor::new(
        std::fs::read(out.path().join("fig08_loop_1A.png")).unwrap(),
    ));
    let mut reader = decoder.read_info().unwrap();
    let mut rgb = vec![0; reader.output_buffer_size()];
    let info = reader.next_frame(&mut rgb).unwrap();
    assert_eq!(info.color_type, png::ColorType::Rgb);
    let pixel = |x: f64, y: f64| {
        let k = 3 * (y as usize * info.width as usize + x as usize);
        (rgb[k], rgb[k + 1], rgb[k + 2])
    };
    let orange = vertices.iter().filter(|&&(x, y)| pixel(x, y) == (213, 94, 0)).count();
    assert!(
        orange * 10 >= vertices.len() * 9,
        "{orange} of {} vertices orange in the PNG",
        vertices.len()
    );
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
