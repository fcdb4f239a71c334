//! Empty cells and missing-value codes: refused, dropped or imputed by choice, named when
//! refused, and never read in columns the model does not use.

use super::*;

/// An empty cell in a numeric column that would be a feature is refused naming its row and
/// column (before: the column was dropped from the features without a word); excluding the
/// column lets the fit go on; a real text column left out of the default features is said
/// on stderr.
#[test]
fn an_empty_cell_in_a_used_column_is_named() -> TestResult {
    let (dir, csv) = scratch_table("gap", 60)?;
    let text = std::fs::read_to_string(&csv)?;
    // Empty the `v` cell of data row 5 (line 6 of the file).
    let gapped: Vec<String> = text
        .lines()
        .enumerate()
        .map(|(i, l)| {
            if i == 5 {
                let mut cells: Vec<&str> = l.split(',').collect();
                cells[3] = "";
                cells.join(",")
            } else {
                l.to_owned()
            }
        })
        .collect();
    std::fs::write(&csv, gapped.join("\n") + "\n")?;
    let model = dir.join("m.json");
    let o = hxai(&fit_args(s(&csv), s(&model)))?;
    assert_eq!(o.status.code(), Some(1));
    let err = common::stderr(&o);
    assert!(
        err.contains("row 5, column `v`: the cell is empty"),
        "{err}"
    );
    let mut args = fit_args(s(&csv), s(&model));
    args.extend(["--exclude", "v,batch"]);
    let o = hxai(&args)?;
    ok(&o, "fit without v");
    assert!(!common::stderr(&o).contains("holds text"));
    let o = hxai(&fit_args(s(&scratch_table("gap-text", 60)?.1), s(&model)))?;
    ok(&o, "fit with a text column");
    assert!(common::stderr(&o).contains("column `batch` holds text"));
    // a column of true/false is named as such, not as text
    let (_dir, flags) = scratch_table("flags", 60)?;
    let with_flag: Vec<String> = std::fs::read_to_string(&flags)?
        .lines()
        .enumerate()
        .map(|(i, l)| match i {
            0 => format!("{l},coolant"),
            _ => format!("{l},{}", if i % 2 == 0 { "true" } else { "FALSE" }),
        })
        .collect();
    std::fs::write(&flags, with_flag.join("\n") + "\n")?;
    let o = hxai(&fit_args(s(&flags), s(&model)))?;
    ok(&o, "fit with a true/false column");
    assert!(
        common::stderr(&o).contains("column `coolant` holds true/false values"),
        "{}",
        common::stderr(&o)
    );
    std::fs::remove_dir_all(&dir)?;
    Ok(())
}

/// `text` with the cells at (data row, column index) emptied.
fn with_gaps(text: &str, gaps: &[(usize, usize)]) -> String {
    with_codes(text, gaps, "")
}

#[test]
fn empty_cells_are_refused_dropped_or_imputed_by_choice() -> TestResult {
    let (dir, csv) = scratch_table("missing", 60)?;
    let text = std::fs::read_to_string(&csv)?;
    // columns: batch,f,r,v,d,Ra; gaps in v (rows 3, 9) and d (row 4); the target in row 20
    let gapped = dir.join("gapped.csv");
    std::fs::write(
        &gapped,
        with_gaps(&text, &[(3, 3), (9, 3), (4, 4), (20, 5)]),
    )?;
    let model = dir.join("m.json");
    let mut args = fit_args(s(&gapped), s(&model));
    args.extend(["--exclude", "batch"]);
    let o = hxai(&args)?;
    assert_eq!(o.status.code(), Some(1));
    let err = common::stderr(&o);
    assert!(
        err.contains("empty cell(s)") && err.contains("--missing drop"),
        "{err}"
    );
    assert!(!model.exists());

    let mut drop = args.clone();
    drop.extend(["--missing", "drop"]);
    let o = hxai(&drop)?;
    ok(&o, "fit --missing drop");
    assert!(
        common::stderr(&o).contains("dropped 4 row(s)"),
        "{}",
        common::stderr(&o)
    );
    let doc: serde_json::Value = serde_json::from_str(&std::fs::read_to_string(&model)?)?;
    assert_eq!(doc["missing"]["policy"], "drop");
    assert!(doc["warnings"].to_string().contains("dropped 4 row(s)"));

    let mut impute = args.clone();
    impute.extend(["--missing", "impute"]);
    let o = hxai(&impute)?;
    ok(&o, "fit --missing impute");
    let err = common::stderr(&o);
    assert!(err.contains("dropped 1 row(s)"), "{err}");
    assert!(err.contains("filled 2 empty cell(s) of `v`"), "{err}");
    let doc: serde_json::Value = serde_json::from_str(&std::fs::read_to_string(&model)?)?;
    assert_eq!(doc["missing"]["policy"], "impute");
    // the median of v over the 59 rows with a target, the two gaps left out
    let mut v: Vec<f64> = text
        .lines()
        .skip(1)
        .enumerate()
        .filter(|(i, _)| ![2, 8, 19].contains(i))
        .map(|(_, l)| l.split(',').nth(3).unwrap_or("").parse::<f64>())
        .collect::<Result<_, _>>()?;
    v.sort_by(f64::total_cmp);
    let median = if v.len() % 2 == 1 {
        v[v.len() / 2]
    } else {
        0.5 * (v[v.len() / 2 - 1] + v[v.len() / 2])
    };
    let stored = doc["missing"]["medians"]["v"]
        .as_f64()
        .ok_or("median of v")?;
    assert!(
        (stored - median).abs() <= 1e-12 * median,
        "{stored} vs {median}"
    );

    // predict: a new row with an empty v is filled with the stored median, so it predicts
    // as the same row with v = median
    let new = dir.join("new.csv");
    let full = dir.join("full.csv");
    let rows: Vec<&str> = text.lines().take(3).collect();
    std::fs::write(&full, rows.join("\n") + "\n")?;
    let mut filled = rows.iter().map(|l| l.to_string()).collect::<Vec<_>>();
    let mut cells: Vec<String> = filled[1].split(',').map(str::to_owned).collect();
    cells[3] = format!("{median}");
    filled[1] = cells.join(",");
    std::fs::write(&full, filled.join("\n") + "\n")?;
    std::fs::write(&new, with_gaps(&(rows.join("\n") + "\n"), &[(1, 3)]))?;
    let out_a = dir.join("pa.csv");
    let out_b = dir.join("pb.csv");
    let o = hxai(&predict_args(&model, &new, &out_a))?;
    assert_eq!(
        o.status.code(),
        Some(1),
        "a gap is refused without --missing"
    );
    let mut pa = predict_args(&model, &new, &out_a);
    pa.extend(["--missing", "impute"]);
    ok(&hxai(&pa)?, "predict --missing impute");
    ok(
        &hxai(&predict_args(&model, &full, &out_b))?,
        "predict the filled row",
    );
    assert_eq!(
        std::fs::read_to_string(&out_a)?,
        std::fs::read_to_string(&out_b)?
    );

    // the physics' gap is refused under impute, naming the column; nothing written
    let phys_gap = dir.join("phys.csv");
    std::fs::write(&phys_gap, with_gaps(&text, &[(5, 1)]))?;
    let model2 = dir.join("m2.json");
    let mut a2 = fit_args(s(&phys_gap), s(&model2));
    a2.extend(["--exclude", "batch", "--missing", "impute"]);
    let o = hxai(&a2)?;
    assert_eq!(o.status.code(), Some(1));
    let err = common::stderr(&o);
    assert!(err.contains("`f`") && err.contains("physics"), "{err}");
    assert!(!model2.exists());
    // a model fitted on complete rows has no medians to fill with
    let model3 = dir.join("m3.json");
    let mut a3 = fit_args(s(&csv), s(&model3));
    a3.extend(["--exclude", "batch"]);
    ok(&hxai(&a3)?, "fit on complete rows");
    let mut p3 = predict_args(&model3, &new, &out_a);
    p3.extend(["--missing", "impute"]);
    let o = hxai(&p3)?;
    assert_eq!(o.status.code(), Some(1));
    assert!(
        common::stderr(&o).contains("stores no"),
        "{}",
        common::stderr(&o)
    );
    Ok(())
}

/// `text` with the cells at (data row, column index) replaced by `code`.
fn with_codes(text: &str, cells: &[(usize, usize)], code: &str) -> String {
    text.lines()
        .enumerate()
        .map(|(i, l)| {
            let mut row: Vec<String> = l.split(',').map(str::to_owned).collect();
            for &(r, c) in cells {
                if i == r {
                    row[c] = code.to_string();
                }
            }
            row.join(",") + "\n"
        })
        .collect()
}

#[test]
fn missing_value_codes_are_read_as_empty_cells_when_named() -> TestResult {
    let (dir, csv) = scratch_table("codes", 60)?;
    let text = std::fs::read_to_string(&csv)?;
    // columns: batch,f,r,v,d,Ra; codes in v (rows 3, 9) and the target (row 20)
    let cells = [(3, 3), (9, 3), (20, 5)];
    let coded = dir.join("coded.csv");
    std::fs::write(&coded, with_codes(&text, &cells, "-9999"))?;
    let gapped = dir.join("gapped.csv");
    std::fs::write(&gapped, with_gaps(&text, &cells))?;

    let plain = dir.join("plain.json");
    let mut args = fit_args(s(&coded), s(&plain));
    args.extend(["--exclude", "batch"]);
    let o = hxai(&args)?;
    ok(&o, "fit with -9999 as a number");
    let err = common::stderr(&o);
    assert!(
        err.contains("missing-value code") && err.contains("--missing-codes=-9999"),
        "{err}"
    );

    let refused = dir.join("refused.json");
    let mut a = fit_args(s(&coded), s(&refused));
    a.extend(["--exclude", "batch", "--missing-codes=-9999"]);
    let o = hxai(&a)?;
    assert_eq!(o.status.code(), Some(1));
    let err = common::stderr(&o);
    assert!(
        err.contains("read 3 cell(s) equal to a --missing-codes value as empty")
            && err.contains("`v` 2")
            && err.contains("`Ra` 1")
            && err.contains("--missing drop"),
        "{err}"
    );
    assert!(!refused.exists());

    let (m_coded, m_gapped) = (dir.join("mc.json"), dir.join("mg.json"));
    let mut a = fit_args(s(&coded), s(&m_coded));
    a.extend([
        "--exclude",
        "batch",
        "--missing-codes",
        "-9999,9.96921e36",
        "--missing",
        "drop",
    ]);
    ok(&hxai(&a)?, "fit --missing-codes -9999 --missing drop");
    let mut b = fit_args(s(&gapped), s(&m_gapped));
    b.extend(["--exclude", "batch", "--missing", "drop"]);
    ok(&hxai(&b)?, "fit the gapped file --missing drop");
    let (jc, jg): (serde_json::Value, serde_json::Value) = (
        serde_json::from_str(&std::fs::read_to_string(&m_coded)?)?,
        serde_json::from_str(&std::fs::read_to_string(&m_gapped)?)?,
    );
    assert_eq!(jc["equation"], jg["equation"]);
    assert_eq!(jc["scores"], jg["scores"]);
    assert_eq!(jc["missing"]["policy"], "drop");
    assert!(jc["warnings"].to_string().contains("dropped 3 row(s)"));

    // hxai sr reads numbers only: the same file without its text column `batch`
    let numbers = dir.join("numbers.csv");
    let no_batch: String = std::fs::read_to_string(&coded)?
        .lines()
        .map(|l| l.split_once(',').map_or(l, |(_, rest)| rest).to_string() + "\n")
        .collect();
    std::fs::write(&numbers, no_batch)?;
    let o = hxai(&[
        "sr",
        "--csv",
        s(&numbers),
        "--target",
        "Ra",
        "--missing-codes=-9999",
        "--missing",
        "drop",
        "--max-evaluations",
        "2000",
        "--json",
    ])?;
    ok(&o, "sr --missing-codes");
    let doc: serde_json::Value = serde_json::from_slice(&o.stdout)?;
    let w = doc["warnings"].to_string();
    assert!(
        w.contains("--missing-codes") && w.contains("dropped 3 row(s)"),
        "{w}"
    );

    let o = hxai(&[
        "sr",
        "--csv",
        s(&numbers),
        "--target",
        "Ra",
        "--missing-codes",
        "none",
    ])?;
    assert_eq!(o.status.code(), Some(2));
    assert!(common::stderr(&o).contains("is not a number"));
    Ok(())
}

/// Issue 52 item 3: a `nan` in a column left out by `--exclude`, or a `1e400` in the target
/// at `hybrid predict` (which does not need it), is not read for numbers; in a column the
/// fit uses, it is refused naming row, column and cell.
#[test]
fn cells_in_columns_not_used_are_not_read_for_numbers() -> TestResult {
    let (dir, data) = scratch_table("unused", 60)?;
    let text = std::fs::read_to_string(&data)?;
    let mut lines: Vec<String> = text.lines().map(str::to_string).collect();
    lines[0].push_str(",junk");
    for (i, l) in lines.iter_mut().enumerate().skip(1) {
        l.push_str(if i == 3 { ",nan" } else { ",1" });
    }
    let junk = dir.join("junk.csv");
    std::fs::write(&junk, lines.join("\n") + "\n")?;
    let model = dir.join("m.json");
    let mut args = fit_args(s(&junk), s(&model));
    args.extend_from_slice(&["--exclude", "junk,batch"]);
    ok(&hxai(&args)?, "fit with nan in an excluded column");
    let used = hxai(&fit_args(s(&junk), s(&dir.join("u.json"))))?;
    assert!(!used.status.success());
    let err = String::from_utf8_lossy(&used.stderr);
    assert!(
        err.contains("row 3, column `junk`: `nan` is not a number"),
        "{err}"
    );
    // the target at predict
    let mut t: Vec<String> = text.lines().map(str::to_string).collect();
    let row = &mut t[5];
    let cut = row.rfind(',').ok_or("comma")?;
    row.truncate(cut);
    row.push_str(",1e400");
    let target = dir.join("target.csv");
    std::fs::write(&target, t.join("\n") + "\n")?;
    let pred = dir.join("p.csv");
    ok(
        &hxai(&predict_args(&model, &target, &pred))?,
        "predict with 1e400 in the unused target",
    );
    Ok(())
}
