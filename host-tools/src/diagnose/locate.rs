//! Where the residual lives: which recordings, branch, part of the stroke,
//! stretch of time, and which covariate it follows.
use super::prepared::Prepared;

/// Number of equal bins along the stroke and along each recording's time.
pub const BINS: usize = 5;

/// Time constant, in sample periods, of the probe lag behind the coil-lag
/// covariate [`CURRENT_NOT_FOLLOWED`].
const LAG_PROBE_SAMPLES: f64 = 8.0;
/// The coil-lag signature's name in the report.
pub const CURRENT_NOT_FOLLOWED: &str = "current change not yet followed (I − I lagged 8 samples)";

#[derive(Clone, Debug, serde::Serialize)]
pub struct Locate {
    /// Recordings by residual RMS, worst first: (file, RMS N).
    pub worst_recordings: Vec<(String, f64)>,
    /// Share of the residual energy on the compression and extension branches.
    pub branch_share: [f64; 2],
    /// Share of residual energy per fifth of each recording's maximum stroke.
    pub stroke_share: [f64; BINS],
    /// Share per fifth of each recording's duration.
    pub time_share: [f64; BINS],
    /// Sample-level correlations of the residual with signatures.
    pub sample_correlations: Vec<(String, f64)>,
    /// Correlations across recordings of the residual's scale
    /// (`Σ r·F̂ / Σ F̂²`) with per-recording covariates.
    pub recording_correlations: Vec<(String, f64)>,
}

pub fn pearson(a: &[f64], b: &[f64]) -> f64 {
    let n = a.len().min(b.len());
    if n < 3 {
        return 0.0;
    }
    let ma = a[..n].iter().sum::<f64>() / n as f64;
    let mb = b[..n].iter().sum::<f64>() / n as f64;
    let (mut sab, mut saa, mut sbb) = (0.0, 0.0, 0.0);
    for i in 0..n {
        let (da, db) = (a[i] - ma, b[i] - mb);
        sab += da * db;
        saa += da * da;
        sbb += db * db;
    }
    if saa <= 0.0 || sbb <= 0.0 {
        0.0
    } else {
        sab / (saa * sbb).sqrt()
    }
}

/// Residual scale per recording: the least-squares `s` in `r ≈ s·F̂`.
pub fn residual_scale(measured: &[f64], predicted: &[f64]) -> f64 {
    let (mut num, mut den) = (0.0, 0.0);
    for (f, p) in measured.iter().zip(predicted) {
        num += (f - p) * p;
        den += p * p;
    }
    if den > 0.0 {
        num / den
    } else {
        0.0
    }
}

fn shares(e: &[f64]) -> Vec<f64> {
    let total: f64 = e.iter().sum();
    e.iter().map(|v| if total > 0.0 { v / total } else { 0.0 }).collect()
}

/// Locates the residual `measured − predicted` over every recording.
pub fn locate(prep: &Prepared, predicted: &[Vec<f64>]) -> Locate {
    let mut worst: Vec<(String, f64)> = Vec::new();
    let (mut branch, mut stroke, mut time) = ([0.0; 2], [0.0; BINS], [0.0; BINS]);
    let (mut res, mut vel, mut acc, mut beyond, mut shift) = (vec![], vec![], vec![], vec![], vec![]);
    let mut unfollowed = vec![];
    let mut per_rec: Vec<(usize, f64)> = Vec::new();
    // An end stop engages at one displacement for every test: threshold on the
    // largest stroke in the data set, not on each test's own.
    let x_all = prep.recs.iter().map(|r| r.max_x_mm()).fold(f64::NEG_INFINITY, f64::max);
    for (i, rec) in prep.recs.iter().enumerate() {
        let p = &predicted[i];
        let n = rec.len();
        let xmax = rec.max_x_mm().max(1e-12);
        let (t0, t1) = (rec.time_s[0], rec.time_s[n - 1]);
        let mut e_rec = 0.0;
        // A coil lag leaves −(∂F/∂I)·(I − I_eff) behind: large just after
        // the recorded current changes, until the coil catches up.
        let lagged = super::design::effective_current_a(rec, Some(LAG_PROBE_SAMPLES * rec.dt_s()));
        for t in (0..n).filter(|&t| rec.in_domain[t]) {
            let r = rec.force_n[t] - p[t];
            let e = r * r;
            e_rec += e;
            branch[usize::from(rec.v_m_s[t] <= 0.0)] += e;
            let sb = ((rec.x_mm[t].max(0.0) / xmax) * BINS as f64).floor() as usize;
            stroke[sb.min(BINS - 1)] += e;
            let tb = (((rec.time_s[t] - t0) / (t1 - t0).max(1e-300)) * BINS as f64).floor() as usize;
            time[tb.min(BINS - 1)] += e;
            res.push(r);
            vel.push(rec.v_m_s[t]);
            acc.push(rec.a_m_s2[t]);
            beyond.push((rec.x_mm[t] - 0.8 * x_all).max(0.0));
            // A time shift τ leaves −τ·dF̂/dt behind.
            let (a, b) = (t.saturating_sub(1), (t + 1).min(n - 1));
            let dt = rec.time_s[b] - rec.time_s[a];
            shift.push(if dt > 0.0 { (p[b] - p[a]) / dt } else { 0.0 });
            unfollowed.push(rec.current_at(t) - lagged[t]);
        }
        worst.push((rec.file.clone(), (e_rec / rec.n_scored().max(1) as f64).sqrt()));
        per_rec.push((i, residual_scale(&rec.force_n, p)));
    }
    worst.sort_by(|a, b| b.1.total_cmp(&a.1));
    let sample_correlations = vec![
        ("velocity".to_string(), pearson(&res, &vel)),
        ("acceleration".to_string(), pearson(&res, &acc)),
        (
            "displacement beyond 80 % of the largest stroke".to_string(),
            pearson(&res, &beyond),
        ),
        ("model force rate dF/dt (time shift)".to_string(), pearson(&res, &shift)),
        (CURRENT_NOT_FOLLOWED.to_string(), pearson(&res, &unfollowed)),
    ];
    let cov = |name: &str, f: &dyn Fn(usize) -> Option<f64>| -> Option<(String, f64)> {
        let pairs: Vec<(f64, f64)> = per_rec.iter().filter_map(|&(i, s)| f(i).map(|c| (c, s))).collect();
        if pairs.len() < 3 {
            return None;
        }
        let (c, s): (Vec<f64>, Vec<f64>) = pairs.into_iter().unzip();
        Some((name.to_string(), pearson(&s, &c)))
    };
    let recording_correlations = [
        cov("sequence", &|i| prep.recs[i].sequence),
        cov("temperature_c", &|i| prep.recs[i].temperature_c),
        cov("current_a", &|i| Some(prep.recs[i].current_a)),
        cov("impact_velocity_m_s", &|i| prep.recs[i].impact_velocity_m_s),
        cov("peak velocity", &|i| Some(prep.recs[i].max_abs_v_m_s())),
        cov("peak stroke", &|i| Some(prep.recs[i].max_x_mm())),
    ]
    .into_iter()
    .flatten()
    .collect();
    let to_arr = |v: Vec<f64>| {
        let mut a = [0.0; BINS];
        a.copy_from_slice(&v);
        a
    };
    let b = shares(&branch);
    Locate {
        worst_recordings: worst,
        branch_share: [b[0], b[1]],
        stroke_share: to_arr(shares(&stroke)),
        time_share: to_arr(shares(&time)),
        sample_correlations,
        recording_correlations,
    }
}

/// Describes where most of the energy is, e.g. "compression branch (71 %)".
pub fn describe(loc: &Locate) -> String {
    let (bi, bs) = if loc.branch_share[0] >= loc.branch_share[1] {
        ("compression", loc.branch_share[0])
    } else {
        ("extension", loc.branch_share[1])
    };
    let argmax = |a: &[f64; BINS]| (0..BINS).max_by(|&x, &y| a[x].total_cmp(&a[y])).unwrap_or(0);
    let s = argmax(&loc.stroke_share);
    let t = argmax(&loc.time_share);
    let worst: Vec<&str> = loc.worst_recordings.iter().take(3).map(|w| w.0.as_str()).collect();
    format!(
        "{bi} branch ({:.0} %), stroke {}–{} % of each test's maximum ({:.0} %), time {}–{} % of each \
         recording ({:.0} %); worst recordings {}",
        bs * 100.0,
        s * 20,
        s * 20 + 20,
        loc.stroke_share[s] * 100.0,
        t * 20,
        t * 20 + 20,
        loc.time_share[t] * 100.0,
        worst.join(", ")
    )
}
