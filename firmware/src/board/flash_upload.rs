//! The table upload on the STM32L4 boards: the flash page behind
//! `mre_protocol::flash_table::TablePage` and the task that answers `mre upload`
//! on the ST-LINK VCP (`mre_protocol::upload`).
use core::sync::atomic::{AtomicBool, AtomicU32, Ordering};
use embassy_stm32::usart::BufferedUart;
use mre_algorithm::table::TableImage;
use mre_protocol::upload::{choose_boot_table, BootTable};

/// The flash page reserved for an uploaded table (`memory.x`'s `TABLE_PAGE`),
/// as an offset into the flash. It lies in bank 2 and the image in bank 1
/// (memory.x ends FLASH at the bank boundary): the L4's read-while-write lets
/// the control loop keep running from bank 1 while the page is erased and written.
const TABLE_PAGE_OFFSET: u32 =
    mre_protocol::flash_table::TABLE_PAGE_ADDRESS - mre_protocol::flash_table::FLASH_BASE_ADDRESS;

/// embassy-stm32's async flash driver: on the L4 its erase and write wait
/// for the FLASH interrupt instead of holding a critical section (the
/// blocking driver masks interrupts for the whole ~22 ms page erase, which
/// would stall the control loop and trip the 5 ms watchdog). The upload task
/// polls each operation to completion in thread mode.
///
/// embassy-stm32 0.6.0 does not handle the data cache on the L4 (its
/// `flash/l.rs` leaves FLASH_ACR alone; embassy's later sources save, disable
/// and reset it, commit 1b9e61437 "fix STM32L4 corrupted data cache after
/// erase/write"), so this page does, in `begin_update` / `end_update`.
/// FLASH_SR's error flags (RM0351 "Flash status register (FLASH_SR)": OPERR 1, PROGERR 3,
/// WRPERR 4, PGAERR 5, SIZERR 6, PGSERR 7, MISERR 8, FASTERR 9, RDERR 14,
/// OPTVERR 15) seen by [`FlashErrorCapture`] since the operation began.
static FLASH_SR_ERRORS: AtomicU32 = AtomicU32::new(0);
const FLASH_SR_ERROR_MASK: u32 = (1 << 1) | (0x7F << 3) | (1 << 14) | (1 << 15);
/// A double-ECC error in the table page since the read began (the NMI).
static TABLE_PAGE_ECC: AtomicBool = AtomicBool::new(false);

/// Bound before embassy's flash interrupt handler: embassy-stm32 0.6.0's
/// L4 `on_interrupt` (`flash/l.rs`) writes 1 to every FLASH_SR error flag
/// before its `wait_ready` reads them, so an erase or program error comes
/// back `Ok`. This handler keeps the flags first.
pub struct FlashErrorCapture;

impl embassy_stm32::interrupt::typelevel::Handler<embassy_stm32::interrupt::typelevel::FLASH> for FlashErrorCapture {
    unsafe fn on_interrupt() {
        let sr = embassy_stm32::pac::FLASH.sr().read().0;
        FLASH_SR_ERRORS.fetch_or(sr & FLASH_SR_ERROR_MASK, Ordering::Relaxed);
    }
}

/// Whether FLASH_ECCR's failing address (bank `bk_ecc`, offset `addr_ecc`
/// in that bank) lies in the table page (bank 2, its last page).
pub fn in_table_page(bk_ecc: bool, addr_ecc: u32) -> bool {
    let in_bank = TABLE_PAGE_OFFSET - mre_protocol::flash_table::FLASH_BANK_BYTES;
    bk_ecc && (in_bank..in_bank + mre_protocol::flash_table::PAGE_BYTES as u32).contains(&addr_ecc)
}

/// The NMI handler saw a double-ECC error in the table page.
pub fn note_table_page_ecc() {
    TABLE_PAGE_ECC.store(true, Ordering::Relaxed);
}

/// Errors of the operation just finished: those the capture kept and
/// those still in FLASH_SR (an operation that raised no interrupt).
fn take_flash_errors() -> Result<(), mre_protocol::flash_table::FlashError> {
    let sr = embassy_stm32::pac::FLASH.sr().read().0 & FLASH_SR_ERROR_MASK;
    let seen = FLASH_SR_ERRORS.swap(0, Ordering::Relaxed) | sr;
    if seen == 0 {
        Ok(())
    } else {
        // Write 1 to clear what is left, so the next operation starts clean.
        embassy_stm32::pac::FLASH
            .sr()
            .write_value(embassy_stm32::pac::flash::regs::Sr(sr));
        Err(mre_protocol::flash_table::FlashError)
    }
}

struct FlashPage {
    flash: embassy_stm32::flash::Flash<'static, embassy_stm32::flash::Async>,
    /// FLASH_ACR.DCEN before the update began.
    data_cache_was_on: bool,
}

impl mre_protocol::flash_table::TablePage for FlashPage {
    /// A read that raised a double-ECC NMI (a torn page) fails: boot then
    /// flies the built-in table.
    fn read(&mut self, offset: usize, buf: &mut [u8]) -> Result<(), mre_protocol::flash_table::FlashError> {
        TABLE_PAGE_ECC.store(false, Ordering::Relaxed);
        self.flash
            .blocking_read(TABLE_PAGE_OFFSET + offset as u32, buf)
            .map_err(|_| mre_protocol::flash_table::FlashError)?;
        if TABLE_PAGE_ECC.swap(false, Ordering::Relaxed) {
            return Err(mre_protocol::flash_table::FlashError);
        }
        Ok(())
    }

    fn erase(&mut self) -> Result<(), mre_protocol::flash_table::FlashError> {
        let end = TABLE_PAGE_OFFSET + mre_protocol::flash_table::PAGE_BYTES as u32;
        FLASH_SR_ERRORS.store(0, Ordering::Relaxed);
        embassy_futures::block_on(self.flash.erase(TABLE_PAGE_OFFSET, end))
            .map_err(|_| mre_protocol::flash_table::FlashError)?;
        take_flash_errors()
    }

    fn write(&mut self, offset: usize, data: &[u8]) -> Result<(), mre_protocol::flash_table::FlashError> {
        FLASH_SR_ERRORS.store(0, Ordering::Relaxed);
        embassy_futures::block_on(self.flash.write(TABLE_PAGE_OFFSET + offset as u32, data))
            .map_err(|_| mre_protocol::flash_table::FlashError)?;
        take_flash_errors()
    }

    /// ST errata sheet ES0250 (STM32L471/475/476/486; §2.2.2 as embassy's
    /// fix cites it), "Data cache might be corrupted during Flash memory
    /// read-while-write operation": the data cache is disabled while bank 2
    /// is erased or programmed. The control loop keeps running from bank 1,
    /// its literals uncached meanwhile.
    fn begin_update(&mut self) {
        let acr = embassy_stm32::pac::FLASH.acr();
        self.data_cache_was_on = acr.read().dcen();
        acr.modify(|w| w.set_dcen(false));
    }

    /// The erratum's second half: reset the data cache (DCRST works only
    /// with DCEN clear), then re-enable it, before anything reads the page.
    fn end_update(&mut self) {
        let acr = embassy_stm32::pac::FLASH.acr();
        acr.modify(|w| w.set_dcrst(true));
        acr.modify(|w| w.set_dcrst(false));
        if self.data_cache_was_on {
            acr.modify(|w| w.set_dcen(true));
        }
    }
}

/// The table upload receiver: the VCP UART (`None` if it could not be
/// configured: boot still reads the page) and the flash page.
pub struct Uplink {
    uart: Option<BufferedUart<'static>>,
    page: FlashPage,
}

impl Uplink {
    pub fn new(
        uart: Option<BufferedUart<'static>>,
        flash: embassy_stm32::flash::Flash<'static, embassy_stm32::flash::Async>,
    ) -> Self {
        Self {
            uart,
            page: FlashPage {
                flash,
                data_cache_was_on: false,
            },
        }
    }
}

/// The table boot flies: the flash page if it holds a valid upload, else
/// the image's own (`mre_protocol::upload::choose_boot_table`).
pub fn boot_table(uplink: &mut Option<Uplink>, built_in: &TableImage<'_>, rate_hz: u32) -> BootTable {
    match uplink.as_mut() {
        Some(up) => choose_boot_table(&mut up.page, built_in, rate_hz),
        // Only after `spawn_uplink`, which `main` calls later.
        None => choose_boot_table(&mut mre_protocol::flash_table::RamPage::erased(), built_in, rate_hz),
    }
}

/// Starts the upload receiver (thread mode, below the control task).
pub fn spawn_uplink(spawner: &embassy_executor::Spawner, uplink: &mut Option<Uplink>) {
    let Some(Uplink { uart: Some(uart), page }) = uplink.take() else {
        return;
    };
    if cfg!(feature = "uploads-disabled") {
        // Deployment build: the VCP is unauthenticated (firmware/README.md).
        defmt::info!("table upload: disabled in this build (feature uploads-disabled)");
        return;
    }
    match upload_task(uart, page) {
        Ok(token) => spawner.spawn(token),
        Err(_) => defmt::error!("upload task already running"),
    }
}

/// `mre upload --port PORT model.toml` lands here: config frames on the
/// VCP, validated, written to the flash page and read back, answered with a
/// hello frame (`TABLE_FAULT` if refused). The table flies after the next
/// reset; the running controller is never swapped mid-operation.
#[embassy_executor::task]
async fn upload_task(mut uart: BufferedUart<'static>, mut page: FlashPage) {
    use embedded_io_async::{Read, Write};
    use mre_protocol::upload::{PortEvent, UploadPort};
    defmt::info!("table upload: listening on the ST-LINK VCP (115200 8N1)");
    let mut port = UploadPort::new();
    let mut buf = [0u8; 32];
    loop {
        let n = match uart.read(&mut buf).await {
            Ok(n) => n,
            Err(e) => {
                defmt::warn!("table upload: VCP read error {}", e);
                continue;
            }
        };
        for &byte in buf.get(..n).unwrap_or_default() {
            let Some(event) = port.push(byte, &mut page, super::UPLOAD_GATE.at_rest()) else {
                continue;
            };
            match &event {
                PortEvent::Ping => {}
                PortEvent::Commit(Ok((t, c))) => defmt::info!(
                    "table upload: stored in the flash page, CRC {=u32:#010x}, {=usize} currents, {=u32} Hz; flown after the next reset",
                    t.crc32(),
                    t.entries().len(),
                    c.rate_hz
                ),
                // Which value was out of limits: `mre upload` names it from the
                // answer, so the names stay out of the image.
                PortEvent::Commit(Err(e)) => defmt::warn!(
                    "table upload not stored: {=str} ({=u16} frames rejected so far)",
                    e.as_str(),
                    port.rejected_frames()
                ),
            }
            if uart.write_all(&event.answer()).await.is_err() {
                defmt::warn!("table upload: VCP write error");
            }
        }
    }
}
