//! Firmware entry point. The board image is built only for
//! `thumbv7em-none-eabihf` (`cargo fw`); on the host this is a stub so that
//! `cargo test` and `cargo clippy --all-targets` cover the whole workspace.
//!
//! One embassy task runs the control loop: wait for the period (a `Ticker`
//! on hardware, the next sample frame in PIL), run the core's
//! [`Controller::step_io`](mre_core::control::Controller::step_io), account
//! for overruns, feed the watchdog, and log statistics once a second.
#![cfg_attr(target_os = "none", no_std, no_main)]

#[cfg(not(target_os = "none"))]
fn main() {
    eprintln!("mre-firmware runs on the board: build it with `cargo fw`");
}

#[cfg(target_os = "none")]
mod board;

#[cfg(target_os = "none")]
mod fw {
    use crate::board;
    use embassy_executor::Spawner;
    use mre_core::control::{ControlConfig, Controller, DEFAULT_RATE_HZ};
    use mre_core::table::Table;

    /// The table this image flies: by default the one `mre tables` generated
    /// from the committed model (`firmware/src/generated_table.rs`); with the
    /// `table-paper` feature the paper's Table 4.
    #[cfg(not(feature = "table-paper"))]
    mod flown {
        pub use mre_core::generated_table::{GENERATED_TABLE as IMAGE, SOURCE_DATASET_SHA256};
        pub const NAME: &str = "generated";
    }
    #[cfg(feature = "table-paper")]
    mod flown {
        pub use mre_core::table::PAPER_TABLE4 as IMAGE;
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
        // Before anything else: the coil pin comes out of reset pulled high.
        board::coil_output_off_at_boot();
        let board = board::init(RATE_HZ);
        defmt::info!(
            "mre-firmware on {=str}, core clock {=u32} Hz",
            board::NAME,
            board::core_clock_hz()
        );

        // A rejected table is not fatal: the controller latches TABLE_FAULT
        // and commands the fail-safe current every period.
        let table = Table::from_image(&flown::IMAGE);
        match &table {
            Ok(t) => defmt::info!(
                "table {=str} format v{=u16}: {=usize} currents, CRC {=u32:#010x} OK, data set sha256 {=str}",
                flown::NAME,
                t.version(),
                t.entries().len(),
                t.crc32(),
                flown::SOURCE_DATASET_SHA256
            ),
            Err(e) => defmt::error!(
                "table {=str} format v{=u16} stored CRC {=u32:#010x} REJECTED: {}, data set sha256 {=str}",
                flown::NAME,
                flown::IMAGE.version,
                flown::IMAGE.crc32,
                defmt::Debug2Format(e),
                flown::SOURCE_DATASET_SHA256
            ),
        }

        let cfg = match ControlConfig::at_rate(RATE_HZ) {
            Ok(cfg) => cfg,
            Err(e) => {
                // Only a build with a bad RATE_HZ gets here: hold the coil at
                // the fail-safe duty and let the watchdog (never fed) reset.
                defmt::error!("control config refused: {}", defmt::Debug2Format(&e));
                board::halt_fail_safe(board)
            }
        };
        #[allow(unused_mut)]
        let mut ctl = match Controller::new(cfg, table) {
            Ok(c) => c,
            Err(e) => {
                defmt::error!("controller refused config: {}", defmt::Debug2Format(&e));
                board::halt_fail_safe(board)
            }
        };
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
        // The task pool holds one control task and this is its only spawn.
        match control_task(ctl, board) {
            Ok(token) => spawner.spawn(token),
            Err(_) => defmt::error!("control task already running"),
        }
    }

    #[embassy_executor::task]
    async fn control_task(mut ctl: Controller, mut board: board::Board) {
        let mut last = ctl.stats();
        let mut known_faults = ctl.latched();
        board.start();
        loop {
            board.io.next_period(&mut ctl).await;
            let t0 = board::cycles();
            let cmd = ctl.step_io(&mut board.io);
            ctl.record_step_cycles(board::cycles().wrapping_sub(t0));
            let overran = board.io.finish_period(&cmd, &ctl);
            ctl.end_period(overran);
            // Fed here only: a stalled control loop must reset the chip.
            board.watchdog.pet();
            if overran {
                defmt::warn!("overrun in period {=u32}", ctl.stats().periods);
            }
            if ctl.latched() != known_faults {
                known_faults = ctl.latched();
                defmt::error!(
                    "fault latched: {=u16:#06x} in period {=u32}; coil at the fail-safe",
                    known_faults.0,
                    ctl.stats().periods
                );
            }

            let s = ctl.stats();
            if s.periods.wrapping_sub(last.periods) >= ctl.config().rate_hz {
                defmt::info!(
                    "stats: periods {=u32} (+{=u32}), overruns {=u32}, fail-safe periods {=u32}, latched {=u16:#06x}, step cycles min/mean/max {=u32}/{=u32}/{=u32}{}",
                    s.periods,
                    s.periods.wrapping_sub(last.periods),
                    s.overruns,
                    s.failsafe_periods,
                    s.latched.0,
                    s.step_cycles_min,
                    s.step_cycles_mean(),
                    s.step_cycles_max,
                    board.io.link_summary()
                );
                #[cfg(all(feature = "bench", feature = "hw"))]
                crate::board::bench_model_step(ctl.table());
                last = s;
                ctl.reset_cycle_stats();
            }
        }
    }
}
