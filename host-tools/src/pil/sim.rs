//! `mre pil`: the drop-test comparison of `mre sim` (passive 0 A, passive
//! 2 A, controlled) with the controlled run closed through the real firmware
//! in QEMU. The same controlled run is repeated in process with the core
//! linked directly; the two must agree sample for sample, which shows that
//! the firmware's I/O path (frames, USART, task) adds no error.
use super::link::PilLink;
use super::qemu::{qemu_binary, Qemu, INSTALL_HINT};
use crate::plant::closed_loop::{
    controlled_impact, law_config, run_passive, setup_for, Comparison, RunResult, RunSpec, SimRequest, SimSetup,
    DEFAULT_RUNS,
};
use crate::plant::stepper::{simulate, CurrentSource, Trajectory};
use anyhow::{anyhow, bail, Context, Result};
use mre_algorithm::control::{ControlConfig, Controller};
use mre_algorithm::law::LawConfig;
use mre_algorithm::table::Table;
use mre_protocol::frame::SampleFrame;
use serde::Serialize;
use std::cell::RefCell;
use std::path::{Path, PathBuf};
use std::time::Duration;

/// What `mre pil` was asked for.
#[derive(Clone, Debug)]
pub struct PilRequest {
    pub sim: SimRequest,
    /// The `pil` firmware image; default: build it (`cargo fw-pil`).
    pub elf: Option<PathBuf>,
}

/// How closely the firmware run matched the in-process run.
#[derive(Clone, Copy, Debug, Serialize, PartialEq)]
pub struct Agreement {
    pub samples: usize,
    pub bit_identical_commands: usize,
    pub max_command_diff_a: f64,
    pub max_displacement_diff_mm: f64,
    pub frames: u64,
}

impl Agreement {
    /// Within f32 rounding: commands within 1e-6 A, trajectories within 1e-9 mm.
    pub fn agrees(&self) -> bool {
        self.samples > 0 && self.max_command_diff_a <= 1.0e-6 && self.max_displacement_diff_mm <= 1.0e-9
    }
}

/// The firmware's own log counters at the end of the drop, read by symbol
/// through QEMU's monitor (`None` over a serial port).
#[derive(Clone, Copy, Debug, Serialize, PartialEq, Eq)]
pub struct FirmwareCounters {
    /// defmt frames the RTT logger dropped (full buffer or contention);
    /// always 0 with the `pil` image's semihosting logger.
    pub log_frames_dropped: u32,
    /// Control-task events that did not fit the log channel.
    pub log_events_dropped: u32,
}

impl FirmwareCounters {
    /// Reads both counters from the running firmware `elf` in `qemu`.
    pub fn read(qemu: &Qemu, elf: &Path) -> Result<Self> {
        let word = |name| -> Result<u32> { qemu.read_word(super::qemu::symbol_address(elf, name)?) };
        Ok(Self {
            log_frames_dropped: word("MRE_LOG_FRAMES_DROPPED")?,
            log_events_dropped: word("MRE_LOG_EVENTS_DROPPED")?,
        })
    }
}

#[derive(Clone, Debug)]
pub struct PilOutcome {
    pub comparison: Comparison,
    /// The firmware's log counters after the drop (QEMU only).
    pub counters: Option<FirmwareCounters>,
    /// Firmware (QEMU) vs the same `Controller` in process.
    pub agreement: Agreement,
    /// Firmware vs `mre sim --controlled` (the core's `ImpactLaw` in process).
    pub agreement_with_sim: Agreement,
}

/// The firmware's configuration for this drop: the board's at the drop's
/// control rate with the setup's installation applied (as the board applies
/// a format 3 table's), and the law `mre sim` runs.
pub fn control_config(setup: &SimSetup) -> Result<ControlConfig> {
    let rate_hz = (1.0 / setup.impact.control_period_s).round() as u32;
    let mut cfg = ControlConfig::at_rate(rate_hz).map_err(|e| anyhow!("control rate {rate_hz} Hz: {e:?}"))?;
    setup.installation.apply(&mut cfg);
    cfg.law = LawConfig {
        period_s: cfg.law.period_s,
        ..law_config(setup)
    };
    cfg.validate().map_err(|e| anyhow!("control configuration: {e:?}"))?;
    Ok(cfg)
}

/// The controlled drop with the firmware's control code linked in process.
pub fn run_in_process(setup: &SimSetup, table: &Table, cfg: &ControlConfig) -> Result<Trajectory> {
    let mut ctl = Controller::new(*cfg, Ok(*table)).map_err(|e| anyhow!("controller: {e:?}"))?;
    let controller = move |x_mm: f32, v_m_s: f32| {
        let current_a = ctl.step_sample(x_mm, Some(v_m_s)).current_a;
        ctl.end_period(false);
        current_a
    };
    simulate(
        &setup.plant,
        &controlled_impact(setup, table),
        CurrentSource::Controller(Box::new(controller)),
    )
}

/// Where the firmware runs.
#[derive(Clone, Copy, Debug)]
pub enum FirmwareLink<'a> {
    /// The `pil` image in QEMU, USART1 on a TCP socket (started here).
    Qemu { elf: &'a Path },
    /// A board (or QEMU on a pty) already running the `pil` image, on this
    /// serial port: `mre pil --serial PORT`.
    Serial { port: &'a Path },
}

impl FirmwareLink<'_> {
    fn label(&self) -> String {
        match self {
            FirmwareLink::Qemu { .. } => "in QEMU".to_owned(),
            FirmwareLink::Serial { port } => format!("on {}", port.display()),
        }
    }
}

/// How long `--serial` pings before giving up (time to reset the board).
pub const SERIAL_HELLO_TIMEOUT: Duration = Duration::from_secs(30);

/// The controlled drop with the firmware in QEMU in the loop.
pub fn run_firmware(setup: &SimSetup, table: &Table, cfg: &ControlConfig, elf: &Path) -> Result<(Trajectory, u64)> {
    let (trajectory, frames, _) = run_firmware_on(setup, table, cfg, FirmwareLink::Qemu { elf })?;
    Ok((trajectory, frames))
}

/// The controlled drop with the firmware on `target` in the loop: the
/// trajectory, the frames exchanged, and (QEMU) the firmware's log counters.
pub fn run_firmware_on(
    setup: &SimSetup,
    table: &Table,
    cfg: &ControlConfig,
    target: FirmwareLink<'_>,
) -> Result<(Trajectory, u64, Option<FirmwareCounters>)> {
    let (qemu, mut link) = match target {
        FirmwareLink::Qemu { elf } => {
            let qemu_bin = qemu_binary().ok_or_else(|| anyhow!("qemu-system-arm not found: {INSTALL_HINT}"))?;
            let (qemu, link): (Qemu, PilLink) = Qemu::start(&qemu_bin, elf, None)?;
            (Some(qemu), link)
        }
        FirmwareLink::Serial { port } => (None, PilLink::serial(port, SERIAL_HELLO_TIMEOUT)?),
    };
    link.upload_config(table, cfg)?;
    let error = RefCell::new(None);
    let mut seq = 0u32;
    let failsafe_a = cfg.law.failsafe_current_a;
    let trajectory = {
        let link = &mut link;
        let error = &error;
        let controller = move |x_mm: f32, v_m_s: f32| {
            seq += 1;
            match link.exchange(&SampleFrame {
                seq,
                x_mm,
                v_m_s: Some(v_m_s),
                force_n: None,
                coil_current_a: None,
            }) {
                Ok(cmd) => cmd.current_a,
                Err(e) => {
                    error.borrow_mut().get_or_insert(e);
                    failsafe_a
                }
            }
        };
        simulate(
            &setup.plant,
            &controlled_impact(setup, table),
            CurrentSource::Controller(Box::new(controller)),
        )?
    };
    if let Some(e) = error.into_inner() {
        return Err(e.context("PIL link failed during the drop"));
    }
    let frames = link.frames();
    let counters = match (&qemu, target) {
        (Some(qemu), FirmwareLink::Qemu { elf }) => Some(FirmwareCounters::read(qemu, elf)?),
        _ => None,
    };
    link.end_of_run()?;
    if let Some(qemu) = qemu {
        let status = qemu.wait(Duration::from_secs(20))?;
        if !status.success() {
            bail!("firmware ended the run with {status}");
        }
    }
    Ok((trajectory, frames, counters))
}

/// The figure of the firmware's coil commands over the host's (file stem; PNG and SVG).
pub const AGREEMENT_FIGURE: &str = "agreement";

/// The coil command the firmware sent each period over the one the same core
/// computed in-process: a line under dots, so a mismatch shows as a dot off it.
fn agreement_figure(firmware: &Trajectory, host: &Trajectory, ag: &Agreement, label: &str, base: &Path) -> Result<()> {
    use crate::plot::{Chart, Series, Style, PALETTE};
    let commands = |t: &Trajectory| {
        t.samples
            .iter()
            .map(|s| (s.time_s * 1e3, s.command_a))
            .collect::<Vec<_>>()
    };
    crate::plot::render(
        &Chart {
            title: format!(
                "Coil command, firmware {label} against the host: {} of {} bit-identical",
                ag.bit_identical_commands, ag.samples
            ),
            x_label: "time t (ms)".into(),
            y_label: "coil command (A)".into(),
            series: vec![
                Series {
                    label: "host, same core in-process".into(),
                    points: commands(host),
                    color: PALETTE[0],
                    style: Style::Line { width: 3 },
                },
                Series {
                    label: format!("firmware {label}"),
                    points: commands(firmware),
                    color: PALETTE[1],
                    style: Style::Dots,
                },
            ],
        },
        base,
    )
}

pub fn compare(a: &Trajectory, b: &Trajectory, frames: u64) -> Agreement {
    let mut ag = Agreement {
        samples: a.samples.len().min(b.samples.len()),
        bit_identical_commands: 0,
        max_command_diff_a: if a.samples.len() == b.samples.len() {
            0.0
        } else {
            f64::INFINITY
        },
        max_displacement_diff_mm: 0.0,
        frames,
    };
    for (p, q) in a.samples.iter().zip(&b.samples) {
        if p.command_a.to_bits() == q.command_a.to_bits() {
            ag.bit_identical_commands += 1;
        }
        ag.max_command_diff_a = ag.max_command_diff_a.max((p.command_a - q.command_a).abs());
        ag.max_displacement_diff_mm = ag.max_displacement_diff_mm.max((p.x_mm - q.x_mm).abs());
    }
    ag
}

/// `mre pil`: runs the comparison with the controlled run in QEMU, checks it
/// against the in-process runs, and writes the `mre sim` report plus
/// `pil.json` into `report_dir`.
pub fn run_pil(request: &PilRequest, report_dir: &Path) -> Result<PilOutcome> {
    let elf = match &request.elf {
        Some(p) => p.clone(),
        None => super::qemu::build_firmware()?,
    };
    run_pil_on(&request.sim, FirmwareLink::Qemu { elf: &elf }, report_dir)
}

/// `mre pil` with the firmware on `target` (QEMU, or `--serial PORT`).
pub fn run_pil_on(sim: &SimRequest, target: FirmwareLink<'_>, report_dir: &Path) -> Result<PilOutcome> {
    let setup = setup_for(sim)?;
    let mut specs = if sim.runs.is_empty() {
        DEFAULT_RUNS.to_vec()
    } else {
        sim.runs.clone()
    };
    if !specs.contains(&RunSpec::Controlled) {
        specs.push(RunSpec::Controlled);
    }
    // The uploaded table carries the installation (format 3), so the
    // firmware flies the one the host plant simulates.
    let table = crate::control_bench::diagnosed_table(&setup.plant, setup.impact.noise_seed)?
        .carrying(setup.installation)
        .map_err(|e| anyhow!("the table with the installation: {e:?}"))?;
    let cfg = control_config(&setup)?;

    let (firmware, frames, counters) = run_firmware_on(&setup, &table, &cfg, target)?;
    let host = run_in_process(&setup, &table, &cfg)?;
    let sim = crate::plant::closed_loop::run_controlled(&setup, &table)?;
    let agreement = compare(&firmware, &host, frames);
    let agreement_with_sim = compare(&firmware, &sim, frames);

    let mut runs = Vec::new();
    for &spec in &specs {
        let (trajectory, label) = match spec {
            RunSpec::Passive(a) => (run_passive(&setup, a)?, spec.label()),
            RunSpec::Controlled => (firmware.clone(), format!("controlled (firmware {})", target.label())),
        };
        runs.push(RunResult::new(spec, label, &setup, trajectory));
    }
    let comparison = Comparison::from_runs(runs);
    crate::plant::sim_report::write_sim_report(&comparison, report_dir)?;
    agreement_figure(
        &firmware,
        &host,
        &agreement,
        &target.label(),
        &report_dir.join(AGREEMENT_FIGURE),
    )?;
    let json = serde_json::json!({
        "firmware_vs_in_process": agreement,
        "firmware_vs_mre_sim": agreement_with_sim,
        "firmware_counters": counters,
    });
    crate::atomic_write::write_atomic_with(&report_dir.join("pil.json"), |buf| {
        serde_json::to_writer_pretty(&mut *buf, &json)?;
        Ok(())
    })
    .context("writing pil.json")?;
    crate::html::Page::new(format!("Closed-loop drop test, firmware {} (PIL)", target.label()))
        .folder(report_dir)
        .write(&report_dir.join("index.html"))?;
    Ok(PilOutcome {
        comparison,
        counters,
        agreement,
        agreement_with_sim,
    })
}
