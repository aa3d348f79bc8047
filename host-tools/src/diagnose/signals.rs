//! Signal primitives on one recording's channels, below every stage that
//! reads them: [`super::prepared`] (branch and range marking) and
//! [`super::design`] (the model's columns) both use them, so neither
//! imports the other for them.

/// Rate-independent hysteresis memory (Masing/Dahl type): after a reversal
/// at `x_r`, the branch relaxes towards its steady curve over a length δ, so
/// the unloading curve depends on where loading turned around, which the
/// paper's single quartic per branch cannot represent.
///
/// Returns, per sample, the distance travelled since the last reversal and
/// the reversal's sample index `(|x − x_r|, index)` (`None` before the first
/// reversal), and the direction of travel (true = compressing). The model's
/// columns, per current, are `e^{−|x − x_r|/(m·δ)}·x_r^p` over
/// [`super::design::MEMORY_LENGTHS`] m and p < [`super::design::MEMORY_POWERS`]: a relaxation whose size
/// follows the turn-around point, without committing to one length. Reversals are
/// found on displacement with a dead band of δ/5, not on the sign of a noisy
/// velocity, so noise at a turn-around does not create spurious reversals.
pub fn memory_feature(x: &[f64], delta_mm: f64) -> (Vec<Option<(f64, f64)>>, Vec<bool>) {
    let n = x.len();
    let mut feature: Vec<Option<(f64, f64)>> = vec![None; n];
    let mut compressing = vec![true; n];
    let band = 0.2 * delta_mm;
    let mut dir = true;
    let mut ext_at = 0usize;
    let mut anchor: Option<(usize, f64)> = None;
    for t in 0..n {
        let beyond = if dir { x[t] >= x[ext_at] } else { x[t] <= x[ext_at] };
        if beyond {
            ext_at = t;
        } else if (x[t] - x[ext_at]).abs() > band {
            // Reversal at the extreme: travel since then belongs to the new direction.
            anchor = Some((ext_at, x[ext_at]));
            dir = !dir;
            let from = ext_at;
            ext_at = t;
            for s in from..t {
                compressing[s] = dir;
                if dir {
                    if x[s] > x[ext_at] {
                        ext_at = s;
                    }
                } else if x[s] < x[ext_at] {
                    ext_at = s;
                }
            }
            for s in from..t {
                feature[s] = Some(((x[s] - x[from]).abs(), from as f64));
            }
        }
        compressing[t] = dir;
        if let Some((at, xr)) = anchor {
            feature[t] = Some(((x[t] - xr).abs(), at as f64));
        }
    }
    (feature, compressing)
}

/// Hat weights `(index, weight)` of `current_a` over `currents_a`, linear in
/// I or in `tanh(I/I_s)`; clamped to the table's range like the core.
pub fn current_weights(currents_a: &[f64], current_a: f64, saturation_i_a: Option<f64>) -> [(usize, f64); 2] {
    let u = |i: f64| saturation_i_a.map_or(i, |s| (i / s).tanh());
    let last = currents_a.len() - 1;
    if current_a <= currents_a[0] {
        return [(0, 1.0), (0, 0.0)];
    }
    if current_a >= currents_a[last] {
        return [(last, 1.0), (last, 0.0)];
    }
    for k in 0..last {
        let (lo, hi) = (currents_a[k], currents_a[k + 1]);
        if current_a < hi {
            if (current_a - lo).abs() < 1e-12 {
                return [(k, 1.0), (k, 0.0)];
            }
            let t = (u(current_a) - u(lo)) / (u(hi) - u(lo));
            return [(k, 1.0 - t), (k + 1, t)];
        }
    }
    [(last, 1.0), (last, 0.0)]
}

/// Linear interpolation of a recording's channel at time `t` (clamped).
pub fn sample_at(time_s: &[f64], y: &[f64], t: f64, hint: &mut usize) -> f64 {
    let n = time_s.len();
    if t <= time_s[0] {
        return y[0];
    }
    if t >= time_s[n - 1] {
        return y[n - 1];
    }
    while *hint + 1 < n && time_s[*hint + 1] < t {
        *hint += 1;
    }
    while *hint > 0 && time_s[*hint] > t {
        *hint -= 1;
    }
    let (t0, t1) = (time_s[*hint], time_s[*hint + 1]);
    let f = (t - t0) / (t1 - t0);
    y[*hint] + f * (y[*hint + 1] - y[*hint])
}
