"""A table hybrid's prediction as a pure function of a DataFrame (`hxai.predict_table`),
on one process and under Dask's map_partitions over a partitioned Parquet dataset:
identical results (issue 67)."""

import subprocess

import numpy as np
import pandas as pd
import pytest

import hxai
from conftest import hxai_binary

FAST = dict(epochs=2, candidates_per_epoch=200, conformal_folds=0)
PHYSICS = "1000*feed_mm^2/(32*nose_radius_mm) + Ra0"


@pytest.fixture(scope="module")
def fitted():
    rows = hxai.simulate("roughness", n_rows=300, seed=5)
    X = rows.drop(columns=["Ra_um", "tool"])
    est = hxai.HybridRegressor(
        PHYSICS, calibrate=["Ra0"], init={"Ra0": 0.0}, correction="multiplicative",
        form="factors", **FAST,
    ).fit(X, rows["Ra_um"])
    fresh = hxai.simulate("roughness", n_rows=2000, seed=6)
    fresh.insert(0, "id", np.arange(len(fresh)))
    return est, fresh


def test_predict_table_equals_the_estimator(fitted):
    est, fresh = fitted
    X = fresh.drop(columns=["id", "Ra_um", "tool"])
    parts = est.predict_parts(X)
    # the text column and the extra numeric ones are ignored; the index is the frame's
    shifted = fresh.set_index(fresh.index + 100)
    for model in (est, est.model_json_):
        got = hxai.predict_table(shifted, model)
        assert list(got.index) == list(shifted.index)
        pd.testing.assert_frame_equal(got.reset_index(drop=True), parts, check_exact=True)


def test_predict_table_equals_the_command_line(fitted, tmp_path):
    est, fresh = fitted
    model, data, out = tmp_path / "m.json", tmp_path / "d.csv", tmp_path / "p.csv"
    model.write_text(est.model_json_)
    fresh.to_csv(data, index=False, float_format="%.17g")
    subprocess.run([hxai_binary(), "hybrid", "predict", "--model", str(model), "--data",
                    str(data), "--out", str(out)], check=True, capture_output=True)
    cli = pd.read_csv(out)
    ours = hxai.predict_table(pd.read_csv(data), est.model_json_)
    np.testing.assert_allclose(ours["hybrid"], cli["hybrid"], rtol=1e-12, atol=0)


def test_dask_map_partitions_equals_one_process(fitted, tmp_path):
    dd = pytest.importorskip("dask.dataframe")
    est, fresh = fitted
    dataset = tmp_path / "dataset"
    # a partitioned Parquet dataset: 4 partitions by a key column (hive layout part=K/)
    fresh.assign(part=fresh["id"] % 4).to_parquet(dataset, partition_cols=["part"],
                                                  index=False)
    ddf = dd.read_parquet(str(dataset))
    assert ddf.npartitions == 4
    text = est.model_json_
    res = ddf.map_partitions(hxai.predict_table, text, meta=hxai.table.meta()).compute()
    whole = ddf.compute()
    single = hxai.predict_table(whole, text)
    pd.testing.assert_frame_equal(res.reset_index(drop=True), single.reset_index(drop=True),
                                  check_exact=True)
    # and row by row the values of the estimator on the original frame
    by_id = single.assign(id=whole["id"].to_numpy()).sort_values("id")
    parts = est.predict_parts(fresh.drop(columns=["id", "Ra_um", "tool"]))
    np.testing.assert_array_equal(by_id["hybrid"].to_numpy(), parts["hybrid"].to_numpy())
    # the estimator's own predict, partition by partition
    feats = [c for c in fresh.columns if c not in ("id", "Ra_um", "tool")]
    est_res = ddf.map_partitions(
        lambda p: pd.Series(est.predict(p[feats]), index=p.index, name="hybrid"),
        meta=pd.Series(dtype="float64", name="hybrid"),
    ).compute()
    np.testing.assert_array_equal(est_res.to_numpy(), single["hybrid"].to_numpy())


def test_predict_table_bad_input(fitted):
    est, fresh = fitted
    with pytest.raises(ValueError, match="DataFrame"):
        hxai.predict_table(fresh.to_numpy(), est)
    with pytest.raises(ValueError, match="fitted HybridRegressor or the JSON text"):
        hxai.predict_table(fresh, hxai.HybridRegressor(PHYSICS))
    with pytest.raises(ValueError, match="feed_mm"):
        hxai.predict_table(fresh.drop(columns=["feed_mm"]), est)
