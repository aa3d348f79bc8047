//! The watchdog supervisor (`mre_runtime::watchdog`): fed only while every
//! supervised task checked in within its deadline.
use mre_runtime::watchdog::{may_feed, CheckIn};

/// The firmware's tasks (main.rs): the status task every 50 ms, deadline
/// 200 ms; the log task with every stats line (1 s), deadline 3 s.
fn tasks(status_ms: u32, log_ms: u32) -> [CheckIn; 2] {
    [
        CheckIn {
            last_ms: status_ms,
            deadline_ms: 200,
        },
        CheckIn {
            last_ms: log_ms,
            deadline_ms: 3_000,
        },
    ]
}

#[test]
fn every_task_on_time_feeds() {
    assert!(may_feed(10_000, &tasks(9_950, 9_500)));
    // Exactly at the deadline still counts.
    assert!(may_feed(10_000, &tasks(9_800, 7_000)));
}

#[test]
fn a_hung_task_stops_the_feeding() {
    // The status task stopped 201 ms ago (the thread-mode executor is stuck).
    assert!(!may_feed(10_000, &tasks(9_799, 9_900)));
    // The log task stopped 3.001 s ago (e.g. blocked on its output).
    assert!(!may_feed(10_000, &tasks(9_990, 6_999)));
    // A task that never checked in after boot (stamped at 0).
    assert!(!may_feed(10_000, &tasks(9_990, 0)));
}

#[test]
fn the_clock_wraps_and_a_racing_check_in_is_on_time() {
    // now just past the u32 wrap, check-ins just before it: 100 ms and 1 s old.
    let now_ms = 50u32;
    assert!(may_feed(now_ms, &tasks(u32::MAX - 49, u32::MAX - 949)));
    assert!(!may_feed(now_ms, &tasks(u32::MAX - 250, u32::MAX - 949)));
    // A check-in stamped 1 ms after the control task read the clock.
    assert!(may_feed(1_000, &tasks(1_001, 1_001)));
}
