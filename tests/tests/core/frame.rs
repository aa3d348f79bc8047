//! The PIL frame protocol: layout, CRC, resync, and rejection of corrupt or
//! out-of-order frames.
use mre_algorithm::Flags;
use mre_protocol::frame::{CommandFrame, FrameError, SampleFrame, SampleReceiver, FRAME_LEN};
use mre_tests::crc32_reference;
use proptest::prelude::*;

fn sample(seq: u32) -> SampleFrame {
    SampleFrame {
        seq,
        x_mm: 1.25,
        v_m_s: Some(-0.5),
        force_n: None,
        coil_current_a: None,
    }
}

/// Whether `frame` is a 24-byte window of `stream` with a valid CRC.
fn sent(stream: &[u8], frame: &SampleFrame) -> bool {
    stream.windows(FRAME_LEN).any(|w| {
        let crc_ok = u32::from_le_bytes(w[20..24].try_into().unwrap()) == crc32_reference(&w[..20]);
        // Compared by canonical encoding, so NaN payloads compare bit for bit.
        crc_ok && SampleFrame::decode(w.try_into().unwrap()).is_ok_and(|d| d.encode() == frame.encode())
    })
}

fn feed(rx: &mut SampleReceiver, bytes: &[u8]) -> Vec<Result<SampleFrame, FrameError>> {
    bytes.iter().filter_map(|&b| rx.push(b)).collect()
}

#[test]
fn reference_crc_matches_the_published_check_value() {
    assert_eq!(crc32_reference(b"123456789"), 0xCBF4_3926);
}

#[test]
fn sample_frame_layout_is_as_documented() {
    let buf = sample(0x0102_0304).encode();
    assert_eq!(buf.len(), FRAME_LEN);
    assert_eq!(&buf[..4], &[0xA5, 0x5A, 1, 0b01]);
    assert_eq!(&buf[4..8], &[4, 3, 2, 1]);
    assert_eq!(&buf[8..12], &1.25f32.to_le_bytes());
    assert_eq!(&buf[12..16], &(-0.5f32).to_le_bytes());
    assert_eq!(&buf[16..20], &[0, 0, 0, 0]);
    assert_eq!(
        u32::from_le_bytes(buf[20..24].try_into().unwrap()),
        crc32_reference(&buf[..20])
    );
}

#[test]
fn command_frame_layout_and_round_trip() {
    let cmd = CommandFrame {
        seq: 7,
        current_a: 1.5,
        target_force_n: 1726.25,
        flags: Flags::SLEW_LIMITED | Flags::FAIL_SAFE,
        rejected: 3,
    };
    let buf = cmd.encode();
    assert_eq!(&buf[..8], &[0xA5, 0x5A, 2, 0, 7, 0, 0, 0]);
    assert_eq!(&buf[16..20], &[0x80, 0x01, 3, 0]);
    assert_eq!(
        u32::from_le_bytes(buf[20..24].try_into().unwrap()),
        crc32_reference(&buf[..20])
    );
    assert_eq!(CommandFrame::decode(&buf), Ok(cmd));
    // A sample frame is not a command frame.
    assert_eq!(
        CommandFrame::decode(&sample(1).encode()),
        Err(FrameError::BadKind { kind: 1 })
    );
}

#[test]
fn optional_fields_round_trip() {
    for s in [
        SampleFrame {
            seq: 1,
            x_mm: 0.0,
            v_m_s: None,
            force_n: None,
            coil_current_a: None,
        },
        SampleFrame {
            seq: 2,
            x_mm: -0.25,
            v_m_s: Some(2.24),
            force_n: Some(950.0),
            coil_current_a: None,
        },
        SampleFrame {
            seq: 3,
            x_mm: 3.0,
            v_m_s: None,
            force_n: Some(-1.0),
            coil_current_a: None,
        },
    ] {
        assert_eq!(SampleFrame::decode(&s.encode()), Ok(s));
    }
}

#[test]
fn every_single_bit_flip_is_rejected() {
    let good = sample(9).encode();
    for bit in 0..FRAME_LEN * 8 {
        let mut bad = good;
        bad[bit / 8] ^= 1 << (bit % 8);
        assert!(SampleFrame::decode(&bad).is_err(), "bit {bit} not detected");
    }
}

#[test]
fn corrupt_frame_is_counted_and_the_next_one_accepted() {
    let mut rx = SampleReceiver::new();
    let mut bad = sample(1).encode();
    bad[9] ^= 0x10;
    let mut stream = bad.to_vec();
    stream.extend_from_slice(&sample(2).encode());
    let out = feed(&mut rx, &stream);
    assert!(matches!(out[0], Err(FrameError::Crc { .. })));
    assert_eq!(out[1], Ok(sample(2)));
    assert_eq!(out.len(), 2);
    assert_eq!(
        (rx.stats().crc_errors, rx.stats().accepted, rx.stats().rejected()),
        (1, 1, 1)
    );
}

#[test]
fn receiver_resyncs_after_garbage_and_a_truncated_frame() {
    let mut rx = SampleReceiver::new();
    let mut stream = vec![0x00, 0xA5, 0x13, 0x5A, 0xFF];
    stream.extend_from_slice(&sample(1).encode()[..10]); // cut off mid-frame
    stream.extend_from_slice(&sample(2).encode());
    stream.extend_from_slice(&sample(3).encode());
    let out = feed(&mut rx, &stream);
    let accepted: Vec<u32> = out.iter().filter_map(|r| r.as_ref().ok()).map(|s| s.seq).collect();
    assert_eq!(accepted, vec![2, 3]);
    assert_eq!(out.iter().filter(|r| r.is_err()).count(), 1);
    assert_eq!(rx.stats().lost, 0, "2 → 3 loses nothing");
}

#[test]
fn out_of_order_and_duplicate_frames_are_rejected_and_gaps_counted() {
    let mut rx = SampleReceiver::new();
    let mut stream = Vec::new();
    for seq in [5, 3, 5, 8, 6] {
        stream.extend_from_slice(&sample(seq).encode());
    }
    let out = feed(&mut rx, &stream);
    assert_eq!(
        out,
        vec![
            Ok(sample(5)),
            Err(FrameError::OutOfOrder { seq: 3, last: 5 }),
            Err(FrameError::Duplicate { seq: 5 }),
            Ok(sample(8)),
            Err(FrameError::OutOfOrder { seq: 6, last: 8 }),
        ]
    );
    let s = rx.stats();
    assert_eq!((s.accepted, s.out_of_order, s.duplicates, s.lost), (2, 2, 1, 2));
    // Duplicates are retries, not faults: only the out-of-order ones count.
    assert_eq!(s.rejected(), 2);
}

proptest! {
    #![proptest_config(mre_tests::proptest_config(256))]
    #[test]
    fn arbitrary_bytes_never_panic_and_never_fake_a_frame(bytes in proptest::collection::vec(any::<u8>(), 0..400)) {
        let mut rx = SampleReceiver::new();
        for r in feed(&mut rx, &bytes).into_iter().flatten() {
            // Anything accepted is a window of the input with a valid CRC
            // that decodes to it (absent fields may hold any bytes).
            prop_assert!(sent(&bytes, &r), "accepted {:?}, never sent", r);
        }
    }

    /// Frames between noise, some with one bit flipped: every accepted frame
    /// was sent intact (CRC-32 detects every single-bit error), and no
    /// frame that was corrupted is accepted.
    #[test]
    fn corrupted_frames_are_never_accepted(
        noise in proptest::collection::vec(proptest::collection::vec(any::<u8>(), 0..30), 1..10),
        flips in proptest::collection::vec(proptest::option::of(0usize..FRAME_LEN * 8), 10),
    ) {
        let mut stream = Vec::new();
        let mut corrupted = Vec::new();
        for (i, n) in noise.iter().enumerate() {
            stream.extend_from_slice(n);
            let seq = i as u32 + 1;
            let mut buf = sample(seq).encode();
            if let Some(bit) = flips[i] {
                buf[bit / 8] ^= 1 << (bit % 8);
                corrupted.push(seq);
            }
            stream.extend_from_slice(&buf);
        }
        let mut rx = SampleReceiver::new();
        for r in feed(&mut rx, &stream).into_iter().flatten() {
            prop_assert!(sent(&stream, &r), "accepted {:?}, never sent", r);
            prop_assert!(!corrupted.contains(&r.seq), "accepted the corrupted frame {:?}", r);
        }
    }

    #[test]
    fn frames_split_by_noise_are_all_recovered(seqs in proptest::collection::vec(1u32..1000, 1..8), noise in proptest::collection::vec(0u8..0xA5, 0..5)) {
        let mut sorted = seqs.clone();
        sorted.sort_unstable();
        sorted.dedup();
        let mut rx = SampleReceiver::new();
        let mut stream = Vec::new();
        for &seq in &sorted {
            stream.extend_from_slice(&noise);
            stream.extend_from_slice(&sample(seq).encode());
        }
        let got: Vec<u32> = feed(&mut rx, &stream).into_iter().map(|r| r.map(|s| s.seq)).collect::<Result<_, _>>().unwrap();
        prop_assert_eq!(got, sorted);
    }
}

mod config_upload {
    use mre_algorithm::control::{ControlConfig, ControlConfigError};
    use mre_algorithm::law::ReboundPolicy;
    use mre_algorithm::table::{Table, TableError, PAPER_TABLE4_ENTRIES};
    use mre_protocol::frame::{
        decode_config, encode_config, ConfigBlobError, ConfigChunk, ConfigCollector, Incoming, SampleReceiver,
        CONFIG_MAX_WORDS,
    };

    fn custom() -> (Table, ControlConfig) {
        let mut entries = PAPER_TABLE4_ENTRIES;
        for e in &mut entries {
            e.x_max_mm *= 10.0;
        }
        let table = Table::new(&entries).unwrap();
        let mut cfg = ControlConfig::at_rate(20_000).unwrap();
        cfg.law.stroke_max_mm = 10.0;
        cfg.law.rebound = ReboundPolicy::Fixed { current_a: 0.5 };
        cfg.stuck_samples = 20;
        (table, cfg)
    }

    fn blob(table: &Table, cfg: &ControlConfig) -> Vec<u32> {
        let mut words = [0u32; CONFIG_MAX_WORDS];
        let n = encode_config(table, cfg, &mut words);
        words[..n].to_vec()
    }

    #[test]
    fn round_trip_restores_table_and_config_exactly() {
        let (table, cfg) = custom();
        let words = blob(&table, &cfg);
        // 2 header words, 13 per current, 13 law, 7 control.
        assert_eq!(words.len(), 2 + 13 * 5 + 13 + 7);
        assert_eq!(decode_config(&words), Ok((table, cfg)));
    }

    #[test]
    fn corrupt_or_short_blobs_are_refused() {
        let (table, cfg) = custom();
        let words = blob(&table, &cfg);
        // A flipped coefficient bit no longer matches the table CRC.
        let mut bad = words.clone();
        bad[5] ^= 1;
        assert!(matches!(
            decode_config(&bad),
            Err(ConfigBlobError::Table(TableError::CrcMismatch { .. }))
        ));
        assert_eq!(
            decode_config(&words[..words.len() - 1]),
            Err(ConfigBlobError::Incomplete)
        );
        // A rate outside 1–40 kHz.
        let mut bad = words.clone();
        let rate_at = words.len() - 7;
        bad[rate_at] = 100_000;
        assert_eq!(
            decode_config(&bad),
            Err(ConfigBlobError::Control(ControlConfigError::Rate { rate_hz: 100_000 }))
        );
    }

    /// Splits a blob into config frames, as the host does.
    fn frames(words: &[u32]) -> Vec<u8> {
        let mut out = Vec::new();
        for (k, chunk) in words.chunks(3).enumerate() {
            let mut three = [0u32; 3];
            three[..chunk.len()].copy_from_slice(chunk);
            out.extend_from_slice(
                &ConfigChunk::Words {
                    index: 3 * k as u32,
                    count: chunk.len() as u8,
                    words: three,
                }
                .encode(),
            );
        }
        out.extend_from_slice(
            &ConfigChunk::Commit {
                total_words: words.len() as u32,
            }
            .encode(),
        );
        out
    }

    #[test]
    fn receiver_and_collector_reassemble_an_upload() {
        let (table, cfg) = custom();
        let mut rx = SampleReceiver::new();
        let mut collector = ConfigCollector::new();
        let mut results = Vec::new();
        for b in frames(&blob(&table, &cfg)) {
            if let Some(Ok(Incoming::Config(chunk))) = rx.push_any(b) {
                results.extend(collector.push(chunk));
            }
        }
        assert_eq!(results, vec![Ok((table, cfg))]);
        // Samples keep their sequence checks; config frames do not use them.
        assert_eq!(rx.stats().accepted, 0);
    }

    #[test]
    fn an_upload_with_a_lost_frame_is_incomplete() {
        let (table, cfg) = custom();
        let bytes = frames(&blob(&table, &cfg));
        let mut rx = SampleReceiver::new();
        let mut collector = ConfigCollector::new();
        let mut results = Vec::new();
        // Drop the second frame (bytes 24..48).
        for (i, &b) in bytes.iter().enumerate() {
            if (24..48).contains(&i) {
                continue;
            }
            if let Some(Ok(Incoming::Config(chunk))) = rx.push_any(b) {
                results.extend(collector.push(chunk));
            }
        }
        assert_eq!(results, vec![Err(ConfigBlobError::Incomplete)]);
    }
}
