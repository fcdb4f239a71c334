//! The `--quick` reproduction end to end, so the glue between the crates cannot rot, and
//! its section "Beyond the paper" (issue 13): both cases, both splits, every model, the
//! figures.
//!
//! Invariants checked: every promised output exists; every table has its rows; the numbers
//! are finite; the sample table has one row per sample with the contract's columns; two runs
//! give identical files and identical "Beyond the paper" results (the committed results must
//! be a pure function of code and seed).
//!
//! `run` computes the section "Beyond the paper" with `beyond::compute` on the same
//! settings, so both tests read one reproduction, computed once (`quick`), instead of
//! running the pipeline once more for the section alone (issue 51: about 80 s of the test
//! run on 2 cores).

use hxai_reproduce::beyond::{figure_name, markdown};
use hxai_reproduce::{ReproduceConfig, Reproduction, run};
use std::sync::OnceLock;

#[path = "../../hybrid/tests/it/common/mod.rs"]
mod hybrid_common;
use hybrid_common::COMPARE_MODELS;

/// The quick reproduction, computed by the first test that asks for it.
fn quick() -> Result<&'static Reproduction, String> {
    static RUN: OnceLock<Result<Reproduction, String>> = OnceLock::new();
    RUN.get_or_init(|| run(&ReproduceConfig::quick(), &mut |_| {}).map_err(|e| e.to_string()))
        .as_ref()
        .map_err(Clone::clone)
}

#[test]
fn quick_run_writes_every_output_and_is_repeatable() -> Result<(), Box<dyn std::error::Error>> {
    let cfg = ReproduceConfig::quick();
    let a = quick()?;
    let names: Vec<&str> = a.files.iter().map(|(n, _)| n.as_str()).collect();
    for want in ["README.md", "results.json", "samples.csv"] {
        assert!(names.contains(&want), "missing {want}");
    }
    for (file, _) in hxai_reproduce::plots_captions() {
        assert!(names.contains(file), "missing figure {file}");
    }
    for (name, content) in &a.files {
        if name.ends_with(".svg") {
            assert!(content.starts_with("<svg"), "{name} is not SVG");
        }
    }

    let r = &a.results;
    let models: Vec<&str> = r.table3.iter().map(|m| m.name.as_str()).collect();
    assert_eq!(
        models,
        [
            "linear", "lasso_cv", "tree_5", "tree_6", "tree_8", "forest", "symbolic"
        ]
    );
    assert!(
        r.table3
            .iter()
            .all(|m| m.test.rmse.is_finite() && m.test.r2.is_finite())
    );
    assert_eq!(r.cv.len(), 3);
    assert!(
        r.cv.iter()
            .all(|c| c.folds.len() == 5 && c.ci_t[0] <= c.ci_normal[0])
    );
    assert!(r.hybrid.physics.rmse.is_finite() && r.hybrid.hybrid.rmse.is_finite());
    assert!(r.symbolic.complexity >= 1);

    let csv = &a
        .files
        .iter()
        .find(|(n, _)| n == "samples.csv")
        .ok_or("no samples.csv")?
        .1;
    let mut lines = csv.lines();
    let header = lines.next().ok_or("empty samples.csv")?;
    let mut want = vec!["record".to_string(), "window".into(), "split".into()];
    want.extend((1..=12).map(|i| format!("f{i}")));
    want.extend(["A_phys".to_string(), "A_true".into(), "delta".into()]);
    assert_eq!(header, want.join(","));
    assert_eq!(lines.count(), r.data.n_samples);

    // The one repeat run, for both tests: the files hold the figures of "Beyond the paper"
    // too, and its results are compared on their own.
    let b = run(&cfg, &mut |_| {})?;
    assert_eq!(a.files, b.files, "two runs with the same seed differ");
    assert_eq!(
        serde_json::to_string(&a.beyond)?,
        serde_json::to_string(&b.beyond)?,
        "results differ between two runs"
    );
    Ok(())
}

/// "Beyond the paper" as `run` computed it (with `beyond::compute`); its repeat run is in
/// `quick_run_writes_every_output_and_is_repeatable`.
#[test]
fn every_case_at_both_splits() -> Result<(), Box<dyn std::error::Error>> {
    let run = quick()?;
    let (a, files) = (&run.beyond, &run.files);
    let names: Vec<&str> = a.cases.iter().map(|c| c.name.as_str()).collect();
    assert_eq!(names, ["roughness", "cutting_force", "tool_life"]);
    for c in &a.cases {
        for (s, kind) in [(&c.random, "random"), (&c.extrapolation, "extrapolate")] {
            assert_eq!(s.split, kind);
            let models: Vec<&str> = s.models.iter().map(|m| m.name.as_str()).collect();
            assert_eq!(models, COMPARE_MODELS);
            assert!(
                s.models
                    .iter()
                    .all(|m| m.metrics.rmse.is_finite() && m.metrics.r2.is_finite())
            );
            assert_eq!(s.n_train + s.n_test, a.rows);
            assert!(!s.parameters.is_empty());
            assert!(s.parameters.iter().all(|p| p.value.is_finite()));
            assert!(!s.hybrid.equation.is_empty());
        }
        // Cross-validation at the random split only.
        assert_eq!(c.random.cv.len(), COMPARE_MODELS.len());
        assert!(c.extrapolation.cv.is_empty());
        // The extrapolation split tests on the high values of its column.
        let [train, test] = c.extrapolation.ranges.ok_or("no ranges")?;
        assert!(train[1] <= test[0], "{train:?} vs {test:?}");
        assert!(
            files
                .iter()
                .any(|(n, svg)| *n == figure_name(&c.name) && svg.starts_with("<svg"))
        );
    }
    let page = markdown(a);
    assert!(page.contains("## Beyond the paper: the framework on three more processes"));
    Ok(())
}
