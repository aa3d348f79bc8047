//! Text as labs write it: the encoding told from the bytes (a byte-order
//! mark for UTF-8 and UTF-16; else UTF-8 when the bytes are valid UTF-8;
//! else the legacy encoding `chardetng` guesses, e.g. Windows-1252 for a
//! German MTS export or GBK for a Chinese Bluehill one), decoded by
//! `encoding_rs`. A file holding NUL bytes without a UTF-16 mark is binary,
//! not text, and is refused at the line of its first NUL.
use encoding_rs::{Encoding, UTF_8};
use std::borrow::Cow;

/// Decoded text and the encoding it was read in.
pub struct Decoded<'a> {
    pub text: Cow<'a, str>,
    pub encoding: &'static Encoding,
}

impl Decoded<'_> {
    /// "UTF-8", "windows-1252", "GBK", … for notes.
    pub fn encoding_name(&self) -> &'static str {
        self.encoding.name()
    }
}

/// The text of `bytes`; `Err(line)` when they are binary (the line of the
/// first NUL byte).
pub fn decode(bytes: &[u8]) -> Result<Decoded<'_>, usize> {
    #[cfg(test)]
    DECODES.with(|n| n.set(n.get() + 1));
    if let Some((encoding, bom)) = Encoding::for_bom(bytes) {
        let (text, _) = encoding.decode_without_bom_handling(&bytes[bom..]);
        return Ok(Decoded { text, encoding });
    }
    if let Some(nul) = bytes.iter().position(|&b| b == 0) {
        return Err(bytes[..nul].iter().filter(|&&b| b == b'\n').count() + 1);
    }
    if let Ok(text) = std::str::from_utf8(bytes) {
        return Ok(Decoded {
            text: Cow::Borrowed(text),
            encoding: UTF_8,
        });
    }
    let mut detector = chardetng::EncodingDetector::new();
    detector.feed(bytes, true);
    // No top-level domain hint; UTF-8 is already ruled out.
    let encoding = detector.guess(None, false);
    let (text, _) = encoding.decode_without_bom_handling(bytes);
    Ok(Decoded { text, encoding })
}

// How many times this thread decoded a file: lets a test check that `mre
// dataset init` decodes each file once (the encoding guess is the costly part).
#[cfg(test)]
thread_local! {
    pub static DECODES: std::cell::Cell<usize> = const { std::cell::Cell::new(0) };
}
