use super::*;
use proptest::prelude::*;

fn names(v: &[&str]) -> Vec<String> {
    v.iter().map(|s| (*s).to_string()).collect()
}

fn dim(text: &str) -> Dimension {
    Dimension::parse(text).expect(text)
}

/// The dimension of a product of powers of inputs.
fn of_product(dims: &[Dimension], e: &[Ratio]) -> [Ratio; 7] {
    let mut out = [Ratio::ZERO; 7];
    for (d, r) in dims.iter().zip(e) {
        for (o, k) in out.iter_mut().zip(d.0) {
            *o = o.sub(r.mul(Ratio::int(i64::from(k))).neg());
        }
    }
    out
}

fn ints(e: &[i64]) -> Vec<Ratio> {
    e.iter().map(|&k| Ratio::int(k)).collect()
}

/// Newton's gravitation with G as a column: one group, and `M` is `G m1^2 / r^2` (the
/// repeating columns are the first three independent ones, G m1 m2 with m1 m2 alike, so r).
#[test]
fn gravitation_reduces_to_one_group() {
    let inputs = names(&["G", "m1", "m2", "r"]);
    let dims = [dim("m^3/(kg*s^2)"), dim("kg"), dim("kg"), dim("m")];
    let red = Reduction::of(&inputs, &dims, dim("N")).expect("reduction");
    assert_eq!(red.groups.len(), 1, "{:?}", red.groups);
    assert_eq!(red.groups[0].1, vec![0, -1, 1, 0]);
    assert_eq!(
        of_product(&dims, &red.scale),
        of_product(&[dim("N")], &[Ratio::int(1)])
    );
    assert_eq!(
        red.describe("F"),
        vec![
            "pi1 = m2/m1".to_string(),
            "F = G*m1^2/r^2 * phi(pi1)".to_string()
        ]
    );
}

/// A pendulum's period: the scale is `sqrt(L/g)`, a half power.
#[test]
fn half_powers_are_kept_exact() {
    let inputs = names(&["L", "g", "theta"]);
    let dims = [dim("m"), dim("m/s^2"), dim("rad")];
    let red = Reduction::of(&inputs, &dims, dim("s")).expect("reduction");
    assert_eq!(
        red.scale,
        vec![Ratio::new(1, 2), Ratio::new(-1, 2), Ratio::ZERO]
    );
    assert_eq!(red.groups, vec![("pi1".to_string(), vec![0, 0, 1])]);
    assert_eq!(red.describe("T")[1], "T = L^(1/2)/g^(1/2) * phi(pi1)");
}

#[test]
fn a_target_no_product_reaches_is_refused() {
    let inputs = names(&["v", "t"]);
    let e = Reduction::of(&inputs, &[dim("m/s"), dim("s")], dim("kg"))
        .expect_err("mass from speed and time")
        .to_string();
    assert!(
        e.contains("dimensional constant") && e.contains("v [m/s]"),
        "{e}"
    );
}

#[test]
fn a_group_name_never_takes_an_input_name() {
    let inputs = names(&["pi1", "x"]);
    let red = Reduction::of(&inputs, &[dim("1"), dim("1")], dim("1")).expect("reduction");
    assert_eq!(red.groups[0].0, "dimensionless_group1");
}

#[test]
fn units_are_required_for_every_column_and_only_for_columns() {
    let inputs = names(&["a", "b"]);
    let given = |v: &[(&str, &str)]| -> Vec<(String, String)> {
        v.iter().map(|(c, u)| ((*c).into(), (*u).into())).collect()
    };
    let e = dimensions(&inputs, "y", &given(&[("a", "m"), ("y", "m")]))
        .expect_err("b has none")
        .to_string();
    assert!(e.contains("no unit for `b`"), "{e}");
    let e = dimensions(
        &inputs,
        "y",
        &given(&[("a", "m"), ("b", "s"), ("y", "m"), ("c", "s")]),
    )
    .expect_err("c is no column")
    .to_string();
    assert!(e.contains("`c`, which is not a column"), "{e}");
    let e = dimensions(
        &inputs,
        "y",
        &given(&[("a", "m"), ("b", "parsec"), ("y", "m")]),
    )
    .expect_err("parsec")
    .to_string();
    assert!(e.contains("column `b`: unit `parsec`"), "{e}");
}

#[test]
fn a_zero_under_a_negative_power_is_refused_by_row() {
    let inputs = names(&["v", "t"]);
    let red = Reduction::of(&inputs, &[dim("m/s"), dim("s")], dim("m")).expect("reduction");
    let data = Table::new(inputs, vec![vec![1.0, 2.0], vec![1.0, 0.0]]).expect("table");
    // y = v t has no group; the scale v t is zero on row 1
    let e = red
        .transform(&data, &[1.0, 0.0])
        .expect_err("zero")
        .to_string();
    assert!(e.contains("row 1"), "{e}");
}

/// Kinetic energy from mass, speed and a distractor height: three columns of independent
/// dimensions leave no group, so the law is `c m v^2` with `c` fitted, and the height
/// cannot enter.
#[test]
fn no_group_left_fits_the_constant_alone() {
    let n = 50;
    let m: Vec<f64> = (0..n).map(|i| 1.0 + f64::from(i) / 10.0).collect();
    let v: Vec<f64> = (0..n).map(|i| 2.0 + f64::from((i * 7) % 11)).collect();
    let h: Vec<f64> = (0..n).map(|i| 1.0 + f64::from((i * 3) % 5)).collect();
    let y: Vec<f64> = m.iter().zip(&v).map(|(m, v)| 0.5 * m * v * v).collect();
    let data = Table::new(names(&["m", "v", "h"]), vec![m, v, h]).expect("table");
    let red = Reduction::of(data.names(), &[dim("kg"), dim("m/s"), dim("m")], dim("J"))
        .expect("reduction");
    assert!(red.groups.is_empty());
    let res = search(&data, &y, Some(&red), &SearchConfig::default(), &mut |_| {}).expect("search");
    assert!(res.best.train_mse < 1e-20, "{}", res.best.train_mse);
    assert_eq!(res.best.features(), vec!["m".to_string(), "v".to_string()]);
}

/// A pendulum with a finite amplitude, `T = 2 pi sqrt(L/g) (1 + theta^2/16)`, over 120
/// rows, with its reduction (one group, theta).
fn pendulum() -> (Table, Vec<f64>, Reduction) {
    let n = 120;
    let l: Vec<f64> = (0..n)
        .map(|i| 0.5 + f64::from((i * 7) % 13) / 6.0)
        .collect();
    let g: Vec<f64> = (0..n).map(|i| 5.0 + f64::from((i * 5) % 11)).collect();
    let th: Vec<f64> = (0..n).map(|i| 0.1 + f64::from(i) / 100.0).collect();
    let y: Vec<f64> = (0..n as usize)
        .map(|i| 2.0 * std::f64::consts::PI * (l[i] / g[i]).sqrt() * (1.0 + th[i] * th[i] / 16.0))
        .collect();
    let data = Table::new(names(&["L", "g", "theta"]), vec![l, g, th]).expect("table");
    let red =
        Reduction::of(data.names(), &[dim("m"), dim("m/s^2"), dim("1")], dim("s")).expect("red");
    (data, y, red)
}

/// A pendulum with a finite amplitude, `T = 2 pi sqrt(L/g) (1 + theta^2/16)`: the search
/// sees one column (theta) and a dimensionless target, and its model, composed back,
/// predicts the period on the original columns.
#[test]
fn a_search_on_the_groups_predicts_the_target() {
    let (data, y, red) = pendulum();
    let cfg = SearchConfig {
        epochs: 3,
        candidates_per_epoch: 300,
        ..SearchConfig::default()
    };
    let res = search(&data, &y, Some(&red), &cfg, &mut |_| {}).expect("search");
    let pred = res.best.predict(&data).expect("predict");
    let worst = pred
        .iter()
        .zip(&y)
        .map(|(p, t)| ((p - t) / t).abs())
        .fold(0.0, f64::max);
    assert!(worst < 1e-6, "{} off by {worst}", res.best.equation());
    assert!(res.best.sympy().contains("sqrt"), "{}", res.best.sympy());
    for m in &res.pareto {
        assert_eq!(m.feature_names, data.names().to_vec());
    }
}

/// Consensus selection with units: each of the B + 1 searches runs on the groups and is
/// composed back, so the winner and the nominated structures are those of the columns, and
/// the winner predicts the period.
#[test]
fn consensus_votes_on_the_composed_structures() {
    let (data, y, red) = pendulum();
    let cfg = SearchConfig {
        epochs: 2,
        candidates_per_epoch: 200,
        consensus_runs: 3,
        ..SearchConfig::default()
    };
    let res = search(&data, &y, Some(&red), &cfg, &mut |_| {}).expect("consensus");
    let c = res.consensus.as_ref().expect("a consensus report");
    assert_eq!(c.runs, 3);
    assert_eq!(res.best.feature_names, data.names().to_vec());
    assert_eq!(crate::stability::structure_of(&res.best), c.structure);
    // the structures are written over the columns, not over the group
    assert!(
        c.structure.contains('L') && c.structure.contains('g'),
        "{}",
        c.structure
    );
    let pred = res.best.predict(&data).expect("predict");
    let worst = pred
        .iter()
        .zip(&y)
        .map(|(p, t)| ((p - t) / t).abs())
        .fold(0.0, f64::max);
    assert!(worst < 1e-3, "{} off by {worst}", res.best.equation());
}

fn arb_dims(n: usize) -> impl Strategy<Value = Vec<[i32; 7]>> {
    prop::collection::vec(
        prop::array::uniform7(prop_oneof![6 => Just(0i32), 1 => -3i32..=3]),
        n + 1,
    )
}

proptest! {
    /// For any dimensions: every group is dimensionless, the scale has the target's
    /// dimension, the groups number the inputs less the rank, and `compose` of the model
    /// `pi_k` (one group) predicts `M * pi_k`.
    #[test]
    fn groups_are_dimensionless_and_compose_agrees(
        d in (1usize..6).prop_flat_map(arb_dims),
        rows in prop::collection::vec(prop::collection::vec(0.5f64..3.0, 6), 4),
    ) {
        let n = d.len() - 1;
        let dims: Vec<Dimension> = d[..n].iter().map(|e| Dimension(*e)).collect();
        let inputs: Vec<String> = (0..n).map(|i| format!("x{i}")).collect();
        let target = Dimension(d[n]);
        let Ok(red) = Reduction::of(&inputs, &dims, target) else {
            return Ok(());
        };
        for (_, e) in &red.groups {
            prop_assert_eq!(of_product(&dims, &ints(e)), [Ratio::ZERO; 7]);
        }
        prop_assert_eq!(of_product(&dims, &red.scale), of_product(&[target], &[Ratio::int(1)]));
        let columns: Vec<Vec<f64>> = (0..n).map(|c| rows.iter().map(|r| r[c]).collect()).collect();
        let data = Table::new(inputs.clone(), columns.clone()).expect("table");
        let y = vec![1.0; rows.len()];
        let (pi, py) = red.transform(&data, &y).expect("transform");
        let Some(pi) = pi else {
            prop_assert!(red.groups.is_empty());
            return Ok(());
        };
        for (k, (name, _)) in red.groups.iter().enumerate() {
            let prog = Program { nodes: vec![Node::Var(k as u16)], affine: false };
            let m = Model::new(pi.names().to_vec(), prog, vec![2.0, 0.5]).expect("model");
            let back = red.compose(&m).expect("compose");
            let got = back.predict(&data).expect("predict");
            for row in 0..rows.len() {
                let want = (2.0 * pi.column(name).expect("group")[row] + 0.5) / py[row];
                prop_assert!((got[row] - want).abs() <= 1e-9 * want.abs(), "{} vs {}", got[row], want);
            }
        }
    }
}
