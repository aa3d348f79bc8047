//! Host tests of the control core live in `tests/`; this crate has no code of its own.
