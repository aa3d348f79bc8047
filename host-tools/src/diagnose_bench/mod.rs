//! Benchmarks of `mre diagnose`, kept outside the estimator: the
//! calibration set ([`calibration`]) run under the frozen rules.
pub mod calibration;
