//! What a fitted table hybrid gives besides predictions: interval methods, the report
//! page and the design of the next runs.

use super::*;

/// Issue 28: `--interval-method` on evaluate, predict and compare; the model file's
/// `conformal`; `interval` {`method`, `nominal`, `coverage`, `n`, `median_width`}.
#[test]
fn interval_methods_are_chosen_and_reported() -> TestResult {
    let (dir, data) = scratch_table("interval-methods", 160)?;
    let model = dir.join("model.json");
    let out = hxai(&fit_args(s(&data), s(&model)))?;
    ok(&out, "fit");
    let file: serde_json::Value = serde_json::from_str(&std::fs::read_to_string(&model)?)?;
    assert_eq!(file["conformal"]["folds"], 5);
    assert_eq!(file["conformal"]["scale"], "linear");
    assert_eq!(
        file["conformal"]["scores"].as_array().map(Vec::len),
        file["split"]["train"].as_array().map(Vec::len)
    );
    for (asked, method) in [
        (None, "conformal"),
        (Some("conformal"), "conformal"),
        (Some("split"), "split"),
        (Some("delta"), "delta"),
    ] {
        let mut extra = vec!["--json", "--interval", "0.9"];
        if let Some(m) = asked {
            extra.extend_from_slice(&["--interval-method", m]);
        }
        let mut args = vec!["hybrid"];
        args.extend(evaluate_args(s(&model), s(&data), &extra));
        let out = hxai(&args)?;
        ok(&out, method);
        let ev: serde_json::Value = serde_json::from_slice(&out.stdout)?;
        let iv = &ev["interval"];
        assert_eq!(iv["method"], method, "{ev}");
        assert_eq!(iv["nominal"], 0.9, "{ev}");
        assert_eq!(iv["n"], 160, "{ev}");
        assert!(iv["coverage"].as_f64().is_some(), "{ev}");
        assert!(iv["median_width"].as_f64().ok_or("width")? >= 0.0, "{ev}");
    }
    // predict with a method: finite bands, lower end first (split conformal's band is
    // centred on the first fold's refit, so on a noise-free table it need not hold the
    // full fit's prediction)
    let pred = dir.join("pred.csv");
    let mut args = predict_args(&model, &data, &pred);
    args.extend_from_slice(&["--interval", "0.9", "--interval-method", "split"]);
    ok(&hxai(&args)?, "predict --interval-method split");
    let written = std::fs::read_to_string(&pred)?;
    let mut lines = written.lines();
    assert_eq!(
        lines.next(),
        Some("physics,correction,hybrid,hybrid_lo,hybrid_hi,outside_training")
    );
    for line in lines {
        let v: Vec<f64> = line.split(',').filter_map(|x| x.parse().ok()).collect();
        assert!(
            v.len() == 6 && v[3] <= v[4] && v[3] <= v[2] && v[2] <= v[4],
            "{line}"
        );
    }
    // a level outside (0, 1): one line naming the flag
    let mut args = vec!["hybrid"];
    args.extend(evaluate_args(
        s(&model),
        s(&data),
        &["--interval", "1.5", "--interval-method", "conformal"],
    ));
    let out = hxai(&args)?;
    assert!(!out.status.success());
    assert!(
        common::stderr(&out).contains("--interval"),
        "{}",
        common::stderr(&out)
    );
    // without conformal folds: delta by default, conformal refused with what to do
    let plain = dir.join("plain.json");
    let mut args = fit_args(s(&data), s(&plain));
    args.extend_from_slice(&["--conformal-folds", "0"]);
    ok(&hxai(&args)?, "fit --conformal-folds 0");
    let mut args = vec!["hybrid"];
    args.extend(evaluate_args(s(&plain), s(&data), &["--json"]));
    let out = hxai(&args)?;
    ok(&out, "evaluate, no conformal");
    let ev: serde_json::Value = serde_json::from_slice(&out.stdout)?;
    assert_eq!(ev["interval"]["method"], "delta", "{ev}");
    let mut args = vec!["hybrid"];
    args.extend(evaluate_args(
        s(&plain),
        s(&data),
        &["--interval-method", "conformal"],
    ));
    let out = hxai(&args)?;
    assert!(!out.status.success());
    assert!(
        common::stderr(&out).contains("--interval-method delta"),
        "{}",
        common::stderr(&out)
    );
    // more folds than training rows
    let (_dir, small) = scratch_table("interval-small", 12)?;
    let mut args = fit_args(s(&small), s(&plain));
    args.extend_from_slice(&["--conformal-folds", "20"]);
    let out = hxai(&args)?;
    assert!(!out.status.success());
    assert!(
        common::stderr(&out).contains("--conformal-folds"),
        "{}",
        common::stderr(&out)
    );
    Ok(())
}

/// `hxai report` (issue 50): one self-contained HTML page with the hybrid as MathML in
/// `#hybrid-equation`, every figure an inline `<svg>` with an accessible name, the sections
/// in the order a reader asks (model, scores, how sure, where it holds, how to reproduce),
/// the comparison's table when given; no address of any resource, no script; the inputs
/// are never written over; a model of `hxai fit`'s kind is refused in words.
#[test]
fn report_is_one_self_contained_page() -> TestResult {
    let (dir, csv) = scratch_table("report", 120)?;
    let model = dir.join("m.json");
    let mut fit = fit_args(s(&csv), s(&model));
    fit.extend(["--exclude", "batch"]);
    ok(&hxai(&fit)?, "fit");
    let mut cmp = hybrid_args("compare", s(&csv), LAW);
    cmp.extend([
        "--calibrate",
        "k",
        "--exclude",
        "batch",
        "--folds",
        "3",
        "--json",
    ]);
    cmp.extend_from_slice(&QUICK);
    let o = hxai(&cmp)?;
    ok(&o, "compare");
    let compare = dir.join("compare.json");
    std::fs::write(&compare, &o.stdout)?;
    let before = std::fs::read(&model)?;

    let page = dir.join("report.html");
    let o = hxai(&[
        "report",
        "--model",
        s(&model),
        "--data",
        s(&csv),
        "--compare",
        s(&compare),
        "--out",
        s(&page),
    ])?;
    ok(&o, "report");
    assert_eq!(std::fs::read(&model)?, before, "the model is never written");
    let html = std::fs::read_to_string(&page)?;
    let svgs = common::assert_self_contained_page(&html);
    assert!(svgs >= 2, "{svgs} figures");
    assert!(html.contains("times the best black box"));
    assert!(html.contains("<th scope=\"col\">test RMSE</th>"));
    assert!(html.contains("hxai hybrid fit --data"));

    // an input as the output is refused; nothing written over it
    let o = hxai(&["report", "--model", s(&model), "--out", s(&model)])?;
    assert_eq!(o.status.code(), Some(1));
    assert_eq!(std::fs::read(&model)?, before);
    // a comparison file that is not one
    let o = hxai(&[
        "report",
        "--model",
        s(&model),
        "--compare",
        s(&model),
        "--out",
        s(&dir.join("x.html")),
    ])?;
    assert_eq!(o.status.code(), Some(1));
    assert!(
        common::stderr(&o).contains("hxai hybrid compare --json"),
        "{}",
        common::stderr(&o)
    );
    Ok(())
}

/// `hxai hybrid design` (issue 49, first part): N runs inside the space (ranges, or a CSV of
/// feasible settings whose rows are the only candidates), written with `predicted`,
/// `spread` and `reason`; `--json` lists the runs and each equation's predictions; a space
/// without a column the model reads, a bad range and `--n 0` are refused with nothing
/// written.
#[test]
fn design_proposes_runs_inside_the_space() -> TestResult {
    let (dir, csv) = scratch_table("design", 80)?;
    let model = dir.join("m.json");
    let mut fit = fit_args(s(&csv), s(&model));
    fit.extend(["--exclude", "batch,d"]);
    ok(&hxai(&fit)?, "fit");
    let next = dir.join("next.csv");
    let mut a = design_args(&model, "f=0.05:0.4,r=0.4:1.6:0.4,v=50:400", "4", &next);
    a.extend(["--goal", "coverage", "--json"]);
    let o = hxai(&a)?;
    ok(&o, "design");
    let doc: serde_json::Value = serde_json::from_slice(&o.stdout)?;
    assert_eq!(doc["goal"], "coverage");
    assert_eq!(doc["runs"].as_array().map(Vec::len), Some(4));
    let text = std::fs::read_to_string(&next)?;
    let mut lines = text.lines();
    assert_eq!(lines.next(), Some("f,r,v,predicted,spread,reason"));
    for l in lines.by_ref().take(4) {
        let c: Vec<f64> = l
            .split(',')
            .take(3)
            .map(|x| x.parse().unwrap_or(f64::NAN))
            .collect();
        assert!((0.05..=0.4).contains(&c[0]), "{l}");
        assert!(
            [0.4, 0.8, 1.2, 1.6].iter().any(|r| (r - c[1]).abs() < 1e-9),
            "{l}"
        );
        assert!((50.0..=400.0).contains(&c[2]), "{l}");
    }
    // a CSV of feasible settings: only its rows
    let feasible = dir.join("feasible.csv");
    std::fs::write(&feasible, "f,r,v\n0.1,0.8,100\n0.2,0.8,200\n0.3,1.2,300\n")?;
    let next2 = dir.join("next2.csv");
    let mut a = design_args(&model, s(&feasible), "2", &next2);
    a.push("--json");
    let o = hxai(&a)?;
    ok(&o, "design from a CSV");
    // the default goal, discriminate, needs alternatives; without them it is precision
    // (the model has a covariance), with a note
    let m: serde_json::Value = serde_json::from_str(&std::fs::read_to_string(&model)?)?;
    let alternatives = m["correction"]["selection"]["alternatives"]
        .as_array()
        .map_or(0, Vec::len);
    let used: serde_json::Value = serde_json::from_slice(&o.stdout)?;
    if alternatives == 0 {
        assert_eq!(used["goal"], "precision", "{used}");
        assert!(
            common::stderr(&o).contains("chosen for precision"),
            "{}",
            common::stderr(&o)
        );
    } else {
        assert_eq!(used["goal"], "discriminate", "{used}");
    }
    let rows: Vec<String> = std::fs::read_to_string(&next2)?
        .lines()
        .skip(1)
        .map(|l| l.split(',').take(3).collect::<Vec<_>>().join(","))
        .collect();
    let allowed = ["0.1,0.8,100.0", "0.2,0.8,200.0", "0.3,1.2,300.0"];
    assert!(
        rows.iter().all(|r| allowed.contains(&r.as_str())),
        "{rows:?}"
    );
    // refused, nothing written
    let none = dir.join("none.csv");
    for (space, n) in [
        ("f=0.05:0.4,r=0.4:1.6", "2"),
        ("f=0.4:0.05,r=1:2,v=1:2", "2"),
        ("f=0.05:0.4,r=0.4:1.6,v=50:400", "0"),
    ] {
        let o = hxai(&design_args(&model, space, n, &none))?;
        assert_eq!(o.status.code(), Some(1), "{space} {n}");
        assert!(!none.exists());
    }
    Ok(())
}
