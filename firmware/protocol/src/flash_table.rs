//! The reserved flash page that holds an uploaded table and configuration,
//! so a table can change without reflashing the image. The page stores the
//! same blob the PIL/upload protocol carries (`frame::encode_config`),
//! behind a small header:
//!
//! | bytes | content |
//! |---|---|
//! | 0..4 | magic `MRET` (`0x5445_524D` little-endian) |
//! | 4..8 | page format (1) |
//! | 8..12 | blob length in words |
//! | 12..16 | CRC-32 (ISO-HDLC) of the blob's bytes |
//! | 16.. | the blob, u32 little-endian; padded with 0xFF to 8 bytes |
//!
//! Boot loads the page and falls back to the built-in table when it is
//! erased, torn (CRC) or refused by the blob's own validation
//! (`Table::from_image`, `ControlConfig::validate`). The board implements
//! [`TablePage`] over embassy-stm32's flash; the host tests over RAM.
use crate::frame::{decode_config, encode_config, ConfigBlobError, CONFIG_MAX_WORDS};
use crc::{Crc, CRC_32_ISO_HDLC};
use mre_algorithm::control::ControlConfig;
use mre_algorithm::table::Table;

pub const MAGIC: u32 = u32::from_le_bytes(*b"MRET");
pub const PAGE_FORMAT: u32 = 1;
const HEADER_BYTES: usize = 16;
/// STM32L4 flash pages are 2 KiB, written in 8-byte double words.
pub const PAGE_BYTES: usize = 2048;
/// The STM32L4's 1 MiB flash: two 512 KiB banks from 0x0800_0000.
pub const FLASH_BASE_ADDRESS: u32 = 0x0800_0000;
pub const FLASH_BANK_BYTES: u32 = 512 * 1024;
/// The table page: the last page of bank 2 (`memory.x` region `TABLE_PAGE`;
/// the image's FLASH region ends at the bank boundary, so nothing is linked
/// in bank 2 and read-while-write keeps the control loop running from bank 1).
pub const TABLE_PAGE_ADDRESS: u32 = FLASH_BASE_ADDRESS + 2 * FLASH_BANK_BYTES - PAGE_BYTES as u32;
pub const WRITE_ALIGN: usize = 8;
const MAX_IMAGE_BYTES: usize = HEADER_BYTES + 4 * CONFIG_MAX_WORDS + WRITE_ALIGN;
const CRC32: Crc<u32> = Crc::<u32>::new(&CRC_32_ISO_HDLC);

/// One erasable flash page (offsets from its start).
pub trait TablePage {
    fn read(&mut self, offset: usize, buf: &mut [u8]) -> Result<(), FlashError>;
    /// Sets every byte of the page to 0xFF.
    fn erase(&mut self) -> Result<(), FlashError>;
    /// `offset` and `data.len()` are multiples of [`WRITE_ALIGN`].
    fn write(&mut self, offset: usize, data: &[u8]) -> Result<(), FlashError>;
    /// Before the first erase or program of an update. The STM32L4 boards
    /// disable the flash data cache here: ST's errata (STM32L47x/L48x, "Data
    /// cache might be corrupted during Flash memory read-while-write
    /// operation") prescribe it while one bank is erased or programmed as the
    /// other is read.
    fn begin_update(&mut self) {}
    /// After the last erase or program of an update, failed or not, and
    /// before the page is read back: reset the data cache, then re-enable it.
    fn end_update(&mut self) {}
}

/// A page in RAM that behaves like STM32L4 flash (erase to 0xFF, aligned
/// writes that can only clear bits): the PIL board's stand-in (QEMU models
/// no flash controller) and the host tests' page.
#[derive(Clone, Debug)]
pub struct RamPage {
    pub bytes: [u8; PAGE_BYTES],
}

impl RamPage {
    pub const fn erased() -> Self {
        Self {
            bytes: [0xFF; PAGE_BYTES],
        }
    }
}

impl TablePage for RamPage {
    fn read(&mut self, offset: usize, buf: &mut [u8]) -> Result<(), FlashError> {
        let src = self
            .bytes
            .get(offset..offset.saturating_add(buf.len()))
            .ok_or(FlashError)?;
        buf.copy_from_slice(src);
        Ok(())
    }

    fn erase(&mut self) -> Result<(), FlashError> {
        self.bytes.fill(0xFF);
        Ok(())
    }

    fn write(&mut self, offset: usize, data: &[u8]) -> Result<(), FlashError> {
        if !offset.is_multiple_of(WRITE_ALIGN) || !data.len().is_multiple_of(WRITE_ALIGN) {
            return Err(FlashError);
        }
        let dst = self
            .bytes
            .get_mut(offset..offset.saturating_add(data.len()))
            .ok_or(FlashError)?;
        for (d, s) in dst.iter_mut().zip(data) {
            *d &= *s;
        }
        Ok(())
    }
}

/// The flash driver failed (the board maps its error here).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct FlashError;

/// Why the page holds no usable table.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum PageError {
    /// Never written (erased) or not our page.
    Empty,
    UnsupportedFormat(u32),
    /// Length out of range or CRC mismatch: a torn or corrupt write.
    Corrupt,
    Refused(ConfigBlobError),
    Flash(FlashError),
    /// The read-back after an upload differs from what was written (an
    /// erase or program that failed silently).
    NotAsWritten,
}

impl PageError {
    /// A short reason for logs (no `core::fmt` on the board).
    pub fn as_str(&self) -> &'static str {
        match self {
            PageError::Empty => "page empty",
            PageError::UnsupportedFormat(_) => "unsupported page format",
            PageError::Corrupt => "page corrupt (length or CRC)",
            PageError::Refused(_) => "table or configuration refused",
            PageError::Flash(_) => "flash read failed",
            PageError::NotAsWritten => "flash read-back differs from what was written",
        }
    }
}

impl From<FlashError> for PageError {
    fn from(e: FlashError) -> Self {
        PageError::Flash(e)
    }
}

/// Loads and validates the stored table and configuration.
pub fn load<P: TablePage + ?Sized>(page: &mut P) -> Result<(Table, ControlConfig), PageError> {
    let mut header = [0u8; HEADER_BYTES];
    page.read(0, &mut header)?;
    let word = |k: usize| {
        let mut w = [0u8; 4];
        let at = k.wrapping_mul(4);
        if let Some(src) = header.get(at..at.wrapping_add(4)) {
            w.copy_from_slice(src);
        }
        u32::from_le_bytes(w)
    };
    if word(0) != MAGIC {
        return Err(PageError::Empty);
    }
    if word(1) != PAGE_FORMAT {
        return Err(PageError::UnsupportedFormat(word(1)));
    }
    let n = word(2) as usize;
    if n == 0 || n > CONFIG_MAX_WORDS {
        return Err(PageError::Corrupt);
    }
    let mut bytes = [0u8; 4 * CONFIG_MAX_WORDS];
    let blob = bytes.get_mut(..n.saturating_mul(4)).ok_or(PageError::Corrupt)?;
    page.read(HEADER_BYTES, blob)?;
    if CRC32.checksum(blob) != word(3) {
        return Err(PageError::Corrupt);
    }
    let mut words = [0u32; CONFIG_MAX_WORDS];
    for (w, b) in words.iter_mut().zip(blob.chunks_exact(4)) {
        if let Ok(b) = <[u8; 4]>::try_from(b) {
            *w = u32::from_le_bytes(b);
        }
    }
    decode_config(words.get(..n).unwrap_or(&[])).map_err(PageError::Refused)
}

/// Erases the page and stores `table` and `cfg`, then reads it back.
pub fn store<P: TablePage + ?Sized>(page: &mut P, table: &Table, cfg: &ControlConfig) -> Result<(), PageError> {
    let mut words = [0u32; CONFIG_MAX_WORDS];
    let n = encode_config(table, cfg, &mut words);
    let mut image = [0xFFu8; MAX_IMAGE_BYTES];
    let mut blob_crc = CRC32.digest();
    for (k, w) in words.iter().take(n).enumerate() {
        let b = w.to_le_bytes();
        blob_crc.update(&b);
        let at = k.wrapping_mul(4).wrapping_add(HEADER_BYTES);
        if let Some(dst) = image.get_mut(at..at.wrapping_add(4)) {
            dst.copy_from_slice(&b);
        }
    }
    let header = [MAGIC, PAGE_FORMAT, n as u32, blob_crc.finalize()];
    for (k, w) in header.iter().enumerate() {
        let at = k.wrapping_mul(4);
        if let Some(dst) = image.get_mut(at..at.wrapping_add(4)) {
            dst.copy_from_slice(&w.to_le_bytes());
        }
    }
    let len = HEADER_BYTES
        .saturating_add(n.saturating_mul(4))
        .div_ceil(WRITE_ALIGN)
        .saturating_mul(WRITE_ALIGN);
    page.begin_update();
    let written = page
        .erase()
        .and_then(|()| page.write(0, image.get(..len).unwrap_or(&[])));
    page.end_update();
    written?;
    // Byte for byte what was written, not merely a valid page: a driver that
    // reports an erase or program error as success (embassy-stm32 0.6's L4
    // flash interrupt clears the error flags before its `wait_ready` reads
    // them, firmware/README.md) leaves the old table or a mix, and a valid
    // old table must not be answered "stored".
    let mut chunk = [0u8; 64];
    let mut at = 0usize;
    while at < len {
        let n = chunk.len().min(len.saturating_sub(at));
        let back = chunk.get_mut(..n).ok_or(PageError::NotAsWritten)?;
        page.read(at, back)?;
        if image.get(at..at.saturating_add(n)) != Some(&*back) {
            return Err(PageError::NotAsWritten);
        }
        at = at.saturating_add(n);
    }
    load(page).map(|_| ())
}
