//! Host tests of the control core live in `tests/`. This crate holds only
//! what several of them share: reference implementations written
//! independently of the core.

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
