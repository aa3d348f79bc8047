//! Real STM32L4 boards (B-L475E-IOT01A, NUCLEO-L476RG): 80 MHz PLL, two
//! ADCs (displacement, velocity), TIM3 PWM coil drive, IWDG, DWT cycle
//! counter. Pins and scaling are documented in `firmware/README.md`;
//! the per-board difference is only the pin table below.
use defmt_rtt as _;

use embassy_stm32::adc::{Adc, AdcChannel, AnyAdcChannel, SampleTime};
use embassy_stm32::gpio::{Input, Level, Output, OutputType, Pull, Speed};
use embassy_stm32::peripherals::{ADC1, ADC2, ADC3, IWDG, TIM3};
use embassy_stm32::time::khz;
use embassy_stm32::timer::low_level::CountingMode;
use embassy_stm32::timer::simple_pwm::{PwmPin, SimplePwm, SimplePwmChannel};
use embassy_stm32::usart::BufferedUart;

use super::flash_upload::Uplink;
use embassy_stm32::wdg::IndependentWatchdog;
use embassy_time::{Duration, Instant, Ticker};
use mre_algorithm::control::Controller;
use mre_algorithm::law::Command;
use mre_algorithm::overcurrent::Sense;
use mre_runtime::boot::{CalibrationTime, FirstCommand, ResetCause};
use mre_runtime::io::{open_loop_duty, Coil, DisplacementSensor, VelocitySensor};
use mre_runtime::pacing::Pacer;

#[cfg(feature = "board-b-l475e-iot01a")]
pub const NAME: &str = "B-L475E-IOT01A";
/// Arduino A0 = PC5 (ADC1_IN14) displacement, A1 = PC4 (ADC2_IN13) velocity,
/// D5 = PB4 (TIM3_CH1, AF2) coil PWM; LED2 = PB14 (green), B1 = PC13.
#[cfg(feature = "board-b-l475e-iot01a")]
macro_rules! board_pins {
    ($p:ident) => {
        ($p.PC5, $p.PC4, $p.PB4, $p.PB14, $p.PC13)
    };
}

/// The ST-LINK virtual COM port: USART1, RX = PB7, TX = PB6.
#[cfg(feature = "board-b-l475e-iot01a")]
macro_rules! vcp_pins {
    ($p:ident) => {
        ($p.USART1, $p.PB7, $p.PB6)
    };
}
#[cfg(feature = "board-b-l475e-iot01a")]
embassy_stm32::bind_interrupts!(struct Irqs {
    USART1 => embassy_stm32::usart::BufferedInterruptHandler<embassy_stm32::peripherals::USART1>;
    // The error capture first: embassy's handler clears FLASH_SR's error flags.
    FLASH => super::flash_upload::FlashErrorCapture, embassy_stm32::flash::InterruptHandler;
});
#[cfg(feature = "board-b-l475e-iot01a")]
use embassy_stm32::interrupt::USART1 as VCP_IRQ;

#[cfg(feature = "board-nucleo-l476rg")]
pub const NAME: &str = "NUCLEO-L476RG";
/// Arduino A0 = PA0 (ADC1_IN5) displacement, A1 = PA1 (ADC2_IN6) velocity,
/// D5 = PB4 (TIM3_CH1, AF2) coil PWM; LD2 = PA5 (green), B1 = PC13.
#[cfg(feature = "board-nucleo-l476rg")]
macro_rules! board_pins {
    ($p:ident) => {
        ($p.PA0, $p.PA1, $p.PB4, $p.PA5, $p.PC13)
    };
}
/// The ST-LINK virtual COM port: USART2, RX = PA3, TX = PA2.
#[cfg(feature = "board-nucleo-l476rg")]
macro_rules! vcp_pins {
    ($p:ident) => {
        ($p.USART2, $p.PA3, $p.PA2)
    };
}
#[cfg(feature = "board-nucleo-l476rg")]
embassy_stm32::bind_interrupts!(struct Irqs {
    USART2 => embassy_stm32::usart::BufferedInterruptHandler<embassy_stm32::peripherals::USART2>;
    // The error capture first: embassy's handler clears FLASH_SR's error flags.
    FLASH => super::flash_upload::FlashErrorCapture, embassy_stm32::flash::InterruptHandler;
});
#[cfg(feature = "board-nucleo-l476rg")]
use embassy_stm32::interrupt::USART2 as VCP_IRQ;

/// What is wired: a velocity transducer on the velocity channel (cargo feature).
pub const HAS_VELOCITY_SENSOR: bool = cfg!(feature = "velocity-sensor");

// Scaling (firmware/README.md, "Wiring"). 12-bit ADC, 3.3 V reference.
/// Nominal VDDA; boot calibration measures it against VREFINT.
const VREF_V: f32 = 3.3;
const ADC_FULL_SCALE: f32 = 4095.0;
/// Displacement: 0.3 V at 0 mm … 3.0 V at 25 mm. The ADC rails (a broken or
/// shorted wire) then read −2.8 mm and 27.8 mm: outside the valid range.
const X_ZERO_V: f32 = 0.3;
const X_MM_PER_V: f32 = 25.0 / 2.7;
/// Velocity transducer conditioned to 1.65 V ± 1.5 V for ±5 m/s (+ = compression).
const V_ZERO_V: f32 = 1.65;
const V_M_S_PER_V: f32 = 5.0 / 1.5;
/// Coil driver: 12 V into a 4 Ω coil, so 100 % duty is 3 A on average.
const COIL_FULL_SCALE_A: f32 = 3.0;
const PWM_KHZ: u32 = 20;
/// 24.5 + 12.5 ADC cycles at 80 MHz: 0.46 µs per conversion.
const SAMPLE_TIME: SampleTime = SampleTime::CYCLES24_5;
/// Coil current sense: a low-side shunt and amplifier, 1 V/A (0.1 Ω × 10),
/// on Arduino A4 = PC1 = ADC3_IN2 on both boards. ADC3 converts it as an
/// injected channel triggered by TIM3_CH4, whose compare sits at half the
/// coil PWM's on-time: every conversion lands at mid on-time.
const I_SENSE_V_PER_A: f32 = 1.0;
const I_SENSE_CHANNEL: u8 = 2;
/// ADC injected trigger JEXT4 = TIM3_CH4 (RM0351, "ADC1/2/3 external
/// triggers for injected channels"; ST's LL driver: `LL_ADC_INJ_TRIG_EXT_TIM3_CH4`
/// = `ADC_JSQR_JEXTSEL_2`, i.e. 4).
const JEXTSEL_TIM3_CH4: u8 = 4;
const JEXTEN_RISING: u8 = 1;

/// 50 periods at 10 kHz: long enough for the 1 Hz stats log, short enough
/// that a hung control loop releases the coil to the reset state quickly.
/// Set by [`Board::start`]: IWDG_PR = 0 (/4), IWDG_RLR = 39, (39 + 1) × 4 /
/// 32 kHz = 5 ms (RM0351 §36.4, "Prescaler register (IWDG_PR)" and
/// "Reload register (IWDG_RLR)").
const WATCHDOG_PR: u8 = 0;
const WATCHDOG_RLR: u16 = 39;
/// Boot, from reset to the first period, is about 2.4 M instructions in
/// the rehosted image (`firmware/rehost`), most of it the table's
/// validation (its order proof): 30 ms at one instruction per cycle, more
/// with flash wait states. So boot runs under a 500 ms timeout (PR /8, RLR
/// 1999) and `Board::start` narrows it to 5 ms.
const BOOT_WATCHDOG_TIMEOUT_US: u32 = 500_000;

/// The core clock: 16 MHz HSI / 2 × 20 / 2 = 80 MHz (PLL R). The one place
/// clocks are set. ADCs run from SYSCLK.
pub const SYSCLK_HZ: u32 = 80_000_000;
fn clock_config() -> embassy_stm32::Config {
    use embassy_stm32::rcc::{mux, Pll, PllMul, PllPreDiv, PllRDiv, PllSource, Sysclk};
    let mut config = embassy_stm32::Config::default();
    config.rcc.hsi = true;
    config.rcc.pll = Some(Pll {
        source: PllSource::HSI,
        prediv: PllPreDiv::DIV2,
        mul: PllMul::MUL20,
        divp: None,
        divq: None,
        divr: Some(PllRDiv::DIV2),
    });
    config.rcc.sys = Sysclk::PLL1_R;
    config.rcc.mux.adcsel = mux::Adcsel::SYS;
    config
}

pub fn core_clock_hz() -> u32 {
    SYSCLK_HZ
}

/// DWT cycle counter (enabled in [`init`]).
#[inline(always)]
pub fn cycles() -> u32 {
    cortex_m::peripheral::DWT::cycle_count()
}

/// Samples per boot zero (50 µs apart: 3.2 ms at rest).
const CAL_SAMPLES: usize = 64;

/// Sensors, coil and pacing: implements the core's I/O traits.
pub struct Io {
    adc_x: Adc<'static, ADC1>,
    ch_x: AnyAdcChannel<'static, ADC1>,
    velocity: Option<(Adc<'static, ADC2>, AnyAdcChannel<'static, ADC2>)>,
    /// ADC3 (kept for its clock and calibration; converts through the PAC
    /// once [`Io::start_current_sense`] ran) and the shunt channel.
    sense: (Adc<'static, ADC3>, AnyAdcChannel<'static, ADC3>),
    /// From calibration with the PWM off (0 if refused or not yet run).
    i_offset_a: f32,
    /// The latest shunt conversion without the offset (A).
    i_raw_a: f32,
    /// The VDDA and current-sense calibration deferred until at rest
    /// (`BootPlan`), and its outcome once, for the log.
    deferred: Option<mre_runtime::calibration::DeferredSenseZero>,
    deferred_done: Option<super::DeferredCalibration>,
    pwm: SimplePwmChannel<'static, TIM3>,
    max_duty: u32,
    ticker: Ticker,
    period: Duration,
    pacer: Pacer,
    /// From boot calibration (nominal if it was refused).
    v_per_lsb: f32,
    x_offset_mm: f32,
    v_zero_m_s: f32,
}

pub struct Board {
    pub io: Io,
    pub watchdog: IndependentWatchdog<'static, IWDG>,
    /// Read by `boot_table`, taken by `spawn_uplink` (`flash_upload`).
    uplink: Option<Uplink>,
    /// Power-on self-test results from `init` (`mre_runtime::boot::SelfTest`).
    sense_converts: bool,
    pwm_reads_back: bool,
}

/// The status LED and the user button B1 (active low on both boards).
pub struct Status {
    led: Output<'static>,
    button: Input<'static>,
}

impl super::StatusIo for Status {
    fn set_led(&mut self, on: bool) {
        self.led.set_level(if on { Level::High } else { Level::Low });
    }

    fn button_pressed(&self) -> bool {
        self.button.is_low()
    }
}

pub fn init(rate_hz: u32) -> (Board, Status) {
    // Read and clear the reset flags before anything can reset again.
    let csr = embassy_stm32::pac::RCC.csr().read().0;
    embassy_stm32::pac::RCC.csr().modify(|w| w.set_rmvf(true));
    // Supervised from here: the IWDG started at its reset configuration
    // (PR /4, RLR 0xFFF: 512 ms on the 32 kHz LSI, which the start forces
    // on; RM0351 "IWDG functional description", §36.4 registers)
    // before the clock set-up and the ADC busy-waits; set to
    // `BOOT_WATCHDOG_TIMEOUT_US` right after `embassy_stm32::init`.
    start_watchdog();
    let cause = ResetCause::from_rcc_csr(csr);
    let plan = cause.boot_plan();
    if cause.is_fault() {
        defmt::warn!("reset cause: {=str} (RCC_CSR {=u32:#010x})", cause.name(), csr);
    } else {
        defmt::info!("reset cause: {=str} (RCC_CSR {=u32:#010x})", cause.name(), csr);
    }
    // A halted core (breakpoint) must not be reset by the watchdog.
    embassy_stm32::pac::DBGMCU.apb1fzr1().modify(|w| w.set_iwdg(true));

    let p = embassy_stm32::init(clock_config());
    let mut watchdog = IndependentWatchdog::new(p.IWDG, BOOT_WATCHDOG_TIMEOUT_US);
    watchdog.unleash();
    watchdog.pet();
    let (pin_x, pin_v, pin_pwm, pin_led, pin_button) = board_pins!(p);
    let pin_i = p.PC1;
    let status = Status {
        led: Output::new(pin_led, Level::Low, Speed::Low),
        button: Input::new(pin_button, Pull::None),
    };

    // SAFETY: only DCB/DWT are touched, once, before anything else uses them.
    let mut core = unsafe { cortex_m::Peripherals::steal() };
    core.DCB.enable_trace();
    core.DWT.enable_cycle_counter();

    let pwm = SimplePwm::new(
        p.TIM3,
        Some(PwmPin::new(pin_pwm, OutputType::PushPull)),
        None,
        None,
        None,
        khz(PWM_KHZ),
        CountingMode::EdgeAlignedUp,
    );
    let mut ch = pwm.split().ch1;
    let max_duty = ch.max_duty_cycle();
    // The fail-safe duty before anything else (the ADCs' calibration
    // busy-waits below) when the reset may have struck mid-impact.
    if plan.first == FirstCommand::FailSafeAtOnce {
        ch.set_duty_cycle(duty_compare(fail_safe_duty(), max_duty));
    }
    ch.enable();

    let period = Duration::from_hz(u64::from(rate_hz));
    let mut io = Io {
        adc_x: Adc::new(p.ADC1),
        ch_x: pin_x.degrade_adc(),
        velocity: HAS_VELOCITY_SENSOR.then(|| (Adc::new(p.ADC2), pin_v.degrade_adc())),
        sense: (Adc::new(p.ADC3), pin_i.degrade_adc()),
        i_offset_a: 0.0,
        i_raw_a: 0.0,
        deferred: None,
        deferred_done: None,
        pwm: ch,
        max_duty,
        ticker: Ticker::every(period),
        period,
        pacer: Pacer::start(Instant::now().as_ticks(), period.as_ticks()),
        v_per_lsb: VREF_V / ADC_FULL_SCALE,
        x_offset_mm: 0.0,
        v_zero_m_s: 0.0,
    };
    // The first coil command, as the reset cause decides (firmware/README.md,
    // "Reset paths"): a reset that may strike mid-impact holds the fail-safe
    // current (stiffest damper) at once and calibrates VDDA and the current
    // sense later, at rest; a reset by the pin alone calibrates them first
    // with the PWM at 0 % (coil off).
    match plan.first {
        FirstCommand::FailSafeAtOnce => io.set_duty(fail_safe_duty()),
        FirstCommand::FailSafeAfterCalibration => {
            io.calibrate_vdda();
            io.calibrate_current_sense();
        }
    }
    if plan.calibration == CalibrationTime::DeferredUntilAtRest {
        defmt::info!("calibration: VDDA and current sense deferred until the damper is at rest");
        io.deferred = Some(mre_runtime::calibration::DeferredSenseZero::default());
    }
    let adc3_enabled = io.start_current_sense();
    // Until the loop runs, hold the fail-safe current (stiffest damper).
    io.set_duty(fail_safe_duty());
    // Power-on self-test, first two checks (the table CRC is `main`'s):
    // the current sense converts (JEOC within 10 PWM periods) and the PWM
    // duty reads back from TIM3 with the drive on the pin.
    let self_test = (
        adc3_enabled && io.sense_converts(),
        io.pwm_reads_back(duty_compare(fail_safe_duty(), io.max_duty)),
    );
    io.calibrate_at_rest();
    feed_watchdog();
    let flash = embassy_stm32::flash::Flash::new(p.FLASH, Irqs);
    let (vcp, vcp_rx, vcp_tx) = vcp_pins!(p);
    let uart = match (
        cortex_m::singleton!(: [u8; 64] = [0; 64]),
        cortex_m::singleton!(: [u8; 256] = [0; 256]),
    ) {
        (Some(tx_buf), Some(rx_buf)) => {
            match BufferedUart::new(
                vcp,
                vcp_rx,
                vcp_tx,
                tx_buf,
                rx_buf,
                Irqs,
                embassy_stm32::usart::Config::default(),
            ) {
                Ok(uart) => Some(uart),
                Err(e) => {
                    defmt::error!("table upload disabled: VCP UART config {}", e);
                    None
                }
            }
        }
        _ => None,
    };
    // The VCP interrupt only fills a ring buffer: below the control task (P1).
    {
        use embassy_stm32::interrupt::{InterruptExt, Priority};
        VCP_IRQ.set_priority(Priority::P3);
        embassy_stm32::interrupt::FLASH.set_priority(Priority::P3);
    }
    let uplink = Some(Uplink::new(uart, flash));
    let (sense_converts, pwm_reads_back) = self_test;
    (
        Board {
            io,
            watchdog,
            uplink,
            sense_converts,
            pwm_reads_back,
        },
        status,
    )
}

/// KR = 0xCCCC: starts the IWDG (a no-op when it runs). RM0351 §36.4,
/// "Key register (IWDG_KR)"; the key is ST's LL driver's `LL_IWDG_KEY_ENABLE`.
fn start_watchdog() {
    embassy_stm32::pac::IWDG
        .kr()
        .write(|w| w.set_key(embassy_stm32::pac::iwdg::vals::Key::START));
}

/// KR = 0xAAAA: reloads the IWDG counter (boot's calibration loops).
fn feed_watchdog() {
    embassy_stm32::pac::IWDG
        .kr()
        .write(|w| w.set_key(embassy_stm32::pac::iwdg::vals::Key::RESET));
}

/// TIM3's compare value for `duty` ∈ [0, 1] (`as` saturates).
fn duty_compare(duty: f32, max_duty: u32) -> u32 {
    (duty * max_duty as f32) as u32
}

/// The installed fail-safe current's duty (`super::failsafe_current_a`).
fn fail_safe_duty() -> f32 {
    open_loop_duty(super::failsafe_current_a(), COIL_FULL_SCALE_A)
}

impl Io {
    fn volts(&self, code: u16) -> f32 {
        f32::from(code) * self.v_per_lsb
    }

    /// Boot calibration (firmware/README.md): VDDA from VREFINT (here), the
    /// current-sense zero with the PWM off, then the displacement offset and
    /// the velocity zero with the mass at rest. Each result is range-checked
    /// (`mre_runtime::calibration`) and logged; a refused one leaves the
    /// nominal scaling.
    fn calibrate_vdda(&mut self) {
        match self.measure_vdda() {
            Ok(vdda) => defmt::info!("calibration: VDDA {=f32} V", vdda),
            Err(e) => defmt::warn!(
                "calibration: VDDA refused ({=str}), assuming {=f32} V",
                e.as_str(),
                VREF_V
            ),
        }
    }

    /// One VREFINT conversion (~3 µs): VDDA, applied if accepted. Does not
    /// log (the control task calls it for a deferred calibration).
    fn measure_vdda(&mut self) -> Result<f32, mre_runtime::calibration::CalError> {
        let mut vref = self.adc_x.enable_vrefint();
        let raw = self.adc_x.blocking_read(&mut vref, SampleTime::CYCLES247_5);
        let vdda = mre_runtime::calibration::vdda_v(raw, vref.calibrated_value())?;
        self.v_per_lsb = vdda / ADC_FULL_SCALE;
        Ok(vdda)
    }

    /// The current-sense offset, with the coil off (PWM at 0 %).
    fn calibrate_current_sense(&mut self) {
        use mre_runtime::calibration::I_SENSE_REST;
        self.i_offset_a = self.rest_zero("current sense zero (A)", I_SENSE_REST, |io| {
            let (adc, ch) = &mut io.sense;
            let code = adc.blocking_read(ch, SAMPLE_TIME);
            io.volts(code) / I_SENSE_V_PER_A
        });
    }

    /// From here on ADC3 converts the shunt once per PWM period, triggered
    /// by TIM3_CH4 at mid on-time (embassy-stm32 0.6's ADC driver for the
    /// L4 has no triggered mode: its ring-buffered mode ignores the trigger
    /// and there is no injected API, so this is PAC). TIM3_CH4 runs in PWM
    /// mode 2: OC4REF rises at CCR4 = CCR1 / 2 ([`Io::set_duty`]).
    /// Returns false when ADC3 did not become ready (the self-test fails).
    fn start_current_sense(&mut self) -> bool {
        use embassy_stm32::pac;
        use embassy_stm32::pac::timer::vals::Ocm;
        pac::TIM3.ccmr_output(1).modify(|w| {
            w.set_ocm(1, Ocm::PWM_MODE2);
            w.set_ocpe(1, true);
        });
        pac::TIM3.ccr(3).write(|w| w.set_ccr(1));
        // CC4E: the channel 4 compare output enabled (RM0351 §31.4.11,
        // TIMx_CCER), so OC4REF's edge reaches the ADC as TIM3_CH4. CH4 has
        // no pin mapped to AF2 here, so nothing is driven.
        // RM0351 §31.4.11, chapter 18 (ADC) and §18.4.6 are corroborated by
        // public citations; the ADC sections below are cited by title
        // (firmware/rehost/stm32l4.py says why). The bits are
        // checked against ST's CMSIS `stm32l475xx.h` V1.3.1 and LL ADC driver
        // (vendored in github.com/nickfox-taterli/stm32l4_disco_test,
        // 21e0a73): TIM_CCER_CC4E bit 12, ADC_CFGR_JQDIS bit 31, ADC_ISR_JEOC
        // bit 5, LL_ADC_INJ_TRIG_EXT_TIM3_CH4 = JEXTSEL 4 (firmware/README.md).
        pac::TIM3.ccer().modify(|w| w.set_cce(3, true));
        // JQDIS = 1: the injected queue disabled (RM0351 "ADC configuration
        // register (ADC_CFGR)" bit 31; "Queue of context for injected
        // conversions"):
        // the JSQR below is the one context, kept after every sequence, and
        // cannot be consumed into an empty queue that ignores triggers. Its
        // reset value is 1; set explicitly rather than trusted (the stm32
        // PAC has no field for it: raw bit). Written with JADSTART = 0.
        pac::ADC3.cfgr().modify(|w| w.0 |= 1 << 31);
        pac::ADC3.jsqr().write(|w| {
            w.set_jl(0);
            w.set_jextsel(JEXTSEL_TIM3_CH4);
            w.set_jexten(JEXTEN_RISING);
            w.set_jsq(0, I_SENSE_CHANNEL);
        });
        // ADC3 enabled before JADSTART: embassy-stm32 0.6 (`adc/v3.rs`)
        // sets ADEN only inside a blocking read, and ADC3's only one is the
        // pin-reset calibration; JADSTART with ADEN = 0 is ignored (RM0351
        // "ADC on-off control (ADEN, ADDIS, ADRDY)": ADRDY cleared by writing
        // 1, ADEN = 1, wait for ADRDY; "ADC control register (ADC_CR)":
        // JADSTART is set only with ADEN = 1
        // and ADDIS = 0). Bounded: ADRDY takes t_STAB (about 1 ADC cycle)
        // plus a few; 10 000 polls are over 0.3 ms at 80 MHz.
        if !pac::ADC3.cr().read().aden() {
            pac::ADC3.isr().write(|w| w.set_adrdy(true));
            pac::ADC3.cr().modify(|w| w.set_aden(true));
            let mut polls = 0u32;
            while !pac::ADC3.isr().read().adrdy() {
                polls = polls.saturating_add(1);
                if polls > 10_000 {
                    return false;
                }
            }
        }
        pac::ADC3.cr().modify(|w| w.set_jadstart(true));
        true
    }

    /// Self-test: an injected conversion ends (JEOC) within 10 PWM periods
    /// of the trigger running (0.5 ms at 20 kHz). JEOC is left set: the
    /// first period reads that conversion.
    fn sense_converts(&mut self) -> bool {
        use embassy_stm32::pac;
        let deadline = Instant::now() + Duration::from_micros(10 * 1_000 / u64::from(PWM_KHZ));
        loop {
            if pac::ADC3.isr().read().jeoc() {
                return true;
            }
            if Instant::now() > deadline {
                return false;
            }
        }
    }

    /// Self-test: TIM3 counts, CH1's output is enabled, CCR1 holds
    /// `compare`, and PB4 is in its alternate function (TIM3_CH1).
    fn pwm_reads_back(&self, compare: u32) -> bool {
        use embassy_stm32::pac;
        pac::TIM3.cr1().read().cen()
            && pac::TIM3.ccer().read().cce(0)
            && u32::from(pac::TIM3.ccr(0).read().ccr()) == compare
            && pac::GPIOB.moder().read().moder(4) == pac::gpio::vals::Moder::ALTERNATE
    }

    /// The displacement offset and the velocity zero with the mass at rest.
    fn calibrate_at_rest(&mut self) {
        use mre_runtime::calibration::{V_REST, X_REST};
        self.x_offset_mm = self.rest_zero("x offset (mm)", X_REST, |io| io.read_x_mm());
        if self.velocity.is_some() {
            self.v_zero_m_s = self.rest_zero("velocity zero (m/s)", V_REST, |io| io.read_v_m_s().unwrap_or(f32::NAN));
        }
    }

    /// The zero of one sensor at rest, 50 µs apart, or 0 if refused (logged).
    fn rest_zero(
        &mut self,
        what: &str,
        limits: mre_runtime::calibration::RestLimits,
        mut read: impl FnMut(&mut Self) -> f32,
    ) -> f32 {
        let mut samples = [0.0f32; CAL_SAMPLES];
        for s in samples.iter_mut() {
            *s = read(self);
            embassy_time::block_for(Duration::from_micros(50));
            // Boot runs under the 500 ms boot timeout: each calibration is
            // 3.2 ms, and fed per sample.
            feed_watchdog();
        }
        match mre_runtime::calibration::rest_offset(&samples, 0.0, limits) {
            Ok(zero) => {
                defmt::info!("calibration: {=str} {=f32}", what, zero);
                zero
            }
            Err(e) => {
                defmt::warn!("calibration: {=str} refused ({=str}), using 0", what, e.as_str());
                0.0
            }
        }
    }

    fn set_duty(&mut self, duty: f32) {
        // duty ∈ [0, 1] by construction; `as` saturates anyway.
        let compare = duty_compare(duty, self.max_duty);
        self.pwm.set_duty_cycle(compare);
        // The current-sense trigger at mid on-time; at least 1 so that a
        // shorted switch at 0 % duty is still sampled.
        let mid = (compare / 2).clamp(1, u32::from(u16::MAX)) as u16;
        embassy_stm32::pac::TIM3.ccr(3).write(|w| w.set_ccr(mid));
    }
}

impl super::BoardIo for Io {
    /// Waits for the next tick of the control rate. Ticks skipped by a
    /// stall are counted as overruns and the ticker re-phased, instead of
    /// letting it catch up with periods microseconds apart.
    /// Returns the number of ticks missed.
    async fn next_period(&mut self, ctl: &mut Controller) -> u32 {
        self.ticker.next().await;
        let missed = self.pacer.wake(Instant::now().as_ticks());
        if missed > 0 {
            self.ticker.reset();
            ctl.record_missed_periods(missed);
        }
        missed
    }

    /// True when this period's work ended after the next tick was due.
    /// A deferred calibration takes this period's conversion while the
    /// damper rests with the coil commanded off (`DeferredSenseZero`), and
    /// VDDA with its last sample.
    fn finish_period(&mut self, cmd: &Command, ctl: &Controller) -> bool {
        if let Some(zero) = self.deferred.as_mut() {
            if let Some(sense_zero_a) = zero.push(ctl.is_at_rest(), cmd.current_a, self.i_raw_a) {
                self.deferred = None;
                if let Ok(a) = sense_zero_a {
                    self.i_offset_a = a;
                }
                let vdda = self.measure_vdda();
                self.deferred_done = Some(super::DeferredCalibration { vdda, sense_zero_a });
            }
        }
        self.pacer.overran(Instant::now().as_ticks())
    }

    fn take_deferred_calibration(&mut self) -> Option<super::DeferredCalibration> {
        self.deferred_done.take()
    }

    /// No frame link on hardware.
    fn link_stats(&self) -> Option<mre_protocol::frame::LinkStats> {
        None
    }

    /// The latest mid-on-time shunt conversion, with its proof of being new:
    /// ADC3's JEOC (end of injected conversion, set by hardware, cleared by
    /// writing 1; RM0351 "ADC interrupt and status register (ADC_ISR)"). No
    /// JEOC since the last period:
    /// `Stale` (a dead trigger chain or ADC reads the old JDR1 for ever).
    /// JEOC is cleared before JDR1 is read, so a conversion that ends in
    /// between is counted new next period, never lost.
    fn coil_current(&mut self) -> Option<Sense> {
        use embassy_stm32::pac;
        if !pac::ADC3.isr().read().jeoc() {
            return Some(Sense::Stale);
        }
        pac::ADC3.isr().write(|w| w.set_jeoc(true));
        let code = pac::ADC3.jdr(0).read().jdata();
        self.i_raw_a = self.volts(code) / I_SENSE_V_PER_A;
        Some(Sense::Fresh(self.i_raw_a - self.i_offset_a))
    }
}

impl DisplacementSensor for Io {
    fn read_x_mm(&mut self) -> f32 {
        let code = self.adc_x.blocking_read(&mut self.ch_x, SAMPLE_TIME);
        (self.volts(code) - X_ZERO_V) * X_MM_PER_V - self.x_offset_mm
    }
}

impl VelocitySensor for Io {
    fn read_v_m_s(&mut self) -> Option<f32> {
        let (adc, ch) = self.velocity.as_mut()?;
        let code = adc.blocking_read(ch, SAMPLE_TIME);
        Some((self.volts(code) - V_ZERO_V) * V_M_S_PER_V - self.v_zero_m_s)
    }
}

impl Coil for Io {
    fn set_current_a(&mut self, current_a: f32) {
        self.set_duty(open_loop_duty(current_a, COIL_FULL_SCALE_A));
    }
}

/// `bench`: DWT cycles of the model step alone (inverse solve at a few
/// operating points, which includes branch data, five Horner quartics and
/// the interpolation), min/mean/max.
#[cfg(feature = "bench")]
pub fn bench_model_step(table: Option<&mre_algorithm::Table>) {
    use mre_algorithm::Branch;
    let Some(table) = table else { return };
    let (mut min, mut max, mut sum) = (u32::MAX, 0u32, 0u32);
    let points = [(0.1f32, 600.0f32), (0.2, 1726.25), (0.5, 3000.0), (0.9, 9000.0)];
    for &(x_mm, force_n) in &points {
        let t0 = cycles();
        let r = table.current_for_branch(core::hint::black_box(x_mm), Branch::Compression, force_n);
        let dt = cycles().wrapping_sub(t0);
        core::hint::black_box(r);
        min = min.min(dt);
        max = max.max(dt);
        sum = sum.wrapping_add(dt);
    }
    defmt::info!(
        "bench model step cycles min/mean/max {=u32}/{=u32}/{=u32}",
        min,
        sum / points.len() as u32,
        max
    );
}

/// The coil as the fault handlers drive it, through the PAC only: TIM3's
/// CCR1 when TIM3 drives the pin (PB4 in alternate function), else the pin
/// low (the reset state's safe level).
struct Tim3Coil;

impl super::FaultCoil for Tim3Coil {
    fn drive_running(&self) -> bool {
        use embassy_stm32::pac;
        pac::RCC.apb1enr1().read().tim3en()
            && pac::TIM3.cr1().read().cen()
            && pac::GPIOB.moder().read().moder(4) == pac::gpio::vals::Moder::ALTERNATE
    }

    fn hold_current_a(&mut self, current_a: f32) {
        use embassy_stm32::pac;
        let arr = pac::TIM3.arr().read().arr();
        let compare = (open_loop_duty(current_a, COIL_FULL_SCALE_A) * (arr as f32 + 1.0)) as u32;
        pac::TIM3
            .ccr(0)
            .write(|w| w.set_ccr(compare.min(u32::from(u16::MAX)) as u16));
    }

    fn off(&mut self) {
        super::coil_pin_low();
    }
}

/// The coil to its safe state from a panic or a HardFault
/// (`super::coil_safe_from_a_fault`), then the watchdog started (a no-op if
/// it runs) and never fed: the chip resets into the reset path of
/// `BootPlan` (watchdog: the fail-safe at once).
fn coil_safe_from_a_fault() {
    super::coil_safe_from_a_fault(&mut Tim3Coil);
    // IWDG_KR = 0xCCCC starts the watchdog (RM0351 §36.4, "Key register
    // (IWDG_KR)"; the key is ST's LL driver's LL_IWDG_KEY_ENABLE).
    embassy_stm32::pac::IWDG
        .kr()
        .write(|w| w.set_key(embassy_stm32::pac::iwdg::vals::Key::START));
}

fn wait_for_the_watchdog() -> ! {
    loop {
        cortex_m::asm::nop();
    }
}

/// Set by the first panic: a panic inside the handler (its defmt frame)
/// skips the log and goes straight to the watchdog.
static PANICKING: core::sync::atomic::AtomicBool = core::sync::atomic::AtomicBool::new(false);

#[panic_handler]
fn panic(info: &core::panic::PanicInfo) -> ! {
    // Interrupts masked first (PRIMASK): the control interrupt can no
    // longer overwrite CCR1 or feed the watchdog.
    cortex_m::interrupt::disable();
    // The coil next: the log may stall (RTT) and must not delay it.
    coil_safe_from_a_fault();
    if !PANICKING.swap(true, core::sync::atomic::Ordering::Relaxed) {
        let (file, line) = info.location().map_or(("?", 0), |l| (l.file(), l.line()));
        defmt::error!(
            "panic at {=str}:{=u32}; coil at its safe state, reset by the watchdog",
            file,
            line
        );
    }
    wait_for_the_watchdog()
}

/// The HardFault handler, entered from `HardFault` (`board/mod.rs`) on a
/// fresh stack: a stack overflow ends here too.
#[no_mangle]
extern "C" fn mre_hard_fault() -> ! {
    cortex_m::interrupt::disable();
    coil_safe_from_a_fault();
    wait_for_the_watchdog()
}

/// NMI. A flash double-ECC error in the table page (an upload torn by power
/// loss; RM0351 "Error code correction (ECC)" in the flash chapter: ECCD in
/// FLASH_ECCR, the
/// failing bank and address in BK_ECC and ADDR_ECC, an NMI raised) is
/// cleared (ECCD, write 1) and noted, and the interrupted page read
/// returns: `flash_upload` then refuses the page and boot flies the
/// built-in table. Any other NMI (an ECC error in the image, the clock
/// security system) is a fault: the coil safe, the watchdog resets.
// SAFETY (cortex-m-rt requires `unsafe fn` for NMI, which can preempt
// critical sections): the handler touches only FLASH_ECCR, an atomic flag
// and, on the fault path, the same registers as the HardFault handler.
#[cortex_m_rt::exception]
unsafe fn NonMaskableInt() {
    use embassy_stm32::pac;
    let eccr = pac::FLASH.eccr().read();
    if eccr.eccd() && super::flash_upload::in_table_page(eccr.bk_ecc(), eccr.addr_ecc()) {
        pac::FLASH.eccr().modify(|w| w.set_eccd(true));
        super::flash_upload::note_table_page_ecc();
        return;
    }
    cortex_m::interrupt::disable();
    coil_safe_from_a_fault();
    wait_for_the_watchdog()
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

    fn boot_table(
        &mut self,
        built_in: &mre_algorithm::table::TableImage<'_>,
        rate_hz: u32,
    ) -> mre_protocol::upload::BootTable {
        super::flash_upload::boot_table(&mut self.uplink, built_in, rate_hz)
    }

    fn spawn_uplink(&mut self, spawner: &embassy_executor::Spawner) {
        super::flash_upload::spawn_uplink(spawner, &mut self.uplink)
    }

    /// The power-on self-test: `init`'s two hardware checks and the table's.
    fn self_test(&self, table_crc_holds: bool) -> mre_runtime::boot::SelfTest {
        mre_runtime::boot::SelfTest {
            sense_converts: self.sense_converts,
            pwm_reads_back: self.pwm_reads_back,
            table_crc_holds,
        }
    }

    /// The installed fail-safe current to the coil (main, once the boot
    /// configuration is known; `super::set_failsafe_current_a`).
    fn hold_fail_safe(&mut self) {
        self.io.set_duty(fail_safe_duty());
    }

    /// Starts the ticker and the watchdog right before the first period.
    fn start(&mut self) {
        self.io.ticker.reset();
        self.io.pacer = Pacer::start(Instant::now().as_ticks(), self.io.period.as_ticks());
        // The 5 ms period of the running loop (RM0351 IWDG "Register access
        // protection": KR = 0x5555
        // unlocks PR and RLR; the new values load at the next reload).
        use embassy_stm32::pac::iwdg::vals::{Key, Pr};
        let iwdg = embassy_stm32::pac::IWDG;
        iwdg.kr().write(|w| w.set_key(Key::ENABLE));
        iwdg.pr().write(|w| w.set_pr(Pr::from_bits(WATCHDOG_PR)));
        iwdg.rlr().write(|w| w.set_rl(WATCHDOG_RLR));
        self.watchdog.unleash();
        self.watchdog.pet();
    }

    /// Holds the fail-safe coil current until the watchdog resets the chip
    /// (configuration refused): started here and never fed, so a fatal fault
    /// at boot retries from reset instead of sleeping for ever.
    fn halt_fail_safe(mut self) -> ! {
        self.io.set_duty(fail_safe_duty());
        // The watchdog is running since `init`: not feeding it resets the chip.
        self.watchdog.unleash();
        loop {
            cortex_m::asm::wfi();
        }
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
