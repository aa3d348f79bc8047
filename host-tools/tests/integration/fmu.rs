//! `mre fmu`'s FMUs loaded by rust-fmi's importer (the `fmi` crate): the
//! damper's force is the core's on a recorded drop (CS and ME), the
//! controller's command is the board controller's, and a refused table page
//! fails initialisation instead of running.
use crate::fmu_support;

use fmi::fmi3::import::Fmi3Import;
use fmi::fmi3::{CoSimulation, Common, Fmi3Model, GetSet};
use fmi::traits::FmiImport;
use fmu_support::*;
use mre_algorithm::control::Controller;
use std::io::{Read, Write};

fn vr(import: &Fmi3Import, name: &str) -> u32 {
    import
        .model_description()
        .model_variables
        .iter_abstract()
        .find(|v| v.name() == name)
        .unwrap_or_else(|| panic!("no variable {name}"))
        .value_reference()
}

fn get(inst: &mut impl GetSet, vr: u32) -> f64 {
    let mut out = [0.0];
    inst.get_float64(&[vr], &mut out).expect("get");
    out[0]
}

#[test]
fn damper_force_is_the_cores_on_a_recorded_drop() {
    let dir = tempfile::tempdir().unwrap();
    let table = every_term_table();
    let model = dir.path().join("every-term.toml");
    std::fs::write(&model, mre_host::table_file::table_to_toml(&table)).unwrap();
    let fmu = mre_fmu(&model, dir.path(), false);
    let import: Fmi3Import = fmi::import::from_path(&fmu).expect("the fmi crate imports damper.fmu");
    let md = import.model_description();
    assert_eq!(md.fmi_version, "3.0");
    assert!(md.model_exchange.is_some() && md.co_simulation.is_some());
    let [x, v, i, f, tau] =
        ["displacement_m", "velocity_m_s", "current_a", "force_n", "coil_tau_s"].map(|n| vr(&import, n));

    let samples = trace();
    let scale = samples
        .iter()
        .map(|s| core_force_n(&table, s).abs())
        .fold(0.0f32, f32::max);
    // x goes in as m and the FMU converts to mm in f32: a few ulps of the force.
    let allowed_n = 8.0 * f64::from(f32::EPSILON) * f64::from(scale);
    let mut cs = import
        .instantiate_cs("damper", false, false, false, false, &[])
        .expect("CS instance");
    cs.enter_initialization_mode(None, 0.0, None).unwrap();
    cs.exit_initialization_mode().unwrap();
    let mut me = import.instantiate_me("damper-me", false, false).expect("ME instance");
    me.enter_initialization_mode(None, 0.0, None).unwrap();
    me.exit_initialization_mode().unwrap();
    // Evaluated in Event Mode, where the branch follows the velocity at every set:
    // in Continuous-Time Mode it is held until the importer handles the velocity's
    // zero crossing as an event (tests/fmu/check_fmus.py's ME trace does that).
    // The model file's coil τ (2 ms), read from the page the FMU carries.
    assert_eq!(get(&mut cs, tau), 2.0e-3_f32 as f64);
    let mut worst_n: f64 = 0.0;
    for s in &samples {
        let inputs = [s.x_mm * 1e-3, s.v_m_s, s.current_a];
        cs.set_float64(&[x, v, i], &inputs).unwrap();
        me.set_float64(&[x, v, i], &inputs).unwrap();
        let core_n = f64::from(core_force_n(&table, s));
        for force in [get(&mut cs, f), get(&mut me, f)] {
            worst_n = worst_n.max((force - core_n).abs());
        }
    }
    assert!(
        worst_n <= allowed_n,
        "damper.fmu's force differs from the core's by up to {worst_n} N (f32 rounding allows {allowed_n} N)"
    );
    // Not trivially equal: the drive spans a real range of forces.
    assert!(scale > 100.0, "the drive should load the damper (peak {scale} N)");
}

#[test]
fn controller_commands_what_the_board_controller_commands() {
    // The model the firmware flies (fitted over the whole 0–15 mm stroke).
    let dir = tempfile::tempdir().unwrap();
    let model = repo().join("models/drop-full-stroke.toml");
    let table = mre_host::table_file::read_table_file(&model).unwrap();
    let damper = mre_fmu(&model, dir.path(), true);
    let import: Fmi3Import =
        fmi::import::from_path(mre_host::fmu::controller_path(&damper)).expect("the fmi crate imports controller.fmu");
    let [x, v, u, period, coil, volts] = [
        "displacement_m",
        "velocity_m_s",
        "coil_command_a",
        "control_period_s",
        "coil_current_a",
        "drive_voltage_v",
    ]
    .map(|n| vr(&import, n));
    let mut cs = import
        .instantiate_cs("controller", false, false, false, false, &[])
        .unwrap();
    cs.enter_initialization_mode(None, 0.0, None).unwrap();
    cs.exit_initialization_mode().unwrap();
    let period_s = get(&mut cs, period);
    assert_eq!(period_s, f64::from(1.0f32 / 10_000.0), "the board's 10 kHz");

    // The board's controller with the same table and installation, fed the same samples.
    let cfg = mre_host::fmu::installation(&table).unwrap();
    let mut board = Controller::new(cfg, Ok(table)).unwrap();
    let mut t = 0.0;
    let mut changed = 0;
    let mut last = f64::NAN;
    // The recording is sampled at 20 kHz: every second sample is one 10 kHz period.
    for s in trace().into_iter().step_by(2) {
        cs.set_float64(&[x, v], &[s.x_mm * 1e-3, s.v_m_s]).unwrap();
        let (mut event, mut terminate, mut early, mut reached) = (false, false, false, 0.0);
        cs.do_step(t, period_s, true, &mut event, &mut terminate, &mut early, &mut reached)
            .unwrap();
        t += period_s;
        let expected = board.step_sample((s.x_mm * 1e-3 * 1e3) as f32, Some(s.v_m_s as f32));
        let command = get(&mut cs, u);
        assert_eq!(command, f64::from(expected.current_a), "tick at {t} s");
        // This model file has no coil τ (the command is the current) and the default
        // installation's 4 Ω coil.
        assert_eq!(get(&mut cs, coil), command, "coil current at {t} s");
        assert_eq!(get(&mut cs, volts), command * 4.0, "drive voltage at {t} s");
        assert!(
            !expected.flags.is_fault(),
            "the drop should fly without a fault ({:?})",
            expected.flags
        );
        changed += usize::from(command != last);
        last = command;
    }
    assert!(changed > 10, "the command should follow the drop ({changed} changes)");
}

#[test]
fn a_refused_table_page_fails_initialisation() {
    let dir = tempfile::tempdir().unwrap();
    let model = dir.path().join("every-term.toml");
    std::fs::write(&model, mre_host::table_file::table_to_toml(&every_term_table())).unwrap();
    let fmu = mre_fmu(&model, dir.path(), false);
    // Flip one byte of the page's blob: its CRC no longer matches.
    let corrupted = dir.path().join("corrupted.fmu");
    {
        let mut zin = zip::ZipArchive::new(std::fs::File::open(&fmu).unwrap()).unwrap();
        let mut zout = zip::ZipWriter::new(std::fs::File::create(&corrupted).unwrap());
        for k in 0..zin.len() {
            let mut entry = zin.by_index(k).unwrap();
            let name = entry.name().to_owned();
            let mut bytes = Vec::new();
            entry.read_to_end(&mut bytes).unwrap();
            if name == "resources/table.page" {
                bytes[40] ^= 0x01;
            }
            zout.start_file(name, zip::write::SimpleFileOptions::default()).unwrap();
            zout.write_all(&bytes).unwrap();
        }
        zout.finish().unwrap();
    }
    let import: Fmi3Import = fmi::import::from_path(&corrupted).unwrap();
    let mut cs = import
        .instantiate_cs("damper", false, false, false, false, &[])
        .unwrap();
    cs.enter_initialization_mode(None, 0.0, None).unwrap();
    assert!(
        cs.exit_initialization_mode().is_err(),
        "a page the board's loader refuses must not be flown"
    );
}

#[test]
fn a_missing_model_file_is_a_sentence() {
    let dir = tempfile::tempdir().unwrap();
    let o = std::process::Command::new(env!("CARGO_BIN_EXE_mre"))
        .args(["fmu", "no-such-model.toml", "--out"])
        .arg(dir.path().join("d.fmu"))
        .output()
        .unwrap();
    assert!(!o.status.success());
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(err.contains("cannot read model file no-such-model.toml"), "{err}");
    assert!(!dir.path().join("d.fmu").exists());
}

#[test]
fn every_binary_exports_every_fmi3_function() {
    let required = fmi_functions(3);
    // Counted by hand in the header: 6 version/logging/instance + 5 mode + 14 getters + 14 setters
    // + 2 dependency + 6 FMU state + 2 derivative + 2 configuration + 8 clock + 2 discrete state
    // + 10 Model Exchange + 3 Co-Simulation + 1 Scheduled Execution.
    assert_eq!(required.len(), 75, "{required:?}");
    let dir = tempfile::tempdir().unwrap();
    let model = dir.path().join("every-term.toml");
    std::fs::write(&model, mre_host::table_file::table_to_toml(&every_term_table())).unwrap();
    let damper = mre_fmu(&model, dir.path(), true);
    for fmu in [damper.clone(), mre_host::fmu::controller_path(&damper)] {
        for (name, bytes) in &checked_binaries(&fmu, ["x86_64-linux", "x86_64-windows"], &required) {
            let expected_format = if name.ends_with(".dll") {
                object::BinaryFormat::Pe
            } else {
                object::BinaryFormat::Elf
            };
            use object::read::Object;
            let file = object::File::parse(&bytes[..]).unwrap();
            assert_eq!(file.format(), expected_format, "{name}");
            assert_eq!(file.architecture(), object::Architecture::X86_64, "{name}");
        }
    }
}

#[test]
fn damper_declares_units_and_ranges_and_warns_out_of_range() {
    use fmi::fmi3::Fmi3Res;
    use fmi::schema::fmi3::{TypeDefinition, Variable};
    let dir = tempfile::tempdir().unwrap();
    let model = dir.path().join("every-term.toml");
    std::fs::write(&model, mre_host::table_file::table_to_toml(&every_term_table())).unwrap();
    let fmu = mre_fmu(&model, dir.path(), false);
    let import: Fmi3Import = fmi::import::from_path(&fmu).unwrap();
    let md = import.model_description();

    // The ampere with its dimension (FMI 3.0: <BaseUnit A="1"/>).
    let units = &md.unit_definitions.as_ref().expect("unit definitions").units;
    let ampere = units.iter().find(|u| u.name == "A").expect("unit A");
    let base = ampere.base_unit.as_ref().expect("A has a BaseUnit");
    assert_eq!((base.a, base.kg, base.m, base.s), (Some(1), None, None, None));
    let newton = units
        .iter()
        .find(|u| u.name == "N")
        .and_then(|u| u.base_unit.as_ref())
        .unwrap();
    assert_eq!((newton.kg, newton.m, newton.s), (Some(1), Some(1), Some(-2)));

    // Table 4 by hand: every stroke starts at 0, the longest ends at 1.1531 mm (0 A);
    // currents 0–2 A; the default installation's fastest impact 2.5 m/s.
    let x_max_m = f64::from(1.1531f32) * 1e-3;
    let expected = [
        ("displacement_m", 0.0, x_max_m),
        ("velocity_m_s", -2.5, 2.5),
        ("current_a", 0.0, 2.0),
    ];
    for (name, min, max) in expected {
        let v = md
            .model_variables
            .variables
            .iter()
            .find_map(|v| match v {
                Variable::Float64(f) if f.name == name => Some(f),
                _ => None,
            })
            .unwrap();
        assert_eq!((v.min, v.max), (Some(min), Some(max)), "{name}");
    }
    let nominal = |ty: &str| {
        md.type_definitions
            .as_ref()
            .unwrap()
            .type_definitions
            .iter()
            .find_map(|t| match t {
                TypeDefinition::Float64(f) if f.name == ty => f.nominal,
                _ => None,
            })
    };
    assert_eq!(nominal("Length"), Some(x_max_m));
    assert_eq!(nominal("Velocity"), Some(2.5));
    assert_eq!(nominal("Current"), Some(2.0));

    let [x, v, i, f] = ["displacement_m", "velocity_m_s", "current_a", "force_n"].map(|n| vr(&import, n));
    let mut cs = import
        .instantiate_cs("damper", false, false, false, false, &[])
        .unwrap();
    cs.enter_initialization_mode(None, 0.0, None).unwrap();
    cs.exit_initialization_mode().unwrap();
    let mut force_at = |inputs: [f64; 3]| -> (Fmi3Res, f64) {
        let status = cs.set_float64(&[x, v, i], &inputs).unwrap();
        (status, get(&mut cs, f))
    };
    let (status, _) = force_at([0.5e-3, 1.0, 1.0]);
    assert_eq!(status, Fmi3Res::OK, "inputs inside their ranges");
    // Expectations by hand from the core's rules: NaN x counts as each stroke's start
    // (0 for every entry), x beyond every stroke as each stroke's end (as 1 m does), a
    // current above the table as its top (2 A), an infinite one as the lowest (0 A), a
    // NaN velocity as the extension branch without viscous force (as v = 0).
    let cases = [
        ("NaN displacement", [f64::NAN, 1.0, 1.0], Some([0.0, 1.0, 1.0])),
        ("12 m (mm meant)", [12.0, 1.0, 1.0], None),
        ("5 A", [0.5e-3, 1.0, 5.0], Some([0.5e-3, 1.0, 2.0])),
        (
            "infinite current",
            [0.5e-3, 1.0, f64::INFINITY],
            Some([0.5e-3, 1.0, 0.0]),
        ),
        ("NaN velocity", [0.5e-3, f64::NAN, 1.0], Some([0.5e-3, 0.0, 1.0])),
        ("-3 m/s", [0.5e-3, -3.0, 0.0], None),
    ];
    for (what, bad, same_as) in cases {
        let (status, force) = force_at(bad);
        assert_eq!(status, Fmi3Res::Warning, "{what}: fmi3SetFloat64 warns");
        assert!(force.is_finite(), "{what}: force {force}");
        if let Some(reference) = same_as {
            let (status, expected) = force_at(reference);
            assert_eq!(status, Fmi3Res::OK, "{what}: the reference {reference:?} is in range");
            assert_eq!(force, expected, "{what}: handled as {reference:?}");
        }
    }
    // Beyond every stroke: each entry at its end, as at 1 m (itself out of range).
    let (_, at_12_m) = force_at([12.0, 1.0, 1.0]);
    let (_, at_1_m) = force_at([1.0, 1.0, 1.0]);
    assert_eq!(at_12_m, at_1_m);
    let (_, at_stroke_end) = force_at([0.9e-3, 1.0, 1.0]);
    assert_ne!(
        at_12_m, at_stroke_end,
        "the clamp check needs a force that varies with x"
    );
}

#[test]
fn the_fmu_documents_itself_and_its_generation() {
    let dir = tempfile::tempdir().unwrap();
    let model = repo().join("models/drop-full-stroke.toml");
    let table = mre_host::table_file::read_table_file(&model).unwrap();
    let out = dir.path().join("damper.fmu");
    let o = std::process::Command::new(env!("CARGO_BIN_EXE_mre"))
        .args(["fmu", "--quiet", "--controller", "--out"])
        .arg(&out)
        .arg(&model)
        .env("SOURCE_DATE_EPOCH", "1000000000")
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let crc = format!("{:#010x}", table.crc32());
    for (fmu, names) in [
        (
            out.clone(),
            &["displacement_m", "velocity_m_s", "current_a", "force_n"][..],
        ),
        (
            mre_host::fmu::controller_path(&out),
            &["displacement_m", "velocity_m_s", "coil_command_a", "flags"][..],
        ),
    ] {
        let mut zip = zip::ZipArchive::new(std::fs::File::open(&fmu).unwrap()).unwrap();
        let mut html = String::new();
        zip.by_name("documentation/index.html")
            .expect("documentation/index.html in the FMU")
            .read_to_string(&mut html)
            .unwrap();
        // The model file's [model] dataset line, its table's CRC, every named variable.
        for needle in [
            "synthetic drop impact, 5.5 kg, seed 108",
            "afdee8e7499416880df4e6c7c6dc27b54bf9d6ce633cb1f6f78b23a8f4f1685e",
            &crc,
            "fmi3Warning",
            "Wiring",
        ]
        .iter()
        .copied()
        .chain(names.iter().copied())
        {
            assert!(html.contains(needle), "{}: index.html lacks {needle:?}", fmu.display());
        }
        let mut xml = String::new();
        zip.by_name("modelDescription.xml")
            .unwrap()
            .read_to_string(&mut xml)
            .unwrap();
        let md: fmi::schema::fmi3::Fmi3ModelDescription = fmi::schema::deserialize(&xml).unwrap();
        // 10⁹ s after the epoch, by hand: 11 574 days (2001-09-09) and 6 400 s (01:46:40).
        assert_eq!(md.generation_date_and_time.as_deref(), Some("2001-09-09T01:46:40Z"));
        assert_eq!(
            md.version.as_deref(),
            Some(format!("{}+table.{:08x}", env!("CARGO_PKG_VERSION"), table.crc32()).as_str())
        );
        assert!(md.generation_tool.as_deref().is_some_and(|t| t.starts_with("mre ")));
    }
}

#[test]
fn generation_dates_by_hand() {
    use mre_host::fmu::generation_date;
    assert_eq!(generation_date(Some("0")).unwrap(), "1970-01-01T00:00:00Z");
    // 2000-02-29 (a leap day of a year divisible by 400): 11 016 days.
    assert_eq!(generation_date(Some("951782400")).unwrap(), "2000-02-29T00:00:00Z");
    // One second before 2025: 20 089 days less a second.
    assert_eq!(generation_date(Some("1735689599")).unwrap(), "2024-12-31T23:59:59Z");
    assert!(generation_date(Some("yesterday")).is_err());
    assert!(generation_date(None).unwrap().ends_with('Z'));
}

#[test]
fn the_same_source_date_epoch_writes_the_same_fmu() {
    // Reproducible builds: with SOURCE_DATE_EPOCH fixed, two runs write identical bytes
    // (zip entries carry no time of their own; the date is the variable's).
    let dir = tempfile::tempdir().unwrap();
    let model = dir.path().join("every-term.toml");
    std::fs::write(&model, mre_host::table_file::table_to_toml(&every_term_table())).unwrap();
    let write = |name: &str, epoch: &str| {
        let out = dir.path().join(name);
        let o = std::process::Command::new(env!("CARGO_BIN_EXE_mre"))
            .args(["fmu", "--quiet", "--out"])
            .arg(&out)
            .arg(&model)
            .env("SOURCE_DATE_EPOCH", epoch)
            .output()
            .unwrap();
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        std::fs::read(out).unwrap()
    };
    let first = write("a.fmu", "1700000000");
    // A second apart: a date taken from the clock would differ.
    std::thread::sleep(std::time::Duration::from_millis(1100));
    assert_eq!(first, write("b.fmu", "1700000000"), "same epoch, same bytes");
    assert_ne!(first, write("c.fmu", "1700000001"), "the date is in the FMU");
}
