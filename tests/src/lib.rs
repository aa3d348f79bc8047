//! Host tests of the control core live in `tests/`. This crate holds only
//! what several of them share: reference implementations written
//! independently of the core, and model tables built by hand.

use mre_algorithm::table::{CurrentEntry, Quartic};
use proptest::test_runner::{Config as ProptestConfig, RngSeed};

/// The seed every property test draws its cases from, so CI meets the same
/// cases on every run (31: the seed `limits.rs` was first fixed to).
pub const PROPTEST_SEED: u64 = 31;

/// The configuration of every `proptest!` block here: `cases` cases from
/// [`PROPTEST_SEED`]; the committed `*.proptest-regressions` files are
/// replayed first, as always. For a fresh seed locally, set it in the
/// environment, which proptest reads over this:
/// `PROPTEST_RNG_SEED=$RANDOM cargo test -p mre-tests` (the failing seed is
/// then the one printed; a failing case is saved to the regressions file).
pub fn proptest_config(cases: u32) -> ProptestConfig {
    ProptestConfig {
        cases,
        rng_seed: RngSeed::Fixed(PROPTEST_SEED),
        ..ProptestConfig::default()
    }
}

/// Bitwise CRC-32 (reflected, poly 0xEDB88320, init and xorout !0): the zlib
/// CRC, written out here independently of the `crc` crate the core uses.
pub fn crc32_reference(bytes: &[u8]) -> u32 {
    let mut crc = !0u32;
    for &b in bytes {
        crc ^= u32::from(b);
        for _ in 0..8 {
            crc = if crc & 1 != 0 {
                (crc >> 1) ^ 0xEDB8_8320
            } else {
                crc >> 1
            };
        }
    }
    !crc
}

/// A table entry whose force on both branches is `a1_n_per_mm·x + a0_n`
/// (x in mm) over 0–20 mm: forces a test can work out by hand.
pub fn linear_entry(current_a: f32, a1_n_per_mm: f32, a0_n: f32) -> CurrentEntry {
    let q = Quartic::new([0.0, 0.0, 0.0, a1_n_per_mm, a0_n]);
    CurrentEntry {
        current_a,
        compression: q,
        extension: q,
        x_min_mm: 0.0,
        x_max_mm: 20.0,
    }
}
