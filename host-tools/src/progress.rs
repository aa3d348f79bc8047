//! Progress on steps that can take more than a second: a spinner with the
//! step's name and elapsed time, or a bar when the amount of work is known.
//! Off unless the CLI turns it on (a terminal, not CI, no `--quiet`), so
//! library callers and tests print nothing.
use indicatif::{ProgressBar, ProgressStyle};
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::Duration;

static ENABLED: AtomicBool = AtomicBool::new(false);

/// Turns progress display on or off for the whole process.
pub fn set_enabled(on: bool) {
    ENABLED.store(on, Ordering::Relaxed);
}

pub fn enabled() -> bool {
    ENABLED.load(Ordering::Relaxed)
}

/// A spinner saying what runs, cleared when dropped.
pub fn spinner(what: &str) -> Spinner {
    if !enabled() {
        return Spinner(ProgressBar::hidden());
    }
    let bar = ProgressBar::new_spinner();
    if let Ok(style) = ProgressStyle::with_template("{spinner} {msg} {elapsed}") {
        bar.set_style(style);
    }
    bar.set_message(what.to_string());
    bar.enable_steady_tick(Duration::from_millis(120));
    Spinner(bar)
}

/// A bar over `len` items (`what` names them), cleared when dropped.
pub fn bar(len: u64, what: &str) -> Spinner {
    if !enabled() {
        return Spinner(ProgressBar::hidden());
    }
    let bar = ProgressBar::new(len);
    if let Ok(style) = ProgressStyle::with_template("{msg} {bar:40} {pos}/{len} {elapsed} (eta {eta})") {
        bar.set_style(style);
    }
    bar.set_message(what.to_string());
    Spinner(bar)
}

/// A progress display that disappears when it goes out of scope.
pub struct Spinner(ProgressBar);

impl Spinner {
    pub fn inc(&self) {
        self.0.inc(1);
    }

    /// Prints a line above the display (without tearing it).
    pub fn println(&self, line: &str) {
        if self.0.is_hidden() {
            eprintln!("{line}");
        } else {
            self.0.println(line);
        }
    }
}

impl Drop for Spinner {
    fn drop(&mut self) {
        self.0.finish_and_clear();
    }
}
