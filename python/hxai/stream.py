"""The tool position in real time: a model written by ``hxai fit`` applied sample by sample,
causally, in bounded memory (``hxai_hybrid::records::stream::Estimator``, ``hxai stream``).

:class:`StreamEstimator` keeps the state of one stream between calls: push the samples of
acceleration as they arrive, in chunks of any size, and get back one row per sample (the
delay is 0: a row is complete when its sample arrives). The rows do not depend on how the
stream was cut into chunks.
"""

import os

import numpy as np
import pandas as pd

from . import _hxai
from ._arrays import as_f64, from_bytes, to_bytes
from .tool import ToolModel

_I64 = np.dtype("<i8")

#: Columns of :meth:`StreamEstimator.push`'s frame, without and with an interval.
COLUMNS = ("sample", "time_s", "physics_um", "hybrid_um")
INTERVAL_COLUMNS = ("hybrid_lo_um", "hybrid_hi_um")


def _model_json(model):
    """The JSON text of ``model``: a :class:`ToolModel`, the JSON text itself, or a path."""
    if isinstance(model, ToolModel):
        return model.model_json
    if isinstance(model, str) and model.lstrip().startswith("{"):
        return model
    if isinstance(model, (str, os.PathLike)):
        return ToolModel.load(model).model_json
    raise ValueError(
        "model: give a hxai.ToolModel (ToolModel.load(path)), the model file's JSON text "
        f"or its path, not {type(model).__name__}"
    )


class StreamEstimator:
    """The causal streaming estimator of the tool position (docs/python.md, "Streaming").

    ``model`` is a :class:`hxai.ToolModel` (or the JSON text of ``hxai fit``'s model file,
    or its path), ``frequency_hz`` the commanded frequency (within the model's physics
    band), ``fs_hz`` the sampling rate. ``interval`` (a level in (0, 1), e.g. 0.95) adds
    the bounds of the hybrid's prediction interval to every row; the model must store the
    uncertainty of its correction (models of ``hxai fit`` do).

    Each row of sample ``i`` uses the trailing window of :attr:`window_samples` samples
    ending at ``i``: the physics displacement at the command frequency (``physics_um``)
    and the hybrid (``hybrid_um``, physics amplitude plus the symbolic correction, updated
    every :attr:`update_step` samples). The first :attr:`warmup_samples` rows, at the start
    and after :meth:`restart`, have no values (NaN).

    ``push`` releases the GIL while the engine runs. One object is one stream: use one per
    thread (two threads pushing into the same object at once get a ``RuntimeError``).
    Errors are ``ValueError`` with the engine's one-line message.
    """

    def __init__(self, model, frequency_hz, fs_hz, interval=None):
        self._est = _hxai.StreamEstimator(
            _model_json(model),
            float(frequency_hz),
            float(fs_hz),
            None if interval is None else float(interval),
        )
        self.frequency_hz = float(frequency_hz)
        self.fs_hz = float(fs_hz)
        self.interval = None if interval is None else float(interval)

    def push(self, accel):
        """Pushes samples of acceleration (m/s^2, a 1-D array-like) and returns the rows they
        complete as a DataFrame, one per sample, in order: ``sample`` (int64, the index since
        the start or the last :meth:`restart`), ``time_s`` (``sample / fs_hz``, s),
        ``physics_um`` and ``hybrid_um`` (float64,
        NaN during the warm-up and while the correction is undefined) and, with an interval,
        ``hybrid_lo_um`` and ``hybrid_hi_um``.

        A NaN or infinite sample is a ``ValueError`` naming its index; nothing of that call
        is pushed then (the estimator stays as it was).
        """
        a = as_f64(accel, "accel")
        bad = np.flatnonzero(~np.isfinite(a))
        if bad.size:
            i = int(bad[0])
            raise ValueError(
                f"accel[{i}] = {a[i]} is not a finite number (sample {self.samples + i} of "
                "the stream); nothing of this call was pushed"
            )
        sample, time, phys, hyb, lo, hi = self._est.push(to_bytes(a, "accel"))
        cols = {
            "sample": np.frombuffer(sample, dtype=_I64).astype(np.int64, copy=True),
            "time_s": from_bytes(time),
            "physics_um": from_bytes(phys),
            "hybrid_um": from_bytes(hyb),
        }
        if self.interval is not None:
            cols["hybrid_lo_um"] = from_bytes(lo)
            cols["hybrid_hi_um"] = from_bytes(hi)
        return pd.DataFrame(cols, columns=self.columns())

    def restart(self):
        """Forgets every sample (after a gap in the stream): the next one is sample 0 and
        starts a new warm-up."""
        self._est.restart()

    def columns(self):
        """Columns of :meth:`push`'s frame."""
        return list(COLUMNS) + (list(INTERVAL_COLUMNS) if self.interval is not None else [])

    @property
    def delay_samples(self):
        """The delay ``D``: the row of sample ``i`` depends on samples up to ``i + D``
        (always 0: a row is complete when its sample arrives)."""
        return self._est.delay_samples

    @property
    def warmup_samples(self):
        """Rows without values at the start and after each restart (the window minus 1)."""
        return self._est.warmup_samples

    @property
    def update_step(self):
        """Samples between two updates of the correction (the features' Welch step)."""
        return self._est.update_step

    @property
    def window_samples(self):
        """The trailing window the estimates are made over, samples (the model's window)."""
        return self._est.window_samples

    @property
    def samples(self):
        """Samples pushed since the start or the last restart."""
        return self._est.samples

    def __repr__(self):
        extra = "" if self.interval is None else f", interval={self.interval}"
        return (
            f"StreamEstimator(frequency_hz={self.frequency_hz}, fs_hz={self.fs_hz}{extra}; "
            f"window {self.window_samples} samples, {self.samples} pushed)"
        )
