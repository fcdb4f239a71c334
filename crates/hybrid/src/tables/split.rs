//! The train/test split of a table fit: extrapolation, grouped or random, and the check
//! of a given split's rows.

use super::TableConfig;
use super::resolve::cols_list;
use crate::HybridError;
use hxai_eval::Split;
use hxai_symreg::Table;
use std::collections::BTreeMap;

/// The split [`fit`](super::fit) uses: with `extrapolate`, the rows (or groups, by their mean)
/// with the top `test_fraction` of that column are the test set; otherwise a seeded random
/// split, grouped when `group` is set, stratified by the level indicators `strata` otherwise.
///
/// # Errors
/// A missing column, `test_fraction` outside (0, 1), or a side left empty.
pub fn split_rows(table: &Table, cfg: &TableConfig) -> Result<(Split, String), HybridError> {
    let n = table.n_rows();
    let groups: Option<Vec<u64>> = match &cfg.group {
        Some(g) => {
            let col = table.column(g).ok_or_else(|| HybridError::MissingColumn {
                what: "group column",
                name: g.clone(),
                columns: cols_list(table),
            })?;
            Some(col.iter().map(|v| (v + 0.0).to_bits()).collect())
        }
        None => None,
    };
    if let Some(e) = &cfg.extrapolate {
        let col = table.column(e).ok_or_else(|| HybridError::MissingColumn {
            what: "extrapolation column",
            name: e.clone(),
            columns: cols_list(table),
        })?;
        if !(cfg.test_fraction > 0.0 && cfg.test_fraction < 1.0) {
            return Err(HybridError::InvalidConfig(format!(
                "test fraction {}: choose a value between 0 and 1",
                cfg.test_fraction
            )));
        }
        // units: rows, or groups keyed by first appearance
        let mut unit_of = vec![0usize; n];
        let mut sums: Vec<(f64, usize, usize)> = Vec::new(); // (sum, count, first row)
        match &groups {
            Some(g) => {
                let mut seen: BTreeMap<u64, usize> = BTreeMap::new();
                for (i, key) in g.iter().enumerate() {
                    let u = *seen.entry(*key).or_insert_with(|| {
                        sums.push((0.0, 0, i));
                        sums.len() - 1
                    });
                    unit_of[i] = u;
                    sums[u].0 += col[i];
                    sums[u].1 += 1;
                }
            }
            None => {
                for (i, v) in col.iter().enumerate() {
                    unit_of[i] = i;
                    sums.push((*v, 1, i));
                }
            }
        }
        let mut order: Vec<usize> = (0..sums.len()).collect();
        order.sort_by(|&a, &b| {
            let ma = sums[a].0 / sums[a].1 as f64;
            let mb = sums[b].0 / sums[b].1 as f64;
            mb.total_cmp(&ma).then(sums[a].2.cmp(&sums[b].2))
        });
        let need = (cfg.test_fraction * n as f64).ceil() as usize;
        let mean = |u: usize| sums[u].0 / sums[u].1 as f64;
        let mut in_test = vec![false; sums.len()];
        let mut taken = 0;
        for &u in &order {
            if taken >= need {
                break;
            }
            in_test[u] = true;
            taken += sums[u].1;
        }
        // equal values stay on one side, so every test value lies above every training
        // value: the tie at the cut goes to the test side, or to the training side when the
        // test side would then hold every row
        if let Some(cut) = (0..sums.len())
            .filter(|&u| in_test[u])
            .map(mean)
            .min_by(f64::total_cmp)
        {
            let tied = |u: usize| mean(u) == cut;
            let all_tied_in = (0..sums.len()).all(|u| in_test[u] || tied(u));
            for (u, t) in in_test.iter_mut().enumerate() {
                if tied(u) {
                    *t = !all_tied_in;
                }
            }
        }
        let (test, train): (Vec<usize>, Vec<usize>) = (0..n).partition(|&i| in_test[unit_of[i]]);
        if test.is_empty() {
            return Err(HybridError::InvalidConfig(format!(
                "the extrapolation split on `{e}` has no value above the others to test on \
                 (the column is constant, or its top value takes more than the training side \
                 can spare): choose another column"
            )));
        }
        if train.is_empty() {
            return Err(HybridError::InvalidConfig(format!(
                "the extrapolation split on `{e}` leaves one side empty: change --test-fraction"
            )));
        }
        return Ok((Split { train, test }, "extrapolate".into()));
    }
    Ok(match groups {
        Some(g) => (
            hxai_eval::grouped_train_test_split(&g, cfg.test_fraction, cfg.seed)?,
            "grouped".into(),
        ),
        None if !cfg.strata.is_empty() => (
            stratified_split(&strata_of(table, &cfg.strata)?, cfg.test_fraction, cfg.seed)?,
            "random".into(),
        ),
        None => (
            hxai_eval::train_test_split(n, cfg.test_fraction, cfg.seed)?,
            "random".into(),
        ),
    })
}

/// The stratum of each row: the first of the indicator columns `strata` that is 1 there
/// (`strata.len()` for a row of none).
///
/// # Errors
/// [`HybridError::MissingColumn`] for an indicator the table lacks.
pub(crate) fn strata_of(table: &Table, strata: &[String]) -> Result<Vec<usize>, HybridError> {
    let mut out = vec![strata.len(); table.n_rows()];
    for (k, name) in strata.iter().enumerate().rev() {
        let col = table
            .column(name)
            .ok_or_else(|| HybridError::MissingColumn {
                what: "level indicator column",
                name: name.clone(),
                columns: cols_list(table),
            })?;
        for (o, v) in out.iter_mut().zip(col) {
            if *v == 1.0 {
                *o = k;
            }
        }
    }
    Ok(out)
}

/// A random split that keeps each stratum on both sides in proportion: within each
/// stratum (rows in table order, shuffled by a generator seeded with `seed` and the
/// stratum), `round(test_fraction * rows)` rows are tested, at most all but one, so every
/// stratum keeps a training row (issue 63: a level of 2-4 rows landed wholly in the test
/// rows and kept its constant's start value).
///
/// # Errors
/// A `test_fraction` outside (0, 1), or a split that tests no row.
pub(crate) fn stratified_split(
    stratum: &[usize],
    test_fraction: f64,
    seed: u64,
) -> Result<Split, HybridError> {
    use rand::SeedableRng;
    use rand::seq::SliceRandom;
    if !(test_fraction > 0.0 && test_fraction < 1.0) {
        return Err(HybridError::InvalidConfig(format!(
            "test fraction {test_fraction}: choose a value between 0 and 1"
        )));
    }
    let mut by: BTreeMap<usize, Vec<usize>> = BTreeMap::new();
    for (i, s) in stratum.iter().enumerate() {
        by.entry(*s).or_default().push(i);
    }
    let (mut train, mut test) = (Vec::new(), Vec::new());
    for (s, mut rows) in by {
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(
            seed ^ (s as u64).wrapping_mul(0x9e37_79b9_7f4a_7c15),
        );
        rows.shuffle(&mut rng);
        let k = ((test_fraction * rows.len() as f64).round() as usize).min(rows.len() - 1);
        test.extend_from_slice(&rows[..k]);
        train.extend_from_slice(&rows[k..]);
    }
    if test.is_empty() {
        return Err(HybridError::InvalidConfig(format!(
            "a split stratified by level at test fraction {test_fraction} tests no row (each \
             level is too small for a test row of its own): raise --test-fraction or give \
             more rows"
        )));
    }
    train.sort_unstable();
    test.sort_unstable();
    Ok(Split { train, test })
}

/// `k` folds of the rows of `stratum` (one stratum per row) that keep each stratum spread
/// over the folds: within each stratum (shuffled as [`stratified_split`] shuffles it) the
/// rows go round the folds in turn, each stratum starting where the last one stopped, so a
/// level of 2 rows is never held out whole while another fold has none of it.
pub(crate) fn stratified_folds(stratum: &[usize], k: usize, seed: u64) -> Vec<Split> {
    use rand::SeedableRng;
    use rand::seq::SliceRandom;
    let mut by: BTreeMap<usize, Vec<usize>> = BTreeMap::new();
    for (i, s) in stratum.iter().enumerate() {
        by.entry(*s).or_default().push(i);
    }
    let mut fold_of = vec![0usize; stratum.len()];
    let mut next = 0;
    for (s, mut rows) in by {
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(
            seed ^ (s as u64).wrapping_mul(0x9e37_79b9_7f4a_7c15),
        );
        rows.shuffle(&mut rng);
        for r in rows {
            fold_of[r] = next % k.max(1);
            next += 1;
        }
    }
    (0..k)
        .map(|f| {
            let (test, train): (Vec<usize>, Vec<usize>) =
                (0..stratum.len()).partition(|&i| fold_of[i] == f);
            Split { train, test }
        })
        .collect()
}

pub(crate) fn check_rows(table: &Table, split: &Split) -> Result<(), HybridError> {
    let n = table.n_rows();
    if split.train.is_empty() {
        return Err(HybridError::NoData("the split has no training rows".into()));
    }
    if let Some(&i) = split.train.iter().chain(&split.test).find(|&&i| i >= n) {
        return Err(HybridError::InvalidConfig(format!(
            "row index {i} is out of range: the table has {n} rows"
        )));
    }
    Ok(())
}
