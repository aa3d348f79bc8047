//! Processor-in-the-loop: the real firmware image runs in
//! `qemu-system-arm -M b-l475e-iot01a` and closes the loop with a plant
//! simulated here, one frame per control period, in lockstep (simulated time
//! is decoupled from wall time).
//!
//! - [`qemu`] finds QEMU and the `pil` firmware image, starts it, and
//!   connects to its USART1 socket.
//! - [`link`] exchanges frames (`mre_protocol::frame`, the firmware's own code).
//! - [`ControlBackend`] is one control period: [`link::PilLink`] runs it in
//!   the firmware, [`InProcess`] runs the same core code linked into the host.
//! - [`run_lockstep`] drives a [`Plant`] with a backend and records every
//!   sample, so a PIL run and a host run can be compared sample for sample.
#[cfg(test)]
mod fault_handler_tests;
pub mod faults;
pub mod link;
pub mod qemu;
pub mod sim;
#[cfg(test)]
mod tests;

use anyhow::{bail, Result};
use mre_algorithm::control::{ControlConfig, Controller, DEFAULT_RATE_HZ};
use mre_algorithm::law::Command;
use mre_algorithm::table::Table;
use mre_algorithm::Flags;
use mre_protocol::frame::{CommandFrame, SampleFrame};

/// One control period: a plant sample in, the controller's answer out.
pub trait ControlBackend {
    fn step(&mut self, sample: &SampleFrame) -> Result<CommandFrame>;
}

/// The firmware's control code linked into the host: the reference a PIL
/// run must reproduce.
pub struct InProcess {
    ctl: Controller,
}

impl InProcess {
    /// The firmware's configuration: the flown (generated) table at the
    /// default rate, as the `pil` image boots.
    pub fn firmware_default() -> Result<Self> {
        let cfg = ControlConfig::at_rate(DEFAULT_RATE_HZ).map_err(|e| anyhow::anyhow!("control config: {e:?}"))?;
        let table =
            Table::from_image(&mre_algorithm::generated_table::GENERATED_TABLE).map_err(|e| anyhow::anyhow!("{e}"))?;
        Self::new(cfg, table)
    }

    pub fn new(cfg: ControlConfig, table: Table) -> Result<Self> {
        let ctl = Controller::new(cfg, Ok(table)).map_err(|e| anyhow::anyhow!("controller: {e:?}"))?;
        Ok(Self { ctl })
    }
}

impl ControlBackend for InProcess {
    fn step(&mut self, sample: &SampleFrame) -> Result<CommandFrame> {
        let cmd = self.ctl.step_sample(sample.x_mm, sample.v_m_s);
        // The board ends every period with an overrun check; PIL never overruns.
        self.ctl.end_period(false);
        Ok(in_process_frame(sample.seq, &cmd))
    }
}

/// The answer an in-process controller gives for period `seq`: its command,
/// as the firmware would frame it (no frame is ever rejected in process).
pub(crate) fn in_process_frame(seq: u32, cmd: &Command) -> CommandFrame {
    CommandFrame {
        seq,
        current_a: cmd.current_a,
        target_force_n: cmd.target_force_n,
        flags: cmd.flags,
        rejected: 0,
    }
}

/// What a closed loop needs from a plant simulator.
pub trait Plant {
    /// The sensor readings the controller sees this period.
    fn measure(&self) -> PlantSample;
    /// Advances one control period with the commanded coil current.
    fn advance(&mut self, current_a: f32, period_s: f32);
}

#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PlantSample {
    pub x_mm: f32,
    /// `None` models a board without a velocity sensor.
    pub v_m_s: Option<f32>,
    pub force_n: Option<f32>,
}

/// One period of a closed-loop run.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LoopRecord {
    pub seq: u32,
    pub sample: PlantSample,
    pub command: CommandFrame,
}

/// Runs `steps` periods in lockstep: measure → backend → advance. The first
/// sequence number is 1. Fails if the backend answers another sequence.
pub fn run_lockstep<P: Plant, B: ControlBackend + ?Sized>(
    plant: &mut P,
    backend: &mut B,
    steps: u32,
    period_s: f32,
) -> Result<Vec<LoopRecord>> {
    let mut records = Vec::with_capacity(steps as usize);
    for seq in 1..=steps {
        let sample = plant.measure();
        let frame = SampleFrame {
            seq,
            x_mm: sample.x_mm,
            v_m_s: sample.v_m_s,
            force_n: sample.force_n,
            coil_current_a: None,
        };
        let command = backend.step(&frame)?;
        if command.seq != seq {
            bail!("controller answered sequence {} to sample {seq}", command.seq);
        }
        plant.advance(command.current_a, period_s);
        records.push(LoopRecord { seq, sample, command });
    }
    Ok(records)
}

/// First difference between two runs beyond f32 rounding, if any.
/// Currents and forces may differ by `rel_tol` relative (plus 1e-6 absolute);
/// flags other than `FRAME_FAULT` must be identical.
pub fn first_mismatch(a: &[LoopRecord], b: &[LoopRecord], rel_tol: f32) -> Option<(usize, String)> {
    if a.len() != b.len() {
        return Some((
            a.len().min(b.len()),
            format!("lengths differ: {} vs {}", a.len(), b.len()),
        ));
    }
    let close = |p: f32, q: f32| (p - q).abs() <= 1.0e-6 + rel_tol * p.abs().max(q.abs());
    for (k, (ra, rb)) in a.iter().zip(b).enumerate() {
        let (ca, cb) = (ra.command, rb.command);
        let fa = Flags(ca.flags.0 & !Flags::FRAME_FAULT.0);
        let fb = Flags(cb.flags.0 & !Flags::FRAME_FAULT.0);
        if !close(ca.current_a, cb.current_a) || !close(ca.target_force_n, cb.target_force_n) || fa != fb {
            return Some((k, format!("sample {k}: {ra:?} vs {rb:?}")));
        }
        if !close(ra.sample.x_mm, rb.sample.x_mm) {
            return Some((
                k,
                format!("plant diverged at sample {k}: {:?} vs {:?}", ra.sample, rb.sample),
            ));
        }
    }
    None
}
