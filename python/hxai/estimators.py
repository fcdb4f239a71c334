"""scikit-learn estimators over hxai's symbolic regression and hybrid table models.

The estimators are plain Python classes: their constructor arguments are stored as given
(scikit-learn's rule), checked and sent to the compiled engine as JSON at ``fit``, and the
fitted model is kept as the JSON text the engine writes, so a fitted estimator pickles and
clones like any other.
"""

import json
import re
import warnings

import numpy as np
import pandas as pd
from sklearn.base import BaseEstimator, RegressorMixin
from sklearn.utils.validation import check_is_fitted, validate_data

from . import _hxai
from ._arrays import columns_of, from_bytes, to_bytes
from ._page import write_page

# The engine's default operators (SearchConfig::default()), read from the compiled engine so
# that they cannot drift from it. The constructors' other defaults are written out, for
# reading; tests/test_estimators.py checks that they agree with the engine's.
DEFAULT_OPERATORS = tuple(json.loads(_hxai.defaults("search"))["operators"])

# The paper's operators plus exp (PAPER_OPERATORS): what the tool case's correction searches
# (`hxai fit`, SearchConfig::paper()).
PAPER_OPERATORS = DEFAULT_OPERATORS[:11]

# The law operators (LAW_OPERATORS: arithmetic, exp, log): what a table hybrid's correction
# searches by default (`hxai hybrid fit`, SearchConfig::laws()), read from the engine.
LAW_OPERATORS = tuple(json.loads(_hxai.defaults("table_search"))["operators"])

# `hxai sr` lets the complexity cap grow by this much per input beyond the first; the engine's
# own default (and `hxai hybrid fit`'s) is 0, the paper's fixed cap. SymbolicRegressor takes
# the CLI's value so that it gives `hxai sr`'s result; HybridRegressor the engine's.
SR_COMPLEXITY_PER_INPUT = 2
# `hxai sr`'s rows per candidate's fit (`--max-fit-rows`; the engine's default is 2000):
# the search fits on a seeded sample of this many rows, the reported models on all rows
SR_MAX_FIT_ROWS = 500
# `hxai sr`'s largest candidate (in nodes) given a structure key (`--max-key-nodes`; the
# engine's default, None, keys every candidate): longer ones are fitted without a key
SR_MAX_KEY_NODES = 14

_SEARCH_KEYS = (
    "seed",
    "epochs",
    "max_complexity",
    "complexity_per_input",
    "operator_complexity",
    "operators",
    "strategy",
    "criterion",
    "complexity_penalty",
    "cv_folds",
    "time_limit_s",
    "max_evaluations",
    "affine_inputs",
    "complexity_measure",
    "candidates_per_epoch",
    "max_fit_rows",
    "lm_iterations",
    "random_start",
    "snap_constants",
    "snap_tolerance",
    "named_constants",
    "separability",
    "power_laws",
    "error_model",
    "nesting",
    "consensus_runs",
    "skip_equivalent",
    "max_key_nodes",
    "simplify",
    "runners_up",
    "defined_margin",
    "prior",
)

_CRITERIA = {
    "bic": "bic",
    "aic": "aic",
    "pareto": "pareto_score",
    "pareto_score": "pareto_score",
    "cv": "cv",
    "mdl": "mdl",
}
_RANDOM_STARTS = {"always": "always", "on_failure": "on_failure", "on-failure": "on_failure"}
_STRATEGIES = {
    "combined": "combined",
    "genetic": "genetic",
    "qlattice": "qlattice",
    "random": "random",
}


def _search_json(est):
    """The search settings of an estimator as the engine's JSON object."""
    s = {k: getattr(est, k) for k in _SEARCH_KEYS}
    if s["operators"] is None:
        s["operators"] = list(DEFAULT_OPERATORS)
    elif isinstance(s["operators"], str):
        s["operators"] = [o.strip() for o in s["operators"].split(",")]
    else:
        s["operators"] = list(s["operators"])
    crit = str(s["criterion"]).lower()
    if crit not in _CRITERIA:
        raise ValueError(f"criterion `{s['criterion']}`: use bic, aic, pareto, cv or mdl")
    s["criterion"] = _CRITERIA[crit]
    strat = str(s["strategy"]).lower()
    if strat not in _STRATEGIES:
        raise ValueError(f"strategy `{s['strategy']}`: use combined, genetic, qlattice or random")
    s["strategy"] = _STRATEGIES[strat]
    start = str(s["random_start"]).lower()
    if start not in _RANDOM_STARTS:
        raise ValueError(f"random_start `{s['random_start']}`: use always or on_failure")
    s["random_start"] = _RANDOM_STARTS[start]
    em = str(s["error_model"]).lower()
    if em not in ("auto", "additive", "multiplicative"):
        raise ValueError(
            f"error_model `{s['error_model']}`: use auto, additive or multiplicative"
        )
    s["error_model"] = em
    oc = s["operator_complexity"]
    if oc is None:
        oc = {}
    if not isinstance(oc, dict):
        raise ValueError(f"operator_complexity must be a dict like {{'sqrt': 2}}, got {oc!r}")
    s["operator_complexity"] = {str(k): int(v) for k, v in oc.items()}
    for k in ("seed", "epochs", "max_complexity", "candidates_per_epoch", "max_fit_rows",
              "lm_iterations", "cv_folds", "complexity_per_input"):
        v = s[k]
        if isinstance(v, bool) or not isinstance(v, (int, np.integer)) or v < 0:
            raise ValueError(f"{k} must be a non-negative integer, got {v!r}")
        s[k] = int(v)
    nest = s["nesting"]
    if nest is None:
        nest = "none"
    if not isinstance(nest, (str, dict)):
        raise ValueError(
            f"nesting must be 'none', 'readable', 'strict', rules like 'exp:exp=0' or a dict like "
            f"{{'exp': {{'exp': 0}}}}, got {nest!r}"
        )
    s["nesting"] = nest
    v = s["consensus_runs"]
    if isinstance(v, bool) or not isinstance(v, (int, np.integer)) or v < 0:
        raise ValueError(f"consensus_runs must be a non-negative integer, got {v!r}")
    s["consensus_runs"] = int(v)
    v = s["runners_up"]
    if isinstance(v, bool) or not isinstance(v, (int, np.integer)) or v < 0:
        raise ValueError(f"runners_up must be a non-negative integer, got {v!r}")
    s["runners_up"] = int(v)
    s["skip_equivalent"] = bool(s["skip_equivalent"])
    mk = s["max_key_nodes"]
    if mk is not None:
        if isinstance(mk, bool) or not isinstance(mk, (int, np.integer)) or mk < 0:
            raise ValueError(f"max_key_nodes must be None or a non-negative integer, got {mk!r}")
        s["max_key_nodes"] = int(mk)
    dm = s["defined_margin"]
    if dm is not None:
        if isinstance(dm, bool) or not isinstance(dm, (int, float, np.integer, np.floating)) or not (
            dm >= 0
        ):
            raise ValueError(
                f"defined_margin must be None (no check) or a share >= 0 of each column's "
                f"range, got {dm!r}"
            )
        s["defined_margin"] = float(dm)
    prior = str(s["prior"]).lower()
    if prior not in ("laws", "uniform"):
        raise ValueError(f"prior `{s['prior']}`: use laws or uniform")
    s["prior"] = prior
    s["simplify"] = bool(s["simplify"])
    s["named_constants"] = bool(s["named_constants"])
    s["separability"] = bool(s["separability"])
    if s["max_evaluations"] is not None:
        s["max_evaluations"] = int(s["max_evaluations"])
    for k in ("complexity_penalty", "snap_tolerance"):
        s[k] = float(s[k])
    if s["time_limit_s"] is not None:
        s["time_limit_s"] = float(s["time_limit_s"])
    return json.dumps(s)


def _n_jobs(est):
    """``n_jobs`` checked: None, -1 or a positive int (the engine refuses more than 1024)."""
    n = est.n_jobs
    if n is None:
        return None
    if isinstance(n, bool) or not isinstance(n, (int, np.integer)) or (n < 1 and n != -1):
        raise ValueError(f"n_jobs must be None, -1 (all cores) or a positive integer, got {n!r}")
    return int(n)


def _names(est, n):
    """Column names: the DataFrame's (``feature_names_in_``), else x0, x1, ..."""
    names = getattr(est, "feature_names_in_", None)
    if names is not None:
        return [str(c) for c in names]
    return [f"x{j}" for j in range(n)]


def _params_frame(params):
    """The constants of ``template_``: one row per name, with ``value`` (as printed),
    ``fitted``, ``std_error`` and the 95 % interval ``ci95_lo``/``ci95_hi`` (NaN where the data
    do not determine them)."""
    rows = []
    for name, p in params.items():
        ci = p.get("ci95") or [float("nan"), float("nan")]
        se = p.get("std_error")
        rows.append((name, p["value"], p["fitted"], float("nan") if se is None else se, ci[0], ci[1]))
    frame = pd.DataFrame(rows, columns=["name", "value", "fitted", "std_error", "ci95_lo", "ci95_hi"])
    # p2 before p10: the engine's order, not the JSON map's
    key = frame["name"].str.extract(r"(\d+)$")[0].astype(float)
    return frame.assign(_k=key).sort_values(["_k", "name"]).drop(columns="_k").reset_index(drop=True)


def _pareto_frame(front):
    """The front as a DataFrame; under ``criterion="mdl"`` with each model's two
    codelengths in nats (``structure_nats``, ``parameters_nats``, the engine's
    ``codelength``)."""
    frame = pd.DataFrame(
        {
            "complexity": [m["complexity"] for m in front],
            "loss": [m["loss"] for m in front],
            "equation": [m["equation"] for m in front],
        }
    )
    if front and all("codelength" in m for m in front):
        frame["structure_nats"] = [m["codelength"]["structure"] for m in front]
        frame["parameters_nats"] = [m["codelength"]["parameters"] for m in front]
    return frame


def _interactions(v):
    """``interactions`` checked: a whole number >= 0."""
    if isinstance(v, bool) or not isinstance(v, (int, np.integer)) or v < 0:
        raise ValueError(f"interactions={v!r}: give a whole number >= 0 (default 3)")
    return int(v)


def _monotone_arg(value):
    """``monotone`` as the settings' {column: "+" or "-"}: ``None`` is none; a dict's
    values may be ``"+"``, ``"-"``, ``1`` or ``-1``."""
    if value is None:
        return {}
    if not isinstance(value, dict):
        raise ValueError(
            f"monotone={value!r}: give a dict {{column: '+' or '-'}}, e.g. {{'speed': '+'}}"
        )
    out = {}
    for col, d in value.items():
        sign = {"+": "+", "-": "-", 1: "+", -1: "-"}.get(d if not isinstance(d, bool) else None)
        if sign is None:
            raise ValueError(
                f"monotone[{col!r}] = {d!r}: write '+' (the effect never decreases) or '-' "
                "(never increases)"
            )
        out[str(col)] = sign
    return out


def _search_rows(v):
    """``search_rows`` checked: an integer of at least 100."""
    if isinstance(v, bool) or not isinstance(v, (int, np.integer)) or v < 100:
        raise ValueError(
            f"search_rows must be an integer >= 100 (the sample the correction's structure "
            f"is searched on), got {v!r}"
        )
    return int(v)


def _folds(v):
    """``conformal_folds`` checked: 0 (none) or at least 2."""
    if isinstance(v, bool) or not isinstance(v, (int, np.integer)) or v < 0 or v == 1:
        raise ValueError(
            f"conformal_folds must be 0 (no conformal intervals) or an integer >= 2, got {v!r}"
        )
    return int(v)


_SYMBOL = re.compile(r"Symbol\('((?:[^'\\]|\\.)*)'\)")


def _readable(v):
    """``v`` (a dict, list or text of the model file) with every ``Symbol('name')`` of its
    texts written as the name, for reading: the sympy text wraps a column named like a sympy
    constant (``E``, ``I``, ``S``, ``N``, ``Q``) that way, which is right for sympy and
    noise for a reader. The model's ``sympy_`` keeps it."""
    if isinstance(v, str):
        return _SYMBOL.sub(
            lambda m: m.group(1).encode("latin-1", "backslashreplace").decode("unicode_escape"),
            v,
        )
    if isinstance(v, dict):
        return {k: _readable(x) for k, x in v.items()}
    if isinstance(v, list):
        return [_readable(x) for x in v]
    return v


def _stability_runs(v):
    """``stability_runs`` checked: a whole number of bootstrap resamples, 0 for none."""
    if isinstance(v, bool) or not isinstance(v, (int, np.integer)) or v < 0:
        raise ValueError(
            f"stability_runs must be 0 (not measured) or a positive integer, got {v!r}"
        )
    return int(v)


def _units(units, target_units, names):
    """``units`` and ``target_units`` checked: both ``None``, or a dict of unit texts keyed
    by column names (every key a column) and one unit text. Returns what ``sr_fit`` takes."""
    if units is None and target_units is None:
        return None, None
    if units is None or target_units is None:
        raise ValueError(
            "units and target_units go together: units={column: unit, ...} for every column "
            "and target_units='unit of y'"
        )
    if not isinstance(units, dict):
        raise ValueError(f"units must be a dict from column name to unit text, got {units!r}")
    if not isinstance(target_units, str):
        raise ValueError(f"target_units must be a unit text such as 'm/s', got {target_units!r}")
    pairs = []
    for k, v in units.items():
        if not isinstance(v, str):
            raise ValueError(f"units[{k!r}] must be a unit text such as 'kg*m/s^2', got {v!r}")
        pairs.append((str(k), v))
    return pairs, target_units


def _level(v):
    """An interval level checked: a probability strictly between 0 and 1."""
    if isinstance(v, bool) or not isinstance(v, (int, float, np.floating)) or not 0 < v < 1:
        raise ValueError(f"level must lie strictly between 0 and 1 (e.g. 0.95), got {v!r}")
    return float(v)


_MISSING = ("refuse", "drop", "impute")


def _missing_policy(est):
    policy = str(getattr(est, "missing", "refuse")).lower()
    if policy not in _MISSING:
        raise ValueError(f"missing `{est.missing}`: use refuse, drop or impute")
    return policy


def _target_gaps(est, X, y):
    """Rows whose target is NaN, before scikit-learn's checks (which refuse NaN in ``y``
    outright): refused naming the target under ``missing='refuse'``, else dropped here (and
    counted by ``_missing_fit`` through the returned count)."""
    if y is None:
        return X, y, 0  # scikit-learn's check says that y is required
    try:
        raw = np.asarray(y)
        if raw.dtype.kind == "c":
            return X, y, 0  # scikit-learn's check refuses complex numbers, naming them
        yv = np.asarray(raw, dtype=np.float64).ravel()
    except (TypeError, ValueError):
        return X, y, 0  # not numbers: scikit-learn's check names the problem
    gaps = np.isnan(yv)
    if not gaps.any():
        return X, y, 0
    if _missing_policy(est) == "refuse":
        raise ValueError(
            f"the target has {int(gaps.sum())} empty cell(s) (NaN) of {len(yv)}; hxai refuses "
            "empty cells by default: choose missing='drop' or missing='impute' (either drops "
            "the rows without a target; the target is never filled)"
        )
    keep = ~gaps
    X = X.iloc[keep] if hasattr(X, "iloc") else np.asarray(X)[keep]
    y = y.iloc[keep] if hasattr(y, "iloc") else yv[keep]
    return X, y, int(gaps.sum())


def _missing_fit(est, X, y, names, protected=(), dropped=0):
    """Empty cells (NaN) of the training rows, by ``est.missing`` (``hxai ... --missing``):
    ``refuse`` raises naming the column, its count and the two other choices; ``drop``
    drops every row with a NaN; ``impute`` drops the rows whose target is NaN and fills a
    feature's NaN with its median on the kept rows (never a ``protected`` column's: the
    physics is never given a made-up value). Returns X, y and the report stored as
    ``missing_`` (policy, medians, dropped_rows, filled)."""
    policy = _missing_policy(est)
    X = np.array(X, dtype=np.float64, copy=True)
    y = np.asarray(y, dtype=np.float64)
    xnan, ynan = np.isnan(X), np.isnan(y)
    report = {"policy": policy, "medians": {}, "dropped_rows": 0, "filled": {}}
    gaps = [(n, int(xnan[:, j].sum())) for j, n in enumerate(names) if xnan[:, j].any()]
    if ynan.any():
        gaps.append(("the target", int(ynan.sum())))
    if policy == "refuse" and gaps:
        n, k = gaps[0]
        raise ValueError(
            f"column `{n}` has {k} empty cell(s) (NaN) of {len(y)}; hxai refuses empty cells "
            "by default: choose missing='drop' (drop the rows with an empty cell) or "
            "missing='impute' (fill a feature's empty cells with its training median)"
        )
    for j, n in enumerate(names):
        if policy != "refuse" and xnan[:, j].all():
            raise ValueError(f"column `{n}` is empty (NaN) in every row: leave it out")
    keep = ~(xnan.any(axis=1) | ynan) if policy == "drop" else ~ynan
    if not keep.any():
        raise ValueError(f"missing='{policy}': every row has an empty cell, no row is left")
    X, y = X[keep], y[keep]
    report["dropped_rows"] = int((~keep).sum()) + dropped
    if policy == "impute":
        for j, n in enumerate(names):
            col = X[:, j]
            empty = np.isnan(col)
            if n in protected:
                if empty.any():
                    raise ValueError(
                        f"column `{n}` has {int(empty.sum())} empty cell(s) and feeds the "
                        "physics, which is never given a made-up value: use missing='drop' "
                        "or fill the cells"
                    )
                continue
            m = float(np.median(col[~empty]))
            report["medians"][n] = m
            if empty.any():
                X[:, j] = np.where(empty, m, col)
                report["filled"][n] = int(empty.sum())
    if report["dropped_rows"]:
        warnings.warn(
            f"missing='{policy}': dropped {report['dropped_rows']} row(s) with an empty cell",
            UserWarning,
            stacklevel=3,
        )
    for n, k in report["filled"].items():
        warnings.warn(
            f"missing='impute': filled {k} empty cell(s) of `{n}` with its training median "
            f"{report['medians'][n]:.6g}",
            UserWarning,
            stacklevel=3,
        )
    return X, y, report


def _per_class_spec(spec):
    """``calibrate_per`` as ``(column, [parameters])``: from ``"COL=P1,P2"`` (as
    ``--calibrate-per``) or ``(COL, [P1, P2])``; ``None`` stays ``None``."""
    if spec is None:
        return None
    if isinstance(spec, str):
        column, sep, params = spec.partition("=")
        params = [p.strip() for p in params.split(",") if p.strip()]
    else:
        try:
            column, params = spec
        except (TypeError, ValueError):
            column, sep, params = "", "", []
        else:
            sep = "="
            params = [params] if isinstance(params, str) else [str(p) for p in params]
    column = str(column).strip()
    if not sep or not column or not params:
        raise ValueError(
            f"calibrate_per={spec!r}: give 'COLUMN=P1,P2' or ('COLUMN', ['P1', 'P2']): the "
            "text column, then the physics parameters fitted once per level of it"
        )
    return column, params


# The command line's flags and the estimator's keywords, longest flag first (so that
# `--calibrate-per` is not read as `--calibrate`).
_KEYWORDS = [
    ("--calibrate-per", "calibrate_per="),
    ("--correction-per", "correction_per="),
    ("--conformal-folds", "conformal_folds="),
    ("--search-rows", "search_rows="),
    ("--max-complexity", "max_complexity="),
    ("--monotone", "monotone="),
    ("--interactions", "interactions="),
    ("--periodic", "periodic="),
    ("--shapes", "shapes="),
    ("--stability", "stability_runs="),
    ("--calibrate", "calibrate="),
    ("--correction", "correction="),
    ("--features", "features="),
    ("--exclude", "exclude="),
    ("--missing", "missing="),
    ("--epochs", "epochs="),
    ("--joint", "joint="),
    ("--init", "init="),
    ("--form", "form="),
    ("--set", "set="),
]
_FLAG = re.compile(
    "|".join(re.escape(f) + r"(?![A-Za-z-])" for f, _ in _KEYWORDS)
)


def _speak_python(message):
    """An engine message with the command line's flags (``--init``) written as the
    estimator's keywords (``init=``)."""
    words = dict(_KEYWORDS)
    return _FLAG.sub(lambda m: words[m.group(0)], message)


class _python_words:
    """Re-raises the engine's ``ValueError`` with the estimator's keywords for its flags."""

    def __enter__(self):
        return self

    def __exit__(self, kind, err, tb):
        if kind is ValueError and err is not None:
            text = _speak_python(str(err))
            if text != str(err):
                raise ValueError(text) from None
        return False


def _is_row_numbers(name, values):
    """Whether a first column is a row number a CSV writer added: named ``rownames``,
    ``Unnamed: 0``, ``index`` or nothing, holding 1..n or 0..n-1."""
    if str(name).strip().lower() not in ("", "rownames", "unnamed: 0", "index"):
        return False
    v = pd.to_numeric(pd.Series(values), errors="coerce").to_numpy(dtype=np.float64)
    n = len(v)
    return n > 1 and (
        np.array_equal(v, np.arange(1, n + 1)) or np.array_equal(v, np.arange(n))
    )


def _row_numbers_left_out(est, X, fitting):
    """``X`` without a first column that is a row number (``rownames``, unnamed, 1..n): it is
    no setting of the process, so it is left out of the features, with a warning at ``fit``
    (``row_number_column_`` names it; ``predict`` leaves it out again)."""
    if not hasattr(X, "columns") or X.shape[1] < 2:
        return X
    first = X.columns[0]
    if fitting:
        est.row_number_column_ = None
        if _is_row_numbers(first, X.iloc[:, 0]):
            est.row_number_column_ = str(first)
            warnings.warn(
                f"the first column `{first}` holds the row numbers 1..n (or 0..n-1), not a "
                "setting of the process: left out of the features (drop it to silence this)",
                UserWarning,
                stacklevel=3,
            )
    skip = getattr(est, "row_number_column_", None)
    if skip is not None and str(first) == skip:
        return X.drop(columns=[first])
    return X


def _refuse_text_columns(X):
    """A DataFrame column of text or categories, named, with what to do (the engine needs
    numbers; numpy's own message was "could not convert string to float: 'B'")."""
    if not hasattr(X, "columns"):
        return
    for c in X.columns:
        col = X[c]
        if pd.api.types.is_numeric_dtype(col) or pd.api.types.is_bool_dtype(col):
            continue
        numeric = pd.to_numeric(col, errors="coerce")
        bad = col[numeric.isna() & col.notna()]
        if len(bad):
            raise ValueError(
                f"column `{c}` holds text ({bad.iloc[0]!r} in row {bad.index[0]!r}): give its "
                f"levels their own constants with calibrate_per='{c}=P1,...' (or "
                f"correction_per='{c}'), or drop the column"
            )


def _comparison_frame(text):
    """The JSON of a comparison as a tidy DataFrame (see ``HybridRegressor.compare``)."""
    doc = json.loads(text)
    cv = {c["name"]: c for c in doc.get("cv", [])}
    p = {t["baseline"]: t.get("p_value") for t in doc.get("t_tests", [])}
    rows = []
    for m in doc["models"]:
        c = cv.get(m["name"])
        k = len(c["r2_folds"]) if c else 0
        rows.append(
            {
                "model": m["name"],
                "rmse": m["rmse"],
                "r2": m["r2"],
                "mae": m["mae"],
                "cv_r2_mean": c["r2_mean"] if c else np.nan,
                "cv_r2_se": c["r2_sd"] / np.sqrt(k) if c and k > 0 else np.nan,
                "cv_rmse_mean": c["rmse_mean"] if c else np.nan,
                "p_value": np.nan if p.get(m["name"]) is None else p[m["name"]],
            }
        )
    frame = pd.DataFrame(rows)
    frame.attrs["json"] = text
    frame.attrs["split"] = doc.get("split")
    frame.attrs["hybrid_over_best_black_box"] = doc.get("hybrid_over_best_black_box")
    return frame


def _with_ebm(frame, names, X, y, seed):
    """The comparison ``frame`` with InterpretML's Explainable Boosting Machine (a glass
    box; ``interpret``'s ``ExplainableBoostingRegressor``, defaults, ``random_state=seed``)
    as the row ``ebm``: trained on the split's training rows over the black boxes' columns
    (the physics' columns and the correction's candidates), scored on its test rows, with
    the paired t-test of the hybrid against it; the comparison's JSON in
    ``frame.attrs["json"]`` gains it among its ``models`` (so ``report(compare=frame)``
    shows it). Where ``interpret`` is not installed the frame is returned as it is and
    ``frame.attrs["ebm"]`` says so (issue 68)."""
    try:
        from interpret.glassbox import ExplainableBoostingRegressor
    except ImportError:
        frame.attrs["ebm"] = (
            "not run: the interpret package is not installed (pip install interpret-core)"
        )
        return frame
    doc = json.loads(frame.attrs["json"])
    model = doc["hybrid"]
    cols = list(dict.fromkeys(model["physics"]["columns"] + model["correction"]["candidates"]))
    idx = [names.index(c) for c in cols if c in names]
    tr, te = model["split"]["train"], model["split"]["test"]
    if not idx or not te:
        frame.attrs["ebm"] = "not run: no test rows or no column for it"
        return frame
    X = np.asarray(X, dtype=np.float64)
    y = np.asarray(y, dtype=np.float64)
    ebm = ExplainableBoostingRegressor(random_state=int(seed))
    ebm.fit(X[np.ix_(tr, idx)], y[tr])
    pred = ebm.predict(X[np.ix_(te, idx)])
    yt = y[te]
    err = pred - yt
    rmse = float(np.sqrt(np.mean(err**2)))
    sst = float(np.sum((yt - yt.mean()) ** 2))
    from .table import predict_table

    p_value = np.nan
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            hybrid = predict_table(pd.DataFrame(X[te], columns=names), json.dumps(model))
        d = err**2 - (np.asarray(hybrid["hybrid"], dtype=np.float64) - yt) ** 2
    except ValueError:
        # a model with constants per level reads level columns that X no longer holds
        d = np.zeros(0)
    if len(d) > 1 and np.std(d) > 0:
        from scipy.stats import ttest_1samp

        p_value = float(ttest_1samp(d, 0.0).pvalue)
    row = {
        "model": "ebm",
        "rmse": rmse,
        "r2": 1.0 - float(np.sum(err**2)) / sst if sst > 0 else np.nan,
        "mae": float(np.mean(np.abs(err))),
        "cv_r2_mean": np.nan,
        "cv_r2_se": np.nan,
        "cv_rmse_mean": np.nan,
        "p_value": p_value,
    }
    hyb = frame.index[frame["model"] == "hybrid"]
    at = int(hyb[0]) if len(hyb) else len(frame)
    out = pd.concat(
        [frame.iloc[:at], pd.DataFrame([row]), frame.iloc[at:]], ignore_index=True
    )
    out.attrs.update(frame.attrs)
    # the comparison's JSON gains the row too, so that report(compare=frame) shows it
    names_in = [m["name"] for m in doc["models"]]
    at_json = names_in.index("hybrid") if "hybrid" in names_in else len(names_in)
    doc["models"].insert(
        at_json, {"name": "ebm", "rmse": row["rmse"], "r2": row["r2"], "mae": row["mae"]}
    )
    out.attrs["json"] = json.dumps(doc)
    out.attrs["ebm"] = (
        f"interpret's ExplainableBoostingRegressor (defaults, random_state={int(seed)}) on "
        f"the split's {len(tr)} training rows over {', '.join(cols)}; not cross-validated"
    )
    return out


def compare(X, y, physics, test_fraction=0.2, folds=5, **settings):
    """``HybridRegressor(physics, **settings).compare(X, y, test_fraction, folds)``: every
    way of modelling ``y`` on the same split, as a tidy DataFrame (see
    :meth:`HybridRegressor.compare`)."""
    return HybridRegressor(physics, **settings).compare(
        X, y, test_fraction=test_fraction, folds=folds
    )


def _columns_arg(v, name):
    """A keyword that names columns (a list, or one name as text)."""
    if v is None:
        return []
    if isinstance(v, str):
        return [v]
    try:
        return list(v)
    except TypeError:
        raise ValueError(f"{name}={v!r}: give a list of column names") from None


def _space_text(space):
    """A dict design space as ``suggest_experiments``' text: ``{col: (lo, hi)}`` or ``(lo,
    hi, step)`` a range, ``[a, b, c]`` levels, a text like ``"45:89"`` as written, a single
    number or word a fixed setting; anything else is refused with how to write it."""
    parts = []
    for col, v in space.items():
        if isinstance(v, str):
            parts.append(f"{col}={v}")
        elif isinstance(v, tuple) and len(v) in (2, 3) and all(
            isinstance(x, (int, float, np.integer, np.floating)) and not isinstance(x, bool)
            for x in v
        ):
            parts.append(f"{col}=" + ":".join(repr(float(x)) for x in v))
        elif isinstance(v, (list, np.ndarray)) and len(v) > 0:
            parts.append(f"{col}=" + "|".join(str(x) for x in v))
        elif isinstance(v, (int, float, np.integer, np.floating)) and not isinstance(v, bool):
            parts.append(f"{col}={float(v)!r}")
        else:
            raise ValueError(
                f"space[{col!r}] = {v!r}: give a range as a tuple (lo, hi) or (lo, hi, step), "
                "levels as a list [a, b, c], one setting as a number, or the text form "
                "'lo:hi'"
            )
    return ",".join(parts)


def _level_cells(X, columns):
    """``X`` without the level ``columns`` (a DataFrame's), and each column's cells as text
    ({column: cells}; an empty cell or NaN as ``""``, which the engine refuses naming the
    row)."""
    if not columns:
        return X, {}
    for column in columns:
        if not hasattr(X, "columns") or column not in list(X.columns):
            raise ValueError(
                f"the model has constants per level of `{column}`: give X as a DataFrame with "
                "that column (its levels as text or numbers)"
            )
    cells = {
        c: ["" if pd.isna(v) else str(v).strip() for v in X[c].tolist()] for c in columns
    }
    return X.drop(columns=list(columns)), cells


def _missing_predict(est, X, names):
    """NaN in rows to predict: filled with the training medians when the estimator was
    fitted with ``missing='impute'``; otherwise refused, naming the column (a prediction is
    one value per row, so no row is dropped here)."""
    nan = np.isnan(X)
    if not nan.any():
        return X
    report = getattr(est, "missing_", None) or {}
    medians = report.get("medians", {})
    X = np.array(X, dtype=np.float64, copy=True)
    for j, n in enumerate(names):
        if not nan[:, j].any():
            continue
        if report.get("policy") != "impute" or n not in medians:
            raise ValueError(
                f"column `{n}` has {int(nan[:, j].sum())} empty cell(s) (NaN) in the rows to "
                "predict; only an estimator fitted with missing='impute' fills them (with "
                "the training medians), and only in its feature columns"
            )
        X[:, j] = np.where(nan[:, j], medians[n], X[:, j])
    return X


class _SearchParams:
    """Search settings shared by both estimators (defaults: hxai's ``SearchConfig``)."""

    def _set_search(self, loc):
        for k in _SEARCH_KEYS:
            setattr(self, k, loc[k])
        self.n_jobs = loc["n_jobs"]

    def __sklearn_tags__(self):
        # NaN in X is an empty cell: refused unless missing='drop' or 'impute' says what to
        # do with it (_missing_fit).
        tags = super().__sklearn_tags__()
        tags.input_tags.allow_nan = str(getattr(self, "missing", "refuse")).lower() != "refuse"
        return tags

    def _repr_mimebundle_(self, **kwargs):
        # Jupyter asks for the mime bundle before `_repr_html_`, and scikit-learn's puts its
        # estimator diagram there: a fitted estimator shows its card instead (unfitted, the
        # diagram of its settings).
        bundle = super()._repr_mimebundle_(**kwargs)
        card = self._repr_html_()
        if card is not None:
            bundle["text/html"] = card
        return bundle


class SymbolicRegressor(_SearchParams, RegressorMixin, BaseEstimator):
    """Symbolic regression (``hxai sr``) as a scikit-learn regressor.

    Parameters are the engine's search settings with ``hxai sr``'s defaults (seed 42, 10
    epochs of 1000 candidates, complexity at most 10 plus 2 per input beyond the first,
    selection by description length ``criterion="mdl"``, ``nesting="strict"``,
    ``power_laws=True``, ``missing="refuse"``). ``fit`` takes a
    DataFrame (its column names become the equation's names) or an array (names x0, x1...).

    Fitted attributes: ``equation_`` (4 significant digits, for reading), ``sympy_`` (full
    precision, sympy-parseable), ``latex_``, ``complexity_``, ``features_`` (columns used),
    ``pareto_`` (DataFrame: complexity, loss = training MSE, equation; under
    ``criterion="mdl"`` also ``structure_nats`` and ``parameters_nats``, each model's two
    codelengths under the prior), ``template_`` (the
    equation with its fitted constants named ``p0``, ``p1``, ...) and ``params_`` (DataFrame:
    name, value, fitted, std_error, ci95_lo, ci95_hi), ``model_json_`` (the
    model as the engine serialises it), ``evaluations_``, ``simplified_`` (reported models
    returned in the shorter form the algebra proves them equal to; ``simplify=False`` keeps
    the search's programs), ``selection_`` (how the equation
    was selected, its structure's share over resamples and the alternatives the data cannot
    tell apart), ``stability_`` (with ``stability_runs=N``: the search rerun on N bootstrap
    resamples, ``{runs, features, structures, r2}`` as ``hxai sr --stability N``; else
    ``None``), ``dimensional_groups_`` (with ``units``: the dimensionless groups searched on,
    else ``None``), ``n_features_in_`` and, from a DataFrame, ``feature_names_in_``.

    ``units`` (a dict from every column name to its unit, e.g. ``{"m": "kg", "v": "m/s"}``)
    with ``target_units`` (the unit of ``y``, e.g. ``"J"``) turns on dimensional analysis as
    ``hxai sr --units``: the columns are reduced to dimensionless groups (Buckingham pi), the
    search runs on those, and the equation is consistent in its units by construction.

    ``separability=True`` (the default, as ``hxai sr``'s) runs AI Feynman's tools: the
    most accurate model tested for a sum or product of parts, a pair of columns that enters
    only as their difference, ratio, product or sum, and a column that enters as a power,
    the smaller problems searched apart; and a polynomial of ``1/y``, ``y**2``, ``1/y**2``,
    ``sqrt(y)`` or ``log(y)`` on searches of up to three columns. ``False`` leaves them out
    (about a quarter less CPU time, fewer laws recovered: docs/benchmarks.md).

    ``random_start="always"`` (the default, as ``hxai sr``'s) fits each new candidate from
    its canonical start and from a seeded random start and keeps the better fit;
    ``"on_failure"`` uses the random start only when the canonical one gives no finite
    loss (a fifth less time, two fewer laws at 1 % noise on the AI Feynman 100:
    docs/benchmarks.md).

    ``prior="laws"`` (``"uniform"`` on ``HybridRegressor``; ``hxai sr --prior``, ``hxai
    hybrid --prior``): the prior over structures the description length
    (``criterion="mdl"``) charges by, learned from 726 written laws (testdata/laws/): a
    power, a product or an exponential of a ratio is cheap, a tanh, a cosine or a Gaussian
    dear; ``"uniform"`` charges every operator alike. Under ``criterion="cv"`` the
    one-standard-error rule picks, among the models it cannot tell apart, the shortest
    description under ``"laws"`` and the lowest complexity under ``"uniform"``; BIC, AIC
    and Pareto do not read it.

    ``defined_margin=0.1`` (both estimators): no model with a pole, a log of a value
    <= 0 or another blow-up within the training box widened by this share of each column's
    range (proven by interval arithmetic during the search); ``None`` turns the check off.

    ``max_key_nodes=N`` (``hxai sr --max-key-nodes N``) computes the structure key (the
    canonical form, to skip a candidate whose structure was fitted before) only for
    candidates of at most N nodes (inputs, constants and operators) and fits longer ones
    without one; ``None`` keys every candidate (``--max-key-nodes all``), ``0`` none. The
    default, 14 (``hxai sr``'s), took about a fifth less CPU time than ``None`` on the AI
    Feynman 100 and recovered as many laws; 10 took 40 % less and recovered 2 fewer at
    noise 0 and 4 fewer at 1 % (docs/benchmarks.md, "Keys for the short programs only").

    ``power_laws=True`` (``hxai sr``'s default; ``--no-power-laws`` turns it off) offers
    selection closed-form factor models of the target: a product ``C * x1**a * x2**b ...``
    and a sum of one-column terms, the power with a fitted exponent first. ``nesting`` is
    ``"strict"`` by default: no transcendental function inside another (except a power
    ``exp(a*log(x))``) and ``sin``/``cos`` only of a sum of inputs; ``"none"`` was the
    default before issue 47 (docs/benchmarks.md, "Laws in small real tables").

    ``error_model="auto"`` (``hxai sr --error-model``) lets the criterion read the scatter
    of a positive target as additive (one size on every row) or multiplicative (in
    proportion to the value), whichever is likelier for the best model under each; then a
    power law over decades (brain against body mass) is judged on every row instead of its
    largest few. The constants are least-squares fits either way. ``"additive"`` was the
    rule before; ``"multiplicative"`` forces it (a target that is not positive is refused).

    ``n_jobs`` is the number of threads of the search: ``None`` (the default) uses every
    core (the engine's shared thread pool, sized by ``RAYON_NUM_THREADS`` if set), ``-1``
    every core in a pool of its own, a positive int that many threads. It is chosen per
    estimator and never changes the result.

    The result is identical to ``hxai sr --csv TABLE --target y`` for the same seed, settings
    and data (the CLI's defaults are these).
    """

    def __init__(
        self,
        *,
        seed=42,
        epochs=10,
        max_complexity=10,
        complexity_per_input=SR_COMPLEXITY_PER_INPUT,
        operator_complexity=None,
        operators=DEFAULT_OPERATORS,
        strategy="combined",
        criterion="mdl",
        complexity_penalty=1.0,
        cv_folds=5,
        time_limit_s=None,
        max_evaluations=None,
        affine_inputs=True,
        complexity_measure="features_plus_operators",
        candidates_per_epoch=1000,
        max_fit_rows=SR_MAX_FIT_ROWS,
        lm_iterations=25,
        random_start="always",
        snap_constants=True,
        snap_tolerance=1e-3,
        named_constants=True,
        separability=True,
        power_laws=True,
        error_model="auto",
        nesting="strict",
        consensus_runs=0,
        skip_equivalent=True,
        max_key_nodes=SR_MAX_KEY_NODES,
        simplify=True,
        runners_up=0,
        defined_margin=0.1,
        prior="laws",
        conformal_folds=5,
        stability_runs=0,
        units=None,
        target_units=None,
        missing="refuse",
        n_jobs=None,
    ):
        self._set_search(locals())
        self.missing = missing
        self.conformal_folds = conformal_folds
        self.stability_runs = stability_runs
        self.units = units
        self.target_units = target_units

    def fit(self, X, y):
        """Searches for an equation of ``y`` over the columns of ``X``. Returns ``self``."""
        settings = _search_json(self)
        X, y, dropped = _target_gaps(self, X, y)
        X, y = validate_data(
            self, X, y, dtype=np.float64, y_numeric=True, ensure_all_finite=False
        )
        names = _names(self, X.shape[1])
        X, y, self.missing_ = _missing_fit(self, X, y, names, dropped=dropped)
        folds = _folds(self.conformal_folds)
        runs = _stability_runs(self.stability_runs)
        units, target_units = _units(self.units, self.target_units, names)
        doc = json.loads(
            _hxai.sr_fit(
                (names, columns_of(X), to_bytes(y, "y")),
                settings,
                _n_jobs(self),
                folds,
                runs,
                (units, target_units),
            )
        )
        best = doc["best"]
        self.model_json_ = best["model"]
        self.equation_ = best["equation"]
        self.sympy_ = best["sympy"]
        self.latex_ = best["latex"]
        self.complexity_ = best["complexity"]
        self.features_ = list(best["features"])
        self.pareto_ = _pareto_frame(doc["pareto"])
        self.template_ = best["template"]
        self.params_ = _params_frame(best["params"])
        self.evaluations_ = doc["evaluations"]
        self.simplified_ = doc["simplified"]
        self.selection_ = _readable(doc["selection"])
        self.stability_ = _readable(doc.get("stability"))
        self.dimensional_groups_ = doc.get("dimensional_groups")
        self.uncertainty_json_ = json.dumps(doc["uncertainty"])
        conf = doc.get("conformal")
        self.conformal_json_ = "" if conf is None else json.dumps(conf)
        if folds and conf is None:
            warnings.warn(
                "no conformal calibration, predict_interval falls back to the delta method: "
                + str(doc.get("conformal_error")),
                stacklevel=2,
            )
        return self

    def _repr_html_(self):
        """A compact card in a notebook: the equation as MathML with its text, its
        complexity and constants with standard errors (unfitted: the parameters)."""
        if not hasattr(self, "model_json_"):
            return None
        import html

        rows = "".join(
            f"<tr><th scope='row'>{html.escape(str(r['name']))}</th><td>{r['value']}</td>"
            f"<td>{'' if pd.isna(r['std_error']) else format(r['std_error'], '.4g')}</td></tr>"
            for _, r in self.params_.iterrows()
        )
        target = html.escape(getattr(self, "target_name_", None) or "y")
        return (
            "<div class='hxai-card'><math display='block'><mrow><mi mathvariant='normal'>"
            f"{target}</mi><mo>=</mo>{_hxai.sr_mathml(self.model_json_)}</mrow></math>"
            f"<pre>{html.escape(self.equation_)}</pre><p>complexity {self.complexity_}, "
            f"{self.evaluations_} models evaluated</p>"
            "<table><thead><tr><th scope='col'>constant</th><th scope='col'>value</th>"
            f"<th scope='col'>standard error</th></tr></thead><tbody>{rows}</tbody></table></div>"
        )

    def predict_interval(self, X, level=0.95, method=None):
        """Prediction intervals at ``level`` on the rows of ``X``: an array of shape
        ``(n, 2)``, lower and upper bound. ``method`` is ``"conformal"`` (CV+ over
        ``conformal_folds`` random folds of the training rows, the equation's constants
        refitted per fold, scores scaled by a line in the prediction; the default),
        ``"split"`` (split conformal on the first fold) or ``"delta"`` (the delta method with
        a constant residual variance). The conformal guarantee holds for rows exchangeable
        with the training rows and the selected structure fixed; ``interval_method_`` names
        the method used."""
        check_is_fitted(self, "model_json_")
        X = validate_data(self, X, dtype=np.float64, reset=False, ensure_all_finite=False)
        names = _names(self, X.shape[1])
        X = _missing_predict(self, X, names)
        lo, hi, used = _hxai.sr_intervals(
            (self.model_json_, self.uncertainty_json_, self.conformal_json_),
            (names, columns_of(X)),
            _level(level),
            method,
        )
        self.interval_method_ = used
        return np.column_stack([from_bytes(lo), from_bytes(hi)])

    def predict(self, X):
        """The equation's values on the rows of ``X`` (same columns as in ``fit``)."""
        check_is_fitted(self, "model_json_")
        X = validate_data(self, X, dtype=np.float64, reset=False, ensure_all_finite=False)
        names = _names(self, X.shape[1])
        X = _missing_predict(self, X, names)
        return from_bytes(_hxai.sr_predict(self.model_json_, names, columns_of(X)))


class HybridRegressor(_SearchParams, RegressorMixin, BaseEstimator):
    """A hybrid of a physics equation and a symbolic correction (``hxai hybrid fit``,
    docs/hybrid-tables.md) as a scikit-learn regressor.

    ``physics`` is infix text over the columns of ``X`` and named parameters: a name is a
    column if ``X`` has it, else a parameter, which must be calibrated (``calibrate``,
    starting values ``init``, default 1) or fixed (``set``). ``correction`` is ``additive``
    (``y = f_p + delta``), ``multiplicative`` (``y = f_p (1 + delta)``) or ``log``
    (``y = f_p exp(delta)``, ``delta`` found on the log scale: for scatter that grows with
    the quantity and for power-law corrections; ``y`` and the physics must be positive); ``delta`` is found
    by symbolic regression on ``features`` (default: every column not in ``exclude``) with
    the search settings. ``form="auto"`` (the default) chooses among ``"none"`` (the
    calibrated physics alone), ``"factors"`` and ``"free"`` by 3-fold cross-validation on
    the training rows with the one-standard-error rule toward the simpler (``choice_``:
    each form's held-out error, the form picked and the rule; a pick of ``"none"`` is also
    a warning). In the free form a term whose constant's 95 % interval spans 0 is dropped
    and the rest refitted when the 5-fold error does not rise by more than one standard
    error (each drop is in ``warnings_``). ``form="factors"`` searches the correction as one closed-form
    factor per column instead (power, linear, exponential, logarithm, pole, saturation, one
    harmonic on a ``periodic`` column;
    kept only where it lowers the cross-validated error; at most one two-column
    interaction): a product of factors for the multiplicative and log corrections, a sum of
    terms for the additive one; its factors are in ``factors_``. ``periodic`` names the
    columns an engineer knows repeat (a spindle angle, a time of day): only these may carry
    a harmonic, and without it no correction has a sine or cosine (``--periodic``). No
    correction has a pole, a log of a value <= 0 or another blow-up within the training
    box widened by 10 % of each column's range (proven by interval arithmetic, issue 64).
    ``joint`` refits physics
    parameters and correction constants together. ``fit`` uses every row it is given
    (split before, as with any estimator).

    Fitted attributes: ``physics_parameters_`` {name: value}, ``physics_standard_errors_``,
    ``hybrid_equation_`` (4 digits), ``hybrid_sympy_`` (full precision), ``hybrid_latex_``,
    the correction's ``equation_``, ``sympy_``, ``latex_``, ``complexity_``, ``features_``,
    ``warnings_`` (the fit's warnings, each also raised as a ``UserWarning``: a column that
    nearly copies the target, a physics that changes sign under a multiplicative
    correction, a correction no better than the physics in cross-validation, constants
    spanning 0 that were kept, residuals that break the delta intervals' assumptions;
    docs/bad-input.md), ``selection_`` and ``stability_`` (with
    ``stability_runs=N``, as ``hxai hybrid fit --stability N``; the shares in ``selection_``
    are then the resamples') and ``model_json_`` (the model file of ``hxai hybrid
    fit``, readable by ``hxai hybrid predict``). ``predict_parts(X)`` returns physics, correction, hybrid and
    ``outside_training``.

    ``calibrate_per="COL=P1,P2"`` (or ``("COL", ["P1", "P2"])``), as ``hxai hybrid fit
    --calibrate-per``: the physics parameters ``P1``, ``P2`` are fitted once per level of the
    column ``COL`` of ``X`` (a DataFrame; the levels as text or numbers), ``physics_parameters_``
    then holds ``P1[level]``; the column is not a feature of the correction, and ``predict``
    needs it too, refusing a level the fit never saw. ``correction_per="COL"``, as ``hxai
    hybrid fit --correction-per``: the correction's structure is shared and its constants are
    refitted on each level's rows (the model file's ``correction_per``); ``predict`` needs the
    column, and ``predict_interval`` is refused for such a model.

    ``n_jobs`` is the number of threads of the fit, as on :class:`SymbolicRegressor`
    (``None``, the default: every core; ``-1``: every core in a pool of its own; a positive
    int: that many); it never changes the result.

    ``monotone`` (issue 68), as ``hxai hybrid fit --monotone``: a dict {column: ``"+"``
    or ``"-"``} (``1`` and ``-1`` too): the correction's effect of that column never
    decreases (``+``) or increases (``-``) over its training range, in every factor and
    pair of the factor form (``form="auto"`` then chooses between none and factors, and
    ``form="free"`` is refused). ``shapes``, as ``--shapes``: the factor form's shapes,
    ``"classic"`` (the default), ``"all"`` (with the hinge ``x + |x - k|``, the smooth
    step ``tanh(w x + c)`` and the saturating power ``1/(1 + k x^q)``) or a comma-separated
    list of names. ``interactions`` (default 3), as ``--interactions``: the most
    two-column factors, each kept only where it lowers the held-out error by more than two
    paired standard errors.

    ``search_rows`` (default 2000), as ``hxai hybrid fit --search-rows``: on more training
    rows, the correction's structure (the form ``auto``'s choice, the search, the conformal
    and stability refits) is found on a sample of this many, stratified on the target; the
    physics' calibration and the correction's constants use every row (the model file's
    ``search_sample``).
    """

    def __init__(
        self,
        physics="",
        *,
        calibrate=(),
        init=None,
        set=None,
        correction="additive",
        form="auto",
        features=None,
        exclude=(),
        periodic=(),
        monotone=None,
        shapes="classic",
        interactions=3,
        joint=False,
        seed=42,
        epochs=10,
        max_complexity=10,
        complexity_per_input=0,
        operator_complexity=None,
        operators=LAW_OPERATORS,
        strategy="combined",
        criterion="cv",
        complexity_penalty=1.0,
        cv_folds=5,
        time_limit_s=None,
        max_evaluations=None,
        affine_inputs=True,
        complexity_measure="features_plus_operators",
        candidates_per_epoch=1000,
        max_fit_rows=2000,
        lm_iterations=25,
        random_start="always",
        snap_constants=True,
        snap_tolerance=1e-3,
        named_constants=False,
        separability=False,
        power_laws=False,
        error_model="additive",
        nesting="readable",
        consensus_runs=0,
        skip_equivalent=True,
        max_key_nodes=None,
        simplify=True,
        runners_up=3,
        defined_margin=0.1,
        prior="uniform",
        conformal_folds=5,
        stability_runs=0,
        missing="refuse",
        calibrate_per=None,
        correction_per=None,
        n_jobs=None,
        search_rows=2000,
    ):
        self.conformal_folds = conformal_folds
        self.search_rows = search_rows
        self.stability_runs = stability_runs
        self.missing = missing
        self.calibrate_per = calibrate_per
        self.correction_per = correction_per
        self.physics = physics
        self.calibrate = calibrate
        self.init = init
        self.set = set
        self.correction = correction
        self.form = form
        self.features = features
        self.exclude = exclude
        self.periodic = periodic
        self.monotone = monotone
        self.shapes = shapes
        self.interactions = interactions
        self.joint = joint
        self._set_search(locals())

    def _target_name(self, y, names):
        name = getattr(y, "name", None)
        name = name if isinstance(name, str) and name else "y"
        if name in names:
            raise ValueError(
                f"the target `{name}` is also a column of X: drop it from X or rename it"
            )
        return name

    def fit(self, X, y):
        """Calibrates the physics on ``(X, y)`` and learns its correction. Returns ``self``."""
        names, target, X, y, settings, n_jobs = self._prepare(X, y)
        with _python_words():
            text = _hxai.table_fit(
                names + [target], columns_of(X) + [to_bytes(y, "y")], json.dumps(settings), n_jobs
            )
        return self._fitted(text, target)

    def compare(self, X, y, test_fraction=0.2, folds=5):
        """Every way of modelling ``y`` on the same split, as ``hxai hybrid compare``: the
        physics as given, calibrated, symbolic regression without physics, physics + random
        forest, gradient boosting and this hybrid, on a seeded random split of ``(X, y)``
        (``test_fraction`` held out, stratified by a ``calibrate_per``/``correction_per``
        column) and over ``folds`` folds (0: none). Returns a tidy DataFrame, one row per
        model: ``model``, ``rmse``, ``r2``, ``mae`` (test rows), ``cv_r2_mean``,
        ``cv_r2_se`` (standard error over the folds), ``cv_rmse_mean``, ``p_value`` (paired
        t-test of the hybrid against it on the test rows; NaN for the hybrid, and where the
        test is undefined). Where ``interpret`` is installed, InterpretML's Explainable
        Boosting Machine is a row ``ebm`` beside the black boxes (test rows only; its
        settings in ``.attrs["ebm"]``, which says so where it is not installed). The
        comparison's JSON is in ``.attrs["json"]``; ``report(compare=
        frame)`` takes the frame. The estimator itself is not refitted."""
        if isinstance(folds, bool) or not isinstance(folds, (int, np.integer)) or folds < 0 or folds == 1:
            raise ValueError(f"folds={folds!r}: give 0 (none) or a whole number >= 2")
        if not (isinstance(test_fraction, (int, float)) and 0 < test_fraction < 1):
            raise ValueError(f"test_fraction={test_fraction!r}: give a number between 0 and 1")
        fitted = {k: v for k, v in vars(self).items() if k.endswith("_") and not k.startswith("__")}
        try:
            names, target, X, y, settings, n_jobs = self._prepare(X, y)
        finally:
            # _prepare records what fit needs (level columns, row numbers): keep the fitted
            # estimator's own
            for k in [k for k in vars(self) if k.endswith("_") and k not in fitted]:
                delattr(self, k)
            vars(self).update(fitted)
        with _python_words():
            text = _hxai.table_compare(
                names + [target],
                columns_of(X) + [to_bytes(y, "y")],
                json.dumps(settings),
                float(test_fraction),
                int(folds),
                n_jobs,
            )
        return _with_ebm(_comparison_frame(text), names, X, y, self.seed)

    def _prepare(self, X, y):
        """The checked settings and columns of a fit (or a comparison) on ``(X, y)``:
        ``(names, target, X, y, settings, n_jobs)``."""
        if not isinstance(self.physics, str) or not self.physics.strip():
            raise ValueError("physics: give the physics equation as text, e.g. 'k*f^2/(32*r)'")
        if self.correction not in ("additive", "multiplicative", "log"):
            raise ValueError(
                f"correction `{self.correction}`: use additive, multiplicative or log"
            )
        if self.form not in ("auto", "none", "free", "factors"):
            raise ValueError(f"form `{self.form}`: use auto, none, free or factors")
        search = json.loads(_search_json(self))
        n_jobs = _n_jobs(self)
        X, y, dropped = _target_gaps(self, X, y)
        per_class = _per_class_spec(self.calibrate_per)
        if self.correction_per is not None and (
            not isinstance(self.correction_per, str) or not self.correction_per.strip()
        ):
            raise ValueError(
                f"correction_per={self.correction_per!r}: give the name of the text column "
                "whose levels get their own correction constants"
            )
        level_columns = []
        if per_class is not None:
            level_columns.append(per_class[0])
        if self.correction_per is not None and self.correction_per.strip() not in level_columns:
            level_columns.append(self.correction_per.strip())
        X = _row_numbers_left_out(self, X, fitting=True)
        X, cells = _level_cells(X, level_columns)
        _refuse_text_columns(X)
        if level_columns and _missing_policy(self) == "drop" and np.isnan(
            np.asarray(X, dtype=np.float64)
        ).any():
            raise ValueError(
                "calibrate_per or correction_per with missing='drop' and empty cells in X is "
                "not supported: drop the rows with NaN first (the level column must keep its rows)"
            )
        self.level_columns_ = level_columns
        y_in = y
        X, y = validate_data(
            self, X, y, dtype=np.float64, y_numeric=True, ensure_all_finite=False
        )
        names = _names(self, X.shape[1])
        target = self._target_name(y_in, names)
        physics_names = set(re.findall(r"[A-Za-z_][A-Za-z0-9_]*", self.physics))
        X, y, self.missing_ = _missing_fit(
            self, X, y, names, protected=[n for n in names if n in physics_names], dropped=dropped
        )
        settings = {
            "target": target,
            "physics": self.physics,
            "calibrate": [str(c) for c in self.calibrate],
            "init": {str(k): float(v) for k, v in (self.init or {}).items()},
            "set": {str(k): float(v) for k, v in (self.set or {}).items()},
            "features": None if self.features is None else [str(c) for c in self.features],
            "exclude": [str(c) for c in self.exclude],
            "periodic": [str(c) for c in _columns_arg(self.periodic, "periodic")],
            "monotone": _monotone_arg(self.monotone),
            "shapes": str(self.shapes),
            "interactions": _interactions(self.interactions),
            "correction": self.correction,
            "form": self.form,
            "joint": bool(self.joint),
            "conformal_folds": _folds(self.conformal_folds),
            "search_rows": _search_rows(self.search_rows),
            "stability_runs": _stability_runs(self.stability_runs),
            "search": search,
        }
        if per_class is not None:
            settings["calibrate_per"] = {
                "column": per_class[0],
                "parameters": per_class[1],
                "cells": cells[per_class[0]],
            }
        if self.correction_per is not None:
            column = self.correction_per.strip()
            settings["correction_per"] = {"column": column, "cells": cells[column]}
        return names, target, X, y, settings, n_jobs

    def _fitted(self, text, target):
        """Records the model file ``text`` of a fit (of the target named ``target``) and its
        attributes; returns ``self``."""
        doc = json.loads(text)
        self.model_json_ = text
        self.target_ = target
        self.physics_parameters_ = dict(doc["physics"]["parameters"])
        self.physics_standard_errors_ = dict(doc["physics"]["standard_errors"])
        self.hybrid_equation_ = doc["hybrid"]["equation"]
        self.hybrid_sympy_ = doc["hybrid"]["sympy"]
        self.hybrid_latex_ = doc["hybrid"]["latex"]
        corr = doc["correction"]
        self.equation_ = corr["equation"]
        self.sympy_ = corr["sympy"]
        self.latex_ = corr["latex"]
        self.complexity_ = corr["complexity"]
        self.features_ = list(corr["features"])
        self.selection_ = _readable(corr.get("selection"))
        self.choice_ = corr.get("choice")
        self.form_ = corr.get("form")
        self.factors_ = corr.get("factors")
        # the learned slots of the physics (`f(C)` in `A*exp(-E/T)*f(C)`): what each became
        self.slots_ = list(doc.get("slots", []))
        self.stability_ = _readable(doc.get("stability"))
        # the traps of the fit (a column copying the target, a physics that changes sign
        # under a multiplicative correction, ...): kept and raised as UserWarning
        self.warnings_ = list(doc.get("warnings", []))
        for w in self.warnings_:
            warnings.warn(w, UserWarning, stacklevel=2)
        return self

    def _levels(self, X):
        """``X`` without the level columns of ``calibrate_per`` and ``correction_per``, and
        their cells ({column: cells}; ``None`` for a model without per-level constants)."""
        X = _row_numbers_left_out(self, X, fitting=False)
        columns = getattr(self, "level_columns_", None) or []
        if not columns:
            _refuse_text_columns(X)
            return X, None
        X, cells = _level_cells(X, columns)
        _refuse_text_columns(X)
        return X, cells

    def _parts(self, X):
        check_is_fitted(self, "model_json_")
        X, levels = self._levels(X)
        X = validate_data(self, X, dtype=np.float64, reset=False, ensure_all_finite=False)
        names = _names(self, X.shape[1])
        X = _missing_predict(self, X, names)
        *parts, warned = _hxai.table_predict(self.model_json_, names, columns_of(X), levels)
        # rows beside the data, predictions of a sign the training target never had
        for w in warned:
            warnings.warn(w, UserWarning, stacklevel=3)
        return parts

    def predict(self, X):
        """The hybrid's values on the rows of ``X`` (a ``UserWarning`` names rows beside the
        data and predictions of a sign the training target never had)."""
        return from_bytes(self._parts(X)[2])

    def predict_interval(self, X, level=0.95, method=None):
        """Prediction intervals of the hybrid at ``level`` on the rows of ``X``: an array of
        shape ``(n, 2)``, lower and upper bound. ``method`` is ``"conformal"`` (CV+ over
        ``conformal_folds`` folds of the training rows, the hybrid's constants refitted per
        fold, scores scaled by a line in the prediction and on the log scale for the
        multiplicative and log forms; the default), ``"split"`` (split conformal on the
        first fold) or ``"delta"`` (the delta method with a constant residual variance), as
        ``hxai hybrid predict --interval-method``. ``interval_method_`` names the method
        used."""
        check_is_fitted(self, "model_json_")
        X, levels = self._levels(X)
        X = validate_data(self, X, dtype=np.float64, reset=False, ensure_all_finite=False)
        names = _names(self, X.shape[1])
        X = _missing_predict(self, X, names)
        lo, hi, used = _hxai.table_intervals(
            self.model_json_, names, columns_of(X), _level(level), method, levels
        )
        self.interval_method_ = used
        return np.column_stack([from_bytes(lo), from_bytes(hi)])

    def _repr_html_(self):
        """A compact card in a notebook: the hybrid as MathML with its text, the calibrated
        parameters with their 95 % intervals, the scores (unfitted: the parameters)."""
        if not hasattr(self, "model_json_"):
            return None
        return _hxai.table_card(self.model_json_)

    def report(self, path, X=None, y=None, compare=None):
        """Writes the HTML page of ``hxai report`` for the fitted model to ``path`` (through a
        temporary file and a rename, never over an existing file that is not HTML): with
        ``X`` and ``y``, the correction's figures drawn on those rows; ``compare``, the JSON
        text (or dict) of ``hxai hybrid compare --json``. Returns the path."""
        check_is_fitted(self, "model_json_")
        names = columns = levels = None
        if X is not None:
            if y is None:
                raise ValueError("report: give y with X (the figures compare the model with it)")
            X, levels = self._levels(X)
            X = validate_data(self, X, dtype=np.float64, reset=False, ensure_all_finite=False)
            names = _names(self, X.shape[1])
            X = _missing_predict(self, X, names)
            yv = np.asarray(y, dtype=np.float64).ravel()
            names = names + [self.target_]
            columns = columns_of(X) + [to_bytes(yv, "y")]
        if isinstance(compare, pd.DataFrame):
            if "json" not in compare.attrs:
                raise ValueError(
                    "report(compare=...): this DataFrame is not one returned by compare() (its "
                    ".attrs['json'] is gone); pass that frame, or the JSON of hxai hybrid compare"
                )
            compare = compare.attrs["json"]
        if isinstance(compare, dict):
            compare = json.dumps(compare)
        return write_page(
            path, _hxai.table_report(self.model_json_, names, columns, levels, compare)
        )

    def suggest_experiments(self, space, n, goal="discriminate", seed=42):
        """The settings of the next ``n`` runs, as ``hxai hybrid design`` (issue 49): ``space``
        is ranges as text (``"f=0.05:0.3,r=0.4:1.2:0.4"``, ``:step`` for levels, ``a|b`` for a
        list; or the same as a dict, ``{"f": (0.05, 0.3), "r": (0.4, 1.2, 0.4), "tool": ["A",
        "B"]}``: a tuple is a range, a list levels, a number one setting), ``tool=A|B`` for the text levels of a model fitted with ``calibrate_per`` or
        ``correction_per``) or a DataFrame of feasible settings (its rows are the only
        candidates; a level column as text or numbers); it must give every column the model
        reads. ``goal`` is ``"discriminate"`` (where the
        selected correction and its alternatives disagree most; ``precision`` when there is
        none, ``coverage`` without a covariance either), ``"coverage"`` (widest interval first, then the farthest from the runs
        picked) or ``"precision"`` (Ds-optimal for the physics parameters, the correction's
        constants as nuisance parameters: the runs that narrow their joint interval most,
        from the model's covariance). Returns a DataFrame: the settings, ``predicted``, ``spread``, ``reason``."""
        check_is_fitted(self, "model_json_")
        if isinstance(space, dict):
            space = _space_text(space)
        if isinstance(space, str):
            text = _hxai.table_design(self.model_json_, space, None, int(n), goal, int(seed))
        else:
            frame = pd.DataFrame(space)
            level_columns = [
                c for c in (getattr(self, "level_columns_", None) or []) if c in frame.columns
            ]
            frame, levels = _level_cells(frame, level_columns)
            cols = [str(c) for c in frame.columns]
            X = np.asarray(frame, dtype=np.float64)
            text = _hxai.table_design(
                self.model_json_, None, (cols, columns_of(X)), int(n), goal, int(seed),
                levels or None,
            )
        doc = json.loads(text)
        out = pd.DataFrame(doc["settings"], columns=doc["columns"])
        for column, cells in doc.get("text", {}).items():
            out[column] = cells
        out["predicted"] = doc["predicted"]
        out["spread"] = doc["spread"]
        out["reason"] = doc["reason"]
        out.attrs["goal"] = doc["goal"]
        return out

    def predict_parts(self, X):
        """A DataFrame with the columns physics, correction, hybrid and
        ``outside_training`` (1 where a column of the row lies outside its training range by
        more than 10 % of the range's width, else 0), as ``hxai hybrid predict`` writes."""
        p, c, h, o = self._parts(X)
        return pd.DataFrame(
            {
                "physics": from_bytes(p),
                "correction": from_bytes(c),
                "hybrid": from_bytes(h),
                "outside_training": from_bytes(o).astype(np.int64),
            }
        )
