//! Spencer's modified Bouc–Wen model (Spencer, Dyke, Sain, Carlson,
//! "Phenomenological model for magnetorheological dampers", J. Eng. Mech. 1997):
//!
//! F = c1·ẏ + k1·x + f0,
//! ẏ = (α·z + c0·ẋ + k0·(x − y)) / (c0 + c1),
//! ż = (ẋ − ẏ)/x_y · (1 − z²(β·sgn((ẋ − ẏ)z) + γ)),  β + γ = 1, r = β − γ,
//!
//! with Spencer's current laws α = αa + αb·I, c0 = c0a + c0b·I, c1 = c1a + c1b·I
//! (his first-order coil filter is left out: the recordings hold the current
//! constant). One parameter set for every current. Integrated in time with
//! the midpoint rule (at most [`MAX_SUBSTEPS`] sub-steps per sample), ẋ and x linear within each sample interval.
use super::bouc_wen::shape_rate;
use super::{all_finite, CurrentLaw, Family, Scales, StepCost};
use crate::compare::tracks::Track;

pub struct Spencer;

/// Parameters whose dynamics need more midpoint sub-steps per sample than
/// this are inadmissible (the explicit rule would be unstable or slow).
pub const MAX_SUBSTEPS: usize = 64;

/// mm per m: ẏ is in m/s, y in mm.
const MM_PER_M: f64 = 1000.0;

struct State {
    y_mm: f64,
    z: f64,
}

struct Coeffs {
    alpha: f64,
    c0: f64,
    c1: f64,
    k0: f64,
    x_y: f64,
    r: f64,
}

impl Coeffs {
    /// ẏ (m/s) and ż (1/s) at displacement x (mm), velocity v (m/s).
    #[inline]
    fn rates(&self, s: &State, x: f64, v: f64) -> (f64, f64) {
        let y_dot = (self.alpha * s.z + self.c0 * v + self.k0 * (x - s.y_mm)) / (self.c0 + self.c1);
        let rel = v - y_dot;
        let z_dot = rel * MM_PER_M / self.x_y * shape_rate(s.z, rel.signum(), self.r);
        (y_dot, z_dot)
    }
}

impl Family for Spencer {
    fn name(&self) -> &'static str {
        "spencer"
    }

    fn equations(&self) -> &'static str {
        "F = c1·ẏ + k1·x + f0; ẏ = (αz + c0ẋ + k0(x − y))/(c0 + c1); ż = (ẋ − ẏ)/x_y·(1 − z²(β·sgn + γ)), β + γ = 1; α, c0, c1 linear in I"
    }

    fn param_names(&self) -> &'static [&'static str] {
        &[
            "alpha_a_n",
            "alpha_b_n_per_a",
            "c0a_n_s_m",
            "c0b_n_s_m_per_a",
            "c1a_n_s_m",
            "c1b_n_s_m_per_a",
            "k0_n_mm",
            "k1_n_mm",
            "f0_n",
            "x_y_mm",
            "r",
        ]
    }

    fn law(&self) -> CurrentLaw {
        CurrentLaw::Joint
    }

    fn bounds(&self, s: &Scales) -> (Vec<f64>, Vec<f64>) {
        let (f, x, v, i) = (s.force_n, s.x_mm, s.v_m_s, s.current_a);
        let c = f / v;
        (
            vec![0.0, -2.0 * f / i, 0.0, -2.0 * c / i, 0.05 * c, -20.0 * c / i, 0.0, -f / x, -0.5 * f, 0.002 * x, -1.0],
            vec![2.0 * f, 2.0 * f / i, 2.0 * c, 2.0 * c / i, 20.0 * c, 20.0 * c / i, f / x, 2.0 * f / x, 0.5 * f, 0.5 * x, 1.0],
        )
    }

    fn simulate(&self, p: &[f64], track: &Track, out: &mut Vec<f64>) -> bool {
        let &[alpha_a, alpha_b, c0a, c0b, c1a, c1b, k0, k1, f0, x_y, r] = p else {
            return false;
        };
        let i = track.current_a;
        // Laws are clamped at zero: a damper coefficient never turns negative.
        let k = Coeffs {
            alpha: (alpha_a + alpha_b * i).max(0.0),
            c0: (c0a + c0b * i).max(0.0),
            c1: (c1a + c1b * i).max(0.0),
            k0,
            x_y,
            r,
        };
        if x_y <= 0.0 || k.c0 + k.c1 <= 0.0 || k0 < 0.0 || !(-1.0..=1.0).contains(&r) {
            return false;
        }
        out.clear();
        let n = track.len();
        if n == 0 {
            return true;
        }
        let (t, xs, vs) = (&track.time_s, &track.x_mm, &track.v_m_s);
        let mut s = State { y_mm: xs[0], z: 0.0 };
        let force = |s: &State, x: f64, v: f64| k.c1 * k.rates(s, x, v).0 + k1 * x + f0;
        out.push(force(&s, xs[0], vs[0]));
        // Stiffest rates: y relaxes at k0/(c0 + c1)·1000 1/s, z through ẏ at α/(c0 + c1)·1000/x_y.
        let lam_y = MM_PER_M * (k.k0 + k.alpha / x_y) / (k.c0 + k.c1);
        for j in 1..n {
            let dt = t[j] - t[j - 1];
            let (x0, x1, v0, v1) = (xs[j - 1], xs[j], vs[j - 1], vs[j]);
            let lam_z = MM_PER_M * v0.abs().max(v1.abs()) * 2.0 / x_y;
            let m = (dt.abs() * (lam_y + lam_z) * 2.0).ceil();
            if !(m <= MAX_SUBSTEPS as f64) {
                return false;
            }
            let m = (m as usize).max(1);
            let h = dt / m as f64;
            for q in 0..m {
                let a = q as f64 / m as f64;
                let b = (q as f64 + 0.5) / m as f64;
                let (xa, va) = (x0 + a * (x1 - x0), v0 + a * (v1 - v0));
                let (xb, vb) = (x0 + b * (x1 - x0), v0 + b * (v1 - v0));
                let (yd, zd) = k.rates(&s, xa, va);
                let mid = State {
                    y_mm: s.y_mm + 0.5 * h * yd * MM_PER_M,
                    z: s.z + 0.5 * h * zd,
                };
                let (yd, zd) = k.rates(&mid, xb, vb);
                s.y_mm += h * yd * MM_PER_M;
                s.z += h * zd;
            }
            out.push(force(&s, x1, v1));
        }
        all_finite(out)
    }

    fn step_cost(&self) -> StepCost {
        // Per sub-step: two rate evaluations (~16 flops, 1 divide each) and the updates.
        StepCost {
            flops: 44,
            divides: 2,
            transcendentals: 0,
            substeps: 8,
            state_floats: 4,
        }
    }
}
