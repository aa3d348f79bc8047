//! Sign conventions (docs/dataset-format.md, "sign"): compression reads
//! positive force and positive displacement. On the loading branch of an
//! impact (from the start of the record to its largest stroke, or to its
//! largest force when the motion is derived) a column that reads the other
//! way is named, so a load cell wired for tension is not fitted as if the
//! damper pulled.
use super::columns::Quantity;

/// A column whose sign contradicts compression-positive, and why.
#[derive(Clone, Debug, PartialEq)]
pub struct Inverted {
    pub quantity: Quantity,
    pub evidence: String,
}

/// True when a record is one-sided, as an impact is: the force's extreme of
/// the minority sign is under a fifth of the other (a shaker test is not).
pub fn one_sided(force_n: &[f64]) -> bool {
    let (lo, hi) = force_n.iter().fold((0.0f64, 0.0f64), |(l, h), &f| (l.min(f), h.max(f)));
    lo.abs().min(hi) < 0.2 * lo.abs().max(hi)
}

/// The end of the loading branch: the largest stroke from the first sample,
/// or the largest force when there is no displacement.
fn loading_end(force_n: &[f64], x_mm: Option<&[f64]>) -> usize {
    let argmax = |v: &mut dyn Iterator<Item = f64>| {
        v.enumerate()
            .fold(
                (0, f64::NEG_INFINITY),
                |(bi, bv), (i, x)| if x > bv { (i, x) } else { (bi, bv) },
            )
            .0
    };
    match x_mm {
        Some(x) if !x.is_empty() => argmax(&mut x.iter().map(|v| (v - x[0]).abs())),
        _ => argmax(&mut force_n.iter().map(|f| f.abs())),
    }
}

/// The columns that read compression negative on the loading branch.
pub fn inverted_columns(
    force_n: &[f64],
    x_mm: Option<&[f64]>,
    v_m_s: Option<&[f64]>,
    accel_m_s2: Option<&[f64]>,
) -> Vec<Inverted> {
    let mut out = Vec::new();
    if force_n.is_empty() {
        return out;
    }
    let end = loading_end(force_n, x_mm);
    let mean = |c: &[f64]| c[..=end.min(c.len() - 1)].iter().sum::<f64>() / (end + 1) as f64;
    let f = mean(force_n);
    if f < 0.0 {
        out.push(Inverted {
            quantity: Quantity::Force,
            evidence: format!("its mean on the loading branch is {f:.4} N"),
        });
    }
    if let Some(x) = x_mm.filter(|x| !x.is_empty()) {
        let stroke = x[end] - x[0];
        if stroke < 0.0 {
            out.push(Inverted {
                quantity: Quantity::Displacement,
                evidence: format!("it moves {stroke:.4} mm from the start to the largest stroke"),
            });
        }
    }
    if let Some(v) = v_m_s.filter(|v| !v.is_empty()) {
        let m = mean(v);
        if m < 0.0 {
            out.push(Inverted {
                quantity: Quantity::Velocity,
                evidence: format!("its mean on the loading branch is {m:.4} m/s"),
            });
        }
    }
    if let Some(a) = accel_m_s2.filter(|a| !a.is_empty()) {
        // At the largest force the striker decelerates: a = g − F/m < 0.
        let k = loading_end(force_n, None);
        if a[k] > 0.0 && force_n[k].abs() > 0.0 {
            out.push(Inverted {
                quantity: Quantity::Acceleration,
                evidence: format!(
                    "it reads {:.4} m/s² at the largest force, where the striker decelerates",
                    a[k]
                ),
            });
        }
    }
    out
}

/// Share of the loading branch's work (|F·dx| summed) by which the net work
/// must be negative before the record is called inverted: a tare jump or
/// noise moves it a little, a wrong sign flips most of it.
const WORK_CLEAR: f64 = 0.25;

/// The work check every record with a measured displacement gets: a passive
/// damper takes work while it is loaded, so ∫F·dx from the first sample to
/// the largest force is positive. When it is clearly negative, force and
/// displacement read opposite ways: the force column is named (its sign is
/// the usual culprit; the evidence says displacement could be instead).
pub fn negative_work(force_n: &[f64], x_mm: &[f64]) -> Option<Inverted> {
    let n = force_n.len().min(x_mm.len());
    if n < 2 {
        return None;
    }
    let end = loading_end(&force_n[..n], None);
    // Trapezoids in N·mm = mJ.
    let (net, gross) = (1..=end).fold((0.0, 0.0), |(net, gross), k| {
        let w = 0.5 * (force_n[k] + force_n[k - 1]) * (x_mm[k] - x_mm[k - 1]);
        (net + w, gross + w.abs())
    });
    (gross > 0.0 && net < -WORK_CLEAR * gross).then(|| Inverted {
        quantity: Quantity::Force,
        evidence: format!(
            "the work done on the damper from the first sample to the largest force (sample {}) is \
             {:.4} J, negative, and a passive damper takes work (if the force reads right, flip \
             displacement_mm instead)",
            end + 1,
            net * 1e-3
        ),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A half-sine impact: x rises to 10 mm, F to 1 kN, v falls from 2 m/s.
    fn impact() -> (Vec<f64>, Vec<f64>, Vec<f64>) {
        let n = 50;
        let th = |k: usize| std::f64::consts::PI * k as f64 / n as f64;
        let x = (0..=n).map(|k| 10.0 * th(k).sin()).collect();
        let f = (0..=n).map(|k| 1000.0 * th(k).sin()).collect();
        let v = (0..=n).map(|k| 2.0 * th(k).cos()).collect();
        (x, f, v)
    }

    #[test]
    fn compression_positive_passes_and_each_inverted_column_is_named() {
        let (x, f, v) = impact();
        assert!(inverted_columns(&f, Some(&x), Some(&v), None).is_empty());
        let neg = |c: &[f64]| c.iter().map(|a| -a).collect::<Vec<_>>();
        let names = |r: Vec<Inverted>| r.into_iter().map(|i| i.quantity).collect::<Vec<_>>();
        assert_eq!(
            names(inverted_columns(&neg(&f), Some(&x), Some(&v), None)),
            [Quantity::Force]
        );
        assert_eq!(
            names(inverted_columns(&f, Some(&neg(&x)), Some(&v), None)),
            [Quantity::Displacement]
        );
        assert_eq!(names(inverted_columns(&f, None, None, None)), Vec::<Quantity>::new());
        assert_eq!(names(inverted_columns(&neg(&f), None, None, None)), [Quantity::Force]);
        assert!(one_sided(&f));
        let shaker: Vec<f64> = (0..100).map(|k| (k as f64 * 0.1).sin()).collect();
        assert!(!one_sided(&shaker));
    }

    #[test]
    fn work_on_loading_is_positive_unless_one_column_is_flipped() {
        let (x, f, _) = impact();
        assert!(negative_work(&f, &x).is_none());
        let neg = |c: &[f64]| c.iter().map(|a| -a).collect::<Vec<_>>();
        assert!(negative_work(&neg(&f), &x).is_some());
        assert!(negative_work(&f, &neg(&x)).is_some());
        // Both flipped: the work cannot tell.
        assert!(negative_work(&neg(&f), &neg(&x)).is_none());
    }
}
