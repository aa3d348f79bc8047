//! Table upload without reflashing: the firmware's receiving end of
//! `mre upload` (the ST-LINK virtual COM port on the boards, USART1 in QEMU).
//!
//! The bytes are the PIL frame protocol's config frames (`frame`: CRC-32 per
//! frame, three words each, then a commit). On commit the blob is decoded
//! and validated (`frame::decode_config`: the table's own CRC, invariants and
//! magnitudes, and the configuration); only then is the flash page erased
//! and written (`flash_table::store`) and read back (`flash_table::load`).
//! A refused upload never touches the page, so the table flown before (an
//! earlier upload, or the built-in one) stays. Every commit is answered with
//! a hello frame, flagged `TABLE_FAULT` unless the page now holds the upload.
//!
//! Boot then picks the table with [`choose_boot_table`]: a valid page first,
//! else the built-in image.
use crate::control::{ControlConfig, ControlConfigError};
use crate::flash_table::{load, store, PageError, TablePage};
use crate::frame::{
    CommandFrame, ConfigBlobError, ConfigChunk, ConfigCollector, Incoming, SampleReceiver, FRAME_LEN, PING_SEQ,
};
use crate::table::{Table, TableError, TableImage};
use crate::Flags;

/// Why an upload was not stored.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum UploadError {
    /// The blob was incomplete (a frame lost or corrupt) or refused by validation.
    Refused(ConfigBlobError),
    /// Writing or reading back the page failed.
    Page(PageError),
}

impl UploadError {
    /// A short reason for logs.
    pub fn as_str(&self) -> &'static str {
        match self {
            UploadError::Refused(ConfigBlobError::Incomplete) => "incomplete (a frame was lost or corrupt)",
            UploadError::Refused(ConfigBlobError::OutOfLimits(_)) => "a value is outside the board's hard limits",
            UploadError::Refused(_) => "table or configuration refused",
            UploadError::Page(e) => e.as_str(),
        }
    }
}

/// What a commit did: the table and configuration the page now holds.
pub type UploadResult = Result<(Table, ControlConfig), UploadError>;

/// Collects config chunks and stores each committed blob on the page.
#[derive(Clone, Copy, Debug, Default)]
pub struct UploadReceiver {
    collector: ConfigCollector,
}

impl UploadReceiver {
    pub const fn new() -> Self {
        Self {
            collector: ConfigCollector::new(),
        }
    }

    /// One config chunk; on a commit, validates, stores and reads back.
    pub fn on_chunk<P: TablePage + ?Sized>(&mut self, chunk: ConfigChunk, page: &mut P) -> Option<UploadResult> {
        let (table, cfg) = match self.collector.push(chunk)? {
            Ok(blob) => blob,
            Err(e) => return Some(Err(UploadError::Refused(e))),
        };
        Some(
            store(page, &table, &cfg)
                .and_then(|()| load(page))
                .map_err(UploadError::Page),
        )
    }
}

/// What an [`UploadPort`] must answer.
// Returned once per commit and answered at once, never stored; no heap to box into.
#[allow(clippy::large_enum_variant)]
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum PortEvent {
    /// The host's handshake: answer `CommandFrame::hello(Flags::NONE)`.
    Ping,
    Commit(UploadResult),
}

impl PortEvent {
    /// The answer frame.
    pub fn answer(&self) -> [u8; FRAME_LEN] {
        match self {
            PortEvent::Ping => CommandFrame::hello(Flags::NONE).encode(),
            PortEvent::Commit(result) => answer(result),
        }
    }
}

/// A byte stream that carries only uploads (the boards' VCP): frames are
/// resynchronised and CRC-checked by [`SampleReceiver`]; anything but config
/// frames is ignored.
#[derive(Clone, Copy, Debug, Default)]
pub struct UploadPort {
    rx: SampleReceiver,
    upload: UploadReceiver,
}

impl UploadPort {
    pub const fn new() -> Self {
        Self {
            rx: SampleReceiver::new(),
            upload: UploadReceiver::new(),
        }
    }

    /// One received byte; `Some` when a frame needs an answer: a commit
    /// (send [`answer`] back) or a ping (send a hello).
    pub fn push<P: TablePage + ?Sized>(&mut self, byte: u8, page: &mut P) -> Option<PortEvent> {
        match self.rx.push_any(byte)? {
            Ok(Incoming::Config(chunk)) => self.upload.on_chunk(chunk, page).map(PortEvent::Commit),
            Ok(Incoming::Sample(s)) if s.seq == PING_SEQ => Some(PortEvent::Ping),
            Ok(Incoming::Sample(_)) | Err(_) => None,
        }
    }

    /// Frames rejected so far (CRC, kind), for the log.
    pub fn rejected_frames(&self) -> u16 {
        self.rx.stats().rejected()
    }
}

/// The answer to a commit: a hello frame, `TABLE_FAULT` unless stored.
pub fn answer(result: &UploadResult) -> [u8; FRAME_LEN] {
    let flags = if result.is_ok() {
        Flags::NONE
    } else {
        Flags::TABLE_FAULT
    };
    CommandFrame::hello(flags).encode()
}

/// Where the table flown after boot came from.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum TableSource {
    /// The flash page (an earlier `mre upload`).
    Uploaded,
    /// The image's own table; why the page was not used.
    BuiltIn(PageError),
}

/// The boot decision: table, configuration and where they came from.
#[derive(Clone, Copy, Debug)]
pub struct BootTable {
    pub table: Result<Table, TableError>,
    pub config: Result<ControlConfig, ControlConfigError>,
    pub source: TableSource,
    /// The page's configuration was for this other rate: only its table is used.
    pub uploaded_rate_ignored_hz: Option<u32>,
}

/// Prefers a valid uploaded page; otherwise the built-in image at the
/// image's `rate_hz` defaults. An uploaded configuration for another control
/// rate than the image's ticker keeps only its table.
pub fn choose_boot_table<P: TablePage + ?Sized>(page: &mut P, built_in: &TableImage<'_>, rate_hz: u32) -> BootTable {
    match load(page) {
        Ok((table, cfg)) if cfg.rate_hz == rate_hz => BootTable {
            table: Ok(table),
            config: Ok(cfg),
            source: TableSource::Uploaded,
            uploaded_rate_ignored_hz: None,
        },
        Ok((table, cfg)) => BootTable {
            table: Ok(table),
            config: ControlConfig::at_rate(rate_hz),
            source: TableSource::Uploaded,
            uploaded_rate_ignored_hz: Some(cfg.rate_hz),
        },
        Err(e) => BootTable {
            table: Table::from_image(built_in),
            config: ControlConfig::at_rate(rate_hz),
            source: TableSource::BuiltIn(e),
            uploaded_rate_ignored_hz: None,
        },
    }
}
