//! `mre sim`: the drop test with the core's impact-mitigation law in the loop
//! (in process), compared with the passive damper at 0 A and 2 A.
//!
//! The controller flies the table a user would make for *this* plant:
//! controller (c) of `mre bench-control` — the plant's recorded campaign,
//! `mre diagnose --model-out`, its model file
//! ([`crate::control_bench::diagnosed_table`]).
//!
//! The drop's mass, the usable stroke, the coil driver and the law's limits
//! are one [`Installation`]: a model file's `[installation]`
//! (`mre sim --model FILE`), else `DEFAULT_INSTALLATION` (the image's). On
//! the default one the passive 0 A drop at 2.24 m/s needs about 16 mm, more
//! than the 12 mm usable stroke, which is why a soft passive setting is not
//! an option.
use super::stepper::{simulate, CoilDriver, CurrentSource, ImpactConfig, ImpactSummary, Plant, Trajectory};
use anyhow::{bail, Context, Result};
use mre_algorithm::installation::{Installation, DEFAULT_INSTALLATION};
use mre_algorithm::law::{ImpactLaw, LawConfig};
use mre_algorithm::Table;
use serde::Serialize;

/// Which current a run uses.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub enum RunSpec {
    /// A constant current (A).
    Passive(f64),
    /// The core's `ImpactLaw` in the loop.
    Controlled,
}

impl RunSpec {
    /// `passive:<A>` or `controlled`.
    pub fn parse(text: &str) -> Result<Self> {
        if text == "controlled" {
            return Ok(RunSpec::Controlled);
        }
        if let Some(a) = text.strip_prefix("passive:") {
            let current_a: f64 = a
                .parse()
                .with_context(|| format!("`{text}`: `{a}` is not a current in A"))?;
            if !(0.0..=2.0).contains(&current_a) {
                bail!("`{text}`: passive current must be within 0–2 A");
            }
            return Ok(RunSpec::Passive(current_a));
        }
        bail!("`{text}`: expected passive:<A> (e.g. passive:0, passive:2) or controlled")
    }

    pub fn label(&self) -> String {
        match self {
            RunSpec::Passive(a) => format!("passive {a} A"),
            RunSpec::Controlled => "controlled".to_owned(),
        }
    }

    /// File-name stem for this run's outputs.
    pub fn slug(&self) -> String {
        match self {
            RunSpec::Passive(a) => format!("passive-{a}a"),
            RunSpec::Controlled => "controlled".to_owned(),
        }
    }
}

/// Settings of a comparison.
#[derive(Clone, Debug)]
pub struct SimSetup {
    pub plant: Plant,
    /// The drop: its mass and coil driver are the installation's
    /// ([`ImpactConfig::for_installation`]).
    pub impact: ImpactConfig,
    /// What the law plans with: usable stroke, coil rating, drive range, sensors.
    pub installation: Installation,
}

impl Default for SimSetup {
    fn default() -> Self {
        Self::for_installation(Plant::nominal(), DEFAULT_INSTALLATION)
    }
}

impl SimSetup {
    /// The paper's drop on `plant` in `installation`.
    pub fn for_installation(plant: Plant, installation: Installation) -> Self {
        Self {
            plant,
            impact: ImpactConfig::for_installation(&installation),
            installation,
        }
    }

    /// Stroke the damper may use (mm): the installation's.
    pub fn usable_stroke_mm(&self) -> f64 {
        f64::from(self.installation.usable_stroke_mm)
    }
}

impl ImpactConfig {
    /// The paper's drop (2.24 m/s, 10 kHz) with the installation's mass and
    /// coil driver (its resistance and supply).
    pub fn for_installation(installation: &Installation) -> Self {
        Self {
            mass_kg: f64::from(installation.mass_kg),
            driver: CoilDriver {
                resistance_ohm: f64::from(installation.coil_resistance_ohm),
                supply_v: f64::from(installation.supply_v),
                ..CoilDriver::default()
            },
            ..ImpactConfig::default()
        }
    }
}

/// One run's outcome.
#[derive(Clone, Debug, Serialize)]
pub struct RunResult {
    pub spec: RunSpec,
    pub label: String,
    pub summary: ImpactSummary,
    pub usable_stroke_mm: f64,
    pub within_stroke: bool,
    #[serde(skip)]
    pub trajectory: Trajectory,
}

/// All runs, and the controlled run's gain over the best passive run that
/// stays within the stroke.
#[derive(Clone, Debug, Serialize)]
pub struct Comparison {
    pub runs: Vec<RunResult>,
    /// `(label of the passive reference, reduction of peak force in %)`.
    pub controlled_vs_passive: Option<(String, f64)>,
}

/// The core law's settings for this plant and drop: the board's defaults
/// with the installation applied (`Installation::apply`, as the board does),
/// the drop's mass, gravity and control period.
pub fn law_config(setup: &SimSetup) -> LawConfig {
    let mut cfg = mre_algorithm::control::ControlConfig::at_rate(mre_algorithm::control::DEFAULT_RATE_HZ);
    let law = match &mut cfg {
        Ok(cfg) => {
            setup.installation.apply(cfg);
            cfg.law
        }
        // The default rate is always valid; the law's defaults otherwise.
        Err(_) => LawConfig::default(),
    };
    LawConfig {
        mass_kg: setup.impact.mass_kg as f32,
        stroke_max_mm: setup.installation.usable_stroke_mm,
        gravity_m_s2: setup.impact.gravity_m_s2 as f32,
        period_s: setup.impact.control_period_s as f32,
        ..law
    }
}

/// Runs the drop with the core's `ImpactLaw` and `table` in the loop. When
/// the table carries a coil time constant the law pre-energises the coil
/// while idle, so the drop starts with the coil settled at that current.
pub fn run_controlled(setup: &SimSetup, table: &Table) -> Result<Trajectory> {
    let mut law = ImpactLaw::new(law_config(setup)).map_err(|e| anyhow::anyhow!("law configuration: {e:?}"))?;
    let impact = controlled_impact(setup, table);
    let controller = move |x_mm: f32, v_m_s: f32| law.step(table, x_mm, v_m_s).current_a;
    simulate(&setup.plant, &impact, CurrentSource::Controller(Box::new(controller)))
}

/// The drop of a controlled run: the coil starts at the current the law
/// held while idle ([`ImpactLaw::idle_current_a`]).
pub fn controlled_impact(setup: &SimSetup, table: &Table) -> ImpactConfig {
    let idle_a = ImpactLaw::new(law_config(setup)).map_or(0.0, |law| law.idle_current_a(table));
    ImpactConfig {
        initial_current_a: f64::from(idle_a),
        ..setup.impact.clone()
    }
}

/// Runs every spec and compares them.
pub fn run_comparison(setup: &SimSetup, specs: &[RunSpec]) -> Result<Comparison> {
    let table = if specs.contains(&RunSpec::Controlled) {
        Some(crate::control_bench::diagnosed_table(
            &setup.plant,
            setup.impact.noise_seed,
        )?)
    } else {
        None
    };
    let mut runs = Vec::new();
    for &spec in specs {
        let trajectory = match (spec, &table) {
            (RunSpec::Passive(a), _) => run_passive(setup, a)?,
            (RunSpec::Controlled, Some(table)) => run_controlled(setup, table)?,
            (RunSpec::Controlled, None) => bail!("internal: no table for the controlled run"),
        };
        runs.push(RunResult::new(spec, spec.label(), setup, trajectory));
    }
    Ok(Comparison::from_runs(runs))
}

/// A passive drop at constant current. A passive damper's coil is energised
/// before the impact.
pub fn run_passive(setup: &SimSetup, current_a: f64) -> Result<Trajectory> {
    let impact = ImpactConfig {
        initial_current_a: current_a,
        ..setup.impact.clone()
    };
    simulate(&setup.plant, &impact, CurrentSource::Constant(current_a))
}

impl RunResult {
    pub fn new(spec: RunSpec, label: String, setup: &SimSetup, trajectory: Trajectory) -> Self {
        let summary = trajectory.summary;
        RunResult {
            spec,
            label,
            summary,
            usable_stroke_mm: setup.usable_stroke_mm(),
            within_stroke: summary.max_stroke_mm <= setup.usable_stroke_mm(),
            trajectory,
        }
    }
}

impl Comparison {
    /// Compares the controlled run with the lowest-peak passive run that
    /// stays within the stroke.
    pub fn from_runs(runs: Vec<RunResult>) -> Self {
        let controlled = runs.iter().find(|r| r.spec == RunSpec::Controlled);
        let reference = runs
            .iter()
            .filter(|r| matches!(r.spec, RunSpec::Passive(_)) && r.within_stroke)
            .min_by(|a, b| a.summary.peak_force_n.total_cmp(&b.summary.peak_force_n));
        let controlled_vs_passive = match (controlled, reference) {
            (Some(c), Some(p)) => Some((
                p.label.clone(),
                100.0 * (1.0 - c.summary.peak_force_n / p.summary.peak_force_n),
            )),
            _ => None,
        };
        Comparison {
            runs,
            controlled_vs_passive,
        }
    }
}

/// What `mre sim` was asked for.
#[derive(Clone, Debug)]
pub struct SimRequest {
    /// Runs; empty = passive 0 A, passive 2 A and controlled.
    pub runs: Vec<RunSpec>,
    /// Concealed effect on the plant (`none`, a vocabulary name, or `random`).
    pub effect: String,
    /// Seeds the effect's parameters and the measurement noise.
    pub seed: u64,
    pub impact_velocity_m_s: f64,
    /// The drop's mass, usable stroke, coil driver and law limits (a model
    /// file's `[installation]`, or the defaults).
    pub installation: Installation,
    pub coil_lag_s: Option<f64>,
    /// The coil's time constant while its current falls (`--coil-lag-off-ms`).
    pub coil_lag_off_s: Option<f64>,
}

impl Default for SimRequest {
    fn default() -> Self {
        Self {
            runs: Vec::new(),
            effect: "none".to_owned(),
            seed: 0,
            impact_velocity_m_s: 2.24,
            installation: DEFAULT_INSTALLATION,
            coil_lag_s: None,
            coil_lag_off_s: None,
        }
    }
}

/// The default comparison.
pub const DEFAULT_RUNS: [RunSpec; 3] = [RunSpec::Passive(0.0), RunSpec::Passive(2.0), RunSpec::Controlled];

/// The calibrated plant with the requested effect (parameters drawn from the
/// seed, sized as `mre synth` sizes them), and the drop.
pub fn setup_for(request: &SimRequest) -> Result<SimSetup> {
    use super::effects::{draw_effect, ConcealedEffect};
    use super::synth::{effect_scale, resolve_effect_name, SynthPlan};
    use rand::SeedableRng;
    let kind = resolve_effect_name(&request.effect, request.seed)?;
    let base = Plant::nominal();
    let scale = effect_scale(&base, &SynthPlan::default())?;
    let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(request.seed);
    rng.set_stream(3);
    let mut plant = base.with_effect(draw_effect(kind, &mut rng, scale)?);
    // `--coil-lag-ms` on a plant without an effect is the coil_lag effect,
    // so the campaign controller (c) is made from shows it too.
    if let (Some(tau_s), ConcealedEffect::None) = (request.coil_lag_s, &plant.effect) {
        plant = plant.with_effect(ConcealedEffect::CoilLag { time_constant_s: tau_s });
    }
    let coil_lag_s = request.coil_lag_s.or(plant.effect.coil_lag_s());
    if request.coil_lag_off_s.is_some() && coil_lag_s.is_none() {
        bail!("--coil-lag-off-ms needs a coil time constant too (--coil-lag-ms, or a coil_lag effect)");
    }
    let mut setup = SimSetup::for_installation(plant, request.installation);
    setup.impact = ImpactConfig {
        impact_velocity_m_s: request.impact_velocity_m_s,
        // `--coil-lag-ms` wins over a `coil_lag` effect's drawn τ.
        coil_lag_s,
        coil_lag_off_s: request.coil_lag_off_s,
        noise_seed: request.seed,
        ..setup.impact
    };
    Ok(setup)
}

/// `mre sim`: runs the comparison and writes the report into `report_dir`.
pub fn run_sim(request: &SimRequest, report_dir: &std::path::Path) -> Result<Comparison> {
    let setup = setup_for(request)?;
    let runs = if request.runs.is_empty() {
        DEFAULT_RUNS.to_vec()
    } else {
        request.runs.clone()
    };
    let cmp = run_comparison(&setup, &runs)?;
    super::sim_report::write_sim_report(&cmp, report_dir)?;
    crate::html::Page::new("Closed-loop drop test (host)")
        .folder(report_dir)
        .write(&report_dir.join("index.html"))?;
    Ok(cmp)
}
