//! Period bookkeeping for the control loop, in integer ticks (µs on the
//! board): which deadline a period has, whether it overran, and how many
//! whole periods were skipped after a stall.
//!
//! embassy's `Ticker` catches up after a stall by firing the missed ticks
//! back to back, microseconds apart: the law would run several "periods" on
//! one sample interval. The board instead asks [`Pacer::wake`] how many
//! periods were missed, re-phases its ticker when any were, and hands the
//! count to [`Controller::record_missed_periods`](mre_algorithm::control::Controller::record_missed_periods).

/// Deadline of the period in progress. Pure arithmetic, no clock.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Pacer {
    period_ticks: u64,
    /// When the next tick is due; the running period's deadline.
    due_ticks: u64,
}

impl Pacer {
    /// The loop starts at `now`: the first tick is one period later.
    /// A zero period is treated as one tick (never divides by zero).
    pub fn start(now_ticks: u64, period_ticks: u64) -> Self {
        let period_ticks = period_ticks.max(1);
        Self {
            period_ticks,
            due_ticks: now_ticks.saturating_add(period_ticks),
        }
    }

    /// The tick due at `due` fired and the loop woke at `now`. Returns the
    /// number of ticks that were missed entirely (0 normally). When it is not
    /// 0 the next deadline is one period from `now`, and the caller must
    /// restart its ticker from `now` too (embassy: `Ticker::reset`).
    pub fn wake(&mut self, now_ticks: u64) -> u32 {
        let late = now_ticks.saturating_sub(self.due_ticks);
        if late < self.period_ticks {
            self.due_ticks = self.due_ticks.saturating_add(self.period_ticks);
            return 0;
        }
        self.due_ticks = now_ticks.saturating_add(self.period_ticks);
        u32::try_from(late.checked_div(self.period_ticks).unwrap_or(u64::MAX)).unwrap_or(u32::MAX)
    }

    /// True when the period's work ended at `now`, after its deadline.
    pub fn overran(&self, now_ticks: u64) -> bool {
        now_ticks >= self.due_ticks
    }

    pub fn due_ticks(&self) -> u64 {
        self.due_ticks
    }
}
