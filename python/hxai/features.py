"""The twelve features of the paper's Table 2 (``hxai-features``) on a NumPy array."""

from . import _hxai
from ._arrays import to_bytes

NAMES = tuple(f"f{i}" for i in range(1, 13))


def extract(accel, fs, command_hz):
    """Features ``f1``..``f12`` of one acceleration record (m/s^2, sampled at ``fs`` Hz,
    commanded at ``command_hz``), as a dict in that order. The record must cover one
    period of the command."""
    values = _hxai.features_extract(to_bytes(accel, "accel"), float(fs), float(command_hz))
    return dict(zip(NAMES, values))
