//! Every way a data set can be rejected. Each `Display` is the whole message a
//! user sees: it names the file, the line and (for a value) the column.
use super::columns::Quantity;
use thiserror::Error;

#[derive(Clone, Debug, Error, PartialEq)]
pub enum DatasetError {
    #[error("{path}: cannot read: {reason}")]
    Unreadable { path: String, reason: String },

    /// A missing key in `dataset.toml`.
    #[error("{path}: line {line}: {message}")]
    Manifest { path: String, line: usize, message: String },

    /// TOML syntax error or a value of the wrong type in `dataset.toml`.
    #[error("{path}: line {line}, column {column}: {message}")]
    Syntax {
        path: String,
        line: usize,
        column: usize,
        message: String,
    },

    #[error(
        "{path}: line {line}, column {column}: `{key}` = {value} is outside the plausible range [{min}, {max}] {unit}"
    )]
    SettingOutOfRange {
        path: String,
        line: usize,
        column: usize,
        key: String,
        value: f64,
        min: f64,
        max: f64,
        unit: &'static str,
    },

    /// A record the CSV reader cannot parse (e.g. not UTF-8).
    #[error("{path}: line {line}: {message}")]
    BadRecord { path: String, line: usize, message: String },

    #[error(
        "{path}: line {line}, column {column} ({name}): `{text}` is outside the plausible {} range [{}, {}] {}",
        .quantity.describe(), .quantity.plausible_range().0, .quantity.plausible_range().1, .quantity.plausible_range().2
    )]
    OutOfRange {
        path: String,
        line: usize,
        column: usize,
        name: String,
        text: String,
        quantity: Quantity,
    },

    #[error("{path}: line {line}: unknown key `{key}` in {section}")]
    UnknownKey {
        path: String,
        line: usize,
        key: String,
        section: String,
    },

    #[error("{path}: line {line}: `{key}` must be a finite number, got {value}")]
    NonFiniteSetting {
        path: String,
        line: usize,
        key: String,
        value: f64,
    },

    #[error("{path}: line {line}: listed file `{file}` does not exist")]
    FileAbsent { path: String, line: usize, file: String },

    #[error("{path}: line {line}: file `{file}` is listed twice (first on line {first_line})")]
    DuplicateFile {
        path: String,
        line: usize,
        file: String,
        first_line: usize,
    },

    #[error("{path}: line {line}, column {column}: unknown column name `{name}` (accepted: {accepted})")]
    UnknownColumn {
        path: String,
        line: usize,
        column: usize,
        name: String,
        accepted: String,
    },

    #[error("{path}: line {line}, column {column}: `{name}` gives the {quantity} a second time")]
    DuplicateColumn {
        path: String,
        line: usize,
        column: usize,
        name: String,
        quantity: String,
    },

    #[error("{path}: line {line}: missing required column for {quantity} (one of {accepted})")]
    MissingColumn {
        path: String,
        line: usize,
        quantity: String,
        accepted: String,
    },

    #[error("{path}: line {line}: {found} fields, expected {expected}")]
    FieldCount {
        path: String,
        line: usize,
        found: usize,
        expected: usize,
    },

    #[error("{path}: line {line}, column {column} ({name}): `{text}` is not a number")]
    NotANumber {
        path: String,
        line: usize,
        column: usize,
        name: String,
        text: String,
    },

    #[error("{path}: line {line}, column {column} ({name}): `{text}` is not finite")]
    NotFinite {
        path: String,
        line: usize,
        column: usize,
        name: String,
        text: String,
    },

    #[error(
        "{path}: line {line}, column {column} ({name}): time {time_s} s does not increase \
         (previous sample {previous_s} s)"
    )]
    TimeNotIncreasing {
        path: String,
        line: usize,
        column: usize,
        name: String,
        time_s: f64,
        previous_s: f64,
    },

    #[error("{path}: line {line}: only {count} samples; a fit needs at least {min}")]
    TooFewSamples {
        path: String,
        line: usize,
        count: usize,
        min: usize,
    },
}
