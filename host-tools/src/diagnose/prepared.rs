//! Recordings in the form every diagnosis stage works on: f64 channels, a
//! derived acceleration, the tabulated (fit) currents and the CV folds.
use crate::dataset::{Dataset, Role, TagValue};
use anyhow::{bail, Result};

/// One recording, ready for analysis.
#[derive(Clone, Debug)]
pub struct Rec {
    /// Index in `Dataset::recordings`.
    pub index: usize,
    pub file: String,
    pub role: Role,
    pub current_a: f64,
    pub sequence: Option<f64>,
    pub temperature_c: Option<f64>,
    pub impact_velocity_m_s: Option<f64>,
    pub time_s: Vec<f64>,
    pub x_mm: Vec<f64>,
    pub v_m_s: Vec<f64>,
    /// Measured if the file had it, else the central difference of velocity.
    pub a_m_s2: Vec<f64>,
    pub force_n: Vec<f64>,
    /// The per-sample coil current (the file's `current_a` column) of a
    /// validate recording, when it has one: a controlled impact whose command
    /// changes during the test. Fit recordings hold their tabulated current.
    pub current_trace_a: Option<Vec<f64>>,
    /// Cross-validation fold (fit recordings only).
    pub fold: Option<usize>,
    /// A label of the fold's group, for the report (e.g. `frequency_hz=1`).
    pub group: String,
    /// Samples where the model is defined, the only ones fitted and scored:
    /// the branch is clear (|v| beyond the velocity noise, see
    /// [`BRANCH_AMBIGUITY_SIGMAS`]) and, for validate recordings, x lies inside
    /// the stroke the bracketing tabulated currents were fitted on.
    pub in_domain: Vec<bool>,
    /// Validate recordings: x inside the fitted stroke (and turn-around range);
    /// `in_domain` is this and a clear branch at v(t).
    pub in_range: Vec<bool>,
    /// Velocity channel noise (m/s), estimated from the recording itself.
    pub velocity_noise_m_s: f64,
    /// The file had no velocity column: v was estimated from x
    /// ([`crate::dataset::velocity`]).
    pub velocity_estimated: bool,
    /// The file had no displacement: x and v were integrated from force or
    /// acceleration.
    pub motion_from: Option<crate::dataset::motion::MotionSource>,
    /// The largest |x| (mm) of every recording run before this one (a
    /// smaller `sequence`, validate ones included): the strain history a
    /// Mullins-type softening remembers. `None` without a run order.
    pub run_peak_before_mm: Option<f64>,
}

impl Rec {
    pub fn len(&self) -> usize {
        self.time_s.len()
    }

    pub fn is_empty(&self) -> bool {
        self.time_s.is_empty()
    }

    /// Samples scored (see `in_domain`).
    pub fn n_scored(&self) -> usize {
        self.in_domain.iter().filter(|b| **b).count()
    }

    /// Samples in range but left out because their branch is ambiguous.
    pub fn n_branch_ambiguous(&self) -> usize {
        self.in_range
            .iter()
            .zip(&self.in_domain)
            .filter(|(r, d)| **r && !**d)
            .count()
    }

    pub fn is_fit(&self) -> bool {
        self.role == Role::Fit
    }

    /// The recorded coil current at sample `t`.
    pub fn current_at(&self, t: usize) -> f64 {
        self.current_trace_a
            .as_ref()
            .and_then(|c| c.get(t).copied())
            .unwrap_or(self.current_a)
    }

    /// The samples a model is fitted and scored on: inside the range, with a
    /// clear branch for the velocity the model reads, v(t − τ) under a sensor
    /// delay τ.
    ///
    /// The paper's model switches branch on the sign of velocity, and the two
    /// branches differ by the whole hysteresis band. At a turn-around the
    /// sample nearest v = 0 falls on either branch by chance (velocity noise),
    /// so one sample can carry an error of thousands of newtons that says
    /// nothing about missing physics and would swamp every per-recording
    /// RMSE. Those samples, |v| < 2σ_v (typically one per turn-around in a
    /// drop test), are neither fitted nor scored; the report counts them.
    pub fn scored_mask(&self, delay_s: Option<f64>) -> Vec<bool> {
        let limit = self.branch_band_m_s();
        let mut hint = 0;
        (0..self.len())
            .map(|t| {
                let v = match delay_s {
                    Some(tau) => super::signals::sample_at(&self.time_s, &self.v_m_s, self.time_s[t] - tau, &mut hint),
                    None => self.v_m_s[t],
                };
                self.in_range[t] && crate::signal::clear_branch(v, limit).is_some()
            })
            .collect()
    }

    /// |v| below this (m/s) leaves the branch to chance ([`Self::scored_mask`]).
    pub fn branch_band_m_s(&self) -> f64 {
        BRANCH_AMBIGUITY_SIGMAS * self.velocity_noise_m_s
    }

    /// The held current, or `first→last` when it changes during the test.
    pub fn current_label(&self) -> String {
        match &self.current_trace_a {
            Some(c) if self.current_change_a() > 0.0 => format!(
                "{}→{}",
                c.first().copied().unwrap_or(self.current_a),
                c.last().copied().unwrap_or(self.current_a)
            ),
            _ => format!("{}", self.current_a),
        }
    }

    /// How far the recorded current moves during the test (A; 0 when held).
    pub fn current_change_a(&self) -> f64 {
        self.current_trace_a.as_ref().map_or(0.0, |c| {
            let (lo, hi) = c
                .iter()
                .fold((f64::INFINITY, f64::NEG_INFINITY), |(l, h), v| (l.min(*v), h.max(*v)));
            hi - lo
        })
    }

    pub fn max_abs_v_m_s(&self) -> f64 {
        self.v_m_s.iter().fold(0.0, |m, v| m.max(v.abs()))
    }

    pub fn max_x_mm(&self) -> f64 {
        self.x_mm.iter().copied().fold(f64::NEG_INFINITY, f64::max)
    }

    pub fn min_x_mm(&self) -> f64 {
        self.x_mm.iter().copied().fold(f64::INFINITY, f64::min)
    }

    /// Median sample period.
    pub fn dt_s(&self) -> f64 {
        let mut d: Vec<f64> = self.time_s.windows(2).map(|w| w[1] - w[0]).collect();
        if d.is_empty() {
            return 0.0;
        }
        d.sort_by(f64::total_cmp);
        d[d.len() / 2]
    }
}

/// How recordings are split into cross-validation folds.
#[derive(Clone, Debug, PartialEq)]
pub enum FoldPlan {
    /// `k` folds, recordings of each current dealt round-robin in order of
    /// peak velocity, so every fold keeps every current and a spread of speeds.
    Stratified { k: usize },
    /// One fold per distinct value of a tag (e.g. `frequency_hz`): whole
    /// groups are held out.
    ByTag(String),
}

/// The data set as the diagnosis sees it.
#[derive(Clone, Debug)]
pub struct Prepared {
    pub recs: Vec<Rec>,
    /// Distinct currents of the fit recordings, ascending: the baseline's table.
    pub currents_a: Vec<f64>,
    pub n_folds: usize,
    /// Free drop: the acceleration is the drop mass's, `a = g − F/M`.
    pub free_drop: bool,
    /// Whether validate recordings may be evidence for a term that changes
    /// only their predictions ([`super::acceptance::Thresholds::validate_evidence`]);
    /// false: no choice reads them.
    pub validate_evidence: bool,
}

impl Prepared {
    pub fn fit_indices(&self) -> Vec<usize> {
        (0..self.recs.len()).filter(|&i| self.recs[i].is_fit()).collect()
    }

    pub fn validate_indices(&self) -> Vec<usize> {
        (0..self.recs.len()).filter(|&i| !self.recs[i].is_fit()).collect()
    }

    pub fn fold_members(&self, fold: usize) -> Vec<usize> {
        (0..self.recs.len())
            .filter(|&i| self.recs[i].fold == Some(fold))
            .collect()
    }

    pub fn training_for(&self, fold: usize) -> Vec<usize> {
        (0..self.recs.len())
            .filter(|&i| self.recs[i].is_fit() && self.recs[i].fold != Some(fold))
            .collect()
    }
}

/// Converts the data set, treating recordings at `validate_currents_a` as
/// `validate` whatever their role says (e.g. 0.5 A of a 0/0.5/1 A campaign).
pub fn prepare(ds: &Dataset, plan: &FoldPlan, validate_currents_a: &[f64]) -> Result<Prepared> {
    let mut recs = Vec::with_capacity(ds.recordings.len());
    for (index, r) in ds.recordings.iter().enumerate() {
        let s = &r.samples;
        if s.len() < 8 {
            bail!("{}: {} samples; the diagnosis needs at least 8", r.file, s.len());
        }
        let all = [&s.time_s, &s.x_mm, &s.v_m_s, &s.force_n];
        if all
            .iter()
            .any(|c| c.len() != s.len() || c.iter().any(|v| !v.is_finite()))
        {
            bail!("{}: channels differ in length or hold NaN/infinite values", r.file);
        }
        let a_m_s2 = match &s.accel_m_s2 {
            Some(a) if a.len() == s.len() && a.iter().all(|v| v.is_finite()) => a.clone(),
            _ => differentiate(&s.time_s, &s.v_m_s),
        };
        let role = r.role_holding_out(validate_currents_a);
        let current_trace_a = match &s.current_a {
            Some(c) if role == Role::Validate => {
                if c.len() != s.len() || c.iter().any(|v| !v.is_finite()) {
                    bail!(
                        "{}: the `current_a` column differs in length or holds NaN/infinite values",
                        r.file
                    );
                }
                Some(c.clone())
            }
            _ => None,
        };
        recs.push(Rec {
            index,
            file: r.file.clone(),
            role,
            current_a: r.current_a,
            sequence: r.sequence.map(f64::from),
            temperature_c: r.temperature_c,
            impact_velocity_m_s: r.impact_velocity_m_s,
            time_s: s.time_s.clone(),
            x_mm: s.x_mm.clone(),
            v_m_s: s.v_m_s.clone(),
            a_m_s2,
            force_n: s.force_n.clone(),
            current_trace_a,
            fold: None,
            group: String::new(),
            in_domain: vec![true; s.len()],
            in_range: vec![true; s.len()],
            velocity_noise_m_s: velocity_noise_m_s(&s.v_m_s),
            velocity_estimated: r.velocity_estimated,
            motion_from: r.motion_from,
            run_peak_before_mm: None,
        });
    }
    let peaks: Vec<(Option<f64>, f64)> = recs
        .iter()
        .map(|r| (r.sequence, r.x_mm.iter().fold(0.0f64, |m, x| m.max(x.abs()))))
        .collect();
    for r in &mut recs {
        r.run_peak_before_mm = r.sequence.map(|n| {
            peaks
                .iter()
                .filter(|(s, _)| s.is_some_and(|s| s < n))
                .fold(0.0f64, |m, (_, p)| m.max(*p))
        });
    }
    let currents_a = crate::dataset::distinct_currents_a(recs.iter().filter(|r| r.is_fit()).map(|r| r.current_a));
    if currents_a.is_empty() {
        bail!("the data set has no `fit` recordings to build the baseline from");
    }
    mark_range(&mut recs, &currents_a);
    for r in &mut recs {
        r.in_domain = r.scored_mask(None);
    }
    let n_folds = assign_folds(&mut recs, ds, plan)?;
    let free_drop = ds
        .recordings
        .iter()
        .all(|r| r.samples.accel_m_s2.is_none() && (r.mass_kg.is_some() || r.impact_velocity_m_s.is_some()));
    Ok(Prepared {
        recs,
        currents_a,
        n_folds,
        free_drop,
        validate_evidence: false,
    })
}

fn assign_folds(recs: &mut [Rec], ds: &Dataset, plan: &FoldPlan) -> Result<usize> {
    match plan {
        FoldPlan::Stratified { k } => {
            // Never more folds than fit recordings: an empty fold is a fold
            // only in name, and the report counts folds.
            let n_fit = recs.iter().filter(|r| r.is_fit()).count();
            let k = (*k).min(n_fit).max(2);
            let currents = crate::dataset::distinct_currents_a(recs.iter().filter(|r| r.is_fit()).map(|r| r.current_a));
            let mut offset = 0;
            for c in currents {
                let mut members: Vec<usize> = (0..recs.len())
                    .filter(|&i| recs[i].is_fit() && recs[i].current_a == c)
                    .collect();
                members.sort_by(|&a, &b| recs[a].max_abs_v_m_s().total_cmp(&recs[b].max_abs_v_m_s()));
                for (j, &i) in members.iter().enumerate() {
                    let fold = (j + offset) % k;
                    recs[i].fold = Some(fold);
                    recs[i].group = format!("fold {}", fold + 1);
                }
                offset += members.len();
            }
            Ok(k)
        }
        FoldPlan::ByTag(tag) => {
            let mut labels: Vec<String> = Vec::new();
            for r in recs.iter_mut().filter(|r| r.is_fit()) {
                let label = match ds.recordings[r.index].tags.get(tag) {
                    Some(TagValue::Number(n)) => format!("{tag}={n}"),
                    Some(TagValue::Text(t)) => format!("{tag}={t}"),
                    None => bail!("{}: no tag `{tag}` to group cross-validation folds by", r.file),
                };
                let fold = match labels.iter().position(|l| *l == label) {
                    Some(p) => p,
                    None => {
                        labels.push(label.clone());
                        labels.len() - 1
                    }
                };
                r.fold = Some(fold);
                r.group = label;
            }
            if labels.len() < 2 {
                bail!("tag `{tag}` has fewer than 2 distinct values: nothing to hold out");
            }
            Ok(labels.len())
        }
    }
}

/// Reversal points of a recording: `(x_r, was_a_maximum)`.
fn reversals(x: &[f64], band_mm: f64) -> Vec<(f64, bool)> {
    let (feature, compressing) = super::signals::memory_feature(x, band_mm * 5.0);
    let mut out: Vec<(f64, bool)> = Vec::new();
    let mut last: Option<usize> = None;
    for t in 0..x.len() {
        if let Some((_, at)) = feature[t] {
            let at = at as usize;
            if last != Some(at) {
                last = Some(at);
                out.push((x[at], !compressing[t]));
            }
        }
    }
    out
}

/// Validate recordings are scored only where the model is defined without
/// extrapolation: within the stroke both bracketing tabulated currents were
/// fitted on (where the core would not clamp x), and, after a reversal, only
/// if the reversal point lies within the range of reversal points of those
/// currents' fit recordings (the reference model's turn-around memory is
/// fitted per current as a function of the reversal point).
fn mark_range(recs: &mut [Rec], currents_a: &[f64]) {
    let span = recs
        .iter()
        .filter(|r| r.is_fit())
        .flat_map(|r| r.x_mm.iter().copied())
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(l, h), x| (l.min(x), h.max(x)));
    let margin = 0.02 * (span.1 - span.0).max(1e-9);
    let band = 0.5 * margin;
    let range =
        |v: &mut dyn Iterator<Item = f64>| v.fold((f64::INFINITY, f64::NEG_INFINITY), |(l, h), x| (l.min(x), h.max(x)));
    // Per current: stroke, range of maxima, range of minima.
    let per_current: Vec<[(f64, f64); 3]> = currents_a
        .iter()
        .map(|&c| {
            let fits: Vec<&Rec> = recs.iter().filter(|r| r.is_fit() && r.current_a == c).collect();
            let stroke = range(&mut fits.iter().flat_map(|r| r.x_mm.iter().copied()));
            let revs: Vec<(f64, bool)> = fits.iter().flat_map(|r| reversals(&r.x_mm, band)).collect();
            let maxima = range(&mut revs.iter().filter(|r| r.1).map(|r| r.0));
            let minima = range(&mut revs.iter().filter(|r| !r.1).map(|r| r.0));
            [stroke, maxima, minima]
        })
        .collect();
    // Limits of the tabulated currents bracketing `current_a`.
    let limits = |current_a: f64| {
        let mut lim = [(f64::NEG_INFINITY, f64::INFINITY); 3];
        for (k, w) in super::signals::current_weights(currents_a, current_a, None) {
            if w > 0.0 {
                for (l, p) in lim.iter_mut().zip(&per_current[k]) {
                    l.0 = l.0.max(p.0 - margin);
                    l.1 = l.1.min(p.1 + margin);
                }
            }
        }
        lim
    };
    for r in recs.iter_mut().filter(|r| !r.is_fit()) {
        let (feature, compressing) = super::signals::memory_feature(&r.x_mm, band * 5.0);
        r.in_range = (0..r.len())
            .map(|t| {
                let lim = limits(r.current_at(t));
                let x = r.x_mm[t];
                let in_stroke = x >= lim[0].0 && x <= lim[0].1;
                let memory_ok = match feature[t] {
                    None => true,
                    Some((_, at)) => {
                        let x_r = r.x_mm[at as usize];
                        let l = if compressing[t] { lim[2] } else { lim[1] };
                        x_r >= l.0 && x_r <= l.1
                    }
                };
                in_stroke && memory_ok
            })
            .collect();
    }
}

/// The one scoring rule, for every stage. A sample of a recording is scored
/// under a model whose force channel lags by τ when it is in range and its
/// branch is clear at t − τ ([`Rec::scored_mask`]; `in_domain` is the rule at
/// τ = 0). Two models (a candidate and the model it would extend in
/// selection and support, the final model and the baseline in the report)
/// are scored on the samples both score: a delay that moves the chance
/// turn-around samples then cannot win by dropping them.
pub fn scored_by_both(a: &[bool], b: &[bool]) -> Vec<bool> {
    a.iter().zip(b).map(|(a, b)| *a && *b).collect()
}

/// The items of `values` at the samples `mask` scores, in order.
pub fn scored<'a, I>(values: I, mask: &'a [bool]) -> impl Iterator<Item = I::Item> + 'a
where
    I: IntoIterator,
    I::IntoIter: 'a,
{
    values.into_iter().zip(mask).filter(|(_, m)| **m).map(|(v, _)| v)
}

pub use crate::signal::BRANCH_AMBIGUITY_SIGMAS;

/// Velocity channel noise (m/s): [`crate::signal::white_noise_sd`].
pub fn velocity_noise_m_s(v: &[f64]) -> f64 {
    crate::signal::white_noise_sd(v)
}

pub use crate::signal::differentiate;
