//! Processor-in-the-loop board for `qemu-system-arm -M b-l475e-iot01a`.
//!
//! QEMU's model has no TIM, ADC or PWR, so `embassy_stm32::init` is not
//! called: USART1 is driven through the PAC (32-bit register accesses only,
//! as QEMU requires), embassy-time runs on a 10 kHz SysTick driver (core
//! clock: MSI 4 MHz after reset), and defmt goes out over semihosting.
//! The control task and the core are the same code as on hardware; only
//! the I/O below differs: each sample frame from the host is one control
//! period, and each period answers with one command frame (`mre_protocol::frame`).
use core::cell::{Cell, RefCell};
use core::sync::atomic::{AtomicBool, AtomicU32, Ordering};
use core::task::Waker;

use cortex_m::peripheral::syst::SystClkSource;
use cortex_m_rt::exception;
use critical_section::Mutex;
#[cfg(feature = "pil-rtt")]
use defmt_rtt as _;
#[cfg(not(feature = "pil-rtt"))]
use defmt_semihosting as _;
use embassy_stm32::pac;
use embassy_time::Timer;
use embassy_time_driver::Driver;
use embassy_time_queue_utils::Queue;
use mre_algorithm::control::Controller;
use mre_algorithm::law::Command;
use mre_algorithm::overcurrent::Sense;
use mre_algorithm::table::TableImage;
use mre_algorithm::Flags;
use mre_protocol::flash_table::RamPage;
use mre_protocol::frame::{
    CommandFrame, FrameError, Incoming, LinkStats, SampleFrame, SampleReceiver, END_OF_RUN_SEQ, FRAME_LEN,
    INJECT_HARDFAULT_SEQ, INJECT_PANIC_SEQ, PING_SEQ,
};
use mre_protocol::upload::{choose_boot_table, BootTable, UploadReceiver};
use mre_runtime::io::{Coil, DisplacementSensor, VelocitySensor};

pub const NAME: &str = "PIL (QEMU b-l475e-iot01a)";
/// MSI after reset; nothing here changes the clock tree.
const CORE_CLOCK_HZ: u32 = 4_000_000;
const SYSTICK_HZ: u32 = 10_000;
/// embassy-time runs at its default 1 MHz tick.
const EMBASSY_TICKS_PER_SYSTICK: u64 = 1_000_000 / SYSTICK_HZ as u64;
/// Empty USART polls before sleeping to the next SysTick: QEMU hands the
/// next byte over only after RDR is read, so spinning briefly keeps a
/// frame's 24 bytes flowing instead of one byte per tick.
const SPIN_POLLS: u32 = 200;

pub fn core_clock_hz() -> u32 {
    CORE_CLOCK_HZ
}

/// QEMU models no DWT cycle counter; instructions are counted with
/// `-icount`/exec traces instead (BENCHMARKS.md).
#[inline(always)]
pub fn cycles() -> u32 {
    0
}

// ---- embassy-time driver on SysTick ----------------------------------------

struct SysTickDriver {
    systicks: Mutex<Cell<u64>>,
    queue: Mutex<RefCell<Queue>>,
}

impl Driver for SysTickDriver {
    fn now(&self) -> u64 {
        critical_section::with(|cs| self.systicks.borrow(cs).get()) * EMBASSY_TICKS_PER_SYSTICK
    }

    fn schedule_wake(&self, at: u64, waker: &Waker) {
        critical_section::with(|cs| {
            // The SysTick handler checks the queue every tick, so the "next
            // alarm changed" result is not needed.
            if let Ok(mut q) = self.queue.borrow(cs).try_borrow_mut() {
                q.schedule_wake(at, waker);
            }
        });
    }
}

embassy_time_driver::time_driver_impl!(static DRIVER: SysTickDriver = SysTickDriver {
    systicks: Mutex::new(Cell::new(0)),
    queue: Mutex::new(RefCell::new(Queue::new())),
});

#[exception]
fn SysTick() {
    critical_section::with(|cs| {
        let ticks = DRIVER.systicks.borrow(cs);
        ticks.set(ticks.get().wrapping_add(1));
        let now = ticks.get() * EMBASSY_TICKS_PER_SYSTICK;
        if let Ok(mut q) = DRIVER.queue.borrow(cs).try_borrow_mut() {
            q.next_expiration(now);
        }
    });
}

// ---- USART1 through the PAC ---------------------------------------------------

fn usart_init() {
    use pac::gpio::vals::Moder;
    pac::RCC.apb2enr().modify(|w| w.set_usart1en(true));
    // PB6 (TX) and PB7 (RX) to USART1 (AF7): the ST-LINK VCP on a real
    // B-L475E-IOT01A (QEMU's model connects USART1 without it).
    pac::RCC.ahb2enr().modify(|w| w.set_gpioben(true));
    for pin in [6, 7] {
        pac::GPIOB.afr(0).modify(|w| w.set_afr(pin, 7));
        pac::GPIOB.moder().modify(|w| w.set_moder(pin, Moder::ALTERNATE));
    }
    // 115200 Bd at 4 MHz (QEMU ignores the rate; real hardware would not).
    pac::USART1.brr().write(|w| w.set_brr((CORE_CLOCK_HZ / 115_200) as u16));
    pac::USART1.cr1().write(|w| {
        w.set_ue(true);
        w.set_te(true);
        w.set_re(true);
    });
}

fn usart_read() -> Option<u8> {
    let isr = pac::USART1.isr().read();
    if isr.ore() {
        // Clear only ORE: writing the whole ISR value to ICR would clear TXE in QEMU.
        pac::USART1.icr().write(|w| w.set_ore(true));
    }
    isr.rxne().then(|| pac::USART1.rdr().read().dr() as u8)
}

fn usart_write(bytes: &[u8]) {
    for &b in bytes {
        while !pac::USART1.isr().read().txe() {}
        pac::USART1.tdr().write(|w| w.set_dr(u16::from(b)));
    }
}

// ---- Board ----------------------------------------------------------------------

/// No hardware watchdog in QEMU's model: feeding is a no-op.
pub struct Watchdog;
impl Watchdog {
    pub fn pet(&mut self) {}
}

pub struct Board {
    pub io: Io,
    pub watchdog: Watchdog,
}

/// The latest sample frame stands in for the sensors; the command goes back
/// in the answer frame.
pub struct Io {
    rx: SampleReceiver,
    upload: UploadReceiver,
    /// Stand-in for the flash page (QEMU models no flash controller): an
    /// upload goes through the same store/read-back as on the boards, and
    /// the controller flies what the page reads back.
    page: RamPage,
    sample: SampleFrame,
    current_a: f32,
    last_reply: Option<[u8; FRAME_LEN]>,
    last_rejected: u16,
    /// A frame carried the plant's coil current: the sense channel is wired.
    sense_wired: bool,
}

/// QEMU's model has no LED or button to speak of: nothing shown, never pressed.
pub struct Status;

impl super::StatusIo for Status {
    fn set_led(&mut self, _on: bool) {}

    fn button_pressed(&self) -> bool {
        false
    }
}

pub fn init(_rate_hz: u32) -> (Board, Status) {
    // SAFETY: the only user of the core peripherals, once, at boot.
    let core = unsafe { cortex_m::Peripherals::steal() };
    let mut syst = core.SYST;
    syst.set_clock_source(SystClkSource::Core);
    syst.set_reload(CORE_CLOCK_HZ / SYSTICK_HZ - 1);
    syst.clear_current();
    syst.enable_interrupt();
    syst.enable_counter();
    usart_init();
    // The stand-in for `init` starting TIM3 on hardware: from here a fault
    // handler holds the fail-safe current instead of leaving the coil off.
    DRIVE_RUNNING.store(true, Ordering::Relaxed);
    #[cfg(feature = "pil-rtt")]
    super::log_drops::rtt::block_if_full_and_fill();
    (
        Board {
            io: Io {
                rx: SampleReceiver::new(),
                upload: UploadReceiver::new(),
                page: RamPage::erased(),
                sample: SampleFrame {
                    seq: 0,
                    x_mm: f32::NAN,
                    v_m_s: None,
                    force_n: None,
                    coil_current_a: None,
                },
                current_a: 0.0,
                last_reply: None,
                last_rejected: 0,
                sense_wired: false,
            },
            watchdog: Watchdog,
        },
        Status,
    )
}

fn send_hello(flags: Flags) {
    usart_write(&CommandFrame::hello(flags).encode());
}

impl super::BoardIo for Io {
    /// Waits for the next valid sample frame (one control period). An
    /// uploaded configuration (config frames + commit) replaces `ctl`.
    /// Simulated time never skips a period: returns 0 missed ticks.
    async fn next_period(&mut self, ctl: &mut Controller) -> u32 {
        loop {
            let mut idle_polls = 0u32;
            while idle_polls < SPIN_POLLS {
                let Some(byte) = usart_read() else {
                    idle_polls += 1;
                    continue;
                };
                idle_polls = 0;
                match self.rx.push_any(byte) {
                    Some(Ok(Incoming::Config(chunk))) => {
                        // At rest: before the first sample, or still (`UPLOAD_GATE`).
                        let at_rest = ctl.stats().periods == 0 || super::UPLOAD_GATE.at_rest();
                        let Some(result) = self.upload.on_chunk(chunk, &mut self.page, at_rest) else {
                            continue;
                        };
                        // The answer says why (mre_protocol::upload::CommitAnswer).
                        let (stored, reply) = (result.is_ok(), mre_protocol::upload::answer(&result));
                        let flown = match result {
                            Ok((table, cfg)) => match Controller::new(cfg, Ok(table)) {
                                Ok(new_ctl) => {
                                    *ctl = new_ctl;
                                    defmt::info!(
                                        "configuration uploaded (page stored and read back): table CRC {=u32:#010x}, {=u32} Hz",
                                        table.crc32(),
                                        cfg.rate_hz
                                    );
                                    true
                                }
                                Err(e) => {
                                    defmt::warn!(
                                        "uploaded configuration refused by the controller: {}",
                                        defmt::Debug2Format(&e)
                                    );
                                    false
                                }
                            },
                            Err(e) => {
                                defmt::warn!("configuration refused: {=str}", e.as_str());
                                false
                            }
                        };
                        if flown || !stored {
                            usart_write(&reply);
                        } else {
                            send_hello(Flags::TABLE_FAULT);
                        }
                    }
                    Some(Ok(Incoming::Sample(sample))) if sample.seq == END_OF_RUN_SEQ => end_of_run(self.rx.stats()),
                    // The host connected after the boot hello (a serial port).
                    Some(Ok(Incoming::Sample(sample))) if sample.seq == PING_SEQ => send_hello(Flags::NONE),
                    // Fault injection (`pil::fault_handler_tests`): a panic or
                    // a HardFault (an undefined instruction, escalated: the
                    // UsageFault handler is not enabled) in the control task.
                    Some(Ok(Incoming::Sample(sample))) if sample.seq == INJECT_PANIC_SEQ => {
                        LAST_SEQ.store(sample.seq, Ordering::Relaxed);
                        inject_panic()
                    }
                    Some(Ok(Incoming::Sample(sample))) if sample.seq == INJECT_HARDFAULT_SEQ => {
                        LAST_SEQ.store(sample.seq, Ordering::Relaxed);
                        cortex_m::asm::udf()
                    }
                    Some(Ok(Incoming::Sample(sample))) => {
                        LAST_SEQ.store(sample.seq, Ordering::Relaxed);
                        self.sample = sample;
                        return 0;
                    }
                    // A host retry: answer again without a second step.
                    Some(Err(FrameError::Duplicate { .. })) => {
                        if let Some(reply) = self.last_reply {
                            usart_write(&reply);
                        }
                    }
                    // Corrupt or out of order: counted by the receiver, skipped.
                    Some(Err(_)) | None => {}
                }
            }
            // Sleep until the next SysTick; QEMU polls the socket meanwhile.
            Timer::after_ticks(1).await;
        }
    }

    /// Sends the answer. Simulated time has no deadline: never an overrun.
    fn finish_period(&mut self, cmd: &Command, _ctl: &Controller) -> bool {
        let rejected = self.rx.stats().rejected();
        let mut flags = cmd.flags;
        if rejected != self.last_rejected {
            flags |= Flags::FRAME_FAULT;
            self.last_rejected = rejected;
        }
        let reply = CommandFrame {
            seq: self.sample.seq,
            // What the coil was given: the same path as a PWM write.
            current_a: self.current_a,
            target_force_n: cmd.target_force_n,
            flags,
            rejected,
        }
        .encode();
        // `pil-rtt`: one log frame per period into the full block-if-full
        // buffer, before the answer: a logger that waits for a reader holds
        // the answer back (`pil::tests`, the full-buffer logging test).
        #[cfg(feature = "pil-rtt")]
        super::log_drops::counted(|| defmt::info!("period {=u32}: coil {=f32} A", self.sample.seq, self.current_a));
        usart_write(&reply);
        self.last_reply = Some(reply);
        false
    }

    fn link_stats(&self) -> Option<LinkStats> {
        Some(self.rx.stats())
    }

    /// QEMU models no ADC: nothing is calibrated.
    fn take_deferred_calibration(&mut self) -> Option<super::DeferredCalibration> {
        None
    }

    /// The plant's coil current; once the host has sent one, a frame
    /// without it is a conversion that did not arrive (a stale channel).
    fn coil_current(&mut self) -> Option<Sense> {
        match self.sample.coil_current_a {
            Some(a) => {
                self.sense_wired = true;
                Some(Sense::Fresh(a))
            }
            None => self.sense_wired.then_some(Sense::Stale),
        }
    }
}

fn end_of_run(stats: LinkStats) -> ! {
    defmt::info!("PIL end of run{}", super::LinkSummary(Some(stats)));
    semihosting::process::exit(0)
}

impl DisplacementSensor for Io {
    fn read_x_mm(&mut self) -> f32 {
        self.sample.x_mm
    }
}

impl VelocitySensor for Io {
    fn read_v_m_s(&mut self) -> Option<f32> {
        self.sample.v_m_s
    }
}

impl Coil for Io {
    fn set_current_a(&mut self, current_a: f32) {
        self.current_a = current_a;
        mirror_coil_on_pb4(current_a);
    }
}

// ---- Panic and HardFault ----------------------------------------------------

/// `init` ran (the stand-in for TIM3 running on hardware).
static DRIVE_RUNNING: AtomicBool = AtomicBool::new(false);
/// The last sample's sequence number: the fault report answers it.
static LAST_SEQ: AtomicU32 = AtomicU32::new(0);

/// The coil command mirrored on PB4 (the coil pin, an output low since
/// `__pre_init`), which QEMU's GPIO model holds for the host to read: high
/// while a current above 0 A is commanded. QEMU models no TIM3, so the
/// duty itself is not visible; the command frame carries the value.
fn mirror_coil_on_pb4(current_a: f32) {
    let on = current_a > 0.0;
    pac::GPIOB.bsrr().write(|w| {
        w.set_bs(4, on);
        w.set_br(4, !on);
    });
}

/// The PIL coil from a fault handler: the PB4 mirror, then one command
/// frame answering the last sample with the commanded current (flag
/// `FAIL_SAFE`), through the PAC as on hardware.
struct PilCoil;

impl PilCoil {
    fn report(current_a: f32) {
        mirror_coil_on_pb4(current_a);
        usart_write(
            &CommandFrame {
                seq: LAST_SEQ.load(Ordering::Relaxed),
                current_a,
                target_force_n: 0.0,
                flags: Flags::FAIL_SAFE,
                rejected: 0,
            }
            .encode(),
        );
    }
}

impl super::FaultCoil for PilCoil {
    fn drive_running(&self) -> bool {
        DRIVE_RUNNING.load(Ordering::Relaxed)
    }

    fn hold_current_a(&mut self, current_a: f32) {
        Self::report(current_a);
    }

    fn off(&mut self) {
        Self::report(0.0);
    }
}

#[allow(clippy::panic)]
fn inject_panic() -> ! {
    panic!("injected by the host (INJECT_PANIC_SEQ)")
}

/// As on hardware: the coil safe first, then the log, then a halt (QEMU has
/// no watchdog to reset it; the host stops QEMU).
#[panic_handler]
fn panic(info: &core::panic::PanicInfo) -> ! {
    super::coil_safe_from_a_fault(&mut PilCoil);
    defmt::error!("panic: {}; coil at its safe state, halted", defmt::Display2Format(info));
    halt()
}

/// The HardFault handler, entered from `HardFault` (`board/mod.rs`) on a
/// fresh stack.
#[no_mangle]
extern "C" fn mre_hard_fault() -> ! {
    super::coil_safe_from_a_fault(&mut PilCoil);
    halt()
}

fn halt() -> ! {
    loop {
        cortex_m::asm::nop();
    }
}

impl super::Board for Board {
    const NAME: &'static str = NAME;
    type Io = Io;
    type Status = Status;

    fn init(rate_hz: u32) -> (Self, Status) {
        init(rate_hz)
    }

    fn core_clock_hz() -> u32 {
        core_clock_hz()
    }

    #[inline(always)]
    fn cycles() -> u32 {
        cycles()
    }

    /// The table boot flies: the page (in RAM here, so empty after QEMU
    /// starts) or the image's own. Uploads arrive on the frame link and
    /// switch the running controller (`Io::next_period`).
    fn boot_table(&mut self, built_in: &TableImage<'_>, rate_hz: u32) -> BootTable {
        choose_boot_table(&mut self.io.page, built_in, rate_hz)
    }

    /// Uploads share the frame link with the samples: no separate receiver.
    fn spawn_uplink(&mut self, _spawner: &embassy_executor::Spawner) {}

    /// The power-on self-test: QEMU models no ADC and no TIM3, so the
    /// hardware checks pass by construction here; the table's is real.
    fn self_test(&self, table_crc_holds: bool) -> mre_runtime::boot::SelfTest {
        mre_runtime::boot::SelfTest {
            sense_converts: true,
            pwm_reads_back: true,
            table_crc_holds,
        }
    }

    /// The fail-safe is commanded by the first answer frame here.
    fn hold_fail_safe(&mut self) {}

    /// Announces the link with a command frame of sequence 0 (`HELLO_SEQ`):
    /// the host sends no sample before it, so no byte can arrive while the
    /// firmware is still booting.
    fn start(&mut self) {
        defmt::info!("PIL link up on USART1: waiting for sample frames");
        send_hello(Flags::NONE);
    }

    /// A fatal fault at boot: QEMU has no watchdog, so the run ends (exit 2).
    fn halt_fail_safe(self) -> ! {
        semihosting::process::exit(2)
    }

    #[inline(always)]
    fn io(&mut self) -> &mut Io {
        &mut self.io
    }

    #[inline(always)]
    fn feed_watchdog(&mut self) {
        self.watchdog.pet();
    }
}

/// `pil` + `bench`: executed-instruction counts of the model step and the
/// control step, read from a QEMU exec trace (`firmware/bench/icount.sh`).
/// Each measured call sits between a call of `mre_mark_begin` and one of
/// `mre_mark_end`; the script counts the instructions executed from the
/// entry of the first to the entry of the second and subtracts the 3 of
/// the markers themselves (begin's `nop; bx lr` and the `bl` to end).
///
/// The windows come in a fixed order, which `icount.sh` labels (it repeats
/// the constants below): per table (the flown one, then the same entries
/// with every format 2 term, with coil lag and sensor delay, and with the
/// terms diagnosis finds on real data), the model grid, then the control step over
/// one whole drop with the velocity sensor, then the same drop without it.
#[cfg(feature = "bench")]
pub mod icount {
    use core::hint::black_box;
    use mre_algorithm::control::Controller;
    use mre_algorithm::table::ModelTerms;
    use mre_algorithm::{Branch, Table};

    #[inline(never)]
    #[no_mangle]
    pub extern "C" fn mre_mark_begin() {
        cortex_m::asm::nop();
    }

    #[inline(never)]
    #[no_mangle]
    pub extern "C" fn mre_mark_end() {
        // Two nops so the linker cannot fold this into `mre_mark_begin`.
        cortex_m::asm::nop();
        cortex_m::asm::nop();
    }

    /// The drop (issue 11's limit case): 5.5 kg arriving at 2.24 m/s,
    /// stopped at constant deceleration `a = v0²/(2·s)` within the 12 mm
    /// usable stroke, so `x(t) = v0·t − a·t²/2`, `v(t) = v0 − a·t`, sampled
    /// every control period from contact (t = 0) until the mass stops
    /// (t = v0/a, 107 periods at 10 kHz), then `REBOUND_PERIODS` more on
    /// the same parabola: the mass moving back out.
    const DROP_V0_M_S: f32 = 2.24;
    const DROP_STROKE_MM: f32 = 12.0;
    const REBOUND_PERIODS: u32 = 10;
    /// Model step grid over the whole stroke: x = 0, 1, …, 12 mm, each at the
    /// drop's velocity there, and each of these forces: from below the 0 A
    /// force to above the 2 A force (saturated: every entry scanned).
    const GRID_STEP_MM: f32 = 1.0;
    const GRID_POINTS: u32 = 13;
    const GRID_FORCES_N: [f32; 5] = [50.0, 400.0, 1200.0, 2500.0, 90_000.0];
    /// Then the same near contact, where every force is close to 0 and the
    /// fitted entries cross (the flown table's 1.5 A and 2 A compression
    /// quartics at 0.435 mm): x = 0, 0.0725, …, 0.87 mm × forces from below
    /// the 0 A force (−10 N) to above the 2 A force.
    const NEAR_STEP_MM: f32 = 0.0725;
    const NEAR_POINTS: u32 = 13;
    const NEAR_FORCES_N: [f32; 5] = [-10.0, 100.0, 300.0, 600.0, 90_000.0];

    /// The drop's deceleration (m/s²).
    fn drop_decel_m_s2() -> f32 {
        DROP_V0_M_S * DROP_V0_M_S / (2.0 * DROP_STROKE_MM * 1.0e-3)
    }

    /// The drop's state (x mm, v m/s) at time `t_s` after contact.
    fn drop_state(t_s: f32) -> (f32, f32) {
        let a = drop_decel_m_s2();
        ((DROP_V0_M_S * t_s - 0.5 * a * t_s * t_s) * 1.0e3, DROP_V0_M_S - a * t_s)
    }

    /// Control periods sampled over the drop: contact to stop, then the rebound.
    fn drop_periods(period_s: f32) -> u32 {
        // Periods up to and including the stop (t = v0/a), as an integer
        // without a float-to-int rounding call: count them.
        let t_stop_s = DROP_V0_M_S / drop_decel_m_s2();
        let mut n = 0;
        while (n as f32) * period_s <= t_stop_s {
            n += 1;
        }
        n + REBOUND_PERIODS
    }

    /// The model step (the inverse at the law's target) over the whole
    /// stroke's grid, then over the near-contact grid.
    fn model_steps(table: &Table) {
        model_grid(table, GRID_STEP_MM, GRID_POINTS, &GRID_FORCES_N);
        model_grid(table, NEAR_STEP_MM, NEAR_POINTS, &NEAR_FORCES_N);
    }

    /// The model step at x = 0, `step_mm`, … (`points` of them), each at the
    /// drop's velocity there (`v² = v0²·(1 − x/s)`), × `forces_n`.
    fn model_grid(table: &Table, step_mm: f32, points: u32, forces_n: &[f32]) {
        let a = drop_decel_m_s2();
        for i in 0..points {
            let x_mm = i as f32 * step_mm;
            // At the stop v² rounds to ±0: no square root of a negative.
            let v2 = DROP_V0_M_S * DROP_V0_M_S - 2.0 * a * x_mm * 1.0e-3;
            let v_m_s = if v2 > 0.0 {
                mre_algorithm::math::sqrt_precise(v2)
            } else {
                0.0
            };
            for &force_n in forces_n {
                let (x_mm, v_m_s, force_n) = (black_box(x_mm), black_box(v_m_s), black_box(force_n));
                mre_mark_begin();
                let r = table.current_for_branch_v(x_mm, v_m_s, Branch::Compression, force_n);
                mre_mark_end();
                black_box(r);
            }
        }
    }

    /// The whole control step (estimator, law, faults) over the drop, on a
    /// fresh copy of `ctl` (as booted: idle, estimator unprimed), with the
    /// velocity sensor, then again without it (the estimator's velocity).
    fn control_steps(ctl: &Controller) {
        let period_s = ctl.config().period_s();
        let periods = drop_periods(period_s);
        for with_sensor in [true, false] {
            let mut c = *ctl;
            for k in 0..periods {
                let (x_mm, v_m_s) = drop_state(k as f32 * period_s);
                let v = with_sensor.then_some(v_m_s);
                let (x_mm, v) = (black_box(x_mm), black_box(v));
                mre_mark_begin();
                let cmd = c.step_sample(x_mm, v);
                mre_mark_end();
                black_box(cmd);
            }
        }
    }

    /// The terms `mre pil` flies for controller (c) on a plant with coil lag
    /// and sensor delay: what diagnosis reports there, without viscosity or
    /// saturation.
    const LAG_AND_DELAY: ModelTerms = ModelTerms {
        coil_tau_s: 2.0e-3,
        sensor_delay_s: 1.0e-4,
        ..ModelTerms::NONE
    };

    /// What `mre diagnose` finds on real drop data: a viscous term that
    /// rises with current (10, 15, …, 30 N·s/m on the five entries), a
    /// saturation current, the coil's τ and a sensor delay.
    const DIAGNOSED: ModelTerms = ModelTerms {
        viscous_n_s_per_m: [10.0, 15.0, 20.0, 25.0, 30.0, 0.0, 0.0, 0.0],
        saturation_current_a: 1.5,
        sensor_delay_s: 1.0e-4,
        coil_tau_s: 2.0e-3,
    };

    /// The flown table and its control step over the drop, then the same
    /// on the flown entries with other terms.
    fn measure(flown: &Table, ctl: &Controller, terms: ModelTerms) {
        let Ok(ctl_terms) = Controller::new(*ctl.config(), Table::with_terms(flown.entries(), terms)) else {
            defmt::error!("icount: terms table refused");
            semihosting::process::exit(1)
        };
        if let Some(t) = ctl_terms.table() {
            model_steps(t);
        }
        control_steps(&ctl_terms);
    }

    /// The flown table, then the same entries with every version 2 term
    /// (coil τ, sensor delay, viscous, saturation: the worst path), then
    /// with coil lag and sensor delay only (what `mre pil` flies), then
    /// with the terms diagnosis finds on real data.
    pub fn run(ctl: &mut Controller) {
        // No SysTick interrupts inside the measured windows.
        // SAFETY: only SYST is touched; the executor has not started yet.
        let mut syst = unsafe { cortex_m::Peripherals::steal() }.SYST;
        syst.disable_interrupt();
        syst.disable_counter();
        let Some(flown) = ctl.table().copied() else {
            defmt::error!("icount: no table");
            semihosting::process::exit(1)
        };
        model_steps(&flown);
        control_steps(ctl);
        measure(&flown, ctl, ModelTerms::EVERY_TERM);
        measure(&flown, ctl, LAG_AND_DELAY);
        measure(&flown, ctl, DIAGNOSED);
        defmt::info!("icount bench done");
        semihosting::process::exit(0)
    }
}
