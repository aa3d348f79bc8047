//! `mre bench-diagnose`: blind cases with concealed effects, scored.
