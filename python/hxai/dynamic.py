"""Grey-box dynamic models (``hxai dynamic``, docs/dynamic.md) as a Python class.

:class:`DynamicRegressor` takes a long DataFrame, one row per sample of one or more runs,
with a time column, the measured states and the inputs (held from one sample to the next).
``fit`` calibrates the engineer's ODE through its trajectories and learns a correction term
inside the derivative; ``predict`` simulates each run from its first reading; ``compare``
scores the physics, the calibrated physics, the hybrid and a NARX gradient boosting by
free-run error on held-out runs. Results equal the command line's for the same settings.
"""

import json

import pandas as pd

from . import _hxai
from ._arrays import frame_columns, from_bytes
from ._page import write_page

_FORMS = ("auto", "none", "factors", "free")


def _list(x, what):
    if x is None:
        return []
    if isinstance(x, str):
        return [x]
    try:
        return [str(v) for v in x]
    except TypeError:
        raise ValueError(f"{what}: give a column name or a list of them") from None


def _numbers(d, what):
    out = {}
    for k, v in (d or {}).items():
        try:
            out[str(k)] = float(v)
        except (TypeError, ValueError):
            raise ValueError(f"{what}[{k!r}] = {v!r}: not a number") from None
    return out


class DynamicRegressor:
    """The engineer's ODE, calibrated, with a learned correction inside the derivative.

    Parameters mirror ``hxai dynamic fit``: ``ode`` (``"T' = (q*n^1.5 - h*(T - Ta))/C"``,
    ``;`` between states), ``states``, ``time``, ``run`` (None: one run), ``inputs``,
    ``calibrate`` (parameter names), ``init`` and ``set`` ({name: value}), ``correction``
    (``"additive"`` or ``"multiplicative"``), ``form`` (``"auto"``, ``"none"``,
    ``"factors"``, ``"free"``), ``initial`` (``"first"`` or ``"estimate"``), ``periodic``,
    ``smooth`` (samples in the derivatives' window), ``seed`` and ``conformal_folds``.

    After ``fit``: ``model_json_`` (the model file's text, as ``hxai dynamic fit --out``
    writes it), ``equation_`` (the hybrid ODE), ``parameters_`` (the hybrid's physics
    parameters), ``physics_parameters_`` (the calibrated physics alone: value, standard
    error, 95 % interval), ``corrections_`` ({state: equation}) and ``warnings_``.
    """

    def __init__(self, ode, states, time, run=None, inputs=(), calibrate=(), init=None,
                 set=None, correction="additive", form="auto", initial="first",
                 periodic=(), smooth=9, seed=42, conformal_folds=5):
        self.ode = ode
        self.states = states
        self.time = time
        self.run = run
        self.inputs = inputs
        self.calibrate = calibrate
        self.init = init
        self.set = set
        self.correction = correction
        self.form = form
        self.initial = initial
        self.periodic = periodic
        self.smooth = smooth
        self.seed = seed
        self.conformal_folds = conformal_folds

    def _settings(self):
        if self.form not in _FORMS:
            raise ValueError(f"form={self.form!r}: use one of {', '.join(_FORMS)}")
        if self.correction not in ("additive", "multiplicative"):
            raise ValueError(
                f"correction={self.correction!r}: use \"additive\" or \"multiplicative\""
            )
        if self.initial not in ("first", "estimate"):
            raise ValueError(f"initial={self.initial!r}: use \"first\" or \"estimate\"")
        return {
            "time": str(self.time),
            "run": None if self.run is None else str(self.run),
            "states": _list(self.states, "states"),
            "inputs": _list(self.inputs, "inputs"),
            "ode": str(self.ode),
            "calibrate": _list(self.calibrate, "calibrate"),
            "init": _numbers(self.init, "init"),
            "set": _numbers(self.set, "set"),
            "correction": self.correction,
            "form": self.form,
            "initial": self.initial,
            "periodic": _list(self.periodic, "periodic"),
            "smooth": int(self.smooth),
            "seed": int(self.seed),
            "conformal_folds": int(self.conformal_folds),
        }

    def _columns(self, data):
        if not isinstance(data, pd.DataFrame):
            raise ValueError("data: give a pandas DataFrame with one row per sample")
        s = self._settings()
        used = [s["time"], *s["states"], *s["inputs"]]
        if s["run"] is not None:
            used.append(s["run"])
        missing = [c for c in used if c not in data.columns]
        if missing:
            raise ValueError(
                f"data has no column {', '.join(missing)} (columns: {', '.join(map(str, data.columns))})"
            )
        frame = data[used].copy()
        if s["run"] is not None and not pd.api.types.is_numeric_dtype(frame[s["run"]]):
            frame[s["run"]] = pd.factorize(frame[s["run"]])[0].astype(float)
        return frame_columns(frame)

    def fit(self, data):
        """Fits on every run of ``data``; returns ``self``."""
        names, cols = self._columns(data)
        self.model_json_ = _hxai.dynamic_fit(names, cols, json.dumps(self._settings()))
        m = json.loads(self.model_json_)
        self.equation_ = m["hybrid_equation"]
        self.parameters_ = m["parameters"]
        self.physics_parameters_ = m["physics_calibrated"]
        self.corrections_ = {c["state"]: c["equation"] for c in m["corrections"]}
        self.warnings_ = m.get("warnings", [])
        return self

    def predict(self, data, interval=None):
        """Each run of ``data`` simulated from its first reading with its inputs.

        A DataFrame on ``data``'s index with ``{state}_hybrid`` and ``{state}_physics`` (the
        calibrated physics) per state, and with ``interval`` (0.9) the conformal band
        ``{state}_lo``, ``{state}_hi`` that holds a whole new run's trajectory at that level.
        """
        if not hasattr(self, "model_json_"):
            raise ValueError("call fit before predict")
        names, cols = self._columns(data)
        hyb, phys, lo, hi, warnings = _hxai.dynamic_predict(
            self.model_json_, names, cols, None if interval is None else float(interval)
        )
        out = pd.DataFrame(index=data.index)
        for j, s in enumerate(_list(self.states, "states")):
            out[f"{s}_physics"] = from_bytes(phys[j])
            out[f"{s}_hybrid"] = from_bytes(hyb[j])
            if lo:
                out[f"{s}_lo"] = from_bytes(lo[j])
                out[f"{s}_hi"] = from_bytes(hi[j])
        out.attrs["warnings"] = list(warnings)
        return out

    def _repr_html_(self):
        """A compact card in a notebook: the hybrid ODE as MathML with its text, the
        calibrated parameters with their 95 % intervals, the free-run scores (unfitted:
        nothing)."""
        if not hasattr(self, "model_json_"):
            return None
        return _hxai.dynamic_card(self.model_json_)

    def report(self, path, data=None):
        """Writes the HTML page of ``hxai report`` for the fitted model to ``path`` (through
        a temporary file and a rename, never over an existing file that is not HTML); with
        ``data``, its first runs drawn against the model's free runs. Returns the path."""
        if not hasattr(self, "model_json_"):
            raise ValueError("call fit before report")
        names = columns = None
        if data is not None:
            names, columns = self._columns(data)
        return write_page(path, _hxai.dynamic_report(self.model_json_, names, columns, "data"))

    def compare(self, data, test_runs=None, test_after=None):
        """``hxai dynamic compare``: a DataFrame with columns ``model``, ``rmse`` (free run
        on the held-out samples) and ``p_value`` (paired t-test over held-out runs of the
        hybrid against each), one row per model (``physics``, ``physics_calibrated``,
        ``hybrid``, ``narx_boosting``); ``attrs["json"]`` holds the whole comparison."""
        names, cols = self._columns(data)
        runs = list(test_runs or [])
        if self.run is not None and not pd.api.types.is_numeric_dtype(data[self.run]):
            levels = list(pd.factorize(data[self.run])[1])
            missing = [r for r in runs if r not in levels]
            if missing:
                raise ValueError(
                    f"test_runs: there is no run {', '.join(map(str, missing))} "
                    f"(runs: {', '.join(map(str, levels))})"
                )
            runs = [levels.index(r) for r in runs]
        split = {
            "test_runs": [float(r) for r in runs],
            "test_after": None if test_after is None else float(test_after),
        }
        text = _hxai.dynamic_compare(names, cols, json.dumps(self._settings()), json.dumps(split))
        c = json.loads(text)
        frame = pd.DataFrame(
            [{"model": m["name"], "rmse": m["rmse"], "p_value": m["p_value"]} for m in c["models"]]
        )
        frame = frame.astype({"rmse": float, "p_value": float})
        frame.attrs["json"] = c
        return frame
