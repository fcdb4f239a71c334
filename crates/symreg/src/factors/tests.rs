//! Tests of the factor form on tables with a known truth: the backfitting recovers a
//! product of three one-column laws factor by factor (constants inside their 95 %
//! intervals), the forward selection leaves a distractor out, the interaction rule finds a
//! true interaction and adds none where there is none, and the model's printed equation
//! equals its prediction.
use super::*;
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

/// Standard normal draws by Box-Muller (rand_distr is not a dependency of this crate).
fn normal(rng: &mut ChaCha8Rng) -> f64 {
    let u: f64 = rng.gen_range(1e-12..1.0);
    let v: f64 = rng.gen_range(0.0..1.0);
    (-2.0 * u.ln()).sqrt() * (2.0 * std::f64::consts::PI * v).cos()
}

/// `n` rows of columns uniform on the given ranges.
fn columns(n: usize, ranges: &[(&str, f64, f64)], seed: u64) -> Table {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let cols: Vec<Vec<f64>> = ranges
        .iter()
        .map(|&(_, lo, hi)| (0..n).map(|_| rng.gen_range(lo..hi)).collect())
        .collect();
    let names = ranges.iter().map(|r| r.0.to_string()).collect();
    Table::new(names, cols).expect("table")
}

fn col<'a>(t: &'a Table, name: &str) -> &'a [f64] {
    t.column(name).expect("column")
}

/// The program indices of each factor's constants, in the order the factors entered.
fn offsets(fit: &FactorFit, link: Link) -> Vec<usize> {
    let mut at = if link == Link::Log { 3 } else { 2 };
    fit.factors
        .iter()
        .map(|f| {
            let start = at;
            let product = link != Link::Additive;
            at += match (f.shape, product) {
                (Shape::Linear | Shape::Log, false) => 1,
                (Shape::Linear | Shape::Log, true) => 2,
                (Shape::Pair | Shape::Periodic, false) => 3,
                (Shape::Pair | Shape::Periodic, true) => 4,
                (_, false) => 2,
                (_, true) => 1,
            };
            start
        })
        .collect()
}

/// The program index of the first constant of the first factor of `shape`.
fn slot_of(fit: &FactorFit, shape: Shape, link: Link) -> usize {
    let k = fit
        .factors
        .iter()
        .position(|f| f.shape == shape)
        .expect("a factor of the shape");
    offsets(fit, link)[k]
}

/// The 95 % interval of the free constant at program index `slot` (`None` where it is not
/// a free constant or has no interval).
fn interval(unc: &crate::uncertainty::Uncertainty, slot: usize) -> Option<[f64; 2]> {
    unc.params
        .iter()
        .zip(&unc.slots)
        .find(|(_, s)| s.as_slice() == [slot])
        .and_then(|((_, e), _)| e.ci95)
}

#[test]
fn a_product_of_three_laws_is_recovered_factor_by_factor() {
    let n = 600;
    let t = columns(
        n,
        &[
            ("f", 0.05, 0.3),
            ("v", 50.0, 300.0),
            ("r", 0.0, 10.0),
            ("d", 1.0, 5.0),
        ],
        7,
    );
    let mut rng = ChaCha8Rng::seed_from_u64(8);
    let (c, p, b, k) = (2.0, 0.7, -0.004, 0.05);
    let y: Vec<f64> = (0..n)
        .map(|i| {
            let truth = c
                * col(&t, "f")[i].powf(p)
                * (b * col(&t, "v")[i]).exp()
                * (1.0 + k * col(&t, "r")[i]);
            truth * (1.0 + 0.01 * normal(&mut rng)) - 1.0
        })
        .collect();
    let fit = fit_factors(&t, &y, Link::Multiplicative, &FactorConfig::default()).expect("fit");
    let got: Vec<(Option<String>, Shape)> = fit
        .factors
        .iter()
        .map(|f| (f.column.clone(), f.shape))
        .collect();
    let mut sorted = got.clone();
    sorted.sort_by(|a, b| a.0.cmp(&b.0));
    assert_eq!(
        sorted,
        [
            (Some("f".into()), Shape::Power),
            (Some("r".into()), Shape::Linear),
            (Some("v".into()), Shape::Exp),
        ],
        "{:?}",
        fit.factors
    );
    // each true constant inside its 95 % interval
    let unc = fit.model.uncertainty(&t, &y).expect("uncertainty");
    let offs = offsets(&fit, Link::Multiplicative);
    let mut checks = vec![(0usize, c)];
    for (f, &o) in fit.factors.iter().zip(&offs) {
        match f.shape {
            Shape::Power => checks.push((o, p)),
            Shape::Exp => checks.push((o, b)),
            Shape::Linear => checks.push((o + 1, k)),
            _ => unreachable!(),
        }
    }
    for (slot, truth) in checks {
        let ci = interval(&unc, slot).expect("an interval");
        assert!(
            ci[0] <= truth && truth <= ci[1],
            "constant {slot}: {truth} outside {ci:?} ({})",
            fit.model.equation()
        );
    }
    // the printed equation is the prediction
    let printed = crate::expr::Expr::from_program(
        &fit.model.program,
        &fit.model.params,
        &fit.model.feature_names,
    );
    let pred = fit.model.predict(&t).expect("predict");
    for (i, p) in pred.iter().enumerate() {
        let v = printed.eval(&|name| col(&t, name)[i]);
        assert!((v - p).abs() <= 1e-9 * p.abs().max(1.0));
    }
}

#[test]
fn a_distractor_is_left_out_of_a_sum() {
    let n = 400;
    let t = columns(
        n,
        &[
            ("a", 1.0, 3.0),
            ("z1", 0.0, 1.0),
            ("b", 0.0, 2.0),
            ("z2", 5.0, 9.0),
        ],
        11,
    );
    let mut rng = ChaCha8Rng::seed_from_u64(12);
    let y: Vec<f64> = (0..n)
        .map(|i| 3.0 * col(&t, "a")[i].powf(1.5) - 2.0 * col(&t, "b")[i] + 0.3 * normal(&mut rng))
        .collect();
    let fit = fit_factors(&t, &y, Link::Additive, &FactorConfig::default()).expect("fit");
    let mut cols: Vec<String> = fit
        .factors
        .iter()
        .filter_map(|f| f.column.clone())
        .collect();
    cols.sort();
    assert_eq!(cols, ["a", "b"], "{}", fit.model.equation());
    assert!(fit.factors.iter().all(|f| f.columns.is_none()));
}

#[test]
fn a_true_interaction_is_found_and_none_is_added_without_one() {
    let n = 500;
    let t = columns(
        n,
        &[
            ("rake", -5.0, 15.0),
            ("time", 1.0, 30.0),
            ("speed", 80.0, 250.0),
        ],
        21,
    );
    let truth = |i: usize, wear: bool| {
        let k_rake = 1.0 - 0.015 * (col(&t, "rake")[i] - 6.0);
        let k_v = (col(&t, "speed")[i] / 100.0).powf(-0.1);
        let k_w = if wear {
            1.0 + 0.05 * col(&t, "time")[i].sqrt() * (col(&t, "speed")[i] / 200.0).powf(1.5)
        } else {
            1.0
        };
        1.3 * k_rake * k_v * k_w
    };
    for wear in [true, false] {
        let mut rng = ChaCha8Rng::seed_from_u64(22);
        let y: Vec<f64> = (0..n)
            .map(|i| truth(i, wear) * (1.0 + 0.005 * normal(&mut rng)) - 1.0)
            .collect();
        let fit = fit_factors(&t, &y, Link::Multiplicative, &FactorConfig::default()).expect("fit");
        let pairs: Vec<&Factor> = fit.factors.iter().filter(|f| f.columns.is_some()).collect();
        if wear {
            assert_eq!(pairs.len(), 1, "{}", fit.model.equation());
            let mut cols = pairs[0].columns.clone().unwrap_or_default();
            cols.sort();
            assert_eq!(cols, ["speed", "time"], "{}", fit.model.equation());
        } else {
            assert!(pairs.is_empty(), "{}", fit.model.equation());
        }
        assert!(fit.factors.iter().all(|f| f.complexity <= 5));
    }
}

#[test]
fn bad_input_is_refused_with_a_message() {
    let t = columns(20, &[("a", 1.0, 2.0)], 1);
    let short = fit_factors(&t, &[1.0; 3], Link::Additive, &FactorConfig::default());
    assert!(short.is_err());
    let mut y = vec![1.0; 20];
    y[4] = f64::NAN;
    let e = fit_factors(&t, &y, Link::Additive, &FactorConfig::default())
        .expect_err("a NaN target is refused");
    assert!(e.to_string().contains("row 5"), "{e}");
}

#[test]
fn the_same_seed_gives_the_same_model_whatever_the_threads() {
    let n = 200;
    let t = columns(n, &[("a", 1.0, 3.0), ("b", 0.0, 2.0)], 31);
    let y: Vec<f64> = (0..n)
        .map(|i| col(&t, "a")[i].sqrt() + 0.1 * col(&t, "b")[i] * ((i * 7) % 5) as f64)
        .collect();
    let one = FactorConfig {
        par: Par::SEQUENTIAL,
        ..FactorConfig::default()
    };
    let two = FactorConfig {
        par: Par::threads(2),
        ..FactorConfig::default()
    };
    let a = fit_factors(&t, &y, Link::Additive, &one).expect("fit");
    let b = fit_factors(&t, &y, Link::Additive, &two).expect("fit");
    assert_eq!(a, b);
}

/// A multiplicative correction over physics spanning three decades, with scatter in the
/// target's units: fitted by `delta`'s own squared error the rows of small physics (whose
/// `delta` the scatter blows up) decide the fit; fitted on the physics' scale
/// ([`fit_factors_on_physics`]) the factor's exponent is recovered and the hybrid's error
/// is the scatter's.
#[test]
fn a_multiplicative_factor_is_fitted_in_the_targets_units() {
    let n = 400;
    let t = columns(n, &[("x", 1.0, 4.0), ("q", 0.01, 10.0)], 41);
    let mut rng = ChaCha8Rng::seed_from_u64(42);
    let sigma = 0.05;
    // the physics is q itself; the truth is q * 1.2 * x^0.5
    let fp: Vec<f64> = col(&t, "q").to_vec();
    let y: Vec<f64> = (0..n)
        .map(|i| fp[i] * 1.2 * col(&t, "x")[i].sqrt() + sigma * normal(&mut rng))
        .collect();
    let delta: Vec<f64> = y.iter().zip(&fp).map(|(y, p)| y / p - 1.0).collect();
    let feats = Table::new(vec!["x".into()], vec![col(&t, "x").to_vec()]).expect("table");
    let cfg = FactorConfig::default();
    let rmse = |fit: &FactorFit| {
        let d = fit.model.predict(&feats).expect("predict");
        let se: f64 = (0..n)
            .map(|i| (fp[i] * (1.0 + d[i]) - y[i]).powi(2))
            .sum::<f64>();
        (se / n as f64).sqrt()
    };
    let scaled = fit_factors_on_physics(&feats, &delta, &fp, Link::Multiplicative, &cfg)
        .expect("fit on the physics' scale");
    let plain = fit_factors(&feats, &delta, Link::Multiplicative, &cfg).expect("plain fit");
    let (r_scaled, r_plain) = (rmse(&scaled), rmse(&plain));
    assert!(
        r_scaled < 1.1 * sigma,
        "{r_scaled} {}",
        scaled.model.equation()
    );
    assert!(r_scaled < r_plain, "{r_scaled} vs {r_plain}");
    assert_eq!(scaled.factors.len(), 1, "{}", scaled.model.equation());
    assert_eq!(scaled.factors[0].shape, Shape::Power);
    // the exponent snapped to 1/2, or within 0.05 of it
    let p = &scaled.model.params;
    let e = p[p.len() - 1];
    assert!((e - 0.5).abs() < 0.05, "{}", scaled.model.equation());
    // physics of another length is refused
    assert!(fit_factors_on_physics(&feats, &delta, &fp[1..], Link::Multiplicative, &cfg).is_err());
}

/// The variance power is read from residuals whose scatter grows as `f_p^theta`: 0 for a
/// gauge's scatter, 1 for scatter in proportion, and in between for 0.5 (within 0.15 on
/// 400 rows), and 0 where the physics hardly varies.
#[test]
fn the_variance_power_is_read_from_the_residuals() {
    let n = 400;
    let mut rng = ChaCha8Rng::seed_from_u64(51);
    let fp: Vec<f64> = (0..n)
        .map(|i| 0.1 * 100f64.powf(i as f64 / n as f64))
        .collect();
    for theta in [0.0, 0.5, 1.0] {
        let y: Vec<f64> = fp
            .iter()
            .map(|p| p + 0.05 * p.powf(theta) * normal(&mut rng))
            .collect();
        let got = super::variance_power(&fp, &y, &vec![0.0; n]);
        assert!((got - theta).abs() < 0.15, "theta {theta}: {got}");
    }
    let flat = vec![2.0; n];
    let y: Vec<f64> = flat.iter().map(|p| p + 0.1 * normal(&mut rng)).collect();
    assert_eq!(super::variance_power(&flat, &y, &vec![0.0; n]), 0.0);
}

/// Scatter in proportion to the physics: the pilot in the target's units is reweighted
/// (theta near 1), and the factor's exponent is recovered.
#[test]
fn a_multiplicative_factor_with_proportional_scatter_is_recovered() {
    let n = 400;
    let t = columns(n, &[("x", 1.0, 4.0), ("q", 0.01, 10.0)], 61);
    let mut rng = ChaCha8Rng::seed_from_u64(62);
    let fp: Vec<f64> = col(&t, "q").to_vec();
    let y: Vec<f64> = (0..n)
        .map(|i| fp[i] * 1.2 * col(&t, "x")[i].powf(0.7) * (1.0 + 0.05 * normal(&mut rng)))
        .collect();
    let delta: Vec<f64> = y.iter().zip(&fp).map(|(y, p)| y / p - 1.0).collect();
    let feats = Table::new(vec!["x".into()], vec![col(&t, "x").to_vec()]).expect("table");
    let fit = fit_factors_on_physics(
        &feats,
        &delta,
        &fp,
        Link::Multiplicative,
        &FactorConfig::default(),
    )
    .expect("fit");
    assert_eq!(fit.factors.len(), 1, "{}", fit.model.equation());
    let p = &fit.model.params;
    assert!(
        (p[p.len() - 1] - 0.7).abs() < 0.05,
        "{}",
        fit.model.equation()
    );
}

#[test]
fn the_best_of_many_distractors_rarely_enters() {
    // one true effect and six columns that carry nothing, on 20 seeds of 150 rows: the best
    // of six noise columns gains more than one paired standard error by chance in a large
    // share of tables; entering at the level shared among the candidates it may enter in a
    // few (the Bonferroni bound: about 16 %, less since the columns' gains are not all
    // counted against the one rule)
    let mut entered = 0;
    for seed in 0..20u64 {
        let n = 150;
        let t = columns(
            n,
            &[
                ("a", 1.0, 3.0),
                ("z1", 0.0, 1.0),
                ("z2", 0.0, 1.0),
                ("z3", 5.0, 9.0),
                ("z4", -1.0, 1.0),
                ("z5", 1.0, 2.0),
                ("z6", 0.0, 10.0),
            ],
            100 + seed,
        );
        let mut rng = ChaCha8Rng::seed_from_u64(200 + seed);
        let y: Vec<f64> = (0..n)
            .map(|i| 2.0 * col(&t, "a")[i].powf(1.5) + 0.5 * normal(&mut rng))
            .collect();
        let fit = fit_factors(&t, &y, Link::Additive, &FactorConfig::default()).expect("fit");
        assert!(
            fit.factors.iter().any(|f| f.column.as_deref() == Some("a")),
            "seed {seed}: {}",
            fit.model.equation()
        );
        if fit.factors.iter().any(|f| f.column.as_deref() != Some("a")) {
            entered += 1;
        }
    }
    assert!(
        entered <= 3,
        "a distractor entered in {entered} of 20 tables"
    );
}

/// An effect that repeats over its column (runout over a spindle's angle in degrees): on
/// each of 10 noise draws the sum's factor of `angle` is one harmonic `a sin(w angle + c)`
/// and a linear effect beside it a line, a distractor enters at most twice; the 95 % intervals of
/// `a` and `w` cover the truth on at least 8 of the 10 (9.5 expected; 7 or fewer has a
/// chance near 1 %). On the same rows with a linear trend in place of the harmonic, no
/// periodic factor is kept.
#[test]
fn a_periodic_effect_is_one_harmonic() {
    let n = 400;
    let t = columns(
        n,
        &[
            ("angle", 0.0, 360.0),
            ("f", 0.0, 1.0),
            ("speed", 80.0, 250.0),
        ],
        31,
    );
    let (a, w, c) = (1.2, std::f64::consts::PI / 180.0, 0.6);
    let mut covered = [0usize; 2];
    let mut distractor = 0;
    for draw in 0..10u64 {
        for periodic in [true, false] {
            let mut rng = ChaCha8Rng::seed_from_u64(100 + draw);
            let y: Vec<f64> = (0..n)
                .map(|i| {
                    let h = if periodic {
                        a * (w * col(&t, "angle")[i] + c).sin()
                    } else {
                        0.002 * col(&t, "angle")[i]
                    };
                    1.5 + h + 0.8 * col(&t, "f")[i] + 0.15 * normal(&mut rng)
                })
                .collect();
            let fit = fit_factors(&t, &y, Link::Additive, &FactorConfig::default()).expect("fit");
            let mut got: Vec<(Option<String>, Shape)> = fit
                .factors
                .iter()
                .map(|f| (f.column.clone(), f.shape))
                .collect();
            got.sort_by(|x, y| x.0.cmp(&y.0));
            if !periodic {
                assert!(
                    got.iter().all(|(_, s)| *s != Shape::Periodic),
                    "{}",
                    fit.model.equation()
                );
                continue;
            }
            // the line may come back as the power law preferred first, its exponent snapped
            // to 1: the same factor; the distractor counted (the entry rule lets one in now
            // and then by chance: `the_best_of_many_distractors_rarely_enters`)
            let shape_of = |c: &str| got.iter().find(|g| g.0.as_deref() == Some(c)).map(|g| g.1);
            assert_eq!(
                shape_of("angle"),
                Some(Shape::Periodic),
                "{}",
                fit.model.equation()
            );
            assert!(
                matches!(shape_of("f"), Some(Shape::Linear | Shape::Power)),
                "{}",
                fit.model.equation()
            );
            distractor += usize::from(shape_of("speed").is_some());
            let at = slot_of(&fit, Shape::Periodic, Link::Additive);
            let unc = fit.model.uncertainty(&t, &y).expect("uncertainty");
            // up to sign: `-a sin(-w x - c)` is the same curve
            let (amp, freq) = (fit.model.params[at], fit.model.params[at + 1]);
            let inside = |ci: [f64; 2], v: f64| ci[0] <= v && v <= ci[1];
            let ci = |slot: usize| interval(&unc, slot).expect("an interval");
            covered[0] += usize::from(inside(ci(at), a * amp.signum()));
            covered[1] += usize::from(inside(ci(at + 1), w * freq.signum()));
        }
    }
    assert!(covered.iter().all(|&k| k >= 8), "covered {covered:?} of 10");
    assert!(
        distractor <= 2,
        "the distractor entered {distractor} of 10 times"
    );
}

/// Backfitting: a shape is chosen again once the other factors are in. Archard-like wear
/// with the truth `2 v^0.4 exp(-T/150)` and 12 % log-normal scatter, 320 rows, a
/// distractor `h`, over 10 noise draws. The temperature's effect, chosen alone, is as well
/// a line as an exponential (within one standard error while the speed's effect is still
/// in the residual); chosen again beside the speed factor it is the exponential. Asserted:
/// the temperature's factor is an exponential and the speed's a power law, with no
/// interaction, on at least 8 of the 10 draws, and the exponential's rate inside its 95 %
/// interval on at least 7. Measured: with backfitting 9 of 10 draws give the true shapes,
/// all 9 with the rate covered; without it (`backfit_rounds: 0`) 4 of 10, the others a
/// line in the temperature and, on four, an interaction `1 + a T^0.5 ...` standing in
/// for the exponential.
#[test]
fn a_shape_is_chosen_again_beside_the_other_factors() {
    let n = 320;
    let mut hits = 0;
    let mut covered = 0;
    for draw in 0..10u64 {
        let t = columns(
            n,
            &[("v", 0.1, 2.0), ("T", 20.0, 200.0), ("h", 20.0, 80.0)],
            40 + draw,
        );
        let mut rng = ChaCha8Rng::seed_from_u64(200 + draw);
        let y: Vec<f64> = (0..n)
            .map(|i| {
                let truth = 2.0 * col(&t, "v")[i].powf(0.4) * (-col(&t, "T")[i] / 150.0).exp();
                truth * (0.12 * normal(&mut rng)).exp() - 1.0
            })
            .collect();
        let fit = fit_factors(&t, &y, Link::Multiplicative, &FactorConfig::default()).expect("fit");
        let mut got: Vec<(Option<String>, Shape)> = fit
            .factors
            .iter()
            .filter(|f| f.column.as_deref() != Some("h"))
            .map(|f| (f.column.clone(), f.shape))
            .collect();
        got.sort_by(|a, b| a.0.cmp(&b.0));
        if got
            != [
                (Some("T".into()), Shape::Exp),
                (Some("v".into()), Shape::Power),
            ]
        {
            continue;
        }
        hits += 1;
        let at = slot_of(&fit, Shape::Exp, Link::Multiplicative);
        let unc = fit.model.uncertainty(&t, &y).expect("uncertainty");
        let ci = interval(&unc, at).expect("an interval");
        covered += usize::from(ci[0] <= -1.0 / 150.0 && -1.0 / 150.0 <= ci[1]);
    }
    assert!(hits >= 8, "the true shapes on {hits} of 10 draws");
    assert!(covered >= 7, "the rate covered on {covered} of 10 draws");
}
