//! The PIL frame decoder on an arbitrary byte stream, as the firmware's
//! receiver sees it. Never a panic; every frame accepted is a 24-byte
//! window of the stream whose CRC-32 (the tests' bitwise reference, not the core's table) is valid
//! and which decodes to the same frame: no frame is made up from noise.
//! (Not "re-encodes to the same bytes": fields a frame marks absent are
//! ignored, so a frame may carry any bytes there.)
#![no_main]
use libfuzzer_sys::fuzz_target;
use mre_protocol::frame::{CommandFrame, ConfigChunk, Incoming, SampleFrame, SampleReceiver, FRAME_LEN};
use mre_tests::crc32_reference;

fn sent(data: &[u8], frame: &Incoming) -> bool {
    data.windows(FRAME_LEN).any(|w| {
        let buf: &[u8; FRAME_LEN] = w.try_into().unwrap();
        let crc_ok = u32::from_le_bytes([w[20], w[21], w[22], w[23]]) == crc32_reference(&w[..20]);
        crc_ok
            && match frame {
                // Compared by canonical encoding, so NaN payloads compare bit for bit.
                Incoming::Sample(s) => SampleFrame::decode(buf).is_ok_and(|d| d.encode() == s.encode()),
                Incoming::Config(c) => ConfigChunk::decode(buf).is_ok_and(|d| d == *c),
            }
    })
}

fuzz_target!(|data: &[u8]| {
    let mut rx = SampleReceiver::new();
    for &b in data {
        if let Some(Ok(frame)) = rx.push_any(b) {
            assert!(sent(data, &frame), "accepted a frame that was never sent: {frame:?}");
        }
    }
    // The host's decoder of the firmware's answers, on every window.
    for w in data.windows(FRAME_LEN) {
        let buf: &[u8; FRAME_LEN] = w.try_into().unwrap();
        if CommandFrame::decode(buf).is_ok() {
            assert_eq!(
                u32::from_le_bytes([w[20], w[21], w[22], w[23]]),
                crc32_reference(&w[..20]),
                "a command frame with a bad CRC decoded"
            );
        }
    }
});
