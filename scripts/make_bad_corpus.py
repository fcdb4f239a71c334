"""Write testdata/bad/: small bad input files for crates/cli/tests/it/bad_input.rs.

Run from the repository root with a python that has pyarrow (for the Parquet cases):
    python scripts/make_bad_corpus.py
The model cases are made from testdata/bad/good/model.json (a model fitted by
`hxai fit` on testdata/bad/good/, see README.md there), edited one field at a time.
"""
import json
import math
import os
from pathlib import Path

import pyarrow as pa
import pyarrow.parquet as pq

ROOT = Path("testdata/bad")
FS, F, SECONDS = 500.0, 20.0, 3.0


def signal(n=int(FS * SECONDS), amp=5.0, f=F, fs=FS):
    w = 2 * math.pi * f
    t = [i / fs for i in range(n)]
    accel = [-amp * 1e-6 * w * w * math.sin(w * x) + 1e-4 * (((i * 7919) % 1000) / 1000 - 0.5) for i, x in enumerate(t)]
    probe = [amp * 1.2 * math.sin(w * x) for x in t]
    return t, accel, probe


def csv(path, header, rows):
    path.parent.mkdir(parents=True, exist_ok=True)
    with open(path, "w", newline="") as f:
        f.write(",".join(header) + "\n")
        for r in rows:
            f.write(",".join(str(v) for v in r) + "\n")


def good():
    d = ROOT / "good"
    manifest = []
    for k, amp in enumerate([4.0, 6.0, 8.0, 10.0]):
        t, a, p = signal(amp=amp)
        name = f"r{k + 1}.parquet"
        d.mkdir(parents=True, exist_ok=True)
        pq.write_table(pa.table({"time_s": t, "accel_ms2": a, "probe_um": p}), d / name)
        manifest.append((f"r{k + 1}", name, amp, F))
    csv(d / "manifest.csv", ["record", "file", "amplitude_um", "frequency_hz"], manifest)


def records():
    d = ROOT / "records"
    t, a, p = signal()
    rows = list(zip(t, a, p))[:200]  # the CSV cases fail before length matters
    csv(d / "duplicate_column.csv", ["time_s", "accel_ms2", "accel_ms2"], [(x, y, 0.0) for x, y, _ in rows])
    ragged = [list(r) for r in rows[:50]]
    ragged[9] = ragged[9][:2]
    csv(d / "ragged_row.csv", ["time_s", "accel_ms2", "probe_um"], ragged)
    bad = [list(r) for r in rows]
    bad[4][1] = "n/a"
    csv(d / "text_cell.csv", ["time_s", "accel_ms2", "probe_um"], bad)
    bad = [list(r) for r in rows]
    bad[6][1] = "nan"
    csv(d / "nan_cell.csv", ["time_s", "accel_ms2", "probe_um"], bad)
    bad = [list(r) for r in rows]
    bad[10][0] = bad[8][0]
    csv(d / "time_not_increasing.csv", ["time_s", "accel_ms2", "probe_um"], bad)
    bad = [list(r) for k, r in enumerate(rows) if k != 100]
    csv(d / "time_gap.csv", ["time_s", "accel_ms2", "probe_um"], bad)
    csv(d / "two_samples.csv", ["time_s", "accel_ms2"], [(0.0, 0.1), (0.001, -0.1)])
    csv(d / "short_with_probe.csv", ["time_s", "accel_ms2", "probe_um"], rows[:100])
    csv(d / "missing_time.csv", ["t", "accel_ms2"], [(x, y) for x, y, _ in rows[:20]])
    csv(d / "header_only.csv", ["time_s", "accel_ms2"], [])
    (d / "empty.csv").write_bytes(b"")
    (d / "binary.csv").write_bytes(bytes(range(256)) * 4)
    (d / "latin1.csv").write_bytes("time_s,accel_ms2,temp_\xb0C\n0,1,2\n".encode("latin-1"))
    csv(d / "huge_number.csv", ["time_s", "accel_ms2"], [(x, "1e400" if i == 3 else y) for i, (x, y, _) in enumerate(rows)])
    csv(d / "record.txt", ["time_s", "accel_ms2"], [(x, y) for x, y, _ in rows[:20]])
    # Parquet types hxai refuses by name, and time stored as integers.
    n = len(t)
    pq.write_table(pa.table({"time_s": t, "accel_ms2": pa.array([float(v) for v in a], pa.float16())}), d / "float16.parquet")
    import decimal
    pq.write_table(
        pa.table({"time_s": t, "accel_ms2": pa.array([decimal.Decimal(f"{v:.6f}") for v in a], pa.decimal128(12, 6))}),
        d / "decimal128.parquet",
    )
    pq.write_table(pa.table({"time_s": pa.array([i * 1_000_000 for i in range(n)], pa.int64()), "accel_ms2": a}), d / "time_ns_int64.parquet")
    pq.write_table(pa.table({"time_s": pa.array([i * 1_000_000 for i in range(n)], pa.timestamp("ns")), "accel_ms2": a}), d / "time_timestamp.parquet")
    # Integer acceleration (ADC counts) of 32 and 64 bits decodes: not an error; 8 and 16
    # bits are refused by name (polars would need extra features to decode them).
    pq.write_table(pa.table({"time_s": t, "accel_ms2": pa.array([int(v * 1000) for v in a], pa.int32()), "probe_um": pa.array([int(v) + 10 for v in p], pa.uint64()), "x": pa.array([1] * len(t), pa.int64()), "z": pa.array([1] * len(t), pa.uint32())}), d / "int_channels.parquet")
    pq.write_table(pa.table({"time_s": t, "accel_ms2": pa.array([int(v * 1000) for v in a], pa.int16())}), d / "int16.parquet")
    pq.write_table(pa.table({"time_s": t, "accel_ms2": pa.array([int(v) % 100 for v in a], pa.uint8())}), d / "uint8.parquet")
    (d / "csv_named.parquet").write_text("time_s,accel_ms2\n0,1\n0.001,2\n")
    good_bytes = (ROOT / "good" / "r1.parquet").read_bytes()
    (d / "truncated.parquet").write_bytes(good_bytes[: len(good_bytes) // 2])
    tbl = pa.table({"time_s": t, "accel_ms2": a, "x": t})
    tbl = tbl.rename_columns(["time_s", "accel_ms2", "accel_ms2"])
    pq.write_table(tbl, d / "duplicate_column.parquet")


def tables():
    d = ROOT / "tables"
    csv(d / "duplicate_y.csv", ["x", "y", "y"], [(i, 2 * i + 1, i * i) for i in range(30)])
    csv(d / "text_column.csv", ["x", "name", "y"], [(i, f"n{i}", 2 * i) for i in range(30)])
    csv(d / "empty_name.csv", ["x", "", "y"], [(i, i, 2 * i) for i in range(30)])
    csv(d / "target_only.csv", ["y"], [(i,) for i in range(30)])
    csv(d / "good.csv", ["x", "y"], [(i / 10, 3 * i / 10 + 1) for i in range(30)])


def folders():
    d = ROOT / "folders"
    h = ["record", "file", "amplitude_um", "frequency_hz"]
    csv(d / "shared_file" / "manifest.csv", h, [("a", "../../good/r1.parquet", 4, 20), ("b", "../../good/r1.parquet", 4, 20), ("c", "../../good/r2.parquet", 6, 20)])
    csv(d / "same_file_two_spellings" / "manifest.csv", h, [("a", "../../good/r1.parquet", 4, 20), ("b", "../../good/./r1.parquet", 4, 20)])
    for name, f in [("frequency_300hz", 300), ("frequency_0_5hz", 0.5), ("frequency_4000hz", 4000)]:
        csv(d / name / "manifest.csv", h, [(f"r{k}", f"../../good/r{k}.parquet", 4 + 2 * (k - 1), f) for k in range(1, 5)])
    csv(d / "record_is_folder" / "manifest.csv", h, [("a", "../../good", 4, 20)])
    csv(d / "missing_file" / "manifest.csv", h, [("a", "nowhere.parquet", 4, 20)])
    csv(d / "short_records" / "manifest.csv", h, [("a", "../../records/short_with_probe.csv", 4, 20), ("b", "../../good/r1.parquet", 4, 20)])
    csv(d / "negative_frequency" / "manifest.csv", h, [("a", "../../good/r1.parquet", 4, -20)])
    csv(d / "probe_in_mm" / "manifest.csv", h, [(f"r{k}", f"../../good/r{k}.parquet", 4000 + 2000 * (k - 1), 20) for k in range(1, 5)])


def configs():
    d = ROOT / "configs"
    d.mkdir(parents=True, exist_ok=True)
    (d / "typo_key.json").write_text('{"seeed": 3}\n')
    (d / "not_json.json").write_text("seed = 3\n")


def models():
    d = ROOT / "models"
    src = ROOT / "good" / "model.json"
    if not src.exists():
        print(f"{src} missing: fit it first (see testdata/bad/README.md); model cases skipped")
        return
    base = json.loads(src.read_text())

    def edit(name, fn):
        m = json.loads(json.dumps(base))
        fn(m)
        (d / name).write_text(json.dumps(m, indent=1) + "\n")

    d.mkdir(parents=True, exist_ok=True)

    def index7(m):
        m["correction"]["model"]["feature_names"] = m["correction"]["model"]["feature_names"][:2]
        nodes = m["correction"]["model"]["program"]["nodes"]
        for i, node in enumerate(nodes):
            if isinstance(node, dict) and "var" in node:
                nodes[i] = {"var": 7}
    edit("input_index_out_of_range.json", index7)
    edit("schema_version_text.json", lambda m: m.__setitem__("schema_version", "1"))
    edit("schema_version_2.json", lambda m: m.__setitem__("schema_version", 2))
    edit("window_1e18.json", lambda m: m["window"].__setitem__("length_s", 1e18))
    edit("discard_1e300.json", lambda m: m["window"].__setitem__("discard_s", 1e300))
    edit("order_100000.json", lambda m: m["physics"].__setitem__("order", 100000))
    edit("params_missing.json", lambda m: m["correction"]["model"].__setitem__("params", []))
    edit("feature_names_renamed.json", lambda m: m["features"].__setitem__("names", [f"g{i}" for i in range(1, 13)]))
    (d / "truncated.json").write_text(src.read_text()[:200])


if __name__ == "__main__":
    good()
    records()
    tables()
    folders()
    configs()
    models()
