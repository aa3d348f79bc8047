//! One installation from a data set to the simulation (#31, point 1):
//! `mre fit` and `mre diagnose --model-out` write `[installation]` (the data
//! set's metadata, then `--installation` options, then the defaults, each
//! stated), `mre tables` carries exactly those values, and `mre sim`,
//! `mre pil`'s upload, `mre bench-control`'s drop and the FMU's controller
//! fly the model file's installation instead of the defaults.
use mre_algorithm::installation::{Installation, DEFAULT_INSTALLATION};
use mre_algorithm::Table;
use mre_host::installation::StatedInstallation;
use std::path::{Path, PathBuf};
use std::process::{Command, Output};

fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("..")
}

fn mre(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_mre")).args(args).output().unwrap()
}

/// `mre fit SET --method lsq --installation OPTION --out MODEL`.
fn fit_lsq(set: &Path, option: &str, model: &Path) -> Output {
    let (set, model) = (set.to_str().unwrap(), model.to_str().unwrap());
    mre(&["fit", set, "--method", "lsq", "--installation", option, "--out", model])
}

fn text(o: &Output) -> (String, String) {
    (
        String::from_utf8_lossy(&o.stdout).into_owned(),
        String::from_utf8_lossy(&o.stderr).into_owned(),
    )
}

/// The 3 kg, 9 mm rig the tests use; everything else the defaults'.
const LAB: Installation = Installation {
    mass_kg: 3.0,
    usable_stroke_mm: 9.0,
    ..DEFAULT_INSTALLATION
};

/// `data/drop-full-stroke` with `edit` applied to its dataset.toml.
fn dataset_copy(dir: &Path, edit: impl Fn(String) -> String) -> PathBuf {
    let src = root().join("data/drop-full-stroke");
    let dst = dir.join("set");
    std::fs::create_dir_all(&dst).unwrap();
    for entry in std::fs::read_dir(&src).unwrap() {
        let entry = entry.unwrap();
        std::fs::copy(entry.path(), dst.join(entry.file_name())).unwrap();
    }
    let toml = std::fs::read_to_string(dst.join("dataset.toml")).unwrap();
    assert_eq!(
        toml.matches("mass_kg = 5.5").count(),
        1,
        "the set declares its mass once"
    );
    std::fs::write(dst.join("dataset.toml"), edit(toml)).unwrap();
    dst
}

/// A model file (the paper's table) carrying LAB as `[installation]`.
fn lab_model(dir: &Path) -> PathBuf {
    let path = dir.join("lab.toml");
    let table = mre_host::table_file::table_to_toml(&Table::paper().unwrap());
    std::fs::write(
        &path,
        format!("{table}\n[installation]\nmass_kg = 3.0\nusable_stroke_mm = 9.0\n"),
    )
    .unwrap();
    path
}

#[test]
fn fit_writes_the_data_sets_mass_and_the_options_and_tables_carries_exactly_them() {
    let dir = tempfile::tempdir().unwrap();
    let set = dataset_copy(dir.path(), |t| t.replace("mass_kg = 5.5", "mass_kg = 3.0"));
    let model = dir.path().join("model.toml");
    let o = fit_lsq(&set, "usable_stroke_mm=9", &model);
    let (out, err) = text(&o);
    assert!(o.status.success(), "{err}");
    // Which value came from where, said.
    assert!(out.contains("mass_kg = 3 from the data set's metadata"), "{out}");
    assert!(out.contains("usable_stroke_mm = 9 from --installation"), "{out}");
    assert!(
        out.contains("coil_rating_a = 2,") && out.contains("from the defaults"),
        "{out}"
    );

    let written = mre_host::table_file::read_installation(&model).unwrap();
    assert_eq!(written, Some(LAB));
    assert!(std::fs::read_to_string(&model).unwrap().contains("format_version = 3"));

    // `mre tables` puts exactly those values in flash, under the CRC.
    let generated = dir.path().join("generated_table.rs");
    let o = mre(&["tables", model.to_str().unwrap(), "--out", generated.to_str().unwrap()]);
    let (out, err) = text(&o);
    assert!(o.status.success(), "{err}");
    assert!(
        out.contains("installation (format 3) from the model file's [installation]"),
        "{out}"
    );
    let (table, _) = mre_host::table_file::read_flash_table(&model).unwrap();
    assert_eq!(table.version(), mre_algorithm::table::FORMAT_VERSION_3);
    assert_eq!(*table.installation(), LAB);
    let source = std::fs::read_to_string(&generated).unwrap();
    assert!(
        source.contains("    mass_kg: 3.0,\n    usable_stroke_mm: 9.0,"),
        "{source}"
    );
}

#[test]
fn fit_without_a_declared_mass_or_with_several_states_the_defaults() {
    // The shaker set declares no mass: every value is the defaults'.
    let ds = mre_host::dataset::Dataset::load(&root().join("data/mr-damper-mts")).unwrap();
    let stated = StatedInstallation::from_dataset(&ds);
    assert_eq!(stated.installation, DEFAULT_INSTALLATION);
    assert_eq!(
        stated.describe().matches(" from ").count(),
        1,
        "one source: {}",
        stated.describe()
    );
    // Two drop masses: no one installation mass; the default stays, said why.
    let dir = tempfile::tempdir().unwrap();
    let set = dataset_copy(dir.path(), |t| {
        t.replacen("[[recording]]\n", "[[recording]]\nmass_kg = 4.0\n", 1)
    });
    let stated = StatedInstallation::from_dataset(&mre_host::dataset::Dataset::load(&set).unwrap());
    assert_eq!(stated.installation.mass_kg, DEFAULT_INSTALLATION.mass_kg);
    assert!(
        stated
            .describe()
            .contains("the data set declares several masses (4, 5.5 kg)"),
        "{}",
        stated.describe()
    );
}

#[test]
fn an_installation_option_outside_the_limits_or_unknown_is_refused_by_name() {
    let dir = tempfile::tempdir().unwrap();
    let model = dir.path().join("model.toml");
    let set = root().join("data/drop-full-stroke");
    for (option, says) in [
        (
            "usable_stroke_mm=30",
            "usable_stroke_mm = 30 is outside the board's limits",
        ),
        ("stroke=9", "unknown key `stroke`"),
        ("mass_kg=heavy", "`heavy` is not a number"),
    ] {
        let o = fit_lsq(&set, option, &model);
        let (_, err) = text(&o);
        assert!(!o.status.success() && err.contains(says), "{option}: {err}");
        assert!(!model.exists(), "{option}: no model written");
    }
    // bench-control and sim read the same options (refused before any run).
    let lab = lab_model(dir.path());
    for cmd in ["bench-control", "sim"] {
        let out_dir = dir.path().join(cmd);
        let flag = if cmd == "sim" { "--report" } else { "--out" };
        let o = mre(&[
            cmd,
            "--model",
            lab.to_str().unwrap(),
            "--installation",
            "mass_kg=1000",
            flag,
            out_dir.to_str().unwrap(),
        ]);
        let (_, err) = text(&o);
        assert!(
            !o.status.success() && err.contains("mass_kg = 1000 is outside the board's limits"),
            "{cmd}: {err}"
        );
    }
}

/// Work the damper absorbed while loading (J): ∫F dx from contact to the
/// largest displacement, on the recorded samples (trapezoids).
fn loading_work_j(csv_path: &Path) -> (f64, f64) {
    let mut reader = csv::Reader::from_path(csv_path).unwrap();
    let headers = reader.headers().unwrap().clone();
    let col = |name: &str| headers.iter().position(|h| h == name).unwrap();
    let (x, f) = (col("displacement_mm"), col("force_n"));
    let rows: Vec<(f64, f64)> = reader
        .records()
        .map(|r| {
            let r = r.unwrap();
            (r[x].parse().unwrap(), r[f].parse().unwrap())
        })
        .collect();
    let peak = (0..rows.len())
        .max_by(|&a, &b| rows[a].0.total_cmp(&rows[b].0))
        .unwrap();
    let work_j: f64 = rows[..=peak]
        .windows(2)
        .map(|w| 0.5 * (w[0].1 + w[1].1) * (w[1].0 - w[0].0) * 1e-3)
        .sum();
    (work_j, rows[peak].0)
}

#[test]
fn mre_sim_flies_the_model_files_mass_and_stroke() {
    let dir = tempfile::tempdir().unwrap();
    let lab = lab_model(dir.path());
    let run = |report: &Path, model: Option<&Path>| {
        let mut args = vec!["sim", "--current", "passive:2", "--current", "passive:0"];
        if let Some(m) = model {
            args.extend(["--model", m.to_str().unwrap()]);
        }
        args.extend(["--report", report.to_str().unwrap()]);
        let o = mre(&args);
        let (out, err) = text(&o);
        assert!(o.status.success(), "{err}");
        out
    };
    let (lab_dir, default_dir) = (dir.path().join("lab"), dir.path().join("default"));
    let out = run(&lab_dir, Some(&lab));
    assert!(
        out.contains(&format!(
            "mass_kg = 3, usable_stroke_mm = 9 from {}'s [installation]",
            lab.display()
        )),
        "{out}"
    );
    let out = run(&default_dir, None);
    assert!(out.contains("from the defaults (DEFAULT_INSTALLATION)"), "{out}");

    // The stroke the runs are judged against is the file's.
    let summary: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(lab_dir.join("summary.json")).unwrap()).unwrap();
    let runs = summary["runs"].as_array().unwrap();
    assert!(runs.iter().all(|r| r["usable_stroke_mm"] == 9.0), "{summary}");

    // The mass, by the work–energy theorem: at the largest stroke the mass
    // is at rest, so the damper has absorbed ½·m·v² + m·g·x_max. 3 kg and
    // 5.5 kg differ by 1.8×; the check holds to 3 % on either.
    let v_m_s: f64 = 2.24;
    for (folder, mass_kg) in [(&lab_dir, 3.0), (&default_dir, 5.5)] {
        for file in ["passive-2a.csv", "passive-0a.csv"] {
            let (work_j, x_max_mm) = loading_work_j(&folder.join(file));
            let energy_j = 0.5 * mass_kg * v_m_s * v_m_s + mass_kg * 9.81 * x_max_mm * 1e-3;
            assert!(
                (work_j / energy_j - 1.0).abs() < 0.03,
                "{file} at {mass_kg} kg: absorbed {work_j:.2} J, expected {energy_j:.2} J"
            );
        }
    }
    // And a lighter mass stops in less stroke at every current.
    for file in ["passive-2a.csv", "passive-0a.csv"] {
        let (_, lab_mm) = loading_work_j(&lab_dir.join(file));
        let (_, default_mm) = loading_work_j(&default_dir.join(file));
        assert!(
            lab_mm < default_mm,
            "{file}: {lab_mm} mm at 3 kg vs {default_mm} mm at 5.5 kg"
        );
    }
}

#[test]
fn the_controller_of_sim_pil_fmu_and_bench_control_plans_with_the_files_installation() {
    use mre_host::plant::closed_loop::{law_config, setup_for, SimRequest};
    let dir = tempfile::tempdir().unwrap();
    let stated = StatedInstallation::from_model_file(&lab_model(dir.path())).unwrap();
    assert_eq!(stated.installation, LAB);
    let setup = setup_for(&SimRequest {
        installation: stated.installation,
        ..SimRequest::default()
    })
    .unwrap();
    // The plant drops the file's mass; the law plans with its mass and stroke.
    assert_eq!(setup.impact.mass_kg, 3.0);
    assert_eq!(setup.usable_stroke_mm(), 9.0);
    let law = law_config(&setup);
    assert_eq!((law.mass_kg, law.stroke_max_mm), (3.0, 9.0));

    // `mre pil`'s upload: the table carries the installation (format 3) and
    // the firmware's decoder accepts the configuration as agreeing with it.
    let cfg = mre_host::pil::sim::control_config(&setup).unwrap();
    assert_eq!((cfg.law.mass_kg, cfg.law.stroke_max_mm), (3.0, 9.0));
    let table = Table::paper().unwrap().carrying(LAB).unwrap();
    let mut words = [0u32; mre_protocol::frame::CONFIG_MAX_WORDS];
    let n = mre_protocol::frame::encode_config(&table, &cfg, &mut words);
    let (flown_table, flown_cfg) = mre_protocol::frame::decode_config(&words[..n]).unwrap();
    assert_eq!(*flown_table.installation(), LAB);
    assert_eq!(flown_cfg, cfg, "the board flies what the host simulates");

    // The FMU's controller: the model file's installation, not the defaults.
    let fmu_cfg = mre_host::fmu::installation(&table).unwrap();
    assert_eq!((fmu_cfg.law.mass_kg, fmu_cfg.law.stroke_max_mm), (3.0, 9.0));
    let default_cfg = mre_host::fmu::installation(&Table::paper().unwrap()).unwrap();
    assert_eq!(
        (default_cfg.law.mass_kg, default_cfg.law.stroke_max_mm),
        (DEFAULT_INSTALLATION.mass_kg, DEFAULT_INSTALLATION.usable_stroke_mm)
    );

    // bench-control's drop.
    let plant = mre_host::plant::stepper::Plant::nominal();
    let drop = mre_host::control_bench::drop_setup(&plant, 60, 1, &LAB);
    assert_eq!((drop.impact.mass_kg, drop.usable_stroke_mm()), (3.0, 9.0));
    assert_eq!(drop.impact.sequence, 61);
}

#[test]
fn mre_pil_flies_a_3_kg_9_mm_installation_sample_for_sample() {
    use mre_host::pil::qemu::{build_firmware, usable_qemu};
    use mre_host::pil::sim::{run_pil, PilRequest};
    use mre_host::plant::closed_loop::{RunSpec, SimRequest};
    if let Err(why) = usable_qemu() {
        assert!(std::env::var_os("CI").is_none(), "QEMU 10 is required in CI: {why}");
        eprintln!("skipped: {why}");
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let request = PilRequest {
        sim: SimRequest {
            installation: LAB,
            runs: vec![RunSpec::Controlled],
            ..SimRequest::default()
        },
        elf: Some(build_firmware().unwrap()),
    };
    let out = run_pil(&request, dir.path()).unwrap();
    // The firmware planned with the uploaded 3 kg / 9 mm installation: its
    // commands match the host's, which plans with the same, bit for bit.
    assert!(out.agreement.agrees(), "{:?}", out.agreement);
    assert_eq!(out.agreement.bit_identical_commands, out.agreement.samples);
    assert!(out.agreement_with_sim.agrees(), "{:?}", out.agreement_with_sim);
    assert_eq!(out.comparison.runs[0].usable_stroke_mm, 9.0);
}
