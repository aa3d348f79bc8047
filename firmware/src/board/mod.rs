//! Board layers: clocks, peripherals and the I/O trait implementations the
//! control task runs against. Exactly one board feature is enabled:
//! - `board-b-l475e-iot01a` (default) and `board-nucleo-l476rg`: real
//!   hardware, shared STM32L4 code in `stm32l4.rs`, pins in one table each;
//! - `pil`: QEMU's `b-l475e-iot01a` machine, samples and commands over USART1.
//!
//! Every layer exports the same items: `NAME`, `Board { io, watchdog }`,
//! `init(rate_hz)`, `Board::start`, `core_clock_hz`, `cycles`,
//! `halt_fail_safe`, and an `io` with `next_period`, `finish_period` and
//! `link_summary`.
#[cfg(all(feature = "hw", feature = "pil"))]
compile_error!("enable one board: `pil` needs `--no-default-features`");
#[cfg(all(feature = "board-b-l475e-iot01a", feature = "board-nucleo-l476rg"))]
compile_error!("enable one board: use `--no-default-features` with `board-nucleo-l476rg`");
#[cfg(not(any(feature = "hw", feature = "pil")))]
compile_error!("enable a board feature (board-b-l475e-iot01a, board-nucleo-l476rg or pil)");

#[cfg(feature = "hw")]
mod stm32l4;
#[cfg(feature = "hw")]
pub use stm32l4::*;

#[cfg(feature = "pil")]
mod pil;
#[cfg(feature = "pil")]
pub use pil::*;
