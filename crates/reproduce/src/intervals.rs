//! The section "Prediction intervals by method" of `docs/results/README.md` (issue 28):
//! coverage and median width of the 95 % intervals of every case, made by each method the
//! model files offer (CV+ conformal, split conformal, the delta method), side by side.

use hxai_hybrid::IntervalMethod;
use hxai_hybrid::IntervalReport;
use hxai_hybrid::tables::TableModel;
use hxai_table::Table;
use serde::Serialize;
use std::fmt::Write as _;

/// Every method, in the order of the table: the default first.
pub const METHODS: [IntervalMethod; 3] = [
    IntervalMethod::Conformal,
    IntervalMethod::Split,
    IntervalMethod::Delta,
];

/// One method's intervals on a test split.
#[derive(Debug, Clone, Serialize)]
pub struct MethodInterval {
    /// Coverage, width and count (`method`, `nominal`, `coverage`, `n`, `median_width`).
    #[serde(flatten)]
    pub report: IntervalReport,
    /// The median of `(hi - lo) / prediction` over the rows (table cases, whose scatter is
    /// relative; `None` for the tool case).
    pub median_relative_width: Option<f64>,
}

/// Each method's intervals at `level` of `model` on the rows `rows` of `table`; a method the
/// model cannot serve on these rows (for example split conformal with too few scores) is
/// left out.
pub fn of_table(
    model: &TableModel,
    table: &Table,
    rows: &[usize],
    level: f64,
) -> Vec<MethodInterval> {
    let Ok(test) = table.select_rows(rows) else {
        return Vec::new();
    };
    let (Some(y), Ok(pred)) = (test.column(&model.target), model.predict(&test)) else {
        return Vec::new();
    };
    METHODS
        .iter()
        .filter_map(|&method| {
            let iv = model.intervals_with(&test, level, method).ok()?;
            let mut rel: Vec<f64> = iv
                .iter()
                .zip(&pred.hybrid)
                .map(|((lo, hi), p)| (hi - lo) / p.abs())
                .filter(|r| r.is_finite())
                .collect();
            rel.sort_by(f64::total_cmp);
            Some(MethodInterval {
                report: IntervalReport::of(method, level, y, &iv),
                median_relative_width: median(&rel),
            })
        })
        .collect()
}

fn median(sorted: &[f64]) -> Option<f64> {
    let n = sorted.len();
    match n {
        0 => None,
        n if n % 2 == 1 => Some(sorted[n / 2]),
        n => Some(0.5 * (sorted[n / 2 - 1] + sorted[n / 2])),
    }
}

fn pct(v: f64) -> String {
    format!("{:.1} %", 100.0 * v)
}

/// The method's cell: `coverage (width)`, or a dash when it was not computed.
fn cell(rows: &[MethodInterval], method: IntervalMethod, relative: bool) -> String {
    let Some(m) = rows.iter().find(|m| m.report.method == method) else {
        return "–".into();
    };
    let width = if relative {
        m.median_relative_width.map_or("–".into(), pct)
    } else {
        m.report
            .median_width
            .map_or("–".into(), |w| format!("{w:.3}"))
    };
    format!("{} ({width})", pct(m.report.coverage))
}

/// One table case as the section shows it (made by `crate::beyond::CaseResult::intervals`).
#[derive(Debug, Clone, Copy)]
pub struct TableCase<'a> {
    /// Human title.
    pub title: &'a str,
    /// `additive` or `multiplicative`.
    pub correction_form: &'a str,
    /// The column of the extrapolation split.
    pub extrapolate: &'a str,
    /// The generator's measurement scatter (log-sd of the measured/true ratio).
    pub noise_rel: Option<f64>,
    /// The random split's, then the extrapolation split's intervals.
    pub splits: [TableSplit<'a>; 2],
}

/// One split of a [`TableCase`].
#[derive(Debug, Clone, Copy)]
pub struct TableSplit<'a> {
    /// `random` or `extrapolate`.
    pub split: &'a str,
    /// Test rows.
    pub n_test: usize,
    /// Each method's intervals on the test rows.
    pub intervals: &'a [MethodInterval],
}

/// The section's markdown: the tool case's `tool` intervals (of the amplitude, on the test
/// windows) and each table case's at both splits.
pub fn markdown(tool: &[MethodInterval], cases: &[TableCase<'_>]) -> String {
    let mut s = String::new();
    let _ = writeln!(
        s,
        "\n## Prediction intervals by method: coverage (median width) at 95 %\n\n\
         Every model file of this page stores what three interval methods need; each cell \
         gives the share of test rows (tool case: test windows' true amplitudes) inside the \
         95 % interval and, in brackets, its median width: in µm for the tool case, relative \
         to the prediction for the tables (their scatter grows with the value). The commands: \
         `hxai evaluate --json --interval-method M` and `hxai hybrid evaluate --json \
         --interval-method M`, key `interval`.\n\n\
         - **conformal** (the default): CV+ over 5 folds of the training rows (grouped by \
         record in the tool case), each fold refitting the model's constants (not its \
         structure), scores normalised by a scale that follows the prediction, on the log \
         scale for the multiplicative and log forms. Guaranteed for rows exchangeable with \
         the training rows (the random splits); **not** at the extrapolation splits, where the \
         test rows lie outside the training range of one column and the width follows the \
         scale model's line only.\n\
         - **split**: split conformal, the first fold's model and that fold's scores (about \
         80 rows here, so its quantile is coarse).\n\
         - **delta**: the delta method with one constant residual variance, as before.\n"
    );
    let _ = writeln!(
        s,
        "| case | split | test rows | conformal | split | delta | measurement scatter's own band |\n|---|---|---:|---|---|---|---|"
    );
    if let Some(n) = tool.first().map(|m| m.report.n) {
        let _ = writeln!(
            s,
            "| tool position (paper), amplitude | random records | {n} | {} | {} | {} | – |",
            cell(tool, IntervalMethod::Conformal, false),
            cell(tool, IntervalMethod::Split, false),
            cell(tool, IntervalMethod::Delta, false)
        );
    }
    for c in cases {
        let band = c
            .noise_rel
            .map_or("–".into(), |sd| pct(2.0 * (1.96 * sd).sinh()));
        for sp in &c.splits {
            let split = if sp.split == "random" {
                "random".to_string()
            } else {
                format!("extrapolation in `{}`", c.extrapolate)
            };
            let _ = writeln!(
                s,
                "| {} ({} form) | {split} | {} | {} | {} | {} | {band} |",
                c.title,
                c.correction_form,
                sp.n_test,
                cell(sp.intervals, IntervalMethod::Conformal, true),
                cell(sp.intervals, IntervalMethod::Split, true),
                cell(sp.intervals, IntervalMethod::Delta, true),
            );
        }
    }
    let _ = writeln!(
        s,
        "\nThe last column is the width of the generator's measurement scatter alone, \
         `2 sinh(1.96 σ)` of the value for log-normal scatter of log-sd σ (docs/cases.md): the \
         narrowest band a perfect model could keep its promise with. The roughness generator \
         adds insert-to-insert scatter of the ploughing term on top, which no column explains, \
         so its honest band is wider than that. Each row is one seeded draw of 80 test rows, \
         where even an exact 95 % method lands outside 93-97 % about 40 % of the time \
         (binomial sd 2.4 points): docs/benchmarks.md pools 30 draws per case \
         (`scripts/interval_coverage.py`)."
    );
    s
}
