"""Conversions between NumPy/pandas and the compiled module (float64 bytes, names)."""

import numpy as np

_F64 = np.dtype("<f8")


def as_f64(x, what):
    """A 1-D float64 array from `x`; ValueError naming `what` otherwise."""
    try:
        a = np.asarray(x, dtype=np.float64)
    except (TypeError, ValueError) as e:
        raise ValueError(f"{what}: cannot convert to float64 numbers ({e})") from None
    if a.ndim != 1:
        raise ValueError(f"{what}: expected a 1-D array, got shape {a.shape}")
    return a


def to_bytes(x, what="x"):
    """Little-endian float64 bytes of a 1-D array (one copy)."""
    return np.ascontiguousarray(as_f64(x, what), dtype=_F64).tobytes()


def from_bytes(b):
    """A writable float64 array from bytes returned by the compiled module."""
    return np.frombuffer(b, dtype=_F64).astype(np.float64, copy=True)


def columns_of(X2d):
    """Column bytes of a 2-D float array."""
    return [to_bytes(X2d[:, j]) for j in range(X2d.shape[1])]


def frame_columns(df):
    """(names, column bytes) of a DataFrame whose columns are all numeric."""
    names = [str(c) for c in df.columns]
    cols = []
    for name, c in zip(names, df.columns):
        try:
            cols.append(to_bytes(df[c].to_numpy(dtype=np.float64), name))
        except (TypeError, ValueError) as e:
            raise ValueError(f"column `{name}`: not numeric ({e})") from None
    return names, cols
