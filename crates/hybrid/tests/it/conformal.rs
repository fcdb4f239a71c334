//! The promise of the table hybrid's conformal intervals (issue 28 item 4): on simulated
//! tables with homoscedastic, multiplicative (log-normal) and heteroscedastic noise, the
//! 95 % intervals cover fresh rows at 95 % within three binomial standard errors, and their
//! median width is at most 1.5 times the width of the true noise's own 95 % band.
//!
//! Coverage is checked on every row, and apart on the rows where `f` is low and where it is
//! high: a band of constant width (the delta method's) passes the first under scatter that
//! grows with `f` but not the others (measured when this test was written: 99.8 % and 84 %
//! under the multiplicative noise).
//!
//! Each case fits `DRAWS` seeded tables of `N_TRAIN` rows (a small search: the guarantee is
//! about the intervals, whatever the correction found) and scores `M_TEST` fresh rows of
//! each. The pooled coverage of `DRAWS * M_TEST` rows is not quite binomial: rows scored
//! against one calibration set share its luck. With `M_TEST` small against `N_TRAIN` the
//! design effect is `1 + M_TEST / N_TRAIN` at most (split conformal's coverage given the
//! calibration set has variance `P (1 - P) / n`), here 1.2, so the standard error is taken
//! as binomial times `sqrt(1.2)`.
#![allow(clippy::unwrap_used)]
use hxai_eval::Split;
use hxai_hybrid::IntervalMethod;
use hxai_hybrid::tables::{CorrectionForm, ResidualScale, TableConfig, fit_split};
use hxai_symreg::Table;
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use rand_distr::{Distribution, Normal};

const DRAWS: u64 = 80;
const N_TRAIN: usize = 200;
const M_TEST: usize = 40;
const LEVEL: f64 = 0.95;
/// `z_{0.975}`, the half-width of the true noise's 95 % band in standard deviations.
const Z975: f64 = 1.959_963_984_540_054;

#[derive(Clone, Copy, Debug)]
enum Noise {
    /// `y = f(x) + N(0, 0.1)`.
    Homoscedastic,
    /// `y = f(x) exp(N(0, 0.08))`.
    Multiplicative,
    /// As `Multiplicative`, fitted with the log correction form `y = f_p exp(delta)`.
    LogForm,
    /// `y = f(x) + N(0, 0.03 f(x))`.
    Heteroscedastic,
}

impl Noise {
    /// The true `f(x)`; `f` runs from 2 to about 10.
    fn truth(self, x1: f64, x2: f64) -> f64 {
        match self {
            Noise::Multiplicative | Noise::LogForm => 2.0 * x1 * (1.0 + 0.3 * x2),
            _ => 2.0 * x1 + 1.5 * x2 * x2,
        }
    }

    fn draw(self, f: f64, rng: &mut ChaCha8Rng) -> f64 {
        let e = Normal::new(0.0, 1.0).unwrap().sample(rng);
        match self {
            Noise::Homoscedastic => f + 0.1 * e,
            Noise::Multiplicative | Noise::LogForm => f * (0.08 * e).exp(),
            Noise::Heteroscedastic => f + 0.03 * f * e,
        }
    }

    /// The width of the true noise's central 95 % band at `f`.
    fn band(self, f: f64) -> f64 {
        match self {
            Noise::Homoscedastic => 2.0 * Z975 * 0.1,
            Noise::Multiplicative | Noise::LogForm => {
                f * ((0.08 * Z975).exp() - (-0.08 * Z975).exp())
            }
            Noise::Heteroscedastic => 2.0 * Z975 * 0.03 * f,
        }
    }

    fn correction(self) -> CorrectionForm {
        match self {
            Noise::Multiplicative => CorrectionForm::Multiplicative,
            Noise::LogForm => CorrectionForm::Log,
            _ => CorrectionForm::Additive,
        }
    }
}

/// `n` rows of `x1` in [1, 4], `x2` in [0, 1], `y`; and each row's `f(x)` and true band
/// width.
fn table(noise: Noise, n: usize, rng: &mut ChaCha8Rng) -> (Table, Vec<f64>, Vec<f64>) {
    let mut cols: Vec<Vec<f64>> = vec![Vec::new(); 3];
    let mut truth = Vec::with_capacity(n);
    let mut band = Vec::with_capacity(n);
    for _ in 0..n {
        let x1: f64 = rng.gen_range(1.0..4.0);
        let x2: f64 = rng.gen_range(0.0..1.0);
        let f = noise.truth(x1, x2);
        for (c, v) in cols.iter_mut().zip([x1, x2, noise.draw(f, rng)]) {
            c.push(v);
        }
        band.push(noise.band(f));
        truth.push(f);
    }
    let names = ["x1", "x2", "y"].iter().map(|s| s.to_string()).collect();
    (Table::new(names, cols).unwrap(), truth, band)
}

fn config(noise: Noise, seed: u64) -> TableConfig {
    let mut cfg = TableConfig::new("y", "k*x1");
    cfg.calibrate = vec!["k".into()];
    cfg.correction = noise.correction();
    cfg.seed = seed;
    // Two epochs: with one (100 candidates) the default selection, cross-validated loss
    // under the one-standard-error rule, often took a correction that misses part of the
    // truth, and the heteroscedastic case's coverage at low `f` fell to 92.1 % (all rows
    // stayed within the band): a misfit model, not the intervals, is then what fails.
    cfg.search.epochs = 2;
    cfg.search.candidates_per_epoch = 100;
    cfg.search.max_complexity = 5;
    cfg
}

/// What one method gives on one case: rows covered of rows scored, overall and where the
/// true `f` is low (below `LOW_F`) and high (above `HIGH_F`), and the median of each row's
/// width over its true band's.
struct Measured {
    all: (usize, usize),
    low: (usize, usize),
    high: (usize, usize),
    width: f64,
}

/// The low end of `f`: about the lowest quarter of the rows.
const LOW_F: f64 = 4.0;
/// The high end of `f`: about the highest quarter of the rows.
const HIGH_F: f64 = 7.5;

fn measure(noise: Noise, method: IntervalMethod) -> Measured {
    let mut m = Measured {
        all: (0, 0),
        low: (0, 0),
        high: (0, 0),
        width: 0.0,
    };
    let mut ratios = Vec::new();
    for draw in 0..DRAWS {
        let mut rng = ChaCha8Rng::seed_from_u64(1000 * draw + noise as u64);
        let (train, _, _) = table(noise, N_TRAIN, &mut rng);
        let (test, truth, band) = table(noise, M_TEST, &mut rng);
        let split = Split {
            train: (0..N_TRAIN).collect(),
            test: Vec::new(),
        };
        let model = fit_split(&train, &config(noise, draw), &split, &mut |_| {}).unwrap();
        // multiplicative scatter is scored on the log scale, for both forms that multiply
        let scale = model.conformal.as_ref().unwrap().scale;
        let log = matches!(noise, Noise::Multiplicative | Noise::LogForm);
        assert_eq!(
            scale == ResidualScale::Log,
            log,
            "{noise:?}: scale {scale:?}"
        );
        let iv = model.intervals_with(&test, LEVEL, method).unwrap();
        let y = test.require("y").unwrap();
        for (((t, (lo, hi)), b), f) in y.iter().zip(&iv).zip(&band).zip(&truth) {
            let hit = usize::from(lo <= t && t <= hi);
            let count = |c: &mut (usize, usize)| {
                c.0 += hit;
                c.1 += 1;
            };
            count(&mut m.all);
            if *f < LOW_F {
                count(&mut m.low);
            }
            if *f > HIGH_F {
                count(&mut m.high);
            }
            ratios.push((hi - lo) / b);
        }
    }
    ratios.sort_by(f64::total_cmp);
    m.width = ratios[ratios.len() / 2];
    m
}

/// Coverage of `(covered, scored)` within three standard errors of `LEVEL`.
fn within(noise: Noise, what: &str, (covered, n): (usize, usize)) {
    let design = 1.0 + M_TEST as f64 / N_TRAIN as f64;
    let se = (LEVEL * (1.0 - LEVEL) / n as f64 * design).sqrt();
    let coverage = covered as f64 / n as f64;
    assert!(
        (coverage - LEVEL).abs() <= 3.0 * se,
        "{noise:?}, {what}: coverage {coverage:.4} of {n} rows outside {LEVEL} +- 3 x {se:.4}"
    );
}

/// Coverage overall and at both ends of `f` (where a band of constant width fails under
/// scatter that grows with `f`), and the median width.
fn check(noise: Noise) {
    let m = measure(noise, IntervalMethod::Conformal);
    within(noise, "all rows", m.all);
    within(noise, "rows of low f", m.low);
    within(noise, "rows of high f", m.high);
    assert!(
        m.width <= 1.5,
        "{noise:?}: median width {:.3} x the true band's",
        m.width
    );
}

#[test]
fn conformal_keeps_its_promise_under_homoscedastic_noise() {
    check(Noise::Homoscedastic);
}

#[test]
fn conformal_keeps_its_promise_under_multiplicative_noise() {
    check(Noise::Multiplicative);
}

#[test]
fn conformal_keeps_its_promise_under_multiplicative_noise_with_the_log_form() {
    check(Noise::LogForm);
}

#[test]
fn conformal_keeps_its_promise_under_heteroscedastic_noise() {
    check(Noise::Heteroscedastic);
}

/// One quick fit of the homoscedastic case on `n` rows with `folds` conformal folds.
fn quick_fit(
    n: usize,
    folds: usize,
) -> Result<(hxai_hybrid::tables::TableModel, Table), hxai_hybrid::HybridError> {
    let mut rng = ChaCha8Rng::seed_from_u64(7);
    let (train, _, _) = table(Noise::Homoscedastic, n, &mut rng);
    let mut cfg = config(Noise::Homoscedastic, 7);
    cfg.conformal_folds = folds;
    let split = Split {
        train: (0..n).collect(),
        test: Vec::new(),
    };
    let model = fit_split(&train, &cfg, &split, &mut |_| {})?;
    Ok((model, train))
}

#[test]
fn the_model_file_keeps_the_calibration_and_old_files_fall_back_to_delta() {
    use hxai_hybrid::tables::TableModel;
    let (model, t) = quick_fit(60, 5).unwrap();
    let conf = model.conformal.as_ref().unwrap();
    assert_eq!(conf.folds, 5);
    assert_eq!(conf.scores.len(), 60);
    let back = TableModel::from_json(&model.to_json()).unwrap();
    assert_eq!(back, model);
    assert_eq!(
        back.default_interval_method(LEVEL),
        Some(IntervalMethod::Conformal)
    );
    let ev = back.evaluate_at(&t, LEVEL).unwrap();
    let iv = ev.interval.unwrap();
    assert_eq!(iv.method, IntervalMethod::Conformal);
    assert_eq!(iv.n, 60);
    assert!(iv.median_width.unwrap() > 0.0);

    // a file written before the key existed: delta by default, conformal refused by name
    let mut old: serde_json::Value = serde_json::from_str(&model.to_json()).unwrap();
    old.as_object_mut().unwrap().remove("conformal");
    let old = TableModel::from_json(&old.to_string()).unwrap();
    assert_eq!(
        old.default_interval_method(LEVEL),
        Some(IntervalMethod::Delta)
    );
    assert_eq!(
        old.evaluate_at(&t, LEVEL).unwrap().interval.unwrap().method,
        IntervalMethod::Delta
    );
    let e = old
        .intervals_with(&t, LEVEL, IntervalMethod::Conformal)
        .unwrap_err()
        .to_string();
    assert!(e.contains("no conformal calibration"), "{e}");

    // a calibration that does not fit the model is refused on the way in
    let mut bad: serde_json::Value = serde_json::from_str(&model.to_json()).unwrap();
    bad["conformal"]["scores"] = serde_json::json!([1.0, 2.0]);
    let e = TableModel::from_json(&bad.to_string())
        .unwrap_err()
        .to_string();
    assert!(e.contains("conformal"), "{e}");
}

#[test]
fn bad_levels_and_too_few_rows_are_errors_that_say_what_to_do() {
    let (model, t) = quick_fit(60, 5).unwrap();
    for level in [0.0, 1.0, -0.5, f64::NAN] {
        for method in [
            IntervalMethod::Conformal,
            IntervalMethod::Split,
            IntervalMethod::Delta,
        ] {
            let e = model.intervals_with(&t, level, method).unwrap_err();
            assert!(e.to_string().contains("between 0 and 1"), "{e}");
        }
    }
    // split conformal calibrates on one fold of 12 rows: too few for 95 %
    let e = model
        .intervals_with(&t, LEVEL, IntervalMethod::Split)
        .unwrap_err()
        .to_string();
    assert!(e.contains("at least 19"), "{e}");
    assert!(model.intervals_with(&t, 0.9, IntervalMethod::Split).is_ok());
    // more folds than training rows
    let e = quick_fit(8, 10).unwrap_err().to_string();
    assert!(e.contains("--conformal-folds"), "{e}");
    let e = quick_fit(60, 1).unwrap_err().to_string();
    assert!(e.contains("at least 2"), "{e}");
    // no folds: no calibration, the delta method
    let (plain, _) = quick_fit(60, 0).unwrap();
    assert!(plain.conformal.is_none());
}

#[test]
fn the_interval_widens_outside_the_training_ranges_only() {
    let (model, _) = quick_fit(200, 5).unwrap();
    let w = model
        .conformal
        .as_ref()
        .and_then(|c| c.widening.as_ref())
        .expect("the fit stores its range hold-outs");
    assert!(!w.held_out.is_empty());
    assert!(w.columns.contains(&"x1".to_string()));
    // x1 was drawn in [1, 4]: 2.5 is inside, 6 and 8 outside
    let names = ["x1", "x2"].iter().map(|s| s.to_string()).collect();
    let t = Table::new(names, vec![vec![2.5, 6.0, 8.0], vec![0.5, 0.5, 0.5]]).unwrap();
    let mut plain = model.clone();
    plain.conformal.as_mut().unwrap().widening = None;
    let width = |m: &hxai_hybrid::tables::TableModel| -> Vec<f64> {
        m.intervals_with(&t, LEVEL, IntervalMethod::Conformal)
            .unwrap()
            .iter()
            .map(|(lo, hi)| hi - lo)
            .collect()
    };
    let (wide, base) = (width(&model), width(&plain));
    assert!(
        (wide[0] - base[0]).abs() <= 1e-12 * base[0],
        "{wide:?} vs {base:?}"
    );
    assert!(
        wide[1] >= base[1] && wide[2] >= base[2],
        "{wide:?} vs {base:?}"
    );
    // the widening grows with the distance
    assert!(
        wide[2] / base[2] >= wide[1] / base[1],
        "{wide:?} vs {base:?}"
    );
}

/// A log correction's physics stays above zero through its calibration. Norton-Arrhenius
/// creep `A s^4 exp(-Q/(8.314 T))` on 60-row tables (rates of 1e-14 to 1e-7 /s, 20 %
/// log-normal scatter, the truth `1e-2 s^4.6 exp(-3e5/(8.314 T))`), started at A = 0.1,
/// Q = 2.8e5, over 12 seeds (each fit with its CV+ folds, which calibrate again): every
/// fit must succeed. Measured without `LmSettings::keep_positive`: seed 3 fails, its
/// calibration stepping `Q` to where the law underflows to 0 on a row, so that `ln(y / f_p)`
/// has no value (first seen in `scripts/design_loop.py`'s creep runs, once the calibration's
/// damping no longer held `Q` at its start).
#[test]
fn a_log_corrections_physics_stays_positive_through_calibration() {
    let mut failed = Vec::new();
    for seed in 0..12u64 {
        let mut rng = ChaCha8Rng::seed_from_u64(500 + seed);
        let noise: Normal<f64> = Normal::new(0.0, 0.2).unwrap();
        let n = 60;
        let mut cols = vec![Vec::new(); 4];
        for _ in 0..n {
            let s: f64 = rng.gen_range(50.0..200.0);
            let t: f64 = rng.gen_range(800.0..1000.0);
            let d: f64 = rng.gen_range(20.0..120.0);
            let rate = 1e-2 * s.powf(4.6) * (-3e5 / (8.314 * t)).exp() * (d / 50.0).powf(-0.5);
            for (c, v) in cols
                .iter_mut()
                .zip([s, t, d, rate * noise.sample(&mut rng).exp()])
            {
                c.push(v);
            }
        }
        let names = ["s", "T", "d", "y"].iter().map(|s| s.to_string()).collect();
        let t = Table::new(names, cols).unwrap();
        let mut cfg = TableConfig::new("y", "A*s^4*exp(-Q/(8.314*T))");
        cfg.calibrate = vec!["A".into(), "Q".into()];
        cfg.init = [("A".to_string(), 0.1), ("Q".to_string(), 2.8e5)]
            .into_iter()
            .collect();
        cfg.correction = CorrectionForm::Log;
        cfg.search.epochs = 2;
        cfg.search.candidates_per_epoch = 200;
        cfg.seed = seed;
        if let Err(e) = hxai_hybrid::tables::fit(&t, &cfg, &mut |_| {}) {
            failed.push(format!("seed {seed}: {e}"));
        }
    }
    assert!(failed.is_empty(), "{failed:#?}");
}
