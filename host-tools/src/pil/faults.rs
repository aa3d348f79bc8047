//! `mre pil --faults SPEC`: the controlled drop through the firmware in QEMU
//! with faults injected on the link and in the sensors, and a report of how
//! many were injected, detected and survived.
//!
//! - `corrupt:R`: a sample frame arrives with one bit flipped (outside the
//!   sync bytes), then intact, as the host's retry. Detected when the
//!   firmware's rejected-frame count in its answer goes up.
//! - `drop:R`: a sample frame is lost; the host's answer timeout notices and
//!   it sends the frame again. Detected when the firmware sent no answer.
//! - `duplicate:R`: a sample frame arrives twice. Detected when the firmware
//!   answers the repeat with its previous answer, byte for byte, without a
//!   second control step.
//! - `sensors`: mid-impact, one NaN displacement, one out-of-range
//!   displacement, then the displacement stuck while the velocity sensor
//!   reports motion. Detected by `NON_FINITE_INPUT`, `SENSOR_RANGE` and
//!   `SENSOR_STUCK` with the fail-safe current commanded.
//! - `upload`: a table upload with one corrupted coefficient word (valid
//!   frames, wrong table CRC) before the real one. Detected by the firmware
//!   answering `TABLE_FAULT`; the real upload must then be accepted.
//! - `sense-stuck`: a drop of its own whose sample frames carry a coil
//!   current stuck at 0 A (an open shunt amplifier). A stuck-at-0 channel
//!   shows only while current flows, and the default drop's law peaks at
//!   0.8 A for a few periods; so this drop flies the rebound policy
//!   `Fixed` at `STUCK_HOLD_A`, which drives the coil from the rebound on.
//!   Detected by `CURRENT_SENSE` with the fail-safe current held.
//! - `sense-stale`: a drop of its own whose frames carry the coil current
//!   (the last command: what a healthy shunt reads) until period
//!   `STALE_FROM`, then none (no new conversion: the firmware's PIL board
//!   reports a stale channel). Detected by `CURRENT_SENSE` within
//!   `overcurrent::STALE_PERIODS` periods, with the fail-safe held.
//! - `all:R` is all of the above, with rate R for the frame faults.
//!
//! Survived means: the firmware kept answering every period with the right
//! sequence, its commands equal those of the same `Controller` run in
//! process on the same (faulty) sensor readings, bit for bit, it holds the
//! fail-safe current once a fault latched (the documented safe state), and it
//! ended the run with exit status 0 (no hang, no panic).
use super::link::PilLink;
use super::qemu::{qemu_binary, Qemu, INSTALL_HINT};
use super::sim::{control_config, PilRequest};
use crate::plant::closed_loop::setup_for;
use crate::plant::stepper::{simulate, CurrentSource};
use anyhow::{anyhow, bail, ensure, Context, Result};
use mre_algorithm::control::{ControlConfig, Controller};
use mre_algorithm::Flags;
use mre_protocol::frame::{encode_config, CommandFrame, SampleFrame, CONFIG_MAX_WORDS, FRAME_LEN};
use rand::{Rng, SeedableRng};
use serde::Serialize;
use std::cell::RefCell;
use std::time::Duration;

/// A lost frame is noticed after this much wall time without an answer
/// (QEMU answers within a millisecond).
const RETRY_TIMEOUT: Duration = Duration::from_millis(300);
/// A duplicate's repeat is always answered, so its answer is awaited this long
/// (a loaded machine can delay QEMU well past `RETRY_TIMEOUT`).
const EXPECTED_ANSWER_TIMEOUT: Duration = Duration::from_secs(10);
const MAX_RETRIES: usize = 5;
/// Sensor faults, by control period (sequence number) into the impact.
const NAN_AT: u32 = 20;
const RANGE_AT: u32 = 30;
const STUCK_FROM: u32 = 40;
/// The sense channel's last conversion arrives in the period before this one.
const STALE_FROM: u32 = 20;
/// The rebound current the stuck-sense drop flies: above
/// `overcurrent::STUCK_DRIVEN_A`, so a healthy shunt would read it.
const STUCK_HOLD_A: f32 = 1.5;

/// What to inject.
#[derive(Clone, Debug, PartialEq)]
pub struct FaultPlan {
    pub corrupt_rate: f64,
    pub drop_rate: f64,
    pub duplicate_rate: f64,
    pub sensors: bool,
    pub upload: bool,
    pub sense_stuck: bool,
    pub sense_stale: bool,
    pub seed: u64,
}

impl FaultPlan {
    /// Parses `corrupt:1e-2,drop:1e-3,duplicate:1e-2,sensors,upload` or `all:1e-2`.
    pub fn parse(spec: &str, seed: u64) -> Result<Self> {
        let mut plan = FaultPlan {
            corrupt_rate: 0.0,
            drop_rate: 0.0,
            duplicate_rate: 0.0,
            sensors: false,
            upload: false,
            sense_stuck: false,
            sense_stale: false,
            seed,
        };
        for item in spec.split(',').map(str::trim).filter(|s| !s.is_empty()) {
            let (name, rate) = match item.split_once(':') {
                Some((n, r)) => {
                    let rate: f64 = r
                        .parse()
                        .with_context(|| format!("--faults {item}: `{r}` is not a rate"))?;
                    ensure!(
                        (0.0..=1.0).contains(&rate),
                        "--faults {item}: a rate is between 0 and 1"
                    );
                    (n, Some(rate))
                }
                None => (item, None),
            };
            match (name, rate) {
                ("corrupt", Some(r)) => plan.corrupt_rate = r,
                ("drop", Some(r)) => plan.drop_rate = r,
                ("duplicate", Some(r)) => plan.duplicate_rate = r,
                ("sensors", None) => plan.sensors = true,
                ("upload", None) => plan.upload = true,
                ("sense-stuck", None) => plan.sense_stuck = true,
                ("sense-stale", None) => plan.sense_stale = true,
                ("all", Some(r)) => {
                    (plan.corrupt_rate, plan.drop_rate, plan.duplicate_rate) = (r, r, r);
                    (plan.sensors, plan.upload, plan.sense_stuck, plan.sense_stale) = (true, true, true, true);
                }
                _ => bail!(
                    "--faults: unknown item `{item}` (corrupt:R, drop:R, duplicate:R, sensors, upload, sense-stuck, sense-stale, all:R)"
                ),
            }
        }
        Ok(plan)
    }
}

/// Counts for one kind of fault.
#[derive(Clone, Debug, Default, Serialize, PartialEq)]
pub struct FaultCount {
    pub kind: String,
    pub injected: u32,
    pub detected: u32,
    pub survived: u32,
}

#[derive(Clone, Debug, Serialize, PartialEq)]
pub struct FaultReport {
    pub faults: Vec<FaultCount>,
    pub periods: usize,
    /// The firmware's commands equal the in-process `Controller`'s on the same readings.
    pub commands_identical_to_reference: bool,
    pub first_difference: Option<String>,
    /// Once a fault latched, every later command was the fail-safe current.
    pub failsafe_held_after_latch: bool,
    pub failsafe_current_a: f32,
    pub final_command_a: f32,
    pub final_flags: String,
    pub firmware_exit: String,
}

impl FaultReport {
    /// Every injected fault detected and survived, and the run ended cleanly.
    pub fn all_detected_and_survived(&self) -> bool {
        self.faults
            .iter()
            .all(|f| f.detected == f.injected && f.survived == f.injected)
            && self.commands_identical_to_reference
            && self.failsafe_held_after_latch
            && self.firmware_exit == "exit status: 0"
    }

    pub fn markdown(&self) -> String {
        let mut s = String::from("| fault | injected | detected | survived |\n|---|---|---|---|\n");
        for f in &self.faults {
            s.push_str(&format!(
                "| {} | {} | {} | {} |\n",
                f.kind, f.injected, f.detected, f.survived
            ));
        }
        s.push_str(&format!(
            "\n{} control periods; commands identical to the in-process controller: {}; fail-safe ({} A) held \
             after a latched fault: {}; last command {} A, flags {}; firmware {}.\n",
            self.periods,
            self.commands_identical_to_reference,
            self.failsafe_current_a,
            self.failsafe_held_after_latch,
            self.final_command_a,
            self.final_flags,
            self.firmware_exit
        ));
        if let Some(d) = &self.first_difference {
            s.push_str(&format!("\nFirst difference: {d}\n"));
        }
        s
    }
}

/// The sensor readings the controller sees, with the planned sensor faults:
/// the same function feeds the firmware and the in-process reference.
struct Sensors {
    enabled: bool,
    x_valid_max_mm: f32,
    stuck_x_mm: Option<f32>,
}

impl Sensors {
    fn read(&mut self, seq: u32, x_mm: f32) -> f32 {
        if !self.enabled {
            return x_mm;
        }
        match seq {
            NAN_AT => f32::NAN,
            RANGE_AT => self.x_valid_max_mm + 10.0,
            s if s >= STUCK_FROM => *self.stuck_x_mm.get_or_insert(x_mm),
            _ => x_mm,
        }
    }
}

/// One frame fault drawn per period, independently per kind.
#[derive(Clone, Copy, Debug, PartialEq)]
enum FrameFault {
    Corrupt { bit: usize },
    Drop,
    Duplicate,
}

fn draw_frame_faults(plan: &FaultPlan, rng: &mut rand_chacha::ChaCha8Rng) -> Vec<FrameFault> {
    let mut faults = Vec::new();
    // Outside the two sync bytes, so the frame is recognised and its CRC fails.
    let bit = rng.random_range(16..FRAME_LEN * 8);
    if rng.random::<f64>() < plan.corrupt_rate {
        faults.push(FrameFault::Corrupt { bit });
    }
    if rng.random::<f64>() < plan.drop_rate {
        faults.push(FrameFault::Drop);
    }
    if rng.random::<f64>() < plan.duplicate_rate {
        faults.push(FrameFault::Duplicate);
    }
    faults
}

#[derive(Default)]
struct Tally {
    corrupt: FaultCount,
    drop: FaultCount,
    duplicate: FaultCount,
    last_rejected: u16,
}

/// Reads answers until one for `seq` arrives; `None` on a timeout.
///
/// An answer to an earlier sequence is skipped: it answers a retry whose
/// first answer was already taken (a slow host or emulator makes the retry
/// timer fire before the answer lands, and the firmware answers both copies).
/// An answer to a later sequence is a protocol error.
fn answer_for(link: &mut PilLink, seq: u32) -> Result<Option<CommandFrame>> {
    loop {
        match link.read_command() {
            Ok(cmd) if cmd.seq == seq => return Ok(Some(cmd)),
            Ok(cmd) if cmd.seq < seq => continue,
            Ok(cmd) => bail!("answer to sequence {} arrived for sample {seq}", cmd.seq),
            Err(e) => match e.downcast_ref::<std::io::Error>() {
                Some(io) if matches!(io.kind(), std::io::ErrorKind::WouldBlock | std::io::ErrorKind::TimedOut) => {
                    return Ok(None)
                }
                _ => return Err(e),
            },
        }
    }
}

/// One period through the faulty link: inject, then retry until answered.
fn exchange(link: &mut PilLink, frame: &SampleFrame, faults: &[FrameFault], tally: &mut Tally) -> Result<CommandFrame> {
    let bytes = frame.encode();
    let mut dropped = false;
    for fault in faults {
        match *fault {
            FrameFault::Corrupt { bit } => {
                let mut bad = bytes;
                bad[bit / 8] ^= 1 << (bit % 8);
                link.send_raw(&bad)?;
                tally.corrupt.injected += 1;
            }
            FrameFault::Drop => {
                tally.drop.injected += 1;
                dropped = true;
            }
            FrameFault::Duplicate => {}
        }
    }
    if dropped {
        // Lost on the wire: the firmware must stay silent until the retry.
        if answer_for(link, frame.seq)?.is_none() {
            tally.drop.detected += 1;
        }
    }
    let mut answer = None;
    for _ in 0..MAX_RETRIES {
        link.send_raw(&bytes)?;
        if let Some(cmd) = answer_for(link, frame.seq)? {
            answer = Some(cmd);
            break;
        }
    }
    let cmd = answer.ok_or_else(|| anyhow!("no answer to sample {} after {MAX_RETRIES} tries", frame.seq))?;
    if dropped {
        tally.drop.survived += 1;
    }
    let corrupted = faults
        .iter()
        .filter(|f| matches!(f, FrameFault::Corrupt { .. }))
        .count() as u32;
    if corrupted > 0 {
        let rise = u32::from(cmd.rejected.saturating_sub(tally.last_rejected));
        tally.corrupt.detected += rise.min(corrupted);
        // Answered, with the right sequence, after the corrupt copy.
        tally.corrupt.survived += corrupted;
    }
    tally.last_rejected = cmd.rejected;
    if faults.contains(&FrameFault::Duplicate) {
        tally.duplicate.injected += 1;
        link.send_raw(&bytes)?;
        link.set_answer_timeout(EXPECTED_ANSWER_TIMEOUT)?;
        let again = answer_for(link, frame.seq);
        link.set_answer_timeout(RETRY_TIMEOUT)?;
        if let Some(again) = again? {
            if again.encode() == cmd.encode() {
                tally.duplicate.detected += 1;
                tally.duplicate.survived += 1;
            }
        }
    }
    Ok(cmd)
}

/// The corrupt upload: the real blob with one coefficient word's bit flipped.
fn corrupt_upload(link: &mut PilLink, table: &mre_algorithm::table::Table, cfg: &ControlConfig) -> Result<FaultCount> {
    let mut words = [0u32; CONFIG_MAX_WORDS];
    let n = encode_config(table, cfg, &mut words);
    // Word 2 is the first table entry's current; flip a low mantissa bit of
    // its first compression coefficient (word 3).
    words[3] ^= 1;
    let answer = link.send_config_words(&words[..n])?;
    let detected = answer.flags.contains(Flags::TABLE_FAULT);
    let good = link.send_config_words(&words_of(table, cfg))?;
    Ok(FaultCount {
        kind: "corrupt table upload".into(),
        injected: 1,
        detected: u32::from(detected),
        survived: u32::from(!good.flags.contains(Flags::TABLE_FAULT)),
    })
}

fn words_of(table: &mre_algorithm::table::Table, cfg: &ControlConfig) -> Vec<u32> {
    let mut words = [0u32; CONFIG_MAX_WORDS];
    let n = encode_config(table, cfg, &mut words);
    words[..n].to_vec()
}

/// Runs the controlled drop through the firmware with `plan`'s faults, and
/// the same `Controller` in process on the same readings as the reference.
pub fn run_faults(request: &PilRequest, plan: &FaultPlan) -> Result<FaultReport> {
    let setup = setup_for(&request.sim)?;
    let table = crate::control_bench::diagnosed_table(&setup.plant, setup.impact.noise_seed)?;
    let cfg = control_config(&setup)?;
    let elf = match &request.elf {
        Some(p) => p.clone(),
        None => super::qemu::build_firmware()?,
    };
    let sensors = || Sensors {
        enabled: plan.sensors,
        x_valid_max_mm: cfg.law.x_valid_max_mm,
        stuck_x_mm: None,
    };

    // The reference: the firmware's control code in process, same readings.
    let mut reference: Vec<CommandFrame> = Vec::new();
    {
        let mut ctl = Controller::new(cfg, Ok(table)).map_err(|e| anyhow!("controller: {e:?}"))?;
        let mut s = sensors();
        let out = &mut reference;
        let controller = move |x_mm: f32, v_m_s: f32| {
            let seq = out.len() as u32 + 1;
            let cmd = ctl.step_sample(s.read(seq, x_mm), Some(v_m_s));
            ctl.end_period(false);
            out.push(super::in_process_frame(seq, &cmd));
            cmd.current_a
        };
        simulate(
            &setup.plant,
            &setup.impact,
            CurrentSource::Controller(Box::new(controller)),
        )?;
    }

    let qemu_bin = qemu_binary().ok_or_else(|| anyhow!("qemu-system-arm not found: {INSTALL_HINT}"))?;
    let (qemu, mut link): (Qemu, PilLink) = Qemu::start(&qemu_bin, &elf, None)?;
    let upload = if plan.upload {
        Some(corrupt_upload(&mut link, &table, &cfg)?)
    } else {
        link.upload_config(&table, &cfg)?;
        None
    };
    link.set_answer_timeout(RETRY_TIMEOUT)?;

    let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(plan.seed);
    let tally = RefCell::new(Tally::default());
    let answers = RefCell::new(Vec::<CommandFrame>::new());
    let error = RefCell::new(None);
    {
        let link = &mut link;
        let mut s = sensors();
        let failsafe_a = cfg.law.failsafe_current_a;
        let controller = |x_mm: f32, v_m_s: f32| {
            let seq = answers.borrow().len() as u32 + 1;
            let frame = SampleFrame {
                seq,
                x_mm: s.read(seq, x_mm),
                v_m_s: Some(v_m_s),
                force_n: None,
                coil_current_a: None,
            };
            let faults = draw_frame_faults(plan, &mut rng);
            match exchange(link, &frame, &faults, &mut tally.borrow_mut()) {
                Ok(cmd) => {
                    answers.borrow_mut().push(cmd);
                    cmd.current_a
                }
                Err(e) => {
                    error.borrow_mut().get_or_insert(e);
                    answers.borrow_mut().push(CommandFrame {
                        seq,
                        current_a: failsafe_a,
                        target_force_n: 0.0,
                        flags: Flags::FAIL_SAFE,
                        rejected: 0,
                    });
                    failsafe_a
                }
            }
        };
        simulate(
            &setup.plant,
            &setup.impact,
            CurrentSource::Controller(Box::new(controller)),
        )?;
    }
    if let Some(e) = error.into_inner() {
        return Err(e.context("PIL link failed during the faulty drop"));
    }
    link.end_of_run()?;
    let status = qemu.wait(Duration::from_secs(20))?;
    let answers = answers.into_inner();
    let tally = tally.into_inner();

    let first_difference = answers.iter().zip(&reference).find_map(|(a, r)| {
        let same = a.current_a.to_bits() == r.current_a.to_bits()
            && a.target_force_n.to_bits() == r.target_force_n.to_bits()
            && Flags(a.flags.0 & !Flags::FRAME_FAULT.0) == r.flags;
        (!same).then(|| format!("period {}: firmware {a:?}, in process {r:?}", a.seq))
    });
    let first_difference = first_difference.or_else(|| {
        (answers.len() != reference.len())
            .then(|| format!("{} firmware periods, {} in process", answers.len(), reference.len()))
    });

    let failsafe_a = cfg.law.failsafe_current_a;
    let latched = Flags::SENSOR_STUCK;
    let latch_at = answers.iter().position(|a| a.flags.contains(latched));
    let failsafe_held_after_latch = latch_at.is_none_or(|k| {
        answers[k..]
            .iter()
            .all(|a| a.current_a == failsafe_a && a.flags.contains(latched))
    });

    let mut faults = vec![tally.corrupt, tally.drop, tally.duplicate];
    faults[0].kind = "corrupt sample frame".into();
    faults[1].kind = "dropped sample frame".into();
    faults[2].kind = "duplicated sample frame".into();
    if plan.sensors {
        let answer = |seq: u32| answers.get(seq as usize - 1);
        let flagged =
            |seq: u32, flag: Flags| answer(seq).is_some_and(|a| a.flags.contains(flag) && a.current_a == failsafe_a);
        let ran_past = |seq: u32| answers.len() > seq as usize;
        let stuck_detected = latch_at.is_some_and(|k| k + 1 >= STUCK_FROM as usize);
        faults.push(FaultCount {
            kind: "NaN displacement sample".into(),
            injected: u32::from(answer(NAN_AT).is_some()),
            detected: u32::from(flagged(NAN_AT, Flags::NON_FINITE_INPUT)),
            survived: u32::from(ran_past(NAN_AT)),
        });
        faults.push(FaultCount {
            kind: "out-of-range displacement".into(),
            injected: u32::from(answer(RANGE_AT).is_some()),
            detected: u32::from(flagged(RANGE_AT, Flags::SENSOR_RANGE)),
            survived: u32::from(ran_past(RANGE_AT)),
        });
        faults.push(FaultCount {
            kind: "displacement stuck mid-impact".into(),
            injected: u32::from(answer(STUCK_FROM).is_some()),
            detected: u32::from(stuck_detected),
            survived: u32::from(stuck_detected && failsafe_held_after_latch),
        });
    }
    if let Some(u) = upload {
        faults.push(u);
    }
    let mut first_difference = first_difference;
    for (on, fault) in [
        (plan.sense_stuck, SenseFault::Stuck),
        (plan.sense_stale, SenseFault::Stale),
    ] {
        if on {
            let (count, difference) = run_sense_drop(&setup, &table, &cfg, &elf, fault)?;
            faults.push(count);
            first_difference = first_difference.or(difference);
        }
    }
    let last = answers.last().copied();
    Ok(FaultReport {
        faults,
        periods: answers.len(),
        commands_identical_to_reference: first_difference.is_none(),
        first_difference,
        failsafe_held_after_latch,
        failsafe_current_a: failsafe_a,
        final_command_a: last.map_or(f32::NAN, |a| a.current_a),
        final_flags: last.map_or_else(String::new, |a| format!("{:?}", a.flags)),
        firmware_exit: status.to_string(),
    })
}

/// A fault of the coil's current-sense channel, each in a drop of its own
/// (a latched fault holds the fail-safe for the rest of a run).
#[derive(Clone, Copy, Debug, PartialEq)]
enum SenseFault {
    /// Every frame carries 0 A, whatever the coil does.
    Stuck,
    /// Frames carry the coil current until `STALE_FROM`, then none.
    Stale,
}

impl SenseFault {
    /// The coil current sample frame `seq` carries; `coil_a` is the last
    /// command, what a healthy shunt reads.
    fn reading(self, seq: u32, coil_a: f32) -> Option<f32> {
        match self {
            SenseFault::Stuck => Some(0.0),
            SenseFault::Stale => (seq < STALE_FROM).then_some(coil_a),
        }
    }

    fn kind(self) -> &'static str {
        match self {
            SenseFault::Stuck => "current sense stuck at 0 A while driven",
            SenseFault::Stale => "current sense stale (no new conversion)",
        }
    }
}

/// What the PIL board hands the monitor for a frame's current (its
/// `coil_current`): fresh when present, stale once a current has been seen.
fn sense_of(reading: Option<f32>, wired: &mut bool) -> Option<mre_algorithm::overcurrent::Sense> {
    use mre_algorithm::overcurrent::Sense;
    match reading {
        Some(a) => {
            *wired = true;
            Some(Sense::Fresh(a))
        }
        None => wired.then_some(Sense::Stale),
    }
}

/// One drop through the firmware with `fault` in the current-sense channel,
/// and the same drop in process; the fault count and the first difference.
fn run_sense_drop(
    setup: &crate::plant::closed_loop::SimSetup,
    table: &mre_algorithm::table::Table,
    cfg: &ControlConfig,
    elf: &std::path::Path,
    fault: SenseFault,
) -> Result<(FaultCount, Option<String>)> {
    let mut cfg = *cfg;
    if fault == SenseFault::Stuck {
        cfg.law.rebound = mre_algorithm::law::ReboundPolicy::Fixed {
            current_a: STUCK_HOLD_A,
        };
    }
    let cfg = &cfg;
    let failsafe_a = cfg.law.failsafe_current_a;
    let mut reference: Vec<CommandFrame> = Vec::new();
    {
        let mut ctl = Controller::new(*cfg, Ok(*table)).map_err(|e| anyhow!("controller: {e:?}"))?;
        let (mut wired, mut coil_a) = (false, 0.0f32);
        let out = &mut reference;
        let controller = move |x_mm: f32, v_m_s: f32| {
            let seq = out.len() as u32 + 1;
            ctl.check_coil_current(sense_of(fault.reading(seq, coil_a), &mut wired));
            let cmd = ctl.step_sample(x_mm, Some(v_m_s));
            ctl.end_period(false);
            coil_a = cmd.current_a;
            out.push(super::in_process_frame(seq, &cmd));
            cmd.current_a
        };
        simulate(
            &setup.plant,
            &setup.impact,
            CurrentSource::Controller(Box::new(controller)),
        )?;
    }

    let qemu_bin = qemu_binary().ok_or_else(|| anyhow!("qemu-system-arm not found: {INSTALL_HINT}"))?;
    let (qemu, mut link): (Qemu, PilLink) = Qemu::start(&qemu_bin, elf, None)?;
    link.upload_config(table, cfg)?;
    let answers = RefCell::new(Vec::<CommandFrame>::new());
    let error = RefCell::new(None);
    {
        let link = &mut link;
        let mut coil_a = 0.0f32;
        let controller = |x_mm: f32, v_m_s: f32| {
            let seq = answers.borrow().len() as u32 + 1;
            let frame = SampleFrame {
                seq,
                x_mm,
                v_m_s: Some(v_m_s),
                force_n: None,
                coil_current_a: fault.reading(seq, coil_a),
            };
            let current_a = match link.exchange(&frame) {
                Ok(cmd) => {
                    answers.borrow_mut().push(cmd);
                    cmd.current_a
                }
                Err(e) => {
                    error.borrow_mut().get_or_insert(e);
                    failsafe_a
                }
            };
            coil_a = current_a;
            current_a
        };
        simulate(
            &setup.plant,
            &setup.impact,
            CurrentSource::Controller(Box::new(controller)),
        )?;
    }
    if let Some(e) = error.into_inner() {
        return Err(e.context("PIL link failed during the current-sense fault drop"));
    }
    link.end_of_run()?;
    let status = qemu.wait(Duration::from_secs(20))?;
    let answers = answers.into_inner();
    let difference = answers
        .iter()
        .zip(&reference)
        .find_map(|(a, r)| {
            let same = a.current_a.to_bits() == r.current_a.to_bits()
                && a.target_force_n.to_bits() == r.target_force_n.to_bits()
                && a.flags == r.flags;
            (!same).then(|| format!("{}: period {}: firmware {a:?}, in process {r:?}", fault.kind(), a.seq))
        })
        .or_else(|| {
            (answers.len() != reference.len()).then(|| {
                format!(
                    "{}: {} firmware periods, {} in process",
                    fault.kind(),
                    answers.len(),
                    reference.len()
                )
            })
        });
    let latch_at = answers.iter().position(|a| a.flags.contains(Flags::CURRENT_SENSE));
    let in_time = match fault {
        // Stale from STALE_FROM: latched by the STALE_PERIODS-th stale frame.
        SenseFault::Stale => latch_at
            .is_some_and(|k| k + 1 == (STALE_FROM + u32::from(mre_algorithm::overcurrent::STALE_PERIODS) - 1) as usize),
        // Latched after STUCK_PERIODS periods driven ≥ STUCK_DRIVEN_A, not before.
        SenseFault::Stuck => latch_at.is_some_and(|k| {
            let driven = answers[..k]
                .iter()
                .rev()
                .take_while(|a| a.current_a >= mre_algorithm::overcurrent::STUCK_DRIVEN_A)
                .count();
            driven == usize::from(mre_algorithm::overcurrent::STUCK_PERIODS)
        }),
    };
    let held = latch_at.is_some_and(|k| {
        answers[k..]
            .iter()
            .all(|a| a.current_a == failsafe_a && a.flags.contains(Flags::CURRENT_SENSE))
    });
    let survived = held && difference.is_none() && status.success();
    Ok((
        FaultCount {
            kind: fault.kind().into(),
            injected: 1,
            detected: u32::from(in_time),
            survived: u32::from(survived),
        },
        difference,
    ))
}

/// `mre pil --faults`: runs, writes `faults.md` and `faults.json` into `report_dir`.
pub fn run_to_report(request: &PilRequest, plan: &FaultPlan, report_dir: &std::path::Path) -> Result<FaultReport> {
    let report = run_faults(request, plan)?;
    crate::atomic_write::write_atomic(&report_dir.join("faults.md"), report.markdown().as_bytes())?;
    crate::atomic_write::write_atomic_with(&report_dir.join("faults.json"), |buf| {
        serde_json::to_writer_pretty(&mut *buf, &report)?;
        Ok(())
    })?;
    Ok(report)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn plans_parse_and_bad_ones_are_refused() {
        let p = FaultPlan::parse("corrupt:1e-2, drop:1e-3,sensors", 7).unwrap();
        assert_eq!((p.corrupt_rate, p.drop_rate, p.duplicate_rate), (1e-2, 1e-3, 0.0));
        assert!(p.sensors && !p.upload);
        let all = FaultPlan::parse("all:0.01", 1).unwrap();
        assert!(all.sensors && all.upload && all.duplicate_rate == 0.01);
        assert!(all.sense_stuck && all.sense_stale);
        let p = FaultPlan::parse("sense-stale", 1).unwrap();
        assert!(p.sense_stale && !p.sense_stuck && !p.sensors);
        for bad in ["corrupt", "drop:2", "stuck", "duplicate:x", "sense-stale:0.1"] {
            assert!(FaultPlan::parse(bad, 0).is_err(), "{bad}");
        }
    }

    /// Every fault at 1e-2 (and a few forced by rate 0.05 so each kind
    /// occurs), in QEMU: all detected, all survived, the run ends cleanly.
    #[test]
    fn every_injected_fault_is_detected_and_survived_in_qemu() {
        if super::super::tests::qemu_or_skip().is_none() {
            return;
        }
        let request = PilRequest {
            sim: Default::default(),
            elf: Some(super::super::tests::firmware()),
        };
        let plan = FaultPlan::parse("all:0.05", 3).unwrap();
        let report = run_faults(&request, &plan).unwrap();
        eprintln!("{}", report.markdown());
        for f in &report.faults {
            assert!(f.injected > 0, "{} was never injected", f.kind);
        }
        assert!(report.all_detected_and_survived(), "{}", report.markdown());
        assert_eq!(
            report.final_command_a, report.failsafe_current_a,
            "ends in the fail-safe state"
        );
    }
}
