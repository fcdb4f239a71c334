#!/usr/bin/env python3
"""Reference results of scikit-learn's Table 3 baselines for hxai-baselines.

Run: `cargo xtask refs` (all ref scripts, pinned versions from scripts/requirements.txt), or
`python3 scripts/ref_baselines.py` in an environment with those versions.
Writes testdata/baselines/reference.json. Not run by CI.
All features are continuous random draws, so no two values tie (tree splits are unique).
"""
import json
import pathlib

import numpy as np
import sklearn
from sklearn.ensemble import RandomForestRegressor
from sklearn.linear_model import LassoCV, LinearRegression
from sklearn.metrics import r2_score
from sklearn.tree import DecisionTreeRegressor

from _common import write_atomic

rng = np.random.default_rng(7)
out = {"versions": {"numpy": np.__version__, "sklearn": sklearn.__version__}}


def rows(a):
    return [list(map(float, r)) for r in a]


# Linear regression: noisy linear data, 60 x 5.
X = rng.normal(0.0, 1.0, (60, 5)) * [1.0, 2.0, 0.5, 3.0, 1.0] + [0.0, 1.0, -2.0, 5.0, 0.3]
y = X @ [1.5, -2.0, 0.0, 0.7, 3.0] + 4.0 + rng.normal(0.0, 0.5, 60)
m = LinearRegression().fit(X, y)
out["linear"] = {"x": rows(X), "y": y.tolist(), "coef": m.coef_.tolist(), "intercept": float(m.intercept_)}

# LassoCV(cv=3): 90 x 8, three irrelevant features, correlated columns.
X = rng.normal(0.0, 1.0, (90, 8))
X[:, 3] += 0.6 * X[:, 0]
y = X @ [2.0, -1.0, 0.5, 0.0, 0.0, 1.2, 0.0, 0.1] + 1.0 + rng.normal(0.0, 1.0, 90)
m = LassoCV(cv=3).fit(X, y)
out["lasso"] = {"x": rows(X), "y": y.tolist(), "alpha": float(m.alpha_), "alphas": m.alphas_.tolist(),
                "coef": m.coef_.tolist(), "intercept": float(m.intercept_),
                "mse_path": rows(m.mse_path_)}

# Best-first trees: 150 train / 50 test, 4 features, nonlinear target.
X = rng.uniform(-2.0, 2.0, (200, 4))
y = np.sin(2.0 * X[:, 0]) + X[:, 1] ** 2 - 0.5 * X[:, 2] * X[:, 3] + rng.normal(0.0, 0.1, 200)
xtr, ytr, xte = X[:150], y[:150], X[150:]
trees = {}
for k in (5, 6, 8):
    t = DecisionTreeRegressor(max_leaf_nodes=k, random_state=0).fit(xtr, ytr)
    trees[str(k)] = {"train_pred": t.predict(xtr).tolist(), "test_pred": t.predict(xte).tolist(),
                     "n_leaves": int(t.get_n_leaves())}
out["tree"] = {"x_train": rows(xtr), "y_train": ytr.tolist(), "x_test": rows(xte), "models": trees}

# Random forest: Friedman #1 style, 300 train / 100 test, 6 features.
X = rng.uniform(0.0, 1.0, (400, 6))
y = (10 * np.sin(np.pi * X[:, 0] * X[:, 1]) + 20 * (X[:, 2] - 0.5) ** 2 + 10 * X[:, 3] + 5 * X[:, 4]
     + rng.normal(0.0, 1.0, 400))
xtr, ytr, xte, yte = X[:300], y[:300], X[300:], y[300:]
f = RandomForestRegressor(n_estimators=200, random_state=42).fit(xtr, ytr)
out["forest"] = {"x_train": rows(xtr), "y_train": ytr.tolist(), "x_test": rows(xte), "y_test": yte.tolist(),
                 "test_r2": float(r2_score(yte, f.predict(xte)))}

path = pathlib.Path(__file__).resolve().parent.parent / "testdata" / "baselines" / "reference.json"
write_atomic(path, json.dumps(out))
print(f"wrote {path}")
print("lasso alpha", m.alpha_ if False else out["lasso"]["alpha"], "forest r2", out["forest"]["test_r2"])
