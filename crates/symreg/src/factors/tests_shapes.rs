//! Tests of issue 68's shapes and monotone constraints on tables with a known truth: a
//! hinge's knot inside its 95 % interval, a smooth step found where the truth switches, and
//! a monotone constraint that holds on a grid (over a pair too) where the unconstrained fit
//! does not.
use super::*;
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

fn normal(rng: &mut ChaCha8Rng) -> f64 {
    let u: f64 = rng.gen_range(1e-12..1.0);
    let v: f64 = rng.gen_range(0.0..1.0);
    (-2.0 * u.ln()).sqrt() * (2.0 * std::f64::consts::PI * v).cos()
}

/// `n` rows of `x` uniform on [0, 10] and `z` on [0, 1], and a target `truth(x, z)` plus
/// normal noise of standard deviation `sd`.
fn table(n: usize, seed: u64, sd: f64, truth: impl Fn(f64, f64) -> f64) -> (Table, Vec<f64>) {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let x: Vec<f64> = (0..n).map(|_| rng.gen_range(0.0..10.0)).collect();
    let z: Vec<f64> = (0..n).map(|_| rng.gen_range(0.0..1.0)).collect();
    let y = x
        .iter()
        .zip(&z)
        .map(|(&a, &b)| truth(a, b) + sd * normal(&mut rng))
        .collect();
    let t = Table::new(vec!["x".into(), "z".into()], vec![x, z]).expect("table");
    (t, y)
}

/// The model's values on a grid: `xs` points of `x` over [0, 10] for each of `zs` values of
/// `z` inside (0, 1) (the middles of `zs` equal bins), `x` varying fastest.
fn grid(model: &Model, xs: usize, zs: usize) -> Vec<f64> {
    let (mut gx, mut gz) = (Vec::new(), Vec::new());
    for j in 0..zs {
        for i in 0..xs {
            gx.push(10.0 * i as f64 / (xs - 1) as f64);
            gz.push((j as f64 + 0.5) / zs as f64);
        }
    }
    let t = Table::new(vec!["x".into(), "z".into()], vec![gx, gz]).expect("grid");
    model.predict(&t).expect("predict")
}

/// Whether every run of `xs` values never falls (beyond rounding).
fn non_decreasing(v: &[f64], xs: usize) -> bool {
    v.chunks(xs).all(|run| {
        run.windows(2)
            .all(|w| w[1] >= w[0] - 1e-9 * (1.0 + w[0].abs()))
    })
}

#[test]
fn a_hinge_is_found_with_its_knot_inside_its_interval() {
    let knot = 6.0;
    let (t, y) = table(400, 3, 0.1, |x, _| 2.0 + 0.8 * (x - knot).max(0.0));
    let cfg = FactorConfig {
        shapes: Shapes::ALL,
        ..FactorConfig::default()
    };
    let fit = fit_factors(&t, &y, Link::Additive, &cfg).expect("fit");
    let shapes: Vec<(Option<String>, Shape)> = fit
        .factors
        .iter()
        .map(|f| (f.column.clone(), f.shape))
        .collect();
    assert_eq!(
        shapes,
        [(Some("x".into()), Shape::Hinge)],
        "{:?}",
        fit.factors
    );
    assert!(fit.factors[0].complexity <= 5);
    // the program: scale, offset, then the term's amplitude and `c` of `x + |x + c|`
    let unc = fit.model.uncertainty(&t, &y).expect("uncertainty");
    let ci = unc
        .params
        .iter()
        .zip(&unc.slots)
        .find(|(_, s)| s.as_slice() == [3])
        .and_then(|((_, e), _)| e.ci95)
        .expect("the knot's interval");
    assert!(
        -ci[1] <= knot && knot <= -ci[0],
        "knot {knot} outside [{}, {}] ({})",
        -ci[1],
        -ci[0],
        fit.model.equation()
    );
    // the classic shapes cannot write it: their fit is worse on the same rows
    let classic = fit_factors(&t, &y, Link::Additive, &FactorConfig::default()).expect("fit");
    assert!(classic.model.train_mse > 1.2 * fit.model.train_mse);
}

#[test]
fn a_switch_is_written_as_a_step_or_a_saturating_power() {
    let sd = 0.05;
    let (t, y) = table(400, 4, sd, |x, _| {
        1.0 + 0.6 / (1.0 + (-(x - 4.0) * 2.0).exp())
    });
    let cfg = FactorConfig {
        shapes: Shapes::ALL,
        ..FactorConfig::default()
    };
    let fit = fit_factors(&t, &y, Link::Additive, &cfg).expect("fit");
    assert_eq!(fit.factors.len(), 1, "{:?}", fit.factors);
    // a logistic in x, or Hill's `1/(1 + k x^q)` (a logistic in log x): both switch once
    assert!(
        matches!(fit.factors[0].shape, Shape::Step | Shape::SaturatingPower),
        "{:?}",
        fit.factors
    );
    assert!(fit.factors[0].complexity <= 5);
    // at the noise, where the classic shapes are not
    assert!(
        fit.model.train_mse < (1.2 * sd).powi(2),
        "{}",
        fit.model.train_mse
    );
    let classic = fit_factors(&t, &y, Link::Additive, &FactorConfig::default()).expect("fit");
    assert!(classic.model.train_mse > (1.2 * sd).powi(2));
    // with the saturating power left out, the step itself
    let cfg = FactorConfig {
        shapes: Shapes::ALL.without(Shape::SaturatingPower),
        ..FactorConfig::default()
    };
    let fit = fit_factors(&t, &y, Link::Additive, &cfg).expect("fit");
    assert_eq!(fit.factors[0].shape, Shape::Step, "{:?}", fit.factors);
    let centre = {
        let p = &fit.model.params;
        -p[p.len() - 1] / p[p.len() - 2]
    };
    assert!((centre - 4.0).abs() < 0.2, "centre {centre}");
}

#[test]
fn shapes_parse_from_their_names() {
    assert_eq!(Shapes::parse("all"), Some(Shapes::ALL));
    assert_eq!(Shapes::parse("classic"), Some(Shapes::CLASSIC));
    let s = Shapes::parse("power, hinge").expect("a list");
    assert!(s.contains(Shape::Power) && s.contains(Shape::Hinge));
    assert!(!s.contains(Shape::Linear) && !s.contains(Shape::Step));
    assert_eq!(Shapes::parse("power,spline"), None);
    assert!(!Shapes::CLASSIC.contains(Shape::SaturatingPower));
    assert!(Shapes::CLASSIC.contains(Shape::Periodic) && Shapes::CLASSIC.contains(Shape::Pair));
    for s in Shape::MAIN {
        assert_eq!(Shape::from_name(s.name()), Some(s));
    }
}

#[test]
fn a_monotone_constraint_holds_on_a_grid_where_the_rows_fall_and_rise() {
    // the rows fall and rise twice over x (a harmonic follows them; every other one-column
    // shape is monotone, and a pair of x and z that reads x alone is no longer taken)
    let (t, y) = table(400, 5, 0.05, |x, _| {
        1.0 + 0.3 * (2.0 * std::f64::consts::PI * x / 5.0).sin()
    });
    let free = fit_factors(&t, &y, Link::Additive, &FactorConfig::default()).expect("fit");
    assert!(
        !non_decreasing(&grid(&free.model, 101, 1), 101),
        "the unconstrained fit should follow the dip: {}",
        free.model.equation()
    );
    for shapes in [Shapes::CLASSIC, Shapes::ALL] {
        let cfg = FactorConfig {
            increasing: 1,
            shapes,
            ..FactorConfig::default()
        };
        let fit = fit_factors(&t, &y, Link::Additive, &cfg).expect("fit");
        assert!(
            non_decreasing(&grid(&fit.model, 401, 1), 401),
            "not monotone: {}",
            fit.model.equation()
        );
    }
}

#[test]
fn a_monotone_constraint_holds_over_a_pair() {
    // x's effect changes sign with z: rising where z > 0.5, falling below
    let (t, y) = table(600, 6, 0.02, |x, z| 1.0 + 0.1 * x * (z - 0.5) + 0.5 * z);
    let free = fit_factors(&t, &y, Link::Additive, &FactorConfig::default()).expect("fit");
    assert!(
        !non_decreasing(&grid(&free.model, 41, 11), 41),
        "the unconstrained fit should hold the interaction: {}",
        free.model.equation()
    );
    let cfg = FactorConfig {
        increasing: 1,
        ..FactorConfig::default()
    };
    let fit = fit_factors(&t, &y, Link::Additive, &cfg).expect("fit");
    assert!(
        non_decreasing(&grid(&fit.model, 41, 21), 41),
        "not monotone in x at every z: {}",
        fit.model.equation()
    );
}

/// A pair factor must read both its columns: a fitted exponent below 0.01 in size makes it
/// the other column's main effect, which is not taken as a pair.
#[test]
fn a_pair_that_reads_one_column_is_not_a_pair() {
    let term = |p: f64, q: f64| Term {
        shape: Shape::Pair,
        cols: vec![0, 1],
        params: vec![1.0, p, q],
        free: vec![true; 3],
    };
    assert!(select::reads_both(&term(1.0, -0.5)));
    assert!(!select::reads_both(&term(-8.8e-17, 1.0)));
    assert!(!select::reads_both(&term(2.0, 0.005)));
}
