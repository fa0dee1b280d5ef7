//! The front door and the book hold together: every relative link in `README.md` and in
//! `docs/**/*.md` names a file that exists, and every `#anchor` a heading of the page it points
//! at; the README stays short enough to read in five minutes.

use std::collections::HashSet;
use std::path::{Path, PathBuf};
use umbra::figures::links;

/// The longest the README may grow (issue 25: a front door, the rest in the book).
const README_MAX_LINES: usize = 250;

fn markdown_files() -> Vec<PathBuf> {
    fn walk(dir: &Path, out: &mut Vec<PathBuf>) {
        for entry in std::fs::read_dir(dir).unwrap().flatten() {
            let path = entry.path();
            if path.is_dir() {
                walk(&path, out);
            } else if path.extension().is_some_and(|e| e == "md") {
                out.push(path);
            }
        }
    }
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let mut files = vec![root.join("README.md")];
    walk(&root.join("docs"), &mut files);
    files
}

/// A heading's anchor as GitHub makes it: lower case, punctuation dropped but for hyphens and
/// underscores, spaces turned into hyphens.
fn slug(heading: &str) -> String {
    heading
        .trim()
        .to_lowercase()
        .chars()
        .filter(|c| c.is_alphanumeric() || matches!(c, ' ' | '-' | '_'))
        .map(|c| if c == ' ' { '-' } else { c })
        .collect()
}

fn anchors(text: &str) -> HashSet<String> {
    text.lines().filter_map(|l| l.strip_prefix('#')).map(|l| slug(l.trim_start_matches('#'))).collect()
}

#[test]
fn every_relative_link_in_the_readme_and_the_book_reaches_a_file_and_a_heading() {
    let mut broken = Vec::new();
    for file in markdown_files() {
        let text = std::fs::read_to_string(&file).unwrap();
        for target in links(&text) {
            if target.contains("://") || target.starts_with("mailto:") || target.is_empty() {
                continue;
            }
            let (path, anchor) = target.split_once('#').unwrap_or((&target, ""));
            let resolved = if path.is_empty() { file.clone() } else { file.parent().unwrap().join(path) };
            if !resolved.exists() {
                broken.push(format!("{}: {target} (no such file)", file.display()));
            } else if !anchor.is_empty()
                && resolved.extension().is_some_and(|e| e == "md")
                && !anchors(&std::fs::read_to_string(&resolved).unwrap()).contains(anchor)
            {
                broken.push(format!("{}: {target} (no such heading)", file.display()));
            }
        }
    }
    assert!(broken.is_empty(), "broken links:\n{}", broken.join("\n"));
}

#[test]
fn the_readme_is_a_front_door() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let readme = std::fs::read_to_string(root.join("README.md")).unwrap();
    let lines = readme.lines().count();
    assert!(lines <= README_MAX_LINES, "README.md has {lines} lines, more than {README_MAX_LINES}");
    // Every chapter of the book is reachable from it, through the book's contents.
    let contents = root.join("docs/book/README.md");
    assert!(links(&readme).iter().any(|l| l.starts_with("docs/book/")), "the README links no chapter");
    let listed: HashSet<String> = links(&std::fs::read_to_string(contents).unwrap()).into_iter().collect();
    for chapter in std::fs::read_dir(root.join("docs/book")).unwrap().flatten() {
        let name = chapter.file_name().to_string_lossy().into_owned();
        if name.ends_with(".md") && name != "README.md" {
            assert!(listed.contains(&name), "docs/book/README.md does not list {name}");
        }
    }
}

#[test]
fn the_readmes_gallery_is_the_grid_umbra_gallery_wrote() {
    // Not retyped: the README shows docs/gallery/gallery.md's grid, its pictures seen from the root.
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let grid = |text: &str| -> Vec<String> {
        text.lines().filter(|l| l.starts_with("| ") && l.contains("](")).map(String::from).collect()
    };
    let written = std::fs::read_to_string(root.join("docs/gallery/gallery.md")).unwrap();
    let readme = std::fs::read_to_string(root.join("README.md")).unwrap();
    let expected: Vec<String> = grid(&written).iter().map(|l| l.replace("](", "](docs/gallery/")).collect();
    let shown: Vec<String> = grid(&readme).into_iter().filter(|l| l.contains("](docs/gallery/")).collect();
    assert!(!expected.is_empty());
    assert_eq!(shown, expected, "run `umbra gallery` and paste docs/gallery/gallery.md's grid into the README");
}

#[test]
fn every_figure_block_is_its_runs_table_as_it_is_now() {
    // Not retyped, not stale: each `<!-- figure: … -->` block is what `umbra docs` writes from
    // its run's file today (src/figures.rs).
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let read = |path: &str| std::fs::read_to_string(root.join(path)).map_err(|e| e.to_string());
    let mut blocks = 0;
    for document in umbra::figures::documents(root) {
        let text = std::fs::read_to_string(&document).unwrap();
        blocks += text.lines().filter(|l| l.trim_start().starts_with("<!-- figure:")).count();
        let written = umbra::figures::rewrite(&text, read).unwrap_or_else(|e| panic!("{}: {e}", document.display()));
        assert!(written == text, "{} has a figure that is not its run's: run `umbra docs`", document.display());
    }
    assert!(blocks > 0, "the README and the book hold figure blocks");
}

#[test]
fn every_share_the_readme_and_the_book_quote_is_in_a_run_they_name_for_it() {
    // One number per fact, each with where it came from: a share quoted in the prose of the
    // README or the book is in a run its paragraph (or else its section) names, so a number
    // retyped after its run was redone, or quoted from one run beside a link to another, fails
    // here (src/figures.rs).
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let read = |path: &str| std::fs::read_to_string(root.join(path)).map_err(|e| e.to_string());
    let unsourced: Vec<String> = umbra::figures::documents(root)
        .iter()
        .flat_map(|doc| {
            let name = doc.strip_prefix(root).unwrap();
            let text = std::fs::read_to_string(doc).unwrap();
            let found = umbra::figures::unsourced_shares(&text, name.parent().unwrap(), read);
            found.into_iter().map(move |f| format!("{}: {f}", name.display()))
        })
        .collect();
    assert!(unsourced.is_empty(), "shares quoted that no run named for them holds:\n{}", unsourced.join("\n"));
}

#[test]
fn links_are_found_outside_code_and_headings_make_githubs_anchors() {
    let text = "see [a](x.md#b-c) and `[no](code)`\n```\n[no](fence)\n```\n![pic](p.png)";
    assert_eq!(links(text), ["x.md#b-c", "p.png"]);
    assert_eq!(slug(" Where shadow maps fail"), "where-shadow-maps-fail");
    assert_eq!(slug("The lab: where the shadows are wrong, live"), "the-lab-where-the-shadows-are-wrong-live");
    assert_eq!(slug("At scale: ten thousand casters"), "at-scale-ten-thousand-casters");
}
