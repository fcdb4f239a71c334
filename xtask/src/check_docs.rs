//! `cargo xtask check-docs`: every repository path that `README.md` and the Markdown files
//! under `docs/` name must exist, so the documentation cannot point at files that were
//! moved, renamed or never committed. CI runs it.
//!
//! What counts as a path:
//! - the target of a Markdown link `[text](target)` that is not a URL or an anchor,
//!   resolved against the linking file's folder;
//! - any word (in prose or code) that starts with a top-level folder of the repository
//!   (`crates/`, `docs/`, `scripts/`, `testdata/`, `xtask/`, `.ci/`, `.cargo/`, ...),
//!   resolved against the repository root; `*` and `?` match within one path component,
//!   and the pattern must match at least one file;
//! - a bare file name ending in `.md`, resolved against the file's folder, then `docs/`,
//!   then the root;
//! - a word starting with `../` and ending in a file extension, resolved against the file's
//!   folder: it must exist inside the repository;
//! - an absolute path ending in a file extension (`/home/me/spec.md`): always reported,
//!   since a reader's clone does not have it.
//!
//! A trailing `:LINE` and trailing punctuation are ignored. Words containing `<`, `{`, `$`
//! or `...` are placeholders, not paths. `target/` and other ignored folders are outputs,
//! not documentation targets, and are not checked.
//!
//! It also fails when a Rust module is missing from the code map of `docs/architecture.md`,
//! so a new module cannot go unmapped. Every crate under `crates/`, plus `xtask` and
//! `python`, has a section there (a `###` heading whose first code span is its folder, such
//! as `` `crates/symreg` ``), and every module of the crate (`src/**/*.rs` other than
//! `lib.rs` and `main.rs`; a `mod.rs` stands for its folder) must be named in that section.
//! A module `m` is named by any of `` `m` `` (a code span holding just the module name),
//! `m.rs` or `m/`, whichever form the module has on disk: the name survives turning a file
//! into a folder and back. A named folder covers the files inside it, because their map is
//! the folder's `mod.rs` header (`search/mod.rs` maps the search, for example).
//! And it fails on the rules of [`crate::code_shape`] (no circle, no file over 600 lines) and
//! of [`crate::features`] (no dependency compiled twice for want of a feature).
use crate::code_shape::problems as shape;
use anyhow::{Context, Result, bail};
use std::path::{Path, PathBuf};

/// Top-level entries that are outputs or local environments, never documentation targets.
const IGNORED_ROOTS: [&str; 2] = ["target", ".git"];

/// The page whose code map must name every module.
const CODE_MAP: &str = "docs/architecture.md";

/// Crate folders outside `crates/` whose modules the code map must name.
const OTHER_CRATES: [&str; 2] = ["xtask", "python"];

/// Runs the check from the repository root.
pub fn run(args: &[String]) -> Result<()> {
    if let Some(a) = args.first() {
        bail!("check-docs takes no arguments (got `{a}`)");
    }
    let root = crate::root();
    let (paths, map) = (check(&root)?, check_code_map(&root)?);
    let found = [paths, map, shape(&root)?, crate::features::problems(&root)?];
    if found.iter().all(Vec::is_empty) {
        println!(
            "check-docs: every path in README.md and docs/ exists, every module is in the \
             code map of {CODE_MAP}, no circle of use, no hand-written file too long, and \
             `cargo xtask` and the Python module build with the test build's features"
        );
        return Ok(());
    }
    found.iter().flatten().for_each(|p| eprintln!("{p}"));
    let [d, u, s, f] = found.each_ref().map(Vec::len);
    bail!("{d} dangling path(s), {u} unmapped module(s), {s} circle(s) or long file(s), {f} twice")
}

/// The modules that the code map does not name, one line each
/// (`docs/architecture.md: crates/X/src/Y.rs is not in the code map`).
fn check_code_map(root: &Path) -> Result<Vec<String>> {
    let page = root.join(CODE_MAP);
    let text =
        std::fs::read_to_string(&page).with_context(|| format!("reading {}", page.display()))?;
    let sections = code_map_sections(&text);
    let mut crates: Vec<String> = Vec::new();
    let crates_dir = root.join("crates");
    for entry in std::fs::read_dir(&crates_dir)
        .with_context(|| format!("listing {}", crates_dir.display()))?
    {
        let entry = entry?;
        if entry.path().join("src").is_dir() {
            crates.push(format!("crates/{}", entry.file_name().to_string_lossy()));
        }
    }
    crates.sort();
    crates.extend(OTHER_CRATES.iter().map(|c| (*c).to_string()));
    let mut problems = Vec::new();
    for krate in &crates {
        let src = root.join(krate).join("src");
        if !src.is_dir() {
            continue;
        }
        let mut modules = Vec::new();
        module_files(&src, &[], &mut modules)?;
        let section = sections
            .iter()
            .find(|(name, _)| name == krate)
            .map_or("", |(_, body)| body.as_str());
        for m in unmapped(section, &modules) {
            problems.push(format!(
                "{CODE_MAP}: {krate}/src/{} is not in the code map",
                m.file
            ));
        }
    }
    Ok(problems)
}

/// The `###` sections of the page's `## Code map`: (the heading's first code span, the
/// heading and body).
fn code_map_sections(text: &str) -> Vec<(String, String)> {
    let mut out: Vec<(String, String)> = Vec::new();
    let mut in_map = false;
    for line in text.lines() {
        if let Some(h) = line.strip_prefix("## ") {
            in_map = h.trim() == "Code map";
            continue;
        }
        if !in_map {
            continue;
        }
        if let Some(h) = line.strip_prefix("### ") {
            let name = h.split('`').nth(1).unwrap_or(h).trim().to_string();
            out.push((name, String::new()));
        }
        if let Some((_, body)) = out.last_mut() {
            body.push_str(line);
            body.push('\n');
        }
    }
    out
}

/// A module file of a crate.
#[derive(Debug, PartialEq)]
struct Module {
    /// Path under `src/` (`search/run.rs`, `cases/mod.rs`).
    file: String,
    /// The module's name and those of the folders that hold it, outermost first
    /// (`["search", "run"]`; `["cases"]` for `cases/mod.rs`).
    names: Vec<String>,
}

/// Every module file under `dir` (a crate's `src/` at the top), sorted by path.
fn module_files(dir: &Path, folders: &[String], out: &mut Vec<Module>) -> Result<()> {
    let entries = sorted_entries(dir)?;
    for p in entries {
        let name = p
            .file_name()
            .map(|n| n.to_string_lossy().into_owned())
            .unwrap_or_default();
        let mut names = folders.to_vec();
        if p.is_dir() {
            names.push(name);
            module_files(&p, &names, out)?;
            continue;
        }
        let Some(stem) = name.strip_suffix(".rs") else {
            continue;
        };
        if folders.is_empty() && (stem == "lib" || stem == "main") {
            continue;
        }
        if stem != "mod" {
            names.push(stem.to_string());
        }
        if names.is_empty() {
            continue; // a `src/mod.rs`: not a module of its own
        }
        let mut file: Vec<&str> = folders.iter().map(String::as_str).collect();
        file.push(&name);
        out.push(Module {
            file: file.join("/"),
            names,
        });
    }
    Ok(())
}

/// The modules that `section` does not name, themselves or through a folder that holds them.
fn unmapped<'a>(section: &str, modules: &'a [Module]) -> Vec<&'a Module> {
    modules
        .iter()
        .filter(|m| !m.names.iter().any(|n| names_module(section, n)))
        .collect()
}

/// Whether `text` names module `name` as `` `name` ``, `name.rs` or `name/`.
fn names_module(text: &str, name: &str) -> bool {
    if text.contains(&format!("`{name}`")) {
        return true;
    }
    let ident = |c: char| c.is_alphanumeric() || c == '_';
    [format!("{name}.rs"), format!("{name}/")]
        .iter()
        .any(|form| {
            text.match_indices(form.as_str()).any(|(i, _)| {
                let before = text[..i].chars().next_back();
                let after = text[i + form.len()..].chars().next();
                !before.is_some_and(ident)
                    && !after.is_some_and(|c| ident(c) && form.ends_with(".rs"))
            })
        })
}

/// The dangling paths, one line each (`file:line: path`).
fn check(root: &Path) -> Result<Vec<String>> {
    let roots = top_level_dirs(root)?;
    let mut files = vec![root.join("README.md")];
    markdown_files(&root.join("docs"), &mut files)?;
    let mut problems = Vec::new();
    for file in &files {
        let text =
            std::fs::read_to_string(file).with_context(|| format!("reading {}", file.display()))?;
        let dir = file.parent().unwrap_or(root);
        let shown = file
            .strip_prefix(root)
            .unwrap_or(file)
            .display()
            .to_string();
        for (i, line) in text.lines().enumerate() {
            for path in named_paths(line, &roots) {
                if !exists(root, dir, &path) {
                    problems.push(format!("{shown}:{}: {}", i + 1, path.text));
                }
            }
        }
    }
    Ok(problems)
}

/// The repository's top-level folders, except outputs and local virtual environments.
fn top_level_dirs(root: &Path) -> Result<Vec<String>> {
    let mut out = Vec::new();
    for entry in std::fs::read_dir(root).with_context(|| format!("listing {}", root.display()))? {
        let entry = entry?;
        let name = entry.file_name().to_string_lossy().into_owned();
        if entry.path().is_dir()
            && !IGNORED_ROOTS.contains(&name.as_str())
            && !name.starts_with(".venv")
        {
            out.push(name);
        }
    }
    Ok(out)
}

fn markdown_files(dir: &Path, out: &mut Vec<PathBuf>) -> Result<()> {
    let entries = sorted_entries(dir)?;
    for p in entries {
        if p.is_dir() {
            markdown_files(&p, out)?;
        } else if p.extension().is_some_and(|e| e == "md") {
            out.push(p);
        }
    }
    Ok(())
}

/// How a named path is resolved.
#[derive(Debug, PartialEq)]
enum Base {
    /// A Markdown link: relative to the linking file.
    File,
    /// A word starting with a top-level folder: relative to the root.
    Root,
    /// A bare `*.md` name: the file's folder, `docs/`, or the root.
    Any,
    /// An absolute path: never part of the repository.
    Outside,
}

#[derive(Debug, PartialEq)]
struct Named {
    text: String,
    base: Base,
}

/// The paths a line names.
fn named_paths(line: &str, roots: &[String]) -> Vec<Named> {
    let mut out = Vec::new();
    // Markdown links.
    let mut rest = line;
    while let Some(i) = rest.find("](") {
        let after = &rest[i + 2..];
        let Some(end) = after.find(')') else { break };
        let target = after[..end].split_whitespace().next().unwrap_or("");
        let target = target.split('#').next().unwrap_or("");
        if !target.is_empty() && !target.contains("://") && !target.starts_with("mailto:") {
            out.push(Named {
                text: target.to_string(),
                base: Base::File,
            });
        }
        rest = &after[end..];
    }
    // Words.
    for word in line.split(|c: char| {
        c.is_whitespace()
            || matches!(
                c,
                '`' | '(' | ')' | '[' | ']' | '"' | '\'' | ',' | ';' | '|' | '='
            )
    }) {
        let w = clean(word);
        if w.is_empty() || w.contains("://") || ["<", "{", "$", "..."].iter().any(|p| w.contains(p))
        {
            continue;
        }
        let first = w.split('/').next().unwrap_or("");
        if w.contains('/') && roots.iter().any(|r| r == first) {
            out.push(Named {
                text: w.to_string(),
                base: Base::Root,
            });
        } else if (w.starts_with('/') || w.starts_with("../")) && has_extension(w) {
            out.push(Named {
                text: w.to_string(),
                base: if w.starts_with('/') {
                    Base::Outside
                } else {
                    Base::File
                },
            });
        } else if !w.contains('/') && w.ends_with(".md") && w.len() > 3 {
            out.push(Named {
                text: w.to_string(),
                base: Base::Any,
            });
        }
    }
    out
}

/// Whether the last component looks like `name.ext` with a short alphabetic extension.
fn has_extension(w: &str) -> bool {
    let last = w.rsplit('/').next().unwrap_or("");
    last.rsplit_once('.').is_some_and(|(stem, ext)| {
        !stem.is_empty()
            && (1..=4).contains(&ext.len())
            && ext.chars().all(|c| c.is_ascii_alphabetic())
    })
}

/// A word without an `#anchor`, emphasis, trailing punctuation, a `:LINE` suffix or a
/// leading `./`.
fn clean(word: &str) -> &str {
    let word = word.split('#').next().unwrap_or("");
    let mut w = word
        .trim_start_matches('*')
        .trim_end_matches(['.', ':', '!', '?', '*']);
    if let Some((head, tail)) = w.rsplit_once(':')
        && !tail.is_empty()
        && tail.chars().all(|c| c.is_ascii_digit() || c == '-')
    {
        w = head;
    }
    w = w.strip_prefix("./").unwrap_or(w);
    w.trim_end_matches('/')
}

fn exists(root: &Path, dir: &Path, p: &Named) -> bool {
    let bases: Vec<PathBuf> = match p.base {
        Base::Outside => return false,
        Base::File if p.text.starts_with("../") => {
            // must resolve inside the repository
            let Ok(found) = dir.join(&p.text).canonicalize() else {
                return false;
            };
            let Ok(root) = root.canonicalize() else {
                return false;
            };
            return found.starts_with(root);
        }
        Base::File => vec![dir.to_path_buf()],
        Base::Root => vec![root.to_path_buf()],
        Base::Any => vec![dir.to_path_buf(), root.join("docs"), root.to_path_buf()],
    };
    bases.iter().any(|b| matches_any(b, &p.text))
}

/// Whether `pattern` (components may hold `*` and `?`) names at least one existing entry
/// under `base`.
fn matches_any(base: &Path, pattern: &str) -> bool {
    if !pattern.contains(['*', '?']) {
        return base.join(pattern).exists();
    }
    let mut current = vec![base.to_path_buf()];
    for comp in pattern.split('/').filter(|c| !c.is_empty()) {
        let mut next = Vec::new();
        for dir in &current {
            if !comp.contains(['*', '?']) {
                let p = dir.join(comp);
                if p.exists() {
                    next.push(p);
                }
                continue;
            }
            let Ok(entries) = std::fs::read_dir(dir) else {
                continue;
            };
            for e in entries.flatten() {
                if wildcard(comp, &e.file_name().to_string_lossy()) {
                    next.push(e.path());
                }
            }
        }
        current = next;
    }
    !current.is_empty()
}

/// `*` matches any run of characters, `?` one character.
fn wildcard(pattern: &str, name: &str) -> bool {
    let p: Vec<char> = pattern.chars().collect();
    let n: Vec<char> = name.chars().collect();
    let (mut i, mut j) = (0, 0);
    let (mut star, mut mark) = (None, 0);
    while j < n.len() {
        if i < p.len() && (p[i] == '?' || p[i] == n[j]) {
            i += 1;
            j += 1;
        } else if i < p.len() && p[i] == '*' {
            star = Some(i);
            mark = j;
            i += 1;
        } else if let Some(s) = star {
            i = s + 1;
            mark += 1;
            j = mark;
        } else {
            return false;
        }
    }
    while i < p.len() && p[i] == '*' {
        i += 1;
    }
    i == p.len()
}

/// The entries of `dir`, sorted by path.
fn sorted_entries(dir: &Path) -> Result<Vec<PathBuf>> {
    let mut entries: Vec<PathBuf> = std::fs::read_dir(dir)
        .with_context(|| format!("listing {}", dir.display()))?
        .map(|e| e.map(|e| e.path()))
        .collect::<Result<_, _>>()?;
    entries.sort();
    Ok(entries)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn roots() -> Vec<String> {
        vec!["crates".into(), "docs".into()]
    }

    #[test]
    fn finds_links_words_and_bare_markdown_names() {
        let got = named_paths(
            "see [map](architecture.md#code), `crates/symreg/src/lib.rs:12`, docs/x/, \
             interfaces.md. and https://example.com/docs/a <crates/NAME> target/out",
            &roots(),
        );
        let texts: Vec<&str> = got.iter().map(|n| n.text.as_str()).collect();
        assert_eq!(
            texts,
            [
                "architecture.md",
                "architecture.md",
                "crates/symreg/src/lib.rs",
                "docs/x",
                "interfaces.md"
            ]
        );
        assert_eq!(got[0].base, Base::File);
        assert_eq!(got[2].base, Base::Root);
        assert_eq!(got[4].base, Base::Any);
    }

    #[test]
    fn paths_outside_the_repository_are_reported() {
        let got = named_paths(
            "(`/work/shared/spec/interfaces.md`, and `../shared/spec/method.md`: 1/f m/s",
            &roots(),
        );
        assert_eq!(got.len(), 2);
        assert_eq!(got[0].base, Base::Outside);
        assert_eq!(got[1].base, Base::File);
        let root = crate::root();
        assert!(!exists(&root, &root, &got[0]));
        assert!(!exists(&root, &root.join("docs"), &got[1]));
        let inside = Named {
            text: "../README.md".into(),
            base: Base::File,
        };
        assert!(exists(&root, &root.join("docs"), &inside));
    }

    #[test]
    fn wildcards_match_within_a_component() {
        assert!(wildcard("fig*.svg", "fig04_command.svg"));
        assert!(wildcard("ref_?.py", "ref_a.py"));
        assert!(!wildcard("fig*.svg", "fig04.csv"));
        assert!(!wildcard("*.md", "md"));
    }

    fn module(file: &str) -> Module {
        let mut names: Vec<String> = file.split('/').map(str::to_string).collect();
        if let Some(last) = names.pop()
            && last != "mod.rs"
        {
            names.push(last.trim_end_matches(".rs").to_string());
        }
        Module {
            file: file.into(),
            names,
        }
    }

    const MAP: &str = "# Architecture\n\n## Code map\n\n### `crates/a` (`hxai-a`)\n\n\
        The `expr` module, `ops.rs`, and the search (`search/`).\n\n### `xtask`\n\n\
        `sub_model.rs` and `model.rsx`.\n\n## Cross-cutting concerns\n\n`fit.rs`\n";

    #[test]
    fn a_module_missing_from_the_code_map_is_reported() {
        let sections = code_map_sections(MAP);
        let names: Vec<&str> = sections.iter().map(|(n, _)| n.as_str()).collect();
        assert_eq!(names, ["crates/a", "xtask"]);
        let (_, a) = &sections[0];
        let (_, x) = &sections[1];
        let modules = [module("fit.rs"), module("model.rs")];
        let missing: Vec<&str> = unmapped(a, &modules)
            .iter()
            .map(|m| m.file.as_str())
            .collect();
        // `fit.rs` is named after the code map, which does not count.
        assert_eq!(missing, ["fit.rs", "model.rs"]);
        // `sub_model.rs` and `model.rsx` are other names.
        assert_eq!(unmapped(x, &modules).len(), 2);
        // A crate without a section: every module is missing.
        assert_eq!(unmapped("", &modules).len(), 2);
    }

    #[test]
    fn a_module_named_in_any_form_is_not_reported() {
        let sections = code_map_sections(MAP);
        let (_, a) = &sections[0];
        // As a module name, a file name or a folder, before and after a split into a
        // folder; a named folder covers its files.
        let modules = [
            module("expr.rs"),
            module("expr/mod.rs"),
            module("expr/parse.rs"),
            module("ops.rs"),
            module("ops/mod.rs"),
            module("search/mod.rs"),
            module("search/run.rs"),
            module("search.rs"),
        ];
        assert!(unmapped(a, &modules).is_empty());
    }

    #[test]
    fn module_files_skip_the_crate_roots() {
        let src = crate::root().join("xtask/src");
        let mut modules = Vec::new();
        assert!(module_files(&src, &[], &mut modules).is_ok());
        let files: Vec<&str> = modules.iter().map(|m| m.file.as_str()).collect();
        assert!(files.contains(&"check_docs.rs"));
        assert!(!files.contains(&"main.rs"));
        let root = crate::root();
        let mut sim = Vec::new();
        assert!(module_files(&root.join("crates/sim/src"), &[], &mut sim).is_ok());
        let cases = sim.iter().find(|m| m.file == "cases/mod.rs");
        assert_eq!(
            cases.map(|m| m.names.clone()),
            Some(vec!["cases".to_string()])
        );
    }

    #[test]
    fn a_missing_path_is_caught_and_a_glob_resolves() {
        let root = crate::root();
        let roots = top_level_dirs(&root).unwrap_or_default();
        assert!(roots.iter().any(|r| r == "crates"));
        let missing = Named {
            text: "docs/parts/baselines-architecture.md".into(),
            base: Base::Root,
        };
        assert!(!exists(&root, &root, &missing));
        let present = Named {
            text: "docs/results/*.svg".into(),
            base: Base::Root,
        };
        assert!(exists(&root, &root, &present));
    }
}
