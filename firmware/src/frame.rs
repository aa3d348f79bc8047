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
//! | 3     | present: bit0 velocity, bit1 force     | 0                               |
//! | 4..8  | sequence u32                           | sequence answered u32           |
//! | 8..12 | x_mm f32                               | current_a f32                   |
//! | 12..16| v_m_s f32 (if bit0)                    | target_force_n f32              |
//! | 16..20| force_n f32 (if bit1)                  | flags u16, rejected frames u16  |
//! | 20..24| CRC-32 of bytes 0..20                  | CRC-32 of bytes 0..20           |
//!
//! The receiver resynchronises on the sync word, so a corrupt or truncated
//! frame costs only that frame. Frames with a bad CRC or kind, or a sequence
//! number older than the last accepted one, are rejected and counted; a
//! repeat of the last sequence is reported as [`FrameError::Duplicate`] so
//! the firmware can re-send its last answer (the host retries on timeout).
use crate::flags::Flags;
use crc::{Crc, CRC_32_ISO_HDLC};

pub const FRAME_LEN: usize = 24;
pub const SYNC: [u8; 2] = [0xA5, 0x5A];
pub const KIND_SAMPLE: u8 = 1;
pub const KIND_COMMAND: u8 = 2;
/// A sample with this sequence number ends a PIL run: the firmware logs its
/// link statistics and exits QEMU (semihosting) with status 0.
pub const END_OF_RUN_SEQ: u32 = u32::MAX;
/// The firmware's first command frame carries this sequence number: the
/// link is up and samples may be sent (samples start at 1).
pub const HELLO_SEQ: u32 = 0;
const PRESENT_V: u8 = 1 << 0;
const PRESENT_FORCE: u8 = 1 << 1;
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
    pub fn encode(&self) -> [u8; FRAME_LEN] {
        let mut buf = [0u8; FRAME_LEN];
        let present =
            if self.v_m_s.is_some() { PRESENT_V } else { 0 } | if self.force_n.is_some() { PRESENT_FORCE } else { 0 };
        let [s0, s1] = SYNC;
        put(&mut buf, 0, [s0, s1, KIND_SAMPLE, present]);
        put(&mut buf, 4, self.seq.to_le_bytes());
        put(&mut buf, 8, self.x_mm.to_le_bytes());
        put(&mut buf, 12, self.v_m_s.unwrap_or(0.0).to_le_bytes());
        put(&mut buf, 16, self.force_n.unwrap_or(0.0).to_le_bytes());
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
            force_n: (present & PRESENT_FORCE != 0).then(|| f(16)),
        })
    }
}

impl CommandFrame {
    pub fn encode(&self) -> [u8; FRAME_LEN] {
        let mut buf = [0u8; FRAME_LEN];
        let [s0, s1] = SYNC;
        put(&mut buf, 0, [s0, s1, KIND_COMMAND, 0]);
        put(&mut buf, 4, self.seq.to_le_bytes());
        put(&mut buf, 8, self.current_a.to_le_bytes());
        put(&mut buf, 12, self.target_force_n.to_le_bytes());
        let [f0, f1] = self.flags.0.to_le_bytes();
        let [r0, r1] = self.rejected.to_le_bytes();
        put(&mut buf, 16, [f0, f1, r0, r1]);
        seal(&mut buf);
        buf
    }

    pub fn decode(buf: &[u8; FRAME_LEN]) -> Result<Self, FrameError> {
        check(buf, KIND_COMMAND)?;
        let [f0, f1, r0, r1] = get4(buf, 16);
        Ok(Self {
            seq: u32::from_le_bytes(get4(buf, 4)),
            current_a: f32::from_le_bytes(get4(buf, 8)),
            target_force_n: f32::from_le_bytes(get4(buf, 12)),
            flags: Flags(u16::from_le_bytes([f0, f1])),
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

    /// Feeds one received byte; returns a result when a frame completes.
    pub fn push(&mut self, byte: u8) -> Option<Result<SampleFrame, FrameError>> {
        self.accept_byte(byte);
        if self.len < FRAME_LEN {
            return None;
        }
        let frame = self.buf;
        self.len = 0;
        match SampleFrame::decode(&frame) {
            Ok(sample) => Some(self.sequence(sample)),
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
            self.len += 1;
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
            self.stats.lost = self.stats.lost.saturating_add(sample.seq - last - 1);
        }
        self.last_seq = Some(sample.seq);
        self.stats.accepted = self.stats.accepted.saturating_add(1);
        Ok(sample)
    }
}
