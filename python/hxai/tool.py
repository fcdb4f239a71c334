"""The tool case's per-record pipeline with a model written by ``hxai fit``.

:func:`predict_records` is a pure function of a pandas DataFrame (one row per sample of
one or more records) and a :class:`ToolModel`: it runs, record by record, what
``hxai predict`` runs (features per window, the physics model, the symbolic correction,
the corrected amplitude) and returns one row per window. Because it depends on nothing but
its arguments, the same function scales out unchanged: Dask's ``map_partitions`` runs it
on each partition of a partitioned Parquet archive (docs/python.md).
"""

import json
import os

import numpy as np
import pandas as pd

from . import _hxai
from ._arrays import from_bytes, to_bytes
from ._page import write_page

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

    def _repr_html_(self):
        """A compact card in a notebook: the hybrid as MathML with its text, the
        correction's constants with their 95 % intervals and its scores at the fit."""
        return _hxai.tool_card(self.model_json)

    def report(self, path, data=None, compare=None):
        """Writes the HTML page of ``hxai report`` for this model to ``path`` (through a
        temporary file and a rename, never over an existing file that is not HTML) and
        returns the path. ``data``, to draw the scores, figures and training ranges on: the
        data folder (``manifest.csv`` and the records, each with ``probe_um``), or a
        DataFrame with one row per sample and the columns ``record``, ``time_s``,
        ``accel_ms2``, ``probe_um`` and ``frequency_hz`` (``fs_hz`` optional, else read from
        ``time_s``). ``compare``: the JSON text (or dict) of ``hxai compare --json``."""
        records, name = None, None
        if data is not None:
            if isinstance(data, pd.DataFrame):
                records, name = _records_of_frame(data), "the DataFrame given"
            else:
                records, name = _records_of_folder(os.fspath(data)), os.fspath(data)
        if isinstance(compare, dict):
            compare = json.dumps(compare)
        return write_page(path, _hxai.tool_report(self.model_json, records, compare, name))

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


def _fs_of(time, rid):
    """The sampling rate of a record from its time stamps, as the command line reads a
    record file: ``(n - 1) / (t_last - t_first)`` (so both draw the same page)."""
    if len(time) < 2:
        raise ValueError(f"record `{rid}`: fewer than two samples")
    span = float(time[-1] - time[0])
    if not span > 0:
        raise ValueError(f"record `{rid}`: `time_s` does not increase")
    return (len(time) - 1) / span


def _record(rid, frame, frequency, fs=None):
    """One record for ``tool_report``: ``(id, fs, frequency, accel, probe)``."""
    missing = [c for c in ("time_s", "accel_ms2", "probe_um") if c not in frame.columns]
    if missing:
        raise ValueError(
            f"record `{rid}`: no column {', '.join(f'`{c}`' for c in missing)}; the report "
            "needs the acceleration and the probe truth"
        )
    frame = frame.sort_values("time_s", kind="stable")
    time = frame["time_s"].to_numpy(dtype=np.float64)
    fs = _fs_of(time, rid) if fs is None else float(fs)
    return (
        str(rid),
        fs,
        float(frequency),
        to_bytes(frame["accel_ms2"].to_numpy(dtype=np.float64), "accel"),
        to_bytes(frame["probe_um"].to_numpy(dtype=np.float64), "probe"),
    )


def _records_of_frame(df):
    """The records of a DataFrame in :func:`predict_records`' shape, with ``probe_um``."""
    missing = [c for c in ("record", "frequency_hz") if c not in df.columns]
    if missing:
        raise ValueError(
            f"no column {', '.join(f'`{c}`' for c in missing)}: the columns are "
            + ", ".join(str(c) for c in df.columns)
        )
    ids = df["record"].astype(str)
    out = []
    for rid in sorted(ids.unique()):
        rec = df[(ids == rid).to_numpy()]
        freq = np.unique(rec["frequency_hz"].to_numpy(dtype=np.float64))
        if len(freq) != 1:
            raise ValueError(f"record `{rid}`: `frequency_hz` must be constant within a record")
        fs = None
        if "fs_hz" in rec.columns:
            fs = float(rec["fs_hz"].iloc[0])
        out.append(_record(rid, rec, freq[0], fs))
    return out


def _records_of_folder(folder):
    """Every record of a data folder (``manifest.csv``: ``record``, ``file``,
    ``frequency_hz``; record files CSV or Parquet)."""
    manifest = os.path.join(folder, "manifest.csv")
    if not os.path.isfile(manifest):
        raise ValueError(f"{folder}: no manifest.csv; give a data folder or a DataFrame")
    entries = pd.read_csv(manifest)
    missing = [c for c in ("record", "file", "frequency_hz") if c not in entries.columns]
    if missing:
        raise ValueError(f"{manifest}: no column {', '.join(f'`{c}`' for c in missing)}")
    out = []
    for _, e in entries.iterrows():
        path = os.path.join(folder, str(e["file"]))
        if path.lower().endswith(".parquet"):
            frame = pd.read_parquet(path)
        else:
            frame = pd.read_csv(path)
        out.append(_record(e["record"], frame, e["frequency_hz"]))
    return out
