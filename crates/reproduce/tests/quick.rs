//! The `--quick` reproduction end to end, so the glue between the crates cannot rot.
//!
//! Invariants checked: every promised output exists; every table has its rows; the numbers
//! are finite; the sample table has one row per sample with the contract's columns; two runs
//! give identical files (the committed results must be a pure function of code and seed).

use hxai_reproduce::{ReproduceConfig, run};

#[test]
fn quick_run_writes_every_output_and_is_repeatable() -> Result<(), Box<dyn std::error::Error>> {
    let cfg = ReproduceConfig::quick();
    let a = run(&cfg, &mut |_| {})?;
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

    let b = run(&cfg, &mut |_| {})?;
    assert_eq!(a.files, b.files, "two runs with the same seed differ");
    Ok(())
}
