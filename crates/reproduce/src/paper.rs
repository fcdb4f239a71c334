//! The numbers the paper publishes (its Table 3, cross-validation, equation and hybrid
//! against physics), printed beside ours in every table. Nothing here feeds a computation.

/// SR on delta, 80/20 hold-out: R^2.
pub const SR_TEST_R2: f64 = 0.945;
/// SR on delta, 80/20 hold-out: RMSE (um).
pub const SR_TEST_RMSE: f64 = 1.26;
/// SR on delta, published complexity.
pub const SR_COMPLEXITY: usize = 5;
/// Models evaluated by the paper's QLattice run.
pub const SR_EVALUATIONS: u64 = 11_296;
/// The paper's equation (eq. 12-13), as printed.
pub const SR_EQUATION: &str =
    "delta = 29.4 e^k - 9.71, k = -3980 (1 - 0.018 f1)^2 (f6 - 0.02)^2 - (0.044 f2 - 1)^2";

/// 5-fold CV on delta: (metric, mean, sd, normal-approximation CI low, high).
pub const CV: [(&str, f64, f64, f64, f64); 3] = [
    ("R2", 0.9213, 0.0178, 0.9057, 0.9369),
    ("RMSE", 1.4658, 0.2588, 1.2389, 1.6927),
    ("MAE", 1.1081, 0.1712, 0.9581, 1.2581),
];

/// Table 3 R^2 on delta by model name (our names); `None` where the paper gives none.
pub fn table3_r2(name: &str) -> Option<f64> {
    match name {
        "lasso_cv" => Some(0.823),
        "tree_5" => Some(0.85),
        "tree_6" => Some(0.91),
        "tree_8" => Some(0.926),
        "forest" => Some(0.814),
        "symbolic" => Some(SR_TEST_R2),
        _ => None,
    }
}

/// Displacement, physics model: RMSE (um).
pub const PHYSICS_RMSE_UM: f64 = 2.87;
/// Displacement, physics model: R^2.
pub const PHYSICS_R2: f64 = 0.814;
/// Displacement, hybrid model: RMSE (um).
pub const HYBRID_RMSE_UM: f64 = 0.6529;
/// Displacement, hybrid model: R^2.
pub const HYBRID_R2: f64 = 0.974;
/// RMSE improvement (%).
pub const IMPROVEMENT_PCT: f64 = 77.27;
/// R^2 change (%).
pub const R2_CHANGE_PCT: f64 = 19.65;
/// Paired t-test p-value.
pub const P_VALUE: f64 = 5.97e-8;
