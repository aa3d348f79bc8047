//! Firmware entry point. The board image is built only for
//! `thumbv7em-none-eabihf` (`cargo fw`); on the host this is a stub so that
//! `cargo test` and `cargo clippy --all-targets` cover the whole workspace.
#![cfg_attr(target_os = "none", no_std, no_main)]

#[cfg(not(target_os = "none"))]
fn main() {
    eprintln!("mre-firmware runs on the board: build it with `cargo fw`");
}

#[cfg(target_os = "none")]
mod fw {
    use defmt_rtt as _;
    use embassy_executor::Spawner;
    use mre_core::table::{Table, PAPER_TABLE4};
    use panic_probe as _;

    #[embassy_executor::main]
    async fn main(_spawner: Spawner) {
        let _p = embassy_stm32::init(Default::default());
        defmt::info!(
            "mre-firmware boot: table v{=u16} stored CRC {=u32:#010x}",
            PAPER_TABLE4.version,
            PAPER_TABLE4.crc32
        );
        match Table::from_image(&PAPER_TABLE4) {
            Ok(t) => defmt::info!(
                "table OK: {=usize} currents, CRC {=u32:#010x}",
                t.entries().len(),
                t.crc32()
            ),
            Err(e) => defmt::error!("table rejected: {}", defmt::Debug2Format(&e)),
        }
    }
}
