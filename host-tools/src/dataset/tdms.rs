//! NI TDMS files (NI, "TDMS File Format Internal Structure": "Lead In",
//! "Meta Data", "Raw Data"), read through the `tdms-rs` crate.
//!
//! Every numeric channel of every group is a column, named from its
//! channel name and its `unit_string` property (`Force` with `kN` →
//! `Force (kN)`). Without a time channel, the time is
//! `wf_start_offset` + k·`wf_increment` (the waveform properties, in s),
//! which all channels must share.
//!
//! `tdms-rs` reads little-endian, non-interleaved segments holding one chunk
//! of raw data each, and takes a cut-off segment as the end of the file. So
//! the segments' lead-ins are checked first: a big-endian, interleaved or
//! DAQmx-raw segment, one that runs past the end of the file, and raw data
//! the channels do not account for (repeated chunks) are refused, never read
//! in part.
use super::error::DatasetError;
use super::read::Cell;
use super::vendor::{Table, VendorReader};
use std::path::Path;
use tdms_rs::{DataType, PropertyValue, TdmsChannel, TdmsFile};

pub const READER: VendorReader = VendorReader {
    name: "NI TDMS",
    recognises,
    read,
};

const TAG: &[u8] = b"TDSm";
const LEAD_IN_BYTES: u64 = 28;
// Table-of-contents flags (NI's "Lead In" section).
const TOC_RAW_DATA: u32 = 1 << 3;
const TOC_INTERLEAVED: u32 = 1 << 5;
const TOC_BIG_ENDIAN: u32 = 1 << 6;
const TOC_DAQMX_RAW: u32 = 1 << 7;

fn recognises(bytes: &[u8]) -> bool {
    bytes.starts_with(TAG)
}

fn u32_at(b: &[u8], at: usize) -> u32 {
    u32::from_le_bytes([b[at], b[at + 1], b[at + 2], b[at + 3]])
}

fn u64_at(b: &[u8], at: usize) -> u64 {
    let mut v = [0u8; 8];
    v.copy_from_slice(&b[at..at + 8]);
    u64::from_le_bytes(v)
}

/// Walks the lead-ins; returns the bytes of raw data the segments hold, or
/// why the file cannot be read whole.
fn raw_data_bytes(bytes: &[u8]) -> Result<u64, String> {
    let len = bytes.len() as u64;
    let (mut at, mut raw, mut segment) = (0u64, 0u64, 0usize);
    while at < len {
        segment += 1;
        let start = at as usize;
        let Some(lead_in) = bytes.get(start..start + LEAD_IN_BYTES as usize) else {
            return Err(format!("the file is cut short in the lead-in of segment {segment}"));
        };
        if &lead_in[..4] != TAG {
            return Err(format!("segment {segment} does not start with the TDSm tag"));
        }
        let toc = u32_at(lead_in, 4);
        let next = u64_at(lead_in, 12);
        let raw_offset = u64_at(lead_in, 20);
        if toc & TOC_BIG_ENDIAN != 0 {
            return Err(format!(
                "segment {segment} is big-endian, which mre's TDMS reader does not read"
            ));
        }
        // DAQmx raw segments are flagged interleaved too: name the DAQmx data.
        if toc & TOC_DAQMX_RAW != 0 {
            return Err(format!(
                "segment {segment} holds DAQmx raw data, which mre's TDMS reader does not read; \
                 log scaled data instead"
            ));
        }
        if toc & TOC_INTERLEAVED != 0 {
            return Err(format!(
                "segment {segment} holds interleaved data, which mre's TDMS reader does not read; \
                 write the channels one after another (decimated)"
            ));
        }
        if next == u64::MAX {
            return Err(format!(
                "segment {segment} was never completed (the writer stopped while writing it)"
            ));
        }
        let end = at
            .checked_add(LEAD_IN_BYTES)
            .and_then(|a| a.checked_add(next))
            .filter(|&e| e <= len)
            .ok_or_else(|| {
                format!("the file is cut short: segment {segment} runs {next} bytes past its lead-in, beyond the end of the file")
            })?;
        if raw_offset > next {
            return Err(format!("segment {segment}'s raw data starts past the segment's end"));
        }
        if toc & TOC_RAW_DATA != 0 {
            raw += next - raw_offset;
        }
        at = end;
    }
    Ok(raw)
}

fn property_f64(channel: &TdmsChannel<'_>, name: &str) -> Option<f64> {
    match channel.property(name)? {
        PropertyValue::Double(v) => Some(*v),
        PropertyValue::Float(v) => Some(f64::from(*v)),
        _ => None,
    }
}

/// A numeric channel's values; `None` for strings, booleans and timestamps.
fn values(channel: &TdmsChannel<'_>) -> Option<Result<Vec<f64>, tdms_rs::TdmsError>> {
    fn read<T: tdms_rs::api::reader::Pod + Default + Into<f64>>(
        channel: &TdmsChannel<'_>,
    ) -> Result<Vec<f64>, tdms_rs::TdmsError> {
        let mut out = vec![T::default(); channel.len()];
        channel.read(0..channel.len(), &mut out)?;
        Ok(out.into_iter().map(Into::into).collect())
    }
    fn read_64<T: tdms_rs::api::reader::Pod + Default>(
        channel: &TdmsChannel<'_>,
        to_f64: fn(T) -> f64,
    ) -> Result<Vec<f64>, tdms_rs::TdmsError> {
        let mut out = vec![T::default(); channel.len()];
        channel.read(0..channel.len(), &mut out)?;
        Ok(out.into_iter().map(to_f64).collect())
    }
    Some(match channel.dtype() {
        DataType::Double => read::<f64>(channel),
        DataType::Float => read::<f32>(channel),
        DataType::I8 => read::<i8>(channel),
        DataType::I16 => read::<i16>(channel),
        DataType::I32 => read::<i32>(channel),
        DataType::U8 => read::<u8>(channel),
        DataType::U16 => read::<u16>(channel),
        DataType::U32 => read::<u32>(channel),
        // Beyond 2^53 a 64-bit integer loses precision; no recording needs that.
        DataType::I64 => read_64::<i64>(channel, |v| v as f64),
        DataType::U64 => read_64::<u64>(channel, |v| v as f64),
        DataType::String | DataType::Boolean | DataType::TimeStamp => return None,
    })
}

/// One channel, read: name, unit (`unit_string`), values and waveform time
/// base (`wf_start_offset`, `wf_increment`).
struct Channel {
    name: String,
    unit: String,
    values: Vec<f64>,
    time_base: (Option<f64>, Option<f64>),
}

struct Group {
    name: String,
    channels: Vec<Channel>,
}

fn read_channel(channel: &TdmsChannel<'_>) -> Result<Channel, String> {
    let name = channel.name().to_string();
    let v = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| values(channel)))
        .map_err(|_| format!("channel `{name}`: corrupt raw data"))?;
    let Some(v) = v else {
        return Err(format!(
            "channel `{name}` holds {:?} values; mre reads numeric channels",
            channel.dtype()
        ));
    };
    let values = v.map_err(|e| format!("channel `{name}`: {e} (the file is cut short or corrupt)"))?;
    let unit = match channel.property("unit_string") {
        Some(PropertyValue::String(u)) if !u.trim().is_empty() => u.trim().to_string(),
        _ => String::new(),
    };
    let time_base = (
        property_f64(channel, "wf_start_offset"),
        property_f64(channel, "wf_increment"),
    );
    Ok(Channel {
        name,
        unit,
        values,
        time_base,
    })
}

/// The channels of one record. All groups together when their channels
/// have distinct names and one length (force in one group, displacement in
/// another); else, as LabVIEW logs levels or runs as groups of the same
/// channels, the group with the longest channels, the others named in notes.
fn one_record(groups: Vec<Group>) -> (Vec<Channel>, Vec<String>) {
    let all: Vec<&Channel> = groups.iter().flat_map(|g| &g.channels).collect();
    let distinct = all
        .iter()
        .enumerate()
        .all(|(i, c)| all[..i].iter().all(|d| d.name != c.name));
    let same_length = all.windows(2).all(|w| w[0].values.len() == w[1].values.len());
    if distinct && same_length {
        return (groups.into_iter().flat_map(|g| g.channels).collect(), Vec::new());
    }
    let longest = |g: &Group| g.channels.iter().map(|c| c.values.len()).max().unwrap_or(0);
    let best = (0..groups.len())
        .max_by_key(|&i| (longest(&groups[i]), std::cmp::Reverse(i)))
        .unwrap_or(0);
    let notes = groups
        .iter()
        .enumerate()
        .filter(|(i, _)| *i != best)
        .map(|(_, g)| format!("skipped group `{}` ({} values per channel at most)", g.name, longest(g)))
        .collect();
    let chosen = groups.into_iter().nth(best).map(|g| g.channels).unwrap_or_default();
    (chosen, notes)
}

fn read(path: &Path, bytes: &[u8]) -> Result<Table, DatasetError> {
    let dpath = path.display().to_string();
    let bad = |message: String| DatasetError::Unreadable {
        path: dpath.clone(),
        reason: message,
    };
    let raw = raw_data_bytes(bytes).map_err(bad)?;
    // The crate's own arithmetic on a corrupt header may overflow (a panic
    // in a debug build): that is this file's error, not mre's.
    let file = std::panic::catch_unwind(|| TdmsFile::open(path))
        .map_err(|_| bad("a corrupt TDMS header (the TDMS reader gave up on it)".to_string()))?
        .map_err(|e| bad(format!("not a readable TDMS file ({e})")))?;
    // The channels' sizes must account for all raw data before any is read
    // (and before a length from the file sizes an allocation).
    let mut accounted = 0u64;
    for channel in file.groups().flat_map(|g| g.channels().collect::<Vec<_>>()) {
        let bytes = (channel.len() as u64).checked_mul(channel.dtype().itemsize() as u64);
        accounted = bytes.and_then(|b| accounted.checked_add(b)).unwrap_or(u64::MAX);
    }
    if accounted != raw {
        return Err(bad(format!(
            "its segments hold {raw} bytes of raw data but its channels account for {accounted} \
             (repeated chunks, or data mre's TDMS reader does not read)"
        )));
    }
    let mut groups: Vec<Group> = Vec::new();
    for group in file.groups() {
        let mut g = Group {
            name: group.name().to_string(),
            channels: Vec::new(),
        };
        for channel in group.channels() {
            g.channels.push(read_channel(&channel).map_err(&bad)?);
        }
        groups.push(g);
    }
    let (chosen, notes) = one_record(groups);
    let mut channels: Vec<(String, String)> = Vec::new();
    let mut columns: Vec<Vec<f64>> = Vec::new();
    let mut time_base: Vec<(Option<f64>, Option<f64>)> = Vec::new();
    for c in chosen {
        if channels.iter().any(|(name, _)| *name == c.name) {
            return Err(bad(format!(
                "two groups have a channel `{}`; mre reads one of each",
                c.name
            )));
        }
        time_base.push(c.time_base);
        channels.push((c.name, c.unit));
        columns.push(c.values);
    }
    if channels.is_empty() {
        return Err(bad("no channels".to_string()));
    }
    let n = columns[0].len();
    if let Some((i, c)) = columns.iter().enumerate().find(|(_, c)| c.len() != n) {
        return Err(bad(format!(
            "channel `{}` has {} values but `{}` has {n}",
            channels[i].0,
            c.len(),
            channels[0].0
        )));
    }
    let mut names: Vec<String> = channels
        .iter()
        .map(|(c, u)| if u.is_empty() { c.clone() } else { format!("{c} ({u})") })
        .collect();
    let has_time = names
        .iter()
        .any(|c| super::columns::map_name(c).is_some_and(|m| m.starts_with("time_")));
    if !has_time {
        // The waveform time base, shared by all channels.
        let first = time_base[0];
        match first {
            (offset, Some(dt)) if dt > 0.0 && time_base.iter().all(|t| *t == first) => {
                let t0 = offset.unwrap_or(0.0);
                names.insert(0, "Time (s)".to_string());
                columns.insert(0, (0..n).map(|k| t0 + k as f64 * dt).collect());
            }
            _ => {
                return Err(bad(
                    "no time channel, and the channels share no waveform time base (wf_increment > 0)".to_string(),
                ))
            }
        }
    }
    let rows = (0..n)
        .map(|k| (k + 1, columns.iter().map(|c| Cell::Number(c[k])).collect()))
        .collect();
    Ok(Table {
        channels: names,
        names_line: 1,
        rows,
        notes,
    })
}
