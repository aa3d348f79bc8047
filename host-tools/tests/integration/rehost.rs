//! The real board images (`cargo fw` for the B-L475E-IOT01A, `cargo
//! fw-nucleo` for the NUCLEO-L476RG; not the PIL image) rehosted on the
//! Unicorn engine with STM32L4 peripheral models written from RM0351
//! (firmware/rehost/stm32l4.py; the scenarios in firmware/rehost/scenarios.py).
//! Needs python3 with `pip install unicorn`; without it the test says so and
//! passes, except under CI (`CI` set), where it fails. Issue 39.
//!
//! `MRE_REHOST_ELF` / `MRE_REHOST_NUCLEO_ELF` name prebuilt images (else
//! they are built here: `cargo fw`, `cargo fw-nucleo`, copied to `target/images/`).
use mre_algorithm::control::{ControlConfig, DEFAULT_RATE_HZ};
use mre_algorithm::installation::{Installation, DEFAULT_INSTALLATION};
use mre_algorithm::table::{CurrentEntry, ModelTerms, Quartic, Table};
use mre_algorithm::Flags;
use mre_protocol::flash_table::{store, RamPage};
use mre_protocol::frame::{config_frames, encode_config, CommandFrame, CONFIG_MAX_WORDS, FRAME_LEN};
use std::path::{Path, PathBuf};
use std::process::Command;
use std::sync::OnceLock;

fn workspace_root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).parent().unwrap().to_path_buf()
}

fn unicorn_available() -> bool {
    Command::new("python3")
        .args(["-c", "import unicorn"])
        .output()
        .is_ok_and(|o| o.status.success())
}

/// False (and a message) when the rehost cannot run here; a failure on CI.
fn rehost_available() -> bool {
    crate::tool_rule::installed_or_skipped(
        unicorn_available(),
        "python3 with the unicorn package",
        "`python3 -m pip install unicorn`",
    )
}

fn build(alias: &str) -> PathBuf {
    mre_host::cargo_build::firmware_image(&workspace_root(), alias).unwrap_or_else(|e| panic!("cargo {alias}: {e:#}"))
}

/// The two board images, built once per test binary.
fn image(board: &str) -> PathBuf {
    static B_L475: OnceLock<PathBuf> = OnceLock::new();
    static NUCLEO: OnceLock<PathBuf> = OnceLock::new();
    match board {
        "b-l475e-iot01a" => B_L475
            .get_or_init(|| match std::env::var_os("MRE_REHOST_ELF") {
                Some(p) => p.into(),
                None => build("fw"),
            })
            .clone(),
        _ => NUCLEO
            .get_or_init(|| match std::env::var_os("MRE_REHOST_NUCLEO_ELF") {
                Some(p) => p.into(),
                None => build("fw-nucleo"),
            })
            .clone(),
    }
}

const BOARDS: [&str; 2] = ["b-l475e-iot01a", "nucleo-l476rg"];

/// Runs one scenario; returns its stdout. Panics with the harness's output
/// when it fails.
fn scenario(board: &str, name: &str, extra: &[(&str, &Path)]) -> String {
    let mut cmd = Command::new("python3");
    cmd.arg(workspace_root().join("firmware/rehost/scenarios.py"))
        .arg("--elf")
        .arg(image(board))
        .args(["--board", board]);
    for (flag, path) in extra {
        cmd.arg(flag).arg(path);
    }
    let out = cmd.arg(name).output().expect("running python3");
    let stdout = String::from_utf8_lossy(&out.stdout).into_owned();
    assert!(
        out.status.success(),
        "{board} {name} failed:\n{stdout}\n{}",
        String::from_utf8_lossy(&out.stderr)
    );
    eprintln!("{}", stdout.lines().last().unwrap_or_default());
    stdout
}

/// A 1 A coil (the weakest the board admits), format 3: its fail-safe is 1 A.
fn one_amp_coil_table() -> (Table, ControlConfig) {
    let installation = Installation {
        coil_rating_a: 1.0,
        ..DEFAULT_INSTALLATION
    };
    let entry = |current_a: f32, k: f32| CurrentEntry {
        current_a,
        compression: Quartic::new([0.0, 0.0, 0.0, k, 0.0]),
        extension: Quartic::new([0.0, 0.0, 0.0, 0.5 * k, 0.0]),
        x_min_mm: 0.0,
        x_max_mm: 15.0,
    };
    let table = Table::with_installation(&[entry(0.0, 100.0), entry(1.0, 900.0)], ModelTerms::NONE, installation)
        .expect("a valid 1 A table");
    let mut cfg = ControlConfig::at_rate(DEFAULT_RATE_HZ).unwrap();
    installation.apply(&mut cfg);
    cfg.validate().expect("a valid 1 A configuration");
    assert_eq!(cfg.law.failsafe_current_a, 1.0);
    (table, cfg)
}

#[test]
fn each_reset_cause_commands_the_coil_and_calibrates_as_documented_and_the_sense_converts() {
    if !rehost_available() {
        return;
    }
    for board in BOARDS {
        for cause in ["power-on", "pin", "iwdg", "software", "brown-out"] {
            scenario(board, &format!("boot:{cause}"), &[]);
        }
    }
}

#[test]
fn an_over_current_removes_the_drive_and_b1_does_not_restore_it() {
    if !rehost_available() {
        return;
    }
    for board in BOARDS {
        scenario(board, "over-current", &[]);
    }
}

#[test]
fn panic_and_hardfault_mask_interrupts_hold_the_safe_state_and_reset_by_the_watchdog() {
    if !rehost_available() {
        return;
    }
    for board in BOARDS {
        // panic-in-panic: a panic inside the handler's log line ends at the
        // second entry (`PANICKING`); planted without it, 200 entries.
        for name in ["panic", "panic-in-panic", "hardfault", "hardfault-after-over-current"] {
            scenario(board, name, &[]);
        }
    }
}

/// The stack guard (memory.x: the stack alone in SRAM2, reserved address
/// space below it): a deliberate overflow (the control interrupt entered
/// with 32 bytes of stack left) faults at the stack's bottom into HardFault,
/// which holds the fail-safe with interrupts masked until the watchdog
/// resets; without the guard the overflow runs into .bss unnoticed.
#[test]
fn a_stack_overflow_faults_at_the_stack_bottom_into_the_safe_state() {
    if !rehost_available() {
        return;
    }
    for board in BOARDS {
        scenario(board, "stack-overflow", &[]);
    }
}

#[test]
fn a_hung_thread_task_ends_in_a_watchdog_reset_into_the_fail_safe() {
    if !rehost_available() {
        return;
    }
    for board in BOARDS {
        scenario(board, "hung-task", &[]);
    }
}

/// The page `mre upload` would leave, written by the core's `store`.
fn stored_page(table: &Table, cfg: &ControlConfig) -> Vec<u8> {
    let mut page = RamPage::erased();
    store(&mut page, table, cfg).unwrap();
    page.bytes.to_vec()
}

#[test]
fn an_uploaded_coil_sets_the_fail_safe_and_a_torn_page_boots_the_built_in_table() {
    if !rehost_available() {
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let (table, cfg) = one_amp_coil_table();
    let page = dir.path().join("page.bin");
    std::fs::write(&page, stored_page(&table, &cfg)).unwrap();
    for board in BOARDS {
        scenario(board, "page", &[("--page", &page)]);
        scenario(board, "torn-page", &[("--page", &page)]);
    }
}

/// The answer frames the board sent on its VCP (the `tx` line).
fn answers(stdout: &str) -> Vec<CommandFrame> {
    let hex = stdout
        .lines()
        .find_map(|l| l.strip_prefix("tx "))
        .expect("the harness prints the VCP's bytes");
    let bytes: Vec<u8> = (0..hex.len() / 2)
        .map(|k| u8::from_str_radix(&hex[2 * k..2 * k + 2], 16).unwrap())
        .collect();
    bytes
        .chunks_exact(FRAME_LEN)
        .map(|c| CommandFrame::decode(c.try_into().unwrap()).expect("an answer frame"))
        .collect()
}

fn page_after(stdout: &str) -> Vec<u8> {
    let hex = stdout.lines().find_map(|l| l.strip_prefix("page ")).unwrap();
    (0..hex.len() / 2)
        .map(|k| u8::from_str_radix(&hex[2 * k..2 * k + 2], 16).unwrap())
        .collect()
}

#[test]
fn an_upload_is_stored_and_one_with_an_erase_or_program_error_is_refused() {
    if !rehost_available() {
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let (table, cfg) = one_amp_coil_table();
    let mut words = [0u32; CONFIG_MAX_WORDS];
    let n = encode_config(&table, &cfg, &mut words);
    let frames: Vec<u8> = config_frames(&words[..n]).flatten().collect();
    let upload = dir.path().join("upload.bin");
    std::fs::write(&upload, frames).unwrap();
    let expected_page = stored_page(&table, &cfg);
    for board in BOARDS {
        let ok = scenario(board, "upload", &[("--upload", &upload)]);
        let a = answers(&ok);
        assert_eq!(a.len(), 1, "{board}: one answer to one commit");
        assert_eq!(a[0].flags, Flags::NONE, "{board}: stored");
        assert_eq!(a[0].rejected, 0);
        assert_eq!(page_after(&ok), expected_page, "{board}: the page holds the upload");
        for failure in ["upload-erase-error", "upload-program-error"] {
            let out = scenario(board, failure, &[("--upload", &upload)]);
            let a = answers(&out);
            assert_eq!(a.len(), 1, "{board} {failure}: one answer");
            // TABLE_FAULT and code 4: the flash page could not be written.
            assert_eq!(a[0].flags, Flags::TABLE_FAULT, "{board} {failure}: answered stored");
            assert_eq!(a[0].rejected, 4, "{board} {failure}");
            assert_ne!(page_after(&out), expected_page, "{board} {failure}");
        }
    }
}
