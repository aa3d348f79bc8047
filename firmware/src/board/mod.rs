//! Board layers: clocks, peripherals and the I/O trait implementations the
//! control task runs against. Exactly one board feature is enabled:
//! - `board-b-l475e-iot01a` (default) and `board-nucleo-l476rg`: real
//!   hardware, shared STM32L4 code in `stm32l4.rs`, pins in one table each;
//! - `pil`: QEMU's `b-l475e-iot01a` machine, samples and commands over USART1.
//!
//! Every layer exports the same items, named below (no glob): `NAME`,
//! `Board { io, watchdog }` (`io` implements [`BoardIo`]), `Status`
//! ([`StatusIo`]), `init(rate_hz)`, `Board::start`, `boot_table` (the
//! uploaded table or the built-in one), `spawn_uplink` (the table upload
//! receiver), `core_clock_hz`, `cycles` and `halt_fail_safe`.
#[cfg(all(feature = "hw", feature = "pil"))]
compile_error!("enable one board: `pil` needs `--no-default-features`");
#[cfg(all(feature = "board-b-l475e-iot01a", feature = "board-nucleo-l476rg"))]
compile_error!("enable one board: use `--no-default-features` with `board-nucleo-l476rg`");
#[cfg(not(any(feature = "hw", feature = "pil")))]
compile_error!("enable a board feature (board-b-l475e-iot01a, board-nucleo-l476rg or pil)");

#[cfg(feature = "hw")]
mod stm32l4;
#[cfg(all(feature = "hw", feature = "bench"))]
pub use stm32l4::bench_model_step;
#[cfg(feature = "hw")]
pub use stm32l4::{boot_table, core_clock_hz, cycles, halt_fail_safe, init, spawn_uplink, Board, Status, NAME};

#[cfg(feature = "pil")]
mod pil;
#[cfg(all(feature = "pil", feature = "bench"))]
pub use pil::icount;
#[cfg(feature = "pil")]
pub use pil::{boot_table, core_clock_hz, cycles, halt_fail_safe, init, spawn_uplink, Board, Status, NAME};

use mre_core::control::{Coil, Controller, DisplacementSensor, VelocitySensor};
use mre_core::frame::LinkStats;
use mre_core::law::Command;

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
    /// The current-sense channel for the monitor (`mre_core::overcurrent`):
    /// on hardware the shunt at mid on-time, `Stale` when no conversion ended
    /// since the last period (ADC3's end-of-injected-conversion flag); in PIL
    /// the plant's coil current, `Stale` when a frame stops carrying one.
    /// `None`: no channel (PIL before the host sent a current).
    fn coil_current(&mut self) -> Option<mre_core::overcurrent::Sense>;
}

/// The status LED and the user button (thread mode).
pub trait StatusIo {
    fn set_led(&mut self, on: bool);
    fn button_pressed(&self) -> bool;
}

/// The coil PWM pin, D5 = PB4 on both boards (and in QEMU's model).
const COIL_PIN: usize = 4;

/// Drives the coil output off (PB4 low, pull-down) through the PAC: the
/// first thing `main` does, before clocks or embassy. After every reset PB4
/// is NJTRST with an internal pull-up, so until this runs the driver input
/// floats high (100 % duty, 3 A). Only the gate pull-down on the driver
/// board (firmware/README.md, "Wiring") covers the microseconds from reset
/// to here. Off (0 A) is the only state a bare GPIO can hold; the 2 A
/// fail-safe follows once TIM3 runs the PWM in `init`.
pub fn coil_output_off_at_boot() {
    use embassy_stm32::pac;
    use embassy_stm32::pac::gpio::vals::{Moder, Pupdr};
    pac::RCC.ahb2enr().modify(|w| w.set_gpioben(true));
    // Output level first, then the mode: the pin never drives high.
    pac::GPIOB.bsrr().write(|w| w.set_br(COIL_PIN, true));
    pac::GPIOB.pupdr().modify(|w| w.set_pupdr(COIL_PIN, Pupdr::PULL_DOWN));
    pac::GPIOB.moder().modify(|w| w.set_moder(COIL_PIN, Moder::OUTPUT));
}

/// The PIL frame link's counters in a log line (nothing on hardware).
pub struct LinkSummary(pub Option<mre_core::frame::LinkStats>);
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
