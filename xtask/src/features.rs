//! The feature-unification check of `cargo xtask check-docs` (issue 51): the third-party
//! crates that `cargo xtask` and the Python module build must have every feature that
//! `cargo test --workspace` turns on, or the test build compiles them (and every crate above
//! them) a second time. A derive's `syn` lacking three features once cost 185 crates and two
//! minutes of every test run after `cargo xtask reproduce` (docs/benchmarks.md).
//!
//! `cargo tree --format '{p}|{f}'` lists each package with the features a build of the given
//! packages resolves: once for `-p xtask` and `-p hxai-python` (normal and build edges, what
//! they compile), once for the workspace with dev-dependencies (what the tests compile). A
//! package in both whose first features lack some of the second's is reported, with the
//! features `crates/hack/Cargo.toml` should turn on.
use anyhow::{Context, Result, bail};
use std::collections::{BTreeMap, BTreeSet};
use std::path::Path;
use std::process::Command;

/// Features of each package (`name vX.Y.Z`), as `cargo tree` lists them.
pub type Features = BTreeMap<String, BTreeSet<String>>;

/// The packages whose own builds must reuse the test build's artifacts.
const SHARING: [&str; 2] = ["xtask", "hxai-python"];

/// The problems found, one line each (empty when every feature set agrees).
///
/// # Errors
/// `cargo tree` failing to run or to resolve.
pub fn problems(root: &Path) -> Result<Vec<String>> {
    let tests = tree(root, &["--workspace", "-e", "normal,build,dev"])?;
    let mut out = Vec::new();
    for p in SHARING {
        let own = tree(root, &["-p", p, "-e", "normal,build"])?;
        for (package, missing) in missing_features(&own, &tests) {
            out.push(format!(
                "crates/hack/Cargo.toml: `{p}` builds {package} without the feature(s) {} that \
                 `cargo test --workspace` turns on, so the tests compile it again: add them",
                missing.into_iter().collect::<Vec<_>>().join(", ")
            ));
        }
    }
    Ok(out)
}

/// `cargo tree` with `args`, read into [`Features`].
fn tree(root: &Path, args: &[&str]) -> Result<Features> {
    let cargo = std::env::var("CARGO").unwrap_or_else(|_| "cargo".into());
    let out = Command::new(&cargo)
        .current_dir(root)
        .args([
            "tree", "--locked", "--prefix", "none", "--format", "{p}|{f}",
        ])
        .args(args)
        .output()
        .with_context(|| format!("running {cargo} tree"))?;
    if !out.status.success() {
        bail!(
            "cargo tree {} failed: {}",
            args.join(" "),
            String::from_utf8_lossy(&out.stderr).trim()
        );
    }
    Ok(parse(&String::from_utf8_lossy(&out.stdout)))
}

/// Reads `cargo tree --prefix none --format '{p}|{f}'`: one `name vX.Y.Z [(path)]
/// [(proc-macro)] [(*)]|f1,f2` a line; a package listed more than once (as a host and a
/// target dependency, say) gets the union of its lines. Workspace members (a path in
/// parentheses) are left out: their features are ours to set.
pub fn parse(text: &str) -> Features {
    let mut out = Features::new();
    for line in text.lines() {
        // `(*)` (listed above) comes after the format's text, so after the features
        let line = line.replace("(*)", "");
        let Some((package, features)) = line.trim().split_once('|') else {
            continue;
        };
        let package = package.replace("(proc-macro)", "");
        let package = package.trim();
        if package.is_empty() || package.contains('(') {
            continue;
        }
        out.entry(package.to_string()).or_default().extend(
            features
                .split(',')
                .map(str::trim)
                .filter(|f| !f.is_empty())
                .map(String::from),
        );
    }
    out
}

/// For each package of `own` also in `tests`, the features `tests` has and `own` lacks
/// (packages with none left out).
pub fn missing_features(own: &Features, tests: &Features) -> Vec<(String, BTreeSet<String>)> {
    own.iter()
        .filter_map(|(p, f)| {
            let missing: BTreeSet<String> = tests.get(p)?.difference(f).cloned().collect();
            (!missing.is_empty()).then(|| (p.clone(), missing))
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_package_lacking_a_test_feature_is_reported_and_members_are_skipped() {
        let own = parse(
            "syn v3.0.9|clone-impls,derive\nserde v1.0.0|std (*)\nsyn v3.0.9|parsing\n\
             hxai-table v0.1.0 (/w/crates/table)|\nserde_derive v1.0.0 (proc-macro)|\n",
        );
        let tests = parse(
            "syn v3.0.9|clone-impls,derive,full,parsing\nserde v1.0.0|std\n\
             hxai-table v0.1.0 (/w/crates/table)|extra\nproptest v1.0.0|std\n\
             serde_derive v1.0.0 (proc-macro)|deserialize_in_place\n",
        );
        assert_eq!(
            own["syn v3.0.9"].len(),
            3,
            "two lines of one package are joined"
        );
        assert!(!own.contains_key("hxai-table v0.1.0 (/w/crates/table)"));
        let missing = missing_features(&own, &tests);
        assert_eq!(missing.len(), 2, "{missing:?}");
        assert_eq!(
            missing[0].0, "serde_derive v1.0.0",
            "a proc-macro is checked too"
        );
        assert_eq!(missing[1].0, "syn v3.0.9");
        assert_eq!(missing[1].1.iter().collect::<Vec<_>>(), ["full"]);
        // a test-only package (proptest) is not a difference; nor is a feature only ours has
        let more = parse("serde v1.0.0|std,alloc\n");
        assert!(missing_features(&more, &tests).is_empty());
    }
}
