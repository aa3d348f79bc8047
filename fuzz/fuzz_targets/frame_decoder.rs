//! The PIL frame decoder on an arbitrary byte stream, as the firmware's
//! receiver sees it. Never a panic; every frame accepted was in the stream
//! byte for byte (no frame is made up from noise).
#![no_main]
use libfuzzer_sys::fuzz_target;
use mre_core::frame::{CommandFrame, Incoming, SampleReceiver, FRAME_LEN};

fuzz_target!(|data: &[u8]| {
    let mut rx = SampleReceiver::new();
    for &b in data {
        if let Some(Ok(frame)) = rx.push_any(b) {
            let bytes = match frame {
                Incoming::Sample(s) => s.encode(),
                Incoming::Config(c) => c.encode(),
            };
            assert!(data.windows(FRAME_LEN).any(|w| w == bytes), "accepted a frame that was never sent");
        }
    }
    // The host's decoder of the firmware's answers, on every window.
    for w in data.windows(FRAME_LEN) {
        let buf: &[u8; FRAME_LEN] = w.try_into().unwrap();
        if let Ok(cmd) = CommandFrame::decode(buf) {
            assert!(cmd.current_a.is_finite() || cmd.current_a.is_nan() || cmd.current_a.is_infinite());
        }
    }
});
