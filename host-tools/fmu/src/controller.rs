//! The impact controller as the board runs it: `mre_algorithm::control::Controller`
//! (the law, its velocity cross-checks and fault latches) stepped once per
//! control period of the configuration on the page, with a measured
//! velocity (the board's `velocity-sensor` wiring).
//!
//! Timing: control ticks fall at `start + k·T`. `doStep(t, h)` runs every
//! tick in `[t, t + h)` on the inputs set for `t`, and the output then holds
//! the last tick's command (zero-order hold, as the coil driver holds it).
//! A communication step of `T` (the default experiment's) gives one tick per
//! step; a longer step reuses its inputs for each tick in it.
//!
//! Outputs: `coil_command_a` is the law's command as the core returns it
//! (with a coil τ the drive over R, kept under its old name); the FMU adds
//! `drive_voltage_v` (that times R) and `coil_current_a`, the coil current
//! the drive gives through the lag `1 − e^{−T/τ}` per tick, for importers
//! that wire a current into the damper (#43 item 5).
use fmi::fmi3::{Fmi3Error, Fmi3Res};
use fmi_export::fmi3::{CSDoStepResult, Context, DefaultLoggingCategory, UserModel};
use fmi_export::FmuModel;
use mre_algorithm::control;
use mre_algorithm::law::ImpactLaw;

/// MRE impact controller as the board runs it (mre_algorithm::control::Controller at the board's control rate): measured displacement and velocity in, commanded coil current and drive voltage out
#[derive(FmuModel, Default, Debug)]
#[model(model_exchange = false, co_simulation = true, user_model = false)]
pub struct Controller {
    /// Measured damper compression from first contact (m), positive into the damper
    #[variable(causality = Input, variability = Continuous, start = 0.0)]
    pub displacement_m: f64,
    /// Measured compression velocity (m/s), positive while compressing
    #[variable(causality = Input, variability = Continuous, start = 0.0)]
    pub velocity_m_s: f64,
    /// The command as the board's law returns it (A), held until the next tick: the drive voltage over the coil resistance (drive_voltage_v / R); equal to coil_current_a when the coil has no time constant. Kept for existing wiring: feed the damper coil_current_a
    #[variable(causality = Output, variability = Discrete, initial = Calculated)]
    pub coil_command_a: f64,
    /// Force the law asked for at the last tick (N); 0 when rebounding or fail-safe
    #[variable(causality = Output, variability = Discrete, initial = Calculated)]
    pub target_force_n: f64,
    /// Status flags of the last tick (mre_algorithm::flags, firmware/README.md): 1 = X_CLAMPED (bit 0), 256 = FAIL_SAFE (bit 8)
    #[variable(causality = Output, variability = Discrete, initial = Calculated)]
    pub flags: u32,
    /// Control period of the board (s): one control tick per period
    #[variable(causality = CalculatedParameter, variability = Fixed, initial = Calculated)]
    pub control_period_s: f64,
    /// Moving mass the law plans for (kg)
    #[variable(causality = CalculatedParameter, variability = Fixed, initial = Calculated)]
    pub mass_kg: f64,
    /// Usable stroke the law stops the mass within (m)
    #[variable(causality = CalculatedParameter, variability = Fixed, initial = Calculated)]
    pub stroke_max_m: f64,
    /// Commanded coil current (A): what the coil carries at the end of the tick under the drive, by the model file's coil time constant (first-order lag from the previous tick's); wire it to the damper's current_a
    #[variable(causality = Output, variability = Discrete, initial = Calculated)]
    pub coil_current_a: f64,
    /// Drive voltage across the coil (V) held until the next tick: coil_command_a times the installation's coil resistance
    #[variable(causality = Output, variability = Discrete, initial = Calculated)]
    pub drive_voltage_v: f64,
    /// Coil resistance of the installation (ohm): drive_voltage_v = coil_command_a times it
    #[variable(causality = CalculatedParameter, variability = Fixed, initial = Calculated)]
    pub coil_resistance_ohm: f64,
    /// The coil's lag per tick, 1 - exp(-T/tau) (1: no lag).
    #[variable(skip = true)]
    coil_alpha: f64,
    #[variable(skip = true)]
    core: Option<control::Controller>,
    /// Control ticks run so far, and the time of tick 0 (s).
    #[variable(skip = true)]
    ticks: u64,
    #[variable(skip = true)]
    start_s: f64,
}

impl Controller {
    /// Back to a fresh instance's state: no core (reloaded from the page,
    /// latches cleared), no ticks, the outputs of before the first tick.
    fn restart(&mut self) {
        self.core = None;
        self.ticks = 0;
        self.coil_command_a = 0.0;
        self.coil_current_a = 0.0;
        self.drive_voltage_v = 0.0;
        self.target_force_n = 0.0;
        self.flags = 0;
    }

    fn core(&mut self, context: &dyn Context<Self>) -> Result<&mut control::Controller, Fmi3Error> {
        if self.core.is_none() {
            let loaded = crate::page::load(context.resource_path()).and_then(|(table, cfg)| {
                let idle_a = ImpactLaw::new(cfg.law)
                    .map(|law| law.idle_current_a(&table))
                    .map_err(|e| format!("the page's law configuration was refused: {e:?}"))?;
                let core = control::Controller::new(cfg, Ok(table))
                    .map_err(|e| format!("the page's control configuration was refused: {e:?}"))?;
                Ok((
                    core,
                    idle_a,
                    cfg,
                    table.terms().coil_tau_s,
                    table.installation().coil_resistance_ohm,
                ))
            });
            match loaded {
                Ok((core, idle_a, cfg, tau_s, ohm)) => {
                    // Before its first tick the coil holds the idle current, settled.
                    self.coil_command_a = f64::from(idle_a);
                    self.coil_current_a = f64::from(idle_a);
                    self.coil_resistance_ohm = f64::from(ohm);
                    self.drive_voltage_v = f64::from(idle_a) * self.coil_resistance_ohm;
                    let period_s = f64::from(cfg.period_s());
                    self.coil_alpha = if tau_s > 0.0 {
                        1.0 - (-period_s / f64::from(tau_s)).exp()
                    } else {
                        1.0
                    };
                    self.control_period_s = f64::from(cfg.period_s());
                    self.mass_kg = f64::from(cfg.law.mass_kg);
                    self.stroke_max_m = f64::from(cfg.law.stroke_max_mm) * 1.0e-3;
                    self.core = Some(core);
                }
                Err(message) => {
                    context.log(
                        Fmi3Error::Error.into(),
                        DefaultLoggingCategory::default(),
                        format_args!("{message}"),
                    );
                    return Err(Fmi3Error::Error);
                }
            }
        }
        self.core.as_mut().ok_or(Fmi3Error::Error)
    }
}

impl UserModel for Controller {
    type LoggingCategory = DefaultLoggingCategory;

    // Leaving initialisation starts the instance afresh: after fmi3Reset
    // the core's latches and the tick count would otherwise carry over.
    fn configurate(&mut self, context: &dyn Context<Self>) -> Result<(), Fmi3Error> {
        crate::export::take_reset(context);
        self.restart();
        self.start_s = context.time();
        self.core(context).map(|_| ())
    }

    fn calculate_values(&mut self, context: &dyn Context<Self>) -> Result<Fmi3Res, Fmi3Error> {
        // Outputs read in Initialization Mode after a reset are a fresh instance's.
        if crate::export::take_reset(context) {
            self.restart();
        }
        self.core(context).map(|_| Fmi3Res::OK)
    }

    fn do_step(
        &mut self,
        context: &mut dyn Context<Self>,
        current_communication_point: f64,
        communication_step_size: f64,
        _no_set_fmu_state_prior_to_current_point: bool,
    ) -> Result<CSDoStepResult, Fmi3Error> {
        let (x_mm, v_m_s) = ((self.displacement_m * 1.0e3) as f32, self.velocity_m_s as f32);
        let period_s = self.control_period_s;
        let end_s = current_communication_point + communication_step_size;
        // Ticks before `end_s`, less a nanosecond of rounding in the sum of steps.
        let due = ((end_s - self.start_s - 1.0e-9) / period_s).ceil().max(0.0) as u64;
        let mut ticks = self.ticks;
        // Loaded first: loading sets the coil's lag and its idle current.
        self.core(&*context)?;
        let (alpha, mut coil_a) = (self.coil_alpha, self.coil_current_a);
        let core = self.core.as_mut().ok_or(Fmi3Error::Error)?;
        let mut last = None;
        while ticks < due {
            let cmd = core.step_sample(x_mm, Some(v_m_s));
            // The coil follows each tick's drive through its first-order lag.
            coil_a += alpha * (f64::from(cmd.current_a) - coil_a);
            last = Some(cmd);
            ticks += 1;
        }
        self.coil_current_a = coil_a;
        self.ticks = ticks;
        if let Some(cmd) = last {
            self.coil_command_a = f64::from(cmd.current_a);
            self.drive_voltage_v = self.coil_command_a * self.coil_resistance_ohm;
            self.target_force_n = f64::from(cmd.target_force_n);
            self.flags = cmd.flags.0;
        }
        context.set_time(end_s);
        Ok(CSDoStepResult::completed(end_s))
    }
}
