//! Board layers: clocks, peripherals and the I/O trait implementations the
//! control task runs against. Exactly one board feature is enabled:
//! - `board-b-l475e-iot01a` (default) and `board-nucleo-l476rg`: real
//!   hardware, shared STM32L4 code in `stm32l4.rs`, pins in one table each;
//! - `pil`: QEMU's `b-l475e-iot01a` machine, samples and commands over USART1.
//!
//! Every board implements the [`Board`] trait; the image picks one in
//! [`Selected`].
#[cfg(all(feature = "hw", feature = "pil"))]
compile_error!("enable one board: `pil` needs `--no-default-features`");
#[cfg(all(feature = "board-b-l475e-iot01a", feature = "board-nucleo-l476rg"))]
compile_error!("enable one board: use `--no-default-features` with `board-nucleo-l476rg`");
#[cfg(not(any(feature = "hw", feature = "pil")))]
compile_error!("enable a board feature (board-b-l475e-iot01a, board-nucleo-l476rg or pil)");

pub mod log_drops;

#[cfg(feature = "hw")]
mod flash_upload;
#[cfg(feature = "hw")]
mod stm32l4;
#[cfg(all(feature = "hw", feature = "bench"))]
pub use stm32l4::bench_model_step;

#[cfg(feature = "pil")]
mod pil;
#[cfg(all(feature = "pil", feature = "bench"))]
pub use pil::icount;

/// The board this image runs on: the one place the image picks it (by the
/// board feature). A new board is one module implementing [`Board`] and one
/// line here.
#[cfg(feature = "hw")]
pub type Selected = stm32l4::Board;
#[cfg(feature = "pil")]
pub type Selected = pil::Board;
/// The selected board's status LED and button.
pub type Status = <Selected as Board>::Status;

/// Everything the image calls on a board (issue 40): bring-up, the boot
/// table, the upload receiver, the self-test, the safe states, the control
/// task's I/O and watchdog. Implemented by `stm32l4::Board` (B-L475E-IOT01A
/// and NUCLEO-L476RG: one STM32L4 layer, pins per board) and `pil::Board`
/// (QEMU). Embassy tasks cannot be generic, so the image names the
/// implementation through [`Selected`].
pub trait Board: Sized {
    /// The board's name in the boot log.
    const NAME: &'static str;
    /// Sensors, coil and pacing (the core's I/O traits).
    type Io: BoardIo;
    type Status: StatusIo;
    /// Clocks, peripherals, the reset cause's first coil command and
    /// calibration (firmware/README.md, "Reset paths").
    fn init(rate_hz: u32) -> (Self, Self::Status);
    fn core_clock_hz() -> u32;
    /// A free-running cycle counter (0 where there is none).
    fn cycles() -> u32;
    /// The uploaded table if its page holds a valid one, else `built_in`.
    fn boot_table(
        &mut self,
        built_in: &mre_algorithm::table::TableImage<'_>,
        rate_hz: u32,
    ) -> mre_protocol::upload::BootTable;
    /// Starts the table upload receiver (a no-op where there is none).
    fn spawn_uplink(&mut self, spawner: &embassy_executor::Spawner);
    /// The power-on self-test's results.
    fn self_test(&self, table_crc_holds: bool) -> mre_runtime::boot::SelfTest;
    /// The installed fail-safe duty, re-commanded once the table is known.
    fn hold_fail_safe(&mut self);
    /// Right before the first period (the watchdog's running timeout).
    fn start(&mut self);
    /// A fatal fault at boot: hold the fail-safe, never return.
    fn halt_fail_safe(self) -> !;
    fn io(&mut self) -> &mut Self::Io;
    /// Feeds the watchdog (the control task, after every step).
    fn feed_watchdog(&mut self);
}

use mre_algorithm::control::Controller;
use mre_runtime::io::{Coil, DisplacementSensor, VelocitySensor};

/// Whether the damper is at rest, for the table upload: written by the
/// control task after each step, read on an upload's commit.
pub static UPLOAD_GATE: mre_protocol::upload::SharedUploadGate = mre_protocol::upload::SharedUploadGate::new();
use mre_algorithm::law::Command;
use mre_protocol::frame::LinkStats;

/// What the control task needs from a board's I/O besides the core's sensor
/// and coil traits: the period's pacing and the PIL link's counters.
// Only this crate implements and calls it (no Send bound is needed).
#[allow(async_fn_in_trait)]
pub trait BoardIo: DisplacementSensor + VelocitySensor + Coil {
    /// Waits for the next control period. Returns how many ticks were
    /// missed entirely (already counted as overruns in `ctl`).
    async fn next_period(&mut self, ctl: &mut Controller) -> u32;
    /// After the step: true when the period's work ended after its deadline.
    fn finish_period(&mut self, cmd: &Command, ctl: &Controller) -> bool;
    /// The frame link's counters (PIL), `None` on hardware.
    fn link_stats(&self) -> Option<LinkStats>;
    /// A calibration deferred by the reset cause that finished this period
    /// (hardware; once), for the thread-mode log.
    fn take_deferred_calibration(&mut self) -> Option<DeferredCalibration>;
    /// The current-sense channel for the monitor (`mre_algorithm::overcurrent`):
    /// on hardware the shunt at mid on-time, `Stale` when no conversion ended
    /// since the last period (ADC3's end-of-injected-conversion flag); in PIL
    /// the plant's coil current, `Stale` when a frame stops carrying one.
    /// `None`: no channel (PIL before the host sent a current).
    fn coil_current(&mut self) -> Option<mre_algorithm::overcurrent::Sense>;
}

/// The outcome of the VDDA and current-sense calibration run at rest.
#[derive(Clone, Copy)]
pub struct DeferredCalibration {
    pub vdda: Result<f32, mre_runtime::calibration::CalError>,
    pub sense_zero_a: Result<f32, mre_runtime::calibration::CalError>,
}

/// The status LED and the user button (thread mode).
pub trait StatusIo {
    fn set_led(&mut self, on: bool);
    fn button_pressed(&self) -> bool;
}

// The coil pin to its safe level before anything else runs, RAM init
// included: cortex-m-rt's reset handler calls `__pre_init` first (its
// `#[pre_init]` attribute is deprecated for `global_asm!`, and Rust code may
// not run before RAM init anyway). After every reset PB4 (D5, the coil PWM,
// TIM3_CH1 on both boards and in QEMU's model) is NJTRST: alternate
// function with a pull-up, so the driver input floats high (100 % duty,
// 3 A) until this runs. It enables GPIOB's clock (RCC_AHB2ENR.GPIOBEN),
// sets the output low (BSRR.BR4) before making PB4 an output with a
// pull-down, so the pin never drives high. Off (0 A) is the only state a
// bare GPIO can hold; `init` then starts the fail-safe duty as the reset
// cause decides (`mre_runtime::boot::BootPlan`). RM0351 §6.4.17 (RCC_AHB2ENR,
// corroborated by a public citation) and the GPIO chapter's "GPIO registers"; the addresses and bits
// match ST's CMSIS `stm32l475xx.h` V1.3.1: RCC 0x4002_1000 + AHB2ENR 0x4C,
// GPIOBEN bit 1, GPIOB 0x4800_0400, PUPDR 0x0C, BSRR 0x18. Instructions from the reset vector to here:
// `firmware/bench/reset_icount.sh`.
core::arch::global_asm!(
    ".section .text.__pre_init,\"ax\",%progbits",
    ".global __pre_init",
    ".type __pre_init,%function",
    ".thumb_func",
    "__pre_init:",
    "ldr r0, =0x4002104C", // RCC_AHB2ENR
    "ldr r1, [r0]",
    "orr r1, r1, #2", // GPIOBEN
    "str r1, [r0]",
    "ldr r1, [r0]",        // read back: the clock runs before GPIOB is written
    "ldr r0, =0x48000400", // GPIOB
    "mov r1, #0x100000",   // BSRR.BR4: output level low first
    "str r1, [r0, #0x18]",
    "ldr r1, [r0, #0x0C]", // PUPDR4 = 0b10, pull-down
    "bic r1, r1, #0x300",
    "orr r1, r1, #0x200",
    "str r1, [r0, #0x0C]",
    "ldr r1, [r0]", // MODER4 = 0b01, general-purpose output
    "bic r1, r1, #0x300",
    "orr r1, r1, #0x100",
    ".global mre_coil_pin_safe",
    "mre_coil_pin_safe:", // the store below is the first coil command
    "str r1, [r0]",
    "bx lr",
    ".ltorg",
    ".size __pre_init, . - __pre_init",
);

// The HardFault vector of every image, ahead of the board's handler
// (`mre_hard_fault`, each board's): MSP back to the top of the stack first.
// The stack lies alone in SRAM2 with reserved address space below it
// (`memory.x`, firmware/README.md "Stack guard"), so an overflow faults at
// its first push past the bottom (a bus error, escalated to HardFault). The
// exception entry's own stacking then fails too, and the core still enters
// this handler (ARMv7-M: a stacking fault on HardFault entry does not lock
// up, the handler runs with the stack pushes lost), but with SP below the
// stack: a Rust prologue's first push there would fault at HardFault's
// priority, which locks the core up. A reset MSP gives the handler a whole
// stack; it never returns, so what the old stack held is not needed.
// cortex-m-rt's `#[exception] HardFault` (its trampoline) is not used.
core::arch::global_asm!(
    ".section .HardFault.user,\"ax\",%progbits",
    ".global HardFault",
    ".type HardFault,%function",
    ".thumb_func",
    "HardFault:",
    "ldr r0, =_stack_start",
    "msr msp, r0",
    "b mre_hard_fault",
    ".ltorg",
    ".size HardFault, . - HardFault",
);

/// Faults the control task had latched at the end of its last period: the
/// status LED's blink code and the fault handlers' over-current check.
pub static LATCHED_FAULTS: core::sync::atomic::AtomicU32 = core::sync::atomic::AtomicU32::new(0);

/// The fail-safe current (A, f32 bits) every board path drives: init, the
/// boot-failure halt, the panic, HardFault and NMI handlers. Until the boot
/// table is read it is [`mre_runtime::boot::BOOT_FAILSAFE_CURRENT_A`] (no
/// higher than the weakest coil the board's limits admit); `main` then sets
/// the installed configuration's (`cfg.law.failsafe_current_a`, never above
/// the installed coil's rating), so a 1 A coil is never driven at 2 A.
static FAILSAFE_CURRENT_A_BITS: core::sync::atomic::AtomicU32 =
    core::sync::atomic::AtomicU32::new(mre_runtime::boot::BOOT_FAILSAFE_CURRENT_A.to_bits());

pub fn failsafe_current_a() -> f32 {
    f32::from_bits(FAILSAFE_CURRENT_A_BITS.load(core::sync::atomic::Ordering::Relaxed))
}

/// The installed configuration's fail-safe current (from `main`, once the
/// boot table and its configuration are known).
pub fn set_failsafe_current_a(current_a: f32) {
    FAILSAFE_CURRENT_A_BITS.store(current_a.to_bits(), core::sync::atomic::Ordering::Relaxed);
}

/// A board's coil as the panic and HardFault handlers drive it: registers
/// only (the PAC), no driver state the fault may have left half-written.
pub trait FaultCoil {
    /// `init` started the coil drive (TIM3's PWM on the pin; PIL: `init` ran).
    fn drive_running(&self) -> bool;
    /// `current_a` through the running drive.
    fn hold_current_a(&mut self, current_a: f32);
    /// The drive removed: the pin at its low level (0 A).
    fn off(&mut self);
}

/// The coil to its safe state from a panic or a HardFault, on every board:
/// the decision is `mre_runtime::boot::coil_after_fault` (fail-safe current
/// through a running drive; off before the drive runs or after a latched
/// over-current), the register writes are the board's `FaultCoil`.
pub fn coil_safe_from_a_fault(coil: &mut impl FaultCoil) -> mre_runtime::boot::CoilAfterFault {
    use mre_runtime::boot::{coil_after_fault, CoilAfterFault};
    let latched = mre_algorithm::Flags(LATCHED_FAULTS.load(core::sync::atomic::Ordering::Relaxed));
    let command = coil_after_fault(coil.drive_running(), latched, failsafe_current_a());
    match command {
        CoilAfterFault::FailSafe { current_a } => coil.hold_current_a(current_a),
        CoilAfterFault::Off => coil.off(),
    }
    command
}

/// The coil pin low through the PAC (a panic or fault before TIM3 runs).
#[cfg(feature = "hw")]
pub fn coil_pin_low() {
    use embassy_stm32::pac;
    use embassy_stm32::pac::gpio::vals::Moder;
    pac::RCC.ahb2enr().modify(|w| w.set_gpioben(true));
    pac::GPIOB.bsrr().write(|w| w.set_br(4, true));
    pac::GPIOB.moder().modify(|w| w.set_moder(4, Moder::OUTPUT));
}

/// The PIL frame link's counters in a log line (nothing on hardware).
pub struct LinkSummary(pub Option<mre_protocol::frame::LinkStats>);
impl defmt::Format for LinkSummary {
    fn format(&self, f: defmt::Formatter<'_>) {
        if let Some(s) = &self.0 {
            defmt::write!(
                f,
                ", frames ok {=u32} crc {=u32} kind {=u32} order {=u32} dup {=u32} lost {=u32}",
                s.accepted,
                s.crc_errors,
                s.bad_kind,
                s.out_of_order,
                s.duplicates,
                s.lost
            );
        }
    }
}
