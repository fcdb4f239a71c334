//! What is reported with a selected model, wherever it is shown: its structure (constants
//! ignored, [`crate::stability::structure_of`]), how it was selected, the share of
//! resamples that gave it back when that was measured, and the alternatives the data cannot
//! tell apart from it.
use crate::canonical::structure_of;
use crate::search::{Criterion, SearchConfig, SearchResult};
use crate::stability::Stability;
use serde::{Deserialize, Serialize};

/// A model's readable forms, the keys every report of a model starts with (model files'
/// `correction`, `hxai sr --json`'s `best` and front, `hxai fit --json`, the Python
/// estimators' summaries): the equation as plain text (4 significant digits), as sympy
/// text (full precision, reproduces `predict`) and as LaTeX, its complexity and the
/// features it uses. Embedded in the larger shapes with `#[serde(flatten)]`, so the keys
/// stay where they were.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct ModelForms {
    /// Plain-text equation.
    pub equation: String,
    /// sympy-parseable equation.
    pub sympy: String,
    /// LaTeX equation.
    pub latex: String,
    /// Complexity (features + operators).
    pub complexity: usize,
    /// Features the equation uses.
    pub features: Vec<String>,
}

impl ModelForms {
    /// The forms of `model`.
    pub fn of(model: &crate::Model) -> Self {
        Self {
            equation: model.equation(),
            sympy: model.sympy(),
            latex: model.latex(),
            complexity: model.complexity(),
            features: model.features(),
        }
    }

    /// The forms of the zero model (`0`, complexity 0, no features).
    pub fn zero() -> Self {
        Self {
            equation: "0".into(),
            sympy: "0".into(),
            latex: "0".into(),
            complexity: 0,
            features: Vec::new(),
        }
    }
}

/// A model as a search's report shows it (`hxai sr --json`'s `best` and `pareto`, the
/// Python `sr_fit`'s): its forms, its loss and scores on the rows, the model itself, and
/// for the selected model its constants with their standard errors.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct ModelSummary {
    /// Equation, sympy, LaTeX, complexity, features.
    #[serde(flatten)]
    pub forms: ModelForms,
    /// Mean squared error on the training rows (`null` when unknown).
    pub loss: f64,
    /// R² on the rows it was scored on (`null` when its prediction is not finite there).
    pub r2: Option<f64>,
    /// Root mean squared error on the same rows (`null` likewise).
    pub rmse: Option<f64>,
    /// The model as JSON text ([`crate::Model::from_json`] reads it back).
    pub model: String,
    /// The constants (keys `template`, `params`, `dof`, `residual_variance`, `reason`
    /// beside the others); absent unless asked for ([`ModelSummary::with_constants`]).
    #[serde(flatten)]
    pub constants: Option<ConstantsSummary>,
    /// Its description length in nats, structure and constants, under the search's prior
    /// (`--criterion mdl` only; absent otherwise).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub codelength: Option<crate::prior::Codelengths>,
}

/// A model's constants as a template with named parameters, each with its standard error
/// and 95 % interval (the parts of [`crate::Uncertainty`] a reader wants; prediction
/// intervals need the rest).
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct ConstantsSummary {
    /// sympy text over the columns and the parameter names.
    pub template: String,
    /// Each parameter with its estimate, in template order (a JSON object).
    #[serde(with = "crate::uncertainty::ordered_map")]
    pub params: Vec<(String, crate::ParamEstimate)>,
    /// Residual degrees of freedom.
    pub dof: usize,
    /// The residual variance of the fit.
    pub residual_variance: f64,
    /// Why standard errors are `null` (`null` when they are given).
    pub reason: Option<String>,
}

impl ModelSummary {
    /// The summary of `model`, scored on `data` against `y`.
    ///
    /// # Errors
    /// [`crate::SrError`] when the model cannot be evaluated on `data` (a missing column).
    pub fn of(
        model: &crate::Model,
        data: &crate::Table,
        y: &[f64],
    ) -> Result<Self, crate::SrError> {
        let scores = hxai_eval::score(y, &model.predict(data)?).ok();
        Ok(Self {
            forms: ModelForms::of(model),
            loss: model.train_mse,
            r2: scores.map(|s| s.r2),
            rmse: scores.map(|s| s.rmse),
            model: model.to_json(),
            constants: None,
            codelength: None,
        })
    }

    /// The summary with the model's constants from `unc` (its uncertainty on the rows).
    pub fn with_constants(mut self, unc: &crate::Uncertainty) -> Self {
        self.constants = Some(ConstantsSummary::of(unc));
        self
    }
}

impl ConstantsSummary {
    /// The reader's part of `unc`.
    pub fn of(unc: &crate::Uncertainty) -> Self {
        Self {
            template: unc.template.clone(),
            params: unc.params.clone(),
            dof: unc.dof,
            residual_variance: unc.residual_variance,
            reason: unc.reason.clone(),
        }
    }
}

/// A fitted correction as a command reports it (`hxai fit --json`'s `correction`): its
/// forms, its constants (when it has any) and how it was selected.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct FittedReport {
    /// Equation, sympy, LaTeX, complexity, features.
    #[serde(flatten)]
    pub forms: ModelForms,
    /// `template`, `params`, `dof`, `residual_variance`, `reason` (absent without
    /// constants).
    #[serde(flatten)]
    pub constants: Option<ConstantsSummary>,
    /// How it was selected (`null` when not recorded).
    pub selection: Option<SelectionReport>,
}

/// What a search reports (`hxai sr --json`, and the Python `sr_fit` with more beside it):
/// the selected model, how it was selected, the Pareto front, the search's counts and, when
/// measured, the stability of its structure.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct SearchReport {
    /// The selected model, with its constants.
    pub best: ModelSummary,
    /// How it was selected and what else the data supports.
    pub selection: SelectionReport,
    /// The Pareto front by increasing complexity (each with its constants when asked for).
    pub pareto: Vec<ModelSummary>,
    /// Models fitted.
    pub evaluations: u64,
    /// Candidates whose structure had been fitted before ([`SearchResult`]).
    pub duplicate_structures: u64,
    /// Reported models returned in a shorter form ([`SearchResult::simplified`]).
    pub simplified: u64,
    /// Wall time of the search, s.
    pub seconds: f64,
    /// Bootstrap stability of the structure (absent unless measured).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub stability: Option<Stability>,
    /// With units given, the dimensionless groups searched on and the target's scale
    /// ([`crate::units::Reduction::describe`]); absent otherwise.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub dimensional_groups: Option<Vec<String>>,
    /// What the user should know about the result: fewer than [`crate::FEW_ROWS`] rows
    /// (absent when empty).
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub warnings: Vec<String>,
}

/// The warning a search on `rows` rows carries when they are fewer than
/// [`crate::FEW_ROWS`]: every candidate had at most `rows - 2` constants, and the law is
/// pinned down by very few points.
pub fn few_rows_warning(rows: usize) -> Option<String> {
    (rows < crate::FEW_ROWS).then(|| {
        format!(
            "only {rows} rows: models were limited to at most {} fitted constants; with so \
             few points, check the equation against more measurements",
            rows.saturating_sub(2)
        )
    })
}

impl SearchReport {
    /// The report of `result` (a search with `cfg` of `y` on `data`), its best model's
    /// constants from `best_uncertainty` (the caller's [`crate::Model::uncertainty`] of it,
    /// which it usually needs too, so it is not computed twice); `front_constants` also
    /// gives every front member its constants. The selection's shares are the stability
    /// runs' when `stability` is given.
    ///
    /// # Errors
    /// [`crate::SrError`] when a model cannot be evaluated on `data`.
    pub fn of(
        result: &SearchResult,
        cfg: &SearchConfig,
        (data, y): (&crate::Table, &[f64]),
        best_uncertainty: &crate::Uncertainty,
        front_constants: bool,
        stability: Option<Stability>,
    ) -> Result<Self, crate::SrError> {
        let summary = |m: &crate::Model, constants: bool| -> Result<ModelSummary, crate::SrError> {
            let s = ModelSummary::of(m, data, y)?;
            Ok(if constants {
                s.with_constants(&m.uncertainty(data, y)?)
            } else {
                s
            })
        };
        let mut selection = SelectionReport::of(result, cfg);
        if let Some(st) = &stability {
            selection = selection.with_stability(st);
        }
        // under the description length, each model's two codelengths: what it was charged
        let symbols = cfg.operators.len() + data.n_cols();
        let codelength = |m: &crate::Model| {
            (cfg.criterion == Criterion::Mdl)
                .then(|| crate::prior::Codelengths::of(m, cfg.prior, symbols, (data, y)))
                .flatten()
        };
        for (a, m) in selection.alternatives.iter_mut().zip(&result.alternatives) {
            a.codelength = codelength(m);
        }
        let mut best = ModelSummary::of(&result.best, data, y)?.with_constants(best_uncertainty);
        best.codelength = codelength(&result.best);
        Ok(Self {
            best,
            selection,
            pareto: result
                .pareto
                .iter()
                .map(|m| {
                    summary(m, front_constants).map(|mut s| {
                        s.codelength = codelength(m);
                        s
                    })
                })
                .collect::<Result<_, _>>()?,
            evaluations: result.evaluations,
            duplicate_structures: result.duplicate_structures,
            simplified: result.simplified,
            seconds: result.seconds,
            stability,
            dimensional_groups: None,
            warnings: few_rows_warning(y.len()).into_iter().collect(),
        })
    }
}

/// Most alternatives a [`SelectionReport`] lists.
pub const MAX_ALTERNATIVES: usize = 3;

/// One model that fits as well as the selected one.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Alternative {
    /// Plain-text equation.
    pub equation: String,
    /// sympy-parseable equation.
    pub sympy: String,
    /// Complexity.
    pub complexity: usize,
    /// Its structure, every constant written `c`.
    pub structure: String,
    /// Share of the consensus runs (or, once measured, of the stability runs) that gave
    /// this structure back; `null` when neither ran.
    pub share: Option<f64>,
    /// Its constants' covariance on the rows it was fitted on, where the fit stored it (a
    /// hybrid's correction, for `hxai hybrid design`'s weighting by each equation's own
    /// prediction variance); absent otherwise.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub uncertainty: Option<crate::Uncertainty>,
    /// Its description length in nats, structure and constants, under the search's prior
    /// (a search's report under `--criterion mdl` only; absent otherwise).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub codelength: Option<crate::prior::Codelengths>,
}

/// How the model was selected and what else the data supports (JSON `selection`).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct SelectionReport {
    /// `bic`, `aic`, `pareto`, `cv` (the criterion of one search) or `consensus`.
    pub method: String,
    /// The selected model's structure, every constant written `c`.
    pub structure: String,
    /// Share of resamples that gave this structure back: of the consensus runs, or of the
    /// stability runs once measured ([`SelectionReport::with_stability`]); `null` otherwise.
    pub share: Option<f64>,
    /// Bootstrap runs the share is over (`null` with the share).
    pub runs: Option<usize>,
    /// Up to three models whose cross-validated loss is within one standard error of the
    /// lowest ("the data cannot tell these apart"), simplest first.
    pub alternatives: Vec<Alternative>,
    /// How the criterion read the target's scatter ([`crate::ErrorModel`],
    /// `--error-model`): written only when `multiplicative`; absent means additive (and
    /// files written before it read as additive, and are written back unchanged).
    #[serde(default, skip_serializing_if = "crate::ErrorModel::is_additive")]
    pub error_model: crate::ErrorModel,
    /// The prior over structures the criterion read (`laws` or `uniform`,
    /// [`crate::Prior`]): written only under the `mdl` and `cv` criteria, the two that read
    /// it.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub prior: Option<String>,
}

impl SelectionReport {
    /// The report of a search run with `cfg`.
    pub fn of(result: &SearchResult, cfg: &SearchConfig) -> Self {
        let consensus = result.consensus.as_ref();
        let share_in = |key: &str| {
            consensus.map(|c| {
                c.nominated
                    .iter()
                    .find(|s| s.template == key)
                    .map_or(0.0, |s| s.share)
            })
        };
        let alternatives = result
            .alternatives
            .iter()
            .take(MAX_ALTERNATIVES)
            .map(|m| {
                let structure = structure_of(m);
                Alternative {
                    equation: m.equation(),
                    sympy: m.sympy(),
                    complexity: m.complexity(),
                    share: share_in(&structure),
                    structure,
                    uncertainty: None,
                    codelength: None,
                }
            })
            .collect();
        let method = if consensus.is_some() {
            "consensus".to_string()
        } else {
            criterion_name(cfg.criterion).to_string()
        };
        Self {
            method,
            structure: structure_of(&result.best),
            share: consensus.map(|c| c.share),
            runs: consensus.map(|c| c.runs),
            alternatives,
            error_model: result.error_model,
            prior: matches!(cfg.criterion, Criterion::Mdl | Criterion::CrossValidation)
                .then(|| cfg.prior.name().to_string()),
        }
    }

    /// The shares measured by a stability run (selection's own, and each alternative's),
    /// replacing any consensus share: the stability runs rerun the whole selection.
    pub fn with_stability(mut self, st: &Stability) -> Self {
        let share = |key: &str| {
            st.structures
                .iter()
                .find(|s| s.template == key)
                .map_or(0.0, |s| s.share)
        };
        self.share = Some(share(&self.structure));
        self.runs = Some(st.runs);
        for a in &mut self.alternatives {
            a.share = Some(share(&a.structure));
        }
        self
    }
}

/// The serialised name of a criterion (as `--criterion` spells it).
pub fn criterion_name(c: Criterion) -> &'static str {
    match c {
        Criterion::Bic => "bic",
        Criterion::Aic => "aic",
        Criterion::ParetoScore => "pareto",
        Criterion::CrossValidation => "cv",
        Criterion::Mdl => "mdl",
    }
}
