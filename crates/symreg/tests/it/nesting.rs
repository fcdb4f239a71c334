//! Nesting constraints hold in every model a search returns.
use hxai_symreg::{Nesting, SearchConfig, Table, search};

/// A target whose best short fits nest transcendentals (`exp(-exp(x))`, a Gumbel curve):
/// under the readable constraints no returned model, on the front or selected, nests one
/// transcendental inside another, though without them the search does.
#[test]
fn every_returned_model_keeps_the_constraints() {
    let n = 200;
    let x: Vec<f64> = (0..n).map(|i| -2.0 + 4.0 * i as f64 / n as f64).collect();
    let z: Vec<f64> = (0..n).map(|i| ((i * 31) % 23) as f64 / 23.0).collect();
    let y: Vec<f64> = x.iter().map(|v| (-(-v).exp()).exp()).collect();
    let data = Table::new(vec!["x".into(), "z".into()], vec![x, z]).expect("table");
    let base = SearchConfig {
        epochs: 3,
        candidates_per_epoch: 300,
        ..SearchConfig::default()
    };
    let readable = Nesting::readable().rules().expect("rules");
    let constrained = SearchConfig {
        nesting: Nesting::readable(),
        ..base.clone()
    };
    let res = search(&data, &y, &constrained, &mut |_| {}).expect("search");
    for m in res.pareto.iter().chain(std::iter::once(&res.best)) {
        assert!(readable.allows(&m.program), "{}", m.equation());
    }
    // the constraint is not vacuous on this target: the free search nests
    let free = search(&data, &y, &base, &mut |_| {}).expect("search");
    assert!(
        free.pareto.iter().any(|m| !readable.allows(&m.program)),
        "{:?}",
        free.pareto.iter().map(|m| m.equation()).collect::<Vec<_>>()
    );
}

/// A bad rule is refused before any work, naming the item.
#[test]
fn a_bad_rule_is_refused_by_the_search() {
    let data = Table::new(vec!["x".into()], vec![(0..20).map(f64::from).collect()]).expect("t");
    let y: Vec<f64> = (0..20).map(|i| f64::from(i) * 2.0).collect();
    let mut n = Nesting::none();
    n.0.entry("exp".into())
        .or_default()
        .insert("nope".into(), 0);
    let cfg = SearchConfig {
        nesting: n,
        ..SearchConfig::default()
    };
    let e = search(&data, &y, &cfg, &mut |_| {})
        .expect_err("a bad nesting rule")
        .to_string();
    assert!(e.contains("nope"), "{e}");
}
