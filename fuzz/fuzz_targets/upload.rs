//! The table/configuration upload path: arbitrary words decoded directly,
//! and the same words sent as an upload (valid-CRC frames through the
//! firmware's receiver and collector). Never a panic; an accepted upload
//! re-encodes to itself, and both paths agree. The board's receiver
//! (`UploadPort` onto a flash-like RAM page) stores exactly what it accepts
//! and leaves the page untouched when it refuses. Nothing accepted lies
//! outside the board's hard limits (`mre_algorithm::limits`), checked here field
//! by field against the wiring's numbers (firmware/README.md, "Hard limits").
#![no_main]
use libfuzzer_sys::fuzz_target;
use mre_protocol::flash_table::{load, RamPage};
use mre_protocol::frame::{
    decode_config, encode_config, ConfigChunk, ConfigCollector, Incoming, SampleReceiver, CONFIG_MAX_WORDS,
};
use mre_protocol::upload::{PortEvent, UploadPort};

fuzz_target!(|data: &[u8]| {
    let words: Vec<u32> = data
        .chunks_exact(4)
        .map(|c| u32::from_le_bytes([c[0], c[1], c[2], c[3]]))
        .collect();
    let direct = decode_config(&words);
    if let Ok((_, cfg)) = &direct {
        let law = &cfg.law;
        assert!((0.0..=2.0).contains(&law.current_min_a) && (0.0..=2.0).contains(&law.current_max_a));
        assert!((1.0..=2.0).contains(&law.failsafe_current_a));
        if let mre_algorithm::law::ReboundPolicy::Fixed { current_a } = law.rebound {
            assert!((0.0..=2.0).contains(&current_a));
        }
        assert!((1.0..=25.0).contains(&law.stroke_max_mm));
        assert!((-2.5..=0.0).contains(&law.x_valid_min_mm) && (1.0..=27.5).contains(&law.x_valid_max_mm));
        assert!((0.1..=20.0).contains(&law.v_valid_max_m_s));
        assert!((1..=100).contains(&cfg.range_fault_samples) && (1..=500).contains(&cfg.stuck_samples));
        assert!((1..=100).contains(&cfg.overrun_limit) && (1..=10_000).contains(&cfg.overrun_window));
        assert_eq!(mre_algorithm::limits::check(cfg, &mre_algorithm::limits::BOARD), Ok(()));
    }
    if let Ok((table, cfg)) = &direct {
        // A table's installation (format 3) is within the wiring's limits,
        // and the configuration is the one it sets.
        let i = table.installation();
        assert!((0.1..=100.0).contains(&i.mass_kg) && (1.0..=25.0).contains(&i.usable_stroke_mm));
        assert!((1.0..=2.0).contains(&i.coil_rating_a) && i.coil_resistance_ohm == 4.0 && i.supply_v == 12.0);
        assert!(i.x_sensor_range_mm == 25.0 && i.v_sensor_full_scale_m_s == 5.0);
        assert!((0.1..=20.0).contains(&i.impact_v_min_m_s) && i.impact_v_min_m_s <= i.impact_v_max_m_s);
        assert!(i.impact_v_max_m_s <= 20.0);
        if table.version() >= mre_algorithm::table::FORMAT_VERSION_3 {
            let mut installed = *cfg;
            i.apply(&mut installed);
            assert_eq!(&installed, cfg);
        }
    }
    if let Ok((table, cfg)) = &direct {
        let mut out = [0u32; CONFIG_MAX_WORDS];
        let n = encode_config(table, cfg, &mut out);
        let again = decode_config(&out[..n]).expect("what was accepted re-encodes to a valid blob");
        assert_eq!(again.0.entries(), table.entries());
        assert_eq!(&again.1, cfg);
    }

    let mut rx = SampleReceiver::new();
    let mut collector = ConfigCollector::new();
    let mut result = None;
    let mut chunks: Vec<ConfigChunk> = words
        .chunks(3)
        .enumerate()
        .map(|(i, w)| ConfigChunk::Words {
            index: (3 * i) as u32,
            count: w.len() as u8,
            words: [w[0], *w.get(1).unwrap_or(&0), *w.get(2).unwrap_or(&0)],
        })
        .collect();
    chunks.push(ConfigChunk::Commit {
        total_words: words.len() as u32,
    });
    let mut port = UploadPort::new();
    let mut page = RamPage::erased();
    let mut stored = None;
    for chunk in chunks {
        for b in chunk.encode() {
            if let Some(Ok(Incoming::Config(c))) = rx.push_any(b) {
                if let Some(r) = collector.push(c) {
                    result = Some(r);
                }
            }
            if let Some(PortEvent::Commit(r)) = port.push(b, &mut page, true) {
                stored = Some(r);
            }
        }
    }
    match (stored.expect("the port answers the commit"), &result) {
        (Ok((t, c)), Some(Ok((t2, c2)))) => {
            assert_eq!(t.entries(), t2.entries());
            assert_eq!(&c, c2);
            let (t3, _) = load(&mut page).expect("what was acknowledged loads back");
            assert_eq!(t3.entries(), t.entries());
        }
        (Err(_), Some(Err(_))) => assert!(page.bytes.iter().all(|&b| b == 0xFF), "a refused upload wrote the page"),
        (s, r) => panic!("the port and the collector disagree: {:?} vs {:?}", s.is_ok(), r.as_ref().map(|r| r.is_ok())),
    }
    let uploaded = result.expect("a commit always answers");
    if words.len() <= CONFIG_MAX_WORDS {
        match (&uploaded, &direct) {
            (Ok((t1, c1)), Ok((t2, c2))) => {
                assert_eq!(t1.entries(), t2.entries());
                assert_eq!(c1, c2);
            }
            (Err(_), Err(_)) => {}
            _ => panic!(
                "the upload and the direct decode disagree: {:?} vs {:?}",
                uploaded.is_ok(),
                direct.is_ok()
            ),
        }
    } else {
        assert!(
            uploaded.is_err(),
            "a blob longer than the largest configuration is refused"
        );
    }
});
