//! Table upload (host side of the firmware's receiver, `mre_protocol::upload`):
//! the bytes `mre upload` sends, through the receiver the boards and the PIL
//! image run, onto a RAM page with flash semantics, then the boot decision.
//! The transfer over a serial port is tested in QEMU
//! (`host-tools/src/pil/tests.rs`, `upload_over_qemu_serial_*`); QEMU has no
//! flash controller, so the page logic is tested here, behind `TablePage`.
use mre_algorithm::control::{ControlConfig, DEFAULT_RATE_HZ};
use mre_algorithm::generated_table::GENERATED_TABLE;
use mre_algorithm::table::{Table, PAPER_TABLE4_ENTRIES};
use mre_algorithm::Flags;
use mre_protocol::flash_table::{PageError, RamPage, TablePage};
use mre_protocol::frame::{config_frames, encode_config, CommandFrame, ConfigBlobError, CONFIG_MAX_WORDS, FRAME_LEN};
use mre_protocol::upload::{answer, choose_boot_table, PortEvent, TableSource, UploadError, UploadPort};

/// Not the built-in table: Table 4 with a doubled stroke.
fn other_table() -> Table {
    let mut entries = PAPER_TABLE4_ENTRIES;
    for e in &mut entries {
        e.x_max_mm *= 2.0;
    }
    Table::new(&entries).unwrap()
}

fn blob(table: &Table, cfg: &ControlConfig) -> Vec<u32> {
    let mut words = [0u32; CONFIG_MAX_WORDS];
    let n = encode_config(table, cfg, &mut words);
    words[..n].to_vec()
}

fn frames(words: &[u32]) -> Vec<[u8; FRAME_LEN]> {
    config_frames(words).collect()
}

/// Feeds the bytes; returns every commit's answer frame.
fn send(port: &mut UploadPort, page: &mut RamPage, frames: &[[u8; FRAME_LEN]]) -> Vec<CommandFrame> {
    let mut answers = Vec::new();
    for b in frames.iter().flatten() {
        if let Some(event) = port.push(*b, page, true) {
            answers.push(CommandFrame::decode(&event.answer()).unwrap());
        }
    }
    answers
}

fn built_in_crc() -> u32 {
    Table::from_image(&GENERATED_TABLE).unwrap().crc32()
}

#[test]
fn a_valid_upload_is_stored_acknowledged_and_flown_at_boot() {
    let table = other_table();
    let cfg = ControlConfig::at_rate(DEFAULT_RATE_HZ).unwrap();
    assert_ne!(
        table.crc32(),
        built_in_crc(),
        "the test needs a table other than the built-in one"
    );
    let (mut port, mut page) = (UploadPort::new(), RamPage::erased());
    // Line noise before the upload is skipped by the sync hunt.
    let mut noise = vec![[0u8; FRAME_LEN]];
    noise[0][..4].copy_from_slice(&[0x00, 0xA5, 0x13, 0xFF]);
    let mut all = noise;
    all.extend(frames(&blob(&table, &cfg)));
    let answers = send(&mut port, &mut page, &all);
    assert_eq!(answers.len(), 1);
    assert_eq!(answers[0].seq, 0, "the answer is a hello frame");
    assert_eq!(answers[0].flags, Flags::NONE);

    let boot = choose_boot_table(&mut page, &GENERATED_TABLE, DEFAULT_RATE_HZ);
    assert_eq!(boot.source, TableSource::Uploaded);
    let flown = boot.table.unwrap();
    assert_eq!(flown.crc32(), table.crc32());
    assert_eq!(flown.entries(), table.entries());
    assert_eq!(boot.config.unwrap(), cfg);
}

#[test]
fn a_corrupt_upload_is_rejected_and_the_built_in_table_is_kept() {
    let table = other_table();
    let cfg = ControlConfig::at_rate(DEFAULT_RATE_HZ).unwrap();
    let mut fr = frames(&blob(&table, &cfg));
    // One bit flipped in a coefficient of the third frame: its CRC fails,
    // the frame is dropped, and the commit finds a word missing.
    fr[2][10] ^= 0x10;
    let (mut port, mut page) = (UploadPort::new(), RamPage::erased());
    let answers = send(&mut port, &mut page, &fr);
    assert_eq!(answers.len(), 1);
    assert_eq!(answers[0].flags, Flags::TABLE_FAULT);
    assert_eq!(port.rejected_frames(), 1);
    assert!(
        page.bytes.iter().all(|&b| b == 0xFF),
        "a refused upload never touches the page"
    );

    let boot = choose_boot_table(&mut page, &GENERATED_TABLE, DEFAULT_RATE_HZ);
    assert_eq!(boot.source, TableSource::BuiltIn(PageError::Empty));
    assert_eq!(boot.table.unwrap().crc32(), built_in_crc());
}

#[test]
fn a_refused_upload_keeps_the_earlier_upload() {
    let cfg = ControlConfig::at_rate(DEFAULT_RATE_HZ).unwrap();
    let first = other_table();
    let (mut port, mut page) = (UploadPort::new(), RamPage::erased());
    assert_eq!(
        send(&mut port, &mut page, &frames(&blob(&first, &cfg)))[0].flags,
        Flags::NONE
    );
    let stored = page.bytes;

    // Every frame intact (valid frame CRCs), but a coefficient of the table
    // replaced by 1e30: the table's own CRC and magnitude checks refuse it.
    let mut words = blob(&Table::paper().unwrap(), &cfg);
    words[5] = 1.0e30f32.to_bits();
    let mut port = UploadPort::new();
    let answers = send(&mut port, &mut page, &frames(&words));
    assert_eq!(answers[0].flags, Flags::TABLE_FAULT);
    assert_eq!(port.rejected_frames(), 0);
    assert_eq!(page.bytes, stored);
    let boot = choose_boot_table(&mut page, &GENERATED_TABLE, DEFAULT_RATE_HZ);
    assert_eq!(boot.source, TableSource::Uploaded);
    assert_eq!(boot.table.unwrap().crc32(), first.crc32());
}

#[test]
fn the_receiver_reports_why_a_commit_failed() {
    let cfg = ControlConfig::at_rate(DEFAULT_RATE_HZ).unwrap();
    let words = blob(&other_table(), &cfg);
    // The commit arrives without its last chunk.
    let mut fr = frames(&words);
    fr.remove(fr.len() - 2);
    let (mut port, mut page) = (UploadPort::new(), RamPage::erased());
    let mut results = Vec::new();
    for b in fr.iter().flatten() {
        if let Some(PortEvent::Commit(r)) = port.push(*b, &mut page, true) {
            results.push(r);
        }
    }
    assert_eq!(
        results.as_slice(),
        &[Err(UploadError::Refused(ConfigBlobError::Incomplete))]
    );
}

/// A page that accepts the erase but fails every write (a worn or locked page).
struct FailingPage(RamPage);
impl TablePage for FailingPage {
    fn read(&mut self, offset: usize, buf: &mut [u8]) -> Result<(), mre_protocol::flash_table::FlashError> {
        self.0.read(offset, buf)
    }
    fn erase(&mut self) -> Result<(), mre_protocol::flash_table::FlashError> {
        self.0.erase()
    }
    fn write(&mut self, _: usize, _: &[u8]) -> Result<(), mre_protocol::flash_table::FlashError> {
        Err(mre_protocol::flash_table::FlashError)
    }
}

#[test]
fn a_flash_write_failure_is_not_acknowledged_and_boot_falls_back() {
    let cfg = ControlConfig::at_rate(DEFAULT_RATE_HZ).unwrap();
    let mut page = FailingPage(RamPage::erased());
    let mut port = UploadPort::new();
    let mut results = Vec::new();
    for b in frames(&blob(&other_table(), &cfg)).iter().flatten() {
        if let Some(PortEvent::Commit(r)) = port.push(*b, &mut page, true) {
            results.push(r);
        }
    }
    assert_eq!(results.len(), 1);
    assert!(matches!(results[0], Err(UploadError::Page(PageError::Flash(_)))));
    assert_eq!(
        CommandFrame::decode(&answer(&results[0])).unwrap().flags,
        Flags::TABLE_FAULT
    );
    let boot = choose_boot_table(&mut page, &GENERATED_TABLE, DEFAULT_RATE_HZ);
    assert_eq!(boot.source, TableSource::BuiltIn(PageError::Empty));
    assert_eq!(boot.table.unwrap().crc32(), built_in_crc());
}

#[test]
fn an_upload_for_another_rate_keeps_its_table_and_the_image_rate() {
    let table = other_table();
    let cfg_20k = ControlConfig::at_rate(20_000).unwrap();
    let (mut port, mut page) = (UploadPort::new(), RamPage::erased());
    assert_eq!(
        send(&mut port, &mut page, &frames(&blob(&table, &cfg_20k)))[0].flags,
        Flags::NONE
    );
    let boot = choose_boot_table(&mut page, &GENERATED_TABLE, DEFAULT_RATE_HZ);
    assert_eq!(boot.source, TableSource::Uploaded);
    assert_eq!(boot.uploaded_rate_ignored_hz, Some(20_000));
    assert_eq!(boot.table.unwrap().crc32(), table.crc32());
    assert_eq!(boot.config.unwrap().rate_hz, DEFAULT_RATE_HZ);
}

#[test]
fn a_torn_page_falls_back_to_the_built_in_table() {
    let cfg = ControlConfig::at_rate(DEFAULT_RATE_HZ).unwrap();
    let (mut port, mut page) = (UploadPort::new(), RamPage::erased());
    send(&mut port, &mut page, &frames(&blob(&other_table(), &cfg)));
    page.bytes[64] ^= 0x01;
    let boot = choose_boot_table(&mut page, &GENERATED_TABLE, DEFAULT_RATE_HZ);
    assert_eq!(boot.source, TableSource::BuiltIn(PageError::Corrupt));
    assert_eq!(boot.table.unwrap().crc32(), built_in_crc());
}

#[test]
fn a_ping_is_answered_with_a_hello_and_never_stored() {
    use mre_protocol::frame::{SampleFrame, PING_SEQ};
    let ping = SampleFrame::ping();
    // The protocol's ping: a sample frame with sequence 0.
    assert_eq!((ping.seq, PING_SEQ), (0, 0));
    let (mut port, mut page) = (UploadPort::new(), RamPage::erased());
    // Twice: pings are not sequenced, so a repeat is not a duplicate.
    let answers = send(&mut port, &mut page, &[ping.encode(), ping.encode()]);
    assert_eq!(answers.len(), 2);
    assert!(answers.iter().all(|a| a.seq == 0 && a.flags == Flags::NONE));
    assert!(page.bytes.iter().all(|&b| b == 0xFF));
}

/// A lab's installation within the board's limits: a 3 kg striker, 9 mm of
/// stroke, a 1.5 A coil.
const LAB: mre_algorithm::installation::Installation = mre_algorithm::installation::Installation {
    mass_kg: 3.0,
    usable_stroke_mm: 9.0,
    coil_rating_a: 1.5,
    ..mre_algorithm::installation::DEFAULT_INSTALLATION
};

/// The configuration `mre upload` sends with a table carrying `LAB`.
fn lab_config() -> ControlConfig {
    let mut cfg = ControlConfig::at_rate(DEFAULT_RATE_HZ).unwrap();
    LAB.apply(&mut cfg);
    cfg
}

/// The largest table the format holds: `MAX_CURRENTS` entries, format 3 with
/// every term (a viscous coefficient on each entry) and an installation, so
/// the blob is `CONFIG_MAX_WORDS` long and its last words lie past bit 127.
fn largest_table() -> Table {
    use mre_algorithm::table::{CurrentEntry, ModelTerms, Quartic, FORMAT_VERSION, MAX_CURRENTS};
    let entries: Vec<CurrentEntry> = (0..MAX_CURRENTS)
        .map(|k| CurrentEntry {
            current_a: 0.25 * k as f32,
            compression: Quartic::new([0.0, 0.0, 0.5, 100.0 + 200.0 * k as f32, 0.0]),
            extension: Quartic::new([0.0, 0.0, 0.1, 30.0 + 60.0 * k as f32, 0.0]),
            x_min_mm: -0.01,
            x_max_mm: 12.0,
        })
        .collect();
    let mut terms = ModelTerms::EVERY_TERM;
    for (k, c) in terms.viscous_n_s_per_m.iter_mut().enumerate() {
        *c = 5.0 * (k + 1) as f32;
    }
    let table = Table::with_installation(&entries, terms, LAB).unwrap();
    assert_eq!(table.version(), FORMAT_VERSION);
    table
}

#[test]
fn the_largest_table_with_every_term_uploads_and_flies_at_boot() {
    let table = largest_table();
    let cfg = lab_config();
    let words = blob(&table, &cfg);
    // 2 header + 13 per entry + 3 terms + 1 viscous per entry + 9
    // installation values + 13 law + 7 control.
    assert_eq!(words.len(), 2 + 8 * 13 + 3 + 8 + 9 + 13 + 7);
    assert_eq!(words.len(), CONFIG_MAX_WORDS);
    let (mut port, mut page) = (UploadPort::new(), RamPage::erased());
    let answers = send(&mut port, &mut page, &frames(&words));
    assert_eq!(answers.len(), 1);
    assert_eq!(answers[0].flags, Flags::NONE);
    let boot = choose_boot_table(&mut page, &GENERATED_TABLE, DEFAULT_RATE_HZ);
    assert_eq!(boot.source, TableSource::Uploaded);
    let flown = boot.table.unwrap();
    assert_eq!(flown.entries(), table.entries());
    assert_eq!(flown.terms(), table.terms());
    assert_eq!(flown.installation(), &LAB);
    let flown_cfg = boot.config.unwrap();
    assert_eq!(flown_cfg, cfg);
    assert_eq!(
        (
            flown_cfg.law.mass_kg,
            flown_cfg.law.stroke_max_mm,
            flown_cfg.law.current_max_a
        ),
        (3.0, 9.0, 1.5)
    );
    // Booted at another rate, the page keeps its table and its installation.
    let other_rate = choose_boot_table(&mut page, &GENERATED_TABLE, DEFAULT_RATE_HZ / 2);
    assert_eq!(other_rate.uploaded_rate_ignored_hz, Some(DEFAULT_RATE_HZ));
    assert_eq!(other_rate.config.unwrap().law.mass_kg, 3.0);
}

#[test]
fn a_word_missing_past_bit_127_is_noticed() {
    let words = blob(&largest_table(), &lab_config());
    // The frame that carries words 129..132 is lost: the commit must see the gap.
    let mut fr = frames(&words);
    fr.remove(129 / 3);
    let (mut port, mut page) = (UploadPort::new(), RamPage::erased());
    let mut results = Vec::new();
    for b in fr.iter().flatten() {
        if let Some(PortEvent::Commit(r)) = port.push(*b, &mut page, true) {
            results.push(r);
        }
    }
    assert_eq!(
        results.as_slice(),
        &[Err(UploadError::Refused(ConfigBlobError::Incomplete))]
    );
    assert!(page.bytes.iter().all(|&b| b == 0xFF));
}

/// What the board answers to a commit it did not store while the damper moves.
#[test]
fn an_upload_in_motion_is_refused_untouched_and_accepted_at_rest() {
    use mre_protocol::upload::CommitAnswer;
    let table = other_table();
    let cfg = ControlConfig::at_rate(DEFAULT_RATE_HZ).unwrap();
    let fr = frames(&blob(&table, &cfg));
    let (mut port, mut page) = (UploadPort::new(), RamPage::erased());
    let mut events = Vec::new();
    for b in fr.iter().flatten() {
        events.extend(port.push(*b, &mut page, false));
    }
    assert_eq!(events, [PortEvent::Commit(Err(UploadError::NotAtRest))]);
    let answer = CommandFrame::decode(&events[0].answer()).unwrap();
    assert_eq!(answer.flags, Flags::TABLE_FAULT);
    assert_eq!(CommitAnswer::from_code(answer.rejected), Some(CommitAnswer::NotAtRest));
    assert!(
        page.bytes.iter().all(|&b| b == 0xFF),
        "an upload in motion never touches the page"
    );

    // The same bytes once the damper is at rest: stored.
    let answers: Vec<_> = fr
        .iter()
        .flatten()
        .filter_map(|b| port.push(*b, &mut page, true))
        .map(|e| CommandFrame::decode(&e.answer()).unwrap())
        .collect();
    assert_eq!(answers.len(), 1);
    assert_eq!(answers[0].flags, Flags::NONE);
    assert_eq!(CommitAnswer::from_code(answers[0].rejected), Some(CommitAnswer::Stored));
    assert_eq!(
        choose_boot_table(&mut page, &GENERATED_TABLE, DEFAULT_RATE_HZ).source,
        TableSource::Uploaded
    );
}

#[test]
fn every_commit_answer_reads_back_as_itself() {
    use mre_algorithm::limits::Limit;
    use mre_protocol::upload::CommitAnswer;
    let mut all = vec![
        CommitAnswer::Stored,
        CommitAnswer::Incomplete,
        CommitAnswer::Invalid,
        CommitAnswer::NotAtRest,
        CommitAnswer::PageFailed,
    ];
    all.extend(Limit::ALL.iter().map(|l| CommitAnswer::OutOfLimits(*l)));
    let mut codes: Vec<u16> = all.iter().map(|a| a.code()).collect();
    for (a, code) in all.iter().zip(&codes) {
        assert_eq!(CommitAnswer::from_code(*code), Some(*a));
    }
    codes.sort_unstable();
    codes.dedup();
    assert_eq!(codes.len(), all.len(), "codes are distinct");
    assert_eq!(CommitAnswer::from_code(0xFFFF), None);
}

/// The gate the control loop keeps: an impact, then rest. Stored only after
/// 0.5 s (5000 periods at 10 kHz) armed, idle and still.
#[test]
fn the_upload_gate_opens_only_after_half_a_second_at_rest() {
    use mre_algorithm::control::Controller;
    use mre_protocol::upload::UploadGate;
    let cfg = ControlConfig::at_rate(DEFAULT_RATE_HZ).unwrap();
    let mut ctl = Controller::new(cfg, Table::from_image(&GENERATED_TABLE)).unwrap();
    let mut gate = UploadGate::new();
    let step = |ctl: &mut Controller, gate: &mut UploadGate, x_mm: f32, v_m_s: f32| {
        let cmd = ctl.step_sample(x_mm, Some(v_m_s));
        gate.observe(ctl, &cmd);
    };
    // At rest for a while: the gate opens at 5000 periods, not before.
    for k in 1..=5000 {
        step(&mut ctl, &mut gate, 0.0, 0.0);
        assert_eq!(gate.at_rest(DEFAULT_RATE_HZ), k >= 5000, "period {k}");
    }
    // An impact: 2 m/s into the damper, 5 mm deep. The gate shuts at once.
    step(&mut ctl, &mut gate, 0.2, 2.0);
    assert!(!gate.at_rest(DEFAULT_RATE_HZ));
    assert_eq!(gate.still_periods(), 0);
    for k in 0..40 {
        step(&mut ctl, &mut gate, 0.2 + 0.12 * k as f32, 2.0 - 0.05 * k as f32);
        assert!(!gate.at_rest(DEFAULT_RATE_HZ));
    }
    // Back at 0 mm but still moving (a rebound): not still.
    step(&mut ctl, &mut gate, 0.0, -0.5);
    assert_eq!(gate.still_periods(), 0);
    // Still again: closed until another 0.5 s has passed.
    for _ in 0..4000 {
        step(&mut ctl, &mut gate, 0.0, 0.0);
    }
    assert!(!gate.at_rest(DEFAULT_RATE_HZ));
    // A latched fault keeps it closed however still the damper is.
    ctl.latch_fault(Flags::OVER_CURRENT);
    for _ in 0..6000 {
        step(&mut ctl, &mut gate, 0.0, 0.0);
    }
    assert!(!gate.at_rest(DEFAULT_RATE_HZ));
}

/// A page whose driver reports success for an erase or a program that did
/// not happen: embassy-stm32 0.6's L4 flash interrupt clears the error flags
/// (FLASH_SR, write 1 to clear) before `wait_ready` reads them, so an erase
/// or program error comes back `Ok` (firmware/README.md, "Uploaded tables").
struct SilentlyFailingPage {
    page: RamPage,
    erase_fails: bool,
    program_fails: bool,
}
impl TablePage for SilentlyFailingPage {
    fn read(&mut self, offset: usize, buf: &mut [u8]) -> Result<(), mre_protocol::flash_table::FlashError> {
        self.page.read(offset, buf)
    }
    fn erase(&mut self) -> Result<(), mre_protocol::flash_table::FlashError> {
        if !self.erase_fails {
            self.page.erase()?;
        }
        Ok(())
    }
    fn write(&mut self, offset: usize, data: &[u8]) -> Result<(), mre_protocol::flash_table::FlashError> {
        if !self.program_fails {
            self.page.write(offset, data)?;
        }
        Ok(())
    }
}

/// Issue 39: an erase error reported as success leaves the old (valid)
/// table; a program error leaves the page erased. Either way the host must
/// be told "not stored" (TABLE_FAULT, page failed), and boot flies what is
/// really on the page. Planted: `store` without its byte-for-byte read-back
/// answers the erase case "stored" (the old page is valid).
#[test]
fn an_erase_or_program_error_reported_as_success_is_refused() {
    let cfg = ControlConfig::at_rate(DEFAULT_RATE_HZ).unwrap();
    // An earlier upload of Table 4 is on the page.
    let mut old = RamPage::erased();
    mre_protocol::flash_table::store(&mut old, &Table::paper().unwrap(), &cfg).unwrap();
    let paper_crc = Table::paper().unwrap().crc32();
    for (erase_fails, program_fails) in [(true, false), (false, true), (true, true)] {
        let mut page = SilentlyFailingPage {
            page: old.clone(),
            erase_fails,
            program_fails,
        };
        let mut port = UploadPort::new();
        let mut results = Vec::new();
        for b in frames(&blob(&other_table(), &cfg)).iter().flatten() {
            if let Some(PortEvent::Commit(r)) = port.push(*b, &mut page, true) {
                results.push(r);
            }
        }
        assert_eq!(results.len(), 1);
        assert_eq!(
            results[0],
            Err(UploadError::Page(PageError::NotAsWritten)),
            "erase fails {erase_fails}, program fails {program_fails}"
        );
        let answer = CommandFrame::decode(&answer(&results[0])).unwrap();
        assert_eq!(answer.flags, Flags::TABLE_FAULT);
        // Code 4: the flash page could not be written or read back.
        assert_eq!(answer.rejected, 4);
        // Boot flies what the page really holds, never the refused upload.
        let boot = choose_boot_table(&mut page.page, &GENERATED_TABLE, DEFAULT_RATE_HZ);
        let flown = boot.table.unwrap().crc32();
        assert_ne!(flown, other_table().crc32());
        match (erase_fails, program_fails) {
            // The new bytes ANDed over the old page (NOR flash clears bits
            // only): the CRC no longer holds, the built-in table flies.
            (true, false) => assert_eq!(boot.source, TableSource::BuiltIn(PageError::Corrupt)),
            // Erased, nothing programmed.
            (false, true) => assert_eq!(boot.source, TableSource::BuiltIn(PageError::Empty)),
            // Nothing happened: the old upload still flies.
            _ => {
                assert_eq!(boot.source, TableSource::Uploaded);
                assert_eq!(flown, paper_crc);
            }
        }
    }
}
