//! The uploaded-table flash page, over a RAM page that behaves like STM32L4
//! flash (erase to 0xFF, 8-byte aligned writes that can only clear bits).
use mre_algorithm::control::ControlConfig;
use mre_algorithm::table::{Table, PAPER_TABLE4_ENTRIES};
use mre_protocol::flash_table::{load, store, FlashError, PageError, TablePage, WRITE_ALIGN};

/// The core's RAM page, asserting alignment and able to lose power mid-write.
struct RamPage {
    page: mre_protocol::flash_table::RamPage,
    bytes: Vec<u8>,
    /// Stop after this many written bytes (a power cut mid-write).
    cut_after: Option<usize>,
}

impl RamPage {
    fn erased() -> Self {
        let page = mre_protocol::flash_table::RamPage::erased();
        Self {
            bytes: page.bytes.to_vec(),
            page,
            cut_after: None,
        }
    }
}

impl TablePage for RamPage {
    fn read(&mut self, offset: usize, buf: &mut [u8]) -> Result<(), FlashError> {
        // Tests edit `bytes` directly: the core page mirrors them.
        self.page.bytes.copy_from_slice(&self.bytes);
        self.page.read(offset, buf)
    }
    fn erase(&mut self) -> Result<(), FlashError> {
        self.page.erase()?;
        self.bytes.copy_from_slice(&self.page.bytes);
        Ok(())
    }
    fn write(&mut self, offset: usize, data: &[u8]) -> Result<(), FlashError> {
        assert_eq!(offset % WRITE_ALIGN, 0, "unaligned write offset");
        assert_eq!(data.len() % WRITE_ALIGN, 0, "unaligned write length");
        let dst = self.bytes.get_mut(offset..offset + data.len()).ok_or(FlashError)?;
        for (k, (d, s)) in dst.iter_mut().zip(data).enumerate() {
            if self.cut_after.is_some_and(|cut| k >= cut) {
                break;
            }
            // NOR flash: programming only clears bits.
            *d &= *s;
        }
        Ok(())
    }
}

fn uploaded() -> (Table, ControlConfig) {
    // Not the built-in table: Table 4 with a longer fitted stroke, at 20 kHz.
    let mut entries = PAPER_TABLE4_ENTRIES;
    for e in &mut entries {
        e.x_max_mm *= 2.0;
    }
    (Table::new(&entries).unwrap(), ControlConfig::at_rate(20_000).unwrap())
}

#[test]
fn an_erased_page_is_empty_and_the_board_falls_back() {
    assert_eq!(load(&mut RamPage::erased()).unwrap_err(), PageError::Empty);
}

#[test]
fn a_stored_table_loads_back_bit_for_bit() {
    let (table, cfg) = uploaded();
    let mut page = RamPage::erased();
    store(&mut page, &table, &cfg).unwrap();
    let (t, c) = load(&mut page).unwrap();
    assert_eq!(t.crc32(), table.crc32());
    assert_eq!(t.entries(), table.entries());
    assert_eq!(c, cfg);
    // Storing again (a second upload) replaces it.
    let other = Table::paper().unwrap();
    store(&mut page, &other, &cfg).unwrap();
    assert_eq!(load(&mut page).unwrap().0.crc32(), other.crc32());
}

#[test]
fn a_torn_or_corrupt_page_is_refused() {
    let (table, cfg) = uploaded();
    // Power cut after the header and 40 bytes of the blob.
    let mut page = RamPage::erased();
    page.cut_after = Some(56);
    assert_eq!(store(&mut page, &table, &cfg), Err(PageError::NotAsWritten));
    assert_eq!(load(&mut page).unwrap_err(), PageError::Corrupt);
    // One flipped bit in the blob.
    let mut page = RamPage::erased();
    store(&mut page, &table, &cfg).unwrap();
    page.bytes[100] ^= 0x04;
    assert_eq!(load(&mut page).unwrap_err(), PageError::Corrupt);
    // An absurd length in the header.
    let mut page = RamPage::erased();
    store(&mut page, &table, &cfg).unwrap();
    page.bytes[8..12].copy_from_slice(&100_000u32.to_le_bytes());
    assert_eq!(load(&mut page).unwrap_err(), PageError::Corrupt);
    // Another page format.
    let mut page = RamPage::erased();
    store(&mut page, &table, &cfg).unwrap();
    page.bytes[4..8].copy_from_slice(&9u32.to_le_bytes());
    assert_eq!(load(&mut page).unwrap_err(), PageError::UnsupportedFormat(9));
}

/// `memory.x` as the linker reads it: the image's FLASH region must end at
/// the bank boundary (bank 2 is erased and written while bank 1 runs), and the
/// `TABLE_PAGE` region must be the page the firmware writes.
#[test]
fn the_linker_keeps_the_image_in_bank_1_and_names_the_table_page() {
    use mre_protocol::flash_table::{FLASH_BANK_BYTES, FLASH_BASE_ADDRESS, PAGE_BYTES, TABLE_PAGE_ADDRESS};
    let text = std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/../memory.x")).unwrap();
    let region = |name: &str| -> (u32, u32) {
        let line = text
            .lines()
            .find(|l| l.trim_start().starts_with(name) && l.contains("ORIGIN"))
            .unwrap_or_else(|| panic!("memory.x has no {name} region"));
        let origin = line.split("ORIGIN = 0x").nth(1).unwrap().split(',').next().unwrap();
        let length = line.split("LENGTH = ").nth(1).unwrap().trim().trim_end_matches('K');
        (
            u32::from_str_radix(origin.trim(), 16).unwrap(),
            length.parse::<u32>().unwrap() * 1024,
        )
    };
    let (flash, flash_len) = region("FLASH ");
    assert_eq!(flash, FLASH_BASE_ADDRESS);
    // RM0351: bank 2 of a 1 MiB STM32L47x starts at 0x0808_0000.
    assert_eq!(flash + flash_len, 0x0808_0000, "FLASH must end at the bank boundary");
    assert_eq!(FLASH_BASE_ADDRESS + FLASH_BANK_BYTES, 0x0808_0000);
    let (page, page_len) = region("TABLE_PAGE");
    assert_eq!(page, TABLE_PAGE_ADDRESS);
    assert_eq!(page, 0x080F_F800, "the last 2 KiB page of the 1 MiB flash");
    assert_eq!(page_len as usize, PAGE_BYTES);
}

/// Records the page operations in order, optionally failing the write.
struct RecordingPage {
    page: mre_protocol::flash_table::RamPage,
    calls: Vec<&'static str>,
    fail_write: bool,
}

impl TablePage for RecordingPage {
    fn read(&mut self, offset: usize, buf: &mut [u8]) -> Result<(), FlashError> {
        self.calls.push("read");
        self.page.read(offset, buf)
    }
    fn erase(&mut self) -> Result<(), FlashError> {
        self.calls.push("erase");
        self.page.erase()
    }
    fn write(&mut self, offset: usize, data: &[u8]) -> Result<(), FlashError> {
        self.calls.push("write");
        if self.fail_write {
            return Err(FlashError);
        }
        self.page.write(offset, data)
    }
    fn begin_update(&mut self) {
        self.calls.push("cache off");
    }
    fn end_update(&mut self) {
        self.calls.push("cache reset, on");
    }
}

/// ST's read-while-write erratum: the data cache is off for the whole erase
/// and program, reset and re-enabled after it (on failure too), and only
/// then is the page read back.
#[test]
fn the_data_cache_is_off_around_erase_and_program_and_reset_before_the_read_back() {
    let (table, cfg) = uploaded();
    for fail_write in [false, true] {
        let mut page = RecordingPage {
            page: mre_protocol::flash_table::RamPage::erased(),
            calls: Vec::new(),
            fail_write,
        };
        let stored = store(&mut page, &table, &cfg);
        assert_eq!(stored.is_ok(), !fail_write);
        let updates: Vec<_> = page.calls.iter().copied().filter(|c| *c != "read").collect();
        assert_eq!(
            updates,
            ["cache off", "erase", "write", "cache reset, on"],
            "fail_write {fail_write}"
        );
        let last_update = page.calls.iter().rposition(|c| *c == "cache reset, on").unwrap();
        assert!(
            page.calls[..last_update].iter().all(|c| *c != "read"),
            "read before the cache was reset: {:?}",
            page.calls
        );
        if !fail_write {
            assert_eq!(page.calls.last(), Some(&"read"), "the read-back follows");
        }
    }
}
