//! Arming before contact: the coil current to have at contact, from the
//! identified model (the table), for a coil too slow to set it during the
//! impact.
//!
//! A mass `m` arriving at `v` at a constant current `I` stops within the
//! usable stroke `s` when the damper's work over the stroke covers the
//! kinetic energy and the weight's work (energy balance):
//! `W_I(s) = ∫₀ˢ F_I(x) dx ≥ ½·m·v² + m·g·s`. With `F_I` the table's
//! compression branch, `W_I` is a quintic per entry (integrated exactly,
//! with the entry's x clamp: constant force outside its fitted stroke), and
//! linear in the interpolation fraction between two entries, so the lowest
//! current that stops the mass within `s` ([`Arming::stop_current_a`])
//! needs one comparison per entry, no iteration. The viscous term is left
//! out: it only adds force, so the current found errs stiff.
//!
//! Without a predicted impact velocity ([`Arming::robust_current_a`]) the law
//! arms for the fastest impact the installation expects, `v_max`. Among
//! fixed currents this is the minimax choice over `[v_min, v_max]`: every
//! fixed current below it runs past the stroke at `v_max`, and at each
//! velocity a higher current stops sooner and harder (higher peak), so every
//! fixed current above it has a higher worst case.
use crate::math;
use crate::table::{CurrentEntry, Table, MAX_CURRENTS};

/// The arming currents of one table, stroke and mass (computed when the table
/// changes, not per period).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Arming {
    /// Work (J) each entry's compression branch does over the usable stroke.
    work_j: [f32; MAX_CURRENTS],
    /// Each entry's interpolation knot (current, or `tanh(I/I_s)`) and current.
    knots: [f32; MAX_CURRENTS],
    currents_a: [f32; MAX_CURRENTS],
    len: usize,
    saturation_current_a: f32,
    half_mass_kg: f32,
    /// `m·g·s`: the weight's work over the stroke (J).
    weight_work_j: f32,
    robust_a: f32,
}

impl Arming {
    /// No table yet: arms at 0 A.
    pub const NONE: Arming = Arming {
        work_j: [0.0; MAX_CURRENTS],
        knots: [0.0; MAX_CURRENTS],
        currents_a: [0.0; MAX_CURRENTS],
        len: 0,
        saturation_current_a: 0.0,
        half_mass_kg: 0.0,
        weight_work_j: 0.0,
        robust_a: 0.0,
    };

    /// The arming currents for `table`, a mass of `mass_kg` and `stroke_mm`
    /// of usable stroke; the robust one for impacts up to `v_max_m_s`.
    pub fn new(table: &Table, mass_kg: f32, gravity_m_s2: f32, stroke_mm: f32, v_max_m_s: f32) -> Arming {
        let mut a = Arming::NONE;
        for (k, e) in table.entries().iter().enumerate() {
            if let (Some(w), Some(knot), Some(i)) = (a.work_j.get_mut(k), a.knots.get_mut(k), a.currents_a.get_mut(k)) {
                *w = compression_work_j(e, stroke_mm);
                *knot = table.knot(k);
                *i = e.current_a;
                a.len = k.wrapping_add(1);
            }
        }
        a.saturation_current_a = table.terms().saturation_current_a;
        a.half_mass_kg = 0.5 * mass_kg;
        a.weight_work_j = mass_kg * gravity_m_s2 * stroke_mm * 1.0e-3;
        a.robust_a = a.stop_current_a(v_max_m_s);
        a
    }

    /// The current for an impact anywhere up to the installation's `v_max`.
    pub fn robust_current_a(&self) -> f32 {
        self.robust_a
    }

    /// The lowest current (A) at which the model stops a mass arriving at
    /// `v_m_s` within the usable stroke: the first entry whose work covers
    /// the energy, interpolated with the entry below. At or below the lowest
    /// entry's work: the lowest current; beyond the highest entry's (the
    /// model cannot stop it) or for a non-finite velocity: the highest.
    pub fn stop_current_a(&self, v_m_s: f32) -> f32 {
        let energy_j = self.half_mass_kg * v_m_s * v_m_s + self.weight_work_j;
        let n = self.len.min(MAX_CURRENTS);
        let (work, _) = self.work_j.split_at(n);
        let (knots, _) = self.knots.split_at(n);
        let (currents, _) = self.currents_a.split_at(n);
        let highest_a = currents.last().copied().unwrap_or(0.0);
        if !energy_j.is_finite() {
            return highest_a;
        }
        let mut below: Option<(f32, f32, f32)> = None;
        for ((&w, &knot), &current_a) in work.iter().zip(knots).zip(currents) {
            if w >= energy_j {
                return match below {
                    // Work is linear in the fraction t between the knots.
                    Some((w0, k0, _)) if w > w0 => {
                        let t = (energy_j - w0) / (w - w0);
                        self.current_at_knot(k0 + t * (knot - k0))
                    }
                    _ => current_a,
                };
            }
            below = Some((w, knot, current_a));
        }
        highest_a
    }

    /// The current whose interpolation knot is `knot`: the knot itself, or
    /// `I_s·atanh(knot)` under saturation.
    fn current_at_knot(&self, knot: f32) -> f32 {
        if self.saturation_current_a > 0.0 {
            self.saturation_current_a * math::atanh(knot)
        } else {
            knot
        }
    }
}

/// Work (J) of `entry`'s compression quartic from 0 to `stroke_mm`, with the
/// model's clamp: the force at the end of the fitted stroke outside it.
pub fn compression_work_j(entry: &CurrentEntry, stroke_mm: f32) -> f32 {
    let q = &entry.compression;
    let (lo, hi) = (entry.x_min_mm, entry.x_max_mm);
    let s = stroke_mm;
    // Below the fitted stroke (from 0 up to x_min): the force at x_min.
    let below_n_mm = q.eval(lo) * (math::clamp(s, 0.0, lo) - math::clamp(0.0, 0.0, lo));
    // Inside it: the quartic's antiderivative.
    let a = math::clamp(0.0, lo, hi);
    let b = math::clamp(s, lo, hi);
    let inside_n_mm = antiderivative(&q.coeffs, b) - antiderivative(&q.coeffs, a);
    // Beyond it: the force at x_max.
    let above_n_mm = if s > hi { q.eval(hi) * (s - hi) } else { 0.0 };
    (below_n_mm + inside_n_mm + above_n_mm) * 1.0e-3
}

/// `∫₀ˣ (c₀x⁴ + c₁x³ + c₂x² + c₃x + c₄) dx` by Horner (N·mm).
fn antiderivative(c: &[f32; 5], x: f32) -> f32 {
    let [a4, a3, a2, a1, a0] = *c;
    ((((a4 / 5.0 * x + a3 / 4.0) * x + a2 / 3.0) * x + a1 / 2.0) * x + a0) * x
}

/// The time (s) a first-order coil (`τ`) driven at the supply's limit
/// (`drive_max_a`, `drive_min_a`: V_s/R, −V_s/R or 0) takes from `from_a`
/// to `to_a`: `τ·ln((u − i₀)/(u − i₁))`, u the limit towards `to_a`. What
/// the approach must leave before contact for the armed current to be
/// there. Infinite when the drive cannot reach `to_a`.
pub fn lead_time_s(tau_s: f32, from_a: f32, to_a: f32, drive_min_a: f32, drive_max_a: f32) -> f32 {
    let u = if to_a >= from_a { drive_max_a } else { drive_min_a };
    let ratio = (u - from_a) / (u - to_a);
    // NaN, below 1 (the drive cannot reach `to_a`) or infinite: never.
    if ratio.is_nan() || ratio < 1.0 || ratio.is_infinite() {
        return if from_a == to_a { 0.0 } else { f32::INFINITY };
    }
    tau_s * math::ln(ratio)
}
