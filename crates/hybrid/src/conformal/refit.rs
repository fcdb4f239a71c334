//! A fold's refit of a model's constants ([`refit_constants`], [`refit_these`]), kept
//! inside the domain where the model is defined ([`step_within_domain`]).

use hxai_symreg::Model;
use hxai_symreg::eval::Evaluator;
use hxai_symreg::fit::{LmSettings, Unknowns, levenberg_marquardt};
use hxai_symreg::uncertainty::is_exact;

/// Halvings of the step from a model's constants to a fold's refit in [`refit_constants`]
/// before the refit is given up for the model's own constants: 2^-30 of the step is below
/// any constant's rounding.
const MAX_DOMAIN_HALVINGS: usize = 30;

/// `model`'s free constants (those that are not whole or half numbers) refitted by
/// Levenberg-Marquardt to `target` on the columns `cols` (the model's features, in order),
/// starting from the model's own values. When the fit is not finite the model is returned
/// as it is: the held-out predictions then say whether it can be used.
///
/// The refit stays defined wherever the model is on the rows `domain` (the same features on
/// every row the fold models will predict, the held-out ones among them): a refit on part of
/// the rows can move a pole or the edge of a log's domain onto a row it did not see (a
/// correction `log(t/(h - 0.05) + 8)` refitted to `h - 0.056` on a table whose smallest `h`
/// is 0.055). The step from the model's constants to the refit's is then halved until the
/// model is finite on those rows again (only the features are read there, never a
/// target).
pub fn refit_constants(model: &Model, cols: &[&[f64]], target: &[f64], domain: &[&[f64]]) -> Model {
    let free: Vec<usize> = (0..model.params.len())
        .filter(|&i| !is_exact(model.params[i]))
        .collect();
    refit_these(model, &free, cols, target, domain)
}

/// [`refit_constants`] with the constants at the indices `free` refitted, whatever their
/// values (the others stay as they are).
pub fn refit_these(
    model: &Model,
    free: &[usize],
    cols: &[&[f64]],
    target: &[f64],
    domain: &[&[f64]],
) -> Model {
    let mut m = model.clone();
    let mut ev = Evaluator::new(&m.program);
    let settings = LmSettings::new(200, 1e-12);
    let mse = levenberg_marquardt(
        &m.program,
        &mut m.params,
        Unknowns::Free(free),
        cols,
        target,
        &settings,
        &mut ev,
    );
    if !mse.is_finite() {
        return model.clone();
    }
    let n = domain.first().map_or(0, |c| c.len());
    let stepped = step_within_domain(&model.params, &m.params, |params| {
        let mut out = Vec::new();
        ev.predict(&m.program, params, domain, n, &mut out);
        Ok::<_, std::convert::Infallible>(out)
    });
    match stepped {
        Ok(Some(params)) => {
            m.params = params;
            m
        }
        _ => model.clone(),
    }
}

/// The longest step from the constants `from` toward `to` (the whole step, or it halved up
/// to [`MAX_DOMAIN_HALVINGS`] times) whose `predict`ions are finite on every row where those
/// of `from` are; `None` when no step is.
///
/// # Errors
/// `predict`'s own.
pub(crate) fn step_within_domain<E>(
    from: &[f64],
    to: &[f64],
    mut predict: impl FnMut(&[f64]) -> Result<Vec<f64>, E>,
) -> Result<Option<Vec<f64>>, E> {
    let defined: Vec<bool> = predict(from)?.iter().map(|v| v.is_finite()).collect();
    let mut t = 1.0;
    for _ in 0..=MAX_DOMAIN_HALVINGS {
        let params: Vec<f64> = from.iter().zip(to).map(|(a, b)| a + t * (b - a)).collect();
        if predict(&params)?
            .iter()
            .zip(&defined)
            .all(|(v, &d)| v.is_finite() || !d)
        {
            return Ok(Some(params));
        }
        t *= 0.5;
    }
    Ok(None)
}
