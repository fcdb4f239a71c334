//! `hxai explain` end to end: a small simulated data folder, a short fit, and the pictures
//! of its correction; old model files without the Pareto front; bad input.

use std::path::{Path, PathBuf};
use std::process::Output;

use crate::common;
use common::{hxai, hxai_ok, s, text};

type TestResult = Result<(), Box<dyn std::error::Error>>;

/// A fitted model and the samples it was fitted on, in a fresh folder `name`.
fn fitted(name: &str) -> Result<(common::Scratch, PathBuf, PathBuf), Box<dyn std::error::Error>> {
    let dir = common::scratch("hxai-cli-explain", name)?;
    let data = dir.join("data");
    let (model, samples) = (dir.join("model.json"), dir.join("samples.csv"));
    let grid = [
        "--fs-hz",
        "2000",
        "--amplitudes",
        "4,8,11",
        "--frequencies",
        "10,20,30,40",
        "--seed",
        "1",
    ];
    common::simulate_small(&data, "1.5", &grid, "simulate failed")?;
    hxai_ok(
        &[
            "fit",
            "--data",
            s(&data),
            "--out",
            s(&model),
            "--epochs",
            "2",
            "--seed",
            "5",
            "--samples",
            s(&samples),
        ],
        "fit failed",
    )?;
    Ok((dir, model, samples))
}

/// Runs `hxai explain` on `model` (with `data` if given) into `out`.
fn explain(model: &Path, data: Option<&Path>, out: &Path) -> Result<Output, std::io::Error> {
    let mut args = vec!["explain", "--model", s(model), "--out", s(out)];
    if let Some(d) = data {
        args.extend(["--data", s(d)]);
    }
    hxai(&args)
}

/// [`explain`], requiring success; `what` names the step in the failure message.
fn explain_ok(
    model: &Path,
    data: Option<&Path>,
    out: &Path,
    what: &str,
) -> Result<Output, std::io::Error> {
    let o = explain(model, data, out)?;
    common::ok(&o, what);
    Ok(o)
}

fn svg(path: &Path) -> Result<String, Box<dyn std::error::Error>> {
    let t = std::fs::read_to_string(path)?;
    assert!(
        t.starts_with("<svg") && t.trim_end().ends_with("</svg>"),
        "{} is not an SVG document",
        path.display()
    );
    Ok(t)
}

/// The text of every `<text>` element of an SVG, trimmed.
fn labels(svg: &str) -> Vec<String> {
    svg.split("<text")
        .skip(1)
        .filter_map(|t| {
            Some(
                t.split_once('>')?
                    .1
                    .split_once("</text>")?
                    .0
                    .trim()
                    .to_owned(),
            )
        })
        .collect()
}

fn model_json(path: &Path) -> Result<serde_json::Value, Box<dyn std::error::Error>> {
    Ok(serde_json::from_str(&std::fs::read_to_string(path)?)?)
}

#[test]
fn explain_draws_the_response_the_parity_and_the_front() -> TestResult {
    let (dir, model, samples) = fitted("ok")?;
    let m = model_json(&model)?;
    let features = m["correction"]["features"]
        .as_array()
        .map(Vec::len)
        .unwrap_or(0);
    assert!(features >= 1, "the fit found no feature: {m}");
    let front = m["correction"]["pareto"]
        .as_array()
        .cloned()
        .unwrap_or_default();
    assert!(!front.is_empty(), "the model file stores no Pareto front");
    for member in &front {
        assert!(member["complexity"].is_u64() && member["loss"].is_f64());
        assert!(member["equation"].is_string());
    }
    let pics = dir.join("pictures").join("new");
    let out = explain_ok(&model, Some(&samples), &pics, "explain failed")?;
    let said = text(&out);
    // the band is drawn by the model file's default method, named in the legend
    let method = said
        .lines()
        .find_map(|l| l.strip_prefix("prediction intervals: 95 %, "))
        .ok_or(format!("no interval method said: {said}"))?;
    assert!(["conformal", "delta"].contains(&method), "{method}");
    // the equation comes with how it was selected, as the model file stores it
    let how = m["correction"]["selection"]["method"]
        .as_str()
        .ok_or(format!("no selection stored: {m}"))?;
    assert!(
        said.contains(&format!("selected by {how}: structure ")),
        "{said}"
    );
    let band = format!("95 % prediction interval ({method})");
    for f in ["response.svg", "predicted_vs_true.svg", "pareto.svg"] {
        assert!(
            said.contains(&format!("wrote {}", s(&pics.join(f)))),
            "{said}"
        );
    }
    // one panel per feature the equation uses, each with its band, curve and points
    let r = svg(&pics.join("response.svg"))?;
    assert_eq!(r.matches("response to ").count(), features);
    let legend = labels(&r);
    for series in [
        band.as_str(),
        "correction, others at their median",
        "train",
        "test",
    ] {
        let n = legend.iter().filter(|l| *l == series).count();
        assert_eq!(n, features, "{series}: {n} legend entries");
    }
    assert_eq!(r.matches("<polygon").count(), features);
    for f in m["correction"]["features"].as_array().into_iter().flatten() {
        let name = f.as_str().unwrap_or_default();
        assert!(r.contains(&format!("response to {name} ")), "{name}");
    }
    let p = labels(&svg(&pics.join("predicted_vs_true.svg"))?);
    let band_test = format!("{band} (test)");
    for series in ["train", "test", band_test.as_str(), "y = x"] {
        assert!(p.iter().any(|l| l == series), "series {series} missing");
    }
    let f = labels(&svg(&pics.join("pareto.svg"))?);
    let selected = format!("selected (complexity {})", m["correction"]["complexity"]);
    for series in ["Pareto front", "members", selected.as_str()] {
        assert!(f.iter().any(|l| l == series), "series {series} missing");
    }
    // nothing but the three pictures (no temporary file left behind)
    let mut names: Vec<String> = std::fs::read_dir(&pics)?
        .map(|e| e.map(|e| e.file_name().to_string_lossy().into_owned()))
        .collect::<Result<_, _>>()?;
    names.sort();
    assert_eq!(
        names,
        ["pareto.svg", "predicted_vs_true.svg", "response.svg"]
    );
    // the same input gives the same bytes
    let again = dir.join("again");
    explain_ok(&model, Some(&samples), &again, "explain failed")?;
    assert_eq!(std::fs::read_to_string(again.join("response.svg"))?, r);
    Ok(())
}

#[test]
fn without_data_or_front_the_missing_pictures_are_named() -> TestResult {
    let (dir, model, samples) = fitted("partial")?;
    let only_front = dir.join("front");
    let out = explain_ok(&model, None, &only_front, "explain without data failed")?;
    assert!(text(&out).contains("not drawn: response.svg needs the rows"));
    assert!(only_front.join("pareto.svg").is_file());
    assert!(!only_front.join("response.svg").exists());

    // a model file written before the front was stored still loads
    let mut m = model_json(&model)?;
    if let Some(c) = m["correction"].as_object_mut() {
        assert!(c.remove("pareto").is_some());
    }
    let old = dir.join("old.json");
    std::fs::write(&old, serde_json::to_string_pretty(&m)?)?;
    let out_old = dir.join("old");
    let out = explain_ok(
        &old,
        Some(&samples),
        &out_old,
        "explain of an old model failed",
    )?;
    assert!(
        text(&out).contains("not drawn: pareto.svg the model file stores no Pareto front"),
        "{}",
        text(&out)
    );
    assert!(out_old.join("response.svg").is_file());
    assert!(!out_old.join("pareto.svg").exists());
    // with neither, there is nothing to draw: an error, and no folder made
    let none = dir.join("none");
    let out = explain(&old, None, &none)?;
    assert!(!out.status.success());
    assert!(text(&out).contains("nothing to draw"), "{}", text(&out));
    assert!(!none.exists());
    Ok(())
}

#[test]
fn bad_input_fails_with_a_message_and_writes_nothing() -> TestResult {
    let (dir, model, samples) = fitted("bad")?;
    let before = std::fs::read(&model)?;
    let pics = dir.join("pics");
    let fails = |args: &[&str], expect: &str| -> TestResult {
        let out = hxai(args)?;
        assert!(!out.status.success(), "{args:?} succeeded");
        let t = text(&out);
        assert!(t.contains(expect), "{args:?}: {t}");
        assert!(!t.contains("panicked"), "{t}");
        assert_eq!(t.lines().count(), 1, "{t}");
        Ok(())
    };
    let missing = dir.join("missing.json");
    fails(
        &["explain", "--model", s(&missing), "--out", s(&pics)],
        "cannot read the model",
    )?;
    let garbage = dir.join("garbage.json");
    std::fs::write(&garbage, "{ not json")?;
    fails(
        &["explain", "--model", s(&garbage), "--out", s(&pics)],
        "cannot load the model",
    )?;
    // --out at the model file itself
    fails(
        &["explain", "--model", s(&model), "--out", s(&model)],
        "--out must be a folder",
    )?;
    // --out at the model's folder, where the model bears a picture's name
    let clash = dir.join("pareto.svg");
    std::fs::write(&clash, &before)?;
    fails(
        &[
            "explain",
            "--model",
            s(&clash),
            "--data",
            s(&samples),
            "--out",
            s(&dir),
        ],
        "the model (--model)",
    )?;
    assert_eq!(std::fs::read(&clash)?, before);
    assert!(!dir.join("response.svg").exists());
    // samples without `delta`, and a level outside (0, 1)
    let no_delta = dir.join("no_delta.csv");
    std::fs::write(&no_delta, "f1,f2\n1,2\n")?;
    fails(
        &[
            "explain",
            "--model",
            s(&model),
            "--data",
            s(&no_delta),
            "--out",
            s(&pics),
        ],
        "no numeric column `delta`",
    )?;
    fails(
        &[
            "explain",
            "--model",
            s(&model),
            "--out",
            s(&pics),
            "--interval",
            "1.5",
        ],
        "--interval must lie strictly between 0 and 1",
    )?;
    assert!(!pics.exists());
    assert_eq!(std::fs::read(&model)?, before);
    Ok(())
}

#[test]
fn explain_draws_a_table_hybrid_too() -> TestResult {
    let dir = common::scratch("hxai-cli-explain", "process")?;
    let (table, model) = (dir.join("ra.csv"), dir.join("ra.json"));
    hxai_ok(
        &[
            "simulate",
            "--case",
            "roughness",
            "--rows",
            "120",
            "--seed",
            "3",
            "--out",
            s(&table),
        ],
        "simulate failed",
    )?;
    hxai_ok(
        &[
            "hybrid",
            "fit",
            "--data",
            s(&table),
            "--target",
            "Ra_um",
            "--physics",
            "1000*feed_mm^2/(32*nose_radius_mm) + Ra0",
            "--calibrate",
            "Ra0",
            "--init",
            "Ra0=0",
            "--correction",
            "multiplicative",
            "--exclude",
            "tool",
            "--epochs",
            "2",
            "--out",
            s(&model),
        ],
        "hybrid fit failed",
    )?;
    let m = model_json(&model)?;
    let features = m["correction"]["features"]
        .as_array()
        .map(Vec::len)
        .unwrap_or(0);
    assert!(
        m["correction"]["pareto"]
            .as_array()
            .is_some_and(|f| !f.is_empty())
    );
    let pics = dir.join("pics");
    explain_ok(
        &model,
        Some(&table),
        &pics,
        "explain of a table hybrid failed",
    )?;
    let r = labels(&svg(&pics.join("response.svg"))?);
    assert_eq!(
        r.iter().filter(|l| l.starts_with("response to ")).count(),
        features
    );
    let p = labels(&svg(&pics.join("predicted_vs_true.svg"))?);
    assert!(
        p.iter()
            .any(|l| l == "true δ (multiplicative correction of Ra_um)"),
        "{p:?}"
    );
    svg(&pics.join("pareto.svg"))?;
    // the band of the model file's default method (conformal), or the one asked for
    assert!(
        r.iter()
            .any(|l| l == "95 % prediction interval (conformal)"),
        "{r:?}"
    );
    let delta_pics = dir.join("pics-delta");
    let out = hxai(&[
        "explain",
        "--model",
        s(&model),
        "--data",
        s(&table),
        "--out",
        s(&delta_pics),
        "--interval-method",
        "delta",
    ])?;
    assert!(out.status.success(), "{}", text(&out));
    assert!(text(&out).contains("prediction intervals: 95 %, delta"));
    let r = labels(&svg(&delta_pics.join("response.svg"))?);
    assert!(
        r.iter().any(|l| l == "95 % prediction interval (delta)"),
        "{r:?}"
    );
    // a table with fewer rows than the model's split is not the fitting table
    let text_of = std::fs::read_to_string(&table)?;
    let short = dir.join("short.csv");
    std::fs::write(
        &short,
        text_of.lines().take(20).collect::<Vec<_>>().join("\n"),
    )?;
    let out = explain(&model, Some(&short), &dir.join("short"))?;
    assert!(!out.status.success());
    assert!(
        text(&out).contains("pass the table the model was fitted on"),
        "{}",
        text(&out)
    );
    Ok(())
}

/// `hxai report` of the recordings' tool model (issue 50): drawn on its data folder, one
/// self-contained page with the hybrid as MathML in `#hybrid-equation`, the sections in
/// the table report's order, the figures inline with accessible names, the evaluation on
/// the test records, the `hxai fit` command that refits it; bad input (a table as the
/// folder, records without the probe, the model as the output, a file that is no model)
/// is one line on stderr with nothing written.
#[test]
fn report_of_the_tool_model_is_one_self_contained_page() -> TestResult {
    let (dir, model, samples) = fitted("report")?;
    let data = dir.join("data");
    let page = dir.join("tool.html");
    let before = std::fs::read(&model)?;
    let o = hxai(&[
        "report",
        "--model",
        s(&model),
        "--data",
        s(&data),
        "--out",
        s(&page),
    ])?;
    common::ok(&o, "report of the tool model");
    assert_eq!(std::fs::read(&model)?, before, "the model is never written");
    let html = std::fs::read_to_string(&page)?;
    assert_eq!(
        common::assert_self_contained_page(&html),
        3,
        "response, parity and front"
    );
    let m = model_json(&model)?;
    // the correction's equation and the test records' evaluation, as the model and
    // `hxai evaluate` give them
    let equation = m["correction"]["equation"].as_str().ok_or("no equation")?;
    assert!(html.contains(&format!("x_hat(t) = (A_phys + ({equation}))")));
    let ev = hxai_ok(
        &[
            "evaluate",
            "--model",
            s(&model),
            "--data",
            s(&data),
            "--json",
        ],
        "evaluate",
    )?;
    let ev: serde_json::Value = serde_json::from_slice(&ev.stdout)?;
    let n = ev["n_windows"].as_u64().ok_or("no n_windows")?;
    assert!(
        html.contains(&format!(
            "the test records: {} records, {n} windows",
            ev["n_records"]
        )),
        "the evaluation's counts"
    );
    assert!(html.contains("Paired t-test"));
    assert!(html.contains("Training ranges of the correction"));
    assert!(html.contains("hxai fit --data"));
    assert!(html.contains(" --seed 5 "));
    common::assert_no_temporary_files(&dir);

    // without the data: the model's own numbers, no figure
    let bare = dir.join("bare.html");
    hxai_ok(
        &["report", "--model", s(&model), "--out", s(&bare)],
        "report without data",
    )?;
    let bare_html = std::fs::read_to_string(&bare)?;
    assert!(!bare_html.contains("<svg"));
    assert!(bare_html.contains("give the data folder"));

    // bad input: one line, nothing written
    let refused = dir.join("refused.html");
    let evaluation = dir.join("evaluation.json");
    std::fs::write(&evaluation, serde_json::to_string(&ev)?)?;
    let cases: Vec<(Vec<&str>, &str)> = vec![
        (
            vec!["--model", s(&model), "--data", s(&samples)],
            "is not a folder",
        ),
        (
            vec!["--model", s(&samples), "--data", s(&data)],
            "cannot load the model",
        ),
        (
            vec!["--model", s(&evaluation), "--data", s(&data)],
            "no model file, neither of `hxai hybrid fit`",
        ),
    ];
    for (args, said) in cases {
        let mut all = vec!["report"];
        all.extend(args);
        all.extend(["--out", s(&refused)]);
        let o = hxai(&all)?;
        assert_eq!(o.status.code(), Some(1), "{all:?}");
        let err = common::stderr(&o);
        assert!(err.contains(said), "{all:?}: {err}");
        assert_eq!(err.trim_end().lines().count(), 1, "{err}");
        assert!(!refused.exists());
    }
    let o = hxai(&["report", "--model", s(&model), "--out", s(&model)])?;
    assert_eq!(o.status.code(), Some(1));
    assert_eq!(std::fs::read(&model)?, before);
    // records without their probe truth
    let bare_data = dir.join("no-probe");
    let grid = ["--format", "csv", "--fs-hz", "2000", "--amplitudes", "4"];
    common::simulate_small(&bare_data, "1.5", &grid, "simulate failed")?;
    for entry in std::fs::read_dir(&bare_data)? {
        let path = entry?.path();
        if path.file_name().is_some_and(|n| n != "manifest.csv") {
            let text = std::fs::read_to_string(&path)?;
            std::fs::write(&path, drop_column(&text, "probe_um"))?;
        }
    }
    let o = hxai(&[
        "report",
        "--model",
        s(&model),
        "--data",
        s(&bare_data),
        "--out",
        s(&refused),
    ])?;
    assert_eq!(o.status.code(), Some(1));
    assert!(
        common::stderr(&o).contains("probe_um"),
        "{}",
        common::stderr(&o)
    );
    assert!(!refused.exists());
    Ok(())
}

/// CSV `text` without the column `name`.
fn drop_column(text: &str, name: &str) -> String {
    let mut lines = text.lines();
    let head: Vec<&str> = lines.next().unwrap_or("").split(',').collect();
    let skip = head.iter().position(|h| *h == name);
    let keep = |line: &str| -> String {
        line.split(',')
            .enumerate()
            .filter(|(i, _)| Some(*i) != skip)
            .map(|(_, c)| c)
            .collect::<Vec<_>>()
            .join(",")
    };
    let mut out = keep(&head.join(","));
    for l in lines {
        out.push('\n');
        out.push_str(&keep(l));
    }
    out.push('\n');
    out
}
