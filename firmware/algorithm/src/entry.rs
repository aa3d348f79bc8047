//! One tabulated current as data: its two branch quartics (compression and
//! extension, [`Branch`]) and their fitted stroke. The bottom of the
//! algorithm's modules: `table` holds these, `order` proves facts about them,
//! `model` and `inverse` evaluate them; it uses none of them.

/// Most currents one table can hold (fixed size: no heap on the board).
pub const MAX_CURRENTS: usize = 8;

/// `F(x) = c[0]·x⁴ + c[1]·x³ + c[2]·x² + c[3]·x + c[4]` (highest power first,
/// as the paper prints it).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Quartic {
    pub coeffs: [f32; 5],
}

impl Quartic {
    pub const fn new(coeffs: [f32; 5]) -> Self {
        Self { coeffs }
    }

    /// Horner's scheme: four multiplies and four adds.
    #[inline]
    pub fn eval(&self, x: f32) -> f32 {
        let [a4, a3, a2, a1, a0] = self.coeffs;
        (((a4 * x + a3) * x + a2) * x + a1) * x + a0
    }

    pub(crate) fn is_finite(&self) -> bool {
        self.coeffs.iter().all(|c| c.is_finite())
    }

    /// A bound on |p(x)| and on every Horner partial for |x| ≤ `x_abs_max`
    /// (≥ 1): Horner over the coefficients' magnitudes. Infinite on overflow.
    pub(crate) fn magnitude_bound(&self, x_abs_max: f32) -> f32 {
        self.coeffs
            .iter()
            .fold(0.0, |acc, c| acc * x_abs_max + crate::math::abs(*c))
    }
}

/// One tabulated current: its two branch quartics and their fitted stroke.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CurrentEntry {
    pub current_a: f32,
    pub compression: Quartic,
    pub extension: Quartic,
    /// Fitted displacement range; outside it the model clamps x (see `model`).
    pub x_min_mm: f32,
    pub x_max_mm: f32,
}

impl CurrentEntry {
    pub(crate) const ZERO: CurrentEntry = CurrentEntry {
        current_a: 0.0,
        compression: Quartic::new([0.0; 5]),
        extension: Quartic::new([0.0; 5]),
        x_min_mm: 0.0,
        x_max_mm: 0.0,
    };
}

/// Which of an entry's two quartics applies.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Branch {
    /// Loading, v > 0.
    Compression,
    /// Unloading, v ≤ 0.
    Extension,
}

impl Branch {
    /// The paper's rule: compression when v > 0, else extension (NaN → extension).
    #[inline]
    pub fn from_velocity(v_m_s: f32) -> Branch {
        if v_m_s > 0.0 {
            Branch::Compression
        } else {
            Branch::Extension
        }
    }
}
