//! Figures in the README and the book copied from a run's files, never retyped. A block
//!
//! ```text
//! <!-- figure: docs/bench-lights-quick/lights.md | rows: 4; 64 -->
//! (what `umbra docs` writes)
//! <!-- /figure -->
//! ```
//!
//! holds the first table of that file (with `after: TEXT`, the first after the first line
//! holding TEXT), only the rows whose first or second cell is one of `rows` if given (separated
//! by `;`; a bench's table names a row by its configuration, the second cell), only the columns
//! whose heading is one of `columns` if given, and under it a line naming the file and the run:
//! the file's line that says what made it (`made by umbra at commit …`, which `umbra bench`
//! writes), or that the run did not say. `umbra
//! docs` writes every block of the README and the book anew from the files; `tests/docs.rs`
//! fails when a block differs from what it would write (a retyped figure, or a run redone since).

use std::path::{Path, PathBuf};

/// What a block asks for.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Figure {
    /// The run's file, from the project's root.
    pub source: String,
    /// The table is the first after the first line holding this.
    pub after: Option<String>,
    /// The rows kept, by their first or second cell (all when empty).
    pub rows: Vec<String>,
    /// The columns kept, by their heading (all when empty).
    pub columns: Vec<String>,
}

/// Why a document's figures cannot be written.
#[derive(Debug, thiserror::Error, PartialEq, Eq)]
pub enum FigureError {
    /// A block's opening line is not `<!-- figure: PATH [| after: TEXT] [| rows: A; B] [| columns: A; B] -->`.
    #[error(
        "line {line}: a figure block opens with `<!-- figure: PATH [| after: TEXT] [| rows: A; B] [| columns: A; B] -->`: {why}"
    )]
    Opening { line: usize, why: String },
    /// A block opened and never closed.
    #[error("line {line}: the figure block is not closed by `<!-- /figure -->`")]
    Unclosed { line: usize },
    /// The source cannot be read.
    #[error("{file}: cannot be read: {why}")]
    Source { file: String, why: String },
    /// The source holds no table where the block asks.
    #[error("{file}: no table{}", after.as_ref().map(|a| format!(" after a line holding {a:?}")).unwrap_or_default())]
    NoTable { file: String, after: Option<String> },
    /// A row asked for is not in the table.
    #[error("{file}: no row of the table has the first or second cell {row:?}")]
    NoRow { file: String, row: String },
    /// A column asked for is not in the table.
    #[error("{file}: no column of the table is headed {column:?}")]
    NoColumn { file: String, column: String },
}

const OPEN: &str = "<!-- figure:";
const CLOSE: &str = "<!-- /figure -->";
/// What a run's file says made it, on a line of its own (see [`made_by`]).
const MADE_BY: &str = "made by umbra at commit";

/// Reads a block's opening line, `line` its number (from 1) for the error.
fn figure(text: &str, line: usize) -> Result<Figure, FigureError> {
    let why = |why: &str| FigureError::Opening { line, why: why.to_string() };
    let inner = text.trim().strip_prefix(OPEN).and_then(|t| t.strip_suffix("-->")).ok_or_else(|| why("no `-->`"))?;
    let mut parts = inner.split('|').map(str::trim);
    let source = parts.next().filter(|s| !s.is_empty()).ok_or_else(|| why("no file named"))?.to_string();
    let mut figure = Figure { source, after: None, rows: Vec::new(), columns: Vec::new() };
    let list = |items: &str| items.split(';').map(|r| r.trim().to_string()).collect();
    for part in parts {
        match part.split_once(':').map(|(k, v)| (k.trim(), v.trim())) {
            Some(("after", text)) if !text.is_empty() => figure.after = Some(text.to_string()),
            Some(("rows", rows)) => figure.rows = list(rows),
            Some(("columns", columns)) => figure.columns = list(columns),
            _ => return Err(why(&format!("{part:?} is none of `after: TEXT`, `rows: A; B`, `columns: A; B`"))),
        }
    }
    Ok(figure)
}

/// The cells of a table row, split at every `|` (the runs' tables hold none inside a cell).
fn cells(row: &str) -> Vec<&str> {
    let row = row.trim();
    let row = row.strip_prefix('|').unwrap_or(row);
    row.strip_suffix('|').unwrap_or(row).split('|').map(str::trim).collect()
}

/// Whether a row is named `name` by its first or second cell, bold marks left out.
fn named(row: &str, name: &str) -> bool {
    cells(row).iter().take(2).any(|c| c.replace("**", "") == name)
}

/// `rows` with only the cells at `keep`.
fn keep_columns(rows: Vec<String>, keep: &[usize]) -> Vec<String> {
    rows.iter()
        .map(|row| {
            let cells = cells(row);
            let kept: Vec<&str> = keep.iter().map(|&i| cells.get(i).copied().unwrap_or("")).collect();
            format!("| {} |", kept.join(" | "))
        })
        .collect()
}

/// The lines `figure` asks for of `source` (the file's text), with the line saying what made it.
pub fn block(figure: &Figure, source: &str) -> Result<Vec<String>, FigureError> {
    let lines: Vec<&str> = source.lines().collect();
    let from = match &figure.after {
        Some(after) => lines.iter().position(|l| l.contains(after.as_str())).map_or(lines.len(), |i| i + 1),
        None => 0,
    };
    let no_table = || FigureError::NoTable { file: figure.source.clone(), after: figure.after.clone() };
    let start = (from..lines.len()).find(|&i| lines[i].starts_with('|')).ok_or_else(no_table)?;
    let table: Vec<&str> = lines[start..].iter().copied().take_while(|l| l.starts_with('|')).collect();
    let (head, body) = table.split_at(table.len().min(2));
    let mut out: Vec<String> = head.iter().map(|l| l.to_string()).collect();
    if figure.rows.is_empty() {
        out.extend(body.iter().map(|l| l.to_string()));
    } else {
        for row in &figure.rows {
            let mine: Vec<&&str> = body.iter().filter(|l| named(l, row)).collect();
            if mine.is_empty() {
                return Err(FigureError::NoRow { file: figure.source.clone(), row: row.clone() });
            }
            out.extend(mine.into_iter().map(|l| l.to_string()));
        }
    }
    if !figure.columns.is_empty() {
        let headings = cells(head[0]);
        let keep = figure
            .columns
            .iter()
            .map(|c| {
                let no_column = || FigureError::NoColumn { file: figure.source.clone(), column: c.clone() };
                headings.iter().position(|h| h == c).ok_or_else(no_column)
            })
            .collect::<Result<Vec<usize>, FigureError>>()?;
        out = keep_columns(out, &keep);
    }
    out.push(String::new());
    out.push(format!("<sub>From `{}`: {}.</sub>", figure.source, what_made(source)));
    Ok(out)
}

/// What a run's file (`source`, its text) says made it, without the full stop: its line
/// `Made by umbra at commit …`, or that the run did not say.
#[must_use]
pub fn what_made(source: &str) -> String {
    let made = source.lines().find(|l| l.to_lowercase().contains(MADE_BY));
    made.map_or("a run that did not say which commit made it".to_string(), |l| {
        l.trim().trim_matches('*').trim_end_matches('.').to_string()
    })
}

/// `document` with every figure block written anew, each from its file (read by `read`, given
/// the path from the project's root).
pub fn rewrite(document: &str, read: impl Fn(&str) -> Result<String, String>) -> Result<String, FigureError> {
    let lines: Vec<&str> = document.lines().collect();
    let mut out: Vec<String> = Vec::with_capacity(lines.len());
    let mut i = 0;
    while i < lines.len() {
        out.push(lines[i].to_string());
        if !lines[i].trim_start().starts_with(OPEN) {
            i += 1;
            continue;
        }
        let figure = figure(lines[i], i + 1)?;
        let close =
            (i + 1..lines.len()).find(|&k| lines[k].trim() == CLOSE).ok_or(FigureError::Unclosed { line: i + 1 })?;
        let source = read(&figure.source).map_err(|why| FigureError::Source { file: figure.source.clone(), why })?;
        out.extend(block(&figure, &source)?);
        out.push(CLOSE.to_string());
        i = close + 1;
    }
    let mut text = out.join("\n");
    if document.ends_with('\n') {
        text.push('\n');
    }
    Ok(text)
}

/// The targets of the inline links and images in `text`: `[label](target)`, outside code.
#[must_use]
pub fn links(text: &str) -> Vec<String> {
    let mut out = Vec::new();
    let mut fenced = false;
    for line in text.lines() {
        if line.trim_start().starts_with("```") {
            fenced = !fenced;
            continue;
        }
        if fenced {
            continue;
        }
        // Inline code spans may hold brackets that are not links.
        let plain: String = line.split('`').step_by(2).collect::<Vec<_>>().join(" ");
        let mut rest = plain.as_str();
        while let Some(at) = rest.find("](") {
            let after = &rest[at + 2..];
            let Some(end) = after.find(')') else { break };
            out.push(after[..end].trim().to_string());
            rest = &after[end..];
        }
    }
    out
}

/// The shares a paragraph quotes: each number written with decimals before ` %`.
fn shares(paragraph: &str) -> Vec<&str> {
    paragraph
        .match_indices(" %")
        .filter_map(|(at, _)| {
            let before = &paragraph[..at];
            let number = &before[before.trim_end_matches(|c: char| c.is_ascii_digit() || c == '.').len()..];
            (number.contains('.') && number.parse::<f64>().is_ok()).then_some(number)
        })
        .collect()
}

/// Whether `text` holds a number that, rounded to as many decimals as `quoted` has, is it.
fn holds(text: &str, quoted: &str) -> bool {
    let decimals = quoted.split_once('.').map_or(0, |(_, d)| d.len());
    text.split(|c: char| !(c.is_ascii_digit() || c == '.'))
        .filter_map(|n| n.parse::<f64>().ok())
        .any(|n| format!("{n:.decimals$}") == quoted)
}

/// `link` (as a document in `base`, a folder from the project's root, writes it) from the
/// project's root, its `#anchor` left out: `../bench/summary.md` in `docs/book` is
/// `docs/bench/summary.md`.
fn from_root(base: &Path, link: &str) -> String {
    let link = link.split('#').next().unwrap_or(link);
    let mut parts: Vec<&str> = Vec::new();
    let base = base.to_str().unwrap_or("");
    let start = if link.starts_with("docs/") { "" } else { base };
    for part in start.split('/').chain(link.split('/')) {
        match part {
            "" | "." => {}
            ".." => {
                parts.pop();
            }
            _ => parts.push(part),
        }
    }
    parts.join("/") + if link.ends_with('/') { "/" } else { "" }
}

/// The words `text` writes in inline code (`` `like this` ``).
fn code_words(text: &str) -> impl Iterator<Item = &str> {
    text.split('`').skip(1).step_by(2).flat_map(str::split_whitespace)
}

/// The runs `text` names, from the project's root: the `docs/bench…` files or folders it links
/// (as a document in `base` links them) or writes in code (`docs/bench-lights/`).
fn runs_named(text: &str, base: &Path) -> Vec<String> {
    let in_code = code_words(text);
    let linked = links(text).into_iter().map(|l| from_root(base, &l));
    linked.chain(in_code.map(|code| from_root(base, code))).filter(|run| run.starts_with("docs/bench")).collect()
}

/// The tests `text` names in code (`--test NAME` or `tests/NAME.rs`), as their files from the
/// project's root: a share a paragraph quotes from a test's printout has no run to be checked
/// against, only the test that prints it again.
fn tests_named(text: &str) -> Vec<String> {
    let words: Vec<&str> = code_words(text).collect();
    let after_flag = words.windows(2).filter(|w| w[0] == "--test").map(|w| format!("tests/{}.rs", w[1]));
    let files = words.iter().filter(|w| w.starts_with("tests/") && w.ends_with(".rs")).map(|w| (*w).to_string());
    after_flag.chain(files).collect()
}

/// The text of the runs named: each file, and the run's own files in its folder (`results.csv`,
/// `summary.md`, `lights.md`), those `read` can read.
fn runs_text(runs: &[String], read: &impl Fn(&str) -> Result<String, String>) -> String {
    let mut text = String::new();
    for run in runs {
        let folder = if run.ends_with('/') { Path::new(run) } else { Path::new(run).parent().unwrap_or(Path::new("")) };
        let own = ["results.csv", "summary.md", "lights.md"].map(|f| folder.join(f).to_string_lossy().into_owned());
        for file in std::iter::once(run.clone()).chain(own) {
            text += &read(&file).unwrap_or_default();
        }
    }
    text
}

/// The shares `document`'s prose quotes that no run it names for them holds, each as `line N:
/// 0.052 %`. `base` is the document's folder from the project's root; `read` reads a file from
/// the root. A paragraph's runs are those it names (links to `docs/bench…` files, or their
/// folders written in code), or else the runs last named in its section (by a paragraph or a
/// figure block since the last heading). A paragraph that names the test printing its numbers
/// (`--test NAME` or `tests/NAME.rs`, a file `read` finds) is left alone, as are tables, code
/// and figure blocks (a run or `umbra` writes those). So a number retyped from a run, or quoted
/// from one run beside a link to another, is found.
pub fn unsourced_shares(document: &str, base: &Path, read: impl Fn(&str) -> Result<String, String>) -> Vec<String> {
    let (mut out, mut paragraph, mut first) = (Vec::new(), String::new(), 0);
    let (mut fenced, mut figure, mut section) = (false, false, Vec::new());
    for (i, line) in document.lines().chain(std::iter::once("")).enumerate() {
        let text = line.trim();
        if text.starts_with('#') && !fenced {
            section.clear();
        }
        if let Some(source) = text.strip_prefix(OPEN).and_then(|t| t.split(['|', ' ']).find(|s| !s.is_empty())) {
            section = vec![from_root(base, source)];
        }
        fenced ^= text.starts_with("```");
        figure = (figure || text.starts_with(OPEN)) && text != CLOSE;
        if text.is_empty() {
            let named = runs_named(&paragraph, base);
            if !named.is_empty() {
                section = named;
            }
            if tests_named(&paragraph).iter().any(|test| read(test).is_ok()) {
                paragraph.clear();
                continue;
            }
            let runs = runs_text(&section, &read);
            out.extend(
                shares(&paragraph).into_iter().filter(|s| !holds(&runs, s)).map(|s| format!("line {first}: {s} %")),
            );
            paragraph.clear();
        } else if !(fenced || figure || text.starts_with('|') || text.starts_with("```") || text == CLOSE) {
            if paragraph.is_empty() {
                first = i + 1;
            }
            paragraph += line;
            paragraph.push('\n');
        }
    }
    out
}

/// The README and every page of the book under `root`, the documents figures are written into.
#[must_use]
pub fn documents(root: &Path) -> Vec<PathBuf> {
    let mut pages: Vec<PathBuf> = std::fs::read_dir(root.join("docs/book"))
        .map(|d| d.flatten().map(|e| e.path()).filter(|p| p.extension().is_some_and(|e| e == "md")).collect())
        .unwrap_or_default();
    pages.sort();
    std::iter::once(root.join("README.md")).chain(pages).collect()
}

/// The line a run's summary carries to say what made it: the commit checked out in `dir` (and
/// whether what is built into umbra had changes not committed: its code, shaders, assets and
/// manifest), as git tells (that git did not tell, where it cannot), and the adapter it ran on.
#[must_use]
pub fn made_by(dir: &Path, adapter: &str) -> String {
    let git = |args: &[&str]| {
        let out = std::process::Command::new("git").args(args).current_dir(dir).output().ok()?;
        out.status.success().then(|| String::from_utf8_lossy(&out.stdout).trim().to_string())
    };
    match git(&["rev-parse", "--short=10", "HEAD"]) {
        Some(commit) => {
            // Only what is built into umbra counts: a run rewrites its own folder under docs/ as
            // it goes, and a script or a test edited meanwhile is not in its binary.
            let built = ["src", "shaders", "assets", "Cargo.toml", "Cargo.lock", "build.rs"];
            let status = ["status", "--porcelain", "--untracked-files=no", "--"].into_iter().chain(built);
            let changed = git(&status.collect::<Vec<_>>()).is_some_and(|s| !s.is_empty());
            let changes = if changed { " with changes not committed" } else { "" };
            format!("Made by umbra at commit {commit}{changes} on {adapter}.")
        }
        None => format!("Made by umbra at a commit git could not tell on {adapter}."),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const RUN: &str = "# a run\n\nMade by umbra at commit abc123.\n\n| n | ms |\n| --- | --- |\n| **4** (default) | 1 |\n\
                       | 64 | 2 |\n\nlater\n\n| x |\n| --- |\n| 9 |\n";

    fn read(path: &str) -> Result<String, String> {
        if path == "run.md" { Ok(RUN.to_string()) } else { Err("no such file".to_string()) }
    }

    #[test]
    fn a_block_is_written_from_its_table_with_the_run_that_made_it() {
        let doc = "text\n<!-- figure: run.md | rows: 64 -->\nretyped | 3\n<!-- /figure -->\nafter\n";
        let written = rewrite(doc, read).unwrap();
        let expected = "text\n<!-- figure: run.md | rows: 64 -->\n| n | ms |\n| --- | --- |\n| 64 | 2 |\n\n\
                        <sub>From `run.md`: Made by umbra at commit abc123.</sub>\n<!-- /figure -->\nafter\n";
        assert_eq!(written, expected);
        assert_eq!(rewrite(&written, read).unwrap(), written, "written again, it is the same");
        let whole = rewrite("<!-- figure: run.md -->\n<!-- /figure -->", read).unwrap();
        assert!(whole.contains("| **4** (default) | 1 |\n| 64 | 2 |"), "{whole}");
        let later = rewrite("<!-- figure: run.md | after: later -->\n<!-- /figure -->", read).unwrap();
        assert!(later.contains("| x |\n| --- |\n| 9 |"), "{later}");
        let bold = rewrite("<!-- figure: run.md | rows: 4 (default) -->\n<!-- /figure -->", read);
        assert!(bold.unwrap().contains("| **4** (default) | 1 |"));
    }

    #[test]
    fn rows_are_named_by_their_first_or_second_cell_and_columns_by_their_heading() {
        let run = "| family | configuration | ms | % |\n| --- | --- | --- | --- |\n| hard | **a** (default) | 1 | 0.5 |\n\
                   | grid | b | 2 | 0.4 |\n| grid | c | 3 | 0.3 |\n";
        let figure = Figure {
            source: "run.md".to_string(),
            after: None,
            rows: vec!["c".to_string(), "a (default)".to_string()],
            columns: vec!["configuration".to_string(), "%".to_string()],
        };
        let out = block(&figure, run).unwrap();
        assert_eq!(out[..4], ["| configuration | % |", "| --- | --- |", "| c | 0.3 |", "| **a** (default) | 0.5 |"]);
        let grid = Figure { rows: vec!["grid".to_string()], columns: Vec::new(), ..figure };
        assert_eq!(block(&grid, run).unwrap().len(), 2 + 2 + 2, "both rows of the family, a gap, the source");
    }

    #[test]
    fn a_share_quoted_in_prose_is_found_in_a_run_its_paragraph_or_section_names() {
        let read = |path: &str| match path {
            "docs/bench-a/summary.md" => Ok("| default | 0.0520 | 12.5 |".to_string()),
            "docs/bench-b/summary.md" => Ok("| default | 0.0611 |".to_string()),
            "docs/bench-b/results.csv" => Ok("default,0.0611,4.7368".to_string()),
            "docs/bench-c/lights.md" => Ok("| 64 | 0.0333 |".to_string()),
            "tests/stability.rs" => Ok("fn main() {}".to_string()),
            _ => Err("no such file".to_string()),
        };
        let doc = "The default gets 0.052 % wrong ([run](docs/bench-a/summary.md#x)), and\n\
                   12.5 % of it, 3 % of all.\n\n\
                   Retyped: 0.061 % here ([run](docs/bench-a/summary.md)).\n\n\
                   Its section's run: 0.052 %.\n\n\
                   # Another section\n\n\
                   No run named: 0.052 %.\n\n\
                   ```\n0.999 % in code\n```\n\
                   | 0.777 % | in a table |\n\n\
                   <!-- figure: docs/bench-b/summary.md -->\n0.555 % in a block\n<!-- /figure -->\n\
                   Beside its block's run: 0.061 % and 4.7 %.\n\n\
                   Named in code, `docs/bench-c/` (0.033 %), not 0.061 %.\n";
        assert_eq!(
            unsourced_shares(doc, Path::new(""), read),
            ["line 4: 0.061 %", "line 10: 0.052 %", "line 22: 0.061 %"]
        );
        let book = "From [a run](../bench-b/summary.md): 0.061 %.\n";
        assert!(unsourced_shares(book, Path::new("docs/book"), read).is_empty(), "a link from the book's folder");
        let printed = "As `cargo test --test stability` prints: 0.777 %.\n\nAs `tests/stability.rs` does: 0.777 %.\n\n\
                       As `cargo test --test gone` did: 0.777 %.\n";
        assert_eq!(unsourced_shares(printed, Path::new(""), read), ["line 5: 0.777 %"], "a test that is not there");
        assert_eq!(shares("of 1,024 lights 0.5 % and 40 % and 0.25 %, x%, 64²·0.1 %"), ["0.5", "0.25", "0.1"]);
        assert_eq!(from_root(Path::new("docs/book"), "../../README.md#x"), "README.md");
        assert_eq!(from_root(Path::new("docs/book"), "docs/bench/"), "docs/bench/");
    }

    #[test]
    fn a_run_that_does_not_say_what_made_it_is_named_so() {
        let figure = Figure { source: "old.md".to_string(), after: None, rows: Vec::new(), columns: Vec::new() };
        let out = block(&figure, "| a |\n| --- |\n| 1 |").unwrap();
        assert_eq!(out.last().unwrap(), "<sub>From `old.md`: a run that did not say which commit made it.</sub>");
    }

    #[test]
    fn broken_blocks_and_sources_are_named() {
        let err = |doc: &str| rewrite(doc, read).unwrap_err();
        assert_eq!(err("a\n<!-- figure: run.md -->\n| x |"), FigureError::Unclosed { line: 2 });
        assert!(matches!(err("<!-- figure: -->\n<!-- /figure -->"), FigureError::Opening { line: 1, .. }));
        assert!(matches!(err("<!-- figure: run.md | colour: red -->\n<!-- /figure -->"), FigureError::Opening { .. }));
        assert!(matches!(err("<!-- figure: gone.md -->\n<!-- /figure -->"), FigureError::Source { .. }));
        let no_row = err("<!-- figure: run.md | rows: 16 -->\n<!-- /figure -->");
        assert_eq!(no_row, FigureError::NoRow { file: "run.md".to_string(), row: "16".to_string() });
        let no_table = err("<!-- figure: run.md | after: nowhere -->\n<!-- /figure -->");
        assert!(matches!(no_table, FigureError::NoTable { .. }), "{no_table}");
        let no_column = err("<!-- figure: run.md | columns: n; us -->\n<!-- /figure -->");
        assert_eq!(no_column, FigureError::NoColumn { file: "run.md".to_string(), column: "us".to_string() });
        assert_eq!(rewrite("no blocks\n", read).unwrap(), "no blocks\n");
    }
}
