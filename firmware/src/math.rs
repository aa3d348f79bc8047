//! The few math functions the core needs, routed through micromath so the host
//! runs the same approximations as the board (std's exact versions would hide
//! differences in host tests).
use micromath::F32Ext;

#[inline]
pub fn abs(x: f32) -> f32 {
    F32Ext::abs(x)
}

/// `x` clamped to `[lo, hi]`; NaN maps to `lo`. Never panics (unlike `f32::clamp`
/// with bad bounds).
#[inline]
pub fn clamp(x: f32, lo: f32, hi: f32) -> f32 {
    if x >= lo {
        if x <= hi {
            x
        } else {
            hi
        }
    } else {
        lo
    }
}
