"""Check that hxai's sympy export reads back with plain `sympy.sympify`.

Reads one JSON document on stdin: {"cases": [{"name": N, "text": T}, ...], "sum": S}, where T
is how the export writes the column name N, and S is the export of an expression that uses
every name once (sum of k * name_k). Checks that each T sympifies to exactly Symbol(N), and
that S has exactly the names as free symbols, all distinct. Prints one line per failure and
exits 1 on any; prints "ok: N names" and exits 0 otherwise.

Used by crates/symreg/tests/it/sympy_export.rs when HXAI_PYTHON names a python with sympy.
"""
import json
import sys

import sympy


def main() -> int:
    doc = json.load(sys.stdin)
    failures = []
    names = []
    for case in doc["cases"]:
        name, text = case["name"], case["text"]
        names.append(name)
        try:
            got = sympy.sympify(text)
        except Exception as e:  # noqa: BLE001 - any failure is a finding
            failures.append(f"{name!r}: sympify({text!r}) failed: {type(e).__name__}: {e}")
            continue
        if got != sympy.Symbol(name):
            failures.append(f"{name!r}: sympify({text!r}) gave {got!r} ({type(got).__name__}), not Symbol({name!r})")
    try:
        total = sympy.sympify(doc["sum"])
        found = sorted(s.name for s in total.free_symbols)
        if found != sorted(names):
            missing = sorted(set(names) - set(found))
            extra = sorted(set(found) - set(names))
            failures.append(f"sum: free symbols differ; missing {missing}, unexpected {extra}")
    except Exception as e:  # noqa: BLE001
        failures.append(f"sum: sympify failed: {type(e).__name__}: {e}")
    for f in failures:
        print(f)
    if failures:
        return 1
    print(f"ok: {len(names)} names (sympy {sympy.__version__})")
    return 0


if __name__ == "__main__":
    sys.exit(main())
