//! Benchmarks of `mre diagnose`, kept outside the estimator: simulated blind
//! cases ([`simulated`]), effects injected into real recordings ([`real`],
//! scored against the [`oracle`]) and the calibration set ([`calibration`])
//! run under the frozen rules.
pub mod calibration;
pub mod oracle;
pub mod outside;
pub mod real;
pub mod simulated;
