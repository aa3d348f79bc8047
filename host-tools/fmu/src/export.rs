//! The FMI 3.0 C functions of both FMUs ([`export_fmu!`](crate::export_fmu)),
//! in place of rust-fmi's `export_fmu!`, for the FMI error contract:
//!
//! - every call runs under `catch_unwind`: a panic becomes `fmi3Error` with
//!   a log line instead of unwinding into (and aborting) the importer;
//! - the calls fmi-export 0.3 leaves as `todo!()` (FMU state, directional
//!   and adjoint derivatives, clocks, `fmi3EvaluateDiscreteStates`,
//!   scheduled execution) return `fmi3Error` and say so, without panicking;
//! - setting a variable that is not an input or a parameter, and a `doStep`
//!   with a step that is not a positive number or from another time than
//!   the instance's, return `fmi3Error` (fmi-export accepts them);
//! - `fmi3SetFloat64` of an input outside its declared range, or NaN or
//!   infinite, returns `fmi3Warning` with a log line per value (the value is
//!   kept and handled by the model, [`crate::ranges`]);
//! - the dependency functions answer from the model structure the XML
//!   declares ([`crate::describe::dependencies`]), not fmi-export's 0.
//!
//! Everything else is delegated to fmi-export's `Fmi3Common`,
//! `Fmi3ModelExchange` and `Fmi3CoSimulation`.
use crate::describe::Kind;
pub use fmi::fmi3::binding as b;
use fmi::fmi3::Fmi3Error;
use fmi_export::fmi3::{BasicContext, Context, Model, ModelInstance, UserModel};
use std::panic::{catch_unwind, AssertUnwindSafe};
use std::sync::Mutex;

/// The instance behind an `fmi3Instance` (the type fmi-export allocates).
type Instance<M> = ModelInstance<M, BasicContext<M>>;

/// A model the C functions are generated for.
pub trait Exported: Model + UserModel + 'static {
    const KIND: Kind;
}

impl Exported for crate::Damper {
    const KIND: Kind = Kind::Damper;
}

impl Exported for crate::Controller {
    const KIND: Kind = Kind::Controller;
}

/// Logs an error through the instance's logger (if the instance exists).
pub fn log_error<M: Exported>(instance: b::fmi3Instance, args: std::fmt::Arguments<'_>) {
    if let Some(inst) = unsafe { (instance as *const Instance<M>).as_ref() } {
        inst.context()
            .log(Fmi3Error::Error.into(), M::LoggingCategory::default(), args);
    }
}

/// Logs a warning through the instance's logger (if the instance exists).
pub fn log_warning<M: Exported>(instance: b::fmi3Instance, args: std::fmt::Arguments<'_>) {
    if let Some(inst) = unsafe { (instance as *const Instance<M>).as_ref() } {
        inst.context()
            .log(fmi::fmi3::Fmi3Res::Warning.into(), M::LoggingCategory::default(), args);
    }
}

/// Declared input ranges by resource folder and FMU (read from the page once per folder).
type RangeCache = Vec<((Kind, std::path::PathBuf), Vec<(u32, crate::ranges::InputRange)>)>;
static RANGES: Mutex<RangeCache> = Mutex::new(Vec::new());

/// The instance's input ranges with their value references; empty when its
/// page cannot be read (initialisation reports that).
fn input_ranges<M: Exported>(instance: b::fmi3Instance) -> Vec<(u32, crate::ranges::InputRange)> {
    let Some(inst) = (unsafe { (instance as *const Instance<M>).as_ref() }) else {
        return Vec::new();
    };
    let key = (M::KIND, inst.context().resource_path().clone());
    let mut cache = RANGES.lock().unwrap_or_else(|e| e.into_inner());
    if let Some((_, ranges)) = cache.iter().find(|(k, _)| *k == key) {
        return ranges.clone();
    }
    let Ok((table, _)) = crate::page::load(&key.1) else {
        return Vec::new();
    };
    let meta = M::build_toplevel_metadata();
    let ranges: Vec<(u32, crate::ranges::InputRange)> = crate::ranges::input_ranges(M::KIND, &table)
        .into_iter()
        .filter_map(|r| {
            meta.model_variables
                .iter_abstract()
                .find(|v| v.name() == r.name)
                .map(|v| (v.value_reference(), r))
        })
        .collect();
    cache.push((key, ranges.clone()));
    ranges
}

/// After a successful set: `fmi3Warning` and a log line for each value out
/// of its input's declared range or not finite, else `status` unchanged.
///
/// # Safety
/// `vrs` and `values` hold `n` elements (the set succeeded on them).
pub unsafe fn check_ranges<M: Exported>(
    instance: b::fmi3Instance,
    vrs: *const b::fmi3ValueReference,
    values: *const f64,
    n: usize,
    status: b::fmi3Status,
) -> b::fmi3Status {
    if status != b::fmi3Status_fmi3OK || n == 0 || vrs.is_null() || values.is_null() {
        return status;
    }
    let ranges = input_ranges::<M>(instance);
    let (vrs, values) = unsafe {
        (
            std::slice::from_raw_parts(vrs, n),
            std::slice::from_raw_parts(values, n),
        )
    };
    let mut result = status;
    for (vr, value) in vrs.iter().zip(values) {
        if let Some((_, range)) = ranges.iter().find(|(r, _)| r == vr) {
            if let Some(why) = crate::ranges::complaint(range, *value) {
                log_warning::<M>(instance, format_args!("fmi3SetFloat64: {why}"));
                result = b::fmi3Status_fmi3Warning;
            }
        }
    }
    result
}

/// A caught panic's message (`panic!` with a literal or a formatted one), for
/// the log line that replaces it (FMI 3.0 and 2.0 alike).
pub fn panic_message(payload: &(dyn std::any::Any + Send)) -> String {
    payload
        .downcast_ref::<&str>()
        .map(|s| (*s).to_owned())
        .or_else(|| payload.downcast_ref::<String>().cloned())
        .unwrap_or_default()
}

/// Runs one C call: a panic becomes `fmi3Error` and a log line.
pub fn guard<M: Exported>(
    instance: b::fmi3Instance,
    function: &str,
    call: impl FnOnce() -> b::fmi3Status,
) -> b::fmi3Status {
    match catch_unwind(AssertUnwindSafe(call)) {
        Ok(status) => status,
        Err(payload) => {
            let why = panic_message(payload.as_ref());
            log_error::<M>(instance, format_args!("{function} failed inside the FMU: {why}"));
            b::fmi3Status_fmi3Error
        }
    }
}

/// A call this FMU does not support: `fmi3Error`, said in the log.
pub fn unsupported<M: Exported>(instance: b::fmi3Instance, function: &str) -> b::fmi3Status {
    log_error::<M>(
        instance,
        format_args!("{function} is not supported by this FMU (see its modelDescription.xml capabilities)"),
    );
    b::fmi3Status_fmi3Error
}

/// FMI 3.0: a null `FMUState` makes `fmi3FreeFMUState` a no-op; this FMU
/// hands out no state, so any other is an error.
///
/// # Safety
/// `instance` is null or an instance this library created; the other
/// pointers are as the FMI 3.0 function they serve defines them.
pub unsafe fn free_fmu_state<M: Exported>(instance: b::fmi3Instance, state: *mut b::fmi3FMUState) -> b::fmi3Status {
    if state.is_null() || unsafe { (*state).is_null() } {
        return b::fmi3Status_fmi3OK;
    }
    unsupported::<M>(instance, "fmi3FreeFMUState")
}

/// Value references the importer may set: inputs and parameters (FMI 3.0
/// §2.2.6: outputs, calculated parameters, locals and the independent
/// variable are never set).
fn settable<M: Exported>() -> Vec<u32> {
    use fmi::schema::fmi3::Causality;
    let meta = M::build_toplevel_metadata();
    meta.model_variables
        .iter_abstract()
        .filter(|v| {
            matches!(
                v.causality(),
                Causality::Input | Causality::Parameter | Causality::StructuralParameter
            )
        })
        .map(|v| v.value_reference())
        .collect()
}

/// `Ok` when every value reference may be set; else logs and `Err(fmi3Error)`.
///
/// # Safety
/// `instance` is null or an instance this library created; the other
/// pointers are as the FMI 3.0 function they serve defines them.
pub unsafe fn check_settable<M: Exported>(
    cache: &std::sync::OnceLock<Vec<u32>>,
    instance: b::fmi3Instance,
    function: &str,
    vrs: *const b::fmi3ValueReference,
    n: usize,
) -> Result<(), b::fmi3Status> {
    if n == 0 {
        return Ok(());
    }
    if vrs.is_null() {
        log_error::<M>(instance, format_args!("{function}: null value references"));
        return Err(b::fmi3Status_fmi3Error);
    }
    let allowed = cache.get_or_init(settable::<M>);
    let vrs = unsafe { std::slice::from_raw_parts(vrs, n) };
    match vrs.iter().find(|vr| !allowed.contains(vr)) {
        None => Ok(()),
        Some(vr) => {
            log_error::<M>(
                instance,
                format_args!("{function}: value reference {vr} is not an input or a parameter and cannot be set"),
            );
            Err(b::fmi3Status_fmi3Error)
        }
    }
}

/// Relative tolerance on a communication point against the instance's time:
/// importers sum steps or multiply them out, which differ in the last bits.
const TIME_TOLERANCE: f64 = 1.0e-9;

/// `Ok` for a step from the instance's time by a positive finite step; else
/// logs and `Err(fmi3Error)` (FMI 3.0 `fmi3DoStep`: `communicationStepSize`
/// > 0, `currentCommunicationPoint` the last step's end).
pub fn check_step<M: Exported>(instance: b::fmi3Instance, t: f64, h: f64) -> Result<(), b::fmi3Status> {
    let Some(inst) = (unsafe { (instance as *const Instance<M>).as_ref() }) else {
        return Err(b::fmi3Status_fmi3Error);
    };
    match step_problem(inst.context().time(), t, h) {
        None => Ok(()),
        Some(p) => {
            log_error::<M>(instance, format_args!("fmi3DoStep: {p}"));
            Err(b::fmi3Status_fmi3Error)
        }
    }
}

/// What is wrong with a step from `t` by `h` for an instance at `now` (FMI
/// 2.0 and 3.0 `doStep`: the step positive, from the last step's end).
pub fn step_problem(now: f64, t: f64, h: f64) -> Option<String> {
    if !(h.is_finite() && h > 0.0) {
        Some(format!("communicationStepSize {h} is not a positive number"))
    } else if !t.is_finite() || (t - now).abs() > TIME_TOLERANCE * now.abs().max(1.0) {
        Some(format!(
            "currentCommunicationPoint {t} s is not the instance's time {now} s (no step back in time or across a gap)"
        ))
    } else {
        None
    }
}

/// The dependencies the XML declares for `vr`, or logs and `Err(fmi3Error)`
/// for a variable that is not an unknown with declared dependencies.
pub fn dependencies_of<M: Exported>(instance: b::fmi3Instance, vr: u32) -> Result<Vec<u32>, b::fmi3Status> {
    match crate::describe::dependencies(M::KIND)
        .into_iter()
        .find(|(v, _)| *v == vr)
    {
        Some((_, deps)) => Ok(deps),
        None => {
            log_error::<M>(
                instance,
                format_args!("value reference {vr} is not an output of this FMU: it has no dependencies to report"),
            );
            Err(b::fmi3Status_fmi3Error)
        }
    }
}

/// Instances reset since their model last looked (by the address of their
/// context, which the model sees): fmi-export's reset restores the start
/// values only, so the model clears its own state on its next call.
static RESETS: Mutex<Vec<usize>> = Mutex::new(Vec::new());

fn context_key<M: UserModel>(context: &dyn Context<M>) -> usize {
    context as *const dyn Context<M> as *const () as usize
}

/// Instances in Model Exchange's Continuous-Time Mode (by context address):
/// the damper holds its branch there (crate::damper).
static CONTINUOUS_TIME: Mutex<Vec<usize>> = Mutex::new(Vec::new());

/// Records whether the instance owning `context` is in Continuous-Time Mode.
pub fn set_continuous_time<M: UserModel>(context: &dyn Context<M>, on: bool) {
    let key = context_key(context);
    let mut keys = CONTINUOUS_TIME.lock().unwrap_or_else(|e| e.into_inner());
    keys.retain(|k| *k != key);
    if on {
        keys.push(key);
    }
}

/// Whether the instance owning `context` is in Continuous-Time Mode.
pub fn in_continuous_time<M: UserModel>(context: &dyn Context<M>) -> bool {
    let key = context_key(context);
    CONTINUOUS_TIME.lock().unwrap_or_else(|e| e.into_inner()).contains(&key)
}

/// [`set_continuous_time`] for a 3.0 instance.
pub fn note_continuous_time<M: Exported>(instance: b::fmi3Instance, on: bool) {
    if let Some(inst) = unsafe { (instance as *const Instance<M>).as_ref() } {
        set_continuous_time::<M>(inst.context(), on);
    }
}

/// Records that `instance` was reset.
pub fn note_reset<M: Exported>(instance: b::fmi3Instance) {
    if let Some(inst) = unsafe { (instance as *const Instance<M>).as_ref() } {
        let key = context_key::<M>(inst.context());
        let mut resets = RESETS.lock().unwrap_or_else(|e| e.into_inner());
        if !resets.contains(&key) {
            resets.push(key);
        }
    }
}

/// Marks the instance's values stale: fmi-export's reset leaves its value
/// cache clean, so a get in Initialization Mode would not reach the model.
/// Setting the first float input to its own value is what dirties it.
///
/// # Safety
/// `instance` is null or an instance this library created; the other
/// pointers are as the FMI 3.0 function they serve defines them.
pub unsafe fn mark_stale<M: Exported + fmi_export::fmi3::Fmi3Common>(instance: b::fmi3Instance) {
    use fmi::schema::fmi3::{Causality, Variable};
    let meta = M::build_toplevel_metadata();
    let Some(vr) = meta.model_variables.variables.iter().find_map(|v| match v {
        Variable::Float64(f) if f.causality == Some(Causality::Input) => Some(f.value_reference),
        _ => None,
    }) else {
        return;
    };
    let mut value = [0.0f64];
    unsafe {
        if M::fmi3_get_float64(instance, &vr, 1, value.as_mut_ptr(), 1) == b::fmi3Status_fmi3OK {
            M::fmi3_set_float64(instance, &vr, 1, value.as_ptr(), 1);
        }
    }
}

/// Forgets `instance` (freed: its address may be reused).
pub fn forget<M: Exported>(instance: b::fmi3Instance) {
    if let Some(inst) = unsafe { (instance as *const Instance<M>).as_ref() } {
        take_reset::<M>(inst.context());
        set_continuous_time::<M>(inst.context(), false);
    }
}

/// Whether the instance owning `context` was reset since the last call.
pub fn take_reset<M: UserModel>(context: &dyn Context<M>) -> bool {
    let key = context_key(context);
    let mut resets = RESETS.lock().unwrap_or_else(|e| e.into_inner());
    let before = resets.len();
    resets.retain(|k| *k != key);
    resets.len() != before
}

/// Generates one guarded C function per entry.
#[doc(hidden)]
#[macro_export]
macro_rules! __mre_fmi_fns {
    ($ty:ty; $( $name:literal fn $f:ident($inst:ident : $it:ty $(, $arg:ident : $at:ty)* $(,)?) => $call:expr; )*) => {
        $(
            #[unsafe(export_name = $name)]
            #[allow(clippy::too_many_arguments, clippy::missing_safety_doc)]
            pub unsafe extern "C" fn $f($inst: $it $(, $arg: $at)*) -> $crate::export::b::fmi3Status {
                $crate::export::guard::<$ty>($inst, $name, || {
                    #[allow(unused_unsafe)]
                    unsafe { $call }
                })
            }
        )*
    };
}

/// Getters (guarded) and setters (guarded, inputs and parameters only) of one type.
#[doc(hidden)]
#[macro_export]
macro_rules! __mre_fmi_getset {
    ($ty:ty; $( $get:literal $gf:ident, $set:literal $sf:ident: $t:ty; )*) => {
        $(
            $crate::__mre_fmi_fns! { $ty;
                $get fn $gf(instance: $crate::export::b::fmi3Instance, vrs: *const $crate::export::b::fmi3ValueReference,
                    n_vrs: usize, values: *mut $t, n_values: usize)
                    => <$ty as ::fmi_export::fmi3::Fmi3Common>::$gf(instance, vrs, n_vrs, values, n_values);
                $set fn $sf(instance: $crate::export::b::fmi3Instance, vrs: *const $crate::export::b::fmi3ValueReference,
                    n_vrs: usize, values: *const $t, n_values: usize)
                    => {
                        static SETTABLE: ::std::sync::OnceLock<Vec<u32>> = ::std::sync::OnceLock::new();
                        match $crate::export::check_settable::<$ty>(&SETTABLE, instance, $set, vrs, n_vrs) {
                            Ok(()) => <$ty as ::fmi_export::fmi3::Fmi3Common>::$sf(instance, vrs, n_vrs, values, n_values),
                            Err(status) => status,
                        }
                    };
            }
        )*
    };
}

/// The FMI 3.0 C API of `$ty` (see the module docs).
#[macro_export]
macro_rules! export_fmu {
    ($ty:ty) => {
        use $crate::export::b as fmi3b;

        #[unsafe(export_name = "fmi3GetVersion")]
        pub extern "C" fn fmi3_get_version() -> *const ::std::os::raw::c_char {
            fmi3b::fmi3Version.as_ptr() as *const _
        }

        #[unsafe(export_name = "fmi3InstantiateModelExchange")]
        #[allow(clippy::missing_safety_doc)]
        pub unsafe extern "C" fn fmi3_instantiate_model_exchange(
            name: fmi3b::fmi3String,
            token: fmi3b::fmi3String,
            resources: fmi3b::fmi3String,
            visible: fmi3b::fmi3Boolean,
            logging_on: fmi3b::fmi3Boolean,
            environment: fmi3b::fmi3InstanceEnvironment,
            log_message: fmi3b::fmi3LogMessageCallback,
        ) -> fmi3b::fmi3Instance {
            ::std::panic::catch_unwind(|| unsafe {
                <$ty as ::fmi_export::fmi3::Fmi3Common>::fmi3_instantiate_model_exchange(
                    name, token, resources, visible, logging_on, environment, log_message,
                )
            })
            .unwrap_or(::std::ptr::null_mut())
        }

        #[unsafe(export_name = "fmi3InstantiateCoSimulation")]
        #[allow(clippy::too_many_arguments, clippy::missing_safety_doc)]
        pub unsafe extern "C" fn fmi3_instantiate_co_simulation(
            name: fmi3b::fmi3String,
            token: fmi3b::fmi3String,
            resources: fmi3b::fmi3String,
            visible: fmi3b::fmi3Boolean,
            logging_on: fmi3b::fmi3Boolean,
            event_mode_used: fmi3b::fmi3Boolean,
            early_return_allowed: fmi3b::fmi3Boolean,
            required: *const fmi3b::fmi3ValueReference,
            n_required: usize,
            environment: fmi3b::fmi3InstanceEnvironment,
            log_message: fmi3b::fmi3LogMessageCallback,
            intermediate_update: fmi3b::fmi3IntermediateUpdateCallback,
        ) -> fmi3b::fmi3Instance {
            ::std::panic::catch_unwind(|| unsafe {
                <$ty as ::fmi_export::fmi3::Fmi3Common>::fmi3_instantiate_co_simulation(
                    name,
                    token,
                    resources,
                    visible,
                    logging_on,
                    event_mode_used,
                    early_return_allowed,
                    required,
                    n_required,
                    environment,
                    log_message,
                    intermediate_update,
                )
            })
            .unwrap_or(::std::ptr::null_mut())
        }

        // Scheduled Execution is not offered (the XML has no such element);
        // fmi-export 0.3 would panic here.
        #[unsafe(export_name = "fmi3InstantiateScheduledExecution")]
        #[allow(clippy::too_many_arguments)]
        pub extern "C" fn fmi3_instantiate_scheduled_execution(
            _name: fmi3b::fmi3String,
            _token: fmi3b::fmi3String,
            _resources: fmi3b::fmi3String,
            _visible: fmi3b::fmi3Boolean,
            _logging_on: fmi3b::fmi3Boolean,
            _environment: fmi3b::fmi3InstanceEnvironment,
            _log_message: fmi3b::fmi3LogMessageCallback,
            _clock_update: fmi3b::fmi3ClockUpdateCallback,
            _lock_preemption: fmi3b::fmi3LockPreemptionCallback,
            _unlock_preemption: fmi3b::fmi3UnlockPreemptionCallback,
        ) -> fmi3b::fmi3Instance {
            ::std::ptr::null_mut()
        }

        #[unsafe(export_name = "fmi3FreeInstance")]
        #[allow(clippy::missing_safety_doc)]
        pub unsafe extern "C" fn fmi3_free_instance(instance: fmi3b::fmi3Instance) {
            let _ = ::std::panic::catch_unwind(|| unsafe {
                $crate::export::forget::<$ty>(instance);
                <$ty as ::fmi_export::fmi3::Fmi3Common>::fmi3_free_instance(instance)
            });
        }

        $crate::__mre_fmi_getset! { $ty;
            "fmi3GetFloat32" fmi3_get_float32, "fmi3SetFloat32" fmi3_set_float32: fmi3b::fmi3Float32;
            "fmi3GetInt64" fmi3_get_int64, "fmi3SetInt64" fmi3_set_int64: fmi3b::fmi3Int64;
            "fmi3GetInt32" fmi3_get_int32, "fmi3SetInt32" fmi3_set_int32: fmi3b::fmi3Int32;
            "fmi3GetInt16" fmi3_get_int16, "fmi3SetInt16" fmi3_set_int16: fmi3b::fmi3Int16;
            "fmi3GetInt8" fmi3_get_int8, "fmi3SetInt8" fmi3_set_int8: fmi3b::fmi3Int8;
            "fmi3GetUInt64" fmi3_get_u_int64, "fmi3SetUInt64" fmi3_set_u_int64: fmi3b::fmi3UInt64;
            "fmi3GetUInt32" fmi3_get_u_int32, "fmi3SetUInt32" fmi3_set_u_int32: fmi3b::fmi3UInt32;
            "fmi3GetUInt16" fmi3_get_u_int16, "fmi3SetUInt16" fmi3_set_u_int16: fmi3b::fmi3UInt16;
            "fmi3GetUInt8" fmi3_get_u_int8, "fmi3SetUInt8" fmi3_set_u_int8: fmi3b::fmi3UInt8;
            "fmi3GetBoolean" fmi3_get_boolean, "fmi3SetBoolean" fmi3_set_boolean: fmi3b::fmi3Boolean;
            "fmi3GetString" fmi3_get_string, "fmi3SetString" fmi3_set_string: fmi3b::fmi3String;
        }

        $crate::__mre_fmi_fns! { $ty;
            "fmi3GetFloat64" fn fmi3_get_float64(instance: fmi3b::fmi3Instance, vrs: *const fmi3b::fmi3ValueReference,
                n_vrs: usize, values: *mut fmi3b::fmi3Float64, n_values: usize)
                => <$ty as ::fmi_export::fmi3::Fmi3Common>::fmi3_get_float64(instance, vrs, n_vrs, values, n_values);
            // Inputs and parameters only; an input out of its declared range warns.
            "fmi3SetFloat64" fn fmi3_set_float64(instance: fmi3b::fmi3Instance, vrs: *const fmi3b::fmi3ValueReference,
                n_vrs: usize, values: *const fmi3b::fmi3Float64, n_values: usize)
                => {
                    static SETTABLE: ::std::sync::OnceLock<Vec<u32>> = ::std::sync::OnceLock::new();
                    match $crate::export::check_settable::<$ty>(&SETTABLE, instance, "fmi3SetFloat64", vrs, n_vrs) {
                        Ok(()) => {
                            let status = <$ty as ::fmi_export::fmi3::Fmi3Common>::fmi3_set_float64(
                                instance, vrs, n_vrs, values, n_values);
                            $crate::export::check_ranges::<$ty>(instance, vrs, values, n_vrs.min(n_values), status)
                        }
                        Err(status) => status,
                    }
                };
            "fmi3SetDebugLogging" fn fmi3_set_debug_logging(instance: fmi3b::fmi3Instance, on: fmi3b::fmi3Boolean,
                n: usize, categories: *const fmi3b::fmi3String)
                => <$ty as ::fmi_export::fmi3::Fmi3Common>::fmi3_set_debug_logging(instance, on, n, categories);
            "fmi3EnterInitializationMode" fn fmi3_enter_initialization_mode(instance: fmi3b::fmi3Instance,
                tolerance_defined: fmi3b::fmi3Boolean, tolerance: fmi3b::fmi3Float64, start: fmi3b::fmi3Float64,
                stop_defined: fmi3b::fmi3Boolean, stop: fmi3b::fmi3Float64)
                => <$ty as ::fmi_export::fmi3::Fmi3Common>::fmi3_enter_initialization_mode(
                    instance, tolerance_defined, tolerance, start, stop_defined, stop);
            "fmi3ExitInitializationMode" fn fmi3_exit_initialization_mode(instance: fmi3b::fmi3Instance)
                => <$ty as ::fmi_export::fmi3::Fmi3Common>::fmi3_exit_initialization_mode(instance);
            "fmi3EnterEventMode" fn fmi3_enter_event_mode(instance: fmi3b::fmi3Instance) => {
                $crate::export::note_continuous_time::<$ty>(instance, false);
                <$ty as ::fmi_export::fmi3::Fmi3Common>::fmi3_enter_event_mode(instance)
            };
            "fmi3Terminate" fn fmi3_terminate(instance: fmi3b::fmi3Instance)
                => <$ty as ::fmi_export::fmi3::Fmi3Common>::fmi3_terminate(instance);
            "fmi3Reset" fn fmi3_reset(instance: fmi3b::fmi3Instance) => {
                $crate::export::note_continuous_time::<$ty>(instance, false);
                let status = <$ty as ::fmi_export::fmi3::Fmi3Common>::fmi3_reset(instance);
                $crate::export::note_reset::<$ty>(instance);
                $crate::export::mark_stale::<$ty>(instance);
                status
            };
            "fmi3GetBinary" fn fmi3_get_binary(instance: fmi3b::fmi3Instance, vrs: *const fmi3b::fmi3ValueReference,
                n_vrs: usize, sizes: *mut usize, values: *mut *mut fmi3b::fmi3Byte, n_values: usize)
                => <$ty as ::fmi_export::fmi3::Fmi3Common>::fmi3_get_binary(instance, vrs, n_vrs, sizes, values, n_values);
            "fmi3SetBinary" fn fmi3_set_binary(instance: fmi3b::fmi3Instance, vrs: *const fmi3b::fmi3ValueReference,
                n_vrs: usize, sizes: *const usize, values: *const *const fmi3b::fmi3Byte, n_values: usize)
                => {
                    static SETTABLE: ::std::sync::OnceLock<Vec<u32>> = ::std::sync::OnceLock::new();
                    match $crate::export::check_settable::<$ty>(&SETTABLE, instance, "fmi3SetBinary", vrs, n_vrs) {
                        Ok(()) => <$ty as ::fmi_export::fmi3::Fmi3Common>::fmi3_set_binary(
                            instance, vrs, n_vrs, sizes, values, n_values),
                        Err(status) => status,
                    }
                };
            "fmi3GetClock" fn fmi3_get_clock(instance: fmi3b::fmi3Instance, _vrs: *const fmi3b::fmi3ValueReference,
                _n: usize, _values: *mut fmi3b::fmi3Clock)
                => $crate::export::unsupported::<$ty>(instance, "fmi3GetClock");
            "fmi3SetClock" fn fmi3_set_clock(instance: fmi3b::fmi3Instance, _vrs: *const fmi3b::fmi3ValueReference,
                _n: usize, _values: *const fmi3b::fmi3Clock)
                => $crate::export::unsupported::<$ty>(instance, "fmi3SetClock");
            "fmi3GetNumberOfVariableDependencies" fn fmi3_get_number_of_variable_dependencies(
                instance: fmi3b::fmi3Instance, vr: fmi3b::fmi3ValueReference, n: *mut usize)
                => match $crate::export::dependencies_of::<$ty>(instance, vr) {
                    Ok(deps) if !n.is_null() => {
                        unsafe { *n = deps.len() };
                        fmi3b::fmi3Status_fmi3OK
                    }
                    Ok(_) => fmi3b::fmi3Status_fmi3Error,
                    Err(status) => status,
                };
            "fmi3GetVariableDependencies" fn fmi3_get_variable_dependencies(instance: fmi3b::fmi3Instance,
                dependent: fmi3b::fmi3ValueReference, element_of_dependent: *mut usize,
                independents: *mut fmi3b::fmi3ValueReference, element_of_independents: *mut usize,
                kinds: *mut fmi3b::fmi3DependencyKind, n: usize)
                => match $crate::export::dependencies_of::<$ty>(instance, dependent) {
                    Ok(deps) if deps.len() <= n => {
                        for (k, vr) in deps.iter().enumerate() {
                            // Scalars: element index 0; the damper's force is a nonlinear function.
                            unsafe {
                                *element_of_dependent.add(k) = 0;
                                *independents.add(k) = *vr;
                                *element_of_independents.add(k) = 0;
                                *kinds.add(k) = fmi3b::fmi3DependencyKind_fmi3Dependent;
                            }
                        }
                        fmi3b::fmi3Status_fmi3OK
                    }
                    Ok(deps) => {
                        $crate::export::log_error::<$ty>(instance, format_args!(
                            "fmi3GetVariableDependencies: {} dependencies, room for {n}", deps.len()));
                        fmi3b::fmi3Status_fmi3Error
                    }
                    Err(status) => status,
                };
            "fmi3GetFMUState" fn fmi3_get_fmu_state(instance: fmi3b::fmi3Instance, _state: *mut fmi3b::fmi3FMUState)
                => $crate::export::unsupported::<$ty>(instance, "fmi3GetFMUState");
            "fmi3SetFMUState" fn fmi3_set_fmu_state(instance: fmi3b::fmi3Instance, _state: fmi3b::fmi3FMUState)
                => $crate::export::unsupported::<$ty>(instance, "fmi3SetFMUState");
            "fmi3FreeFMUState" fn fmi3_free_fmu_state(instance: fmi3b::fmi3Instance, state: *mut fmi3b::fmi3FMUState)
                => $crate::export::free_fmu_state::<$ty>(instance, state);
            "fmi3SerializedFMUStateSize" fn fmi3_serialized_fmu_state_size(instance: fmi3b::fmi3Instance,
                _state: fmi3b::fmi3FMUState, _size: *mut usize)
                => $crate::export::unsupported::<$ty>(instance, "fmi3SerializedFMUStateSize");
            "fmi3SerializeFMUState" fn fmi3_serialize_fmu_state(instance: fmi3b::fmi3Instance,
                _state: fmi3b::fmi3FMUState, _bytes: *mut fmi3b::fmi3Byte, _size: usize)
                => $crate::export::unsupported::<$ty>(instance, "fmi3SerializeFMUState");
            "fmi3DeserializeFMUState" fn fmi3_deserialize_fmu_state(instance: fmi3b::fmi3Instance,
                _bytes: *const fmi3b::fmi3Byte, _size: usize, _state: *mut fmi3b::fmi3FMUState)
                => $crate::export::unsupported::<$ty>(instance, "fmi3DeserializeFMUState");
            "fmi3GetDirectionalDerivative" fn fmi3_get_directional_derivative(instance: fmi3b::fmi3Instance,
                _unknowns: *const fmi3b::fmi3ValueReference, _n_unknowns: usize,
                _knowns: *const fmi3b::fmi3ValueReference, _n_knowns: usize,
                _seed: *const fmi3b::fmi3Float64, _n_seed: usize,
                _sensitivity: *mut fmi3b::fmi3Float64, _n_sensitivity: usize)
                => $crate::export::unsupported::<$ty>(instance, "fmi3GetDirectionalDerivative");
            "fmi3GetAdjointDerivative" fn fmi3_get_adjoint_derivative(instance: fmi3b::fmi3Instance,
                _unknowns: *const fmi3b::fmi3ValueReference, _n_unknowns: usize,
                _knowns: *const fmi3b::fmi3ValueReference, _n_knowns: usize,
                _seed: *const fmi3b::fmi3Float64, _n_seed: usize,
                _sensitivity: *mut fmi3b::fmi3Float64, _n_sensitivity: usize)
                => $crate::export::unsupported::<$ty>(instance, "fmi3GetAdjointDerivative");
            "fmi3EnterConfigurationMode" fn fmi3_enter_configuration_mode(instance: fmi3b::fmi3Instance)
                => <$ty as ::fmi_export::fmi3::Fmi3Common>::fmi3_enter_configuration_mode(instance);
            "fmi3ExitConfigurationMode" fn fmi3_exit_configuration_mode(instance: fmi3b::fmi3Instance)
                => <$ty as ::fmi_export::fmi3::Fmi3Common>::fmi3_exit_configuration_mode(instance);
            "fmi3GetIntervalDecimal" fn fmi3_get_interval_decimal(instance: fmi3b::fmi3Instance,
                _vrs: *const fmi3b::fmi3ValueReference, _n: usize, _intervals: *mut fmi3b::fmi3Float64,
                _qualifiers: *mut fmi3b::fmi3IntervalQualifier)
                => $crate::export::unsupported::<$ty>(instance, "fmi3GetIntervalDecimal");
            "fmi3GetIntervalFraction" fn fmi3_get_interval_fraction(instance: fmi3b::fmi3Instance,
                _vrs: *const fmi3b::fmi3ValueReference, _n: usize, _counters: *mut fmi3b::fmi3UInt64,
                _resolutions: *mut fmi3b::fmi3UInt64, _qualifiers: *mut fmi3b::fmi3IntervalQualifier)
                => $crate::export::unsupported::<$ty>(instance, "fmi3GetIntervalFraction");
            "fmi3GetShiftDecimal" fn fmi3_get_shift_decimal(instance: fmi3b::fmi3Instance,
                _vrs: *const fmi3b::fmi3ValueReference, _n: usize, _shifts: *mut fmi3b::fmi3Float64)
                => $crate::export::unsupported::<$ty>(instance, "fmi3GetShiftDecimal");
            "fmi3GetShiftFraction" fn fmi3_get_shift_fraction(instance: fmi3b::fmi3Instance,
                _vrs: *const fmi3b::fmi3ValueReference, _n: usize, _counters: *mut fmi3b::fmi3UInt64,
                _resolutions: *mut fmi3b::fmi3UInt64)
                => $crate::export::unsupported::<$ty>(instance, "fmi3GetShiftFraction");
            "fmi3SetIntervalDecimal" fn fmi3_set_interval_decimal(instance: fmi3b::fmi3Instance,
                _vrs: *const fmi3b::fmi3ValueReference, _n: usize, _intervals: *const fmi3b::fmi3Float64)
                => $crate::export::unsupported::<$ty>(instance, "fmi3SetIntervalDecimal");
            "fmi3SetIntervalFraction" fn fmi3_set_interval_fraction(instance: fmi3b::fmi3Instance,
                _vrs: *const fmi3b::fmi3ValueReference, _n: usize, _counters: *const fmi3b::fmi3UInt64,
                _resolutions: *const fmi3b::fmi3UInt64)
                => $crate::export::unsupported::<$ty>(instance, "fmi3SetIntervalFraction");
            "fmi3SetShiftDecimal" fn fmi3_set_shift_decimal(instance: fmi3b::fmi3Instance,
                _vrs: *const fmi3b::fmi3ValueReference, _n: usize, _shifts: *const fmi3b::fmi3Float64)
                => $crate::export::unsupported::<$ty>(instance, "fmi3SetShiftDecimal");
            "fmi3SetShiftFraction" fn fmi3_set_shift_fraction(instance: fmi3b::fmi3Instance,
                _vrs: *const fmi3b::fmi3ValueReference, _n: usize, _counters: *const fmi3b::fmi3UInt64,
                _resolutions: *const fmi3b::fmi3UInt64)
                => $crate::export::unsupported::<$ty>(instance, "fmi3SetShiftFraction");
            "fmi3EvaluateDiscreteStates" fn fmi3_evaluate_discrete_states(instance: fmi3b::fmi3Instance)
                => $crate::export::unsupported::<$ty>(instance, "fmi3EvaluateDiscreteStates");
            "fmi3UpdateDiscreteStates" fn fmi3_update_discrete_states(instance: fmi3b::fmi3Instance,
                need_update: *mut fmi3b::fmi3Boolean, terminate: *mut fmi3b::fmi3Boolean,
                nominals_changed: *mut fmi3b::fmi3Boolean, values_changed: *mut fmi3b::fmi3Boolean,
                next_defined: *mut fmi3b::fmi3Boolean, next: *mut fmi3b::fmi3Float64)
                => <$ty as ::fmi_export::fmi3::Fmi3Common>::fmi3_update_discrete_states(
                    instance, need_update, terminate, nominals_changed, values_changed, next_defined, next);
            "fmi3ActivateModelPartition" fn fmi3_activate_model_partition(instance: fmi3b::fmi3Instance,
                _clock: fmi3b::fmi3ValueReference, _time: fmi3b::fmi3Float64)
                => $crate::export::unsupported::<$ty>(instance, "fmi3ActivateModelPartition");

            // Model Exchange
            "fmi3EnterContinuousTimeMode" fn fmi3_enter_continuous_time_mode(instance: fmi3b::fmi3Instance) => {
                let status = <$ty as ::fmi_export::fmi3::Fmi3ModelExchange>::fmi3_enter_continuous_time_mode(instance);
                // The damper holds its branch from here to the next event.
                if status == fmi3b::fmi3Status_fmi3OK {
                    $crate::export::note_continuous_time::<$ty>(instance, true);
                }
                status
            };
            "fmi3CompletedIntegratorStep" fn fmi3_completed_integrator_step(instance: fmi3b::fmi3Instance,
                no_set_prior: fmi3b::fmi3Boolean, enter_event_mode: *mut fmi3b::fmi3Boolean,
                terminate: *mut fmi3b::fmi3Boolean)
                => <$ty as ::fmi_export::fmi3::Fmi3ModelExchange>::fmi3_completed_integrator_step(
                    instance, no_set_prior, enter_event_mode, terminate);
            "fmi3SetTime" fn fmi3_set_time(instance: fmi3b::fmi3Instance, time: fmi3b::fmi3Float64)
                => <$ty as ::fmi_export::fmi3::Fmi3ModelExchange>::fmi3_set_time(instance, time);
            "fmi3SetContinuousStates" fn fmi3_set_continuous_states(instance: fmi3b::fmi3Instance,
                states: *const fmi3b::fmi3Float64, n: usize)
                => <$ty as ::fmi_export::fmi3::Fmi3ModelExchange>::fmi3_set_continuous_states(instance, states, n);
            "fmi3GetContinuousStateDerivatives" fn fmi3_get_continuous_state_derivatives(
                instance: fmi3b::fmi3Instance, derivatives: *mut fmi3b::fmi3Float64, n: usize)
                => <$ty as ::fmi_export::fmi3::Fmi3ModelExchange>::fmi3_get_continuous_state_derivatives(
                    instance, derivatives, n);
            "fmi3GetEventIndicators" fn fmi3_get_event_indicators(instance: fmi3b::fmi3Instance,
                indicators: *mut fmi3b::fmi3Float64, n: usize)
                => <$ty as ::fmi_export::fmi3::Fmi3ModelExchange>::fmi3_get_event_indicators(instance, indicators, n);
            "fmi3GetContinuousStates" fn fmi3_get_continuous_states(instance: fmi3b::fmi3Instance,
                states: *mut fmi3b::fmi3Float64, n: usize)
                => <$ty as ::fmi_export::fmi3::Fmi3ModelExchange>::fmi3_get_continuous_states(instance, states, n);
            "fmi3GetNominalsOfContinuousStates" fn fmi3_get_nominals_of_continuous_states(
                instance: fmi3b::fmi3Instance, nominals: *mut fmi3b::fmi3Float64, n: usize)
                => <$ty as ::fmi_export::fmi3::Fmi3ModelExchange>::fmi3_get_nominals_of_continuous_states(
                    instance, nominals, n);
            "fmi3GetNumberOfEventIndicators" fn fmi3_get_number_of_event_indicators(instance: fmi3b::fmi3Instance,
                n: *mut usize)
                => <$ty as ::fmi_export::fmi3::Fmi3ModelExchange>::fmi3_get_number_of_event_indicators(instance, n);
            "fmi3GetNumberOfContinuousStates" fn fmi3_get_number_of_continuous_states(instance: fmi3b::fmi3Instance,
                n: *mut usize)
                => <$ty as ::fmi_export::fmi3::Fmi3ModelExchange>::fmi3_get_number_of_continuous_states(instance, n);

            // Co-Simulation
            "fmi3EnterStepMode" fn fmi3_enter_step_mode(instance: fmi3b::fmi3Instance)
                => <$ty as ::fmi_export::fmi3::Fmi3CoSimulation>::fmi3_enter_step_mode(instance);
            "fmi3GetOutputDerivatives" fn fmi3_get_output_derivatives(instance: fmi3b::fmi3Instance,
                vrs: *const fmi3b::fmi3ValueReference, n_vrs: usize, orders: *const fmi3b::fmi3Int32,
                values: *mut fmi3b::fmi3Float64, n_values: usize)
                => <$ty as ::fmi_export::fmi3::Fmi3CoSimulation>::fmi3_get_output_derivatives(
                    instance, vrs, n_vrs, orders, values, n_values);
            "fmi3DoStep" fn fmi3_do_step(instance: fmi3b::fmi3Instance, t: fmi3b::fmi3Float64,
                h: fmi3b::fmi3Float64, no_set_prior: fmi3b::fmi3Boolean, event_needed: *mut fmi3b::fmi3Boolean,
                terminate: *mut fmi3b::fmi3Boolean, early_return: *mut fmi3b::fmi3Boolean,
                last_time: *mut fmi3b::fmi3Float64)
                => match $crate::export::check_step::<$ty>(instance, t, h) {
                    Ok(()) => <$ty as ::fmi_export::fmi3::Fmi3CoSimulation>::fmi3_do_step(
                        instance, t, h, no_set_prior, event_needed, terminate, early_return, last_time),
                    Err(status) => status,
                };
        }
    };
}
