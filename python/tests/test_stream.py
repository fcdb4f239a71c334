"""hxai.StreamEstimator: the causal streaming estimator (hxai_hybrid::records::stream) from Python.
Chunking does not change the rows, the rows track the probe as well as the offline
`ToolModel.predict`, the warm-up is NaN, the interval brackets the hybrid, bad input is a
ValueError."""

import os
import re
import subprocess
import threading

import numpy as np
import pandas as pd
import pytest

import hxai
from conftest import ROOT, hxai_binary

MODEL = ROOT / "testdata" / "bad" / "good" / "model.json"  # written by `hxai fit`
FS = 2000.0
F = 20.0


@pytest.fixture(scope="module")
def model():
    return hxai.ToolModel.load(MODEL)


@pytest.fixture(scope="module")
def record():
    # one 3 s record at 2 kHz: 6000 samples, a 0.5 s (1000-sample) window
    return hxai.simulate(
        amplitudes_um=[6.0], frequencies_hz=[F], repeats=1, duration_s=3.0, fs_hz=FS, seed=5
    )


@pytest.fixture(scope="module")
def model_with_uncertainty(tmp_path_factory):
    """A model that stores its correction's uncertainty (the one in testdata predates it):
    `hxai simulate` + `hxai fit`, well under a second."""
    binary = hxai_binary()
    d = tmp_path_factory.mktemp("fit")
    run = dict(check=True, capture_output=True, text=True)
    subprocess.run(
        [binary, "simulate", "--out", str(d / "data"), "--repeats", "1", "--duration-s", "2",
         "--fs-hz", "2000", "--amplitudes", "4", "8", "--frequencies", "10", "20", "30", "40",
         "--seed", "5"],
        **run,
    )
    subprocess.run(
        [binary, "fit", "--data", str(d / "data"), "--out", str(d / "model.json"),
         "--epochs", "2", "--threads", "1"],
        **run,
    )
    return hxai.ToolModel.load(d / "model.json")


def test_properties_and_frame(model, record):
    est = hxai.StreamEstimator(model, F, FS)
    assert est.delay_samples == 0
    assert est.window_samples == 1000 and est.warmup_samples == 999
    assert est.update_step > 0
    rows = est.push(record["accel_ms2"])  # a Series is fine
    assert list(rows.columns) == ["sample", "time_s", "physics_um", "hybrid_um"]
    assert rows["sample"].dtype == np.int64
    assert rows["physics_um"].dtype == np.float64 and rows["hybrid_um"].dtype == np.float64
    np.testing.assert_array_equal(rows["sample"], np.arange(len(record)))
    np.testing.assert_array_equal(rows["time_s"], np.arange(len(record)) / est.fs_hz)
    assert est.samples == len(record)
    empty = est.push(np.zeros(0))
    assert empty.empty and list(empty.dtypes) == list(rows.dtypes)
    # the model as JSON text or as a path gives the same rows
    for other in (model.model_json, MODEL, str(MODEL)):
        again = hxai.StreamEstimator(other, F, FS).push(record["accel_ms2"].to_numpy())
        pd.testing.assert_frame_equal(again, rows)


def test_chunks_of_any_size_give_the_same_rows(model, record):
    a = record["accel_ms2"].to_numpy()
    whole = hxai.StreamEstimator(model, F, FS).push(a)
    rng = np.random.default_rng(11)
    for _ in range(3):
        est = hxai.StreamEstimator(model, F, FS)
        cuts = np.sort(rng.integers(0, len(a), size=rng.integers(5, 40)))
        parts = [est.push(c) for c in np.split(a, cuts)]  # includes empty and 1-sample chunks
        assert sum(len(p) for p in parts) == len(a)
        pd.testing.assert_frame_equal(pd.concat(parts, ignore_index=True), whole,
                                      check_exact=True)


def test_restart_is_a_fresh_estimator(model, record):
    a = record["accel_ms2"].to_numpy()
    est = hxai.StreamEstimator(model, F, FS)
    est.push(a[:2500])
    est.restart()
    assert est.samples == 0
    after = est.push(a[2500:])
    fresh = hxai.StreamEstimator(model, F, FS).push(a[2500:])
    pd.testing.assert_frame_equal(after, fresh, check_exact=True)
    assert after["sample"].iloc[0] == 0


def test_tracks_the_probe_like_offline_predict(model, record):
    a = record["accel_ms2"].to_numpy()
    probe = record["probe_um"].to_numpy()
    est = hxai.StreamEstimator(model, F, FS)
    rows = est.push(a)
    offline = model.predict(a, FS, F)["hybrid"]
    after = slice(est.warmup_samples, None)  # the samples the stream has values for
    stream_h = rows["hybrid_um"].to_numpy()[after]
    assert np.isfinite(stream_h).all() and np.isfinite(offline[after]).all()

    def rmse(x):
        return float(np.sqrt(np.mean((x - probe[after]) ** 2)))

    stream_rmse, offline_rmse = rmse(stream_h), rmse(offline[after])
    assert stream_rmse <= 1.1 * offline_rmse, (stream_rmse, offline_rmse)
    # and it is a displacement of the right size, not a trivially small error
    assert 0.5 * 6.0 < np.sqrt(2.0) * np.std(stream_h) < 2.0 * 6.0


@pytest.mark.parametrize("f_hz", [F, 30.0])  # 30 Hz: whole periods fill less than the window
def test_warm_up_rows_are_nan(model, f_hz):
    rec = hxai.simulate(
        amplitudes_um=[6.0], frequencies_hz=[f_hz], repeats=1, duration_s=3.0, fs_hz=FS, seed=5
    )
    est = hxai.StreamEstimator(model, f_hz, FS)
    rows = est.push(rec["accel_ms2"].to_numpy())
    w = est.warmup_samples
    for col in ("physics_um", "hybrid_um"):
        missing = rows[col].isna().to_numpy()
        assert missing.sum() == w, col
        assert missing[:w].all() and not missing[w:].any(), col


def test_interval_brackets_the_hybrid(model_with_uncertainty, record):
    est = hxai.StreamEstimator(model_with_uncertainty, F, FS, interval=0.95)
    rows = est.push(record["accel_ms2"].to_numpy())
    assert list(rows.columns) == [
        "sample", "time_s", "physics_um", "hybrid_um", "hybrid_lo_um", "hybrid_hi_um"
    ]
    w = est.warmup_samples
    assert rows.iloc[:w, 2:].isna().all().all()
    after = rows.iloc[w:]
    assert after.notna().all().all()
    assert (after["hybrid_lo_um"] <= after["hybrid_um"]).all()
    assert (after["hybrid_um"] <= after["hybrid_hi_um"]).all()
    assert (after["hybrid_hi_um"] > after["hybrid_lo_um"]).any()
    # the interval leaves the other columns as they are without it
    plain = hxai.StreamEstimator(model_with_uncertainty, F, FS).push(
        record["accel_ms2"].to_numpy()
    )
    pd.testing.assert_frame_equal(rows[plain.columns], plain, check_exact=True)


def test_bad_input_is_a_value_error(model, record):
    with pytest.raises(ValueError, match="outside the physics model's pass band"):
        hxai.StreamEstimator(model, 1000.0, FS)
    with pytest.raises(ValueError, match="Nyquist"):
        hxai.StreamEstimator(model, F, 300.0)
    with pytest.raises(ValueError, match="sampling rate"):
        hxai.StreamEstimator(model, F, -1.0)
    with pytest.raises(ValueError, match="between 0 and 1"):
        hxai.StreamEstimator(model, F, FS, interval=1.5)
    with pytest.raises(ValueError, match="uncertainty"):
        hxai.StreamEstimator(model, F, FS, interval=0.95)  # this model stores none
    with pytest.raises(ValueError, match="ToolModel"):
        hxai.StreamEstimator(42, F, FS)

    a = record["accel_ms2"].to_numpy()
    est = hxai.StreamEstimator(model, F, FS)
    with pytest.raises(ValueError, match=r"1-D array, got shape \(3, 2\)"):
        est.push(np.zeros((3, 2)))
    with pytest.raises(ValueError, match="1-D array"):
        est.push(1.0)
    with pytest.raises(ValueError, match="float64"):
        est.push(["a", "b"])
    first = est.push(a[:100])
    bad = a[100:200].copy()
    bad[7] = np.nan
    with pytest.raises(ValueError, match=r"accel\[7\] = nan is not a finite number \(sample 107"):
        est.push(bad)
    bad[7] = np.inf
    with pytest.raises(ValueError, match=r"accel\[7\] = inf"):
        est.push(bad)
    # nothing of a refused call was pushed: the stream goes on as if it never happened
    assert est.samples == 100
    rest = est.push(a[100:])
    pd.testing.assert_frame_equal(
        pd.concat([first, rest], ignore_index=True),
        hxai.StreamEstimator(model, F, FS).push(a),
        check_exact=True,
    )


def test_streams_in_threads(model, record):
    """push releases the GIL; estimators in different threads are independent."""
    a = record["accel_ms2"].to_numpy()
    want = hxai.StreamEstimator(model, F, FS).push(a)
    got = [None] * 4

    def work(k):
        est = hxai.StreamEstimator(model, F, FS)
        got[k] = pd.concat([est.push(c) for c in np.array_split(a, 7 + k)], ignore_index=True)

    threads = [threading.Thread(target=work, args=(k,)) for k in range(4)]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    for g in got:
        pd.testing.assert_frame_equal(g, want, check_exact=True)


def test_docs_streaming_example_runs(tmp_path, monkeypatch):
    """docs/python.md's "Streaming" block runs as written from the repository root's layout."""
    text = (ROOT / "docs" / "python.md").read_text(encoding="utf-8")
    section = text.split("## Streaming", 1)[1].split("\n## ", 1)[0]
    blocks = re.findall(r"```python\n(.*?)```", section, flags=re.S)
    assert len(blocks) == 1
    os.symlink(ROOT / "testdata", tmp_path / "testdata")
    monkeypatch.chdir(tmp_path)
    scope = {"__name__": "__docs__"}
    exec(compile(blocks[0], "docs/python.md Streaming", "exec"), scope)
    assert len(scope["rows"]) == 200 and scope["rows"]["hybrid_um"].notna().all()
