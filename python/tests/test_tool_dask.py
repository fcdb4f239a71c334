"""The tool case's per-record pipeline (features, physics, hybrid) on one process and under
Dask's map_partitions over a partitioned Parquet archive: identical results."""

import json
import subprocess

import numpy as np
import pandas as pd
import pytest

import hxai
from conftest import ROOT, hxai_binary

MODEL = ROOT / "testdata" / "bad" / "good" / "model.json"  # written by `hxai fit`


@pytest.fixture(scope="module")
def records():
    # 4 records, 2 s at 2 kHz: small, three 0.5 s windows each after the 0.25 s discard
    return hxai.simulate(
        amplitudes_um=[4.0, 8.0], frequencies_hz=[20.0, 30.0], repeats=1, duration_s=2.0,
        fs_hz=2000.0, seed=3,
    )


def test_simulate_tool_frame(records):
    assert records["record"].nunique() == 4
    assert len(records) == 4 * 4000
    one = records[records["record"] == records["record"].iloc[0]]
    np.testing.assert_allclose(np.diff(one["time_s"]), 1 / 2000.0, rtol=1e-9)
    assert {"accel_ms2", "probe_um", "command_um", "encoder_um"} <= set(records.columns)


def test_simulate_n_jobs_changes_nothing():
    """The records do not depend on the threads that simulate them."""
    small = dict(amplitudes_um=[4.0, 8.0], frequencies_hz=[20.0], repeats=1, duration_s=0.5,
                 fs_hz=2000.0, seed=3)
    pd.testing.assert_frame_equal(
        hxai.simulate(n_jobs=1, **small), hxai.simulate(n_jobs=2, **small)
    )
    with pytest.raises(ValueError, match="n_jobs"):
        hxai.simulate(n_jobs=0, **small)


def test_simulate_cases_and_bad_settings():
    r = hxai.simulate("roughness", n_rows=50, seed=2)
    assert len(r) == 50 and "Ra_um" in r.columns
    again = hxai.simulate("roughness", n_rows=50, seed=2)
    pd.testing.assert_frame_equal(r, again)
    assert "Fc_N" in hxai.simulate("cutting_force", n_rows=20).columns
    # tool_life (docs/cases.md section 3): with no scatter, measured over Taylor's law is
    # the documented feed power law.
    d = hxai.sim.defaults("tool_life")
    t = hxai.simulate("tool_life", n_rows=30, noise_rel=0.0)
    taylor = (d["taylor_c_m_min"] / t["cutting_speed_m_min"]) ** (1.0 / d["taylor_n"])
    np.testing.assert_allclose(
        t["tool_life_min"] / taylor, (t["feed_mm"] / 0.25) ** -2.4, rtol=1e-12
    )
    with pytest.raises(ValueError, match="unknown setting `rows`"):
        hxai.simulate("roughness", rows=10)
    with pytest.raises(ValueError, match="unknown case"):
        hxai.simulate("milling")
    with pytest.raises(ValueError):
        hxai.simulate(fs_hz=-1.0)


def test_tool_model_equals_cli_predict(records, tmp_path):
    binary = hxai_binary()
    model = hxai.ToolModel.load(MODEL)
    rid = records["record"].iloc[0]
    rec = records[records["record"] == rid]
    csv = tmp_path / "rec.csv"
    rec[["time_s", "accel_ms2"]].to_csv(csv, index=False, float_format="%.17g")
    rec_back = pd.read_csv(csv)
    out = tmp_path / "pred.csv"
    done = subprocess.run(
        [binary, "predict", "--model", str(MODEL), "--record", str(csv),
         "--frequency-hz", "20", "--out", str(out), "--json"],
        check=True, capture_output=True, text=True,
    )
    cli = pd.read_csv(out)
    ours = model.predict(rec_back["accel_ms2"].to_numpy(), 2000.0, 20.0, rid)
    np.testing.assert_array_equal(ours["physics"], cli["physics_um"].to_numpy())
    np.testing.assert_array_equal(ours["hybrid"], cli["hybrid_um"].to_numpy())
    # the windows carry the same keys and values on both sides (one row type in the library);
    # the command line's start_s is the record's time stamp, Python's start / fs
    cli_windows = pd.DataFrame(json.loads(done.stdout)["windows"])
    keys = ["window", "start", "len", "a_phys_um", "phase_rad", "delta_hat_um", "a_corr_um"]
    pd.testing.assert_frame_equal(ours["windows"][keys], cli_windows[keys])
    t0 = rec_back["time_s"].iloc[0]
    np.testing.assert_allclose(ours["windows"]["start_s"] + t0, cli_windows["start_s"],
                               rtol=0, atol=1e-9)


def test_dask_map_partitions_equals_one_process(records, tmp_path):
    dd = pytest.importorskip("dask.dataframe")
    model = hxai.ToolModel.load(MODEL)
    archive = tmp_path / "archive"
    # a fleet's archive: one Parquet partition per record (hive layout record=ID/)
    records.to_parquet(archive, partition_cols=["record"], index=False)

    single = hxai.predict_records(records, model)
    assert len(single) == 4 * 3 and single["a_corr_um"].notna().all()

    ddf = dd.read_parquet(str(archive))
    assert ddf.npartitions == 4
    res = ddf.map_partitions(hxai.predict_records, model, meta=model.meta()).compute()
    res = res.sort_values(["record", "window"]).reset_index(drop=True)
    pd.testing.assert_frame_equal(res, single, check_exact=True)


def test_predict_records_bad_input(records):
    model = hxai.ToolModel.load(MODEL)
    with pytest.raises(ValueError, match="no column `fs_hz`"):
        hxai.predict_records(records.drop(columns="fs_hz"), model)
    bad = records.copy()
    bad.loc[bad.index[5], "frequency_hz"] = 99.0
    with pytest.raises(ValueError, match="constant within a record"):
        hxai.predict_records(bad, model)
    with pytest.raises(ValueError, match="too short|window"):
        model.predict(np.zeros(100), 2000.0, 20.0)
