"""The tool case's per-record pipeline with a model written by ``hxai fit``.

:func:`predict_records` is a pure function of a pandas DataFrame (one row per sample of
one or more records) and a :class:`ToolModel`: it runs, record by record, what
``hxai predict`` runs (features per window, the physics model, the symbolic correction,
the corrected amplitude) and returns one row per window. Because it depends on nothing but
its arguments, the same function scales out unchanged: Dask's ``map_partitions`` runs it
on each partition of a partitioned Parquet archive (docs/python.md).
"""

import json

import numpy as np
import pandas as pd

from . import _hxai
from ._arrays import from_bytes, to_bytes

#: Columns of :func:`predict_records`' result before the model's feature columns.
WINDOW_COLUMNS = (
    "record",
    "window",
    "start",
    "len",
    "start_s",
    "a_phys_um",
    "phase_rad",
    "delta_hat_um",
    "a_corr_um",
)


class ToolModel:
    """A tool-case hybrid model (the JSON file ``hxai fit`` writes). Holds the text only,
    so it pickles (Dask ships it to workers) and every call reads it afresh."""

    def __init__(self, model_json):
        if not isinstance(model_json, str):
            raise ValueError("ToolModel takes the model file's JSON text (see ToolModel.load)")
        doc = json.loads(model_json)
        self.model_json = model_json
        self.feature_names = list(doc["features"]["names"])
        self.equation = doc["correction"]["equation"]

    @classmethod
    def load(cls, path):
        """Reads a model file written by ``hxai fit --out PATH``."""
        with open(path, encoding="utf-8") as f:
            return cls(f.read())

    def predict(self, accel, fs_hz, frequency_hz, record="record"):
        """One record: a dict with ``physics`` and ``hybrid`` (arrays, micrometres, one
        value per sample, as ``hxai predict``), ``windows`` (a DataFrame, one row per
        window: :data:`WINDOW_COLUMNS` and the features) and ``warnings``."""
        phys, hyb, windows, warnings = _hxai.tool_predict(
            self.model_json, str(record), to_bytes(accel, "accel"), float(fs_hz),
            float(frequency_hz)
        )
        rows = []
        for w in json.loads(windows):
            row = {"record": str(record)}
            row.update({k: w[k] for k in WINDOW_COLUMNS[1:]})
            row.update(w["features"])
            rows.append(row)
        return {
            "physics": from_bytes(phys),
            "hybrid": from_bytes(hyb),
            "windows": pd.DataFrame(rows, columns=self.columns()),
            "warnings": list(warnings),
        }

    def columns(self):
        """Columns of :func:`predict_records`' result."""
        return list(WINDOW_COLUMNS) + self.feature_names

    def meta(self):
        """An empty frame with :func:`predict_records`' columns and dtypes (Dask's ``meta``)."""
        cols = {c: pd.Series(dtype="float64") for c in self.columns()}
        cols["record"] = pd.Series(dtype="object")
        for c in ("window", "start", "len"):
            cols[c] = pd.Series(dtype="int64")
        return pd.DataFrame(cols)


def predict_records(
    df,
    model,
    record="record",
    accel="accel_ms2",
    time="time_s",
    fs="fs_hz",
    frequency="frequency_hz",
):
    """Runs the tool case's pipeline on every record of ``df`` (a pandas DataFrame, one row
    per sample; every record whole within ``df``) and returns one row per window, records
    in sorted order.

    ``df`` needs the columns named by ``record`` (record id), ``accel`` (m/s^2), ``time``
    (s, to order the samples), ``fs`` (sampling rate, Hz) and ``frequency`` (commanded
    frequency, Hz), ``fs`` and ``frequency`` constant within a record. ``model`` is a
    :class:`ToolModel`. Records with no rows in ``df`` give nothing, so a partition of an
    archive gives the rows of the records it holds.
    """
    if not isinstance(model, ToolModel):
        raise ValueError("model: give a hxai.ToolModel (ToolModel.load(path))")
    missing = [c for c in (record, accel, time, fs, frequency) if c not in df.columns]
    if missing:
        raise ValueError(
            f"no column {', '.join(f'`{c}`' for c in missing)}: the columns are "
            + ", ".join(str(c) for c in df.columns)
        )
    out = [model.meta()]
    ids = df[record].astype(str)
    for rid in sorted(ids.unique()):
        rec = df[(ids == rid).to_numpy()].sort_values(time, kind="stable")
        fs_values = np.unique(rec[fs].to_numpy(dtype=np.float64))
        f_values = np.unique(rec[frequency].to_numpy(dtype=np.float64))
        if len(fs_values) != 1 or len(f_values) != 1:
            raise ValueError(
                f"record `{rid}`: `{fs}` and `{frequency}` must be constant within a record"
            )
        res = model.predict(rec[accel].to_numpy(dtype=np.float64), fs_values[0], f_values[0], rid)
        out.append(res["windows"])
    result = pd.concat(out, ignore_index=True) if len(out) > 1 else out[0]
    return result.astype(model.meta().dtypes.to_dict())
