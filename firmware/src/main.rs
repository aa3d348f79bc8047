//! Firmware entry point. The board image is built only for
//! `thumbv7em-none-eabihf` (`cargo fw`); on the host this is a stub so that
//! `cargo test` and `cargo clippy --all-targets` cover the whole workspace.
#![cfg_attr(target_os = "none", no_std, no_main)]

#[cfg(not(target_os = "none"))]
fn main() {
    eprintln!("mre-firmware runs on the board: build it with `cargo fw`");
}
