//! Per-class constants: physics parameters per level (`--calibrate-per`) and the
//! correction's constants per level (`--correction-per`).

use super::*;

/// `--calibrate-per insul=a,b` on `MASS::whiteside` (one line per insulation state): the
/// model file holds `a[After]`, `a[Before]`, ... with standard errors and `per_class`, the
/// slopes are those of R's `lm(Gas ~ Insul/Temp)` within the scatter of a 45-row training
/// split (the exact comparison, on every row, is hxai-hybrid's `per_class` test), `predict`
/// reproduces the fit, and a level the fit never saw is refused by name with nothing
/// written.
#[test]
fn per_class_constants_give_one_line_per_level() -> TestResult {
    let dir = common::scratch("hxai-cli-hybrid-table", "per-class")?;
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("../..");
    let data = root.join("testdata/real/whiteside.csv");
    let model = dir.join("m.json");
    let args = [
        "hybrid",
        "fit",
        "--data",
        s(&data),
        "--target",
        "gas",
        "--physics",
        "a + b*temp",
        "--calibrate-per",
        "insul=a,b",
        "--epochs",
        "1",
        "--out",
        s(&model),
    ];
    let out = hxai(&args)?;
    ok(&out, "fit --calibrate-per");
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(
        !err.contains("insul` holds text"),
        "no left-out warning: {err}"
    );
    let m: serde_json::Value = serde_json::from_str(&std::fs::read_to_string(&model)?)?;
    let p = &m["physics"]["parameters"];
    let se = &m["physics"]["standard_errors"];
    for k in ["a[After]", "a[Before]", "b[After]", "b[Before]"] {
        assert!(p[k].is_f64(), "{k}: {p}");
        assert!(se[k].is_f64(), "{k}: {se}");
    }
    assert_eq!(m["per_class"]["column"], "insul");
    // the black boxes on the same split, in the model file's scores (issue 48)
    let bb = &m["scores"]["black_boxes"];
    let ratio = bb["hybrid_over_best_black_box"].as_f64().ok_or("ratio")?;
    let best = bb["best_black_box"]["rmse"].as_f64().ok_or("best")?;
    let hybrid = m["scores"]["test"]["hybrid"]["rmse"]
        .as_f64()
        .ok_or("hybrid")?;
    assert!((ratio - hybrid / best).abs() <= 1e-12 * ratio, "{bb}");
    assert!(
        best <= bb["physics_forest"].as_f64().ok_or("forest")?
            && best <= bb["boosting"].as_f64().ok_or("boosting")?,
        "{bb}"
    );
    assert!(String::from_utf8_lossy(&out.stdout).contains("times the best black box's test RMSE"));
    assert_eq!(
        m["per_class"]["levels"],
        serde_json::json!(["After", "Before"])
    );
    // R: slopes -0.2779 (after) and -0.3932 (before), standard errors 0.023
    let b_after = p["b[After]"].as_f64().ok_or("b")?;
    let b_before = p["b[Before]"].as_f64().ok_or("b")?;
    assert!((b_after + 0.2779).abs() < 0.07, "{b_after}");
    assert!((b_before + 0.3932).abs() < 0.07, "{b_before}");
    // predict on the fitting table
    let pred = dir.join("p.csv");
    ok(
        &hxai(&[
            "hybrid",
            "predict",
            "--model",
            s(&model),
            "--data",
            s(&data),
            "--out",
            s(&pred),
        ])?,
        "predict",
    );
    // an unseen level: refused by name, nothing written
    let other = dir.join("other.csv");
    std::fs::write(&other, "insul,temp,gas\nBefore,1.0,6.0\nLater,2.0,5.0\n")?;
    let none = dir.join("none.csv");
    let out = hxai(&[
        "hybrid",
        "predict",
        "--model",
        s(&model),
        "--data",
        s(&other),
        "--out",
        s(&none),
    ])?;
    assert!(!out.status.success());
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(err.contains("\"Later\"") && err.contains("row 2"), "{err}");
    assert!(!none.exists());
    // design over the text levels (issue 49): ranges with `insul=After|Before`, and a CSV
    // of settings with the text column; every run inside the space, each `predicted` what
    // `hybrid predict` gives at its settings (so the level indicators are the model's)
    let next = dir.join("next.csv");
    let mut a = design_args(&model, "temp=-1:10,insul=After|Before", "6", &next);
    a.extend(["--goal", "coverage"]);
    ok(&hxai(&a)?, "design over levels");
    let text = std::fs::read_to_string(&next)?;
    assert!(
        text.starts_with("temp,insul,predicted,spread,reason\n"),
        "{text}"
    );
    let runs: Vec<Vec<String>> = text
        .lines()
        .skip(1)
        .map(|l| l.split(',').map(str::to_string).collect())
        .collect();
    assert_eq!(runs.len(), 6);
    let levels: std::collections::BTreeSet<&str> = runs.iter().map(|r| r[1].as_str()).collect();
    assert_eq!(
        levels.len(),
        2,
        "coverage spreads the runs over both levels: {text}"
    );
    for r in &runs {
        let t: f64 = r[0].parse()?;
        assert!((-1.0..=10.0).contains(&t), "{r:?}");
    }
    let predicted = dir.join("next-predicted.csv");
    ok(
        &hxai(&predict_args(&model, &next, &predicted))?,
        "predict the runs",
    );
    let pred = std::fs::read_to_string(&predicted)?;
    let header: Vec<&str> = pred.lines().next().ok_or("header")?.split(',').collect();
    let h = header
        .iter()
        .position(|c| *c == "hybrid")
        .ok_or("hybrid column")?;
    for (r, line) in runs.iter().zip(pred.lines().skip(1)) {
        let want: f64 = r[2].parse()?;
        let got: f64 = line.split(',').nth(h).ok_or("cell")?.parse()?;
        assert!(
            (want - got).abs() <= 1e-9 * want.abs().max(1.0),
            "{want} vs {got}"
        );
    }
    // a CSV of settings with the level column: only its rows
    let feasible = dir.join("feasible.csv");
    std::fs::write(&feasible, "insul,temp\nBefore,2\nAfter,2\nAfter,8\n")?;
    let next2 = dir.join("next2.csv");
    let mut a = design_args(&model, s(&feasible), "2", &next2);
    a.extend(["--goal", "coverage", "--json"]);
    let o = hxai(&a)?;
    ok(&o, "design from a CSV with levels");
    let doc: serde_json::Value = serde_json::from_slice(&o.stdout)?;
    for run in doc["runs"].as_array().ok_or("runs")? {
        let setting = (
            run["settings"]["insul"].as_str(),
            run["settings"]["temp"].as_f64(),
        );
        assert!(
            [
                (Some("Before"), Some(2.0)),
                (Some("After"), Some(2.0)),
                (Some("After"), Some(8.0))
            ]
            .contains(&setting),
            "{run}"
        );
    }
    // refused, naming the problem, nothing written: a level the fit never saw, and a
    // space without the level column
    for (space, needle) in [
        ("temp=0:5,insul=Before|Sideways", "\"Sideways\""),
        ("temp=0:5", "`insul`"),
    ] {
        let o = hxai(&design_args(&model, space, "2", &none))?;
        assert_eq!(o.status.code(), Some(1), "{space}");
        let err = common::stderr(&o);
        assert!(err.contains(needle), "{space}: {err}");
        assert!(!none.exists());
    }
    // a bad spec names the form to write
    let mut bad = args.to_vec();
    bad[9] = "insul";
    let out = hxai(&bad)?;
    assert!(!out.status.success());
    assert!(String::from_utf8_lossy(&out.stderr).contains("COLUMN=P1,P2"));
    Ok(())
}

/// `--correction-per batch` (issue 48): on `y = 2*x + c[batch]*z` with three batches in
/// words, the fit prints each batch's correction and stores `correction_per`; its test RMSE
/// is below the shared correction's; `predict` reads the text column, refuses a batch the
/// fit never saw (nothing written) and refuses `--interval` in words.
#[test]
fn correction_constants_per_batch() -> TestResult {
    let dir = common::scratch("hxai-cli-hybrid-table", "correction-per")?;
    let data = dir.join("batches.csv");
    let mut text = String::from("batch,x,z,y\n");
    for i in 0..240 {
        let b = i % 3;
        let x = 1.0 + 4.0 * ((i * 7) % 31) as f64 / 30.0;
        let z = 0.5 + 2.5 * ((i * 11) % 37) as f64 / 36.0;
        let y = 2.0 * x + [1.0, 2.5, 4.0][b] * z;
        text.push_str(&format!("{},{x},{z},{y}\n", ["alpha", "beta", "gamma"][b]));
    }
    std::fs::write(&data, &text)?;
    let fit = |out: &Path, per: bool| -> Result<std::process::Output, Box<dyn std::error::Error>> {
        let mut a = vec![
            "hybrid",
            "fit",
            "--data",
            s(&data),
            "--target",
            "y",
            "--physics",
            "k*x",
            "--calibrate",
            "k",
            "--epochs",
            "2",
            "--out",
            s(out),
        ];
        if per {
            a.extend(["--correction-per", "batch"]);
        }
        Ok(hxai(&a)?)
    };
    let (shared, per) = (dir.join("shared.json"), dir.join("per.json"));
    ok(&fit(&shared, false)?, "fit, shared correction");
    let o = fit(&per, true)?;
    ok(&o, "fit --correction-per batch");
    let stdout = String::from_utf8_lossy(&o.stdout);
    assert!(
        stdout.contains("correction constants per level of `batch`")
            && stdout.contains("batch=gamma"),
        "{stdout}"
    );
    let read = |p: &Path| -> Result<serde_json::Value, Box<dyn std::error::Error>> {
        Ok(serde_json::from_str(&std::fs::read_to_string(p)?)?)
    };
    let (js, jp) = (read(&shared)?, read(&per)?);
    assert_eq!(
        jp["correction_per"]["levels"],
        serde_json::json!(["alpha", "beta", "gamma"])
    );
    let rmse = |j: &serde_json::Value| j["scores"]["test"]["hybrid"]["rmse"].as_f64();
    let (a, b) = (
        rmse(&jp).ok_or("per rmse")?,
        rmse(&js).ok_or("shared rmse")?,
    );
    assert!(a < 0.5 * b, "per-batch test RMSE {a}, shared {b}");

    let pred = dir.join("p.csv");
    ok(
        &hxai(&predict_args(&per, &data, &pred))?,
        "predict with the batch column",
    );
    let other = dir.join("other.csv");
    std::fs::write(&other, "batch,x,z\nalpha,2,1\ndelta,2,1\n")?;
    let none = dir.join("none.csv");
    let o = hxai(&predict_args(&per, &other, &none))?;
    assert_eq!(o.status.code(), Some(1));
    let err = common::stderr(&o);
    assert!(err.contains("\"delta\"") && err.contains("row 2"), "{err}");
    assert!(!none.exists());
    let mut iv = predict_args(&per, &data, &none);
    iv.extend(["--interval", "0.9"]);
    let o = hxai(&iv)?;
    assert_eq!(o.status.code(), Some(1));
    assert!(
        common::stderr(&o).contains("--correction-per"),
        "{}",
        common::stderr(&o)
    );
    assert!(!none.exists());
    Ok(())
}
