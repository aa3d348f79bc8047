//! A JSON report as HTML tables. Every number shown carries the JSON pointer
//! it came from (`data-json-path="report.json#/recordings/0/rmse_n"`), so a
//! test can read report.json itself and check each number on the page.
use super::escape;
use serde_json::Value;
use std::fmt::Write;

/// Longer arrays of numbers are summarised (count, min, max), not listed.
const MAX_LISTED_NUMBERS: usize = 12;
/// Rows shown of a long array of objects; the rest is in the JSON file.
const MAX_ROWS: usize = 300;

/// `file#pointer` for the data attribute.
fn pointer(file: &str, path: &[String]) -> String {
    let mut s = format!("{file}#");
    for p in path {
        s.push('/');
        s.push_str(&p.replace('~', "~0").replace('/', "~1"));
    }
    s
}

/// A number with four significant digits (integers exactly), as people read
/// a report; report.json keeps full precision.
pub fn format_number(v: f64) -> String {
    if !v.is_finite() {
        return v.to_string();
    }
    if v == v.trunc() && v.abs() < 1e15 {
        return format!("{}", v as i64);
    }
    let mag = v.abs().log10().floor() as i32;
    if (-4..6).contains(&mag) {
        let decimals = (3 - mag).max(0) as usize;
        format!("{v:.decimals$}")
    } else {
        format!("{v:.3e}")
    }
}

fn scalar(out: &mut String, file: &str, path: &[String], v: &Value) {
    match v {
        Value::Number(n) => {
            let x = n.as_f64().unwrap_or(f64::NAN);
            let _ = write!(
                out,
                "<span class=\"num\" data-json-path=\"{}\">{}</span>",
                escape(&pointer(file, path)),
                format_number(x)
            );
        }
        Value::String(s) => out.push_str(&escape(s)),
        Value::Bool(b) => out.push_str(if *b { "yes" } else { "no" }),
        Value::Null => out.push_str("<span class=\"null\">–</span>"),
        _ => {}
    }
}

/// Renders any value: objects as key/value tables, arrays of objects as one
/// table with a column per (flattened) field, short arrays of scalars inline.
pub fn render(out: &mut String, file: &str, path: &mut Vec<String>, v: &Value) {
    match v {
        Value::Object(map) => {
            out.push_str("<table class=\"kv\">\n");
            for (k, child) in map {
                path.push(k.clone());
                let _ = write!(out, "<tr><th>{}</th><td>", escape(k));
                render(out, file, path, child);
                out.push_str("</td></tr>\n");
                path.pop();
            }
            out.push_str("</table>\n");
        }
        Value::Array(items) if !items.is_empty() && items.iter().all(Value::is_object) => {
            rows_table(out, file, path, items)
        }
        Value::Array(items) => inline_array(out, file, path, items),
        _ => scalar(out, file, path, v),
    }
}

fn inline_array(out: &mut String, file: &str, path: &mut Vec<String>, items: &[Value]) {
    let numbers: Vec<f64> = items.iter().filter_map(Value::as_f64).collect();
    if items.len() > MAX_LISTED_NUMBERS && numbers.len() == items.len() {
        let min = numbers.iter().cloned().fold(f64::INFINITY, f64::min);
        let max = numbers.iter().cloned().fold(f64::NEG_INFINITY, f64::max);
        let _ = write!(
            out,
            "<span class=\"summary\">{} values, {} … {}</span>",
            items.len(),
            format_number(min),
            format_number(max)
        );
        return;
    }
    if items.is_empty() {
        out.push_str("<span class=\"null\">none</span>");
    }
    for (i, item) in items.iter().enumerate() {
        if i > 0 {
            out.push_str(if item.is_object() || item.is_array() {
                "\n"
            } else {
                ", "
            });
        }
        path.push(i.to_string());
        render(out, file, path, item);
        path.pop();
    }
}

/// Field paths of an object, nested objects flattened (`largest_error/x_mm`).
fn columns(v: &Value, prefix: &mut Vec<String>, out: &mut Vec<Vec<String>>) {
    if let Value::Object(map) = v {
        for (k, child) in map {
            prefix.push(k.clone());
            if child.is_object() {
                columns(child, prefix, out);
            } else if !out.contains(prefix) {
                out.push(prefix.clone());
            }
            prefix.pop();
        }
    }
}

fn rows_table(out: &mut String, file: &str, path: &mut Vec<String>, items: &[Value]) {
    let mut cols: Vec<Vec<String>> = Vec::new();
    for item in items {
        columns(item, &mut Vec::new(), &mut cols);
    }
    // A field that is an object in some rows shows as its flattened fields;
    // its own column stays only for rows where it is a plain value (e.g.
    // `"Controlled"` beside `{ "Passive": 2 }`), never for null alone.
    let flattened = |c: &Vec<String>| cols.iter().any(|o| o.len() > c.len() && o.starts_with(c));
    let at = |item: &Value, c: &[String]| c.iter().try_fold(item, |v, k| v.get(k)).cloned();
    // (path, whether its objects are shown flattened elsewhere)
    let cols: Vec<(Vec<String>, bool)> = cols
        .iter()
        .map(|c| (c.clone(), flattened(c)))
        .filter(|(c, split)| {
            !split
                || items
                    .iter()
                    .any(|i| at(i, c).is_some_and(|v| !v.is_null() && !v.is_object()))
        })
        .collect();
    out.push_str("<div class=\"scroll\"><table class=\"rows\">\n<thead><tr>");
    for (c, _) in &cols {
        let _ = write!(out, "<th>{}</th>", escape(&c.join(" ")).replace('_', "_<wbr>"));
    }
    out.push_str("</tr></thead>\n<tbody>\n");
    for (i, item) in items.iter().enumerate().take(MAX_ROWS) {
        out.push_str("<tr>");
        for (c, split) in &cols {
            out.push_str("<td>");
            let cell = c.iter().try_fold(item, |v, k| v.get(k));
            // An object here is already shown in its flattened columns.
            if let Some(cell) = cell.filter(|v| !(*split && v.is_object())) {
                path.push(i.to_string());
                path.extend(c.iter().cloned());
                render(out, file, path, cell);
                path.truncate(path.len() - c.len() - 1);
            }
            out.push_str("</td>");
        }
        out.push_str("</tr>\n");
    }
    out.push_str("</tbody></table></div>\n");
    if items.len() > MAX_ROWS {
        let _ = writeln!(
            out,
            "<p class=\"note\">First {MAX_ROWS} of {} rows; all are in {}.</p>",
            items.len(),
            escape(file)
        );
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn numbers_keep_four_significant_digits() {
        assert_eq!(format_number(3.0), "3");
        assert_eq!(format_number(-120.0), "-120");
        assert_eq!(format_number(0.123456), "0.1235");
        assert_eq!(format_number(12.3456), "12.35");
        assert_eq!(format_number(0.00123456), "0.001235");
        assert_eq!(format_number(123456.7), "123457");
        assert_eq!(format_number(2.5e6), "2500000");
        assert_eq!(format_number(2.55e6 + 0.5), "2.550e6");
        assert_eq!(format_number(1.5e-7), "1.500e-7");
    }

    #[test]
    fn every_number_carries_its_pointer() {
        let v = serde_json::json!({
            "model": "paper",
            "recordings": [
                { "file": "a/b.txt", "rmse_n": 1.25, "largest_error": { "x_mm": 2.5 } },
                { "file": "c.txt", "rmse_n": 0.5, "largest_error": { "x_mm": -1.0 } }
            ]
        });
        let mut s = String::new();
        render(&mut s, "report.json", &mut Vec::new(), &v);
        assert!(s.contains("data-json-path=\"report.json#/recordings/0/rmse_n\">1.250<"));
        assert!(s.contains("data-json-path=\"report.json#/recordings/1/largest_error/x_mm\">-1<"));
        assert!(s.contains("a/b.txt"));
        // One header per flattened field, in first-seen order.
        let headers: Vec<&str> = s.match_indices("<th>").map(|(i, _)| &s[i + 4..i + 8]).collect();
        assert_eq!(headers.len(), 2 /* kv keys */ + 3 /* columns */);
    }

    #[test]
    fn a_field_null_in_some_rows_and_an_object_in_others_is_flattened() {
        let v = serde_json::json!([{ "b": null }, { "b": { "lo": 1.5, "hi": 2.5 } }]);
        let mut s = String::new();
        render(&mut s, "r.json", &mut Vec::new(), &v);
        assert_eq!(s.matches("<th>").count(), 2, "b lo, b hi; no plain b column: {s}");
        assert!(s.contains("data-json-path=\"r.json#/1/b/hi\">2.500<"));
        assert!(!s.contains("class=\"kv\""), "no table inside a cell");

        // A plain value beside objects keeps its column (for its rows only).
        let v = serde_json::json!([{ "spec": "Controlled" }, { "spec": { "Passive": 2.0 } }]);
        let mut s = String::new();
        render(&mut s, "r.json", &mut Vec::new(), &v);
        assert_eq!(s.matches("<th>").count(), 2, "spec, spec Passive: {s}");
        assert!(s.contains("Controlled") && s.contains("data-json-path=\"r.json#/1/spec/Passive\">2<"));
        assert!(!s.contains("class=\"kv\""), "no table inside a cell");
    }

    #[test]
    fn pointer_escapes_slash_and_tilde() {
        assert_eq!(pointer("r.json", &["a/b".into(), "c~d".into()]), "r.json#/a~1b/c~0d");
    }
}
