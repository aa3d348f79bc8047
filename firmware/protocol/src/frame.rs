//! The processor-in-the-loop frame protocol, shared by the firmware's PIL
//! board (USART1 under QEMU) and the host's `mre pil` link.
//!
//! Lockstep: the host sends one [`SampleFrame`] per control period; the
//! firmware runs one control step on it and answers with one
//! [`CommandFrame`] carrying the same sequence number. Both are 24 bytes,
//! little-endian, with a CRC-32 (ISO-HDLC, as zlib) over bytes 0..20:
//!
//! | bytes | sample (host → board, kind 1)          | command (board → host, kind 2)  |
//! |-------|----------------------------------------|---------------------------------|
//! | 0..2  | sync `A5 5A`                           | sync `A5 5A`                    |
//! | 2     | kind = 1                               | kind = 2                        |
//! | 3     | present: bit0 v, bit1 force, bit2 coil current | flags bits 16..24 (0 before `OVER_CURRENT`) |
//! | 4..8  | sequence u32                           | sequence answered u32           |
//! | 8..12 | x_mm f32                               | current_a f32                   |
//! | 12..16| v_m_s f32 (if bit0)                    | target_force_n f32              |
//! | 16..20| force_n f32 (bit1) or coil_current_a f32 (bit2) | flags bits 0..16 u16, rejected frames u16 |
//! | 20..24| CRC-32 of bytes 0..20                  | CRC-32 of bytes 0..20           |
//!
//! The receiver resynchronises on the sync word, so a corrupt or truncated
//! frame costs only that frame. Frames with a bad CRC or kind, or a sequence
//! number older than the last accepted one, are rejected and counted; a
//! repeat of the last sequence is reported as [`FrameError::Duplicate`] so
//! the firmware can re-send its last answer (the host retries on timeout).
use crc::{Crc, CRC_32_ISO_HDLC};
use mre_algorithm::flags::Flags;

pub const FRAME_LEN: usize = 24;
pub const SYNC: [u8; 2] = [0xA5, 0x5A];
pub const KIND_SAMPLE: u8 = 1;
pub const KIND_COMMAND: u8 = 2;
/// A sample with this sequence number ends a PIL run: the firmware logs its
/// link statistics and exits QEMU (semihosting) with status 0.
pub const END_OF_RUN_SEQ: u32 = u32::MAX;
/// PIL images only: a sample with this sequence number makes the firmware
/// panic in the control task (fault injection; its handler answers with
/// the coil's safe command, firmware/README.md "Panic and HardFault").
pub const INJECT_PANIC_SEQ: u32 = u32::MAX - 1;
/// PIL images only: the same with a HardFault (an undefined instruction).
pub const INJECT_HARDFAULT_SEQ: u32 = u32::MAX - 2;
/// The firmware's first command frame carries this sequence number: the
/// link is up and samples may be sent (samples start at 1).
pub const HELLO_SEQ: u32 = 0;
/// A sample frame with this sequence number is a ping: the firmware answers
/// with a hello and runs no step. A host that connects to a board already
/// running (a serial port: `mre pil --serial`, `mre upload`) missed the boot
/// hello, so it pings until one arrives. Pings are not sequenced.
pub const PING_SEQ: u32 = HELLO_SEQ;
const PRESENT_V: u8 = 1 << 0;
const PRESENT_FORCE: u8 = 1 << 1;
const PRESENT_COIL_CURRENT: u8 = 1 << 2;
const CRC_AT: usize = 20;

const CRC32: Crc<u32> = Crc::<u32>::new(&CRC_32_ISO_HDLC);

/// One plant sample for one control period.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SampleFrame {
    pub seq: u32,
    pub x_mm: f32,
    /// `None`: the board config has no velocity sensor; the estimator is used.
    pub v_m_s: Option<f32>,
    /// Measured force, for logging only (the law does not use it).
    pub force_n: Option<f32>,
    /// The coil current the shunt measures (the simulated plant's coil),
    /// checked by the over-current monitor. Takes the force's place in the
    /// frame (bytes 16..20, present bit 2): a frame carries one of the two.
    pub coil_current_a: Option<f32>,
}

/// The firmware's answer to one sample.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CommandFrame {
    pub seq: u32,
    pub current_a: f32,
    pub target_force_n: f32,
    pub flags: Flags,
    /// Frames rejected so far (saturating).
    pub rejected: u16,
}

/// Why a frame was refused.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum FrameError {
    Crc {
        stored: u32,
        computed: u32,
    },
    BadSync,
    BadKind {
        kind: u8,
    },
    /// Older than the last accepted sequence number.
    OutOfOrder {
        seq: u32,
        last: u32,
    },
    /// The last accepted sequence number again (a host retry).
    Duplicate {
        seq: u32,
    },
}

fn put(buf: &mut [u8; FRAME_LEN], at: usize, bytes: [u8; 4]) {
    for (slot, b) in buf.iter_mut().skip(at).zip(bytes) {
        *slot = b;
    }
}

fn get4(buf: &[u8; FRAME_LEN], at: usize) -> [u8; 4] {
    let mut out = [0u8; 4];
    for (slot, b) in out.iter_mut().zip(buf.iter().skip(at)) {
        *slot = *b;
    }
    out
}

fn seal(buf: &mut [u8; FRAME_LEN]) {
    let (body, _) = buf.split_at(CRC_AT);
    let crc = CRC32.checksum(body);
    put(buf, CRC_AT, crc.to_le_bytes());
}

/// Checks sync, CRC and kind of a complete frame.
fn check(buf: &[u8; FRAME_LEN], kind: u8) -> Result<(), FrameError> {
    if buf.get(..2) != Some(&SYNC[..]) {
        return Err(FrameError::BadSync);
    }
    let (body, _) = buf.split_at(CRC_AT);
    let computed = CRC32.checksum(body);
    let stored = u32::from_le_bytes(get4(buf, CRC_AT));
    if stored != computed {
        return Err(FrameError::Crc { stored, computed });
    }
    let found = buf.get(2).copied().unwrap_or(0);
    if found != kind {
        return Err(FrameError::BadKind { kind: found });
    }
    Ok(())
}

impl SampleFrame {
    /// The host's handshake ([`PING_SEQ`]): answered with a hello, no step.
    pub fn ping() -> Self {
        Self {
            seq: PING_SEQ,
            x_mm: 0.0,
            v_m_s: None,
            force_n: None,
            coil_current_a: None,
        }
    }

    pub fn encode(&self) -> [u8; FRAME_LEN] {
        let mut buf = [0u8; FRAME_LEN];
        let slot4 = match (self.coil_current_a, self.force_n) {
            (Some(i), _) => Some((PRESENT_COIL_CURRENT, i)),
            (None, Some(f)) => Some((PRESENT_FORCE, f)),
            (None, None) => None,
        };
        let present = if self.v_m_s.is_some() { PRESENT_V } else { 0 } | slot4.map_or(0, |(bit, _)| bit);
        let [s0, s1] = SYNC;
        put(&mut buf, 0, [s0, s1, KIND_SAMPLE, present]);
        put(&mut buf, 4, self.seq.to_le_bytes());
        put(&mut buf, 8, self.x_mm.to_le_bytes());
        put(&mut buf, 12, self.v_m_s.unwrap_or(0.0).to_le_bytes());
        put(&mut buf, 16, slot4.map_or(0.0, |(_, value)| value).to_le_bytes());
        seal(&mut buf);
        buf
    }

    /// Decodes one complete frame (no sequence check: see [`SampleReceiver`]).
    pub fn decode(buf: &[u8; FRAME_LEN]) -> Result<Self, FrameError> {
        check(buf, KIND_SAMPLE)?;
        let present = buf.get(3).copied().unwrap_or(0);
        let f = |at| f32::from_le_bytes(get4(buf, at));
        Ok(Self {
            seq: u32::from_le_bytes(get4(buf, 4)),
            x_mm: f(8),
            v_m_s: (present & PRESENT_V != 0).then(|| f(12)),
            force_n: (present & (PRESENT_FORCE | PRESENT_COIL_CURRENT) == PRESENT_FORCE).then(|| f(16)),
            coil_current_a: (present & PRESENT_COIL_CURRENT != 0).then(|| f(16)),
        })
    }
}

impl CommandFrame {
    /// The hello frame (sequence [`HELLO_SEQ`]): sent when the PIL link comes
    /// up, and as the answer to a configuration commit (`TABLE_FAULT` when
    /// the upload was refused or not stored).
    pub fn hello(flags: Flags) -> Self {
        Self {
            seq: HELLO_SEQ,
            current_a: 0.0,
            target_force_n: 0.0,
            flags,
            rejected: 0,
        }
    }

    pub fn encode(&self) -> [u8; FRAME_LEN] {
        let mut buf = [0u8; FRAME_LEN];
        let [s0, s1] = SYNC;
        let [f0, f1, f2, _] = self.flags.0.to_le_bytes();
        put(&mut buf, 0, [s0, s1, KIND_COMMAND, f2]);
        put(&mut buf, 4, self.seq.to_le_bytes());
        put(&mut buf, 8, self.current_a.to_le_bytes());
        put(&mut buf, 12, self.target_force_n.to_le_bytes());
        let [r0, r1] = self.rejected.to_le_bytes();
        put(&mut buf, 16, [f0, f1, r0, r1]);
        seal(&mut buf);
        buf
    }

    pub fn decode(buf: &[u8; FRAME_LEN]) -> Result<Self, FrameError> {
        check(buf, KIND_COMMAND)?;
        let [f0, f1, r0, r1] = get4(buf, 16);
        let f2 = buf.get(3).copied().unwrap_or(0);
        Ok(Self {
            seq: u32::from_le_bytes(get4(buf, 4)),
            current_a: f32::from_le_bytes(get4(buf, 8)),
            target_force_n: f32::from_le_bytes(get4(buf, 12)),
            flags: Flags(u32::from_le_bytes([f0, f1, f2, 0])),
            rejected: u16::from_le_bytes([r0, r1]),
        })
    }
}

/// Link counters, reported in every command frame and in the stats log.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct LinkStats {
    pub accepted: u32,
    pub crc_errors: u32,
    pub bad_kind: u32,
    pub out_of_order: u32,
    pub duplicates: u32,
    /// Sequence numbers skipped between accepted frames (lost frames).
    pub lost: u32,
    /// Bytes thrown away while looking for a sync word.
    pub skipped_bytes: u32,
}

impl LinkStats {
    /// Frames refused (corrupt or out of order), saturated to the frame field.
    pub fn rejected(&self) -> u16 {
        let n = self
            .crc_errors
            .saturating_add(self.bad_kind)
            .saturating_add(self.out_of_order);
        u16::try_from(n).unwrap_or(u16::MAX)
    }
}

/// What a complete frame from the host carried.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Incoming {
    Sample(SampleFrame),
    Config(ConfigChunk),
}

/// Byte-stream receiver for sample frames with resync and sequence checks.
#[derive(Clone, Copy, Debug)]
pub struct SampleReceiver {
    buf: [u8; FRAME_LEN],
    len: usize,
    last_seq: Option<u32>,
    stats: LinkStats,
}

impl Default for SampleReceiver {
    fn default() -> Self {
        Self::new()
    }
}

impl SampleReceiver {
    pub const fn new() -> Self {
        Self {
            buf: [0; FRAME_LEN],
            len: 0,
            last_seq: None,
            stats: LinkStats {
                accepted: 0,
                crc_errors: 0,
                bad_kind: 0,
                out_of_order: 0,
                duplicates: 0,
                lost: 0,
                skipped_bytes: 0,
            },
        }
    }

    pub fn stats(&self) -> LinkStats {
        self.stats
    }

    /// Feeds one received byte; returns a result when a sample frame
    /// completes. Config frames are refused here (counted as a bad kind);
    /// a receiver that accepts them uses [`SampleReceiver::push_any`].
    pub fn push(&mut self, byte: u8) -> Option<Result<SampleFrame, FrameError>> {
        match self.push_any(byte)? {
            Ok(Incoming::Sample(s)) => Some(Ok(s)),
            Ok(Incoming::Config(_)) => {
                self.stats.bad_kind = self.stats.bad_kind.saturating_add(1);
                Some(Err(FrameError::BadKind { kind: KIND_CONFIG }))
            }
            Err(e) => Some(Err(e)),
        }
    }

    /// Feeds one received byte; returns a sample or config chunk when a
    /// frame completes. Only samples go through the sequence checks.
    pub fn push_any(&mut self, byte: u8) -> Option<Result<Incoming, FrameError>> {
        self.accept_byte(byte);
        if self.len < FRAME_LEN {
            return None;
        }
        let frame = self.buf;
        self.len = 0;
        let decoded = if frame.get(2) == Some(&KIND_CONFIG) {
            ConfigChunk::decode(&frame).map(Incoming::Config)
        } else {
            SampleFrame::decode(&frame).map(Incoming::Sample)
        };
        match decoded {
            Ok(Incoming::Sample(sample)) if sample.seq == PING_SEQ => Some(Ok(Incoming::Sample(sample))),
            Ok(Incoming::Sample(sample)) => Some(self.sequence(sample).map(Incoming::Sample)),
            Ok(chunk) => Some(Ok(chunk)),
            Err(e) => {
                match e {
                    FrameError::BadKind { .. } => self.stats.bad_kind = self.stats.bad_kind.saturating_add(1),
                    _ => self.stats.crc_errors = self.stats.crc_errors.saturating_add(1),
                }
                // The sync word may have been a payload byte: rescan the rest.
                for &b in frame.iter().skip(1) {
                    self.accept_byte(b);
                }
                Some(Err(e))
            }
        }
    }

    /// Sync hunting: keeps a byte only if it can start or extend a frame.
    fn accept_byte(&mut self, byte: u8) {
        let [s0, s1] = SYNC;
        let keep = match self.len {
            0 => byte == s0,
            1 if byte != s1 => {
                // "A5 A5 5A": the second A5 may be the real start.
                self.stats.skipped_bytes = self.stats.skipped_bytes.saturating_add(1);
                if byte != s0 {
                    self.len = 0;
                    self.stats.skipped_bytes = self.stats.skipped_bytes.saturating_add(1);
                }
                return;
            }
            _ => true,
        };
        if !keep {
            self.stats.skipped_bytes = self.stats.skipped_bytes.saturating_add(1);
            return;
        }
        if let Some(slot) = self.buf.get_mut(self.len) {
            *slot = byte;
            self.len = self.len.saturating_add(1);
        }
    }

    fn sequence(&mut self, sample: SampleFrame) -> Result<SampleFrame, FrameError> {
        if let Some(last) = self.last_seq {
            if sample.seq == last {
                self.stats.duplicates = self.stats.duplicates.saturating_add(1);
                return Err(FrameError::Duplicate { seq: sample.seq });
            }
            if sample.seq < last {
                self.stats.out_of_order = self.stats.out_of_order.saturating_add(1);
                return Err(FrameError::OutOfOrder { seq: sample.seq, last });
            }
            self.stats.lost = self
                .stats
                .lost
                .saturating_add(sample.seq.saturating_sub(last).saturating_sub(1));
        }
        self.last_seq = Some(sample.seq);
        self.stats.accepted = self.stats.accepted.saturating_add(1);
        Ok(sample)
    }
}

// ---- Configuration upload (PIL) ---------------------------------------------
//
// Before the first sample the host may upload the controller's table and
// configuration, so the firmware controls the simulated plant with the same
// table and parameters as the host's in-process run. The configuration is a
// blob of 32-bit words (see `encode_config`), sent in config frames (kind 3)
// of up to three words each:
//
// | bytes  | config frame (host → board, kind 3)                            |
// |--------|----------------------------------------------------------------|
// | 0..3   | sync `A5 5A`, kind 3                                           |
// | 3      | words in this frame (1–3); 0 = commit: bytes 4..8 = total words |
// | 4..8   | index of the first word u32                                    |
// | 8..20  | up to three words, little-endian                               |
// | 20..24 | CRC-32 of bytes 0..20                                          |
//
// On commit the firmware decodes the blob, validates the table (its own
// CRC-32 and invariants, `Table::from_image`) and the configuration, and
// answers with a hello frame (sequence 0) whose flags are `NONE` when it
// switched, or `TABLE_FAULT` when it refused and kept its built-in table; its
// `rejected` field then says why (`upload::CommitAnswer`: incomplete,
// invalid, a named value out of the board's limits, not at rest, page failed).

pub const KIND_CONFIG: u8 = 3;
/// Header (2) + 13 per table entry + terms + installation + law (13) +
/// control (7).
pub const CONFIG_MAX_WORDS: usize =
    2 + 13 * MAX_CURRENTS + TERMS_MAX_WORDS + INSTALLATION_WORDS + LAW_WORDS + CONTROL_WORDS;
/// Version 2 tables append their terms: saturation current, sensor delay,
/// coil τ, then one viscous coefficient per entry.
const TERMS_MAX_WORDS: usize = 3 + MAX_CURRENTS;

fn terms_words(version: u16, count: usize) -> usize {
    if version >= mre_algorithm::table::FORMAT_VERSION_2 {
        count.saturating_add(3)
    } else {
        0
    }
}
/// Version 3 tables then append their installation, one word per value.
const INSTALLATION_WORDS: usize = mre_algorithm::installation::FIELD_COUNT;

fn installation_words(version: u16) -> usize {
    if version >= mre_algorithm::table::FORMAT_VERSION_3 {
        INSTALLATION_WORDS
    } else {
        0
    }
}
const LAW_WORDS: usize = 13;

/// The blob's length for `count` entries of format `version`.
fn blob_words(version: u16, count: usize) -> Option<usize> {
    count
        .checked_mul(13)?
        .checked_add(terms_words(version, count))?
        .checked_add(installation_words(version))?
        .checked_add(2 + LAW_WORDS + CONTROL_WORDS)
}
const CONTROL_WORDS: usize = 7;

use mre_algorithm::control::ControlConfig;
use mre_algorithm::installation::{Installation, DEFAULT_INSTALLATION};
use mre_algorithm::law::{LawConfig, ReboundPolicy};
use mre_algorithm::table::{CurrentEntry, ModelTerms, Quartic, Table, TableImage, MAX_CURRENTS};

/// One received piece of the configuration blob.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ConfigChunk {
    Words { index: u32, count: u8, words: [u32; 3] },
    Commit { total_words: u32 },
}

impl ConfigChunk {
    pub fn encode(&self) -> [u8; FRAME_LEN] {
        let mut buf = [0u8; FRAME_LEN];
        let [s0, s1] = SYNC;
        match *self {
            ConfigChunk::Words { index, count, words } => {
                put(&mut buf, 0, [s0, s1, KIND_CONFIG, count]);
                put(&mut buf, 4, index.to_le_bytes());
                for (k, w) in words.iter().enumerate() {
                    put(&mut buf, k.wrapping_mul(4).wrapping_add(8), w.to_le_bytes());
                }
            }
            ConfigChunk::Commit { total_words } => {
                put(&mut buf, 0, [s0, s1, KIND_CONFIG, 0]);
                put(&mut buf, 4, total_words.to_le_bytes());
            }
        }
        seal(&mut buf);
        buf
    }

    pub fn decode(buf: &[u8; FRAME_LEN]) -> Result<Self, FrameError> {
        check(buf, KIND_CONFIG)?;
        let count = buf.get(3).copied().unwrap_or(0);
        let index = u32::from_le_bytes(get4(buf, 4));
        if count == 0 {
            return Ok(ConfigChunk::Commit { total_words: index });
        }
        if count > 3 {
            return Err(FrameError::BadKind { kind: KIND_CONFIG });
        }
        let w = |k: usize| u32::from_le_bytes(get4(buf, k.wrapping_mul(4).wrapping_add(8)));
        Ok(ConfigChunk::Words {
            index,
            count,
            words: [w(0), w(1), w(2)],
        })
    }
}

/// A blob as the frames that upload it: config chunks of up to three words,
/// then the commit (host side: `mre pil`, `mre upload`).
pub fn config_frames(words: &[u32]) -> impl Iterator<Item = [u8; FRAME_LEN]> + '_ {
    let chunks = words.chunks(3).enumerate().map(|(k, chunk)| {
        let mut three = [0u32; 3];
        for (d, s) in three.iter_mut().zip(chunk) {
            *d = *s;
        }
        ConfigChunk::Words {
            index: (k as u32).saturating_mul(3),
            count: chunk.len() as u8,
            words: three,
        }
        .encode()
    });
    let commit = ConfigChunk::Commit {
        total_words: words.len() as u32,
    };
    chunks.chain(core::iter::once(commit.encode()))
}

/// Why an uploaded configuration was refused.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ConfigBlobError {
    /// Wrong length, a missing word, or a word index out of range.
    Incomplete,
    Table(mre_algorithm::table::TableError),
    Control(mre_algorithm::control::ControlConfigError),
    BadRebound,
    /// Consistent, but outside what the board's hardware takes (`limits`).
    OutOfLimits(mre_algorithm::limits::Limit),
    /// The table's installation (format 3) is outside the board's limits.
    InstallationOutOfLimits(mre_algorithm::limits::InstallationLimit),
    /// The configuration's mass, stroke, coil or sensor values are not the
    /// ones the table's installation (format 3) sets (`Installation::apply`).
    InstallationMismatch,
}

/// Appends the blob for `table` and `cfg` to `out` (returns the word count):
/// word 0 = format version | entry count << 16, word 1 = table CRC-32, then
/// per entry current, x_min, x_max, compression c0..c4, extension c0..c4;
/// format 2 on: saturation current, sensor delay, coil τ, one viscous
/// coefficient per entry; format 3 on: the installation's values
/// (`Installation::FIELD_NAMES`' order); then the law (mass, stroke, g, current min/max, slew, fail-safe, rebound
/// kind (0 minimum, 1 fixed, 2 hold), rebound current, branch band, x valid
/// min/max, v valid max) and the control settings (rate, α, range samples,
/// stuck samples, stuck speed, overrun limit, overrun window). f32 as bits.
pub fn encode_config(table: &Table, cfg: &ControlConfig, out: &mut [u32; CONFIG_MAX_WORDS]) -> usize {
    let entries = table.entries();
    let mut words = out.iter_mut();
    let mut n = 0usize;
    let mut push = |w: u32| {
        if let Some(slot) = words.next() {
            *slot = w;
            n = n.saturating_add(1);
        }
    };
    push(u32::from(table.version()) | ((entries.len() as u32) << 16));
    push(table.crc32());
    for e in entries {
        for f in [e.current_a, e.x_min_mm, e.x_max_mm] {
            push(f.to_bits());
        }
        for c in e.compression.coeffs.iter().chain(e.extension.coeffs.iter()) {
            push(c.to_bits());
        }
    }
    if terms_words(table.version(), entries.len()) > 0 {
        let t = table.terms();
        for f in [t.saturation_current_a, t.sensor_delay_s, t.coil_tau_s] {
            push(f.to_bits());
        }
        for c in t.viscous_n_s_per_m.iter().take(entries.len()) {
            push(c.to_bits());
        }
    }
    if installation_words(table.version()) > 0 {
        for v in table.installation().to_array() {
            push(v.to_bits());
        }
    }
    let law = &cfg.law;
    let (rebound_kind, rebound_a) = match law.rebound {
        ReboundPolicy::Minimum => (0, 0.0),
        ReboundPolicy::Fixed { current_a } => (1, current_a),
        ReboundPolicy::Hold => (2, 0.0),
    };
    for f in [
        law.mass_kg,
        law.stroke_max_mm,
        law.gravity_m_s2,
        law.current_min_a,
        law.current_max_a,
        law.slew_a_per_s,
    ] {
        push(f.to_bits());
    }
    push(law.failsafe_current_a.to_bits());
    push(rebound_kind);
    for f in [
        rebound_a,
        law.branch_band_m_s,
        law.x_valid_min_mm,
        law.x_valid_max_mm,
        law.v_valid_max_m_s,
    ] {
        push(f.to_bits());
    }
    push(cfg.rate_hz);
    push(cfg.estimator_alpha.to_bits());
    push(u32::from(cfg.range_fault_samples));
    push(u32::from(cfg.stuck_samples));
    push(cfg.stuck_min_speed_m_s.to_bits());
    push(u32::from(cfg.overrun_limit));
    push(u32::from(cfg.overrun_window));
    n
}

/// Inverse of [`encode_config`], with full validation: the table goes
/// through `Table::from_image` (version, invariants, CRC), the control
/// configuration through `ControlConfig::validate` and the board's hard
/// limits (`limits::BOARD`).
pub fn decode_config(words: &[u32]) -> Result<(Table, ControlConfig), ConfigBlobError> {
    let mut it = words.iter().copied();
    let mut next = || it.next().ok_or(ConfigBlobError::Incomplete);
    let head = next()?;
    let version = (head & 0xFFFF) as u16;
    let count = (head >> 16) as usize;
    if count > MAX_CURRENTS || Some(words.len()) != blob_words(version, count) {
        return Err(ConfigBlobError::Incomplete);
    }
    let crc32 = next()?;
    let mut entries = [CurrentEntry {
        current_a: 0.0,
        compression: Quartic::new([0.0; 5]),
        extension: Quartic::new([0.0; 5]),
        x_min_mm: 0.0,
        x_max_mm: 0.0,
    }; MAX_CURRENTS];
    for e in entries.iter_mut().take(count) {
        e.current_a = f32::from_bits(next()?);
        e.x_min_mm = f32::from_bits(next()?);
        e.x_max_mm = f32::from_bits(next()?);
        for c in e.compression.coeffs.iter_mut().chain(e.extension.coeffs.iter_mut()) {
            *c = f32::from_bits(next()?);
        }
    }
    let mut terms = ModelTerms::NONE;
    if terms_words(version, count) > 0 {
        terms.saturation_current_a = f32::from_bits(next()?);
        terms.sensor_delay_s = f32::from_bits(next()?);
        terms.coil_tau_s = f32::from_bits(next()?);
        for c in terms.viscous_n_s_per_m.iter_mut().take(count) {
            *c = f32::from_bits(next()?);
        }
    }
    let mut installation = DEFAULT_INSTALLATION.to_array();
    if installation_words(version) > 0 {
        for v in installation.iter_mut() {
            *v = f32::from_bits(next()?);
        }
    }
    let image = TableImage {
        version,
        entries: entries.get(..count).unwrap_or(&[]),
        terms,
        installation: Installation::from_array(installation),
        crc32,
    };
    let table = Table::from_image(&image).map_err(ConfigBlobError::Table)?;

    let mut f = || next().map(f32::from_bits);
    let (mass_kg, stroke_max_mm, gravity_m_s2, current_min_a, current_max_a, slew_a_per_s, failsafe_current_a) =
        (f()?, f()?, f()?, f()?, f()?, f()?, f()?);
    let rebound_kind = f()?.to_bits();
    let rebound_a = f()?;
    let rebound = match rebound_kind {
        0 => ReboundPolicy::Minimum,
        1 => ReboundPolicy::Fixed { current_a: rebound_a },
        2 => ReboundPolicy::Hold,
        _ => return Err(ConfigBlobError::BadRebound),
    };
    let (branch_band_m_s, x_valid_min_mm, x_valid_max_mm, v_valid_max_m_s) = (f()?, f()?, f()?, f()?);
    let rate_hz = f()?.to_bits();
    let estimator_alpha = f()?;
    let small = |w: u32| u16::try_from(w).map_err(|_| ConfigBlobError::Incomplete);
    let range_fault_samples = small(f()?.to_bits())?;
    let stuck_samples = small(f()?.to_bits())?;
    let stuck_min_speed_m_s = f()?;
    let overrun_limit = small(f()?.to_bits())?;
    let overrun_window = small(f()?.to_bits())?;
    let period_s = if rate_hz > 0 { 1.0 / rate_hz as f32 } else { 0.0 };
    let mut cfg = ControlConfig {
        rate_hz,
        law: LawConfig {
            mass_kg,
            stroke_max_mm,
            gravity_m_s2,
            current_min_a,
            current_max_a,
            slew_a_per_s,
            failsafe_current_a,
            rebound,
            branch_band_m_s,
            x_valid_min_mm,
            x_valid_max_mm,
            v_valid_max_m_s,
            period_s,
            // Board constants: the same on host and board, not uploaded.
            ..LawConfig::default()
        },
        estimator_alpha,
        range_fault_samples,
        stuck_samples,
        stuck_min_speed_m_s,
        overrun_limit,
        overrun_window,
        // Board constants (the sensor's wiring), not uploaded.
        v_sensor_full_scale_m_s: mre_algorithm::control::V_SENSOR_FULL_SCALE_M_S,
        disagree_m_s: mre_algorithm::control::DISAGREE_M_S,
        disagree_samples: mre_algorithm::control::DISAGREE_SAMPLES,
    };
    if table.version() >= mre_algorithm::table::FORMAT_VERSION_3 {
        // The installation sets the board's wiring (not uploaded) and must
        // agree with the uploaded law values it determines.
        let installation = table.installation();
        mre_algorithm::limits::check_installation_board(installation)
            .map_err(ConfigBlobError::InstallationOutOfLimits)?;
        let mut uploaded = cfg;
        installation.apply(&mut cfg);
        // What is not uploaded (the drive range, the armed current, the
        // fastest expected impact, the velocity sensor's scale) is the
        // installation's; the rest must agree.
        uploaded.law.drive_min_a = cfg.law.drive_min_a;
        uploaded.law.drive_max_a = cfg.law.drive_max_a;
        uploaded.law.armed_current_a = cfg.law.armed_current_a;
        uploaded.law.impact_v_max_m_s = cfg.law.impact_v_max_m_s;
        uploaded.v_sensor_full_scale_m_s = cfg.v_sensor_full_scale_m_s;
        if uploaded != cfg {
            return Err(ConfigBlobError::InstallationMismatch);
        }
    }
    cfg.validate().map_err(ConfigBlobError::Control)?;
    mre_algorithm::limits::check_board(&cfg).map_err(ConfigBlobError::OutOfLimits)?;
    Ok((table, cfg))
}

/// Which words of a blob have arrived: one bit per word, sized from
/// [`CONFIG_MAX_WORDS`] (the largest table with every term).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct ReceivedWords([u32; RECEIVED_WORDS_LEN]);

const RECEIVED_WORDS_LEN: usize = CONFIG_MAX_WORDS.div_ceil(32);

impl ReceivedWords {
    pub const fn none() -> Self {
        Self([0; RECEIVED_WORDS_LEN])
    }

    /// Marks word `at`; false (nothing marked) when it is past the largest blob.
    pub fn mark(&mut self, at: usize) -> bool {
        if at >= CONFIG_MAX_WORDS {
            return false;
        }
        match self.0.get_mut(at / 32) {
            Some(bits) => {
                *bits |= 1 << (at % 32);
                true
            }
            None => false,
        }
    }

    pub fn has(&self, at: usize) -> bool {
        at < CONFIG_MAX_WORDS && self.0.get(at / 32).is_some_and(|bits| bits & (1 << (at % 32)) != 0)
    }

    /// Every word `0..n` has arrived (false when `n` exceeds the largest blob).
    pub fn all_below(&self, n: usize) -> bool {
        n <= CONFIG_MAX_WORDS && (0..n).all(|at| self.has(at))
    }
}

/// Collects config chunks into a blob (firmware side).
#[derive(Clone, Copy, Debug)]
pub struct ConfigCollector {
    words: [u32; CONFIG_MAX_WORDS],
    received: ReceivedWords,
}

impl Default for ConfigCollector {
    fn default() -> Self {
        Self::new()
    }
}

impl ConfigCollector {
    pub const fn new() -> Self {
        Self {
            words: [0; CONFIG_MAX_WORDS],
            received: ReceivedWords::none(),
        }
    }

    /// Stores a chunk; on commit returns the decoded configuration (and
    /// starts over either way).
    pub fn push(&mut self, chunk: ConfigChunk) -> Option<Result<(Table, ControlConfig), ConfigBlobError>> {
        match chunk {
            ConfigChunk::Words { index, count, words } => {
                for (k, w) in words.iter().take(usize::from(count)).enumerate() {
                    let at = (index as usize).saturating_add(k);
                    if let Some(slot) = self.words.get_mut(at) {
                        *slot = *w;
                        self.received.mark(at);
                    }
                }
                None
            }
            ConfigChunk::Commit { total_words } => {
                let n = total_words as usize;
                let result = match self.words.get(..n) {
                    Some(words) if self.received.all_below(n) => decode_config(words),
                    _ => Err(ConfigBlobError::Incomplete),
                };
                *self = Self::new();
                Some(result)
            }
        }
    }
}
