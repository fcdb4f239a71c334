//! Consensus selection: the structure the bootstrap searches give back, the same for any
//! thread count.
use hxai_symreg::consensus::STABLE_SHARE;
use hxai_symreg::{SearchConfig, SelectionReport, Table, search};

/// `y = 2 + 3 exp(-0.5 x1)` with a deterministic 1 % wiggle; `x2` and `x3` are distractors.
fn data() -> (Table, Vec<f64>) {
    let n = 160;
    let x1: Vec<f64> = (0..n).map(|i| 0.05 * i as f64).collect();
    let x2: Vec<f64> = (0..n).map(|i| ((i * 37) % 17) as f64).collect();
    let x3: Vec<f64> = (0..n).map(|i| ((i * 11) % 7) as f64 / 7.0).collect();
    let y: Vec<f64> = x1
        .iter()
        .enumerate()
        .map(|(i, v)| {
            (2.0 + 3.0 * (-0.5 * v).exp()) * (1.0 + 0.01 * (((i * 7919) % 13) as f64 - 6.0) / 6.0)
        })
        .collect();
    let t = Table::new(
        vec!["x1".into(), "x2".into(), "x3".into()],
        vec![x1, x2, x3],
    );
    (t.expect("table"), y)
}

fn cfg() -> SearchConfig {
    SearchConfig {
        epochs: 2,
        candidates_per_epoch: 200,
        consensus_runs: 5,
        ..SearchConfig::paper()
    }
}

/// The winner is a structure at least half the runs gave back, it uses the one informative
/// column, the report says so, and one or two threads give the same answer.
#[test]
fn consensus_picks_a_stable_structure_whatever_the_threads() {
    let (t, y) = data();
    let run = |threads: usize| {
        rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .expect("pool")
            .install(|| search(&t, &y, &cfg(), &mut |_| {}))
            .expect("search")
    };
    let one = run(1);
    let two = run(2);
    assert_eq!(one.best, two.best);
    let c = one.consensus.as_ref().expect("a consensus report");
    assert_eq!(c.runs, 5);
    assert!(c.share >= STABLE_SHARE, "{c:?}");
    assert_eq!(c.nominated[0].template, c.structure);
    assert_eq!(
        one.best.features(),
        vec!["x1".to_string()],
        "{}",
        one.best.equation()
    );
    let report = SelectionReport::of(&one, &cfg());
    assert_eq!(report.method, "consensus");
    assert_eq!(report.share, Some(c.share));
    assert_eq!(report.structure, c.structure);
    assert!(report.alternatives.len() <= 3);
}

/// Without consensus the report names the criterion and has no share.
#[test]
fn one_search_reports_its_criterion_and_no_share() {
    let (t, y) = data();
    let cfg = SearchConfig {
        consensus_runs: 0,
        ..cfg()
    };
    let res = search(&t, &y, &cfg, &mut |_| {}).expect("search");
    assert!(res.consensus.is_none());
    let report = SelectionReport::of(&res, &cfg);
    assert_eq!(report.method, "bic");
    assert_eq!(report.share, None);
    assert!(
        report
            .alternatives
            .iter()
            .all(|a| a.structure != report.structure)
    );
    let too_many = SearchConfig {
        consensus_runs: 100_000,
        ..cfg
    };
    assert!(search(&t, &y, &too_many, &mut |_| {}).is_err());
}
