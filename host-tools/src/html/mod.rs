//! The HTML report: one self-contained `index.html` per analysis command,
//! beside its report.md, and one for `mre demo` linking every step.
//!
//! A page is built from the files a command wrote into its folders (staged
//! or already on disk, see [`crate::atomic_write::files_in`]): each markdown
//! report rendered, each figure embedded as a data URI (PNG, or SVG when
//! there is no PNG), each JSON report as tables whose numbers carry the JSON
//! pointer they came from, and links to every CSV, JSON and markdown file.
//! No script and no external resource, so it works offline and from a
//! `file://` URL.
//!
//! A command adds its page as the last step of writing its report (the
//! outputs staged before are found even though they are not published yet):
//!
//! ```ignore
//! crate::html::Page::new("Comparison of models")
//!     .folder(report_dir)            // report.md, *.png/*.svg, *.json, *.csv there
//!     .file(json_path)               // a JSON written elsewhere, if any
//!     .write(&report_dir.join("index.html"))?;
//! ```
//!
//! The demo's step pages are linked from `out/index.html` when they sit
//! beside the step's report (`DemoStep::report` → `index.html`).
pub mod json;

use anyhow::{Context, Result};
use std::fmt::Write;
use std::path::{Path, PathBuf};

/// The page's style: system fonts, readable line length, tables that scroll
/// sideways on a narrow screen instead of squeezing.
const CSS: &str = include_str!("style.css");
/// JSON files smaller than this are shown unfolded.
const OPEN_JSON_BYTES: usize = 40_000;

/// Escapes text for HTML content and attribute values.
pub fn escape(s: &str) -> String {
    let mut out = String::with_capacity(s.len());
    for c in s.chars() {
        match c {
            '&' => out.push_str("&amp;"),
            '<' => out.push_str("&lt;"),
            '>' => out.push_str("&gt;"),
            '"' => out.push_str("&quot;"),
            '\'' => out.push_str("&#39;"),
            c => out.push(c),
        }
    }
    out
}

/// One report page: a title, a lead paragraph, and the folders whose
/// outputs it shows (in order).
pub struct Page {
    title: String,
    lead: Option<String>,
    folders: Vec<PathBuf>,
    files: Vec<PathBuf>,
}

impl Page {
    pub fn new(title: impl Into<String>) -> Self {
        Page {
            title: title.into(),
            lead: None,
            folders: Vec::new(),
            files: Vec::new(),
        }
    }

    /// A sentence under the title (plain text).
    pub fn lead(mut self, text: impl Into<String>) -> Self {
        self.lead = Some(text.into());
        self
    }

    /// Shows the outputs in `dir` (its own section when the page has several).
    pub fn folder(mut self, dir: &Path) -> Self {
        self.folders.push(dir.to_path_buf());
        self
    }

    /// Shows one more file written elsewhere (e.g. `diagnose --json PATH`).
    pub fn file(mut self, path: &Path) -> Self {
        self.files.push(path.to_path_buf());
        self
    }

    /// Renders the page and writes it (atomically) to `dest`; links are
    /// relative to `dest`'s folder.
    pub fn write(&self, dest: &Path) -> Result<()> {
        let html = self.render(dest)?;
        crate::atomic_write::write_atomic(dest, html.as_bytes())
    }

    fn render(&self, dest: &Path) -> Result<String> {
        let base = dest.parent().unwrap_or(Path::new("."));
        let mut body = String::new();
        let several = self.folders.len() > 1;
        for dir in &self.folders {
            let files: Vec<(PathBuf, PathBuf)> = crate::atomic_write::files_in(dir)
                .into_iter()
                .filter(|(d, _)| !crate::atomic_write::same_path(d, dest))
                .collect();
            let label = relative(base, dir).display().to_string();
            // The page's own folder needs no heading; its subfolders do.
            if several && label != "." && !label.is_empty() {
                let _ = writeln!(body, "<section><h2 class=\"folder\">{}</h2>", escape(&label));
            } else {
                body.push_str("<section>\n");
            }
            render_files(&mut body, base, &files, !several)?;
            body.push_str("</section>\n");
        }
        // Files already shown with their folder are not shown twice.
        let extra: Vec<&PathBuf> = self
            .files
            .iter()
            .filter(|f| {
                !self
                    .folders
                    .iter()
                    .any(|d| crate::atomic_write::same_path(f.parent().unwrap_or(Path::new(".")), d))
            })
            .collect();
        if !extra.is_empty() {
            let files: Vec<(PathBuf, PathBuf)> = extra
                .into_iter()
                .map(|f| {
                    let readable = crate::atomic_write::files_in(f.parent().unwrap_or(Path::new(".")))
                        .into_iter()
                        .find(|(d, _)| crate::atomic_write::same_path(d, f))
                        .map(|(_, r)| r)
                        .unwrap_or_else(|| f.clone());
                    (f.clone(), readable)
                })
                .collect();
            body.push_str("<section>\n");
            render_files(&mut body, base, &files, false)?;
            body.push_str("</section>\n");
        }
        Ok(skeleton(&self.title, self.lead.as_deref(), &body))
    }
}

/// `path` relative to `base` when it lies below it; else as given.
fn relative(base: &Path, path: &Path) -> PathBuf {
    let abs = |p: &Path| std::path::absolute(p).unwrap_or_else(|_| p.to_path_buf());
    match abs(path).strip_prefix(abs(base)) {
        Ok(rel) if rel.as_os_str().is_empty() => PathBuf::from("."),
        Ok(rel) => rel.to_path_buf(),
        Err(_) => abs(path),
    }
}

/// A link's `href`: relative path with `/` separators, or a file URL.
fn href(base: &Path, path: &Path) -> String {
    let rel = relative(base, path);
    let s = rel.to_string_lossy().replace('\\', "/");
    if rel.is_absolute() {
        format!("file://{s}")
    } else {
        s
    }
}

fn extension(p: &Path) -> String {
    p.extension()
        .map(|e| e.to_string_lossy().to_ascii_lowercase())
        .unwrap_or_default()
}

fn read(dest: &Path, from: &Path) -> Result<Vec<u8>> {
    std::fs::read(from).with_context(|| format!("cannot read {} for the HTML report", dest.display()))
}

/// Markdown reports, figures, JSON tables and the file list of one folder.
fn render_files(out: &mut String, base: &Path, files: &[(PathBuf, PathBuf)], top: bool) -> Result<()> {
    let h = if top { "h2" } else { "h3" };
    // Figures a report shows itself are embedded there, not repeated below.
    let mut shown: Vec<PathBuf> = Vec::new();
    for (dest, from) in files.iter().filter(|(d, _)| extension(d) == "md") {
        let text = String::from_utf8_lossy(&read(dest, from)?).into_owned();
        out.push_str(&markdown(&text, base, files, &mut shown));
    }
    // A figure saved as PNG and SVG is embedded once, in the smaller form.
    let size = |p: &Path| std::fs::metadata(p).map_or(u64::MAX, |m| m.len());
    let figures: Vec<&(PathBuf, PathBuf)> = files
        .iter()
        .filter(|(d, from)| {
            let e = extension(d);
            let other = if e == "png" { "svg" } else { "png" };
            let smaller_twin = files
                .iter()
                .find(|(o, _)| *o == d.with_extension(other))
                .is_some_and(|(_, o_from)| (size(o_from), other) < (size(from), e.as_str()));
            (e == "png" || e == "svg") && !smaller_twin && !shown.contains(d)
        })
        .collect();
    if !figures.is_empty() {
        let _ = writeln!(out, "<{h}>Figures</{h}>\n<div class=\"figures\">");
        for (dest, _) in figures {
            let name = escape(&dest.file_name().unwrap_or_default().to_string_lossy());
            let _ = writeln!(
                out,
                "<figure><a href=\"{link}\"><img src=\"{link}\" alt=\"{name}\"></a>\
                 <figcaption>{name}</figcaption></figure>",
                link = escape(&href(base, dest)),
            );
        }
        out.push_str("</div>\n");
    }
    for (dest, from) in files.iter().filter(|(d, _)| extension(d) == "json") {
        let name = dest.file_name().unwrap_or_default().to_string_lossy().into_owned();
        let bytes = read(dest, from)?;
        // A JSON file mre did not write (left in the folder by someone) does
        // not stop the command: the page says what is wrong with it.
        let value: serde_json::Value = match serde_json::from_slice(&bytes) {
            Ok(v) => v,
            Err(e) => {
                let _ = writeln!(
                    out,
                    "<p class=\"note\"><code>{}</code> is not valid JSON ({e}); not shown.</p>",
                    escape(&name)
                );
                continue;
            }
        };
        // Small reports open; long ones (a diagnosis's every candidate) folded.
        let open = if bytes.len() < OPEN_JSON_BYTES { " open" } else { "" };
        let _ = writeln!(
            out,
            "<details class=\"data\"{open}><summary>Data: <code>{}</code> (the numbers of the file, 4 significant digits)</summary>",
            escape(&name)
        );
        out.push_str("<div class=\"scroll\">\n");
        json::render(out, &href(base, dest), &mut Vec::new(), &value);
        out.push_str("</div></details>\n");
    }
    let links: Vec<&PathBuf> = files
        .iter()
        .map(|(d, _)| d)
        .filter(|d| ["csv", "json", "md", "toml", "svg", "rs", "txt", "fmu"].contains(&extension(d).as_str()))
        .collect();
    if !links.is_empty() {
        let _ = writeln!(out, "<{h}>Files</{h}>\n<ul class=\"files\">");
        for d in links {
            let _ = writeln!(out, "<li><a href=\"{0}\">{0}</a></li>", escape(&href(base, d)));
        }
        out.push_str("</ul>\n");
    }
    Ok(())
}

/// A markdown report as HTML; its headings move one level down, below the
/// page's own title. Images it shows from its own folder (`files`) are
/// linked relative to the page (`base`; never embedded, so a figure is stored
/// once) and added to `shown`.
fn markdown(text: &str, base: &Path, files: &[(PathBuf, PathBuf)], shown: &mut Vec<PathBuf>) -> String {
    use pulldown_cmark::{CowStr, Event, HeadingLevel, Options, Parser, Tag, TagEnd};
    let demote = |l: HeadingLevel| HeadingLevel::try_from(l as usize + 1).unwrap_or(l);
    let parser = Parser::new_ext(text, Options::ENABLE_TABLES).map(|e| match e {
        Event::Start(Tag::Image {
            link_type,
            dest_url,
            title,
            id,
        }) => {
            let local = files
                .iter()
                .find(|(d, _)| d.file_name().is_some_and(|n| n.to_string_lossy() == *dest_url));
            let dest_url = match local {
                Some((d, _)) => {
                    shown.push(d.clone());
                    CowStr::from(href(base, d))
                }
                None => dest_url,
            };
            Event::Start(Tag::Image {
                link_type,
                dest_url,
                title,
                id,
            })
        }
        // Raw HTML in a report is shown as text, never interpreted.
        Event::Html(s) | Event::InlineHtml(s) => Event::Text(s),
        Event::Start(Tag::Heading {
            level,
            id,
            classes,
            attrs,
        }) => Event::Start(Tag::Heading {
            level: demote(level),
            id,
            classes,
            attrs,
        }),
        Event::End(TagEnd::Heading(level)) => Event::End(TagEnd::Heading(demote(level))),
        e => e,
    });
    let mut html = String::new();
    pulldown_cmark::html::push_html(&mut html, parser);
    // Wide tables scroll inside their own box.
    html.replace("<table>", "<div class=\"scroll\"><table>")
        .replace("</table>", "</table></div>")
}

fn skeleton(title: &str, lead: Option<&str>, body: &str) -> String {
    let lead = lead
        .map(|l| format!("<p class=\"lead\">{}</p>\n", escape(l)))
        .unwrap_or_default();
    format!(
        "<!doctype html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n\
         <meta name=\"viewport\" content=\"width=device-width, initial-scale=1\">\n\
         <title>{t}</title>\n<style>\n{CSS}</style>\n</head>\n<body>\n<main>\n\
         <header><h1>{t}</h1>\n{lead}<p class=\"by\">mre {v}</p></header>\n{body}</main>\n</body>\n</html>\n",
        t = escape(title),
        v = env!("CARGO_PKG_VERSION"),
    )
}

/// One entry of the demo's index page.
pub struct IndexEntry<'a> {
    pub title: &'a str,
    pub headline: &'a str,
    /// The step's page (or report) to link; `None` when it has none.
    pub link: Option<&'a Path>,
    /// Files offered for download beside the headline (the demo's FMUs).
    pub downloads: &'a [PathBuf],
}

/// A result shown as a figure at the top of the demo's `index.html`.
pub struct ResultFigure {
    pub image: PathBuf,
    /// The step's page the figure links to.
    pub page: PathBuf,
    pub caption: String,
    /// Said in place of the figure when its step wrote none (a skipped step).
    pub missing: String,
}

/// The demo's `index.html` in `dir`: the result figures (linked, never
/// embedded), then one row per step with its headline and a link to the
/// step's page.
pub fn write_index(
    dir: &Path,
    title: &str,
    lead: &str,
    results: &[ResultFigure],
    entries: &[IndexEntry],
) -> Result<()> {
    let dest = dir.join("index.html");
    let mut body = String::from("<section class=\"results\">\n<h2>Results</h2>\n<div class=\"figures\">\n");
    for r in results {
        let caption = escape(&r.caption);
        if r.image.is_file() {
            let _ = writeln!(
                body,
                "<figure class=\"result\"><a href=\"{page}\"><img src=\"{image}\" alt=\"{caption}\"></a>\
                 <figcaption>{caption} <a href=\"{page}\">Open the step's page</a>.</figcaption></figure>",
                page = escape(&href(dir, &r.page)),
                image = escape(&href(dir, &r.image)),
            );
        } else {
            let _ = writeln!(
                body,
                "<figure class=\"result missing\"><p class=\"note\">{}</p><figcaption>{caption}</figcaption></figure>",
                escape(&r.missing)
            );
        }
    }
    body.push_str("</div>\n</section>\n<h2>Steps</h2>\n<ol class=\"steps\">\n");
    for e in entries {
        let heading = match e.link {
            Some(link) => format!("<a href=\"{}\">{}</a>", escape(&href(dir, link)), escape(e.title)),
            None => escape(e.title),
        };
        let downloads: Vec<String> = e
            .downloads
            .iter()
            .map(|d| {
                let name = d.file_name().unwrap_or_default().to_string_lossy();
                format!("<a href=\"{}\">{}</a>", escape(&href(dir, d)), escape(&name))
            })
            .collect();
        let downloads = if downloads.is_empty() {
            String::new()
        } else {
            format!(". Download: {}", downloads.join(", "))
        };
        let _ = writeln!(
            body,
            "<li><h3>{heading}</h3><p>{}{downloads}</p></li>",
            escape(e.headline)
        );
    }
    body.push_str("</ol>\n");
    crate::atomic_write::write_atomic(&dest, skeleton(title, Some(lead), &body).as_bytes())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn page_shows_markdown_figures_json_and_links() {
        let dir = tempfile::tempdir().unwrap();
        let d = dir.path();
        std::fs::write(
            d.join("report.md"),
            "# Validation\n\n| a | b |\n|---|---|\n| 1 | <x> |\n\n![loops](loops.svg)\n",
        )
        .unwrap();
        std::fs::write(
            d.join("loops.svg"),
            "<svg xmlns='http://www.w3.org/2000/svg' width='5' height='5'/>",
        )
        .unwrap();
        std::fs::write(d.join("report.json"), r#"{"rmse_n": 0.125}"#).unwrap();
        std::fs::write(d.join("run.csv"), "t,x\n").unwrap();
        std::fs::write(d.join("damper.fmu"), b"PK").unwrap();
        std::fs::write(
            d.join("fig.svg"),
            "<svg xmlns='http://www.w3.org/2000/svg' width='4' height='4'/>",
        )
        .unwrap();
        crate::atomic_write::command(|| Page::new("Validation & co").folder(d).write(&d.join("index.html"))).unwrap();
        let html = std::fs::read_to_string(d.join("index.html")).unwrap();
        assert!(html.contains("<title>Validation &amp; co</title>"));
        assert!(html.contains("<th>a</th>"), "markdown table rendered");
        assert!(html.contains("&lt;x&gt;"), "raw HTML in markdown is escaped");
        assert!(html.contains("data-json-path=\"report.json#/rmse_n\">0.1250<"));
        // Figures are linked beside the page, never embedded: each is stored once.
        assert!(!html.contains("base64"), "no embedded image");
        // The figure the report shows is shown there and not repeated in the gallery.
        assert!(html.contains("<img src=\"loops.svg\" alt=\"loops\""), "{html}");
        assert!(html.contains("<img src=\"fig.svg\""), "gallery figure linked");
        assert_eq!(html.matches("<figcaption>").count(), 1, "only fig.svg in the gallery");
        assert!(html.contains("<a href=\"run.csv\">run.csv</a>"));
        // An FMU is a download the page offers, not a file left unlisted.
        assert!(html.contains("<a href=\"damper.fmu\">damper.fmu</a>"));
        assert!(!html.contains("<script"), "no script");
    }

    #[test]
    fn a_broken_json_file_in_the_folder_is_named_not_fatal() {
        let dir = tempfile::tempdir().unwrap();
        let d = dir.path();
        std::fs::write(d.join("notes.json"), "{ not json").unwrap();
        Page::new("x").folder(d).write(&d.join("index.html")).unwrap();
        let html = std::fs::read_to_string(d.join("index.html")).unwrap();
        assert!(html.contains("<code>notes.json</code> is not valid JSON"), "{html}");
    }

    #[test]
    fn page_sees_outputs_staged_by_the_same_command() {
        let dir = tempfile::tempdir().unwrap();
        let d = dir.path().join("report");
        crate::atomic_write::command(|| {
            crate::atomic_write::write_atomic(&d.join("summary.md"), b"# Drop test\n")?;
            assert!(!d.join("summary.md").exists(), "still staged");
            Page::new("Drop").folder(&d).write(&d.join("index.html"))
        })
        .unwrap();
        let html = std::fs::read_to_string(d.join("index.html")).unwrap();
        assert!(html.contains("<h2>Drop test</h2>"), "{html}");
    }

    #[test]
    fn index_links_steps_relative_to_itself() {
        let dir = tempfile::tempdir().unwrap();
        let d = dir.path();
        let page = d.join("sim").join("index.html");
        std::fs::create_dir_all(d.join("sim")).unwrap();
        std::fs::write(d.join("sim/force.png"), b"png").unwrap();
        let results = [
            ResultFigure {
                image: d.join("sim/force.png"),
                page: page.clone(),
                caption: "The controlled drop".into(),
                missing: "no figure".into(),
            },
            ResultFigure {
                image: d.join("pil/agreement.png"),
                page: d.join("pil/index.html"),
                caption: "PIL".into(),
                missing: "skipped: no QEMU".into(),
            },
        ];
        write_index(
            d,
            "demo",
            "all steps",
            &results,
            &[
                IndexEntry {
                    title: "drop test",
                    headline: "peak 3 % lower",
                    link: Some(&page),
                    downloads: &[],
                },
                IndexEntry {
                    title: "FMUs",
                    headline: "wrote 1 FMU",
                    link: None,
                    downloads: &[d.join("fmu").join("damper.fmu")],
                },
                IndexEntry {
                    title: "PIL",
                    headline: "skipped",
                    link: None,
                    downloads: &[],
                },
            ],
        )
        .unwrap();
        let html = std::fs::read_to_string(d.join("index.html")).unwrap();
        assert!(html.contains("<a href=\"sim/index.html\">drop test</a>"));
        assert!(html.contains("<h3>PIL</h3><p>skipped</p>"));
        // Results first: a figure that exists is shown (linked, not embedded)
        // and links to its page; one that does not says why instead.
        let results_at = html.find("<section class=\"results\">").unwrap();
        assert!(results_at < html.find("<ol class=\"steps\">").unwrap());
        assert!(
            html.contains("<a href=\"sim/index.html\"><img src=\"sim/force.png\" alt=\"The controlled drop\"></a>"),
            "{html}"
        );
        assert!(
            html.contains("<p class=\"note\">skipped: no QEMU</p><figcaption>PIL</figcaption>"),
            "{html}"
        );
        assert!(
            !html.contains("pil/agreement.png"),
            "no link to a figure that is not there"
        );
        assert!(
            html.contains("<p>wrote 1 FMU. Download: <a href=\"fmu/damper.fmu\">damper.fmu</a></p>"),
            "{html}"
        );
    }
}
