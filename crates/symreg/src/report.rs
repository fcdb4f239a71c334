//! What is reported with a selected model, wherever it is shown: its structure (constants
//! ignored, [`crate::stability::structure_of`]), how it was selected, the share of
//! resamples that gave it back when that was measured, and the alternatives the data cannot
//! tell apart from it.
use crate::search::{Criterion, SearchConfig, SearchResult};
use crate::stability::{Stability, structure_of};
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
    }
}
