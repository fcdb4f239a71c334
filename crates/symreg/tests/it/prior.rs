//! The prior over structures learned from written laws (`SearchConfig::prior`, issue 65):
//! under the description length, a straight line through six noisy points of a
//! calibration beats a cosine that fits them a little better.
#![allow(clippy::unwrap_used)]
use hxai_symreg::{Criterion, Node, Op, Prior, SearchConfig, Table, search};

/// `hxai sr`'s defaults that matter here, with `prior`.
fn sr_config(prior: Prior) -> SearchConfig {
    SearchConfig {
        prior,
        ..crate::common::sr_defaults()
    }
}

/// Six standards of a calibration line `0.02 + 0.4 c` read with a normal scatter of 0.012
/// (one draw, written out). Under the uniform prior the same search picks
/// `-1.59*exp(-(0.322*c + 0.29)**2) + 1.5` on these rows (measured 2026-12-06).
fn calibration() -> (Table, Vec<f64>) {
    let c = vec![0.1, 0.5, 1.0, 1.5, 2.0, 2.5];
    let y = vec![0.066, 0.1985, 0.4107, 0.6209, 0.8377, 1.0201];
    (Table::new(vec!["c".into()], vec![c]).unwrap(), y)
}

#[test]
fn a_line_through_six_noisy_points_beats_a_cosine() {
    let (data, y) = calibration();
    let cfg = sr_config(Prior::Laws);
    let r = search(&data, &y, &cfg, &mut |_| {}).unwrap();
    let best = &r.best;
    for op in [Op::Sin, Op::Cos, Op::Tanh, Op::Gaussian] {
        assert!(
            !best.program.nodes.contains(&Node::Op(op)),
            "{op:?} in {}",
            best.equation()
        );
    }
    // it extrapolates like the line: twice the largest standard within 5 %
    let probe = Table::new(vec!["c".into()], vec![vec![5.0]]).unwrap();
    let p = best.predict(&probe).unwrap()[0];
    assert!(
        (p - 2.02).abs() < 0.05 * 2.02,
        "{p} at c = 5: {}",
        best.equation()
    );
    let sel = hxai_symreg::SelectionReport::of(&r, &cfg);
    assert_eq!(sel.prior.as_deref(), Some("laws"));
}

/// The prior is read by the description length and by cross-validation's pick, and named
/// only there.
#[test]
fn other_criteria_do_not_name_a_prior() {
    let (data, y) = calibration();
    let named = |criterion: Criterion, prior: Prior| {
        let cfg = SearchConfig {
            criterion,
            ..sr_config(prior)
        };
        let r = search(&data, &y, &cfg, &mut |_| {}).unwrap();
        hxai_symreg::SelectionReport::of(&r, &cfg).prior
    };
    assert!(named(Criterion::Bic, Prior::Laws).is_none());
    assert_eq!(
        named(Criterion::CrossValidation, Prior::Uniform).as_deref(),
        Some("uniform")
    );
}

/// The search's report shows each model's two codelengths under the description length
/// (the selected one, every model of the Pareto front, every alternative), the structure's
/// being the prior's price of its program; other criteria show none.
#[test]
fn the_report_shows_each_models_two_codelengths() {
    let (data, y) = calibration();
    let report = |cfg: &SearchConfig| {
        let r = search(&data, &y, cfg, &mut |_| {}).unwrap();
        let unc = r.best.uncertainty(&data, &y).unwrap();
        let rep = hxai_symreg::SearchReport::of(&r, cfg, (&data, &y), &unc, false, None).unwrap();
        (r, rep)
    };
    let cfg = sr_config(Prior::Laws);
    let (r, rep) = report(&cfg);
    let prior = hxai_symreg::prior::LawPrior::builtin();
    let best = rep.best.codelength.expect("the best's codelengths");
    assert!((best.structure - prior.codelength_program(&r.best.program)).abs() < 1e-12);
    assert!(best.parameters >= 0.0);
    assert!(!rep.pareto.is_empty());
    assert!(rep.pareto.iter().all(|s| s.codelength.is_some()));
    assert!(
        rep.selection
            .alternatives
            .iter()
            .all(|a| a.codelength.is_some())
    );
    // the uniform prior prices a structure by its complexity
    let cfg = sr_config(Prior::Uniform);
    let (r, rep) = report(&cfg);
    let symbols = (cfg.operators.len() + 1) as f64;
    let best = rep.best.codelength.expect("the best's codelengths");
    assert!((best.structure - r.best.complexity as f64 * symbols.ln()).abs() < 1e-12);
    let cfg = SearchConfig {
        criterion: Criterion::Bic,
        ..sr_config(Prior::Laws)
    };
    let (_, rep) = report(&cfg);
    assert!(rep.best.codelength.is_none());
    assert!(rep.pareto.iter().all(|s| s.codelength.is_none()));
}
