//! Missed control periods: the pacer reports whole skipped ticks instead of
//! letting the ticker catch up, and the controller counts them as overruns.
use mre_algorithm::control::{ControlConfig, Controller};
use mre_algorithm::table::Table;
use mre_algorithm::Flags;
use mre_runtime::pacing::Pacer;

#[test]
fn on_time_and_late_periods_advance_by_one_period() {
    // 100 µs periods from t = 0: ticks due at 100, 200, 300 …
    let mut p = Pacer::start(0, 100);
    assert_eq!(p.due_ticks(), 100);
    assert_eq!(p.wake(100), 0);
    assert_eq!(p.due_ticks(), 200);
    assert!(!p.overran(150));
    // Woken 99 µs late: late, but no tick was skipped.
    assert_eq!(p.wake(299), 0);
    assert_eq!(p.due_ticks(), 300);
    // Work ending at or after the next tick is an overrun.
    assert!(p.overran(300));
}

#[test]
fn a_stall_reports_the_skipped_ticks_and_rephases() {
    let mut p = Pacer::start(0, 100);
    // The tick due at 100 is served at 530: ticks 200, 300, 400 and 500
    // passed unserved (4), and the next deadline is 630, not 200.
    assert_eq!(p.wake(530), 4);
    assert_eq!(p.due_ticks(), 630);
    assert_eq!(p.wake(630), 0);
    assert_eq!(p.due_ticks(), 730);
    // Exactly one period late: one tick skipped.
    assert_eq!(p.wake(830), 1);
}

#[test]
fn a_zero_period_never_divides_by_zero() {
    let mut p = Pacer::start(5, 0);
    assert_eq!(p.wake(5 + 1 + 3), 3);
}

#[test]
fn a_long_stall_latches_overrun_in_the_controller() {
    let cfg = ControlConfig::at_rate(10_000).unwrap();
    let mut c = Controller::new(cfg, Table::paper()).unwrap();
    let mut p = Pacer::start(0, 100);
    // A 2 ms stall at 10 kHz: 19 whole ticks missed, beyond the limit of 10.
    let missed = p.wake(100 + 1_900 + 50);
    assert_eq!(missed, 19);
    c.record_missed_periods(missed);
    assert_eq!(c.stats().overruns, 19);
    assert!(c.latched().contains(Flags::OVERRUN));
}
