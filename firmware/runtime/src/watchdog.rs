//! Who may feed the watchdog: the control task feeds it after every period,
//! but only while every supervised thread-mode task has checked in within
//! its deadline. A hung task (or a thread-mode executor that a task keeps
//! busy) then stops the feeding and the watchdog resets the chip into the
//! fail-safe reset path (`crate::boot::BootPlan`). Pure logic over
//! millisecond timestamps, host-tested in `tests/tests/core/watchdog.rs`.

/// One supervised task: when it last checked in, and how long it may go
/// without (ms).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct CheckIn {
    pub last_ms: u32,
    pub deadline_ms: u32,
}

impl CheckIn {
    /// True when the task checked in at most `deadline_ms` before `now_ms`.
    /// Timestamps wrap (u32 ms: 49 days); a check-in stamped after `now_ms`
    /// (a thread-mode store racing the control task's read of the clock)
    /// counts as on time: the difference is taken as signed.
    pub fn on_time(&self, now_ms: u32) -> bool {
        let age_ms = now_ms.wrapping_sub(self.last_ms) as i32;
        age_ms <= 0 || age_ms.unsigned_abs() <= self.deadline_ms
    }
}

/// The watchdog may be fed at `now_ms` only if every task is on time.
pub fn may_feed(now_ms: u32, tasks: &[CheckIn]) -> bool {
    tasks.iter().all(|t| t.on_time(now_ms))
}
