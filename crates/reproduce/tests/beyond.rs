//! The section "Beyond the paper" (issue 13) on the quick settings: both cases, both
//! splits, every model, the figures, and two runs giving identical output (the committed
//! results must be a pure function of code and seed).

use hxai_reproduce::ReproduceConfig;
use hxai_reproduce::beyond::{compute, figure_name, markdown};

#[path = "../../hybrid/tests/it/common/mod.rs"]
mod hybrid_common;
use hybrid_common::COMPARE_MODELS;

#[test]
fn every_case_at_both_splits_and_repeatable() -> Result<(), Box<dyn std::error::Error>> {
    let cfg = ReproduceConfig::quick();
    let (a, files) = compute(&cfg, &mut |_| {})?;
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
        assert_eq!(c.random.cv.len(), 5);
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
    let page = markdown(&a);
    assert!(page.contains("## Beyond the paper: the framework on three more processes"));
    let (b, files_b) = compute(&cfg, &mut |_| {})?;
    assert_eq!(files, files_b, "figures differ between two runs");
    assert_eq!(
        serde_json::to_string(&a)?,
        serde_json::to_string(&b)?,
        "results differ between two runs"
    );
    Ok(())
}
