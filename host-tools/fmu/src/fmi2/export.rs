//! The FMI 2.0 C functions ([`export_fmi2!`](crate::export_fmi2)): each
//! checks its pointers, runs under `catch_unwind` (a panic becomes
//! `fmi2Error` and a log line, the instance goes to its error state) and
//! calls [`Instance`](super::Instance). The functions this FMU does not
//! implement (FMU state, directional derivatives, input and output
//! derivatives, the asynchronous Co-Simulation status calls, String and
//! Boolean variables, which it has none of) return `fmi2Error` and say so.
use super::{b2, Instance, Mode, Type, ERROR, OK};
use crate::export::Exported;
use fmi_export::fmi3::ModelGetSet;
use std::ffi::CStr;
use std::panic::{catch_unwind, AssertUnwindSafe};

/// Runs `call` on the instance behind `c`: `fmi2Error` for a null
/// component, and for a panic (logged; the instance is then in error).
///
/// # Safety
/// `c` is null or a component `fmi2Instantiate` of this library returned
/// for `M` and not yet freed.
pub unsafe fn with<M: Exported + ModelGetSet<M>>(
    c: b2::fmi2Component,
    function: &str,
    call: impl FnOnce(&mut Instance<M>) -> b2::fmi2Status,
) -> b2::fmi2Status {
    let p = c as *mut Instance<M>;
    if p.is_null() {
        return ERROR;
    }
    match catch_unwind(AssertUnwindSafe(|| call(unsafe { &mut *p }))) {
        Ok(status) => status,
        Err(payload) => {
            let why = crate::export::panic_message(payload.as_ref());
            // The closure's borrow ended with the unwind.
            let inst = unsafe { &mut *p };
            inst.mode = Mode::Error;
            inst.error(function, format_args!("failed inside the FMU: {why}"))
        }
    }
}

/// A call this FMU does not support: `fmi2Error`, said in the log.
///
/// # Safety
/// As [`with`].
pub unsafe fn unsupported<M: Exported + ModelGetSet<M>>(c: b2::fmi2Component, function: &str) -> b2::fmi2Status {
    unsafe {
        with::<M>(c, function, |inst| {
            inst.error(
                function,
                format_args!("not supported by this FMU (see its modelDescription.xml capabilities)"),
            )
        })
    }
}

/// A pointer and a count as a slice; `None` (an error) for null with `n > 0`.
///
/// # Safety
/// A non-null `p` points at `n` elements.
pub unsafe fn slice<'a, T>(p: *const T, n: usize) -> Option<&'a [T]> {
    if n == 0 {
        Some(&[])
    } else if p.is_null() {
        None
    } else {
        Some(unsafe { std::slice::from_raw_parts(p, n) })
    }
}

/// As [`slice`], writable.
///
/// # Safety
/// A non-null `p` points at `n` writable elements.
pub unsafe fn slice_mut<'a, T>(p: *mut T, n: usize) -> Option<&'a mut [T]> {
    if n == 0 {
        Some(&mut [])
    } else if p.is_null() {
        None
    } else {
        Some(unsafe { std::slice::from_raw_parts_mut(p, n) })
    }
}

/// `fmi2Instantiate`: null (after a log line when the importer gave a
/// logger) for a wrong GUID, an interface the model lacks, or no resources.
///
/// # Safety
/// The pointers are null or as FMI 2.0 defines them.
pub unsafe fn instantiate<M: Exported + ModelGetSet<M>>(
    name: b2::fmi2String,
    fmu_type: b2::fmi2Type,
    guid: b2::fmi2String,
    resource_location: b2::fmi2String,
    functions: *const b2::fmi2CallbackFunctions,
    logging_on: b2::fmi2Boolean,
) -> b2::fmi2Component {
    let text = |p: b2::fmi2String| (!p.is_null()).then(|| unsafe { CStr::from_ptr(p) }.to_string_lossy().into_owned());
    let callbacks = unsafe { functions.as_ref() };
    let (logger, environment) = callbacks.map_or((None, std::ptr::null_mut()), |f| (f.logger, f.componentEnvironment));
    let name = text(name).unwrap_or_else(|| M::KIND.stem().to_owned());
    let model_exchange = fmu_type == b2::fmi2Type_fmi2ModelExchange;
    let location = text(resource_location).unwrap_or_default();
    let resources = super::path_from_uri(&location).unwrap_or_default();
    let inst = Instance::<M>::new(&name, model_exchange, resources, logger, environment, logging_on != 0);
    let problem = if guid.is_null() || text(guid).as_deref() != Some(M::INSTANTIATION_TOKEN) {
        Some(format!(
            "GUID {:?} is not this FMU's {}",
            text(guid),
            M::INSTANTIATION_TOKEN
        ))
    } else if fmu_type != b2::fmi2Type_fmi2CoSimulation && !(model_exchange && M::SUPPORTS_MODEL_EXCHANGE) {
        Some(format!("fmuType {fmu_type} is not an interface this FMU provides"))
    } else if super::path_from_uri(&location).is_none() {
        Some(format!("fmuResourceLocation {location:?} is not a file: URI"))
    } else {
        None
    };
    match problem {
        Some(why) => {
            inst.error("fmi2Instantiate", format_args!("{why}"));
            std::ptr::null_mut()
        }
        None => Box::into_raw(Box::new(inst)) as b2::fmi2Component,
    }
}

/// `fmi2FreeInstance`.
///
/// # Safety
/// As [`with`]; `c` is not used afterwards.
pub unsafe fn free_instance<M: Exported + ModelGetSet<M>>(c: b2::fmi2Component) {
    if !c.is_null() {
        let inst = unsafe { Box::from_raw(c as *mut Instance<M>) };
        // A panic in a model's drop must not cross into the importer.
        let _ = catch_unwind(AssertUnwindSafe(move || drop(inst)));
    }
}

/// `fmi2GetReal` / `fmi2GetInteger`.
///
/// # Safety
/// As [`with`]; `vrs` and `values` hold `n` elements.
pub unsafe fn get<M: Exported + ModelGetSet<M>, T: Copy>(
    c: b2::fmi2Component,
    function: &'static str,
    ty: Type,
    vrs: *const b2::fmi2ValueReference,
    n: usize,
    values: *mut T,
    convert: fn(f64) -> T,
) -> b2::fmi2Status {
    unsafe {
        with::<M>(c, function, |inst| {
            let (Some(vrs), Some(values)) = (slice(vrs, n), slice_mut(values, n)) else {
                return inst.error(function, format_args!("null value references or values"));
            };
            inst.get(function, vrs, ty, |k, v| values[k] = convert(v))
        })
    }
}

/// `fmi2SetReal`.
///
/// # Safety
/// As [`with`]; `vrs` and `values` hold `n` elements.
pub unsafe fn set_real<M: Exported + ModelGetSet<M>>(
    c: b2::fmi2Component,
    vrs: *const b2::fmi2ValueReference,
    n: usize,
    values: *const b2::fmi2Real,
) -> b2::fmi2Status {
    unsafe {
        with::<M>(c, "fmi2SetReal", |inst| {
            let (Some(vrs), Some(values)) = (slice(vrs, n), slice(values, n)) else {
                return inst.error("fmi2SetReal", format_args!("null value references or values"));
            };
            inst.set_real(vrs, values)
        })
    }
}

/// Setters of types whose variables are all outputs or absent
/// (`fmi2SetInteger`, `fmi2SetBoolean`, `fmi2SetString`) and getters of
/// absent types: OK for no value reference, else `fmi2Error`.
///
/// # Safety
/// As [`with`].
pub unsafe fn none_settable<M: Exported + ModelGetSet<M>>(
    c: b2::fmi2Component,
    function: &str,
    n: usize,
) -> b2::fmi2Status {
    unsafe {
        with::<M>(c, function, |inst| {
            if n == 0 {
                OK
            } else {
                inst.error(
                    function,
                    format_args!("this FMU has no variable of this type that can be accessed so"),
                )
            }
        })
    }
}

/// The `fmi2*` functions for `$ty`, an [`Exported`] model.
#[macro_export]
macro_rules! export_fmi2 {
    ($ty:ty) => {
        #[allow(clippy::missing_safety_doc)]
        mod fmi2_functions {
            use $crate::fmi2::b2;
            use $crate::fmi2::export as x;
            use $crate::fmi2::Type;
            type M = $ty;

            #[unsafe(export_name = "fmi2GetTypesPlatform")]
            pub extern "C" fn fmi2_get_types_platform() -> *const ::std::os::raw::c_char {
                b2::fmi2TypesPlatform.as_ptr() as *const _
            }
            #[unsafe(export_name = "fmi2GetVersion")]
            pub extern "C" fn fmi2_get_version() -> *const ::std::os::raw::c_char {
                b2::fmi2Version.as_ptr() as *const _
            }
            #[unsafe(export_name = "fmi2Instantiate")]
            pub unsafe extern "C" fn fmi2_instantiate(
                name: b2::fmi2String,
                fmu_type: b2::fmi2Type,
                guid: b2::fmi2String,
                resources: b2::fmi2String,
                functions: *const b2::fmi2CallbackFunctions,
                _visible: b2::fmi2Boolean,
                logging_on: b2::fmi2Boolean,
            ) -> b2::fmi2Component {
                ::std::panic::catch_unwind(::std::panic::AssertUnwindSafe(|| unsafe {
                    x::instantiate::<M>(name, fmu_type, guid, resources, functions, logging_on)
                }))
                .unwrap_or(::std::ptr::null_mut())
            }
            #[unsafe(export_name = "fmi2FreeInstance")]
            pub unsafe extern "C" fn fmi2_free_instance(c: b2::fmi2Component) {
                unsafe { x::free_instance::<M>(c) }
            }
            #[unsafe(export_name = "fmi2SetDebugLogging")]
            pub unsafe extern "C" fn fmi2_set_debug_logging(
                c: b2::fmi2Component,
                on: b2::fmi2Boolean,
                _n: usize,
                _categories: *const b2::fmi2String,
            ) -> b2::fmi2Status {
                // One category (the models log under one): on or off for all.
                unsafe {
                    x::with::<M>(c, "fmi2SetDebugLogging", |i| {
                        <_ as ::fmi_export::fmi3::Context<M>>::set_logging(&mut i.ctx, Default::default(), on != 0);
                        b2::fmi2Status_fmi2OK
                    })
                }
            }
            #[unsafe(export_name = "fmi2SetupExperiment")]
            pub unsafe extern "C" fn fmi2_setup_experiment(
                c: b2::fmi2Component,
                _tol_defined: b2::fmi2Boolean,
                _tol: b2::fmi2Real,
                start: b2::fmi2Real,
                stop_defined: b2::fmi2Boolean,
                stop: b2::fmi2Real,
            ) -> b2::fmi2Status {
                unsafe {
                    x::with::<M>(c, "fmi2SetupExperiment", |i| {
                        i.setup_experiment(start, (stop_defined != 0).then_some(stop))
                    })
                }
            }
            #[unsafe(export_name = "fmi2EnterInitializationMode")]
            pub unsafe extern "C" fn fmi2_enter_initialization_mode(c: b2::fmi2Component) -> b2::fmi2Status {
                unsafe {
                    x::with::<M>(c, "fmi2EnterInitializationMode", |i| {
                        i.enter_initialization_mode()
                    })
                }
            }
            #[unsafe(export_name = "fmi2ExitInitializationMode")]
            pub unsafe extern "C" fn fmi2_exit_initialization_mode(c: b2::fmi2Component) -> b2::fmi2Status {
                unsafe { x::with::<M>(c, "fmi2ExitInitializationMode", |i| i.exit_initialization_mode()) }
            }
            #[unsafe(export_name = "fmi2Terminate")]
            pub unsafe extern "C" fn fmi2_terminate(c: b2::fmi2Component) -> b2::fmi2Status {
                unsafe { x::with::<M>(c, "fmi2Terminate", |i| i.terminate()) }
            }
            #[unsafe(export_name = "fmi2Reset")]
            pub unsafe extern "C" fn fmi2_reset(c: b2::fmi2Component) -> b2::fmi2Status {
                unsafe { x::with::<M>(c, "fmi2Reset", |i| i.reset()) }
            }
            #[unsafe(export_name = "fmi2GetReal")]
            pub unsafe extern "C" fn fmi2_get_real(
                c: b2::fmi2Component,
                vrs: *const b2::fmi2ValueReference,
                n: usize,
                values: *mut b2::fmi2Real,
            ) -> b2::fmi2Status {
                unsafe { x::get::<M, f64>(c, "fmi2GetReal", Type::Real, vrs, n, values, |v| v) }
            }
            #[unsafe(export_name = "fmi2GetInteger")]
            pub unsafe extern "C" fn fmi2_get_integer(
                c: b2::fmi2Component,
                vrs: *const b2::fmi2ValueReference,
                n: usize,
                values: *mut b2::fmi2Integer,
            ) -> b2::fmi2Status {
                // FMI 2.0 has no unsigned type: the 3.0 UInt32 flags as Integer (bit 31 is unused).
                unsafe {
                    x::get::<M, b2::fmi2Integer>(c, "fmi2GetInteger", Type::Integer, vrs, n, values, |v| {
                        v as u32 as b2::fmi2Integer
                    })
                }
            }
            #[unsafe(export_name = "fmi2GetBoolean")]
            pub unsafe extern "C" fn fmi2_get_boolean(
                c: b2::fmi2Component,
                _vrs: *const b2::fmi2ValueReference,
                n: usize,
                _values: *mut b2::fmi2Boolean,
            ) -> b2::fmi2Status {
                unsafe { x::none_settable::<M>(c, "fmi2GetBoolean", n) }
            }
            #[unsafe(export_name = "fmi2GetString")]
            pub unsafe extern "C" fn fmi2_get_string(
                c: b2::fmi2Component,
                _vrs: *const b2::fmi2ValueReference,
                n: usize,
                _values: *mut b2::fmi2String,
            ) -> b2::fmi2Status {
                unsafe { x::none_settable::<M>(c, "fmi2GetString", n) }
            }
            #[unsafe(export_name = "fmi2SetReal")]
            pub unsafe extern "C" fn fmi2_set_real(
                c: b2::fmi2Component,
                vrs: *const b2::fmi2ValueReference,
                n: usize,
                values: *const b2::fmi2Real,
            ) -> b2::fmi2Status {
                unsafe { x::set_real::<M>(c, vrs, n, values) }
            }
            #[unsafe(export_name = "fmi2SetInteger")]
            pub unsafe extern "C" fn fmi2_set_integer(
                c: b2::fmi2Component,
                _vrs: *const b2::fmi2ValueReference,
                n: usize,
                _values: *const b2::fmi2Integer,
            ) -> b2::fmi2Status {
                unsafe { x::none_settable::<M>(c, "fmi2SetInteger", n) }
            }
            #[unsafe(export_name = "fmi2SetBoolean")]
            pub unsafe extern "C" fn fmi2_set_boolean(
                c: b2::fmi2Component,
                _vrs: *const b2::fmi2ValueReference,
                n: usize,
                _values: *const b2::fmi2Boolean,
            ) -> b2::fmi2Status {
                unsafe { x::none_settable::<M>(c, "fmi2SetBoolean", n) }
            }
            #[unsafe(export_name = "fmi2SetString")]
            pub unsafe extern "C" fn fmi2_set_string(
                c: b2::fmi2Component,
                _vrs: *const b2::fmi2ValueReference,
                n: usize,
                _values: *const b2::fmi2String,
            ) -> b2::fmi2Status {
                unsafe { x::none_settable::<M>(c, "fmi2SetString", n) }
            }
            #[unsafe(export_name = "fmi2GetFMUstate")]
            pub unsafe extern "C" fn fmi2_get_fmu_state(
                c: b2::fmi2Component,
                _s: *mut b2::fmi2FMUstate,
            ) -> b2::fmi2Status {
                unsafe { x::unsupported::<M>(c, "fmi2GetFMUstate") }
            }
            #[unsafe(export_name = "fmi2SetFMUstate")]
            pub unsafe extern "C" fn fmi2_set_fmu_state(c: b2::fmi2Component, _s: b2::fmi2FMUstate) -> b2::fmi2Status {
                unsafe { x::unsupported::<M>(c, "fmi2SetFMUstate") }
            }
            #[unsafe(export_name = "fmi2FreeFMUstate")]
            pub unsafe extern "C" fn fmi2_free_fmu_state(
                c: b2::fmi2Component,
                s: *mut b2::fmi2FMUstate,
            ) -> b2::fmi2Status {
                // Freeing no state is a no-op; this FMU hands out none.
                if s.is_null() || unsafe { (*s).is_null() } {
                    return b2::fmi2Status_fmi2OK;
                }
                unsafe { x::unsupported::<M>(c, "fmi2FreeFMUstate") }
            }
            #[unsafe(export_name = "fmi2SerializedFMUstateSize")]
            pub unsafe extern "C" fn fmi2_serialized_fmu_state_size(
                c: b2::fmi2Component,
                _s: b2::fmi2FMUstate,
                _size: *mut usize,
            ) -> b2::fmi2Status {
                unsafe { x::unsupported::<M>(c, "fmi2SerializedFMUstateSize") }
            }
            #[unsafe(export_name = "fmi2SerializeFMUstate")]
            pub unsafe extern "C" fn fmi2_serialize_fmu_state(
                c: b2::fmi2Component,
                _s: b2::fmi2FMUstate,
                _bytes: *mut b2::fmi2Byte,
                _size: usize,
            ) -> b2::fmi2Status {
                unsafe { x::unsupported::<M>(c, "fmi2SerializeFMUstate") }
            }
            #[unsafe(export_name = "fmi2DeSerializeFMUstate")]
            pub unsafe extern "C" fn fmi2_deserialize_fmu_state(
                c: b2::fmi2Component,
                _bytes: *const b2::fmi2Byte,
                _size: usize,
                _s: *mut b2::fmi2FMUstate,
            ) -> b2::fmi2Status {
                unsafe { x::unsupported::<M>(c, "fmi2DeSerializeFMUstate") }
            }
            #[unsafe(export_name = "fmi2GetDirectionalDerivative")]
            pub unsafe extern "C" fn fmi2_get_directional_derivative(
                c: b2::fmi2Component,
                _u: *const b2::fmi2ValueReference,
                _nu: usize,
                _z: *const b2::fmi2ValueReference,
                _nz: usize,
                _dv: *const b2::fmi2Real,
                _dz: *mut b2::fmi2Real,
            ) -> b2::fmi2Status {
                unsafe { x::unsupported::<M>(c, "fmi2GetDirectionalDerivative") }
            }

            // Model Exchange
            #[unsafe(export_name = "fmi2EnterEventMode")]
            pub unsafe extern "C" fn fmi2_enter_event_mode(c: b2::fmi2Component) -> b2::fmi2Status {
                unsafe { x::with::<M>(c, "fmi2EnterEventMode", |i| i.enter_event_mode()) }
            }
            #[unsafe(export_name = "fmi2NewDiscreteStates")]
            pub unsafe extern "C" fn fmi2_new_discrete_states(
                c: b2::fmi2Component,
                info: *mut b2::fmi2EventInfo,
            ) -> b2::fmi2Status {
                unsafe {
                    x::with::<M>(c, "fmi2NewDiscreteStates", |i| match info.as_mut() {
                        Some(info) => i.new_discrete_states(info),
                        None => i.error("fmi2NewDiscreteStates", format_args!("null fmi2EventInfo")),
                    })
                }
            }
            #[unsafe(export_name = "fmi2EnterContinuousTimeMode")]
            pub unsafe extern "C" fn fmi2_enter_continuous_time_mode(c: b2::fmi2Component) -> b2::fmi2Status {
                unsafe {
                    x::with::<M>(c, "fmi2EnterContinuousTimeMode", |i| {
                        i.enter_continuous_time_mode()
                    })
                }
            }
            #[unsafe(export_name = "fmi2CompletedIntegratorStep")]
            pub unsafe extern "C" fn fmi2_completed_integrator_step(
                c: b2::fmi2Component,
                _no_set_prior: b2::fmi2Boolean,
                enter_event_mode: *mut b2::fmi2Boolean,
                terminate: *mut b2::fmi2Boolean,
            ) -> b2::fmi2Status {
                unsafe {
                    x::with::<M>(c, "fmi2CompletedIntegratorStep", |i| {
                        if let Err(s) = i.expect_me("fmi2CompletedIntegratorStep") {
                            return s;
                        }
                        match (enter_event_mode.as_mut(), terminate.as_mut()) {
                            (Some(e), Some(t)) => {
                                // No step events: the branch switch is a state event.
                                *e = 0;
                                *t = 0;
                                b2::fmi2Status_fmi2OK
                            }
                            _ => i.error(
                                "fmi2CompletedIntegratorStep",
                                format_args!("null output pointers"),
                            ),
                        }
                    })
                }
            }
            #[unsafe(export_name = "fmi2SetTime")]
            pub unsafe extern "C" fn fmi2_set_time(c: b2::fmi2Component, time: b2::fmi2Real) -> b2::fmi2Status {
                unsafe { x::with::<M>(c, "fmi2SetTime", |i| i.set_time(time)) }
            }
            #[unsafe(export_name = "fmi2SetContinuousStates")]
            pub unsafe extern "C" fn fmi2_set_continuous_states(
                c: b2::fmi2Component,
                _x: *const b2::fmi2Real,
                n: usize,
            ) -> b2::fmi2Status {
                unsafe {
                    x::with::<M>(c, "fmi2SetContinuousStates", |i| {
                        i.no_states("fmi2SetContinuousStates", n)
                    })
                }
            }
            #[unsafe(export_name = "fmi2GetDerivatives")]
            pub unsafe extern "C" fn fmi2_get_derivatives(
                c: b2::fmi2Component,
                _dx: *mut b2::fmi2Real,
                n: usize,
            ) -> b2::fmi2Status {
                unsafe { x::with::<M>(c, "fmi2GetDerivatives", |i| i.no_states("fmi2GetDerivatives", n)) }
            }
            #[unsafe(export_name = "fmi2GetEventIndicators")]
            pub unsafe extern "C" fn fmi2_get_event_indicators(
                c: b2::fmi2Component,
                z: *mut b2::fmi2Real,
                n: usize,
            ) -> b2::fmi2Status {
                unsafe {
                    x::with::<M>(c, "fmi2GetEventIndicators", |i| match x::slice_mut(z, n) {
                        Some(z) => i.get_event_indicators(z),
                        None => i.error("fmi2GetEventIndicators", format_args!("null indicators")),
                    })
                }
            }
            #[unsafe(export_name = "fmi2GetContinuousStates")]
            pub unsafe extern "C" fn fmi2_get_continuous_states(
                c: b2::fmi2Component,
                _x: *mut b2::fmi2Real,
                n: usize,
            ) -> b2::fmi2Status {
                unsafe {
                    x::with::<M>(c, "fmi2GetContinuousStates", |i| {
                        i.no_states("fmi2GetContinuousStates", n)
                    })
                }
            }
            #[unsafe(export_name = "fmi2GetNominalsOfContinuousStates")]
            pub unsafe extern "C" fn fmi2_get_nominals_of_continuous_states(
                c: b2::fmi2Component,
                _x: *mut b2::fmi2Real,
                n: usize,
            ) -> b2::fmi2Status {
                unsafe {
                    x::with::<M>(c, "fmi2GetNominalsOfContinuousStates", |i| {
                        i.no_states("fmi2GetNominalsOfContinuousStates", n)
                    })
                }
            }

            // Co-Simulation
            #[unsafe(export_name = "fmi2DoStep")]
            pub unsafe extern "C" fn fmi2_do_step(
                c: b2::fmi2Component,
                t: b2::fmi2Real,
                h: b2::fmi2Real,
                no_set_prior: b2::fmi2Boolean,
            ) -> b2::fmi2Status {
                unsafe { x::with::<M>(c, "fmi2DoStep", |i| i.do_step(t, h, no_set_prior != 0)) }
            }
            #[unsafe(export_name = "fmi2SetRealInputDerivatives")]
            pub unsafe extern "C" fn fmi2_set_real_input_derivatives(
                c: b2::fmi2Component,
                _vrs: *const b2::fmi2ValueReference,
                _n: usize,
                _orders: *const b2::fmi2Integer,
                _values: *const b2::fmi2Real,
            ) -> b2::fmi2Status {
                unsafe { x::unsupported::<M>(c, "fmi2SetRealInputDerivatives") }
            }
            #[unsafe(export_name = "fmi2GetRealOutputDerivatives")]
            pub unsafe extern "C" fn fmi2_get_real_output_derivatives(
                c: b2::fmi2Component,
                _vrs: *const b2::fmi2ValueReference,
                _n: usize,
                _orders: *const b2::fmi2Integer,
                _values: *mut b2::fmi2Real,
            ) -> b2::fmi2Status {
                unsafe { x::unsupported::<M>(c, "fmi2GetRealOutputDerivatives") }
            }
            #[unsafe(export_name = "fmi2CancelStep")]
            pub unsafe extern "C" fn fmi2_cancel_step(c: b2::fmi2Component) -> b2::fmi2Status {
                unsafe { x::unsupported::<M>(c, "fmi2CancelStep") }
            }
            #[unsafe(export_name = "fmi2GetStatus")]
            pub unsafe extern "C" fn fmi2_get_status(
                c: b2::fmi2Component,
                _s: b2::fmi2StatusKind,
                _v: *mut b2::fmi2Status,
            ) -> b2::fmi2Status {
                unsafe { x::unsupported::<M>(c, "fmi2GetStatus") }
            }
            #[unsafe(export_name = "fmi2GetRealStatus")]
            pub unsafe extern "C" fn fmi2_get_real_status(
                c: b2::fmi2Component,
                _s: b2::fmi2StatusKind,
                _v: *mut b2::fmi2Real,
            ) -> b2::fmi2Status {
                unsafe { x::unsupported::<M>(c, "fmi2GetRealStatus") }
            }
            #[unsafe(export_name = "fmi2GetIntegerStatus")]
            pub unsafe extern "C" fn fmi2_get_integer_status(
                c: b2::fmi2Component,
                _s: b2::fmi2StatusKind,
                _v: *mut b2::fmi2Integer,
            ) -> b2::fmi2Status {
                unsafe { x::unsupported::<M>(c, "fmi2GetIntegerStatus") }
            }
            #[unsafe(export_name = "fmi2GetBooleanStatus")]
            pub unsafe extern "C" fn fmi2_get_boolean_status(
                c: b2::fmi2Component,
                _s: b2::fmi2StatusKind,
                _v: *mut b2::fmi2Boolean,
            ) -> b2::fmi2Status {
                unsafe { x::unsupported::<M>(c, "fmi2GetBooleanStatus") }
            }
            #[unsafe(export_name = "fmi2GetStringStatus")]
            pub unsafe extern "C" fn fmi2_get_string_status(
                c: b2::fmi2Component,
                _s: b2::fmi2StatusKind,
                _v: *mut b2::fmi2String,
            ) -> b2::fmi2Status {
                unsafe { x::unsupported::<M>(c, "fmi2GetStringStatus") }
            }
        }
    };
}
