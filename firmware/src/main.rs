//! Firmware entry point. The board image is built only for
//! `thumbv7em-none-eabihf` (`cargo fw`); on the host this is a stub so that
//! `cargo test` and `cargo clippy --all-targets` cover the whole workspace.
//!
//! One embassy task runs the control loop: wait for the period (a `Ticker`
//! on hardware, the next sample frame in PIL), run the core's
//! [`ControllerIo::step_io`](mre_runtime::io::ControllerIo::step_io), account
//! for overruns, feed the watchdog while every thread-mode task checks in
//! (`mre_runtime::watchdog`). On hardware it runs on an
//! `InterruptExecutor` (UART4's vector, which nothing else uses) at high
//! priority; it never logs itself but posts events to a channel that the
//! thread-mode main task drains into defmt, so a stalled log reader (RTT
//! buffer full) can never hold up a control period. Events that do not fit
//! are counted and reported with the next stats line.
#![cfg_attr(target_os = "none", no_std, no_main)]

#[cfg(not(target_os = "none"))]
fn main() {
    eprintln!("mre-firmware runs on the board: build it with `cargo fw`");
}

#[cfg(target_os = "none")]
mod board;

#[cfg(target_os = "none")]
mod fw {
    use crate::board::{self, Board, BoardIo, StatusIo};
    use core::sync::atomic::{AtomicBool, AtomicU32, Ordering};
    use embassy_executor::Spawner;
    use embassy_sync::blocking_mutex::raw::CriticalSectionRawMutex;
    use embassy_sync::channel::Channel;
    use mre_algorithm::control::{Controller, Stats, DEFAULT_RATE_HZ};
    use mre_protocol::frame::LinkStats;
    use mre_protocol::upload::TableSource;
    use mre_runtime::io::ControllerIo;

    // Log lines carry embassy-time's µs since boot.
    defmt::timestamp!("{=u64:us}", embassy_time::Instant::now().as_micros());

    /// What the control task reports; logged in thread mode.
    enum Event {
        /// B1 pressed: faults cleared (at rest) or the clear refused.
        ClearRequest {
            cleared: bool,
            latched: u32,
        },
        Overrun {
            period: u32,
        },
        Missed {
            ticks: u32,
            period: u32,
        },
        FaultLatched {
            latched: u32,
            period: u32,
        },
        Stats {
            stats: Stats,
            new_periods: u32,
            link: Option<LinkStats>,
        },
        Calibrated(board::DeferredCalibration),
    }
    static EVENTS: Channel<CriticalSectionRawMutex, Event, 16> = Channel::new();
    /// Events the channel had no room for; `mre pil` reads it by symbol.
    #[no_mangle]
    static MRE_LOG_EVENTS_DROPPED: AtomicU32 = AtomicU32::new(0);
    /// Latched faults (written by the control task): the status LED, the fault handlers.
    use board::LATCHED_FAULTS as LATCHED;
    /// Set by a press of B1, taken by the control task.
    static CLEAR_REQUEST: AtomicBool = AtomicBool::new(false);

    /// Thread-mode check-ins for the watchdog (ms since boot,
    /// `mre_runtime::watchdog`): the status task every 50 ms, and the log task
    /// with every event (a stats line at least once a second). The upload
    /// task waits for bytes and is not a heartbeat: a busy loop in it (or in
    /// any thread-mode task) starves the status task and is caught there.
    const STATUS_TASK: usize = 0;
    const LOG_TASK: usize = 1;
    static CHECK_INS: [AtomicU32; 2] = [AtomicU32::new(0), AtomicU32::new(0)];
    const DEADLINES_MS: [u32; 2] = [200, 3_000];

    fn now_ms() -> u32 {
        embassy_time::Instant::now().as_millis() as u32
    }

    fn check_in(task: usize) {
        if let Some(slot) = CHECK_INS.get(task) {
            slot.store(now_ms(), Ordering::Relaxed);
        }
    }

    /// True when every thread-mode task checked in within its deadline.
    fn thread_tasks_on_time() -> bool {
        let tasks = core::array::from_fn::<_, 2, _>(|k| mre_runtime::watchdog::CheckIn {
            last_ms: CHECK_INS[k].load(Ordering::Relaxed),
            deadline_ms: DEADLINES_MS[k],
        });
        mre_runtime::watchdog::may_feed(now_ms(), &tasks)
    }

    /// Never blocks: a full channel drops the event and counts it.
    fn post(event: Event) {
        if EVENTS.try_send(event).is_err() {
            MRE_LOG_EVENTS_DROPPED.fetch_add(1, Ordering::Relaxed);
        }
    }

    #[cfg(feature = "hw")]
    static CONTROL_EXECUTOR: embassy_executor::InterruptExecutor = embassy_executor::InterruptExecutor::new();

    #[cfg(feature = "hw")]
    use embassy_stm32::interrupt;

    #[cfg(feature = "hw")]
    #[interrupt]
    #[allow(non_snake_case)]
    unsafe fn UART4() {
        // SAFETY: the executor was started on this vector in `main`.
        unsafe { CONTROL_EXECUTOR.on_interrupt() }
    }

    /// The table this image flies: by default the one `mre tables` generated
    /// from the committed model (`firmware/src/generated_table.rs`); with the
    /// `table-paper` feature the paper's Table 4.
    #[cfg(not(feature = "table-paper"))]
    mod flown {
        pub use mre_algorithm::generated_table::{GENERATED_TABLE as IMAGE, SOURCE_DATASET_SHA256};
        pub const NAME: &str = "generated";
    }
    #[cfg(feature = "table-paper")]
    mod flown {
        pub use mre_algorithm::table::PAPER_TABLE4 as IMAGE;
        pub const SOURCE_DATASET_SHA256: &str = "";
        pub const NAME: &str = "paper Table 4";
    }

    /// Control rate: 10 kHz, or 20 kHz with the `rate-20khz` feature.
    const RATE_HZ: u32 = if cfg!(feature = "rate-20khz") {
        20_000
    } else {
        DEFAULT_RATE_HZ
    };

    #[embassy_executor::main]
    async fn main(spawner: Spawner) {
        // The coil pin is already low (`__pre_init`, board/mod.rs); `init`
        // commands the fail-safe as the reset cause decides.
        let (mut board, status) = board::Selected::init(RATE_HZ);
        defmt::info!(
            "mre-firmware on {=str}, core clock {=u32} Hz",
            board::Selected::NAME,
            board::Selected::core_clock_hz()
        );

        // A rejected table is not fatal: the controller latches TABLE_FAULT
        // and commands the fail-safe current every period. An uploaded table
        // (flash page, `mre upload`) is preferred; an erased, torn or invalid
        // page falls back to the built-in one (`mre_protocol::upload`).
        let boot = board.boot_table(&flown::IMAGE, RATE_HZ);
        match (&boot.source, &boot.table) {
            (TableSource::Uploaded, Ok(t)) => defmt::info!(
                "table uploaded (flash page) format v{=u16}: {=usize} currents, CRC {=u32:#010x} OK",
                t.version(),
                t.entries().len(),
                t.crc32()
            ),
            (TableSource::BuiltIn(why), Ok(t)) => defmt::info!(
                "no uploaded table ({=str}): table {=str} format v{=u16}: {=usize} currents, CRC {=u32:#010x} OK, data set sha256 {=str}",
                why.as_str(),
                flown::NAME,
                t.version(),
                t.entries().len(),
                t.crc32(),
                flown::SOURCE_DATASET_SHA256
            ),
            (_, Err(e)) => defmt::error!(
                "table {=str} format v{=u16} stored CRC {=u32:#010x} REJECTED: {=str}, data set sha256 {=str}",
                flown::NAME,
                flown::IMAGE.version,
                flown::IMAGE.crc32,
                table_error_name(e),
                flown::SOURCE_DATASET_SHA256
            ),
        }
        if let Some(rate_hz) = boot.uploaded_rate_ignored_hz {
            defmt::warn!(
                "uploaded configuration is for {=u32} Hz, the image runs {=u32} Hz: its table with the image's defaults",
                rate_hz,
                RATE_HZ
            );
        }
        if let Ok(t) = &boot.table {
            let i = t.installation();
            defmt::info!(
                "installation ({=str}): mass {=f32} kg, stroke {=f32} mm, coil {=f32} A {=f32} ohm, supply {=f32} V, x sensor {=f32} mm, v sensor {=f32} m/s, impacts {=f32}..{=f32} m/s",
                if t.version() >= 3 { "from the table" } else { "format 1/2 table carries none: the defaults" },
                i.mass_kg, i.usable_stroke_mm, i.coil_rating_a, i.coil_resistance_ohm, i.supply_v,
                i.x_sensor_range_mm, i.v_sensor_full_scale_m_s, i.impact_v_min_m_s, i.impact_v_max_m_s
            );
        }
        let table = boot.table;
        let table_crc_holds = table.is_ok();
        let cfg = match boot.config {
            Ok(cfg) => {
                // The installed coil's fail-safe from here on (init, the
                // halt, the fault handlers): never above its rating.
                board::set_failsafe_current_a(cfg.law.failsafe_current_a);
                board.hold_fail_safe();
                cfg
            }
            Err(e) => {
                // Only a build with a bad RATE_HZ gets here: hold the coil at
                // the fail-safe duty and let the watchdog (never fed) reset.
                defmt::error!("control config refused: {=str}", config_error_name(&e));
                board.halt_fail_safe()
            }
        };
        let mut ctl = match Controller::new(cfg, table) {
            Ok(c) => c,
            Err(e) => {
                defmt::error!("controller refused config: {=str}", config_error_name(&e));
                board.halt_fail_safe()
            }
        };
        // Power-on self-test before arming: one clear report either way; a
        // failed check latches its fault so the controller never arms and
        // holds the fail-safe (the LED blinks the fault's code, every
        // command frame and stats line carries it).
        let self_test = board.self_test(table_crc_holds);
        match self_test.first_failure() {
            None => defmt::info!("self-test passed: current sense converts, PWM duty reads back, table CRC holds"),
            Some(why) => {
                let faults = self_test.faults();
                ctl.latch_boot_faults(faults);
                LATCHED.store(ctl.latched().0, Ordering::Relaxed);
                defmt::error!(
                    "BOOT FAILURE: self-test: {=str}; not armed, coil at the fail-safe {=f32} A (latched {=u32:#010x})",
                    why,
                    board::failsafe_current_a(),
                    faults.0
                );
            }
        }
        // Instruction-count benchmark image: measure, then exit QEMU.
        #[cfg(all(feature = "pil", feature = "bench"))]
        board::icount::run(&mut ctl);

        defmt::info!(
            "control {=u32} Hz, fail-safe {=f32} A, output {=f32}..{=f32} A, slew {=f32} A/s, stroke {=f32} mm, mass {=f32} kg",
            cfg.rate_hz,
            cfg.law.failsafe_current_a,
            cfg.law.current_min_a,
            cfg.law.current_max_a,
            cfg.law.slew_a_per_s,
            cfg.law.stroke_max_mm,
            cfg.law.mass_kg
        );
        // Every supervised task starts on time.
        check_in(STATUS_TASK);
        check_in(LOG_TASK);
        board.spawn_uplink(&spawner);
        match status_task(status) {
            Ok(token) => spawner.spawn(token),
            Err(_) => defmt::error!("status task already running"),
        }
        // The task pool holds one control task and this is its only spawn.
        match control_task(ctl, board) {
            #[cfg(feature = "hw")]
            Ok(token) => {
                use interrupt::{InterruptExt, Priority};
                // Above everything but the time driver's alarm (P0).
                interrupt::UART4.set_priority(Priority::P1);
                CONTROL_EXECUTOR.start(interrupt::UART4).spawn(token);
            }
            // PIL: simulated time, one executor in thread mode.
            #[cfg(not(feature = "hw"))]
            Ok(token) => spawner.spawn(token),
            Err(_) => defmt::error!("control task already running"),
        }
        log_events().await
    }

    // Errors are logged by name: `defmt::Debug2Format` would link
    // `core::fmt` with float printing (~13 KB of flash, BENCHMARKS.md).
    fn table_error_name(e: &mre_algorithm::TableError) -> &'static str {
        use mre_algorithm::TableError as E;
        match e {
            E::Empty => "empty",
            E::TooManyEntries { .. } => "too many entries",
            E::UnsupportedVersion { .. } => "unsupported version",
            E::UnsortedCurrents { .. } => "currents not ascending",
            E::NonFiniteValue { .. } => "non-finite value",
            E::BadStroke { .. } => "bad stroke",
            E::CrcMismatch { .. } => "CRC mismatch",
            E::TooLarge { .. } => "value too large",
            E::BadTerm { term } => term,
            E::BadInstallation { field } => field,
        }
    }

    fn config_error_name(e: &mre_algorithm::control::ControlConfigError) -> &'static str {
        use mre_algorithm::control::ControlConfigError as E;
        match e {
            E::Rate { .. } => "control rate out of range",
            E::Law(_) => "law configuration",
            E::PeriodMismatch => "law period does not match the rate",
            E::Estimator => "estimator gains",
            E::Counts => "fault counts",
        }
    }

    /// One defmt frame, counted if the logger drops it (`board::log_drops`).
    macro_rules! log {
        ($level:ident, $($arg:tt)*) => {
            board::log_drops::counted(|| defmt::$level!($($arg)*))
        };
    }

    /// Thread mode: turns the control task's events into defmt lines.
    async fn log_events() -> ! {
        // Counters as of the last stats line: each line reports what is new.
        let (mut reported_dropped, mut reported_frames) = (0, 0);
        loop {
            let event = EVENTS.receive().await;
            check_in(LOG_TASK);
            match event {
                Event::Overrun { period } => log!(warn, "overrun in period {=u32}", period),
                Event::ClearRequest { cleared: true, latched } => {
                    log!(
                        info,
                        "B1: faults cleared at rest (still latched: {=u32:#010x})",
                        latched
                    )
                }
                Event::ClearRequest {
                    cleared: false,
                    latched,
                } => log!(
                    warn,
                    "B1: faults not cleared, the damper is not at rest (latched {=u32:#010x})",
                    latched
                ),
                Event::Missed { ticks, period } => {
                    log!(
                        warn,
                        "{=u32} control periods missed before period {=u32}",
                        ticks,
                        period
                    )
                }
                Event::FaultLatched { latched, period } => {
                    log!(error,
                    "fault latched: {=u32:#010x} in period {=u32}; coil at the fail-safe (drive off on over-current)",
                    latched,
                    period
                )
                }
                Event::Calibrated(c) => {
                    match c.vdda {
                        Ok(v) => log!(info, "calibration at rest: VDDA {=f32} V", v),
                        Err(e) => log!(warn, "calibration at rest: VDDA refused ({=str}), nominal", e.as_str()),
                    }
                    match c.sense_zero_a {
                        Ok(a) => log!(info, "calibration at rest: current sense zero (A) {=f32}", a),
                        Err(e) => log!(
                            warn,
                            "calibration at rest: current sense zero refused ({=str}), 0",
                            e.as_str()
                        ),
                    }
                }
                Event::Stats {
                    stats: s,
                    new_periods,
                    link,
                } => {
                    let dropped = MRE_LOG_EVENTS_DROPPED.load(Ordering::Relaxed);
                    let frames = board::log_drops::frames_dropped();
                    log!(info,
                        "stats: periods {=u32} (+{=u32}), overruns {=u32}, fail-safe periods {=u32}, latched {=u32:#010x}, step cycles min/mean/max {=u32}/{=u32}/{=u32}, log events dropped {=u32}, log frames dropped {=u32}{}",
                        s.periods,
                        new_periods,
                        s.overruns,
                        s.failsafe_periods,
                        s.latched.0,
                        s.step_cycles_min,
                        s.step_cycles_mean(),
                        s.step_cycles_max,
                        dropped.wrapping_sub(reported_dropped),
                        frames.wrapping_sub(reported_frames),
                        board::LinkSummary(link)
                    );
                    reported_dropped = dropped;
                    reported_frames = frames;
                }
            }
        }
    }

    /// Thread mode, every 50 ms: the status LED (heartbeat or the latched
    /// fault's blink code) and B1, whose press asks the control task to
    /// clear latched faults.
    #[embassy_executor::task]
    async fn status_task(mut status: board::Status) {
        use mre_runtime::status::{led_on, SLOT_MS};
        let mut ticker = embassy_time::Ticker::every(embassy_time::Duration::from_millis(u64::from(SLOT_MS)));
        let (mut slot, mut was_pressed) = (0u32, false);
        loop {
            ticker.next().await;
            check_in(STATUS_TASK);
            status.set_led(led_on(mre_algorithm::Flags(LATCHED.load(Ordering::Relaxed)), slot));
            let pressed = status.button_pressed();
            if pressed && !was_pressed {
                CLEAR_REQUEST.store(true, Ordering::Relaxed);
            }
            was_pressed = pressed;
            slot = slot.wrapping_add(1);
        }
    }

    #[embassy_executor::task]
    async fn control_task(mut ctl: Controller, mut board: board::Selected) {
        let mut last = ctl.stats();
        let mut known_faults = ctl.latched();
        board.start();
        loop {
            let missed = board.io().next_period(&mut ctl).await;
            if missed > 0 {
                post(Event::Missed {
                    ticks: missed,
                    period: ctl.stats().periods,
                });
            }
            // The shunt at mid on-time of the last PWM period, checked before
            // the step: an over-current already removes this period's drive,
            // a stale or stuck channel latches CURRENT_SENSE.
            ctl.check_coil_current(board.io().coil_current());
            // Latched faults published as soon as latched (not at the end
            // of the period): a fault handler that runs mid-period must see
            // an over-current latched this period and keep the drive off.
            LATCHED.store(ctl.latched().0, Ordering::Relaxed);
            let t0 = board::Selected::cycles();
            let cmd = ctl.step_io(board.io());
            ctl.record_step_cycles(board::Selected::cycles().wrapping_sub(t0));
            LATCHED.store(ctl.latched().0, Ordering::Relaxed);
            board::UPLOAD_GATE.observe(&ctl, &cmd);
            let overran = board.io().finish_period(&cmd, &ctl);
            if let Some(c) = board.io().take_deferred_calibration() {
                post(Event::Calibrated(c));
            }
            ctl.end_period(overran);
            // Fed here only, and only while the thread-mode tasks check in:
            // a stalled control loop or a hung task must reset the chip.
            if thread_tasks_on_time() {
                board.feed_watchdog();
            }
            if overran {
                post(Event::Overrun {
                    period: ctl.stats().periods,
                });
            }
            if CLEAR_REQUEST.swap(false, Ordering::Relaxed) {
                let cleared = ctl.clear_faults_if_at_rest();
                known_faults = ctl.latched();
                post(Event::ClearRequest {
                    cleared,
                    latched: known_faults.0,
                });
            }
            LATCHED.store(ctl.latched().0, Ordering::Relaxed);
            if ctl.latched() != known_faults {
                known_faults = ctl.latched();
                post(Event::FaultLatched {
                    latched: known_faults.0,
                    period: ctl.stats().periods,
                });
            }

            let s = ctl.stats();
            if s.periods.wrapping_sub(last.periods) >= ctl.config().rate_hz {
                post(Event::Stats {
                    stats: s,
                    new_periods: s.periods.wrapping_sub(last.periods),
                    link: board.io().link_stats(),
                });
                #[cfg(all(feature = "bench", feature = "hw"))]
                crate::board::bench_model_step(ctl.table());
                last = s;
                ctl.reset_cycle_stats();
            }
        }
    }
}
