//! `hxai sr` end to end: the JSON document of the interface contract on a table with a known
//! law, and clear errors (non-zero exit, a message naming the problem) for bad input.

use std::path::{Path, PathBuf};

use crate::common;
use common::hxai;

type TestResult = Result<(), Box<dyn std::error::Error>>;

/// A fresh scratch folder holding the table `name` with `text`: the folder and the table's
/// path.
fn table(name: &str, text: &str) -> Result<(common::Scratch, PathBuf), std::io::Error> {
    let dir = common::scratch("hxai-cli-sr", name)?;
    let path = dir.join(name);
    std::fs::write(&path, text)?;
    Ok((dir, path))
}

/// Runs `hxai sr --csv CSV --target y --json EXTRA...`, requires success, parses stdout.
fn sr_json(csv: &Path, extra: &[&str]) -> Result<serde_json::Value, Box<dyn std::error::Error>> {
    let mut args = vec![
        "sr",
        "--csv",
        csv.to_str().ok_or("path")?,
        "--target",
        "y",
        "--json",
    ];
    args.extend_from_slice(extra);
    let out = hxai(&args)?;
    assert!(
        out.status.success(),
        "{extra:?}: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    Ok(serde_json::from_slice(&out.stdout)?)
}

/// y = 2.5 x1 x2 on a 12 x 12 grid, plus an unused column.
fn law_csv() -> String {
    let mut s = String::from("x1,x2,unused,y\n");
    for i in 0..12 {
        for j in 0..12 {
            let (x1, x2) = (0.5 + 0.25 * i as f64, 1.0 + 0.2 * j as f64);
            let unused = ((i * 7 + j * 3) % 11) as f64;
            s.push_str(&format!("{x1},{x2},{unused},{}\n", 2.5 * x1 * x2));
        }
    }
    s
}

#[test]
fn json_document_follows_the_contract_and_finds_the_law() -> TestResult {
    let (_dir, csv) = table("law.csv", &law_csv())?;
    let doc = sr_json(&csv, &["--epochs", "3"])?;
    let keys = [
        "equation",
        "sympy",
        "latex",
        "complexity",
        "features",
        "r2",
        "rmse",
        "loss",
        "model",
    ];
    let best = &doc["best"];
    // the model text reads back as the model (one summary type, hxai_symreg::ModelSummary)
    let text = best["model"].as_str().ok_or("model")?;
    assert_eq!(
        hxai_symreg::Model::from_json(text)?.equation(),
        best["equation"].as_str().ok_or("equation")?
    );
    assert!(doc["selection"]["method"].is_string(), "{doc}");
    // an exact law: both error models sit at the loss floor, and the tie stays additive
    // (written only when multiplicative)
    assert!(doc["selection"].get("error_model").is_none(), "{doc}");
    for k in keys {
        assert!(!best[k].is_null(), "best.{k} missing in {best}");
    }
    assert!(doc["evaluations"].as_u64().ok_or("evaluations")? > 0);
    assert!(doc["seconds"].as_f64().ok_or("seconds")? >= 0.0);
    let front = doc["pareto"].as_array().ok_or("pareto")?;
    assert!(!front.is_empty());
    for m in front {
        for k in keys {
            assert!(!m[k].is_null(), "pareto entry lacks {k}: {m}");
        }
    }
    // the law: a product of the two used inputs, exactly (noise-free data)
    assert!(best["r2"].as_f64().ok_or("r2")? > 1.0 - 1e-9, "{best}");
    let mut feats: Vec<&str> = best["features"]
        .as_array()
        .ok_or("features")?
        .iter()
        .filter_map(|v| v.as_str())
        .collect();
    feats.sort_unstable();
    assert_eq!(feats, ["x1", "x2"]);
    assert_eq!(best["complexity"].as_u64(), Some(3), "{best}");
    // issue 15: every reported model has its constants as a template with named parameters
    for m in front.iter().chain([best]) {
        assert!(m["template"].is_string(), "template missing in {m}");
        let params = m["params"].as_object().ok_or("params")?;
        for (name, p) in params {
            assert!(name.starts_with('p'), "{name}");
            assert!(p["value"].is_number(), "{m}");
            assert!(
                p.get("std_error").is_some() && p.get("ci95").is_some(),
                "{m}"
            );
        }
    }
    Ok(())
}

#[test]
fn bad_input_gives_a_clear_error() -> TestResult {
    let (_dir, good) = table("good.csv", &law_csv())?;
    let good = good.to_str().ok_or("path")?;
    let cases: Vec<(Vec<String>, &str)> = vec![
        (vec!["--target".into(), "nope".into()], "nope"),
        (
            vec![
                "--target".into(),
                "unused".into(),
                "--error-model".into(),
                "multiplicative".into(),
            ],
            "needs a positive target, but row 0 is 0",
        ),
        (
            vec![
                "--target".into(),
                "y".into(),
                "--operators".into(),
                "add,frobnicate".into(),
            ],
            "frobnicate",
        ),
        (
            vec![
                "--target".into(),
                "y".into(),
                "--criterion".into(),
                "aicc".into(),
            ],
            "aicc",
        ),
        (
            vec![
                "--target".into(),
                "y".into(),
                "--complexity-penalty=-1".into(),
            ],
            "--complexity-penalty must be finite",
        ),
        (
            vec![
                "--target".into(),
                "y".into(),
                "--max-evaluations".into(),
                "0".into(),
            ],
            "--max-evaluations",
        ),
        (
            vec![
                "--target".into(),
                "y".into(),
                "--max-fit-rows".into(),
                "4".into(),
            ],
            "--max-fit-rows is 4",
        ),
        (
            vec![
                "--target".into(),
                "y".into(),
                "--lm-iterations".into(),
                "0".into(),
            ],
            "--lm-iterations is 0",
        ),
        (
            vec![
                "--target".into(),
                "y".into(),
                "--candidates-per-epoch".into(),
                "0".into(),
            ],
            "--candidates-per-epoch is 0",
        ),
        (
            vec![
                "--target".into(),
                "y".into(),
                "--random-start".into(),
                "sometimes".into(),
            ],
            "invalid value 'sometimes' for '--random-start",
        ),
        (
            vec![
                "--target".into(),
                "y".into(),
                "--random-start".into(),
                "sometimes".into(),
            ],
            "[possible values: always, on-failure]",
        ),
        (
            vec![
                "--target".into(),
                "y".into(),
                "--max-key-nodes".into(),
                "many".into(),
            ],
            "`many` is not a number of nodes (0 or more) or `all`",
        ),
    ];
    for (extra, needle) in cases {
        let mut args = vec!["sr".to_string(), "--csv".into(), good.into()];
        args.extend(extra);
        let refs: Vec<&str> = args.iter().map(|s| s.as_str()).collect();
        let out = hxai(&refs)?;
        let err = String::from_utf8_lossy(&out.stderr);
        assert!(!out.status.success(), "{args:?} should fail");
        assert!(
            err.contains(needle),
            "{args:?}: stderr does not name '{needle}': {err}"
        );
        assert!(!err.contains("panicked"), "{err}");
    }
    let constant: String = (0..12).map(|i| format!("{i},2\n")).collect();
    let short: String = (0..4).map(|i| format!("{i},{}\n", 2 * i)).collect();
    let files = [
        (
            table("constant.csv", &format!("x,y\n{constant}"))?,
            "constant",
        ),
        (
            table("nan.csv", "x,y\n1,2\n2,NaN\n3,4\n4,5\n5,6\n")?,
            "not finite",
        ),
        (table("short.csv", &format!("x,y\n{short}"))?, "too few"),
    ];
    for ((_dir, path), needle) in files {
        let out = hxai(&["sr", "--csv", path.to_str().ok_or("path")?, "--target", "y"])?;
        let err = String::from_utf8_lossy(&out.stderr);
        assert!(!out.status.success(), "{} should fail", path.display());
        assert!(
            err.contains(needle) && !err.contains("panicked"),
            "{}: {err}",
            path.display()
        );
    }
    Ok(())
}

// The search settings of the library are reachable from the command line: each strategy and
// criterion runs, and the evaluation budget is respected.
#[test]
fn strategy_criterion_and_budget_options() -> TestResult {
    let (_dir, csv) = table("law2.csv", &law_csv())?;
    for (strategy, criterion) in [
        ("qlattice", "aic"),
        ("genetic", "pareto"),
        ("combined", "bic"),
        ("combined", "mdl"),
    ] {
        let doc = sr_json(
            &csv,
            &[
                "--strategy",
                strategy,
                "--criterion",
                criterion,
                "--max-evaluations",
                "500",
            ],
        )?;
        let evals = doc["evaluations"].as_u64().ok_or("evaluations")?;
        assert!(
            evals > 0 && evals <= 500,
            "{strategy}/{criterion}: {evals} evaluations"
        );
        assert!(
            doc["best"]["r2"].as_f64().ok_or("r2")? > 0.9,
            "{strategy}/{criterion}: {doc}"
        );
    }
    // the search's fitting effort: rows, candidates per epoch, iterations per fit; and
    // which candidates get a structure key
    let small_search = |max_key_nodes: &str| {
        sr_json(
            &csv,
            &[
                "--max-fit-rows",
                "60",
                "--candidates-per-epoch",
                "200",
                "--lm-iterations",
                "10",
                "--epochs",
                "3",
                "--no-separability",
                "--random-start",
                "on-failure",
                "--max-key-nodes",
                max_key_nodes,
            ],
        )
    };
    let doc = small_search("0")?;
    assert_eq!(doc["duplicate_structures"], 0, "no candidate keyed");
    let evals = doc["evaluations"].as_u64().ok_or("evaluations")?;
    assert!(evals <= 3 * 200, "{evals} evaluations in 3 epochs of 200");
    assert!(doc["best"]["r2"].as_f64().ok_or("r2")? > 0.999, "{doc}");
    // `all` keys every candidate (the library's default), so duplicates are found again
    let all = small_search("all")?;
    let dups = all["duplicate_structures"].as_u64().ok_or("duplicates")?;
    assert!(dups > 0, "`all` keyed no candidate: {all}");
    Ok(())
}

// `--operator-complexity` sets what each operator counts; malformed entries, unknown
// operators and out-of-range values are refused with a message naming the entry.
#[test]
fn operator_complexity_option() -> TestResult {
    let (_dir, csv) = table("law_opc.csv", &law_csv())?;
    let doc = sr_json(
        &csv,
        &[
            "--operator-complexity",
            "mul=3,div=3",
            "--max-evaluations",
            "300",
        ],
    )?;
    assert!(doc["best"]["complexity"].as_u64().is_some(), "{doc}");
    let path = csv.to_str().ok_or("path")?;
    for (value, needle) in [
        ("sqrt", "not NAME=VALUE"),
        ("sqrt=two", "not a whole number"),
        ("cube=2", "unknown operator `cube`"),
        ("sqrt=0", "choose 1 to 20"),
        ("sqrt=2,sqrt=3", "twice"),
    ] {
        let out = hxai(&[
            "sr",
            "--csv",
            path,
            "--target",
            "y",
            "--operator-complexity",
            value,
        ])?;
        let err = String::from_utf8_lossy(&out.stderr);
        assert!(!out.status.success(), "{value} should fail");
        assert!(
            err.contains(needle) && !err.contains("panicked"),
            "{value}: {err}"
        );
    }
    Ok(())
}

/// `--units`: a period `T = 2 pi sqrt(L/g)` with a distractor mass. L, g and m have
/// independent dimensions and none is left over, so no search runs: the law comes back as
/// `c * sqrt(L/g)` with the mass out by construction, and the JSON names the (empty) list of
/// groups and the target's scale. A bad unit is refused naming its column.
#[test]
fn units_reduce_the_search_and_keep_the_law_consistent() -> TestResult {
    let mut s = String::from("L,g,m,y\n");
    for i in 0..40 {
        let (l, g, m) = (
            0.5 + 0.05 * f64::from(i),
            5.0 + f64::from((i * 7) % 11),
            1.0 + f64::from((i * 3) % 5),
        );
        s.push_str(&format!(
            "{l},{g},{m},{}\n",
            2.0 * std::f64::consts::PI * (l / g).sqrt()
        ));
    }
    let (_dir, csv) = table("period.csv", &s)?;
    let doc = sr_json(&csv, &["--units", "L=m,g=m/s^2,m=kg,y=s"])?;
    assert_eq!(
        doc["dimensional_groups"],
        serde_json::json!(["y = c * L^(1/2)/g^(1/2)"])
    );
    let best = &doc["best"];
    assert!(best["r2"].as_f64().ok_or("r2")? > 1.0 - 1e-12, "{best}");
    assert_eq!(best["features"], serde_json::json!(["L", "g"]));
    let out = hxai(&[
        "sr",
        "--csv",
        csv.to_str().ok_or("path")?,
        "--target",
        "y",
        "--units",
        "L=m,g=m/s^2,m=stone,y=s",
    ])?;
    assert!(!out.status.success());
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(err.contains("column `m`: unit `stone`"), "{err}");
    Ok(())
}

/// AI Feynman's tools are on by default: on `2.5 x1 x2` (a product of parts over one input
/// each) the parts are searched apart, which the JSON's evaluation count shows;
/// `--no-separability` leaves them out, and `--separability` (the flag of when they were
/// opt-in) still runs, as the default.
#[test]
fn separability_is_the_default_and_searches_the_parts() -> TestResult {
    let (_dir, csv) = table("separable.csv", &law_csv())?;
    let plain = sr_json(&csv, &["--epochs", "2", "--no-separability"])?;
    let split = sr_json(&csv, &["--epochs", "2"])?;
    let flagged = sr_json(&csv, &["--epochs", "2", "--separability"])?;
    let count = |d: &serde_json::Value| d["evaluations"].as_u64().ok_or("evaluations");
    assert!(count(&split)? > count(&plain)?, "{split}");
    assert_eq!(split["best"], flagged["best"]);
    assert!(split["best"]["r2"].as_f64().ok_or("r2")? > 1.0 - 1e-9);
    let both = hxai(&[
        "sr",
        "--csv",
        csv.to_str().ok_or("path")?,
        "--target",
        "y",
        "--separability",
        "--no-separability",
    ])?;
    assert!(!both.status.success());
    Ok(())
}

/// AI Feynman's tools on the relativistic mass `m0/sqrt(1 - v^2/c^2)`: the product splits
/// off `m0`, `v` and `c` enter only through `v/c` (a symmetry of the oracle), and on that one
/// input `1/sqrt(1 - z^2)` is a polynomial of `1/y^2`: the law comes back as it is written.
#[test]
fn separability_finds_the_symmetry_and_the_transformed_polynomial() -> TestResult {
    let mut s = String::from("m0,v,c,y\n");
    for i in 0..300 {
        let m0 = 1.0 + 4.0 * f64::from((i * 7) % 100) / 100.0;
        let v = 1.0 + f64::from((i * 13) % 100) / 100.0;
        let c = 3.0 + 7.0 * f64::from((i * 29) % 100) / 100.0;
        s.push_str(&format!(
            "{m0},{v},{c},{}\n",
            m0 / (1.0 - v * v / (c * c)).sqrt()
        ));
    }
    let (_dir, csv) = table("relativistic.csv", &s)?;
    let doc = sr_json(&csv, &["--epochs", "3"])?;
    let best = &doc["best"];
    assert_eq!(best["equation"], "m0/sqrt(-(v/c)**2 + 1)", "{doc}");
    assert!(best["r2"].as_f64().ok_or("r2")? > 1.0 - 1e-12, "{doc}");
    Ok(())
}

/// Simplification after the search: with units, Newton's gravitation is searched on the
/// one group `m2/m1` and composed back as `G*m1^2/r^2 * phi(m2/m1)`; the composition is
/// returned in its canonical form, where `m1` cancels, so the equation reads as the law.
/// Without units the search's own models are shortened (`simplified` counts them), and
/// `--no-simplify` reports the programs as written, with none counted.
#[test]
fn reported_models_come_back_in_their_shorter_form() -> TestResult {
    let mut s = String::from("G,m1,m2,r,y\n");
    for i in 0..120 {
        let f = f64::from(i);
        let (g, m1, m2, r) = (
            1.0 + 0.01 * f64::from((i * 7) % 100),
            1.0 + 0.04 * f64::from((i * 13) % 100),
            1.0 + 0.04 * f64::from((i * 29) % 100),
            1.0 + 0.04 * (f % 100.0),
        );
        s.push_str(&format!("{g},{m1},{m2},{r},{}\n", g * m1 * m2 / (r * r)));
    }
    let (_dir, csv) = table("gravitation.csv", &s)?;
    let doc = sr_json(
        &csv,
        &[
            "--units",
            "G=m^3/(kg*s^2),m1=kg,m2=kg,r=m,y=N",
            "--epochs",
            "3",
        ],
    )?;
    assert_eq!(doc["best"]["sympy"], "G*m1*m2/r**2", "{}", doc["best"]);
    // the same units as a row under the header
    let mut lines = s.lines();
    let header = lines.next().ok_or("header")?;
    let rest: Vec<&str> = lines.collect();
    let (_row_dir, with_row) = table(
        "gravitation_units.csv",
        &format!("{header}\nm^3/(kg*s^2),kg,kg,m,N\n{}\n", rest.join("\n")),
    )?;
    let from_row = sr_json(&with_row, &["--units", "row", "--epochs", "3"])?;
    assert_eq!(from_row["best"]["sympy"], doc["best"]["sympy"]);
    assert_eq!(from_row["dimensional_groups"], doc["dimensional_groups"]);
    // consensus with units: the votes are on the composed structures, so the structure the
    // report names is over the columns (it was refused before)
    let voted = sr_json(
        &csv,
        &[
            "--units",
            "G=m^3/(kg*s^2),m1=kg,m2=kg,r=m,y=N",
            "--epochs",
            "2",
            "--consensus",
            "2",
        ],
    )?;
    assert_eq!(voted["selection"]["method"], "consensus", "{voted}");
    let structure = voted["selection"]["structure"]
        .as_str()
        .ok_or("structure")?;
    assert!(
        structure.contains("m1") && structure.contains('r'),
        "{voted}"
    );
    assert_eq!(
        voted["best"]["features"], doc["best"]["features"],
        "{voted}"
    );
    let plain = sr_json(&csv, &["--epochs", "3"])?;
    let count = |d: &serde_json::Value| d["simplified"].as_u64().ok_or("simplified");
    assert!(count(&plain)? > 0, "{plain}");
    let written = sr_json(&csv, &["--epochs", "3", "--no-simplify"])?;
    assert_eq!(count(&written)?, 0);
    Ok(())
}

// An engineer's calibration table of six points: a two-constant law is searched with at most
// four constants per model, found, and the result carries a warning that says how few rows
// there are (stderr and JSON `warnings`); four rows are still refused.
#[test]
fn a_two_constant_law_on_six_rows_is_found_with_a_warning() -> TestResult {
    let rows: String = (1..=6)
        .map(|i| {
            let x = i as f64;
            format!("{x},{}\n", 2.0 * x.powf(1.5))
        })
        .collect();
    let (_dir, path) = table("six.csv", &format!("x,y\n{rows}"))?;
    let p = path.to_str().ok_or("path")?;
    let out = hxai(&["sr", "--csv", p, "--target", "y", "--json"])?;
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "{err}");
    assert!(err.contains("warning: only 6 rows"), "{err}");
    let doc: serde_json::Value = serde_json::from_slice(&out.stdout)?;
    let warnings = doc["warnings"].as_array().ok_or("warnings")?;
    assert!(
        warnings.iter().any(|w| w
            .as_str()
            .is_some_and(|s| s.contains("at most 4 fitted constants"))),
        "{warnings:?}"
    );
    let r2 = doc["best"]["r2"].as_f64().ok_or("r2")?;
    assert!(r2 > 0.999_999, "R^2 {r2}: {}", doc["best"]["equation"]);
    let n_params = doc["best"]["params"].as_object().ok_or("params")?.len();
    assert!(n_params <= 4, "{n_params} constants on 6 rows");
    Ok(())
}
