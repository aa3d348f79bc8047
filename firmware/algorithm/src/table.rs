//! Per-current coefficient tables: the paper's model as data.
//!
//! A table holds, for each tabulated coil current (ascending), one quartic for
//! the compression branch and one for the extension branch, and the stroke the
//! quartics were fitted on. x is in mm and F in N, as the paper's Table 4.
//!
//! Tables are stored in flash as a [`TableImage`] (version + entries + CRC-32)
//! and only become a usable [`Table`] through a validating constructor, so a
//! corrupt or inconsistent table is never evaluated.
use crate::entry::Branch;
pub use crate::entry::{CurrentEntry, Quartic, MAX_CURRENTS};
use crate::installation::{Installation, DEFAULT_INSTALLATION, FIELD_COUNT as INSTALLATION_WORDS};
use crate::order::OrderFacts;
use crate::saturation::{interpolation_variable, SegmentMap};
use crc::{Crc, CRC_32_ISO_HDLC};

/// The newest format version, written by [`Table::with_installation`]:
/// version 3 adds the [`Installation`] (what `mre tables` and `mre upload`
/// write). Version 2 ([`Table::with_terms`]) added [`ModelTerms`]; version 1
/// is the paper's quartics only ([`Table::new`]). Versions 1 and 2 still
/// load, with [`DEFAULT_INSTALLATION`]. The version is covered by the CRC.
pub const FORMAT_VERSION: u16 = FORMAT_VERSION_3;
/// The paper's format: per-current quartics and their strokes only.
pub const FORMAT_VERSION_1: u16 = 1;
/// Adds [`ModelTerms`].
pub const FORMAT_VERSION_2: u16 = 2;
/// Adds the [`Installation`].
pub const FORMAT_VERSION_3: u16 = 3;
/// Longest delay or time constant a table may carry (s): beyond it the value
/// is a unit mistake, not a damper.
pub const MAX_TERM_TIME_S: f32 = 0.1;

const CRC32: Crc<u32> = Crc::<u32>::new(&CRC_32_ISO_HDLC);
/// Bytes hashed per entry: current, x range, 2 × 5 coefficients, all f32.
const ENTRY_BYTES: usize = 13 * 4;
/// Version 2 appends, as f32: saturation current, sensor delay, coil time
/// constant and one viscous coefficient per entry.
const TERMS_BYTES: usize = (3 + MAX_CURRENTS) * 4;
/// Version 3 appends the installation's values, as f32, in
/// [`Installation::FIELD_NAMES`]' order.
const INSTALLATION_BYTES: usize = INSTALLATION_WORDS * 4;
const IMAGE_BYTES: usize = 3 + MAX_CURRENTS * ENTRY_BYTES + TERMS_BYTES + INSTALLATION_BYTES;

/// What format version 2 adds to the paper's model: the terms `mre diagnose`
/// identifies that matter to control. All zero = the paper's model.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ModelTerms {
    /// Viscous coefficient per entry (N·s/m, same index as the entries): the
    /// force gains `c(I)·v`, with `c` interpolated between currents like the
    /// quartics. Entries past the table's length are ignored (keep them 0).
    pub viscous_n_s_per_m: [f32; MAX_CURRENTS],
    /// Magnetic saturation: interpolate between currents linearly in
    /// `w = tanh(I / I_s)` instead of in `I`. 0 = linear in I.
    pub saturation_current_a: f32,
    /// How far the displacement and velocity the controller samples lag the
    /// true motion (s); the law predicts across it. 0 = none.
    pub sensor_delay_s: f32,
    /// The coil current's first-order time constant L/R behind its drive
    /// command (s); the law inverts it. 0 = the current follows at once.
    pub coil_tau_s: f32,
}

impl ModelTerms {
    /// The paper's model: no extra term.
    pub const NONE: ModelTerms = ModelTerms {
        viscous_n_s_per_m: [0.0; MAX_CURRENTS],
        saturation_current_a: 0.0,
        sensor_delay_s: 0.0,
        coil_tau_s: 0.0,
    };

    /// Every term at once (coil τ 2 ms, sensor delay 0.1 ms, a viscous term
    /// on the second entry, saturation at 1.5 A): the longest path through
    /// the model and the law, which the instruction-count bench and the PIL
    /// agreement test fly.
    pub const EVERY_TERM: ModelTerms = ModelTerms {
        viscous_n_s_per_m: [0.0, 30.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0],
        saturation_current_a: 1.5,
        sensor_delay_s: 1.0e-4,
        coil_tau_s: 2.0e-3,
    };

    pub fn is_none(&self) -> bool {
        *self == Self::NONE
    }

    fn validate(&self) -> Result<(), TableError> {
        if !self
            .viscous_n_s_per_m
            .iter()
            .all(|c| c.is_finite() && crate::math::abs(*c) <= MAX_VISCOUS_N_S_PER_M)
        {
            return Err(TableError::BadTerm {
                term: "viscous_n_s_per_m",
            });
        }
        let i_s = self.saturation_current_a;
        if !(i_s.is_finite() && i_s >= 0.0) {
            return Err(TableError::BadTerm {
                term: "saturation_current_a",
            });
        }
        let time_ok = |t: f32| t.is_finite() && (0.0..=MAX_TERM_TIME_S).contains(&t);
        if !time_ok(self.sensor_delay_s) {
            return Err(TableError::BadTerm { term: "sensor_delay_s" });
        }
        if !time_ok(self.coil_tau_s) {
            return Err(TableError::BadTerm { term: "coil_tau_s" });
        }
        Ok(())
    }
}

/// Largest force (N) a table may produce anywhere in its fitted stroke, and
/// the largest |x| (mm), |current| (A) and viscous coefficient (N·s/m) it may
/// hold. The damper makes a few kN; quartics extrapolated over a long fitted
/// stroke reach 1e8 N (Table 4 at 10× its stroke), so the force bound sits
/// above that and still 29 orders below f32 overflow (3.4e38): every Horner
/// step and the inverse's arithmetic stay finite, and an extreme (e.g.
/// uploaded) table is refused instead of making the inverse NaN.
pub const MAX_TABLE_FORCE_N: f32 = 1.0e9;
pub const MAX_TABLE_X_MM: f32 = 1.0e3;
pub const MAX_TABLE_CURRENT_A: f32 = 100.0;
pub const MAX_VISCOUS_N_S_PER_M: f32 = 1.0e5;

/// A table as it is stored in flash or in a generated source file.
#[derive(Clone, Copy, Debug)]
pub struct TableImage<'a> {
    pub version: u16,
    pub entries: &'a [CurrentEntry],
    /// Version 1 images must carry [`ModelTerms::NONE`].
    pub terms: ModelTerms,
    /// Version 1 and 2 images must carry [`DEFAULT_INSTALLATION`].
    pub installation: Installation,
    pub crc32: u32,
}

/// Why a table was rejected.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum TableError {
    Empty,
    TooManyEntries {
        count: usize,
    },
    UnsupportedVersion {
        version: u16,
    },
    /// Currents must be finite and strictly ascending.
    UnsortedCurrents {
        index: usize,
    },
    NonFiniteValue {
        index: usize,
    },
    /// The fitted stroke must be finite with `x_min_mm < x_max_mm`.
    BadStroke {
        index: usize,
    },
    CrcMismatch {
        stored: u32,
        computed: u32,
    },
    /// A value's magnitude is beyond the `MAX_TABLE_*` bounds.
    TooLarge {
        index: usize,
    },
    /// A version 2 term is non-finite or out of range (or a version 1 image
    /// carries terms).
    BadTerm {
        term: &'static str,
    },
    /// A version 3 installation value is not a finite positive value (or
    /// its impact range is reversed), or a version 1 or 2 image carries an
    /// installation other than the default.
    BadInstallation {
        field: &'static str,
    },
}

impl core::fmt::Display for TableError {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        match *self {
            TableError::Empty => write!(f, "table has no entries"),
            TableError::TooManyEntries { count } => {
                write!(f, "table has {count} entries, at most {MAX_CURRENTS} fit")
            }
            TableError::UnsupportedVersion { version } => {
                write!(
                    f,
                    "table format version {version} is not supported (expected {FORMAT_VERSION_1}..={FORMAT_VERSION})"
                )
            }
            TableError::UnsortedCurrents { index } => {
                write!(f, "entry {index}: currents must be finite and strictly ascending")
            }
            TableError::NonFiniteValue { index } => {
                write!(f, "entry {index}: coefficient or stroke is NaN or infinite")
            }
            TableError::BadStroke { index } => {
                write!(f, "entry {index}: fitted stroke needs x_min_mm < x_max_mm")
            }
            TableError::TooLarge { index } => write!(
                f,
                "entry {index}: a value exceeds the table bounds (|force| {MAX_TABLE_FORCE_N} N, |x| {MAX_TABLE_X_MM} mm, |I| {MAX_TABLE_CURRENT_A} A)"
            ),
            TableError::CrcMismatch { stored, computed } => {
                write!(
                    f,
                    "table CRC mismatch: stored {stored:#010x}, computed {computed:#010x}"
                )
            }
            TableError::BadTerm { term } => {
                write!(f, "model term {term} is non-finite or out of range")
            }
            TableError::BadInstallation { field } => {
                write!(
                    f,
                    "installation value {field} is not a finite positive value (or the impact range is reversed)"
                )
            }
        }
    }
}

/// A validated table. The only way to get one is through [`Table::new`] or
/// [`Table::from_image`], which check every invariant the model relies on.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Table {
    version: u16,
    len: usize,
    entries: [CurrentEntry; MAX_CURRENTS],
    crc32: u32,
    terms: ModelTerms,
    installation: Installation,
    /// Each entry's interpolation knot: its current, or `tanh(I/I_s)` under
    /// saturation (computed once here, not per period).
    knots: [f32; MAX_CURRENTS],
    /// True under a saturation term (interpolation in tanh(I/I_s)).
    saturated: bool,
    /// Per segment under saturation: the inverse's map from the segment
    /// fraction back to current, a polynomial fitted here (`saturation.rs`)
    /// or the exact atanh where no fit is within its tolerance.
    segment_maps: [SegmentMap; MAX_CURRENTS],
    /// The sensor delay d as the factors of a prediction across it:
    /// `[d·10³, ½·d²·10³]` (mm per m/s, mm per m/s²).
    delay_factors: [f32; 2],
    has_viscous: bool,
    /// The stroke every entry was fitted on (the intersection of their
    /// ranges; empty if they share none). Inside it no x needs clamping, which
    /// lets the inverse skip per-entry clamps on its hot path.
    shared_x_min_mm: f32,
    shared_x_max_mm: f32,
    /// Each entry's force at the ends of its stroke, `[compression,
    /// extension]` at x_min and at x_max: what it gives for any clamped x,
    /// computed once (by the same Horner evaluation) so that a clamped entry
    /// costs a load instead of a clamp and a quartic on the hot path.
    end_low_n: [[f32; 2]; MAX_CURRENTS],
    end_high_n: [[f32; 2]; MAX_CURRENTS],
    /// Per branch `[compression, extension]`: where in the shared stroke
    /// the forces are proven to rise strictly with current, and where one
    /// entry's is the largest (`order.rs`), which lets the inverse answer
    /// with fewer quartics there (with a viscous term: for the velocities
    /// they carry).
    order: [OrderFacts; 2],
    /// Per branch: where the inverse's ascending region starts, but at most
    /// just above the shared stroke (the next f32 after its top), so that
    /// an x below it lies at or below the shared stroke's top.
    scan_below_mm: [f32; 2],
}

impl Table {
    /// Validates `entries` and seals them as a version 1 table (the paper's
    /// model, no extra terms).
    pub fn new(entries: &[CurrentEntry]) -> Result<Self, TableError> {
        Self::build(FORMAT_VERSION_1, entries, ModelTerms::NONE, DEFAULT_INSTALLATION)
    }

    /// Validates `entries` and `terms` and seals them as a version 2 table.
    pub fn with_terms(entries: &[CurrentEntry], terms: ModelTerms) -> Result<Self, TableError> {
        Self::build(FORMAT_VERSION_2, entries, terms, DEFAULT_INSTALLATION)
    }

    /// Validates `entries`, `terms` and `installation` and seals them as a
    /// version 3 table.
    pub fn with_installation(
        entries: &[CurrentEntry],
        terms: ModelTerms,
        installation: Installation,
    ) -> Result<Self, TableError> {
        Self::build(FORMAT_VERSION_3, entries, terms, installation)
    }

    fn build(
        version: u16,
        entries: &[CurrentEntry],
        terms: ModelTerms,
        installation: Installation,
    ) -> Result<Self, TableError> {
        validate_entries(entries)?;
        terms.validate()?;
        if version == FORMAT_VERSION_1 && !terms.is_none() {
            return Err(TableError::BadTerm {
                term: "terms in a version 1 table",
            });
        }
        if let Some(field) = installation.invalid_field() {
            return Err(TableError::BadInstallation { field });
        }
        if version < FORMAT_VERSION_3 && installation != DEFAULT_INSTALLATION {
            return Err(TableError::BadInstallation {
                field: "installation in a version 1 or 2 table",
            });
        }
        let mut table = Table {
            version,
            len: entries.len(),
            entries: [CurrentEntry::ZERO; MAX_CURRENTS],
            crc32: content_crc(version, entries, &terms, &installation),
            terms,
            installation,
            knots: [0.0; MAX_CURRENTS],
            saturated: terms.saturation_current_a > 0.0,
            segment_maps: [SegmentMap::EXACT; MAX_CURRENTS],
            delay_factors: [
                terms.sensor_delay_s * 1.0e3,
                0.5 * terms.sensor_delay_s * terms.sensor_delay_s * 1.0e3,
            ],
            has_viscous: terms.viscous_n_s_per_m.iter().take(entries.len()).any(|c| *c != 0.0),
            shared_x_min_mm: f32::NEG_INFINITY,
            shared_x_max_mm: f32::INFINITY,
            end_low_n: [[0.0; 2]; MAX_CURRENTS],
            end_high_n: [[0.0; 2]; MAX_CURRENTS],
            order: [OrderFacts::NONE; 2],
            scan_below_mm: [f32::INFINITY; 2],
        };
        let ends = table.end_low_n.iter_mut().zip(table.end_high_n.iter_mut());
        for (((slot, knot), entry), (low, high)) in table
            .entries
            .iter_mut()
            .zip(table.knots.iter_mut())
            .zip(entries)
            .zip(ends)
        {
            *slot = *entry;
            *low = [
                entry.compression.eval(entry.x_min_mm),
                entry.extension.eval(entry.x_min_mm),
            ];
            *high = [
                entry.compression.eval(entry.x_max_mm),
                entry.extension.eval(entry.x_max_mm),
            ];
            *knot = interpolation_variable(entry.current_a, terms.saturation_current_a);
            table.shared_x_min_mm = table.shared_x_min_mm.max(entry.x_min_mm);
            table.shared_x_max_mm = table.shared_x_max_mm.min(entry.x_max_mm);
        }
        // tanh flattens: far above I_s neighbouring knots can round to the same
        // value, and the interpolation would divide by zero.
        let knots = table.knots.get(..table.len).unwrap_or(&[]);
        let flat = knots.windows(2).any(|w| match w {
            // Not strictly ascending, NaN included.
            [a, b] => b.partial_cmp(a) != Some(core::cmp::Ordering::Greater),
            _ => false,
        });
        // The inverse needs atanh of every knot: none may round to ±1.
        let saturated_to_one = terms.saturation_current_a > 0.0
            && knots
                .iter()
                .any(|k| crate::math::abs(*k).partial_cmp(&1.0) != Some(core::cmp::Ordering::Less));
        if flat || saturated_to_one {
            return Err(TableError::BadTerm {
                term: "saturation_current_a",
            });
        }
        let (lo_mm, hi_mm) = (table.shared_x_min_mm, table.shared_x_max_mm);
        for (facts, branch) in table.order.iter_mut().zip([Branch::Compression, Branch::Extension]) {
            *facts = OrderFacts::prove(entries, &terms.viscous_n_s_per_m, branch, lo_mm, hi_mm);
        }
        table.set_scan_below();
        if table.saturated {
            let knots = table.knots.get(..table.len).unwrap_or(&[]);
            for ((map, pair), currents) in table
                .segment_maps
                .iter_mut()
                .zip(knots.windows(2))
                .zip(entries.windows(2))
            {
                if let (&[w0, w1], [e0, e1]) = (pair, currents) {
                    let fit = SegmentMap::fit(w0, w1, terms.saturation_current_a, e0.current_a, e1.current_a);
                    *map = fit.map_or(SegmentMap::EXACT, |f| f.map);
                }
            }
        }
        Ok(table)
    }

    /// Validates a stored image, including its version and CRC.
    pub fn from_image(image: &TableImage<'_>) -> Result<Self, TableError> {
        if !(FORMAT_VERSION_1..=FORMAT_VERSION).contains(&image.version) {
            return Err(TableError::UnsupportedVersion { version: image.version });
        }
        let table = Self::build(image.version, image.entries, image.terms, image.installation)?;
        if table.crc32 != image.crc32 {
            return Err(TableError::CrcMismatch {
                stored: image.crc32,
                computed: table.crc32,
            });
        }
        Ok(table)
    }

    /// The paper's Table 4 (built-in default).
    pub fn paper() -> Result<Self, TableError> {
        Self::from_image(&PAPER_TABLE4)
    }

    #[inline]
    pub fn entries(&self) -> &[CurrentEntry] {
        // `len` ≤ MAX_CURRENTS by construction; the min (a conditional
        // move) lets the compiler drop the slice's bounds check.
        let (head, _) = self.entries.split_at(self.len.min(MAX_CURRENTS));
        head
    }

    /// The entries as the inverse's scans walk them.
    #[inline(always)]
    pub(crate) fn entry_array(&self) -> Entries<'_> {
        Entries {
            all: &self.entries,
            len: self.len,
        }
    }

    pub fn version(&self) -> u16 {
        self.version
    }

    pub fn crc32(&self) -> u32 {
        self.crc32
    }

    /// The version 2 terms ([`ModelTerms::NONE`] for a version 1 table).
    #[inline]
    pub fn terms(&self) -> &ModelTerms {
        &self.terms
    }

    /// The installation the table carries (version 3), or
    /// [`DEFAULT_INSTALLATION`] for a version 1 or 2 table.
    #[inline]
    pub fn installation(&self) -> &Installation {
        &self.installation
    }

    /// The same entries and terms sealed as a version 3 table carrying
    /// `installation`.
    pub fn carrying(&self, installation: Installation) -> Result<Table, TableError> {
        Self::with_installation(self.entries(), self.terms, installation)
    }

    /// The table as a flash image (what `Table::from_image` reads back).
    pub fn image(&self) -> TableImage<'_> {
        TableImage {
            version: self.version,
            entries: self.entries(),
            terms: self.terms,
            installation: self.installation,
            crc32: self.crc32,
        }
    }

    /// Entry `index`'s interpolation knot (its current, or `tanh(I/I_s)`).
    #[inline]
    pub(crate) fn knot(&self, index: usize) -> f32 {
        self.knots.get(index).copied().unwrap_or(0.0)
    }

    /// `[d·10³, ½·d²·10³]` for the sensor delay d: x (mm) moves
    /// `v·f[0] + a·f[1]` across it.
    #[inline]
    pub fn delay_factors(&self) -> [f32; 2] {
        self.delay_factors
    }

    /// True under a saturation term.
    #[inline(always)]
    pub(crate) fn saturated(&self) -> bool {
        self.saturated
    }

    /// Segment `index`'s map back to current under saturation (`index` <
    /// [`MAX_CURRENTS`]: the mask only spares the bounds check).
    #[inline(always)]
    pub fn segment_map(&self, index: usize) -> &SegmentMap {
        const _: () = assert!(MAX_CURRENTS.is_power_of_two());
        #[allow(clippy::indexing_slicing)] // masked below the array's length
        &self.segment_maps[index & (MAX_CURRENTS - 1)]
    }

    /// True when some entry has a viscous term (else the model skips it).
    #[inline]
    pub fn has_viscous(&self) -> bool {
        self.has_viscous
    }

    /// Entry `index`'s viscous coefficient (N·s/m).
    #[inline]
    pub(crate) fn viscous(&self, index: usize) -> f32 {
        self.terms.viscous_n_s_per_m.get(index).copied().unwrap_or(0.0)
    }

    /// True when `x_mm` lies in every entry's fitted stroke (so no entry
    /// clamps it). False for NaN.
    #[inline]
    pub fn in_shared_stroke(&self, x_mm: f32) -> bool {
        x_mm >= self.shared_x_min_mm && x_mm <= self.shared_x_max_mm
    }

    /// The stroke every entry was fitted on (empty if they share none).
    #[inline(always)]
    pub(crate) fn shared_x_min_mm(&self) -> f32 {
        self.shared_x_min_mm
    }

    #[inline(always)]
    pub(crate) fn shared_x_max_mm(&self) -> f32 {
        self.shared_x_max_mm
    }

    /// The proven order facts of `branch` (`order.rs`).
    #[inline(always)]
    pub fn order_facts(&self, branch: Branch) -> &OrderFacts {
        match branch {
            Branch::Compression => &self.order[0],
            Branch::Extension => &self.order[1],
        }
    }

    fn set_scan_below(&mut self) {
        let above_stroke = next_up(self.shared_x_max_mm);
        for (below, facts) in self.scan_below_mm.iter_mut().zip(self.order) {
            *below = if facts.ascending_from_mm < above_stroke {
                facts.ascending_from_mm
            } else {
                above_stroke
            };
        }
    }

    /// Where `branch`'s ascending region starts, at most just above the
    /// shared stroke (see the field).
    #[inline(always)]
    pub(crate) fn scan_below_mm(&self, branch: Branch) -> f32 {
        match branch {
            Branch::Compression => self.scan_below_mm[0],
            Branch::Extension => self.scan_below_mm[1],
        }
    }

    /// The same table without the proven order facts: the inverse then
    /// always scans every entry it needs, keeping the nearest force. The
    /// reference the shortcut is tested against.
    #[doc(hidden)]
    pub fn without_order_facts(&self) -> Table {
        let mut table = Table {
            order: [OrderFacts::NONE; 2],
            ..*self
        };
        table.set_scan_below();
        table
    }

    /// Entry `index` (= `e`)'s force on `branch` at `x_mm` clamped to its
    /// stroke, the clamped ends from the precomputed table. The caller maps
    /// a non-finite x to −∞ (it then counts as x_min, as in the forward
    /// model); a NaN that slips through gets the x_min end too.
    #[inline(always)]
    pub(crate) fn clamped_force_n(&self, index: usize, e: &CurrentEntry, branch: Branch, x_mm: f32) -> f32 {
        let b = match branch {
            Branch::Compression => 0,
            Branch::Extension => 1,
        };
        let end = |ends: &[[f32; 2]; MAX_CURRENTS]| ends.get(index).and_then(|f| f.get(b)).copied().unwrap_or(0.0);
        // Past the end first: beyond the stiff entries' strokes it is the
        // common case.
        if x_mm > e.x_max_mm {
            end(&self.end_high_n)
        } else if x_mm >= e.x_min_mm {
            match branch {
                Branch::Compression => e.compression.eval(x_mm),
                Branch::Extension => e.extension.eval(x_mm),
            }
        } else {
            end(&self.end_low_n)
        }
    }

    /// Lowest and highest tabulated current.
    pub fn current_range_a(&self) -> (f32, f32) {
        let e = self.entries();
        match (e.first(), e.last()) {
            (Some(lo), Some(hi)) => (lo.current_a, hi.current_a),
            _ => (0.0, 0.0),
        }
    }
}

/// The next f32 above a finite or infinite `x` (`f32::next_up`, which the
/// workspace's minimum Rust version lacks); NaN stays NaN.
fn next_up(x: f32) -> f32 {
    if x.is_nan() || x == f32::INFINITY {
        return x;
    }
    if x == 0.0 {
        return f32::from_bits(1);
    }
    let bits = x.to_bits();
    f32::from_bits(if x > 0.0 {
        bits.wrapping_add(1)
    } else {
        bits.wrapping_sub(1)
    })
}

fn validate_entries(entries: &[CurrentEntry]) -> Result<(), TableError> {
    if entries.is_empty() {
        return Err(TableError::Empty);
    }
    if entries.len() > MAX_CURRENTS {
        return Err(TableError::TooManyEntries { count: entries.len() });
    }
    let mut previous_current = f32::NEG_INFINITY;
    for (index, e) in entries.iter().enumerate() {
        if !e.compression.is_finite() || !e.extension.is_finite() {
            return Err(TableError::NonFiniteValue { index });
        }
        // `!(a > b)` also rejects NaN.
        if !e.current_a.is_finite() || e.current_a <= previous_current {
            return Err(TableError::UnsortedCurrents { index });
        }
        if !e.x_min_mm.is_finite() || !e.x_max_mm.is_finite() {
            return Err(TableError::NonFiniteValue { index });
        }
        if e.x_min_mm >= e.x_max_mm {
            return Err(TableError::BadStroke { index });
        }
        // The inverse evaluates each quartic only inside its stroke.
        let x_abs_max = crate::math::abs(e.x_min_mm).max(crate::math::abs(e.x_max_mm)).max(1.0);
        // Infinite on overflow; NaN cannot occur (the values are finite).
        let too_large = |q: &Quartic| q.magnitude_bound(x_abs_max) > MAX_TABLE_FORCE_N;
        if x_abs_max > MAX_TABLE_X_MM
            || crate::math::abs(e.current_a) > MAX_TABLE_CURRENT_A
            || too_large(&e.compression)
            || too_large(&e.extension)
        {
            return Err(TableError::TooLarge { index });
        }
        previous_current = e.current_a;
    }
    Ok(())
}

/// CRC-32 (ISO-HDLC, as zlib) over the version (u16 LE), the entry count (u8)
/// and every entry's f32 fields in little-endian order: current, x_min, x_max,
/// compression c0..c4, extension c0..c4; from version 2 on, then the terms:
/// saturation current, sensor delay, coil τ and the entries' viscous
/// coefficients; from version 3 on, then the installation's values in
/// [`Installation::FIELD_NAMES`]' order (each version hashes exactly as
/// before the next existed).
/// `const`, so flash images carry a CRC
/// computed by the compiler; the host's table generator writes the same value.
// Indexing is bounded by construction (count ≤ MAX_CURRENTS, so `at` ≤
// IMAGE_BYTES); iterators are not available in `const fn`.
#[allow(clippy::indexing_slicing)]
pub const fn content_crc(
    version: u16,
    entries: &[CurrentEntry],
    terms: &ModelTerms,
    installation: &Installation,
) -> u32 {
    let mut buf = [0u8; IMAGE_BYTES];
    let count = if entries.len() > MAX_CURRENTS {
        MAX_CURRENTS
    } else {
        entries.len()
    };
    let v = version.to_le_bytes();
    buf[0] = v[0];
    buf[1] = v[1];
    buf[2] = count as u8;
    let mut at = 3;
    let mut i = 0;
    while i < count {
        let e = &entries[i];
        let mut fields = [0f32; 13];
        fields[0] = e.current_a;
        fields[1] = e.x_min_mm;
        fields[2] = e.x_max_mm;
        let mut k: usize = 0;
        while k < 5 {
            fields[k.wrapping_add(3)] = e.compression.coeffs[k];
            fields[k.wrapping_add(8)] = e.extension.coeffs[k];
            k = k.wrapping_add(1);
        }
        at = push_le(&mut buf, at, &fields, 13);
        i = i.wrapping_add(1);
    }
    if version >= FORMAT_VERSION_2 {
        let mut fields = [0f32; 3 + MAX_CURRENTS];
        fields[0] = terms.saturation_current_a;
        fields[1] = terms.sensor_delay_s;
        fields[2] = terms.coil_tau_s;
        let mut k = 0;
        while k < count {
            fields[k.wrapping_add(3)] = terms.viscous_n_s_per_m[k];
            k = k.wrapping_add(1);
        }
        at = push_le(&mut buf, at, &fields, count.wrapping_add(3));
    }
    if version >= FORMAT_VERSION_3 {
        at = push_le(&mut buf, at, &installation.to_array(), INSTALLATION_WORDS);
    }
    let (used, _) = buf.split_at(at);
    CRC32.checksum(used)
}

/// Writes `fields[..n]` as little-endian f32 into `buf` from `at`; returns
/// the end. Callers keep `at + 4·n ≤ IMAGE_BYTES` (see `content_crc`).
#[allow(clippy::indexing_slicing)]
const fn push_le(buf: &mut [u8; IMAGE_BYTES], mut at: usize, fields: &[f32], n: usize) -> usize {
    let mut f = 0;
    while f < n {
        let b = fields[f].to_bits().to_le_bytes();
        buf[at] = b[0];
        buf[at.wrapping_add(1)] = b[1];
        buf[at.wrapping_add(2)] = b[2];
        buf[at.wrapping_add(3)] = b[3];
        at = at.wrapping_add(4);
        f = f.wrapping_add(1);
    }
    at
}

const fn paper_entry(current_a: f32, c: [f32; 5], e: [f32; 5], x_max_mm: f32) -> CurrentEntry {
    CurrentEntry {
        current_a,
        compression: Quartic::new(c),
        extension: Quartic::new(e),
        x_min_mm: 0.0,
        x_max_mm,
    }
}

/// The paper's Table 4 (x in mm, F in N; see `shared/paper/README.md` on units).
///
/// The paper does not publish the fitted stroke. Each loop starts at x = 0 and
/// closes where its compression and extension quartics cross again, so that
/// crossing (0.88–1.15 mm, found by root-finding the branch difference) is
/// used as `x_max_mm`. A host test checks the branches meet there.
pub const PAPER_TABLE4_ENTRIES: [CurrentEntry; 5] = [
    paper_entry(
        0.0,
        [-1201.40, 4792.40, -8317.70, 8945.10, -236.86],
        [-2198.30, 5862.70, -1052.60, 465.53, 2.19],
        1.1531,
    ),
    paper_entry(
        0.5,
        [-10630.00, 15621.00, -3332.90, 3968.60, 93.28],
        [-8708.80, 20027.00, -7723.00, 1209.50, -19.39],
        1.0838,
    ),
    paper_entry(
        1.0,
        [3422.00, -8986.60, 2936.20, 9330.20, 336.52],
        [-2193.60, 8677.00, -7363.90, 7180.70, -22.37],
        1.0891,
    ),
    paper_entry(
        1.5,
        [-7302.70, 8103.30, -1859.90, 8441.90, 37.99],
        [-1962.30, 7596.90, -2696.10, 4795.50, -65.56],
        0.9823,
    ),
    paper_entry(
        2.0,
        [-6619.60, 19772.00, -24021.00, 19016.00, -105.53],
        [32293.00, -61171.00, 35010.00, 3166.00, -58.19],
        0.8819,
    ),
];

/// The built-in default table as a flash image, CRC computed at compile time.
pub static PAPER_TABLE4: TableImage<'static> = TableImage {
    version: FORMAT_VERSION_1,
    entries: &PAPER_TABLE4_ENTRIES,
    terms: ModelTerms::NONE,
    installation: DEFAULT_INSTALLATION,
    crc32: content_crc(
        FORMAT_VERSION_1,
        &PAPER_TABLE4_ENTRIES,
        &ModelTerms::NONE,
        &DEFAULT_INSTALLATION,
    ),
};

/// A table's entries as the scans walk them: the whole fixed array and how
/// many are in use (at least one), so that a scan tests its end once per
/// entry and needs no slice of checked length.
#[derive(Clone, Copy)]
pub(crate) struct Entries<'a> {
    pub(crate) all: &'a [CurrentEntry; MAX_CURRENTS],
    pub(crate) len: usize,
}

impl<'a> Entries<'a> {
    /// Entry 0: every table has one (`Table::build` refuses an empty one),
    /// so no check is needed.
    #[inline(always)]
    pub(crate) fn first(&self) -> &'a CurrentEntry {
        let [first, ..] = self.all;
        first
    }

    /// Entries 1, 2, … of the array with their indices (the caller stops at `len`).
    #[inline(always)]
    pub(crate) fn rest(&self) -> impl Iterator<Item = (usize, &'a CurrentEntry)> {
        self.all.iter().enumerate().skip(1)
    }

    #[inline(always)]
    pub(crate) fn last_index(&self) -> usize {
        self.len.saturating_sub(1)
    }
}
