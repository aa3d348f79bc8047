//! `mre upload --port PORT model.toml`: sends a table (and the control
//! configuration) to a running board over its serial port, without
//! reflashing. The board validates it, writes its reserved flash page, reads
//! it back and answers; it flies the table after its next reset
//! (firmware/README.md, "Uploaded tables"). The PIL image in QEMU takes the
//! same upload on USART1 and flies it at once.
//!
//! The bytes are the PIL protocol's config frames (`mre_protocol::frame`), so
//! the firmware's receiver (`mre_protocol::upload`) is the code the host tests
//! and the fuzz target (`fuzz/fuzz_targets/upload.rs`) exercise.
use crate::pil::link::PilLink;
use crate::table_file::read_flash_table;
use anyhow::{anyhow, bail, Context, Result};
use mre_algorithm::control::{ControlConfig, DEFAULT_RATE_HZ};
use mre_algorithm::table::Table;
use mre_algorithm::Flags;
use mre_protocol::frame::{encode_config, CONFIG_MAX_WORDS};
use std::path::Path;
use std::time::Duration;

/// How long to ping for the board's hello before giving up.
pub const HELLO_TIMEOUT: Duration = Duration::from_secs(10);

/// What was uploaded and acknowledged.
#[derive(Clone, Copy, Debug)]
pub struct Uploaded {
    pub table_crc32: u32,
    pub mass_kg: f32,
    pub stroke_mm: f32,
    pub currents: usize,
    pub rate_hz: u32,
    pub words: usize,
}

/// What `mre upload` sends: the model (or table) file's table as format 3,
/// carrying the file's `[installation]` (or the defaults), and the board's
/// default configuration at `rate_hz` with that installation applied
/// (`Installation::apply`: mass, usable stroke, the coil's rating, the drive
/// range, the sensors). The board refuses a configuration that disagrees
/// with the table's installation. Fails, naming the value, when the
/// installation is outside the board's hard limits.
pub fn upload_payload(model: &Path, rate_hz: u32) -> Result<(Table, ControlConfig)> {
    let (table, _) = read_flash_table(model)?;
    let mut cfg = ControlConfig::at_rate(rate_hz).map_err(|e| anyhow!("control rate {rate_hz} Hz: {e:?}"))?;
    table.installation().apply(&mut cfg);
    Ok((table, cfg))
}

/// The board's hard limits (`mre_algorithm::limits::BOARD`), checked before
/// sending: the board would refuse the same values.
pub fn check_board_limits(cfg: &ControlConfig) -> Result<()> {
    use mre_algorithm::limits::{check, BOARD};
    if let Err(limit) = check(cfg, &BOARD) {
        let range = limit.range(&BOARD);
        bail!(
            "{} = {} is outside the board's limits {} to {} ({}); nothing was sent",
            limit.name(),
            limit.value(cfg),
            range.min,
            range.max,
            limit.why()
        );
    }
    Ok(())
}

/// What a board's answer to a commit says, as a sentence.
pub fn refusal(code: u16) -> String {
    use mre_algorithm::limits::BOARD;
    use mre_protocol::upload::{CommitAnswer, REST_BEFORE_UPLOAD_S};
    match CommitAnswer::from_code(code) {
        Some(CommitAnswer::NotAtRest) => format!(
            "the board did not store the upload because the damper was not at rest (armed, idle and still for {REST_BEFORE_UPLOAD_S} s); retry when it is still"
        ),
        Some(CommitAnswer::OutOfLimits(limit)) => {
            let range = limit.range(&BOARD);
            format!(
                "the board refused the upload: {} is outside its limits {} to {} ({})",
                limit.name(),
                range.min,
                range.max,
                limit.why()
            )
        }
        Some(CommitAnswer::InstallationOutOfLimits(limit)) => {
            let range = limit.range(&BOARD);
            format!(
                "the board refused the upload: the table's installation value {} is outside its limits {} to {} ({})",
                limit.name(),
                range.min,
                range.max,
                limit.why()
            )
        }
        Some(CommitAnswer::Incomplete) => "the board received the upload incomplete (a frame was lost or corrupt)".into(),
        Some(CommitAnswer::Invalid) => "the board refused the table or configuration as invalid (its log says why)".into(),
        Some(CommitAnswer::PageFailed) => "the board could not write or read back its flash page".into(),
        Some(CommitAnswer::Stored) | None => "the board refused the upload or could not store it (its log says why)".into(),
    }
}

/// Sends `table` and `cfg` over an open link and waits for the answer.
/// Fails, before sending, when a value is outside the board's hard limits,
/// and when the board refuses or could not store them.
pub fn upload_over(link: &mut PilLink, table: &Table, cfg: &ControlConfig) -> Result<Uploaded> {
    check_board_limits(cfg)?;
    crate::table_file::check_installation_limits(table.installation()).context("nothing was sent")?;
    let mut words = [0u32; CONFIG_MAX_WORDS];
    let n = encode_config(table, cfg, &mut words);
    let answer = link.send_config_words(&words[..n])?;
    if answer.flags.contains(Flags::TABLE_FAULT) {
        bail!("{}; it keeps the table it had", refusal(answer.rejected));
    }
    Ok(Uploaded {
        table_crc32: table.crc32(),
        mass_kg: cfg.law.mass_kg,
        stroke_mm: cfg.law.stroke_max_mm,
        currents: table.entries().len(),
        rate_hz: cfg.rate_hz,
        words: n,
    })
}

/// `mre upload --port PORT MODEL [--rate-hz R]`.
pub fn run_upload(port: &Path, model: &Path, rate_hz: Option<u32>) -> Result<Uploaded> {
    let (table, cfg) = upload_payload(model, rate_hz.unwrap_or(DEFAULT_RATE_HZ))?;
    let mut link = PilLink::serial(port, HELLO_TIMEOUT)
        .context("is the board powered and running the firmware, and is PORT its ST-LINK VCP?")?;
    upload_over(&mut link, &table, &cfg)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn an_out_of_limit_value_is_named_in_a_sentence() {
        let mut cfg = ControlConfig::at_rate(DEFAULT_RATE_HZ).unwrap();
        check_board_limits(&cfg).unwrap();
        cfg.law.failsafe_current_a = 0.0;
        let msg = check_board_limits(&cfg).unwrap_err().to_string();
        assert!(
            msg.starts_with("failsafe_current_a = 0 is outside the board's limits 1 to 2 ("),
            "{msg}"
        );
        assert!(msg.ends_with("; nothing was sent"), "{msg}");
    }

    #[test]
    fn a_model_file_s_installation_is_what_is_sent() {
        let dir = tempfile::tempdir().unwrap();
        let base = std::fs::read_to_string(crate::pil::qemu::workspace_root().join("models/drop-none.toml")).unwrap();
        let with = dir.path().join("lab.toml");
        std::fs::write(
            &with,
            format!("{base}\n[installation]\nmass_kg = 3.0\nusable_stroke_mm = 9.0\n"),
        )
        .unwrap();
        let (_, cfg) = upload_payload(&with, DEFAULT_RATE_HZ).unwrap();
        assert_eq!((cfg.law.mass_kg, cfg.law.stroke_max_mm), (3.0, 9.0));
        check_board_limits(&cfg).unwrap();
        // Without the section: the image's defaults, the installation's.
        let (_, cfg) = upload_payload(
            &crate::pil::qemu::workspace_root().join("models/drop-none.toml"),
            DEFAULT_RATE_HZ,
        )
        .unwrap();
        assert_eq!(cfg, ControlConfig::at_rate(DEFAULT_RATE_HZ).unwrap());
        // A stroke past the displacement sensor is named before anything is sent.
        let bad = dir.path().join("bad.toml");
        std::fs::write(&bad, format!("{base}\n[installation]\nusable_stroke_mm = 30.0\n")).unwrap();
        let msg = format!("{:#}", upload_payload(&bad, DEFAULT_RATE_HZ).unwrap_err());
        assert!(
            msg.contains("[installation] usable_stroke_mm = 30 is outside the board's limits 1 to 25"),
            "{msg}"
        );
        // The table carries the installation (format 3) under its CRC.
        let (table, _) = upload_payload(&with, DEFAULT_RATE_HZ).unwrap();
        assert_eq!(table.version(), 3);
        assert_eq!(
            (table.installation().mass_kg, table.installation().usable_stroke_mm),
            (3.0, 9.0)
        );
    }

    #[test]
    fn the_board_s_reasons_read_as_sentences() {
        use mre_protocol::upload::{answer, CommitAnswer, UploadError};
        let code = |r| mre_protocol::frame::CommandFrame::decode(&answer(&r)).unwrap().rejected;
        assert!(refusal(code(Err(UploadError::NotAtRest))).contains("not at rest"));
        let limit = mre_algorithm::limits::Limit::XValidMax;
        let r = Err(UploadError::Refused(mre_protocol::frame::ConfigBlobError::OutOfLimits(
            limit,
        )));
        assert_eq!(CommitAnswer::from_code(code(r)), Some(CommitAnswer::OutOfLimits(limit)));
        assert!(refusal(code(r))
            .starts_with("the board refused the upload: x_valid_max_mm is outside its limits 1 to 27.5"));
    }
}
