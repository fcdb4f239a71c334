//! Tables as they come: sentinel values, European and untidy CSV files, repeated
//! parameters, too many folds and wide tables, each told in one line.

use super::*;

/// Issue 52's sentinel values: a `-9999` (a logger's missing-value code) in the target is
/// fitted but named by row on stderr and in the model's `warnings`; a target of `1e300`
/// under the log correction (whose squared errors overflow) is refused naming the row, and
/// the model file already there is left as it was, never replaced by one that cannot be
/// read back.
#[test]
fn sentinel_values_are_named_and_overflowing_scores_refused() -> TestResult {
    let (dir, data) = scratch_table("sentinel", 80)?;
    let text = std::fs::read_to_string(&data)?;
    let with = |row: usize, value: &str| -> String {
        text.lines()
            .enumerate()
            .map(|(i, l)| {
                if i == row {
                    let mut f: Vec<&str> = l.split(',').collect();
                    let n = f.len();
                    f[n - 1] = value;
                    f.join(",")
                } else {
                    l.to_string()
                }
            })
            .collect::<Vec<_>>()
            .join("\n")
            + "\n"
    };
    let coded = dir.join("coded.csv");
    std::fs::write(&coded, with(5, "-9999"))?;
    let model = dir.join("m.json");
    let args = fit_args(s(&coded), s(&model));
    let out = hxai(&args)?;
    ok(&out, "fit with -9999");
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(
        err.contains("row 5 (-9999)") && err.contains("missing-value code"),
        "{err}"
    );
    let m: serde_json::Value = serde_json::from_str(&std::fs::read_to_string(&model)?)?;
    assert!(
        m["warnings"]
            .as_array()
            .ok_or("warnings")?
            .iter()
            .any(|w| w.as_str().is_some_and(|w| w.contains("row 5 (-9999)"))),
        "{}",
        m["warnings"]
    );
    // 1e300 under the log correction: refused, the old model kept
    let huge = dir.join("huge.csv");
    std::fs::write(&huge, with(7, "1e300"))?;
    let before = std::fs::read(&model)?;
    let mut args = fit_args(s(&huge), s(&model));
    args.extend_from_slice(&["--correction", "log"]);
    let out = hxai(&args)?;
    assert!(
        !out.status.success(),
        "a fit whose scores overflow must fail"
    );
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(err.contains("row 7") && err.contains("1e300"), "{err}");
    assert_eq!(std::fs::read(&model)?, before, "the old model file is kept");
    Ok(())
}

/// Issue 52's names and settings: `--calibrate k,k` is refused (it used to fit and report
/// `k` as undetermined), `--cv-folds` above the training rows is refused (it used to
/// cross-validate with fewer folds in silence), and a physics typo on a 40-column table
/// lists 12 columns and the count of the rest instead of every name.
#[test]
fn repeated_parameters_too_many_folds_and_wide_tables_are_told_briefly() -> TestResult {
    let (dir, data) = scratch_table("settings", 40)?;
    let model = dir.join("m.json");
    let mut args = hybrid_args("fit", s(&data), LAW);
    args.extend_from_slice(&["--calibrate", "k,k", "--out", s(&model)]);
    let out = hxai(&args)?;
    assert!(!out.status.success());
    assert!(
        String::from_utf8_lossy(&out.stderr).contains("`k` is named twice in --calibrate"),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let mut args = fit_args(s(&data), s(&model));
    args.extend_from_slice(&["--cv-folds", "1000"]);
    let out = hxai(&args)?;
    assert!(!out.status.success());
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(
        err.contains("cannot make 1000 cross-validation folds"),
        "{err}"
    );
    assert!(!model.exists());
    // a wide table
    let wide = dir.join("wide.csv");
    let names: Vec<String> = (0..40).map(|j| format!("c{j}")).collect();
    let mut text = names.join(",") + ",y\n";
    for i in 0..30 {
        let row: Vec<String> = (0..41)
            .map(|j| format!("{}", (i * 7 + j * 3) % 11 + 1))
            .collect();
        text.push_str(&(row.join(",") + "\n"));
    }
    std::fs::write(&wide, text)?;
    let out = hxai(&[
        "hybrid",
        "fit",
        "--data",
        s(&wide),
        "--target",
        "y",
        "--physics",
        "k*c1 + cc9",
        "--calibrate",
        "k",
        "--out",
        s(&model),
    ])?;
    assert!(!out.status.success());
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(
        err.contains("`cc9`") && err.contains("the nearest of 41: "),
        "{err}"
    );
    assert!(err.len() < 600, "{} characters: {err}", err.len());
    Ok(())
}

/// A European CSV (`;` between cells, a decimal comma, a header with units) read with
/// `--delimiter ';' --decimal ','` gives the same model as the plain CSV; a file with blank
/// lines, Excel's trailing `,,,` rows and old-Mac `\r` line ends is read too (the skipped
/// rows counted on stderr), and a header repeated mid-file is named by row and cell
/// (issues 48 and 52).
#[test]
fn european_and_untidy_csv_files_are_read() -> TestResult {
    let (dir, data) = scratch_table("european", 60)?;
    let plain = std::fs::read_to_string(&data)?;
    // the same table with units in two names, `;` and decimal commas
    let euro: String = plain
        .lines()
        .enumerate()
        .map(|(i, l)| {
            if i == 0 {
                "batch;f [mm];r;v;d;Ra".to_string()
            } else {
                l.replace(',', ";").replace('.', ",")
            }
        })
        .collect::<Vec<_>>()
        .join("\n")
        + "\n";
    let euro_path = dir.join("euro.csv");
    std::fs::write(&euro_path, euro)?;
    let renamed = dir.join("renamed.csv");
    std::fs::write(&renamed, plain.replacen("batch,f,", "batch,f [mm],", 1))?;
    let law = "k*`f [mm]`^2/(32*r)";
    let fit = |path: &Path,
               out: &Path,
               extra: &[&str]|
     -> Result<serde_json::Value, Box<dyn std::error::Error>> {
        let mut args = hybrid_args("fit", s(path), law);
        args.extend_from_slice(&CALIBRATE_K);
        args.extend_from_slice(&["--out", s(out), "--exclude", "batch"]);
        args.extend_from_slice(&QUICK);
        args.extend_from_slice(extra);
        let o = hxai(&args)?;
        ok(&o, "fit");
        Ok(serde_json::from_str(&std::fs::read_to_string(out)?)?)
    };
    let a = fit(&renamed, &dir.join("a.json"), &[])?;
    let b = fit(
        &euro_path,
        &dir.join("b.json"),
        &["--delimiter", ";", "--decimal", ","],
    )?;
    assert_eq!(a["physics"]["parameters"], b["physics"]["parameters"]);
    assert_eq!(a["hybrid"]["equation"], b["hybrid"]["equation"]);
    // a comma cannot be both
    let c_json = dir.join("c.json");
    let mut args = hybrid_args("fit", s(&euro_path), law);
    args.extend_from_slice(&["--out", s(&c_json), "--decimal", ",", "--delimiter", ","]);
    let o = hxai(&args)?;
    assert!(!o.status.success());
    assert!(String::from_utf8_lossy(&o.stderr).contains("--delimiter ';'"));
    // blank lines, Excel's trailing rows, lone \r line ends
    let untidy = plain.replacen('\n', "\n\n", 3).replace('\n', "\r") + ",,,,,\r,,,,,\r";
    let untidy_path = dir.join("untidy.csv");
    std::fs::write(&untidy_path, untidy)?;
    let d_json = dir.join("d.json");
    let mut args = fit_args(s(&untidy_path), s(&d_json));
    args.extend_from_slice(&["--exclude", "batch"]);
    let o = hxai(&args)?;
    ok(&o, "fit an untidy file");
    assert!(
        String::from_utf8_lossy(&o.stderr).contains("skipped 5 blank line(s)"),
        "{}",
        String::from_utf8_lossy(&o.stderr)
    );
    // a header repeated in the middle: row and cell named
    let header = plain.lines().next().ok_or("header")?;
    let repeated: String = plain
        .lines()
        .enumerate()
        .flat_map(|(i, l)| if i == 10 { vec![header, l] } else { vec![l] })
        .collect::<Vec<_>>()
        .join("\n");
    let rep_path = dir.join("repeated.csv");
    std::fs::write(&rep_path, repeated + "\n")?;
    let o = hxai(&fit_args(s(&rep_path), s(&dir.join("e.json"))))?;
    assert!(!o.status.success());
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(
        err.contains("row 10") && err.contains("is not a number"),
        "{err}"
    );
    Ok(())
}
