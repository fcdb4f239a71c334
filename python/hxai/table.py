"""A table hybrid's prediction as a pure function of a pandas DataFrame.

:func:`predict_table` runs what ``hxai hybrid predict`` runs (the physics with its
calibrated parameters, the correction, their combination, the rows beside the training
data) on the rows of one DataFrame, with a model given as its JSON text (the file ``hxai
hybrid fit --out`` writes) or as a fitted :class:`~hxai.HybridRegressor`. Each row's
prediction depends on that row alone, so the function runs unchanged on each partition of a
partitioned Parquet dataset under Dask's ``map_partitions`` and gives the same values as one
process (docs/python.md, "A million rows").
"""

import json
import warnings

import numpy as np
import pandas as pd

from . import _hxai
from ._arrays import frame_columns, from_bytes

#: Columns of :func:`predict_table`'s result, as ``hxai hybrid predict`` writes them.
PREDICTION_COLUMNS = ("physics", "correction", "hybrid", "outside_training")


def _model_text(model):
    """The model file's JSON text of ``model`` (a fitted HybridRegressor or the text)."""
    if isinstance(model, str):
        return model
    text = getattr(model, "model_json_", None)
    if text is None:
        raise ValueError(
            "predict_table takes a fitted HybridRegressor or the JSON text of a model file "
            "written by `hxai hybrid fit --out` (read it with open(path).read())"
        )
    return text


def _level_columns(doc):
    """The text columns a model with per-level constants reads (``calibrate_per``,
    ``correction_per``)."""
    cols = []
    for key in ("per_class", "correction_per"):
        col = (doc.get(key) or {}).get("column")
        if col and col not in cols:
            cols.append(col)
    return cols


def predict_table(df, model):
    """The hybrid's prediction of every row of ``df`` (a pandas DataFrame holding the
    columns the model reads; other columns, numeric or not, are ignored) with ``model`` (a
    fitted :class:`~hxai.HybridRegressor`, or the JSON text of ``hxai hybrid fit``'s model
    file). Returns a DataFrame with ``df``'s index and the columns
    :data:`PREDICTION_COLUMNS`: the same values ``hxai hybrid predict`` writes for these rows
    (``outside_training`` 1 where a column of the row lies outside its training range by more
    than 10 % of its width). The warnings of ``hxai hybrid predict`` about the rows are
    ``UserWarning``; a missing column or a level the fit never saw is a ``ValueError``.

    A pure function of its arguments, so Dask runs it per partition::

        ddf.map_partitions(hxai.predict_table, text, meta=hxai.table.meta())
    """
    if not isinstance(df, pd.DataFrame):
        raise ValueError(f"predict_table takes a pandas DataFrame, got {type(df).__name__}")
    text = _model_text(model)
    doc = json.loads(text)
    level_cols = _level_columns(doc)
    missing = [c for c in level_cols if c not in df.columns]
    if missing:
        raise ValueError(
            f"the model has constants per level of `{missing[0]}`, and the table has no such "
            "column"
        )
    levels = {c: df[c].astype(str).tolist() for c in level_cols} or None
    numeric = df.drop(columns=level_cols).select_dtypes(include=[np.number, "bool"])
    names, columns = frame_columns(numeric)
    p, c, h, o, warned = _hxai.table_predict(text, names, columns, levels)
    for w in warned:
        warnings.warn(w, UserWarning, stacklevel=2)
    return pd.DataFrame(
        {
            "physics": from_bytes(p),
            "correction": from_bytes(c),
            "hybrid": from_bytes(h),
            "outside_training": from_bytes(o).astype(np.int64),
        },
        index=df.index,
    )


def meta():
    """An empty frame with :func:`predict_table`'s columns and dtypes (Dask's ``meta``)."""
    cols = {c: pd.Series(dtype="float64") for c in PREDICTION_COLUMNS[:3]}
    cols["outside_training"] = pd.Series(dtype="int64")
    return pd.DataFrame(cols)
