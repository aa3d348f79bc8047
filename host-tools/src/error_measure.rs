//! The one error measure every report, page and JSON file of `mre` uses
//! (docs/error-measure.md): NRMSE = RMSE / (max F − min F), the root-mean-square
//! error over a set of samples divided by the range of the *measured* force
//! over the same samples. JSON carries it as a fraction (`nrmse`); pages print
//! it in percent.

/// What reports print beside the number.
pub const DEFINITION: &str = "NRMSE = RMSE / (max F − min F) of the measured force over the same samples";

/// Root-mean-square difference (N) of two equally long force series; 0 for none.
pub fn rmse_n(measured_n: &[f64], model_n: &[f64]) -> f64 {
    let n = measured_n.len().min(model_n.len());
    if n == 0 {
        return 0.0;
    }
    let sse: f64 = measured_n.iter().zip(model_n).map(|(m, p)| (m - p) * (m - p)).sum();
    (sse / n as f64).sqrt()
}

/// Range of the measured force (max − min), the measure's denominator.
pub fn range_n(measured_n: &[f64]) -> f64 {
    let (lo, hi) = measured_n
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), &f| {
            (lo.min(f), hi.max(f))
        });
    if hi >= lo {
        hi - lo
    } else {
        0.0
    }
}

/// `rmse_n / range_n` as a fraction; NaN when the measured force does not vary
/// (no scale to judge the error against: reports print "–").
pub fn nrmse(rmse_n: f64, range_n: f64) -> f64 {
    if range_n > 0.0 {
        rmse_n / range_n
    } else {
        f64::NAN
    }
}

/// The NRMSE of `model_n` against `measured_n`.
pub fn nrmse_of(measured_n: &[f64], model_n: &[f64]) -> f64 {
    nrmse(rmse_n(measured_n, model_n), range_n(measured_n))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn nrmse_divides_by_the_measured_range() {
        // Errors 3 and −4: RMSE = √((9 + 16)/2) = √12.5; measured range 5 − (−10) = 15.
        let got = nrmse_of(&[-10.0, 5.0], &[-7.0, 9.0]);
        assert!((got - 12.5f64.sqrt() / 15.0).abs() < 1e-12, "{got}");
    }

    #[test]
    fn a_constant_measured_force_has_no_scale() {
        assert!(nrmse_of(&[2.0, 2.0], &[1.0, 3.0]).is_nan());
        assert_eq!(rmse_n(&[], &[]), 0.0);
    }
}
