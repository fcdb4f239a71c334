//! The options of `hxai hybrid fit | predict | evaluate | compare` (clap). Defaults that the
//! library owns (split, seed, search budget) are read from `TableConfig::new`, so the
//! help shows the values a fit uses and no number is written twice.
use hxai_hybrid::tables::{CorrectionForm, TableConfig};
use std::path::PathBuf;

/// The library's settings of a table hybrid, for the defaults shown and used here.
fn defaults() -> TableConfig {
    TableConfig::new("", "")
}

/// Arguments of `hxai hybrid`.
#[derive(Debug, clap::Args)]
pub struct Args {
    #[command(subcommand)]
    pub(crate) command: Sub,
}

#[derive(Debug, clap::Subcommand)]
pub(crate) enum Sub {
    /// Calibrate a physics equation, learn its correction, write the model file.
    Fit(FitArgs),
    /// Physics, correction and hybrid for every row of a table.
    Predict(PredictArgs),
    /// Physics vs hybrid on the rows of a table (needs the target column).
    Evaluate(EvaluateArgs),
    /// Physics, calibrated physics, symbolic regression, physics + forest and the hybrid on
    /// the same splits, with k-fold CV and paired t-tests.
    Compare(CompareArgs),
    /// The settings of the next runs: where the alternatives the data cannot tell apart
    /// disagree most (`--goal discriminate`), or where the intervals are widest
    /// (`--goal coverage`), never outside the space given.
    Design(super::design::DesignArgs),
}

/// `--correction` values.
#[derive(Debug, Clone, Copy, clap::ValueEnum)]
pub(crate) enum CorrectionArg {
    /// y = f_p + delta.
    Additive,
    /// y = f_p (1 + delta).
    Multiplicative,
    /// y = f_p exp(delta), delta found on the log scale: for scatter that grows with the
    /// quantity (log-normal) and power-law corrections. Target and physics must be positive.
    Log,
}

/// `--form` values.
#[derive(Debug, Clone, Copy, clap::ValueEnum)]
pub(crate) enum FormArg {
    /// Free-form symbolic regression over every feature.
    Free,
    /// One closed-form factor per column (power, linear, exponential, logarithm, pole,
    /// saturation, one harmonic), kept only where it lowers the cross-validated error, at most one
    /// two-column interaction: a product of factors (multiplicative, log) or a sum of terms
    /// (additive).
    Factors,
    /// No correction: the calibrated physics alone.
    None,
    /// none, factors or free, chosen by 3-fold cross-validation on the training rows with
    /// the one-standard-error rule toward the simpler.
    Auto,
}

impl From<FormArg> for hxai_hybrid::tables::Form {
    fn from(f: FormArg) -> Self {
        match f {
            FormArg::Free => hxai_hybrid::tables::Form::Free,
            FormArg::Factors => hxai_hybrid::tables::Form::Factors,
            FormArg::None => hxai_hybrid::tables::Form::None,
            FormArg::Auto => hxai_hybrid::tables::Form::Auto,
        }
    }
}

/// Options shared by `fit` and `compare`.
#[derive(Debug, clap::Args)]
pub(crate) struct Common {
    /// Table (CSV or Parquet, by extension).
    #[arg(long)]
    pub(crate) data: PathBuf,
    /// Column to model.
    #[arg(long)]
    pub(crate) target: String,
    /// Physics equation over column and parameter names, e.g. "kc*b*h^(1-mc)".
    #[arg(long)]
    pub(crate) physics: String,
    /// Parameters fitted on the training rows (comma-separated).
    #[arg(long, value_delimiter = ',')]
    pub(crate) calibrate: Vec<String>,
    /// Starting values of calibrated parameters: P1=V,P2=V (default 1).
    #[arg(long, value_delimiter = ',')]
    pub(crate) init: Vec<String>,
    /// Values of parameters that are not calibrated: P=V (repeat or comma-separate).
    #[arg(long, value_delimiter = ',')]
    pub(crate) set: Vec<String>,
    /// Feature columns of the correction, comma-separated (default: every column except
    /// target and group); a name holding a comma in backquotes: `` `rate, 1/s` ``.
    #[arg(long, conflicts_with = "exclude")]
    pub(crate) features: Option<Vec<String>>,
    /// Columns left out of the default feature set, comma-separated (backquotes as for
    /// `--features`).
    #[arg(long)]
    pub(crate) exclude: Vec<String>,
    /// Columns an engineer knows repeat (a spindle angle, a time of day), comma-separated:
    /// only these may carry a harmonic (sin, cos) in the correction; without it, none does.
    #[arg(long)]
    pub(crate) periodic: Vec<String>,
    /// Monotone effects, comma-separated `COL=+` (the correction's effect of COL never
    /// decreases over its training range) or `COL=-` (never increases): respected by every
    /// factor and pair of the factor form (with it, auto chooses between none and factors,
    /// and --form free is refused).
    #[arg(long)]
    pub(crate) monotone: Vec<String>,
    /// The factor form's shapes: classic (power, linear, exp, log, pole, saturation, pair,
    /// periodic where declared; the default), all (with the threshold and saturation shapes
    /// hinge, step and saturating_power), or a comma-separated list of shape names.
    #[arg(long, default_value = "classic")]
    pub(crate) shapes: String,
    /// Most two-column interaction factors of the factor form; each is kept only where it
    /// lowers the held-out error by more than two paired standard errors.
    #[arg(long, default_value_t = defaults().factors.interactions)]
    pub(crate) interactions: usize,
    /// How the correction enters the hybrid.
    #[arg(long, value_enum, default_value_t = CorrectionArg::Additive)]
    pub(crate) correction: CorrectionArg,
    /// How the correction is searched: chosen by cross-validation among none (the physics
    /// alone), factors and free (auto, the default), or forced.
    #[arg(long, value_enum, default_value_t = FormArg::Auto)]
    pub(crate) form: FormArg,
    /// Rows sharing this column's value stay on one side of every split.
    #[arg(long)]
    pub(crate) group: Option<String>,
    /// Share of rows (or groups) held out for testing.
    #[arg(long, default_value_t = defaults().test_fraction)]
    pub(crate) test_fraction: f64,
    /// Test on the rows with the top --test-fraction of this column (train low, test high).
    #[arg(long)]
    pub(crate) extrapolate: Option<String>,
    /// Seed of the split and the search.
    #[arg(long, default_value_t = defaults().seed)]
    pub(crate) seed: u64,
    /// Epochs of the symbolic-regression search.
    #[arg(long, default_value_t = defaults().search.epochs)]
    pub(crate) epochs: usize,
    /// Largest complexity of the correction (input leaves + operators).
    #[arg(long, default_value_t = defaults().search.max_complexity)]
    pub(crate) max_complexity: usize,
    /// Comma-separated operators of the correction's search, from: add sub mul div exp log
    /// sqrt square inverse sin cos tanh abs gaussian gaussian2 (default: the law operators,
    /// add sub mul div exp log: power laws, exponentials and quotients).
    #[arg(long, value_delimiter = ',')]
    pub(crate) operators: Option<Vec<String>>,
    /// Which operator may appear inside which: `readable` (the default of corrections: no
    /// exp, log, sin, cos, tanh or gaussian inside another, except a power law
    /// `exp(a*log(x))`), `none`, or rules `OUTER:INNER=MAX` (e.g. `readable,exp:log=0`).
    #[arg(long)]
    pub(crate) nesting: Option<String>,
    /// Consensus selection: also search N bootstrap resamples of the rows and select the
    /// structure most of them give back among their near-best models, refitted on all rows
    /// (0, the default, selects by --criterion from one search). In the factor form: the
    /// factor set (columns and shapes) most of the N + 1 selections give back; the model
    /// file's `correction.selection.share` is the share of the N resamples that did.
    #[arg(long)]
    pub(crate) consensus: Option<usize>,
    /// How the correction's equation is chosen among the search's candidates (see
    /// `hxai sr --help`; default `cv`, the library's for table hybrids).
    #[arg(long, value_enum)]
    pub(crate) criterion: Option<crate::strategy::CriterionArg>,
    /// The prior over structures by which the criterion picks the correction (see
    /// `hxai sr --help`; default `uniform`, the library's for table hybrids: under `cv`,
    /// the lowest complexity within one standard error; `laws` picks the shortest
    /// description under the model of written laws instead).
    #[arg(long, value_enum)]
    pub(crate) prior: Option<crate::strategy::PriorArg>,
    /// Folds of `--criterion cv`.
    #[arg(long, default_value_t = defaults().search.cv_folds)]
    pub(crate) cv_folds: usize,
    /// Refit physics parameters and correction constants together once the correction's
    /// structure is chosen (the two-stage values are reported too).
    #[arg(long)]
    pub(crate) joint: bool,
    /// Folds of the CV+ calibration of conformal prediction intervals, stored in the model
    /// file (each fold refits the hybrid's constants, not its structure); 0 fits without
    /// them (the delta method is then the only interval).
    #[arg(long, default_value_t = hxai_hybrid::conformal::DEFAULT_CONFORMAL_FOLDS)]
    pub(crate) conformal_folds: usize,
    /// Training rows above which the correction's structure (the form `auto`'s choice, the
    /// search, the conformal and stability refits) is found on a sample of this many rows
    /// stratified on the target; the physics' calibration and the correction's constants
    /// always use every training row (docs/hybrid-tables.md, "Large tables").
    #[arg(long, default_value_t = hxai_hybrid::tables::SEARCH_ROWS)]
    pub(crate) search_rows: usize,
    /// Empty cells: `refuse` (the default; the message names the column, its count and the
    /// other choices), `drop` (drop the rows with an empty cell in a column the model
    /// reads) or `impute` (fill a feature's empty cells with its training median, stored
    /// in the model file so `predict` fills new rows the same way; never the target's,
    /// whose empty rows are dropped, nor the physics columns', whose gaps are refused).
    #[arg(long, default_value = "refuse", value_parser = hxai_data::MissingPolicy::parse)]
    pub(crate) missing: hxai_data::MissingPolicy,
    /// Physics parameters fitted once per level of a text column: COL=P1,P2 (e.g.
    /// `material=kc` for Kienzle's kc per material). The model file holds `P1[level]` per
    /// level with its standard error; `predict` refuses a level the fit never saw.
    #[arg(long)]
    pub(crate) calibrate_per: Option<String>,
    /// The correction's constants refitted per level of a text column COL (its structure
    /// shared): "the same law, its constants per batch of material". `predict` refuses a
    /// level the fit never saw; prediction intervals are not built for it.
    #[arg(long)]
    pub(crate) correction_per: Option<String>,
    /// Print one JSON document on stdout instead of text.
    #[arg(long)]
    pub(crate) json: bool,
}

#[derive(Debug, clap::Args)]
pub(crate) struct FitArgs {
    #[command(flatten)]
    pub(crate) common: Common,
    /// Where to write the model file (JSON).
    #[arg(long)]
    pub(crate) out: PathBuf,
    /// Also rerun the correction's search on N seeded bootstrap resamples of the training
    /// rows; the model file gets `stability` (feature and structure shares, out-of-bag R^2).
    #[arg(long)]
    pub(crate) stability: Option<usize>,
}

#[derive(Debug, clap::Args)]
pub(crate) struct CompareArgs {
    #[command(flatten)]
    pub(crate) common: Common,
    /// Folds of the cross-validation (0 to skip it).
    #[arg(long, default_value_t = 5)]
    pub(crate) folds: usize,
    /// Nominal level of the hybrid's prediction intervals whose coverage on the test rows
    /// is reported.
    #[arg(long, default_value_t = hxai_hybrid::DEFAULT_INTERVAL)]
    pub(crate) interval: f64,
    /// How the prediction intervals are made (default: conformal where the model has it).
    #[arg(long, value_enum)]
    pub(crate) interval_method: Option<crate::strategy::IntervalMethodArg>,
}

#[derive(Debug, clap::Args)]
pub(crate) struct PredictArgs {
    /// Model file written by `hxai hybrid fit`.
    #[arg(long)]
    pub(crate) model: PathBuf,
    /// Table (CSV or Parquet).
    #[arg(long)]
    pub(crate) data: PathBuf,
    /// Output table (CSV or Parquet): columns physics, correction, hybrid (and hybrid_lo,
    /// hybrid_hi with --interval).
    #[arg(long)]
    pub(crate) out: PathBuf,
    /// Add the hybrid's prediction interval at this level (e.g. 0.95) as the columns
    /// hybrid_lo and hybrid_hi.
    #[arg(long)]
    pub(crate) interval: Option<f64>,
    /// How the prediction intervals are made (default: conformal where the model file
    /// stores its calibration, else delta).
    #[arg(long, value_enum, requires = "interval")]
    pub(crate) interval_method: Option<crate::strategy::IntervalMethodArg>,
    /// Empty cells in the columns the model reads: `refuse` (the default), `drop` (drop
    /// those rows, counted on stderr) or `impute` (fill them with the training medians the
    /// model file stores; a model fitted without `--missing impute` has none).
    #[arg(long, default_value = "refuse", value_parser = hxai_data::MissingPolicy::parse)]
    pub(crate) missing: hxai_data::MissingPolicy,
}

#[derive(Debug, clap::Args)]
pub(crate) struct EvaluateArgs {
    /// Model file written by `hxai hybrid fit`.
    #[arg(long)]
    pub(crate) model: PathBuf,
    /// Table (CSV or Parquet) with the target column.
    #[arg(long)]
    pub(crate) data: PathBuf,
    /// Nominal level of the prediction intervals whose coverage is reported.
    #[arg(long, default_value_t = hxai_hybrid::DEFAULT_INTERVAL)]
    pub(crate) interval: f64,
    /// How the prediction intervals are made (default: conformal where the model file
    /// stores its calibration, else delta).
    #[arg(long, value_enum)]
    pub(crate) interval_method: Option<crate::strategy::IntervalMethodArg>,
    /// Empty cells in the columns the model reads: `refuse` (the default), `drop` (drop
    /// those rows, counted on stderr) or `impute` (fill them with the training medians the
    /// model file stores; a model fitted without `--missing impute` has none).
    #[arg(long, default_value = "refuse", value_parser = hxai_data::MissingPolicy::parse)]
    pub(crate) missing: hxai_data::MissingPolicy,
    /// Print one JSON document on stdout instead of text.
    #[arg(long)]
    pub(crate) json: bool,
}

/// Column names given to `flag` (each value comma-separated, the flag repeatable): a name
/// in backquotes may hold a comma (`` `rate, 1/s` ``), as in the physics equation.
///
/// # Errors
/// An unmatched backquote, or an empty name.
pub(crate) fn column_names(values: &[String], flag: &str) -> anyhow::Result<Vec<String>> {
    let mut out = Vec::new();
    for v in values {
        let mut name = String::new();
        let mut quoted = false;
        let mut push = |name: &mut String| -> anyhow::Result<()> {
            let n = name.trim();
            let n = n
                .strip_prefix('`')
                .and_then(|x| x.strip_suffix('`'))
                .unwrap_or(n);
            anyhow::ensure!(
                !n.trim().is_empty(),
                "{flag} {v:?}: an empty column name (two commas in a row, or one at an end?)"
            );
            out.push(n.to_string());
            name.clear();
            Ok(())
        };
        for ch in v.chars() {
            match ch {
                '`' => {
                    quoted = !quoted;
                    name.push(ch);
                }
                ',' if !quoted => push(&mut name)?,
                _ => name.push(ch),
            }
        }
        anyhow::ensure!(
            !quoted,
            "{flag} {v:?}: a backquote is not closed (a name with a comma is written `name, unit`)"
        );
        push(&mut name)?;
    }
    Ok(out)
}

impl Common {
    /// The library's configuration for these options.
    pub(crate) fn config(&self) -> anyhow::Result<TableConfig> {
        let c = self;
        let mut cfg = TableConfig::new(&c.target, &c.physics);
        cfg.calibrate = c.calibrate.iter().map(|s| s.trim().to_string()).collect();
        cfg.init = crate::strategy::pairs(&c.init, "--init", "a number")?;
        cfg.set = crate::strategy::pairs(&c.set, "--set", "a number")?;
        cfg.features = c
            .features
            .as_ref()
            .map(|f| column_names(f, "--features"))
            .transpose()?;
        cfg.exclude = column_names(&c.exclude, "--exclude")?;
        cfg.periodic = column_names(&c.periodic, "--periodic")?;
        if let Some(p) = cfg.periodic.iter().find(|p| p.contains('=')) {
            anyhow::bail!(
                "--periodic {p}: a fixed period is not built yet; name the column alone \
                 (--periodic {}) and the fit finds the period",
                p.split('=').next().unwrap_or_default()
            );
        }
        for m in column_names(&c.monotone, "--monotone")? {
            match m.rsplit_once('=').map(|(col, d)| (col.trim(), d.trim())) {
                Some((col, "+")) if !col.is_empty() => cfg.increasing.push(col.to_string()),
                Some((col, "-")) if !col.is_empty() => cfg.decreasing.push(col.to_string()),
                _ => anyhow::bail!(
                    "--monotone {m}: write COL=+ (the effect never decreases) or COL=- \
                     (never increases)"
                ),
            }
        }
        cfg.factors.interactions = c.interactions;
        cfg.factors.shapes = hxai_symreg::factors::Shapes::parse(&c.shapes).ok_or_else(|| {
            anyhow::anyhow!(
                "--shapes {}: write classic, all, or shape names among power, linear, \
                 exp, log, pole, saturation, hinge, saturating_power, step, periodic, \
                 pair",
                c.shapes
            )
        })?;
        cfg.correction = match c.correction {
            CorrectionArg::Additive => CorrectionForm::Additive,
            CorrectionArg::Multiplicative => CorrectionForm::Multiplicative,
            CorrectionArg::Log => CorrectionForm::Log,
        };
        cfg.form = c.form.into();
        cfg.group = c.group.clone();
        cfg.test_fraction = c.test_fraction;
        cfg.extrapolate = c.extrapolate.clone();
        cfg.seed = c.seed;
        cfg.joint = c.joint;
        cfg.conformal_folds = c.conformal_folds;
        cfg.search_rows = c.search_rows;
        crate::strategy::SearchFlags {
            epochs: Some(c.epochs),
            max_complexity: Some(c.max_complexity),
            criterion: c.criterion.map(Into::into),
            cv_folds: Some(c.cv_folds),
            operators: c.operators.as_deref(),
            nesting: c.nesting.as_deref(),
            consensus: c.consensus,
            prior: c.prior.map(Into::into),
            ..Default::default()
        }
        .apply(&mut cfg.search)?;
        Ok(cfg)
    }
}

#[cfg(test)]
mod tests {
    use super::column_names;

    fn v(s: &[&str]) -> Vec<String> {
        s.iter().map(|x| x.to_string()).collect()
    }

    /// Issue 52: a column whose name holds a comma is given in backquotes; plain names are
    /// split on commas and trimmed; repeated flags add up; a lone backquote or an empty
    /// name is refused in words.
    #[test]
    fn names_with_commas_are_given_in_backquotes() -> anyhow::Result<()> {
        assert_eq!(
            column_names(&v(&["a, `rate, 1/s` ,b", "c"]), "--exclude")?,
            v(&["a", "rate, 1/s", "b", "c"])
        );
        assert_eq!(column_names(&v(&["`x`"]), "--features")?, v(&["x"]));
        let e = column_names(&v(&["a,`b"]), "--exclude").err();
        assert!(e.is_some_and(|e| e.to_string().contains("not closed")));
        let e = column_names(&v(&["a,,b"]), "--exclude").err();
        assert!(e.is_some_and(|e| e.to_string().contains("empty column name")));
        Ok(())
    }
}
