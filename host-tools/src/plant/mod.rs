//! The drop-impact plant: the physical world the diagnosis, the closed-loop
//! controller and the processor-in-the-loop runs are tested against.
//!
//! - [`law`]: the true force law (elastic backbone that stiffens, smooth
//!   rate-independent hysteresis, field-dependent gain), calibrated to the
//!   paper's Table 5 peaks. The physics and the calibration are in
//!   `README.md` beside this file.
//! - [`effects`]: concealed effects from `docs/effects.md`.
//! - [`measure`]: the instrument (sampling, noise, quantisation).
//! - [`base_laws`], [`synth_mts`]: shaker/MTS campaigns (`mre synth --campaign
//!   mts`) from a rate-independent Dahl or Bouc–Wen base law, outside the
//!   paper's class.
//! - [`calibration`]: campaigns with effects in other forms than the
//!   diagnosis' candidates, for calibrating its rules.
//! - [`stepper`]: RK4 drop simulation, one control period at a time
//!   ([`PlantStepper`]) or a whole impact ([`simulate`]).
pub mod base_laws;
pub mod calibration;
pub mod closed_loop;
pub mod effects;
pub mod law;
pub mod measure;
pub mod outside;
pub mod plots;
pub mod sim_report;
pub mod stepper;
pub mod synth;
pub mod synth_mts;

pub use effects::{ConcealedEffect, Effect, DROP_EFFECTS};
pub use law::LawParams;
pub use measure::MeasurementModel;
pub use stepper::{
    simulate, CoilDriver, CurrentSource, ImpactConfig, ImpactSummary, Plant, PlantStepper, Sample, Trajectory,
};
