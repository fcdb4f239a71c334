//! The learned correction, one type for both halves: what a model file stores of it, how
//! it is made from a search, how it predicts `delta_hat` and how it is explained.
//!
//! Both halves learn the same thing: a symbolic model of the physics' error `delta` from
//! feature columns. They differ in what `kind` says (the record half: a symbolic or a zero
//! correction, always added to the latent amplitude; the table half: the form in which the
//! correction enters, [`CorrectionForm`](crate::tables::CorrectionForm)), so the type is
//! generic over the kind and nothing else.

use crate::HybridError;
use crate::explain::{Band, ExplainData, Explanation, ParetoMember};
use hxai_eval::IntervalMethod;
use hxai_symreg::{Model, ModelForms, SelectionReport, Uncertainty};
use hxai_table::Table;
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;

/// How the correction is searched.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Form {
    /// Free-form symbolic regression over every feature ([`hxai_symreg::search()`]).
    #[default]
    Free,
    /// One closed-form factor per column, forward-selected under cross-validation, at most
    /// one interaction ([`hxai_symreg::factors`]): a product of factors for the
    /// multiplicative and log corrections, a sum of terms for the additive one.
    Factors,
    /// No correction: the calibrated physics alone (the hybrid is the physics).
    None,
    /// `none`, `factors` or `free`, chosen by cross-validation on the training rows with
    /// the one-standard-error rule toward the simpler ([`crate::tables::auto`]); the model file says
    /// which (`correction.form`) and how (`correction.choice`).
    Auto,
}

impl Form {
    /// `free`, `factors`, `none` or `auto`.
    pub fn name(self) -> &'static str {
        match self {
            Form::Free => "free",
            Form::Factors => "factors",
            Form::None => "none",
            Form::Auto => "auto",
        }
    }

    /// Parses `free`, `factors`, `none` or `auto`.
    ///
    /// # Errors
    /// [`crate::HybridError::InvalidConfig`] naming the choices.
    pub fn parse(s: &str) -> Result<Self, crate::HybridError> {
        match s.trim().to_ascii_lowercase().as_str() {
            "free" => Ok(Form::Free),
            "factors" | "factor" => Ok(Form::Factors),
            "none" => Ok(Form::None),
            "auto" => Ok(Form::Auto),
            other => Err(crate::HybridError::InvalidConfig(format!(
                "unknown correction form {other:?}: use auto, none, factors or free"
            ))),
        }
    }
}

impl std::fmt::Display for Form {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.name())
    }
}

/// Alternatives of a factor-form correction the report keeps: the selected columns with
/// another shape that the held-out error cannot tell apart, the closest first.
pub const FACTOR_ALTERNATIVES: usize = 3;

/// A factor-form search written as the parts of a search's result ([`factor_search`]).
pub(crate) struct FactorSearch {
    /// The correction.
    pub(crate) model: Model,
    /// How it was selected, with up to [`FACTOR_ALTERNATIVES`] alternatives.
    pub(crate) selection: SelectionReport,
    /// The models it was chosen from: itself, then its alternatives.
    pub(crate) pareto: Vec<Model>,
    /// Its factors, in the order they entered.
    pub(crate) factors: Vec<hxai_symreg::factors::Factor>,
}

/// The factor form's search of `delta` on the feature table `ft`
/// ([`hxai_symreg::factors::fit_factors`]; with `physics`, each row's physics prediction,
/// [`hxai_symreg::factors::fit_factors_on_physics`], which weighs a multiplicative link's
/// rows in the target's units): one adapter for both halves, the records' additive
/// correction and the tables' every link.
///
/// # Errors
/// The factor form's own.
pub(crate) fn factor_search(
    ft: &Table,
    delta: &[f64],
    physics: Option<&[f64]>,
    link: hxai_symreg::factors::Link,
    fc: &hxai_symreg::factors::FactorConfig,
) -> Result<FactorSearch, crate::HybridError> {
    let fit = match physics {
        Some(fp) => hxai_symreg::factors::fit_factors_on_physics(ft, delta, fp, link, fc)?,
        None => hxai_symreg::factors::fit_factors(ft, delta, link, fc)?,
    };
    let alternatives = fit
        .alternatives
        .iter()
        .take(FACTOR_ALTERNATIVES)
        .map(|m| hxai_symreg::Alternative {
            equation: m.equation(),
            sympy: m.sympy(),
            complexity: m.complexity(),
            structure: hxai_symreg::stability::structure_of(m),
            share: None,
            uncertainty: None,
            codelength: None,
        })
        .collect();
    // with `--consensus N`: the share of the N resamples that gave the factor set back
    let share = fit.consensus.as_ref();
    let selection = SelectionReport {
        method: "factors".into(),
        structure: hxai_symreg::stability::structure_of(&fit.model),
        share: share.map(|c| c.agreeing as f64 / c.runs.max(1) as f64),
        runs: share.map(|c| c.runs),
        alternatives,
        error_model: hxai_symreg::ErrorModel::Additive,
        prior: None,
    };
    let mut pareto = vec![fit.model.clone()];
    pareto.extend(fit.alternatives.iter().cloned());
    Ok(FactorSearch {
        model: fit.model,
        selection,
        pareto,
        factors: fit.factors,
    })
}

/// The correction as a model file stores it: its kind, the readable forms and the fitted
/// model with its uncertainty, Pareto front and selection (JSON `correction`).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct CorrectionInfo<K> {
    /// What kind of correction: [`CorrectionKind`](crate::records::CorrectionKind) in a
    /// record model, [`CorrectionForm`](crate::tables::CorrectionForm) in a table model.
    pub kind: K,
    /// The equation's forms, complexity and features (JSON keys `equation`, `sympy`,
    /// `latex`, `complexity`, `features` beside `kind`).
    #[serde(flatten)]
    pub forms: ModelForms,
    /// Feature columns the search was offered (table models; absent in record models,
    /// whose features are the feature map's).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub candidates: Vec<String>,
    /// The fitted symbolic model (`null` for the record half's zero correction; a table
    /// model always has one).
    pub model: Option<Model>,
    /// The model's constants as a template with named parameters, their standard errors
    /// and 95 % intervals, and the covariance prediction intervals use, fitted to `delta`
    /// on the training rows (`hxai_symreg::uncertainty`). Absent for the zero correction
    /// and in files written before it existed.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub uncertainty: Option<Uncertainty>,
    /// The Pareto front of the search the model was chosen from (complexity, training loss
    /// and equation of each member), for `hxai explain`. Absent for the zero correction and
    /// in files written before it was stored.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub pareto: Option<Vec<ParetoMember>>,
    /// How the correction was selected, its structure's share over resamples (consensus or
    /// stability runs) and the alternatives the data cannot tell apart from it
    /// ([`SelectionReport`]); absent in files written before it was stored.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub selection: Option<SelectionReport>,
    /// How the correction was searched: `free` (the search's own expressions), `factors`
    /// (one closed-form factor per column, [`hxai_symreg::factors`]) or `none`; under `auto`
    /// the form it picked. The same text on disk as the `--form` flag; absent in older
    /// files.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub form: Option<Form>,
    /// The factors of a `factors` correction, in the order they entered (JSON `factors`:
    /// `column` or `columns`, `shape`, `equation`, `template`, `complexity`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub factors: Option<Vec<hxai_symreg::factors::Factor>>,
    /// With `--form auto`: each form's cross-validated error, the form picked and the rule
    /// ([`FormChoice`], made by `tables::auto`); absent otherwise.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub choice: Option<FormChoice>,
}

impl<K> CorrectionInfo<K> {
    /// A symbolic model of kind `kind`, with its readable forms and nothing else.
    pub fn symbolic(kind: K, model: Model) -> Self {
        Self {
            kind,
            forms: ModelForms::of(&model),
            candidates: Vec::new(),
            model: Some(model),
            uncertainty: None,
            pareto: None,
            selection: None,
            form: None,
            factors: None,
            choice: None,
        }
    }

    /// The correction a search learned: `model` (the selected one, or it refitted) with the
    /// uncertainty of its constants on the training rows (`features`, `delta`), the front
    /// `pareto` it was chosen from, and how it was selected.
    ///
    /// # Errors
    /// Those of [`Model::uncertainty`].
    pub fn learned(
        kind: K,
        model: Model,
        features: &Table,
        delta: &[f64],
        pareto: &[Model],
        selection: SelectionReport,
    ) -> Result<Self, HybridError> {
        Ok(Self {
            uncertainty: Some(model.uncertainty(features, delta)?),
            pareto: Some(ParetoMember::front(pareto)),
            selection: Some(selection),
            ..Self::symbolic(kind, model)
        })
    }

    /// What a command reports of the correction (`hxai fit --json`'s `correction`): its
    /// forms, its constants and how it was selected.
    pub fn report(&self) -> hxai_symreg::FittedReport {
        hxai_symreg::FittedReport {
            forms: self.forms.clone(),
            constants: self
                .uncertainty
                .as_ref()
                .map(hxai_symreg::ConstantsSummary::of),
            selection: self.selection.clone(),
        }
    }

    /// The fitted model.
    ///
    /// # Errors
    /// [`HybridError::ModelFormat`] for a correction without one (`correction.model` is
    /// missing or `null`).
    pub fn fitted(&self) -> Result<&Model, HybridError> {
        self.model.as_ref().ok_or_else(|| {
            HybridError::ModelFormat("the correction stores no model (`correction.model`)".into())
        })
    }

    /// `delta_hat` for every row of `features` (columns looked up by name): the model's
    /// prediction, or 0 for a correction without a model (the zero correction).
    ///
    /// # Errors
    /// [`HybridError::UnknownFeature`] for a feature the model reads that `features` lacks,
    /// and the model's errors.
    pub fn predict(&self, features: &Table) -> Result<Vec<f64>, HybridError> {
        let Some(model) = &self.model else {
            return Ok(vec![0.0; features.n_rows()]);
        };
        for name in model.features() {
            if features.index_of(&name).is_none() {
                return Err(HybridError::UnknownFeature {
                    name,
                    available: features.names().join(", "),
                });
            }
        }
        if features.n_rows() == 0 {
            return Ok(Vec::new());
        }
        Ok(model.predict(features)?)
    }

    /// The explanation of the correction ([`crate::explain::explain`]): with `data` its
    /// response to each feature it uses and predicted vs true `delta`, with the band
    /// `band` (the correction's prediction intervals by one method); the Pareto front when
    /// the file stores it.
    ///
    /// # Errors
    /// [`HybridError::InvalidConfig`] for a correction without a model (nothing to
    /// explain), and those of [`crate::explain::explain`].
    pub fn explain(
        &self,
        band: Option<(&Band<'_>, IntervalMethod)>,
        data: Option<&ExplainData<'_>>,
        level: f64,
    ) -> Result<Explanation, HybridError> {
        let Some(model) = &self.model else {
            return Err(HybridError::InvalidConfig(
                "the model's correction is zero: there is no equation to explain".into(),
            ));
        };
        crate::explain::explain(model, band, self.pareto.as_deref(), data, "delta", level)
    }
}

/// One form's cross-validated error (JSON `correction.choice.cv.FORM`).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct CvError {
    /// Mean of the hybrid's held-out squared errors (each training row held out once in
    /// `--form auto`; the folds' mean errors in the constants' rule): infinite (JSON
    /// `null`) when a fold's correction has no finite value on a held-out row.
    #[serde(deserialize_with = "null_as_infinity")]
    pub mean: f64,
    /// Its standard error (sample sd of those errors over the square root of their count; infinite, JSON
    /// `null`, with an infinite error or one fold).
    #[serde(deserialize_with = "null_as_infinity")]
    pub se: f64,
}

/// JSON has no infinity: serde_json writes it as `null`; a cross-validated error reads
/// `null` back as infinite.
fn null_as_infinity<'de, D: serde::Deserializer<'de>>(d: D) -> Result<f64, D::Error> {
    Ok(Option::<f64>::deserialize(d)?.unwrap_or(f64::INFINITY))
}

/// How `--form auto` chose (JSON `correction.choice`).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct FormChoice {
    /// Each candidate form's cross-validated error.
    pub cv: BTreeMap<String, CvError>,
    /// The form picked.
    pub picked: String,
    /// The rule, in words.
    pub rule: String,
}

impl FormChoice {
    /// The sentence for a report: the form picked and why.
    pub fn sentence(&self) -> String {
        let cv = |f: &str| {
            self.cv.get(f).map_or_else(
                || "-".to_string(),
                |e| {
                    format!(
                        "{} +- {}",
                        crate::error::num(e.mean.sqrt()),
                        crate::error::num(e.se / (2.0 * e.mean.sqrt().max(f64::MIN_POSITIVE)))
                    )
                },
            )
        };
        let why = if self.picked == "none" {
            "the physics alone is as good as any correction these rows support"
        } else {
            "the simplest form within one standard error of the best"
        };
        format!(
            "correction form: {} ({why}; held-out RMSE none {}, factors {}, free {})",
            self.picked,
            cv("none"),
            cv("factors"),
            cv("free")
        )
    }
}

#[cfg(test)]
mod choice_file {
    #![allow(clippy::unwrap_used)]
    use super::*;

    /// A form whose folds had no finite error is written as `null` and read back as
    /// infinite (a model file with it failed to save once).
    #[test]
    fn an_infinite_cv_error_reads_back() {
        let mut cv = BTreeMap::new();
        cv.insert(
            "free".to_string(),
            CvError {
                mean: f64::INFINITY,
                se: f64::INFINITY,
            },
        );
        cv.insert(
            "none".to_string(),
            CvError {
                mean: 1.5,
                se: 0.25,
            },
        );
        let c = FormChoice {
            cv,
            picked: "none".into(),
            rule: "r".into(),
        };
        let text = serde_json::to_string(&c).unwrap();
        assert!(text.contains("null"), "{text}");
        let back: FormChoice = serde_json::from_str(&text).unwrap();
        assert_eq!(back, c);
    }
}
