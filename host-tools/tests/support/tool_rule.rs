//! The rule every test that needs an outside tool (FMPy, Wine, unicorn,
//! QEMU 10) follows: without it the test says why and is skipped, except on
//! CI (`CI` set), where `.ci/run` must have installed it and the test fails.

/// True when the tool is there; otherwise a "skipped: …" line, or a
/// failure on CI naming what `.ci/run` must install.
pub fn installed_or_skipped(installed: bool, missing: &str, install: &str) -> bool {
    if !installed {
        assert!(
            std::env::var_os("CI").is_none(),
            "{missing} is missing on CI: .ci/run must {install}"
        );
        eprintln!("skipped: {missing} is not installed ({install})");
    }
    installed
}
