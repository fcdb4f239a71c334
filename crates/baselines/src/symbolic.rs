//! The symbolic-regression model of `hxai-symreg` behind the [`Regressor`] trait.

use crate::matrix::{check_fit, check_predict};
use crate::{BaselineError, Regressor};
use hxai_symreg::{Model, SearchConfig, SearchResult, Table};
use std::borrow::Cow;

/// Adapter over [`hxai_symreg::search()`]: `fit` runs the search on the columns of `x`
/// (under the table's names unless [`SymbolicRegressor::with_names`] renames them) and keeps
/// the best model; `predict` evaluates its equation.
#[derive(Debug, Clone)]
pub struct SymbolicRegressor {
    /// Search settings (default: the paper's, seed 42, 10 epochs).
    pub config: SearchConfig,
    names: Option<Vec<String>>,
    result: Option<SearchResult>,
    fitted: Option<usize>,
}

impl Default for SymbolicRegressor {
    fn default() -> Self {
        Self::new(SearchConfig::paper())
    }
}

impl SymbolicRegressor {
    /// An unfitted model with the given search settings.
    pub fn new(config: SearchConfig) -> Self {
        Self {
            config,
            names: None,
            result: None,
            fitted: None,
        }
    }

    /// Uses `names` for the feature columns (so equations read `f1`, `f6`, ...).
    pub fn with_names(mut self, names: Vec<String>) -> Self {
        self.names = Some(names);
        self
    }

    /// The best model found (after `fit`).
    pub fn model(&self) -> Option<&Model> {
        self.result.as_ref().map(|r| &r.best)
    }

    /// The whole search result (best model, Pareto front, evaluations, seconds).
    pub fn result(&self) -> Option<&SearchResult> {
        self.result.as_ref()
    }

    /// `x` under the names the equation uses: itself, or a renamed copy.
    fn named<'a>(&self, x: &'a Table) -> Result<Cow<'a, Table>, BaselineError> {
        match &self.names {
            None => Ok(Cow::Borrowed(x)),
            Some(n) if n.as_slice() == x.names() => Ok(Cow::Borrowed(x)),
            Some(n) if n.len() == x.n_cols() => {
                Ok(Cow::Owned(Table::new(n.clone(), x.columns().to_vec())?))
            }
            Some(n) => Err(BaselineError::FeatureCount {
                fitted: n.len(),
                got: x.n_cols(),
            }),
        }
    }
}

impl Regressor for SymbolicRegressor {
    fn name(&self) -> &str {
        "symbolic"
    }

    fn fit(&mut self, x: &Table, y: &[f64]) -> Result<(), BaselineError> {
        check_fit(x, y)?;
        let data = self.named(x)?;
        let result = hxai_symreg::search(&data, y, &self.config, &mut |_| {})
            .map_err(|e| BaselineError::Symbolic(e.to_string()))?;
        self.result = Some(result);
        self.fitted = Some(x.n_cols());
        Ok(())
    }

    fn predict(&self, x: &Table) -> Result<Vec<f64>, BaselineError> {
        check_predict(self.name(), self.fitted, x)?;
        let model = self.model().ok_or_else(|| BaselineError::NotFitted {
            model: "symbolic".into(),
        })?;
        let data = self.named(x)?;
        model
            .predict(&data)
            .map_err(|e| BaselineError::Symbolic(e.to_string()))
    }
}
