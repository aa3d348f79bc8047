//! Counts the defmt frames the RTT logger dropped. The boards' defmt-rtt
//! (`disable-blocking-mode` + `drop-on-contention`) publishes a frame with a
//! single move of the up channel's write cursor once the whole frame is
//! staged, and drops a frame that does not fit or collides: a log call after
//! which the cursor has not moved was dropped. The semihosting logger (the
//! plain `pil` image) never drops (QEMU takes each frame before the core
//! goes on), so there the count stays 0.
use core::sync::atomic::{AtomicU32, Ordering};

/// Frames dropped since boot. Logged (as a difference) in the stats line;
/// `mre pil` reads it by symbol through QEMU's monitor.
#[no_mangle]
pub static MRE_LOG_FRAMES_DROPPED: AtomicU32 = AtomicU32::new(0);

pub fn frames_dropped() -> u32 {
    MRE_LOG_FRAMES_DROPPED.load(Ordering::Relaxed)
}

/// Logs through `log` (one defmt frame) and counts it if it was dropped.
#[cfg(any(feature = "hw", feature = "pil-rtt"))]
pub fn counted(log: impl FnOnce()) {
    let before = rtt::write_cursor();
    log();
    if rtt::write_cursor() == before {
        MRE_LOG_FRAMES_DROPPED.fetch_add(1, Ordering::Relaxed);
    }
}

/// Semihosting: nothing is dropped.
#[cfg(not(any(feature = "hw", feature = "pil-rtt")))]
pub fn counted(log: impl FnOnce()) {
    log()
}

#[cfg(any(feature = "hw", feature = "pil-rtt"))]
pub mod rtt {
    extern "C" {
        /// defmt-rtt's control block (SEGGER layout: 16-byte id, two u32
        /// channel counts, then the up channel: name, buffer, size, write,
        /// read, flags, each 32 bits).
        static _SEGGER_RTT: [u32; 12];
    }
    const WRITE_WORD: usize = 9;
    #[cfg(feature = "pil-rtt")]
    const FLAGS_WORD: usize = 11;
    /// SEGGER_RTT_MODE_BLOCK_IF_FIFO_FULL, what probe-rs writes.
    #[cfg(feature = "pil-rtt")]
    const BLOCK_IF_FULL: u32 = 2;

    fn word(index: usize) -> *mut u32 {
        // SAFETY: only the address is taken; the block has 12 words.
        unsafe { core::ptr::addr_of!(_SEGGER_RTT).cast::<u32>().cast_mut().add(index) }
    }

    pub(super) fn write_cursor() -> u32 {
        // SAFETY: an aligned word of the control block; the logger updates it.
        unsafe { word(WRITE_WORD).read_volatile() }
    }

    /// `pil-rtt`: the up channel as `probe-rs run` leaves it, block-if-full,
    /// with no reader (QEMU has none), filled before the first period.
    /// defmt-rtt's default features would spin in a critical section on the
    /// next frame for ever; the boards' features drop it and it is counted.
    #[cfg(feature = "pil-rtt")]
    pub fn block_if_full_and_fill() {
        // The control block is set up by the logger's first frame.
        defmt::info!("PIL with the RTT logger: up channel set to block-if-full, no reader");
        // SAFETY: the flags word, written once here as a probe would.
        unsafe { word(FLAGS_WORD).write_volatile(BLOCK_IF_FULL) };
        // 1 KiB buffer, ~10 bytes a frame: 400 frames fill it with room to spare.
        for k in 0..400u32 {
            super::counted(|| defmt::info!("filling the RTT buffer: frame {=u32}", k));
        }
    }
}
