//! The panic and HardFault handlers in QEMU (issue 25): a fault injected in
//! the control task (`INJECT_PANIC_SEQ`, `INJECT_HARDFAULT_SEQ`) must leave
//! the coil at its safe command before the firmware halts. The PIL image
//! runs the boards' decision (`board::coil_safe_from_a_fault`, the core's
//! `coil_after_fault`) with its own register writes: PB4, QEMU's GPIO model,
//! mirrors the command (high while a current above 0 A is commanded), and
//! one command frame reports the value. QEMU models no TIM3: the boards'
//! CCR1 write is not covered here (firmware/README.md).
use super::link::PilLink;
use super::qemu::Qemu;
use super::tests::{firmware, qemu_or_skip};
use mre_algorithm::Flags;
use mre_protocol::frame::{SampleFrame, INJECT_HARDFAULT_SEQ, INJECT_PANIC_SEQ};
use std::time::Duration;

/// The documented fail-safe (firmware/README.md): 2 A, the paper's stiffest
/// table current, so the mass cannot bottom out.
const FAILSAFE_A: f32 = 2.0;
const GPIOB_MODER: u32 = 0x4800_0400;
/// RM0351 GPIOx_ODR at offset 0x14.
const GPIOB_ODR: u32 = GPIOB_MODER + 0x14;
const PB4: u32 = 1 << 4;

fn start() -> Option<(Qemu, PilLink)> {
    let qemu = qemu_or_skip()?;
    Some(Qemu::start(&qemu, &firmware(), None).expect("starting QEMU"))
}

/// A sample of the damper at rest (no impact: the law commands 0 A).
fn at_rest(seq: u32, coil_current_a: Option<f32>) -> SampleFrame {
    SampleFrame {
        seq,
        x_mm: 0.0,
        v_m_s: Some(0.0),
        force_n: None,
        coil_current_a,
    }
}

/// Sends the injecting sample and returns the handler's report.
fn inject(link: &mut PilLink, seq: u32) -> mre_protocol::frame::CommandFrame {
    link.set_answer_timeout(Duration::from_secs(10)).unwrap();
    link.send_raw(&at_rest(seq, None).encode()).unwrap();
    let report = link
        .read_command()
        .expect("no command frame after the injected fault: the handler did not report a coil command");
    assert_eq!(report.seq, seq, "{report:?}");
    report
}

fn pb4_level(qemu: &Qemu) -> bool {
    let moder = qemu.read_word(GPIOB_MODER).unwrap();
    assert_eq!((moder >> 8) & 0b11, 0b01, "PB4 is an output (MODER {moder:#010x})");
    qemu.read_word(GPIOB_ODR).unwrap() & PB4 != 0
}

/// Halted, not exited: QEMU is still running a while after the fault.
fn assert_halted(qemu: Qemu) {
    assert!(
        qemu.wait(Duration::from_millis(500)).is_err(),
        "the firmware exited after the fault instead of halting with the coil safe"
    );
}

/// Runs periods at rest with the coil off, injects `seq`'s fault, and checks
/// the fail-safe current is commanded afterwards, on the frame and on PB4.
fn fault_at_rest_holds_the_failsafe(seq: u32) {
    let Some((qemu, mut link)) = start() else { return };
    for k in 1..=5 {
        let cmd = link.exchange(&at_rest(k, None)).unwrap();
        assert_eq!(cmd.current_a, 0.0, "before the fault the coil is off: {cmd:?}");
    }
    assert!(!pb4_level(&qemu), "PB4 low before the fault (coil off)");
    let report = inject(&mut link, seq);
    assert_eq!(report.current_a, FAILSAFE_A, "{report:?}");
    assert!(report.flags.contains(Flags::FAIL_SAFE), "{report:?}");
    assert!(
        pb4_level(&qemu),
        "PB4 high after the fault (fail-safe current commanded)"
    );
    assert_halted(qemu);
}

#[test]
fn a_panic_in_the_control_task_leaves_the_coil_at_the_failsafe_current() {
    fault_at_rest_holds_the_failsafe(INJECT_PANIC_SEQ);
}

#[test]
fn a_hardfault_in_the_control_task_leaves_the_coil_at_the_failsafe_current() {
    fault_at_rest_holds_the_failsafe(INJECT_HARDFAULT_SEQ);
}

#[test]
fn a_panic_after_a_latched_over_current_keeps_the_drive_removed() {
    // The over-current monitor latches after three periods above 2.4 A
    // (`mre_algorithm::overcurrent`); a fault after that must not drive the 2 A
    // fail-safe into the failed coil.
    let Some((qemu, mut link)) = start() else { return };
    let mut tripped = None;
    for k in 1..=3 {
        tripped = Some(link.exchange(&at_rest(k, Some(3.0))).unwrap());
    }
    let tripped = tripped.unwrap();
    assert!(tripped.flags.contains(Flags::OVER_CURRENT), "{tripped:?}");
    let report = inject(&mut link, INJECT_PANIC_SEQ);
    assert_eq!(report.current_a, 0.0, "{report:?}");
    assert!(!pb4_level(&qemu), "PB4 low after the fault (drive removed)");
    assert_halted(qemu);
}
