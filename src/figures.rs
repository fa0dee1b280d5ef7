//! Figures in the README and the book copied from a run's files, never retyped. A block
//!
//! ```text
//! <!-- figure: docs/bench-lights-quick/lights.md | rows: 4; 64 -->
//! (what `umbra docs` writes)
//! <!-- /figure -->
//! ```
//!
//! holds the first table of that file (with `after: TEXT`, the first after the first line
//! holding TEXT), only the rows whose first cell is one of `rows` if given (separated by `;`),
//! and under it a line naming the file and the run: the file's line that says what made it
//! (`made by umbra at commit …`, which `umbra bench` writes), or that the run did not say. `umbra
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
    /// The rows kept, by their first cell (all when empty).
    pub rows: Vec<String>,
}

/// Why a document's figures cannot be written.
#[derive(Debug, thiserror::Error, PartialEq, Eq)]
pub enum FigureError {
    /// A block's opening line is not `<!-- figure: PATH [| after: TEXT] [| rows: A; B] -->`.
    #[error("line {line}: a figure block opens with `<!-- figure: PATH [| after: TEXT] [| rows: A; B] -->`: {why}")]
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
    #[error("{file}: no row of the table has the first cell {row:?}")]
    NoRow { file: String, row: String },
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
    let mut figure = Figure { source, after: None, rows: Vec::new() };
    for part in parts {
        match part.split_once(':').map(|(k, v)| (k.trim(), v.trim())) {
            Some(("after", text)) if !text.is_empty() => figure.after = Some(text.to_string()),
            Some(("rows", rows)) => figure.rows = rows.split(';').map(|r| r.trim().to_string()).collect(),
            _ => return Err(why(&format!("{part:?} is neither `after: TEXT` nor `rows: A; B`"))),
        }
    }
    Ok(figure)
}

/// The first cell of a table row, its bold marks left out.
fn first_cell(row: &str) -> String {
    row.trim().trim_start_matches('|').split('|').next().unwrap_or("").replace("**", "").trim().to_string()
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
            let mine: Vec<&&str> = body.iter().filter(|l| first_cell(l) == *row).collect();
            if mine.is_empty() {
                return Err(FigureError::NoRow { file: figure.source.clone(), row: row.clone() });
            }
            out.extend(mine.into_iter().map(|l| l.to_string()));
        }
    }
    let made = lines
        .iter()
        .find(|l| l.to_lowercase().contains(MADE_BY))
        .map(|l| l.trim().trim_matches('*').trim_end_matches('.'));
    let run = made.map_or("a run that did not say which commit made it".to_string(), str::to_string);
    out.push(String::new());
    out.push(format!("<sub>From `{}`: {run}.</sub>", figure.source));
    Ok(out)
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
/// whether it had changes not committed), as git tells (that git did not tell, where it cannot),
/// and the adapter it ran on.
#[must_use]
pub fn made_by(dir: &Path, adapter: &str) -> String {
    let git = |args: &[&str]| {
        let out = std::process::Command::new("git").args(args).current_dir(dir).output().ok()?;
        out.status.success().then(|| String::from_utf8_lossy(&out.stdout).trim().to_string())
    };
    match git(&["rev-parse", "--short=10", "HEAD"]) {
        Some(commit) => {
            let changed = git(&["status", "--porcelain", "--untracked-files=no"]).is_some_and(|s| !s.is_empty());
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
    fn a_run_that_does_not_say_what_made_it_is_named_so() {
        let figure = Figure { source: "old.md".to_string(), after: None, rows: Vec::new() };
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
        assert_eq!(rewrite("no blocks\n", read).unwrap(), "no blocks\n");
    }
}
