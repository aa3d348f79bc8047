//! FMI 2.0 for both FMUs: the same models ([`crate::Damper`],
//! [`crate::Controller`]) behind the `fmi2*` C functions, exported from the
//! same libraries as the FMI 3.0 ones (the names do not clash), so one
//! binary serves `mre fmu --fmi-version 2` and `3`.
//!
//! fmi-export 0.3 has no FMI 2.0 side; rust-fmi's `fmi-sys` has the 2.0
//! types (`fmi_sys::fmi2`), which this module uses. The model code is the
//! 3.0 one: this module drives the models through fmi-export's
//! `UserModel` and `ModelGetSet` traits with its own [`Ctx`] (the 3.0
//! `Context` over FMI 2.0's logger and resource URI), so no physics is
//! written twice.
//!
//! The error contract is the 3.0 one ([`crate::export`]): every call runs
//! under `catch_unwind`; calls out of order, setting an output or a
//! calculated parameter, a bad `fmi2DoStep`, and every function this FMU
//! does not implement return `fmi2Error` with a log line; an input out of
//! its declared range gives `fmi2Warning`; `fmi2Reset` makes a fresh model.
//!
//! - [`describe`]: the 2.0 `modelDescription.xml`,
//! - [`export`]: the C functions ([`export_fmi2!`](crate::export_fmi2)).
pub mod describe;
pub mod export;

use crate::export::Exported;
use fmi::fmi3::{Fmi3Error, Fmi3Res, Fmi3Status};
use fmi::schema::fmi3::{Causality, Variable};
use fmi_export::fmi3::{Context, ModelGetSet, UserModel};
pub use fmi_sys::fmi2 as b2;
use std::ffi::CString;
use std::marker::PhantomData;
use std::path::PathBuf;

/// FMI 2.0 statuses (`fmi2Status`).
pub const OK: b2::fmi2Status = b2::fmi2Status_fmi2OK;
pub const WARNING: b2::fmi2Status = b2::fmi2Status_fmi2Warning;
pub const ERROR: b2::fmi2Status = b2::fmi2Status_fmi2Error;

/// FMI 2.0's instance states (FMI 2.0.4 §3.2.3 and §4.2.4).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Mode {
    Instantiated,
    Initialization,
    /// Model Exchange.
    Event,
    ContinuousTime,
    /// Co-Simulation.
    StepComplete,
    Terminated,
    /// After a call failed inside the model: only reset, free, get.
    Error,
}

/// The importer's logger and where the FMU's resources are: the 3.0
/// `Context` the models are written against, served by FMI 2.0.
pub struct Ctx<M> {
    logger: b2::fmi2CallbackLogger,
    environment: b2::fmi2ComponentEnvironment,
    instance_name: CString,
    /// `fmi2SetDebugLogging`: OK-level messages only when on; warnings and
    /// errors always (FMI 2.0 §2.1.5 lets the FMU report them regardless).
    logging_on: bool,
    resource_path: PathBuf,
    time: f64,
    stop_time: Option<f64>,
    _model: PhantomData<fn() -> M>,
}

impl<M: UserModel + 'static> Context<M> for Ctx<M> {
    fn logging_on(&self, _category: M::LoggingCategory) -> bool {
        self.logging_on
    }

    fn set_logging(&mut self, _category: M::LoggingCategory, enabled: bool) {
        self.logging_on = enabled;
    }

    fn log(&self, status: Fmi3Status, category: M::LoggingCategory, args: std::fmt::Arguments<'_>) {
        let status: fmi::fmi3::binding::fmi3Status = status.into();
        // FMI 3.0 and 2.0 number OK … Fatal alike (0 … 4).
        let status = status as b2::fmi2Status;
        if status == OK && !self.logging_on {
            return;
        }
        self.message(status, &category.to_string(), &args.to_string());
    }

    fn resource_path(&self) -> &PathBuf {
        &self.resource_path
    }

    fn initialize(&mut self, start_time: f64, stop_time: Option<f64>) {
        self.time = start_time;
        self.stop_time = stop_time;
    }

    fn time(&self) -> f64 {
        self.time
    }

    fn set_time(&mut self, time: f64) {
        self.time = time;
    }

    fn stop_time(&self) -> Option<f64> {
        self.stop_time
    }

    fn as_any_mut(&mut self) -> &mut dyn std::any::Any {
        self
    }
}

impl<M> Ctx<M> {
    /// Sends one message to the importer's logger. The logger is printf-like
    /// (FMI 2.0 §2.1.5): a `%` in the text is doubled, no arguments follow.
    fn message(&self, status: b2::fmi2Status, category: &str, text: &str) {
        let Some(logger) = self.logger else { return };
        let text = CString::new(text.replace('%', "%%").replace('\0', " ")).unwrap_or_default();
        let category = CString::new(category.replace('\0', " ")).unwrap_or_default();
        unsafe {
            logger(
                self.environment,
                self.instance_name.as_ptr(),
                status,
                category.as_ptr(),
                text.as_ptr(),
            )
        };
    }
}

/// A variable's FMI 2.0 type.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Type {
    Real,
    Integer,
}

/// One variable as the 2.0 layer needs it (from the 3.0 metadata the derive builds).
#[derive(Clone, Debug)]
pub struct Var {
    pub vr: u32,
    pub name: String,
    pub ty: Type,
    pub causality: Causality,
}

/// The model's variables without the independent `time` (FMI 2.0 declares none).
pub fn variables<M: Exported>() -> Vec<Var> {
    let meta = M::build_toplevel_metadata();
    meta.model_variables
        .variables
        .iter()
        .filter_map(|v| {
            let (vr, name, ty, causality) = match v {
                Variable::Float64(f) => (f.value_reference, f.name.clone(), Type::Real, f.causality),
                Variable::UInt32(f) => (f.value_reference, f.name.clone(), Type::Integer, f.causality),
                _ => return None,
            };
            let causality = causality.unwrap_or_default();
            (causality != Causality::Independent).then_some(Var {
                vr,
                name,
                ty,
                causality,
            })
        })
        .collect()
}

/// One FMI 2.0 instance: the model, its context and its state.
pub struct Instance<M: Exported> {
    pub model: M,
    pub ctx: Ctx<M>,
    pub model_exchange: bool,
    pub mode: Mode,
    /// Inputs or time changed since the model last computed its outputs.
    dirty: bool,
    variables: Vec<Var>,
    /// The inputs' declared ranges by value reference (read from the page on first set).
    ranges: Option<Vec<(u32, crate::ranges::InputRange)>>,
}

impl<M: Exported> Drop for Instance<M> {
    fn drop(&mut self) {
        // Freed: its address may be reused.
        crate::export::set_continuous_time::<M>(&self.ctx, false);
    }
}

/// `file:` URI → path (FMI 2.0 §2.1.5: `fmuResourceLocation` is a URI;
/// importers write `file:///abs/path`, `file:/abs/path` or
/// `file://localhost/abs/path`, with `%XX` escapes).
pub fn path_from_uri(uri: &str) -> Option<PathBuf> {
    let rest = uri.strip_prefix("file:")?;
    let rest = rest
        .strip_prefix("//localhost")
        .or_else(|| rest.strip_prefix("//"))
        .unwrap_or(rest);
    let bytes = rest.as_bytes();
    let mut out = Vec::with_capacity(bytes.len());
    let mut i = 0;
    while i < bytes.len() {
        if bytes[i] == b'%' && i + 2 < bytes.len() {
            let hex = std::str::from_utf8(&bytes[i + 1..i + 3]).ok()?;
            out.push(u8::from_str_radix(hex, 16).ok()?);
            i += 3;
        } else {
            out.push(bytes[i]);
            i += 1;
        }
    }
    let mut path = String::from_utf8(out).ok()?;
    // Windows: /C:/dir → C:/dir
    if path.len() > 2 && path.as_bytes()[0] == b'/' && path.as_bytes()[2] == b':' {
        path.remove(0);
    }
    Some(PathBuf::from(path))
}

impl<M: Exported + ModelGetSet<M>> Instance<M> {
    pub fn new(
        instance_name: &str,
        model_exchange: bool,
        resource_path: PathBuf,
        logger: b2::fmi2CallbackLogger,
        environment: b2::fmi2ComponentEnvironment,
        logging_on: bool,
    ) -> Self {
        let mut model = M::default();
        model.set_start_values();
        Instance {
            model,
            ctx: Ctx {
                logger,
                environment,
                instance_name: CString::new(instance_name.replace('\0', " ")).unwrap_or_default(),
                logging_on,
                resource_path,
                time: 0.0,
                stop_time: None,
                _model: PhantomData,
            },
            model_exchange,
            mode: Mode::Instantiated,
            dirty: true,
            variables: variables::<M>(),
            ranges: None,
        }
    }

    /// Logs an error naming `function` and returns `fmi2Error`.
    pub fn error(&self, function: &str, why: std::fmt::Arguments<'_>) -> b2::fmi2Status {
        self.ctx.message(ERROR, "logStatusError", &format!("{function}: {why}"));
        ERROR
    }

    /// `Ok` when the instance is in one of `modes`; else logs and `fmi2Error`.
    pub fn expect(&self, function: &str, modes: &[Mode]) -> Result<(), b2::fmi2Status> {
        if modes.contains(&self.mode) {
            Ok(())
        } else {
            Err(self.error(
                function,
                format_args!("not allowed in state {:?} (allowed in {modes:?})", self.mode),
            ))
        }
    }

    /// `Ok` for a Model Exchange instance; else logs and `fmi2Error`.
    pub fn expect_me(&self, function: &str) -> Result<(), b2::fmi2Status> {
        if self.model_exchange {
            Ok(())
        } else {
            Err(self.error(
                function,
                format_args!("a Model Exchange function on a Co-Simulation instance"),
            ))
        }
    }

    fn status(&self, result: Result<Fmi3Res, Fmi3Error>) -> b2::fmi2Status {
        match result {
            Ok(Fmi3Res::OK) => OK,
            Ok(Fmi3Res::Warning) => WARNING,
            Err(e) => {
                let s: Fmi3Status = e.into();
                let s: fmi::fmi3::binding::fmi3Status = s.into();
                s as b2::fmi2Status
            }
        }
    }

    /// The model's outputs from its current inputs and time, if stale.
    fn update(&mut self) -> Result<(), b2::fmi2Status> {
        if self.dirty && self.mode != Mode::Instantiated {
            let r = self.model.calculate_values(&self.ctx);
            if r.is_err() {
                return Err(self.status(r));
            }
            self.dirty = false;
        }
        Ok(())
    }

    pub fn setup_experiment(&mut self, start_s: f64, stop_s: Option<f64>) -> b2::fmi2Status {
        if let Err(s) = self.expect("fmi2SetupExperiment", &[Mode::Instantiated]) {
            return s;
        }
        if !start_s.is_finite() || stop_s.is_some_and(|stop| stop.is_nan() || stop < start_s) {
            return self.error(
                "fmi2SetupExperiment",
                format_args!("start time {start_s} s, stop time {stop_s:?} s: not an interval"),
            );
        }
        self.ctx.initialize(start_s, stop_s);
        OK
    }

    pub fn enter_initialization_mode(&mut self) -> b2::fmi2Status {
        if let Err(s) = self.expect("fmi2EnterInitializationMode", &[Mode::Instantiated]) {
            return s;
        }
        self.mode = Mode::Initialization;
        self.dirty = true;
        OK
    }

    pub fn exit_initialization_mode(&mut self) -> b2::fmi2Status {
        if let Err(s) = self.expect("fmi2ExitInitializationMode", &[Mode::Initialization]) {
            return s;
        }
        // As fmi-export's 3.0 instance: outputs, then `configurate`.
        if let Err(s) = self.update() {
            self.mode = Mode::Error;
            return s;
        }
        let r = self.model.configurate(&self.ctx);
        if r.is_err() {
            self.mode = Mode::Error;
            return ERROR;
        }
        self.dirty = true;
        self.mode = if self.model_exchange {
            Mode::Event
        } else {
            Mode::StepComplete
        };
        OK
    }

    pub fn terminate(&mut self) -> b2::fmi2Status {
        if let Err(s) = self.expect(
            "fmi2Terminate",
            &[Mode::Event, Mode::ContinuousTime, Mode::StepComplete],
        ) {
            return s;
        }
        self.mode = Mode::Terminated;
        OK
    }

    /// A fresh model with its start values, as after `fmi2Instantiate`.
    pub fn reset(&mut self) -> b2::fmi2Status {
        self.model = M::default();
        self.model.set_start_values();
        self.ctx.initialize(0.0, None);
        self.mode = Mode::Instantiated;
        crate::export::set_continuous_time::<M>(&self.ctx, false);
        self.dirty = true;
        OK
    }

    fn var(&self, function: &str, vr: u32, ty: Type) -> Result<&Var, b2::fmi2Status> {
        self.variables
            .iter()
            .find(|v| v.vr == vr && v.ty == ty)
            .ok_or_else(|| self.error(function, format_args!("no {ty:?} variable has value reference {vr}")))
    }

    /// Reads `values.len()` variables of type `ty` (`fmi2GetReal`, `fmi2GetInteger`).
    pub fn get(&mut self, function: &str, vrs: &[u32], ty: Type, mut put: impl FnMut(usize, f64)) -> b2::fmi2Status {
        if let Err(s) = self.expect(
            function,
            &[
                Mode::Initialization,
                Mode::Event,
                Mode::ContinuousTime,
                Mode::StepComplete,
                Mode::Terminated,
                Mode::Error,
            ],
        ) {
            return s;
        }
        if let Err(s) = self.update() {
            return s;
        }
        for (k, vr) in vrs.iter().enumerate() {
            if let Err(s) = self.var(function, *vr, ty) {
                return s;
            }
            // fmi-export's getters count from the first variable after `time` (value reference 1).
            let index = vr - 1;
            let value = match ty {
                Type::Real => {
                    let mut v = [0.0];
                    self.model.get_float64(index, &mut v, &self.ctx).map(|_| v[0])
                }
                Type::Integer => {
                    let mut v = [0u32];
                    self.model.get_uint32(index, &mut v, &self.ctx).map(|_| f64::from(v[0]))
                }
            };
            match value {
                Ok(v) => put(k, v),
                Err(_) => return self.error(function, format_args!("value reference {vr} could not be read")),
            }
        }
        OK
    }

    fn input_ranges(&mut self) -> &[(u32, crate::ranges::InputRange)] {
        if self.ranges.is_none() {
            let ranges = crate::page::load(&self.ctx.resource_path)
                .map(|(table, _)| {
                    crate::ranges::input_ranges(M::KIND, &table)
                        .into_iter()
                        .filter_map(|r| self.variables.iter().find(|v| v.name == r.name).map(|v| (v.vr, r)))
                        .collect()
                })
                .unwrap_or_default();
            self.ranges = Some(ranges);
        }
        self.ranges.as_deref().unwrap_or_default()
    }

    /// `fmi2SetReal`: inputs and parameters only; out of range → `fmi2Warning`.
    pub fn set_real(&mut self, vrs: &[u32], values: &[f64]) -> b2::fmi2Status {
        const F: &str = "fmi2SetReal";
        if let Err(s) = self.expect(
            F,
            &[
                Mode::Instantiated,
                Mode::Initialization,
                Mode::Event,
                Mode::ContinuousTime,
                Mode::StepComplete,
            ],
        ) {
            return s;
        }
        // All checked before any is set: a refused call changes nothing.
        for vr in vrs {
            let v = match self.var(F, *vr, Type::Real) {
                Ok(v) => v,
                Err(s) => return s,
            };
            if !matches!(v.causality, Causality::Input | Causality::Parameter) {
                return self.error(
                    F,
                    format_args!(
                        "{} (value reference {vr}) is not an input or a parameter and cannot be set",
                        v.name
                    ),
                );
            }
        }
        let mut status = OK;
        for (vr, value) in vrs.iter().zip(values) {
            if self.model.set_float64(vr - 1, &[*value], &self.ctx).is_err() {
                return self.error(F, format_args!("value reference {vr} could not be set"));
            }
            let complaint = self
                .input_ranges()
                .iter()
                .find(|(r, _)| r == vr)
                .and_then(|(_, range)| crate::ranges::complaint(range, *value));
            if let Some(why) = complaint {
                self.ctx.message(WARNING, "logStatusWarning", &format!("{F}: {why}"));
                status = WARNING;
            }
        }
        self.dirty = true;
        status
    }

    /// `fmi2DoStep` (Co-Simulation).
    pub fn do_step(&mut self, t: f64, h: f64, no_set_prior: bool) -> b2::fmi2Status {
        const F: &str = "fmi2DoStep";
        if self.model_exchange {
            return self.error(F, format_args!("a Co-Simulation function on a Model Exchange instance"));
        }
        if let Err(s) = self.expect(F, &[Mode::StepComplete]) {
            return s;
        }
        if let Some(problem) = crate::export::step_problem(self.ctx.time, t, h) {
            return self.error(F, format_args!("{problem}"));
        }
        if let Err(s) = self.update() {
            return s;
        }
        let r = self.model.do_step(&mut self.ctx, t, h, no_set_prior);
        self.dirty = true;
        match r {
            Ok(_) => OK,
            Err(e) => {
                self.mode = Mode::Error;
                self.status(Err(e))
            }
        }
    }

    // Model Exchange.

    pub fn enter_event_mode(&mut self) -> b2::fmi2Status {
        const F: &str = "fmi2EnterEventMode";
        if let Err(s) = self
            .expect_me(F)
            .and_then(|_| self.expect(F, &[Mode::Event, Mode::ContinuousTime]))
        {
            return s;
        }
        self.mode = Mode::Event;
        crate::export::set_continuous_time::<M>(&self.ctx, false);
        self.dirty = true;
        OK
    }

    /// `fmi2NewDiscreteStates`: the model's event update.
    pub fn new_discrete_states(&mut self, info: &mut b2::fmi2EventInfo) -> b2::fmi2Status {
        const F: &str = "fmi2NewDiscreteStates";
        if let Err(s) = self.expect_me(F).and_then(|_| self.expect(F, &[Mode::Event])) {
            return s;
        }
        let mut flags = fmi::EventFlags::default();
        let r = self.model.event_update(&self.ctx, &mut flags);
        self.dirty = true;
        *info = b2::fmi2EventInfo {
            newDiscreteStatesNeeded: flags.discrete_states_need_update.into(),
            terminateSimulation: flags.terminate_simulation.into(),
            nominalsOfContinuousStatesChanged: flags.nominals_of_continuous_states_changed.into(),
            valuesOfContinuousStatesChanged: flags.values_of_continuous_states_changed.into(),
            nextEventTimeDefined: flags.next_event_time.is_some().into(),
            nextEventTime: flags.next_event_time.unwrap_or(0.0),
        };
        self.status(r)
    }

    pub fn enter_continuous_time_mode(&mut self) -> b2::fmi2Status {
        const F: &str = "fmi2EnterContinuousTimeMode";
        if let Err(s) = self.expect_me(F).and_then(|_| self.expect(F, &[Mode::Event])) {
            return s;
        }
        self.mode = Mode::ContinuousTime;
        // The damper holds its branch from here to the next event.
        crate::export::set_continuous_time::<M>(&self.ctx, true);
        OK
    }

    pub fn set_time(&mut self, time_s: f64) -> b2::fmi2Status {
        const F: &str = "fmi2SetTime";
        if let Err(s) = self
            .expect_me(F)
            .and_then(|_| self.expect(F, &[Mode::Event, Mode::ContinuousTime]))
        {
            return s;
        }
        if !time_s.is_finite() {
            return self.error(F, format_args!("time {time_s} s is not a number"));
        }
        self.ctx.set_time(time_s);
        self.dirty = true;
        OK
    }

    /// ME functions on the continuous states: this model has none, so `n` must be 0.
    pub fn no_states(&self, function: &str, n: usize) -> b2::fmi2Status {
        if let Err(s) = self.expect_me(function) {
            return s;
        }
        if n != 0 {
            return self.error(
                function,
                format_args!("{n} states asked for; this model has no continuous state"),
            );
        }
        OK
    }

    pub fn get_event_indicators(&mut self, out: &mut [f64]) -> b2::fmi2Status {
        const F: &str = "fmi2GetEventIndicators";
        if let Err(s) = self.expect_me(F).and_then(|_| {
            self.expect(
                F,
                &[
                    Mode::Initialization,
                    Mode::Event,
                    Mode::ContinuousTime,
                    Mode::Terminated,
                ],
            )
        }) {
            return s;
        }
        if out.len() != M::MAX_EVENT_INDICATORS {
            return self.error(
                F,
                format_args!(
                    "{} indicators asked for; the model has {}",
                    out.len(),
                    M::MAX_EVENT_INDICATORS
                ),
            );
        }
        if let Err(s) = self.update() {
            return s;
        }
        match self.model.get_event_indicators(&self.ctx, out) {
            Ok(true) => OK,
            Ok(false) => b2::fmi2Status_fmi2Discard,
            Err(e) => self.status(Err(e)),
        }
    }
}
