//! `mre model` and the table file format.
use mre_algorithm::model::Branch;
use mre_algorithm::Table;
use mre_host::loops::{fitted_stroke_mm, model_loop, write_loop_csv};
use mre_host::table_file::{load_table, parse_table_toml, table_to_toml};

const PAPER_TOML: &str = include_str!("../../../data/paper/table4.toml");

#[test]
fn paper_toml_file_reads_as_the_built_in_table() {
    let from_file = parse_table_toml(PAPER_TOML).expect("paper TOML parses");
    let built_in = Table::paper().expect("valid");
    assert_eq!(from_file.entries().len(), 5);
    for (a, b) in from_file.entries().iter().zip(built_in.entries()) {
        assert_eq!(a.current_a, b.current_a);
        assert_eq!(a.compression, b.compression);
        assert_eq!(a.extension, b.extension);
        // The file has no stroke; it defaults to the loop's closing point,
        // which the built-in table stores rounded to 1e-4 mm.
        assert_eq!(a.x_min_mm, 0.0);
        assert!(
            (a.x_max_mm - b.x_max_mm).abs() < 1e-4,
            "{} vs {}",
            a.x_max_mm,
            b.x_max_mm
        );
    }
}

#[test]
fn table_toml_round_trips() {
    let t = Table::paper().expect("valid");
    let again = parse_table_toml(&table_to_toml(&t)).expect("own output parses");
    assert_eq!(again, t);
}

#[test]
fn bad_table_files_are_refused_with_a_reason() {
    let unsorted = "[[current]]\ncurrent_a = 1.0\ncompression=[0,0,0,1,0]\nextension=[0,0,0,1,0]\nx_min_mm=0\nx_max_mm=1\n\
                    [[current]]\ncurrent_a = 0.5\ncompression=[0,0,0,1,0]\nextension=[0,0,0,1,0]\nx_min_mm=0\nx_max_mm=1\n";
    let err = format!("{:#}", parse_table_toml(unsorted).unwrap_err());
    assert!(
        err.contains("entry 1: currents must be finite and strictly ascending"),
        "{err}"
    );

    let typo = "[[current]]\ncurrent_a = 1.0\ncompresion=[0,0,0,1,0]\nextension=[0,0,0,1,0]\n";
    let err = format!("{:#}", parse_table_toml(typo).unwrap_err());
    assert!(err.contains("unknown field `compresion`"), "{err}");

    let half_stroke = "[[current]]\ncurrent_a = 1.0\ncompression=[0,0,0,1,0]\nextension=[0,0,0,1,0]\nx_max_mm=1\n";
    let err = format!("{:#}", parse_table_toml(half_stroke).unwrap_err());
    assert!(err.contains("give both x_min_mm and x_max_mm, or neither"), "{err}");

    let missing = load_table("/nonexistent/table.toml").unwrap_err();
    assert!(format!("{missing:#}").contains("cannot read table file /nonexistent/table.toml"));
}

#[test]
fn interpolated_loop_spans_the_shared_stroke_of_its_neighbours() {
    let t = Table::paper().expect("valid");
    // 0.7 A lies between 0.5 A (x_max 1.0838) and 1 A (x_max 1.0891).
    let (lo, hi) = fitted_stroke_mm(&t, 0.7);
    assert_eq!((lo, hi), (0.0, 1.0838));
    let pts = model_loop(&t, 0.7, 11).expect("in range");
    assert_eq!(pts.len(), 11);
    assert_eq!(pts[0].x_mm, 0.0);
    assert!((pts[10].x_mm - 1.0838).abs() < 1e-6);
    // Each point is the paper's interpolation of its neighbours (0.4 of the way from 0.5 A to 1 A).
    for p in &pts {
        let x = p.x_mm as f32;
        let lo_f = t.entries()[1].compression.eval(x) as f64;
        let hi_f = t.entries()[2].compression.eval(x) as f64;
        assert!((p.compression_n - (lo_f + 0.4 * (hi_f - lo_f))).abs() < 0.05);
        assert_eq!(
            p.extension_n,
            t.force_on_branch(x, Branch::Extension, 0.7).force_n as f64
        );
    }
}

#[test]
fn out_of_range_requests_are_errors_not_clamps() {
    let t = Table::paper().expect("valid");
    assert!(model_loop(&t, 2.5, 11).is_err());
    assert!(model_loop(&t, f32::NAN, 11).is_err());
    assert!(model_loop(&t, 1.0, 1).is_err());
}

#[test]
fn csv_has_a_unit_carrying_header() {
    let t = Table::paper().expect("valid");
    let pts = model_loop(&t, 1.0, 3).expect("in range");
    let mut buf = Vec::new();
    write_loop_csv(&mut buf, &pts).expect("writes");
    let text = String::from_utf8(buf).expect("utf8");
    let mut lines = text.lines();
    assert_eq!(lines.next(), Some("x_mm,compression_force_n,extension_force_n"));
    // At x = 0 the quartics equal their constant terms (Table 4, 1 A): 336.52 and −22.37 N.
    let first: Vec<f64> = lines
        .next()
        .expect("row")
        .split(',')
        .map(|v| v.parse().expect("number"))
        .collect();
    assert_eq!(first[0], 0.0);
    assert!((first[1] - 336.52).abs() < 1e-3 && (first[2] + 22.37).abs() < 1e-3);
}
