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
//! A valid upload is stored only while the damper is at rest
//! ([`UploadGate`]: the law armed and idle, no motion, for
//! [`REST_BEFORE_UPLOAD_S`]); otherwise it is refused with
//! [`UploadError::NotAtRest`] and the page is not touched: the host retries.
//!
//! Boot then picks the table with [`choose_boot_table`]: a valid page first,
//! else the built-in image.
use crate::flash_table::{load, store, PageError, TablePage};
use crate::frame::{
    CommandFrame, ConfigBlobError, ConfigChunk, ConfigCollector, Incoming, SampleReceiver, FRAME_LEN, PING_SEQ,
};
use core::sync::atomic::{AtomicBool, AtomicU32, Ordering};
use mre_algorithm::control::{ControlConfig, ControlConfigError, Controller};
use mre_algorithm::law::Command;
use mre_algorithm::table::{Table, TableError, TableImage};
use mre_algorithm::Flags;

/// Why an upload was not stored.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum UploadError {
    /// The blob was incomplete (a frame lost or corrupt) or refused by validation.
    Refused(ConfigBlobError),
    /// Valid, but the damper was not at rest: not stored (retry when still).
    NotAtRest,
    /// Writing or reading back the page failed.
    Page(PageError),
}

impl UploadError {
    /// A short reason for logs.
    pub fn as_str(&self) -> &'static str {
        match self {
            UploadError::Refused(ConfigBlobError::Incomplete) => "incomplete (a frame was lost or corrupt)",
            UploadError::Refused(ConfigBlobError::OutOfLimits(_) | ConfigBlobError::InstallationOutOfLimits(_)) => {
                "a value out of the board's limits"
            }
            UploadError::Refused(ConfigBlobError::InstallationMismatch) => {
                "configuration disagrees with the table's installation"
            }
            UploadError::Refused(_) => "table or configuration refused",
            UploadError::NotAtRest => "not at rest (retry when still)",
            UploadError::Page(e) => e.as_str(),
        }
    }
}

/// What a commit did: the table and configuration the page now holds.
pub type UploadResult = Result<(Table, ControlConfig), UploadError>;

/// How long the damper must have been still before an upload is stored: an
/// impact (tens of ms) and its rebounds are long over.
pub const REST_BEFORE_UPLOAD_S: f32 = 0.5;

/// The upload's side of the control loop: counts the periods the damper has
/// been at rest, the law armed (no fault latched) and idle (no force asked,
/// not compressing), no motion (`Controller::is_at_rest`).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct UploadGate {
    still_periods: u32,
}

impl UploadGate {
    pub const fn new() -> Self {
        Self { still_periods: 0 }
    }

    /// A gate that has seen this many still periods (the boards keep the
    /// count in an atomic between the control and upload tasks).
    pub const fn with_still_periods(still_periods: u32) -> Self {
        Self { still_periods }
    }

    /// After each control step.
    pub fn observe(&mut self, ctl: &Controller, cmd: &Command) {
        let still = !ctl.latched().is_fault()
            && !cmd.flags.is_fault()
            && cmd.target_force_n == 0.0
            && cmd.branch == mre_algorithm::Branch::Extension
            && ctl.is_at_rest();
        self.still_periods = if still { self.still_periods.saturating_add(1) } else { 0 };
    }

    pub fn still_periods(&self) -> u32 {
        self.still_periods
    }

    /// Still for [`REST_BEFORE_UPLOAD_S`] at `rate_hz`.
    pub fn at_rest(&self, rate_hz: u32) -> bool {
        self.still_periods as f32 >= REST_BEFORE_UPLOAD_S * rate_hz as f32
    }
}

/// An [`UploadGate`] shared between the control loop (the only writer,
/// [`SharedUploadGate::observe`] after each step) and the upload receiver.
#[derive(Debug, Default)]
pub struct SharedUploadGate {
    still_periods: AtomicU32,
    at_rest: AtomicBool,
}

impl SharedUploadGate {
    pub const fn new() -> Self {
        Self {
            still_periods: AtomicU32::new(0),
            at_rest: AtomicBool::new(false),
        }
    }

    pub fn observe(&self, ctl: &Controller, cmd: &Command) {
        let mut gate = UploadGate::with_still_periods(self.still_periods.load(Ordering::Relaxed));
        gate.observe(ctl, cmd);
        self.still_periods.store(gate.still_periods(), Ordering::Relaxed);
        self.at_rest
            .store(gate.at_rest(ctl.config().rate_hz), Ordering::Relaxed);
    }

    pub fn at_rest(&self) -> bool {
        self.at_rest.load(Ordering::Relaxed)
    }
}

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

    /// One config chunk; on a commit, validates, then (only `at_rest`)
    /// stores and reads back.
    pub fn on_chunk<P: TablePage + ?Sized>(
        &mut self,
        chunk: ConfigChunk,
        page: &mut P,
        at_rest: bool,
    ) -> Option<UploadResult> {
        let (table, cfg) = match self.collector.push(chunk)? {
            Ok(blob) => blob,
            Err(e) => return Some(Err(UploadError::Refused(e))),
        };
        if !at_rest {
            return Some(Err(UploadError::NotAtRest));
        }
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
    /// (send [`answer`] back) or a ping (send a hello). `at_rest`: the
    /// damper's [`UploadGate`] now.
    pub fn push<P: TablePage + ?Sized>(&mut self, byte: u8, page: &mut P, at_rest: bool) -> Option<PortEvent> {
        match self.rx.push_any(byte)? {
            Ok(Incoming::Config(chunk)) => self.upload.on_chunk(chunk, page, at_rest).map(PortEvent::Commit),
            Ok(Incoming::Sample(s)) if s.seq == PING_SEQ => Some(PortEvent::Ping),
            Ok(Incoming::Sample(_)) | Err(_) => None,
        }
    }

    /// Frames rejected so far (CRC, kind), for the log.
    pub fn rejected_frames(&self) -> u16 {
        self.rx.stats().rejected()
    }
}

/// The answer to a commit: a hello frame, `TABLE_FAULT` unless stored, with
/// why in its `rejected` field ([`CommitAnswer::code`]).
pub fn answer(result: &UploadResult) -> [u8; FRAME_LEN] {
    let flags = if result.is_ok() {
        Flags::NONE
    } else {
        Flags::TABLE_FAULT
    };
    let mut hello = CommandFrame::hello(flags);
    hello.rejected = CommitAnswer::of(result).code();
    hello.encode()
}

/// Why a commit was answered as it was, as the answer frame carries it.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum CommitAnswer {
    Stored,
    /// A frame was lost or corrupt.
    Incomplete,
    /// The table or configuration is invalid.
    Invalid,
    /// A value is outside the board's hard limits.
    OutOfLimits(mre_algorithm::limits::Limit),
    /// A table's installation value is outside the board's hard limits.
    InstallationOutOfLimits(mre_algorithm::limits::InstallationLimit),
    /// Valid, but the damper was not at rest: retry when it is still.
    NotAtRest,
    /// The flash page could not be written or read back.
    PageFailed,
}

const CODE_STORED: u16 = 0;
const CODE_INCOMPLETE: u16 = 1;
const CODE_INVALID: u16 = 2;
const CODE_NOT_AT_REST: u16 = 3;
const CODE_PAGE_FAILED: u16 = 4;
/// Out of limits: this plus the limit's index in `Limit::ALL`.
const CODE_OUT_OF_LIMITS: u16 = 0x100;
/// Installation out of limits: this plus the value's index in
/// `Installation::FIELD_NAMES`.
const CODE_INSTALLATION_OUT_OF_LIMITS: u16 = 0x200;

impl CommitAnswer {
    pub fn of(result: &UploadResult) -> Self {
        match result {
            Ok(_) => CommitAnswer::Stored,
            Err(UploadError::Refused(ConfigBlobError::Incomplete)) => CommitAnswer::Incomplete,
            Err(UploadError::Refused(ConfigBlobError::OutOfLimits(l))) => CommitAnswer::OutOfLimits(*l),
            Err(UploadError::Refused(ConfigBlobError::InstallationOutOfLimits(l))) => {
                CommitAnswer::InstallationOutOfLimits(*l)
            }
            Err(UploadError::Refused(_)) => CommitAnswer::Invalid,
            Err(UploadError::NotAtRest) => CommitAnswer::NotAtRest,
            Err(UploadError::Page(_)) => CommitAnswer::PageFailed,
        }
    }

    pub fn code(&self) -> u16 {
        match self {
            CommitAnswer::Stored => CODE_STORED,
            CommitAnswer::Incomplete => CODE_INCOMPLETE,
            CommitAnswer::Invalid => CODE_INVALID,
            CommitAnswer::NotAtRest => CODE_NOT_AT_REST,
            CommitAnswer::PageFailed => CODE_PAGE_FAILED,
            // `Limit` is fieldless: its discriminant is its index in `Limit::ALL`.
            CommitAnswer::OutOfLimits(l) => CODE_OUT_OF_LIMITS.saturating_add(*l as u16),
            CommitAnswer::InstallationOutOfLimits(l) => CODE_INSTALLATION_OUT_OF_LIMITS.saturating_add(u16::from(l.0)),
        }
    }

    /// The host's reading of an answer frame's `rejected` field (`None`:
    /// a code this host does not know).
    pub fn from_code(code: u16) -> Option<Self> {
        match code {
            CODE_STORED => Some(CommitAnswer::Stored),
            CODE_INCOMPLETE => Some(CommitAnswer::Incomplete),
            CODE_INVALID => Some(CommitAnswer::Invalid),
            CODE_NOT_AT_REST => Some(CommitAnswer::NotAtRest),
            CODE_PAGE_FAILED => Some(CommitAnswer::PageFailed),
            CODE_INSTALLATION_OUT_OF_LIMITS.. => {
                let k = code.checked_sub(CODE_INSTALLATION_OUT_OF_LIMITS)?;
                u8::try_from(k)
                    .ok()
                    .filter(|k| usize::from(*k) < mre_algorithm::installation::FIELD_COUNT)
                    .map(|k| CommitAnswer::InstallationOutOfLimits(mre_algorithm::limits::InstallationLimit(k)))
            }
            _ => mre_algorithm::limits::Limit::ALL
                .get(usize::from(code.checked_sub(CODE_OUT_OF_LIMITS)?))
                .map(|l| CommitAnswer::OutOfLimits(*l)),
        }
    }
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
/// image's `rate_hz` defaults with the built-in table's installation
/// ([`installed_config`]). An uploaded configuration for another control
/// rate than the image's ticker keeps only its table (and its installation).
pub fn choose_boot_table<P: TablePage + ?Sized>(page: &mut P, built_in: &TableImage<'_>, rate_hz: u32) -> BootTable {
    match load(page) {
        Ok((table, cfg)) if cfg.rate_hz == rate_hz => BootTable {
            table: Ok(table),
            config: Ok(cfg),
            source: TableSource::Uploaded,
            uploaded_rate_ignored_hz: None,
        },
        Ok((table, cfg)) => BootTable {
            config: installed_config(&table, rate_hz),
            table: Ok(table),
            source: TableSource::Uploaded,
            uploaded_rate_ignored_hz: Some(cfg.rate_hz),
        },
        Err(e) => {
            // A built-in installation outside the board's limits is refused
            // like a corrupt table: fail-safe current, TABLE_FAULT latched.
            let table = Table::from_image(built_in).and_then(|t| {
                mre_algorithm::limits::check_installation_board(t.installation())
                    .map(|()| t)
                    .map_err(|l| TableError::BadInstallation { field: l.name() })
            });
            BootTable {
                config: match &table {
                    Ok(t) => installed_config(t, rate_hz),
                    Err(_) => ControlConfig::at_rate(rate_hz),
                },
                table,
                source: TableSource::BuiltIn(e),
                uploaded_rate_ignored_hz: None,
            }
        }
    }
}

/// The defaults at `rate_hz` with `table`'s installation applied (a format
/// 1 or 2 table's is [`mre_algorithm::installation::DEFAULT_INSTALLATION`], which
/// the defaults already are).
pub fn installed_config(table: &Table, rate_hz: u32) -> Result<ControlConfig, ControlConfigError> {
    let mut cfg = ControlConfig::at_rate(rate_hz)?;
    table.installation().apply(&mut cfg);
    cfg.validate()?;
    Ok(cfg)
}
