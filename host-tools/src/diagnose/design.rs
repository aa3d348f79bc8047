//! The augmented model and its least-squares design.
//!
//! `F(t) = s_r · [ Σ_k w_k(I) · Q_{k,branch}(x(t−τ)) + Σ_k w_k(I)·c_k·φ(v(t−τ))
//!               + k_e·max(0, x(t−τ) − x_e)² + m_s·a(t−τ) ]`
//!
//! `w_k` are the hat weights of linear interpolation between tabulated
//! currents (on `tanh(I/I_s)` under magnetic saturation); a fit recording sits
//! on one tabulated current, so only validate recordings are interpolated.
//! `s_r = 1 − Δ·g_r` is the per-recording softening factor. Every term but the
//! grid-searched `τ, v0, x_e, I_s, n0` is linear, so each fit is one QR solve.
//!
//! Speed: each recording's rows are compressed once into the R factor of the
//! QR of `[A_r | y_r]` (on its non-zero columns only). Stacking the R factors
//! of any set of recordings gives the same least-squares problem as stacking
//! their rows, so cross-validation folds and bootstrap resamples cost a small
//! solve each, and a constant row scale `s_r` just scales `R_A`.
use super::prepared::{Prepared, Rec};
use super::signals::{current_weights, sample_at};
use super::terms::{Block, Sample, Term, REGISTRY};
use crate::linalg;
use crate::vocabulary::Effect;
use anyhow::Result;
use nalgebra::{DMatrix, DVector};

/// Powers of x in each branch quartic (x⁰..x⁴).
pub const QUARTIC_TERMS: usize = 5;

/// Relaxation lengths of the turn-around memory basis, as multiples of δ.
pub const MEMORY_LENGTHS: [f64; 3] = [0.4, 1.0, 2.5];
/// Powers of the turn-around displacement x_r scaling each basis function.
pub const MEMORY_POWERS: usize = 2;
/// Memory columns per current and direction of travel: the powers of x_r at
/// each length after a turn-around, and one column for the start from rest
/// (see [`START_FROM_REST`]).
pub const MEMORY_TERMS: usize = MEMORY_LENGTHS.len() * MEMORY_POWERS + 1;
/// The start from rest relaxes over one length, this fraction of the fit
/// recordings' stroke span (the middle of the δ searched by
/// `candidates::memory_variants`), the same in every memory variant. One
/// length: a start spans a quarter cycle, as few as 5 samples on a 5 Hz,
/// 5 ms test, too few to pin three nearly collinear lengths (their held-out
/// predictions blew up). Not tied to δ: then the start's fit steered the
/// choice of δ (a 4.4 ms delay injected into the real set picked δ = 0.6 mm
/// for the start's sake, and every candidate then failed on top of it).
pub const START_SPAN_FRACTION: f64 = 0.025;
/// A recording starts from rest when its first speed is at most this
/// fraction of its peak speed (an MTS test started at standstill; a drop or
/// a sinusoid already running starts near its peak speed).
pub const START_FROM_REST: f64 = 0.1;

/// Where the memory's current stretch of travel started, seen from one sample.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Anchor {
    /// Travel since the anchor (mm).
    pub distance_mm: f64,
    /// Displacement at the anchor (mm).
    pub x_r_mm: f64,
    /// The anchor is the start from rest, not a reversal.
    pub from_rest: bool,
}

/// [`super::signals::memory_feature`] for the model's own branches: a reversal is where the
/// sign of v changes (the quartic's branch switch), anchored at x there.
/// Using the same direction as the quartic matters: where a displacement-
/// based direction and the sign of v disagree (a few samples at each
/// turn-around when v leads or lags x, or under a sensor delay), the memory
/// term of one branch would be added to the quartic of the other, and the
/// model would spike.
///
/// Noise near a slow turn-around: the direction switches only when v
/// passes `band_m_s` on the other side (the branch-ambiguity band, the same
/// one that leaves |v| < band unscored, so every scored sample's direction
/// is still the sign of its v), and the reversal is anchored at the last
/// sign change of v before that. Switching on every sign change let the
/// noise flip v back and forth around a slow extreme (a 25 mm, 0.1 Hz test
/// stays within 2σ_v for ±12 samples): each flip pair re-anchored the memory
/// as if the material had just turned around from the other branch, the
/// next scored samples were predicted off by the whole loop width (up to
/// 670 N on a Bouc–Wen law), and a half-sample "sensor delay", which
/// averages v over two samples and flips less, won by that.
///
/// A recording that starts from rest ([`START_FROM_REST`]) is anchored at
/// its first sample until the first reversal, flagged `true`: the material
/// leaves standstill as it leaves a turn-around (the force builds over the
/// same pre-yield length), but from a relaxed state rather than from the
/// opposite branch, so that stretch gets its own coefficients. Without it
/// the first quarter cycle of every real MTS test was predicted on the
/// steady branch (≈ 13 % of the final residual energy on the bundled set).
pub fn memory_feature_on_branches(
    time_s: &[f64],
    x: &[f64],
    v: &[f64],
    band_m_s: f64,
) -> (Vec<Option<Anchor>>, Vec<bool>) {
    let peak = v.iter().fold(0.0f64, |m, v| m.max(v.abs()));
    let mut anchor: Option<(f64, bool)> = match (x.first(), v.first()) {
        (Some(&x0), Some(&v0)) if peak > 0.0 && v0.abs() <= START_FROM_REST * peak => Some((x0, true)),
        _ => None,
    };
    // The direction of travel; none yet while a start stays inside the band.
    let mut direction: Option<bool> = None;
    let mut last_sign_change = 0;
    let mut compressing = Vec::with_capacity(v.len());
    let feature = (0..x.len())
        .map(|t| {
            if t > 0 && (v[t] > 0.0) != (v[t - 1] > 0.0) {
                last_sign_change = t;
            }
            let outside = v[t].abs() > band_m_s;
            match direction {
                None if outside => direction = Some(v[t] > 0.0),
                Some(c) if outside && c != (v[t] > 0.0) => {
                    direction = Some(!c);
                    anchor = Some((turning_point_mm(time_s, x, v, last_sign_change.max(1)), false));
                }
                _ => {}
            }
            compressing.push(direction.unwrap_or(v[t] > 0.0));
            anchor.map(|(x_r_mm, from_rest)| Anchor {
                distance_mm: (x[t] - x_r_mm).abs(),
                x_r_mm,
                from_rest,
            })
        })
        .collect();
    (feature, compressing)
}

/// Per sample, the share of a full turn-around's relaxation still ahead,
/// `(1 − s·z)/2` in [0, 1] (s = ±1 the direction of travel, `compressing`),
/// of a first-order rate-independent state over length `length_mm`:
/// `z ← s + (z − s)·e^{−|Δx|/length}` (Dahl's law, exponent 1), started
/// relaxed (z = 0) when the recording starts from rest and saturated in the
/// first direction when it starts in motion. After a stroke that saturated it this
/// is `e^{−d/length}`, the old column; after a shorter stroke (a minor
/// loop of a multisine, a small sinusoid against a long memory) it is
/// smaller: a material recovers after a reversal only what the stroke
/// before it displaced (the return-point memory of Preisach/Masing laws).
/// Without it every minor reversal was predicted with the whole loop's
/// transient (on outside-class play plants the memory basis lost held out
/// on the multisines, 0.61×, and was never named).
pub fn reversal_share(x: &[f64], compressing: &[bool], length_mm: f64, from_rest: bool) -> Vec<f64> {
    let sign = |c: bool| if c { 1.0 } else { -1.0 };
    let mut z = match compressing.first() {
        Some(&c) if !from_rest => sign(c),
        _ => 0.0,
    };
    let mut last = x.first().copied().unwrap_or(0.0);
    x.iter()
        .zip(compressing)
        .map(|(&xt, &c)| {
            let s = sign(c);
            z = s + (z - s) * (-(xt - last).abs() / length_mm.max(1e-12)).exp();
            last = xt;
            (1.0 - s * z) / 2.0
        })
        .collect()
}

/// Where x turned around between samples `t − 1` and `t` (v changes sign):
/// v taken linear across the interval, x at its zero crossing. Anchoring at
/// the sample after the crossing instead puts every reversal half a sample
/// late on average, which on coarsely sampled sinusoids (5 ms at 5 Hz) a
/// sensor-delay term then "explains".
fn turning_point_mm(time_s: &[f64], x: &[f64], v: &[f64], t: usize) -> f64 {
    let (v0, v1) = (v[t - 1], v[t]);
    let dt = time_s[t] - time_s[t - 1];
    if v0 == v1 || dt <= 0.0 {
        return x[t];
    }
    let phi = (v0 / (v0 - v1)).clamp(0.0, 1.0);
    // x in mm, v in m/s.
    x[t - 1] + 1e3 * 0.5 * v0 * phi * dt
}

/// Rate dependence `c(I)·φ(v)`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Viscous {
    /// `φ(v) = v`.
    Linear,
    /// `φ(v) = v0·tanh(v/v0)`.
    Saturating { v0_m_s: f64 },
    /// `φ = v_τ`, v through a first-order lag τ (a spring in series with
    /// the dashpot: a Maxwell branch), relaxed when the recording starts
    /// ([`crate::diagnose::terms::maxwell_velocity_m_s`]).
    Maxwell { tau_s: f64 },
}

/// Softening covariate, per recording or per sample.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum SofteningLaw {
    /// `g = 1 − e^{−(n−1)/n0}` with n the recording's `sequence`.
    Sequence { n0: f64 },
    /// As `Sequence`, judged between runs of one motion at different
    /// places in the run (crossed by motion, not by test condition).
    Run { n0: f64 },
    /// `g = T − T_ref` (°C): a linear drift with temperature.
    Temperature { t_ref_c: f64 },
    /// Within a test: `g(t) = 1 − e^{−(k−1)/k0}` with k the cycle of sample
    /// t, counted from the displacement reversals ([`cycle_index`]).
    Cycle { k0: f64 },
    /// Strain history (Mullins): `g(t) = 1 − e^{−u/u0}` with
    /// `u = X(t)² − x(t)²` (mm²), X(t) the largest |x| of the run so far
    /// (every recording run before this one, [`Rec::run_peak_before_mm`],
    /// and this one up to t): softer the further below the run's largest
    /// displacement the sample lies.
    History { u0_mm2: f64 },
}

impl SofteningLaw {
    /// The recording's covariate (its largest, for a per-sample law).
    pub fn covariate(&self, rec: &Rec) -> f64 {
        match *self {
            SofteningLaw::Sequence { n0 } | SofteningLaw::Run { n0 } => {
                rec.sequence.map_or(0.0, |n| 1.0 - (-(n - 1.0) / n0).exp())
            }
            SofteningLaw::Temperature { t_ref_c } => rec.temperature_c.map_or(0.0, |t| t - t_ref_c),
            SofteningLaw::Cycle { .. } | SofteningLaw::History { .. } => {
                self.per_sample(rec).into_iter().fold(0.0, f64::max)
            }
        }
    }

    /// The law varies within a recording.
    pub fn within_test(&self) -> bool {
        matches!(self, SofteningLaw::Cycle { .. } | SofteningLaw::History { .. })
    }

    /// The covariate at each sample of `rec`.
    pub fn per_sample(&self, rec: &Rec) -> Vec<f64> {
        match *self {
            SofteningLaw::Cycle { k0 } => cycle_index(&rec.x_mm)
                .iter()
                .map(|&k| 1.0 - (-(k - 1.0) / k0).exp())
                .collect(),
            SofteningLaw::History { u0_mm2 } => {
                let mut peak = rec.run_peak_before_mm.unwrap_or(0.0);
                rec.x_mm
                    .iter()
                    .map(|&x| {
                        peak = peak.max(x.abs());
                        1.0 - (-(peak * peak - x * x) / u0_mm2).exp()
                    })
                    .collect()
            }
            _ => vec![self.covariate(rec); rec.len()],
        }
    }
}

/// A reversal counts once the displacement has come back from its running
/// extreme by this share of the recording's stroke: sensor noise and the
/// ripples of a multisine below it are not reversals.
const REVERSAL_BAND: f64 = 0.1;

/// The cycle (1, 2, …) each sample lies in: one more every two
/// displacement reversals, the first cycle from the start of the test.
pub fn cycle_index(x_mm: &[f64]) -> Vec<f64> {
    let (lo, hi) = range_of(x_mm.iter());
    let band = REVERSAL_BAND * (hi - lo);
    let mut out = vec![1.0; x_mm.len()];
    if band.is_nan() || band <= 0.0 {
        return out;
    }
    // The reversal samples: each running extreme left by more than the band.
    let mut reversals = Vec::new();
    let (mut ext, mut at, mut rising) = (x_mm[0], 0usize, None::<bool>);
    for (t, &x) in x_mm.iter().enumerate() {
        match rising {
            None if (x - ext).abs() > band => rising = Some(x > ext),
            None => {}
            Some(up) if (up && x > ext) || (!up && x < ext) => {
                ext = x;
                at = t;
            }
            Some(up) if (x - ext).abs() > band => {
                reversals.push(at);
                rising = Some(!up);
                ext = x;
                at = t;
            }
            Some(_) => {}
        }
    }
    let mut n = 0;
    for (t, k) in out.iter_mut().enumerate() {
        while n < reversals.len() && reversals[n] <= t {
            n += 1;
        }
        *k = 1.0 + (n / 2) as f64;
    }
    out
}

/// Which missing-physics terms the model carries (an empty set = the paper's model).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Terms {
    pub delay_s: Option<f64>,
    pub viscous: Option<Viscous>,
    pub end_stop_x_mm: Option<f64>,
    /// The stop sits at the extension end (x below `end_stop_x_mm`, pushing
    /// back with negative force) instead of the compression end: on a shaker
    /// or MTS test the stroke is two-sided.
    pub end_stop_lower: bool,
    /// Law and its fitted Δ (Δ is solved, not searched).
    pub softening: Option<SofteningLaw>,
    pub saturation_i_a: Option<f64>,
    /// Coil time constant L/R (s): the material sees the recorded current
    /// through a first-order lag (see [`effective_current_a`]).
    pub coil_lag_s: Option<f64>,
    /// Turn-around memory length δ (mm): not a vocabulary effect but part of
    /// the reference model (see [`super::signals::memory_feature`]).
    pub memory_mm: Option<f64>,
    /// Yield / dry-friction knee v0 (m/s) of `f(I)·tanh(v/v0)`: a force that
    /// changes sign at turn-around and is the same at every speed tested
    /// (rate-independent: part of `hysteresis_memory`, not viscous damping).
    pub friction_v0_m_s: Option<f64>,
    /// The state of every other term, by its vocabulary word: a new term
    /// keeps its searched value here and needs no field above.
    pub settings: Settings,
}

impl Terms {
    /// Parameters the solve finds outside the linear columns (the softening
    /// depth Δ, by its 1-D search in [`Designs::solve_in`]).
    pub fn solved_scalars(&self) -> usize {
        usize::from(self.softening.is_some())
    }

    /// Every term of `self`, plus those of `other` that `self` lacks: the
    /// joint model of terms chosen one at a time.
    pub fn merged(self, other: Terms) -> Terms {
        let stop = if self.end_stop_x_mm.is_some() { self } else { other };
        let mut settings = self.settings;
        for (e, v) in other.settings.0.iter().flatten() {
            if settings.get(*e).is_none() {
                settings = settings.with(*e, Some(*v));
            }
        }
        Terms {
            delay_s: self.delay_s.or(other.delay_s),
            viscous: self.viscous.or(other.viscous),
            end_stop_x_mm: stop.end_stop_x_mm,
            end_stop_lower: stop.end_stop_lower,
            softening: self.softening.or(other.softening),
            saturation_i_a: self.saturation_i_a.or(other.saturation_i_a),
            coil_lag_s: self.coil_lag_s.or(other.coil_lag_s),
            memory_mm: self.memory_mm.or(other.memory_mm),
            friction_v0_m_s: self.friction_v0_m_s.or(other.friction_v0_m_s),
            settings,
        }
    }
}

/// Terms a [`Settings`] can hold at once (the registry's length at most).
pub const SETTINGS_CAPACITY: usize = 16;

/// Searched values of terms, one per vocabulary word (`inertia`'s presence,
/// a new term's value), in a fixed-size `Copy` set so [`Terms`] stays `Copy`.
/// Kept in vocabulary order, so two equal sets compare equal.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Settings([Option<(Effect, f64)>; SETTINGS_CAPACITY]);

impl Settings {
    /// The value set for `effect`'s term, if it is in the model.
    pub fn get(&self, effect: Effect) -> Option<f64> {
        self.0.iter().flatten().find(|(e, _)| *e == effect).map(|(_, v)| *v)
    }

    /// The same set with `effect`'s term at `value`, or without it (`None`).
    pub fn with(self, effect: Effect, value: Option<f64>) -> Settings {
        let mut entries: Vec<(Effect, f64)> = self.0.iter().flatten().copied().filter(|(e, _)| *e != effect).collect();
        entries.extend(value.map(|v| (effect, v)));
        entries.sort_by_key(|(e, _)| *e);
        let mut out = Settings::default();
        // One entry per term at most, and the registry fits the capacity
        // (a test in `terms` checks it).
        for (slot, entry) in out.0.iter_mut().zip(entries) {
            *slot = Some(entry);
        }
        out
    }
}

/// One term's block of columns in a [`Layout`].
#[derive(Clone, Copy)]
pub struct Placed {
    pub term: &'static dyn Term,
    /// Which of the term's [`Term::blocks`].
    pub index: usize,
    pub block: Block,
    /// First global column.
    pub at: usize,
}

impl std::fmt::Debug for Placed {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "{} block {} ({:?}) at {}",
            self.term.effect().name(),
            self.index,
            self.block,
            self.at
        )
    }
}

/// Global column layout of a [`Terms`] over a table of currents: the
/// quartics, then each registered term's blocks in registry order.
#[derive(Clone, Debug)]
pub struct Layout {
    pub n_currents: usize,
    pub blocks: Vec<Placed>,
    /// The memory basis block (its columns are built here, not by a shape).
    pub memory_at: Option<usize>,
    pub n_cols: usize,
}

impl Layout {
    pub fn new(n_currents: usize, terms: &Terms) -> Self {
        let mut n = n_currents * 2 * QUARTIC_TERMS;
        let mut blocks = Vec::new();
        for &term in REGISTRY {
            for (index, block) in term.blocks(terms).into_iter().enumerate() {
                blocks.push(Placed {
                    term,
                    index,
                    block,
                    at: n,
                });
                n += match block {
                    Block::PerCurrent => n_currents,
                    Block::Global => 1,
                    Block::MemoryBasis => 2 * MEMORY_TERMS * n_currents,
                };
            }
        }
        let at = |block: Block| blocks.iter().find(|p| p.block == block).map(|p| p.at);
        Layout {
            n_currents,
            memory_at: at(Block::MemoryBasis),
            blocks,
            n_cols: n,
        }
    }

    /// First column of block `index` of `effect`'s term.
    pub fn at(&self, effect: Effect, index: usize) -> Option<usize> {
        self.blocks
            .iter()
            .find(|p| p.term.effect() == effect && p.index == index)
            .map(|p| p.at)
    }

    pub fn quartic_col(&self, current: usize, compression: bool, power: usize) -> usize {
        (current * 2 + usize::from(!compression)) * QUARTIC_TERMS + power
    }

    /// Memory column of current k, direction, basis function j.
    pub fn memory_col(&self, compression: bool, j: usize, current: usize) -> Option<usize> {
        self.memory_at
            .map(|at| at + (current * 2 + usize::from(!compression)) * MEMORY_TERMS + j)
    }

    /// Number of linear coefficients the added terms bring.
    pub fn extra_cols(&self) -> usize {
        self.n_cols - self.n_currents * 2 * QUARTIC_TERMS
    }
}

/// The current the material responds to at each sample: the recorded
/// current, or, with a coil lag τ, that current through a first-order lag
/// started in steady state (the coil is energised before contact). Between
/// samples the recorded value is taken to switch at mid-interval, so the
/// sampling does not bias τ by half a sample.
pub fn effective_current_a(rec: &Rec, coil_lag_s: Option<f64>) -> Vec<f64> {
    let n = rec.len();
    let recorded: Vec<f64> = (0..n).map(|t| rec.current_at(t)).collect();
    let Some(tau) = coil_lag_s.filter(|tau| *tau > 0.0) else {
        return recorded;
    };
    let mut out = Vec::with_capacity(n);
    let mut i_eff = recorded.first().copied().unwrap_or(rec.current_a);
    for t in 0..n {
        if t > 0 {
            let half = (-(rec.time_s[t] - rec.time_s[t - 1]).max(0.0) / (2.0 * tau)).exp();
            i_eff = recorded[t - 1] + (i_eff - recorded[t - 1]) * half;
            i_eff = recorded[t] + (i_eff - recorded[t]) * half;
        }
        out.push(i_eff);
    }
    out
}

/// The end stop's force per unit stiffness: `max(0, x − x_e)²` at the
/// compression end, `−max(0, x_e − x)²` at the extension end (the stop pushes
/// back towards the middle of the stroke either way).
pub fn end_stop_shape(x_mm: f64, x_e_mm: f64, lower: bool) -> f64 {
    if lower {
        let d = (x_e_mm - x_mm).max(0.0);
        -d * d
    } else {
        let d = (x_mm - x_e_mm).max(0.0);
        d * d
    }
}

/// One recording's design on its non-zero columns.
#[derive(Clone, Debug)]
pub struct RecDesign {
    /// Global column of each local column.
    pub cols: Vec<usize>,
    pub a: DMatrix<f64>,
    /// Compressed `[R_A | r_y]` (fit recordings only).
    pub r_a: Option<DMatrix<f64>>,
    pub r_y: Option<DVector<f64>>,
    /// Under a within-test softening law: `R_G`, from the QR of
    /// `[A | G | y]` with `G` each column of A times the sample's covariate,
    /// so `‖(A − ΔG)β − y‖ = ‖(R_A − ΔR_G)β − r_y‖` for every Δ.
    pub r_g: Option<DMatrix<f64>>,
    /// Samples fitted and scored under these terms ([`Rec::scored_mask`]).
    pub mask: Vec<bool>,
}

impl RecDesign {
    /// `A_r · β` (before the softening scale).
    pub fn predict(&self, beta: &[f64]) -> Vec<f64> {
        let b = DVector::from_iterator(self.cols.len(), self.cols.iter().map(|&c| beta[c]));
        (&self.a * b).iter().copied().collect()
    }
}

/// The designs of every recording under one [`Terms`].
#[derive(Clone, Debug)]
pub struct Designs {
    pub terms: Terms,
    pub layout: Layout,
    pub recs: Vec<RecDesign>,
    /// The relaxation length of a start from rest ([`START_SPAN_FRACTION`]).
    pub start_mm: f64,
    /// Each recording's covariate ranges (for [`Span`]).
    pub ranges: Vec<Ranges>,
}

/// A least-squares solution over some training recordings.
#[derive(Clone, Debug)]
pub struct Solution {
    pub beta: Vec<f64>,
    /// Softening Δ (0 when the model has no softening).
    pub delta: f64,
    pub sse: f64,
    /// The covariates its training recordings cover: a prediction beyond it
    /// continues each column along its tangent ([`Span`]).
    pub span: Span,
    /// Sign-constrained columns ([`Term::nonnegative`]) held at their bound,
    /// 0: their unconstrained value had the wrong sign.
    pub at_bound: Vec<usize>,
}

/// The span of each covariate over a fit's training recordings: the
/// model's physical range. Beyond it a polynomial in x (the quartics, the
/// stop's power) would grow as x⁴, so every column a prediction evaluates
/// beyond the span continues along its tangent at the span's edge: the force
/// grows no faster than the slope the fit saw at its edge (a spring's force
/// continues, a saturated one stays flat). Linear columns (`c·v`, `m·a`) are
/// their own tangent; bounded ones (a tanh, a decay) flatten.
#[derive(Clone, Debug, PartialEq)]
pub struct Span {
    /// Per tabulated current: x (mm) and v (m/s) of the training recordings
    /// at that current (the whole training set's where it has none).
    pub x_mm: Vec<(f64, f64)>,
    pub v_m_s: Vec<(f64, f64)>,
    /// x and a over all training recordings.
    pub all_x_mm: (f64, f64),
    pub a_m_s2: (f64, f64),
}

fn range_of<'a>(values: impl Iterator<Item = &'a f64>) -> (f64, f64) {
    values.fold((f64::INFINITY, f64::NEG_INFINITY), |(l, h), v| (l.min(*v), h.max(*v)))
}

fn within(r: (f64, f64), outer: (f64, f64)) -> bool {
    r.0 >= outer.0 && r.1 <= outer.1
}

/// One recording's covariate ranges.
#[derive(Clone, Copy, Debug)]
pub struct Ranges {
    pub x_mm: (f64, f64),
    pub v_m_s: (f64, f64),
    pub a_m_s2: (f64, f64),
}

impl Ranges {
    fn of(rec: &Rec) -> Ranges {
        Ranges {
            x_mm: range_of(rec.x_mm.iter()),
            v_m_s: range_of(rec.v_m_s.iter()),
            a_m_s2: range_of(rec.a_m_s2.iter()),
        }
    }
}

impl Span {
    /// No limit on any covariate, at each of `n_currents` currents.
    pub fn unbounded(n_currents: usize) -> Span {
        let everything = (f64::NEG_INFINITY, f64::INFINITY);
        Span {
            x_mm: vec![everything; n_currents],
            v_m_s: vec![everything; n_currents],
            all_x_mm: everything,
            a_m_s2: everything,
        }
    }

    /// The span of `train`'s recordings, from each recording's precomputed
    /// [`Ranges`] (an unbounded span when `train` is empty).
    fn from_ranges(prep: &Prepared, ranges: &[Ranges], train: &[usize]) -> Span {
        let everything = (f64::NEG_INFINITY, f64::INFINITY);
        let or_all = |r: (f64, f64), all: (f64, f64)| if r.0 <= r.1 { r } else { all };
        let union = |rs: &mut dyn Iterator<Item = (f64, f64)>| {
            rs.fold((f64::INFINITY, f64::NEG_INFINITY), |(l, h), r| (l.min(r.0), h.max(r.1)))
        };
        let all_x = or_all(union(&mut train.iter().map(|&i| ranges[i].x_mm)), everything);
        let all_v = or_all(union(&mut train.iter().map(|&i| ranges[i].v_m_s)), everything);
        let a = or_all(union(&mut train.iter().map(|&i| ranges[i].a_m_s2)), everything);
        let at = |c: f64| train.iter().copied().filter(move |&i| prep.recs[i].current_a == c);
        Span {
            x_mm: prep
                .currents_a
                .iter()
                .map(|&c| or_all(union(&mut at(c).map(|i| ranges[i].x_mm)), all_x))
                .collect(),
            v_m_s: prep
                .currents_a
                .iter()
                .map(|&c| or_all(union(&mut at(c).map(|i| ranges[i].v_m_s)), all_v))
                .collect(),
            all_x_mm: all_x,
            a_m_s2: a,
        }
    }

    /// A recording with these ranges, at every current it touches, stays
    /// inside the span.
    fn covers(&self, r: &Ranges, touched: &[usize]) -> bool {
        within(r.x_mm, self.all_x_mm)
            && within(r.a_m_s2, self.a_m_s2)
            && touched
                .iter()
                .all(|&k| within(r.x_mm, self.x_mm[k]) && within(r.v_m_s, self.v_m_s[k]))
    }

    /// Where current `k`'s columns are evaluated for sample `s`
    /// ([`tangent_points`]).
    fn points(&self, k: usize, s: &Sample) -> [(f64, Sample); 2] {
        tangent_points(s, [self.x_mm[k], self.v_m_s[k], self.a_m_s2])
    }

    /// As [`Span::points`] for the global columns (x over every current).
    fn points_global(&self, s: &Sample) -> [(f64, Sample); 2] {
        let everything = (f64::NEG_INFINITY, f64::INFINITY);
        tangent_points(s, [self.all_x_mm, everything, self.a_m_s2])
    }

    /// `x_r^p` inside current `k`'s x span, continued along its tangent
    /// beyond it.
    fn power(&self, k: usize, x_r: f64, p: i32) -> f64 {
        let (lo, hi) = self.x_mm[k];
        let e = x_r.clamp(lo, hi);
        if p == 0 {
            1.0
        } else {
            e.powi(p) + f64::from(p) * e.powi(p - 1) * (x_r - e)
        }
    }
}

/// The one-sided step of [`tangent_points`], as a fraction of the span's width.
const TANGENT_STEP: f64 = 0.02;

/// The points, with weights, at which a column is evaluated so that its
/// value beyond `bounds` (x, v, a) continues along its tangent at the edge:
/// inside, `s` itself (weight 1, the second weight 0); outside, the edge
/// point `e` and a point `e − η·d` inside (d = s − e), weighted `1 + 1/η`
/// and `−1/η`, i.e. `f(e) + (f(e) − f(e − η·d))/η`, a one-sided difference
/// over 2 % of the span's width. A span of zero width has no tangent: the
/// column is held at its edge value.
fn tangent_points(s: &Sample, bounds: [(f64, f64); 3]) -> [(f64, Sample); 2] {
    let at = [s.x_mm, s.v_m_s, s.a_m_s2];
    let edge = [0, 1, 2].map(|j| at[j].clamp(bounds[j].0, bounds[j].1));
    let d = [0, 1, 2].map(|j| at[j] - edge[j]);
    let sample = |c: [f64; 3]| Sample {
        x_mm: c[0],
        v_m_s: c[1],
        a_m_s2: c[2],
        v_lag_m_s: s.v_lag_m_s,
    };
    if d.iter().all(|dj| *dj == 0.0) {
        return [(1.0, *s), (0.0, *s)];
    }
    let eta = (0..3)
        .filter(|&j| d[j] != 0.0)
        .map(|j| TANGENT_STEP * (bounds[j].1 - bounds[j].0) / d[j].abs())
        .fold(1.0f64, f64::min);
    if eta <= 0.0 || !eta.is_finite() {
        return [(1.0, sample(edge)), (0.0, sample(edge))];
    }
    let inner = [0, 1, 2].map(|j| edge[j] - eta * d[j]);
    [(1.0 + 1.0 / eta, sample(edge)), (-1.0 / eta, sample(inner))]
}

impl Designs {
    pub fn build(prep: &Prepared, terms: &Terms) -> Designs {
        let layout = Layout::new(prep.currents_a.len(), terms);
        let span = prep
            .fit_indices()
            .iter()
            .flat_map(|&i| prep.recs[i].x_mm.iter().copied())
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(l, h), x| (l.min(x), h.max(x)));
        let start_mm = (START_SPAN_FRACTION * (span.1 - span.0)).max(1e-9);
        let recs = prep
            .recs
            .iter()
            .map(|r| design_for(prep, r, terms, &layout, start_mm, None))
            .collect();
        Designs {
            terms: *terms,
            layout,
            recs,
            start_mm,
            ranges: prep.recs.iter().map(Ranges::of).collect(),
        }
    }

    /// Solves over `train` with fixed per-recording scales (1 if `None`).
    pub fn solve_scaled(&self, prep: &Prepared, train: &[usize], scale: &dyn Fn(usize) -> f64) -> Result<Solution> {
        self.solve_rows(prep, train, scale, 0.0)
    }

    /// As [`Designs::solve_scaled`], each recording's rows
    /// `scale·R_A − delta·R_G` where it has an `R_G` (a within-test law).
    fn solve_rows(
        &self,
        prep: &Prepared,
        train: &[usize],
        scale: &dyn Fn(usize) -> f64,
        delta: f64,
    ) -> Result<Solution> {
        let rows: usize = train
            .iter()
            .map(|&i| self.recs[i].r_a.as_ref().map_or(0, |r| r.nrows()))
            .sum();
        let p = self.layout.n_cols;
        let mut a = DMatrix::<f64>::zeros(rows, p);
        let mut y = DVector::<f64>::zeros(rows);
        let mut at = 0;
        for &i in train {
            let d = &self.recs[i];
            let (Some(ra), Some(ry)) = (&d.r_a, &d.r_y) else {
                continue;
            };
            let s = scale(i);
            let rg = d.r_g.as_ref().filter(|g| g.shape() == ra.shape());
            for row in 0..ra.nrows() {
                for (lc, &gc) in d.cols.iter().enumerate() {
                    a[(at + row, gc)] = s * ra[(row, lc)] - rg.map_or(0.0, |g| delta * g[(row, lc)]);
                }
                y[at + row] = ry[row];
            }
            at += ra.nrows();
        }
        // Columns no training recording touches (e.g. an end stop nobody
        // reached) are left out and get a zero coefficient.
        let mut used: Vec<usize> = (0..p).filter(|&c| a.column(c).iter().any(|v| *v != 0.0)).collect();
        // Sign constraints ([`Term::nonnegative`]: a stop's stiffness, a
        // damping coefficient, a yield force, a mass): least squares with
        // those columns ≥ 0, by an active set over the handful of them
        // (Lawson–Hanson's, with the other columns free). A column whose
        // value comes out negative is held at 0; a held one whose gradient
        // says it would come back positive is released.
        let constrained: Vec<usize> = self
            .layout
            .blocks
            .iter()
            .filter(|p| p.term.nonnegative(&self.terms, p.index))
            .flat_map(|p| {
                let n = match p.block {
                    Block::PerCurrent => self.layout.n_currents,
                    Block::Global => 1,
                    Block::MemoryBasis => 2 * MEMORY_TERMS * self.layout.n_currents,
                };
                p.at..p.at + n
            })
            .filter(|c| used.contains(c))
            .collect();
        let mut held: Vec<usize> = Vec::new();
        let mut last_feasible: Option<Solution> = None;
        // Each pass holds or releases at least one column; the bound keeps a
        // cycle finite (it then returns the last feasible solution).
        for _ in 0..4 * constrained.len() + 4 {
            used.retain(|c| !held.contains(c));
            let ls = linalg::solve(&a.select_columns(&used), &y)?;
            let mut beta = vec![0.0; p];
            for (k, &c) in used.iter().enumerate() {
                beta[c] = ls.coeffs[k];
            }
            let negative: Vec<usize> = constrained.iter().copied().filter(|&c| beta[c] < 0.0).collect();
            if !negative.is_empty() {
                held.extend(negative);
                continue;
            }
            // Feasible. KKT: a held column whose residual correlation is
            // positive would lower the SSE above 0.
            let residual = &y - &a * DVector::from_column_slice(&beta);
            let release = held
                .iter()
                .copied()
                .map(|c| {
                    (
                        c,
                        a.column(c).dot(&residual) / a.column(c).norm().max(f64::MIN_POSITIVE),
                    )
                })
                .filter(|(_, g)| *g > 1e-9 * residual.norm().max(1.0))
                .max_by(|l, r| l.1.total_cmp(&r.1));
            let sol = Solution {
                beta,
                delta: 0.0,
                sse: ls.sse,
                span: Span::from_ranges(prep, &self.ranges, train),
                at_bound: held.clone(),
            };
            match release {
                Some((c, _)) => {
                    held.retain(|&h| h != c);
                    used.push(c);
                    used.sort_unstable();
                    last_feasible = Some(sol);
                }
                None => return Ok(sol),
            }
        }
        last_feasible.ok_or_else(|| anyhow::anyhow!("the sign-constrained least squares did not settle"))
    }

    /// Solves over `train`. With softening, `F = (1 − Δ·g_r)·Q(x)`: for a
    /// given Δ, Q is one scaled linear solve, so Δ is found by golden-section
    /// search on the training SSE (alternating updates crawl, because Q's
    /// scale and Δ are nearly interchangeable when most tests have softened).
    pub fn solve(&self, prep: &Prepared, train: &[usize]) -> Result<Solution> {
        self.solve_in(prep, train, (-0.3, 0.6), 10)
    }

    /// As [`Designs::solve`], searching Δ within `bracket` only (e.g. near
    /// the full-data Δ when refitting a cross-validation fold).
    pub fn solve_in(
        &self,
        prep: &Prepared,
        train: &[usize],
        bracket: (f64, f64),
        iterations: usize,
    ) -> Result<Solution> {
        let Some(law) = self.terms.softening else {
            return self.solve_scaled(prep, train, &|_| 1.0);
        };
        let within = law.within_test();
        let g: Vec<f64> = prep.recs.iter().map(|r| law.covariate(r)).collect();
        let at = |delta: f64| {
            let solved = if within {
                self.solve_rows(prep, train, &|_| 1.0, delta)
            } else {
                self.solve_scaled(prep, train, &|i| 1.0 - delta * g[i])
            };
            solved.map(|mut s| {
                s.delta = delta;
                s
            })
        };
        let (mut lo, mut hi) = bracket;
        let phi = 0.5 * (5f64.sqrt() - 1.0);
        let (mut a, mut b) = (hi - phi * (hi - lo), lo + phi * (hi - lo));
        let (mut fa, mut fb) = (at(a)?, at(b)?);
        for _ in 0..iterations {
            if fa.sse < fb.sse {
                hi = b;
                b = a;
                fb = fa;
                a = hi - phi * (hi - lo);
                fa = at(a)?;
            } else {
                lo = a;
                a = b;
                fa = fb;
                b = lo + phi * (hi - lo);
                fb = at(b)?;
            }
        }
        Ok(if fa.sse < fb.sse { fa } else { fb })
    }

    /// Predicted force of recording `i`. Where a recording leaves the span of
    /// `sol`'s training recordings, each column continues along its tangent
    /// at the span's edge ([`Span`]).
    pub fn predict(&self, prep: &Prepared, i: usize, sol: &Solution) -> Vec<f64> {
        let s: Vec<f64> = match self.terms.softening {
            Some(law) => law
                .per_sample(&prep.recs[i])
                .iter()
                .map(|g| 1.0 - sol.delta * g)
                .collect(),
            None => vec![1.0; prep.recs[i].len()],
        };
        let stored = &self.recs[i];
        let touched: Vec<usize> = (0..self.layout.n_currents)
            .filter(|&k| {
                stored.cols.contains(&self.layout.quartic_col(k, true, 0))
                    || stored.cols.contains(&self.layout.quartic_col(k, false, 0))
            })
            .collect();
        let mut p = if sol.span.covers(&self.ranges[i], &touched) {
            stored.predict(&sol.beta)
        } else {
            let continued = design_for(
                prep,
                &prep.recs[i],
                &self.terms,
                &self.layout,
                self.start_mm,
                Some(&sol.span),
            );
            // Columns the terms do not build (an oracle's extra column) are
            // kept as stored.
            let mut p = continued.predict(&sol.beta);
            let built = Layout::new(self.layout.n_currents, &self.terms).n_cols;
            for (lc, &c) in stored.cols.iter().enumerate() {
                if c >= built && continued.cols.binary_search(&c).is_err() {
                    for (t, v) in p.iter_mut().enumerate() {
                        *v += stored.a[(t, lc)] * sol.beta[c];
                    }
                }
            }
            p
        };
        p.iter_mut().zip(&s).for_each(|(v, s)| *v *= s);
        p
    }
}

/// `start_mm`: the relaxation length of a start from rest ([`START_SPAN_FRACTION`]).
/// `span`: continue each column along its tangent beyond it (a prediction
/// beyond its fit's training recordings), or `None` (as recorded).
fn design_for(
    prep: &Prepared,
    rec: &Rec,
    terms: &Terms,
    layout: &Layout,
    start_mm: f64,
    span: Option<&Span>,
) -> RecDesign {
    // Interpolation weights per sample: one set for a held current, one per
    // sample when the recorded current changes during the test.
    // A delayed force channel shows the current of τ ago too.
    let weights_at: Vec<[(usize, f64); 2]> = match rec.current_trace_a {
        Some(_) => {
            let current = effective_current_a(rec, terms.coil_lag_s);
            let mut hint = 0;
            (0..rec.len())
                .map(|t| match terms.delay_s {
                    Some(tau) => sample_at(&rec.time_s, &current, rec.time_s[t] - tau, &mut hint),
                    None => current[t],
                })
                .map(|i| current_weights(&prep.currents_a, i, terms.saturation_i_a))
                .collect()
        }
        None => vec![current_weights(&prep.currents_a, rec.current_a, terms.saturation_i_a)],
    };
    let mut touched: Vec<usize> = weights_at
        .iter()
        .flat_map(|ws| ws.iter().filter(|(_, w)| *w != 0.0).map(|(k, _)| *k))
        .collect();
    touched.sort_unstable();
    touched.dedup();
    let mut cols: Vec<usize> = Vec::new();
    for &k in &touched {
        for comp in [true, false] {
            for p in 0..QUARTIC_TERMS {
                cols.push(layout.quartic_col(k, comp, p));
            }
        }
        for p in layout.blocks.iter().filter(|p| p.block == Block::PerCurrent) {
            cols.push(p.at + k);
        }
    }
    for comp in [true, false] {
        for j in 0..MEMORY_TERMS {
            for &k in &touched {
                cols.extend(layout.memory_col(comp, j, k));
            }
        }
    }
    cols.extend(layout.blocks.iter().filter(|p| p.block == Block::Global).map(|p| p.at));
    cols.sort_unstable();
    cols.dedup();
    let local = |c: usize| cols.binary_search(&c).unwrap_or(0);
    let n = rec.len();
    let mut a = DMatrix::<f64>::zeros(n, cols.len());
    let (mut hx, mut hv, mut ha) = (0, 0, 0);
    let (xs, vs, accs): (Vec<f64>, Vec<f64>, Vec<f64>) = match terms.delay_s {
        Some(tau) => (0..n)
            .map(|t| {
                let ts = rec.time_s[t] - tau;
                (
                    sample_at(&rec.time_s, &rec.x_mm, ts, &mut hx),
                    sample_at(&rec.time_s, &rec.v_m_s, ts, &mut hv),
                    sample_at(&rec.time_s, &rec.a_m_s2, ts, &mut ha),
                )
            })
            .fold((vec![], vec![], vec![]), |(mut a, mut b, mut c), (x, v, acc)| {
                a.push(x);
                b.push(v);
                c.push(acc);
                (a, b, c)
            }),
        None => (rec.x_mm.clone(), rec.v_m_s.clone(), rec.a_m_s2.clone()),
    };
    let v_lag = match terms.viscous {
        Some(Viscous::Maxwell { tau_s }) => super::terms::maxwell_velocity_m_s(&rec.time_s, &vs, tau_s),
        _ => Vec::new(),
    };
    let memory = terms
        .memory_mm
        .map(|_| memory_feature_on_branches(&rec.time_s, &xs, &vs, rec.branch_band_m_s()));
    // Per basis length: the share of a full turn-around still ahead.
    let shares: Vec<Vec<f64>> = match (&memory, terms.memory_mm) {
        (Some((m, dir)), Some(delta)) => {
            let from_rest = m.first().copied().flatten().is_some_and(|a| a.from_rest);
            MEMORY_LENGTHS
                .iter()
                .map(|len| reversal_share(&xs, dir, len * delta, from_rest))
                .collect()
        }
        _ => Vec::new(),
    };
    let per_current: Vec<&Placed> = layout.blocks.iter().filter(|p| p.block == Block::PerCurrent).collect();
    let global: Vec<&Placed> = layout.blocks.iter().filter(|p| p.block == Block::Global).collect();
    for t in 0..n {
        let (x, v, acc) = (xs[t], vs[t], accs[t]);
        let sample = Sample {
            x_mm: x,
            v_m_s: v,
            a_m_s2: acc,
            v_lag_m_s: v_lag.get(t).copied().unwrap_or(v),
        };
        let comp = v > 0.0;
        let weights = &weights_at[t.min(weights_at.len() - 1)];
        for &(k, w) in weights {
            if w == 0.0 {
                continue;
            }
            // The branch stays the recorded one; only the covariates move.
            let points = span.map_or([(1.0, sample), (0.0, sample)], |s| s.points(k, &sample));
            for (weight, at_k) in points.into_iter().filter(|(weight, _)| *weight != 0.0) {
                let mut xp = w * weight;
                for p in 0..QUARTIC_TERMS {
                    a[(t, local(layout.quartic_col(k, comp, p)))] += xp;
                    xp *= at_k.x_mm;
                }
                for p in &per_current {
                    a[(t, local(p.at + k))] += w * weight * p.term.shape(terms, p.index, &at_k);
                }
            }
        }
        if let (Some((m, dir)), Some(_)) = (&memory, terms.memory_mm) {
            if let Some(Anchor {
                distance_mm: d,
                x_r_mm: x_r,
                from_rest,
            }) = m[t]
            {
                // (column, decay, power of x_r), no allocation per sample
                let mut basis = [(0usize, 0.0f64, 0i32); MEMORY_TERMS];
                let used = if from_rest {
                    basis[0] = (MEMORY_TERMS - 1, (-d / start_mm).exp(), 0);
                    1
                } else {
                    for (l, share) in shares.iter().enumerate() {
                        let e = share[t];
                        for p in 0..MEMORY_POWERS {
                            basis[l * MEMORY_POWERS + p] = (l * MEMORY_POWERS + p, e, p as i32);
                        }
                    }
                    MEMORY_TERMS - 1
                };
                for &(k, w) in weights.iter().filter(|(_, w)| *w != 0.0) {
                    for &(j, decay, p) in &basis[..used] {
                        // x_r^p beyond the span continues along its tangent
                        // (the decay is bounded already).
                        let x_r_p = span.map_or(x_r.powi(p), |s| s.power(k, x_r, p));
                        if let Some(c) = layout.memory_col(dir[t], j, k) {
                            a[(t, local(c))] += w * decay * x_r_p;
                        }
                    }
                }
            }
        }
        let points = span.map_or([(1.0, sample), (0.0, sample)], |s| s.points_global(&sample));
        for p in &global {
            a[(t, local(p.at))] = points
                .iter()
                .filter(|(weight, _)| *weight != 0.0)
                .map(|(weight, at)| weight * p.term.shape(terms, p.index, at))
                .sum();
        }
    }
    // Keep only the columns this recording touches (e.g. no compression
    // memory in a drop, which never reverses into compression).
    let keep: Vec<usize> = (0..cols.len())
        .filter(|&c| a.column(c).iter().any(|v| *v != 0.0))
        .collect();
    let (cols, a) = if keep.len() < cols.len() {
        (
            keep.iter().map(|&c| cols[c]).collect::<Vec<_>>(),
            a.select_columns(&keep),
        )
    } else {
        (cols, a)
    };
    let mask = rec.scored_mask(terms.delay_s);
    let (r_a, r_g, r_y) = match terms.softening {
        Some(law) if law.within_test() => compress_softened(rec, &a, &law.per_sample(rec), &mask),
        _ => {
            let (r_a, r_y) = compress(rec, &a, &mask);
            (r_a, None, r_y)
        }
    };
    RecDesign {
        cols,
        a,
        r_a,
        r_y,
        r_g,
        mask,
    }
}

/// The R factor of the QR of `[A | y]` over the masked samples of a fit
/// recording (validate recordings are never fitted: `None`).
pub fn compress(rec: &Rec, a: &DMatrix<f64>, mask: &[bool]) -> (Option<DMatrix<f64>>, Option<DVector<f64>>) {
    if !rec.is_fit() {
        return (None, None);
    }
    // Only the samples where the model is defined are fitted.
    let rows: Vec<usize> = (0..a.nrows()).filter(|&t| mask[t]).collect();
    let c = a.ncols();
    let mut ay = DMatrix::<f64>::zeros(rows.len(), c + 1);
    ay.view_mut((0, 0), (rows.len(), c)).copy_from(&a.select_rows(&rows));
    ay.set_column(
        c,
        &DVector::from_iterator(rows.len(), rows.iter().map(|&t| rec.force_n[t])),
    );
    let r = ay.qr().r();
    (Some(r.columns(0, c).into_owned()), Some(r.column(c).into_owned()))
}

/// As [`compress`] for a within-test softening: the R factor of
/// `[A | G | y]`, `G` each column of A times the sample's covariate `g`,
/// split into `R_A`, `R_G` and `r_y` (one Q holds `A − ΔG` and y for every Δ).
#[allow(clippy::type_complexity)]
pub fn compress_softened(
    rec: &Rec,
    a: &DMatrix<f64>,
    g: &[f64],
    mask: &[bool],
) -> (Option<DMatrix<f64>>, Option<DMatrix<f64>>, Option<DVector<f64>>) {
    if !rec.is_fit() {
        return (None, None, None);
    }
    let rows: Vec<usize> = (0..a.nrows()).filter(|&t| mask[t]).collect();
    let (r_a, r_g, r_y) = softened_r(a, g, &rec.force_n, &rows);
    (Some(r_a), Some(r_g), Some(r_y))
}

/// `R_A, R_G, r_y` of the QR of `[A | G | y]` over `rows`.
fn softened_r(a: &DMatrix<f64>, g: &[f64], y: &[f64], rows: &[usize]) -> (DMatrix<f64>, DMatrix<f64>, DVector<f64>) {
    let c = a.ncols();
    let mut m = DMatrix::<f64>::zeros(rows.len(), 2 * c + 1);
    for (k, &t) in rows.iter().enumerate() {
        for l in 0..c {
            m[(k, l)] = a[(t, l)];
            m[(k, c + l)] = a[(t, l)] * g[t];
        }
        m[(k, 2 * c)] = y[t];
    }
    let r = m.qr().r();
    (
        r.columns(0, c).into_owned(),
        r.columns(c, c).into_owned(),
        r.column(2 * c).into_owned(),
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Evidence: hand-written. A 3-cycle sine from x = 0, 100 samples a
    /// cycle, with a ±0.05 mm wiggle (below the band: 10 % of the 2 mm
    /// stroke): reversals at the peaks and troughs, samples 25, 75, 125, …,
    /// 275; a cycle ends every second one.
    #[test]
    fn cycles_are_counted_every_two_reversals() {
        let x: Vec<f64> = (0..=300)
            .map(|t| {
                let p = 2.0 * std::f64::consts::PI * t as f64 / 100.0;
                p.sin() + 0.05 * (13.0 * p).sin()
            })
            .collect();
        let k = cycle_index(&x);
        assert_eq!((k[0], k[70]), (1.0, 1.0));
        assert_eq!((k[80], k[170]), (2.0, 2.0));
        assert_eq!((k[180], k[270]), (3.0, 3.0));
        assert_eq!((k[280], k[300]), (4.0, 4.0));
        // A flat record has one cycle.
        assert!(cycle_index(&[0.0; 10]).iter().all(|&k| k == 1.0));
    }

    /// Evidence: linear algebra (a Q with orthonormal columns keeps norms).
    /// `‖(A − ΔG)β − y‖` on the rows equals `‖(R_A − ΔR_G)β − r_y‖` on the
    /// compressed ones for any Δ and β, since `[A | G | y]·z` with
    /// `z = (β, −Δβ, −1)` is `Q·R·z`.
    #[test]
    fn one_factoring_serves_every_softening_depth() {
        let n = 60;
        let a = DMatrix::from_fn(n, 3, |t, l| ((t * (l + 2)) as f64 * 0.37).sin() + l as f64);
        let g: Vec<f64> = (0..n).map(|t| 1.0 - (-(t as f64) / 20.0).exp()).collect();
        let y: Vec<f64> = (0..n).map(|t| (t as f64 * 0.11).cos() * 5.0).collect();
        let rows: Vec<usize> = (0..n).filter(|t| t % 7 != 3).collect();
        let (ra, rg, ry) = softened_r(&a, &g, &y, &rows);
        let beta = DVector::from_vec(vec![1.5, -0.7, 2.0]);
        for delta in [-0.2, 0.0, 0.35] {
            let raw: f64 = rows
                .iter()
                .map(|&t| {
                    let f = (1.0 - delta * g[t]) * (a.row(t) * &beta)[0];
                    (f - y[t]).powi(2)
                })
                .sum::<f64>()
                .sqrt();
            let packed = ((&ra - &rg * delta) * &beta - &ry).norm();
            assert!((raw - packed).abs() < 1e-9 * raw, "Δ = {delta}: {raw} vs {packed}");
        }
    }

    /// Hand-written physics: a Dahl element `F = f₀·z`, `dz/dx = (s − z)/L`
    /// (s = ±1 the direction of travel), integrated by small Euler steps
    /// (its own integration, not the closed form), on a stroke with a minor
    /// loop: up 0 → 10 mm (saturates), down to 9.5 mm, up to 12 mm. Its
    /// force after each reversal is `s·f₀·(1 − 2·share)`, so the memory
    /// column `share` must follow it at the minor reversal too, where the
    /// material recovers only what the 0.5 mm stroke displaced: the share
    /// there starts at `1 − e^{−0.5} = 0.393`, not at 1 as after a full
    /// stroke (the column before the fix, `e^{−d/L}`, is off by 0.61).
    #[test]
    fn the_reversal_share_follows_a_dahl_element_through_a_minor_loop() {
        let length_mm = 1.0;
        let h = 1e-4;
        let mut x = Vec::new();
        let ramp = |x: &mut Vec<f64>, from: f64, to: f64| {
            let n = ((to - from) / h).abs().round() as usize;
            x.extend((1..=n).map(|k| from + (to - from) * k as f64 / n as f64));
        };
        x.push(0.0);
        ramp(&mut x, 0.0, 10.0);
        ramp(&mut x, 10.0, 9.5);
        ramp(&mut x, 9.5, 12.0);
        let compressing: Vec<bool> = (0..x.len())
            .map(|t| if t == 0 { true } else { x[t] > x[t - 1] })
            .collect();
        let share = reversal_share(&x, &compressing, length_mm, false);
        // Euler on the Dahl law, started saturated (z = 1).
        let mut z = 1.0f64;
        let mut worst = 0.0f64;
        for t in 1..x.len() {
            let s = if compressing[t] { 1.0 } else { -1.0 };
            z += (s - z) * (x[t] - x[t - 1]).abs() / length_mm;
            worst = worst.max((z - s * (1.0 - 2.0 * share[t])).abs());
        }
        assert!(worst < 1e-3, "Dahl force vs column: {worst}");
        // By hand: just after the minor reversal at 9.5 mm.
        let at = (1..x.len())
            .find(|&t| compressing[t] && !compressing[t - 1])
            .expect("the minor reversal");
        assert!((x[at - 1] - 9.5).abs() < 1e-9);
        assert!((share[at] - (1.0 - (-0.5f64).exp())).abs() < 1e-3, "{}", share[at]);
    }
}
