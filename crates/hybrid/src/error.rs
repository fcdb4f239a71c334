//! The one error type of `hxai-hybrid`.

/// Everything that can go wrong while building samples, fitting, predicting or evaluating.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum HybridError {
    /// The physics model or the sine fit refused the signal.
    #[error("signal processing failed: {0}")]
    Signal(#[from] hxai_signal::SignalError),
    /// Feature extraction refused a window.
    #[error("feature extraction failed: {0}")]
    Features(#[from] hxai_features::FeatureError),
    /// An error while processing one record (and window), with that context.
    #[error("record `{record}`{}: {source}", window.map(|w| format!(", window {w}")).unwrap_or_default())]
    InRecord {
        /// Record id.
        record: String,
        /// Window index (from 0), when the error is about one window.
        window: Option<usize>,
        /// The cause.
        source: Box<HybridError>,
    },
    /// The symbolic-regression search or a symbolic model failed.
    #[error("symbolic regression failed: {0}")]
    Symreg(#[from] hxai_symreg::SrError),
    /// A table of features or samples broke a table invariant (a non-finite value, ...).
    #[error("table: {0}")]
    Table(#[from] hxai_table::TableError),
    /// A statistic could not be computed.
    #[error("{0}")]
    Eval(#[from] hxai_eval::EvalError),
    /// A record is too short for even one window.
    #[error(
        "record `{record}` lasts {} s but one window needs {} s \
         ({} s discarded at each end + a {} s window); use a longer record (or fit the model \
         with a shorter --window-s or --discard-s)",
        num(*seconds), num(*needed_s), num(*discard_s), num(*window_s)
    )]
    RecordTooShort {
        /// Record id.
        record: String,
        /// Its duration.
        seconds: f64,
        /// Duration needed.
        needed_s: f64,
        /// Window length.
        window_s: f64,
        /// Discarded at each end.
        discard_s: f64,
    },
    /// Fitting or evaluating needs the ground truth, and the record has none.
    #[error(
        "record `{record}` has no ground-truth channel (`probe_um`); it is needed to fit and to evaluate"
    )]
    NoTruth {
        /// Record id.
        record: String,
    },
    /// Input channels of one record differ in length.
    #[error("record `{record}`: the signal has {signal} samples but the ground truth has {truth}")]
    LengthMismatch {
        /// Record id.
        record: String,
        /// Signal length.
        signal: usize,
        /// Ground-truth length.
        truth: usize,
    },
    /// The commanded frequency of a record lies outside the physics model's pass band, where
    /// the band-pass removes the motion and the model would answer near zero.
    #[error(
        "record `{record}`: the commanded frequency {} Hz lies outside the physics model's pass band {}..{} Hz",
        num(*frequency_hz), num(*low_hz), num(*high_hz)
    )]
    FrequencyOutOfBand {
        /// Record id.
        record: String,
        /// Its commanded frequency.
        frequency_hz: f64,
        /// Lower band edge.
        low_hz: f64,
        /// Upper band edge.
        high_hz: f64,
    },
    /// A setting is out of range.
    #[error("invalid setting: {0}")]
    InvalidConfig(String),
    /// There is nothing to fit or to evaluate.
    #[error("{0}")]
    NoData(String),
    /// The model file was written by another schema version.
    #[error(
        "the model file has schema_version {found} but this hxai reads version {expected} (a JSON number); refit the model with this version"
    )]
    SchemaVersion {
        /// Version in the file.
        found: String,
        /// Version this code reads.
        expected: u32,
    },
    /// The model file is not valid JSON of the expected shape.
    #[error("the model file is not a valid hxai hybrid model: {0}")]
    ModelFormat(String),
    /// The correction model asks for features the feature map does not produce.
    #[error(
        "the correction model uses feature `{name}`, which the feature map does not produce (it has: {available})"
    )]
    UnknownFeature {
        /// The missing feature.
        name: String,
        /// The features available.
        available: String,
    },
    /// The physics equation does not parse.
    #[error("physics equation `{}`: {source}", shorten(equation))]
    Equation {
        /// The equation text.
        equation: String,
        /// What the parser reported (with the character position).
        source: hxai_symreg::SrError,
    },
    /// A name in the physics equation is neither a column nor a parameter.
    #[error(
        "physics equation: `{name}` at character {position} is neither a column of the table nor a parameter; \
         fit it with --calibrate {name}, give it with --set {name}=VALUE, or fix the spelling (columns: {columns})"
    )]
    UnknownName {
        /// The name.
        name: String,
        /// 1-based character position of its first use.
        position: usize,
        /// The table's columns, comma-separated.
        columns: String,
    },
    /// A parameter (in --calibrate, --set or --init) is also a column of the table.
    #[error(
        "`{name}` is given as a parameter (--{flag}) but it is also a column of the table; \
         a name in the equation is a column when the table has it: rename the parameter"
    )]
    ParameterIsColumn {
        /// The name.
        name: String,
        /// The option that names it (`calibrate`, `set`, `init`).
        flag: &'static str,
    },
    /// A parameter given in --calibrate, --set or --init does not appear in the equation.
    #[error(
        "parameter `{name}` (--{flag}) does not appear in the physics equation `{}`",
        shorten(equation)
    )]
    ParameterNotInEquation {
        /// The name.
        name: String,
        /// The option that names it.
        flag: &'static str,
        /// The equation.
        equation: String,
    },
    /// The target column appears in the physics equation.
    #[error(
        "the physics equation uses the target column `{name}` (at character {position}): the physics must predict the target from other columns"
    )]
    TargetInPhysics {
        /// The target.
        name: String,
        /// 1-based character position of its first use.
        position: usize,
    },
    /// A column named in the configuration is not in the table.
    #[error("{what} `{name}` is not a column of the table (columns: {columns})")]
    MissingColumn {
        /// Which setting names it (`target`, `feature`, `group`, ...).
        what: &'static str,
        /// The name.
        name: String,
        /// The table's columns, comma-separated.
        columns: String,
    },
    /// No feature column is left for the correction.
    #[error("{0}")]
    NoFeatures(String),
    /// The physics prediction cannot be used at a row.
    #[error("row {} of the table (counted from 1, header not counted): the physics prediction is {}, {why}", row + 1, num(*value))]
    BadPhysics {
        /// Row index, 0-based in the table's order.
        row: usize,
        /// The physics value there.
        value: f64,
        /// Why it cannot be used.
        why: String,
    },
    /// The correction is not finite at a row (outside the domain of its equation).
    #[error(
        "row {} of the table (counted from 1, header not counted): the correction is {value} (the row lies outside the domain of the correction's equation)",
        row + 1
    )]
    BadCorrection {
        /// Row index, 0-based.
        row: usize,
        /// The correction's value there.
        value: f64,
    },
    /// A baseline model (the forest of `compare`) failed.
    #[error("baseline model failed: {0}")]
    Baseline(#[from] hxai_baselines::BaselineError),
}

// A number for a message: the one formatting of the workspace, `hxai_table::format_number`.
pub(crate) use hxai_table::format_number as num;

impl HybridError {
    /// Wraps the error with the record (and window) it happened in.
    pub fn in_record(self, record: &str, window: Option<usize>) -> HybridError {
        HybridError::InRecord {
            record: record.to_owned(),
            window,
            source: Box::new(self),
        }
    }
}

/// An equation as messages quote it: whole up to 80 characters, else its start and its
/// length, so that a runaway equation does not become a runaway message.
fn shorten(equation: &str) -> String {
    const SHOWN: usize = 80;
    let n = equation.chars().count();
    if n <= SHOWN {
        equation.to_owned()
    } else {
        let head: String = equation.chars().take(SHOWN).collect();
        format!("{head}... ({n} characters)")
    }
}
