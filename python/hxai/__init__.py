"""hxai from Python: symbolic regression and hybrid physics + symbolic models as
scikit-learn estimators, the signal chain and features on NumPy arrays, and the simulators
as pandas DataFrames, all computed by hxai's compiled Rust engine (``hxai._hxai``).

- :class:`SymbolicRegressor`: symbolic regression (``hxai sr``) as a scikit-learn regressor.
- :class:`HybridRegressor`: a physics equation over the columns, calibrated, plus a symbolic
  correction (``hxai hybrid fit``, docs/hybrid-tables.md); :func:`compare` and
  ``HybridRegressor.compare`` (``hxai hybrid compare``) as a tidy DataFrame.
- :class:`ToolModel` and :func:`predict_records`: the tool case's per-record pipeline with a
  model written by ``hxai fit`` (features, physics, hybrid), a pure function of a pandas
  DataFrame that Dask's ``map_partitions`` runs over a partitioned archive.
- :func:`predict_table`: a table hybrid's prediction (``hxai hybrid predict``) as a pure
  function of a DataFrame and the model, for Dask's ``map_partitions`` over a partitioned
  Parquet dataset.
- :class:`StreamEstimator`: the same model applied sample by sample, causally (``hxai
  stream``): push chunks of acceleration, get one DataFrame row per sample.
- :mod:`hxai.signal`, :mod:`hxai.features`: the signal functions in scipy's shapes, the
  twelve features.
- :class:`DynamicRegressor`: grey-box dynamic models (``hxai dynamic``, docs/dynamic.md):
  the engineer's ODE calibrated through its trajectories, with a learned correction term.
- :func:`simulate`: the machine simulator and the table cases as DataFrames.

Every result equals the command line's for the same seed and data; errors are ValueErrors
with the command line's one-line messages.
"""

from . import _hxai
from . import features, signal
from .dynamic import DynamicRegressor
from .estimators import HybridRegressor, SymbolicRegressor, compare
from .sim import simulate
from .stream import StreamEstimator
from .table import predict_table
from .tool import ToolModel, predict_records

__version__ = _hxai.__version__

__all__ = [
    "SymbolicRegressor",
    "HybridRegressor",
    "compare",
    "DynamicRegressor",
    "ToolModel",
    "predict_records",
    "predict_table",
    "StreamEstimator",
    "simulate",
    "signal",
    "features",
]
