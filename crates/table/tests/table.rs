//! The table's invariants (one length, unique non-empty names, finite values) hold after
//! every constructor and method, and every bad input is a typed error, never a panic.
#![allow(clippy::unwrap_used)]
use hxai_table::{Table, TableError};
use proptest::prelude::*;

fn names(n: usize) -> Vec<String> {
    (0..n).map(|i| format!("c{i}")).collect()
}

#[test]
fn constructor_refuses_each_bad_shape_by_name() {
    assert_eq!(Table::new(vec![], vec![]), Err(TableError::NoColumns));
    assert_eq!(
        Table::new(names(2), vec![vec![1.0]]),
        Err(TableError::NamesColumnsMismatch {
            names: 2,
            columns: 1
        })
    );
    assert_eq!(
        Table::new(vec!["a".into(), " ".into()], vec![vec![1.0], vec![2.0]]),
        Err(TableError::EmptyName { index: 1 })
    );
    assert_eq!(
        Table::new(vec!["y".into(), "y".into()], vec![vec![1.0], vec![2.0]]),
        Err(TableError::DuplicateName("y".into()))
    );
    assert_eq!(
        Table::new(names(2), vec![vec![1.0, 2.0], vec![2.0]]),
        Err(TableError::RaggedColumns {
            name: "c1".into(),
            expected: 2,
            got: 1
        })
    );
    let e = Table::new(names(1), vec![vec![1.0, f64::NAN]]).unwrap_err();
    assert!(matches!(e, TableError::NonFinite { row: 1, .. }), "{e}");
}

#[test]
fn views_and_selections_address_the_right_rows() {
    let t = Table::new(
        names(2),
        vec![vec![0.0, 1.0, 2.0, 3.0], vec![10.0, 11.0, 12.0, 13.0]],
    )
    .unwrap();
    let v = t.view(1..3).unwrap();
    assert_eq!(v.n_rows(), 2);
    assert_eq!(v.column("c1"), Some(&[11.0, 12.0][..]));
    assert_eq!(v.to_table().column("c0"), Some(&[1.0, 2.0][..]));
    assert!(t.view(3..5).is_err());
    assert_eq!(t.row(2), vec![2.0, 12.0]);
    assert_eq!(
        t.to_row_major(),
        vec![0.0, 10.0, 1.0, 11.0, 2.0, 12.0, 3.0, 13.0]
    );
    assert_eq!(
        t.select_rows(&[4]),
        Err(TableError::RowOutOfRange { row: 4, n_rows: 4 })
    );
    let s = t.select_columns(&["c1"]).unwrap();
    assert_eq!(s.names(), &["c1".to_string()]);
    assert!(matches!(
        t.select_columns(&["nope"]),
        Err(TableError::UnknownColumn { .. })
    ));
    let mut m = t.clone();
    assert!(m.push_column("c0".into(), vec![0.0; 4]).is_err());
    assert!(m.push_column("c2".into(), vec![0.0; 3]).is_err());
    m.push_column("c2".into(), vec![5.0; 4]).unwrap();
    assert_eq!(m.remove_column("c0").unwrap(), vec![0.0, 1.0, 2.0, 3.0]);
    assert_eq!(m.names(), &["c1".to_string(), "c2".to_string()]);
}

#[test]
fn deserialising_checks_the_invariants() {
    let ok: Table = serde_json::from_str(r#"{"names":["a"],"columns":[[1.0,2.0]]}"#).unwrap();
    assert_eq!(ok.n_rows(), 2);
    let bad = serde_json::from_str::<Table>(r#"{"names":["a","a"],"columns":[[1.0],[2.0]]}"#);
    assert!(bad.is_err());
    let round: Table = serde_json::from_str(&serde_json::to_string(&ok).unwrap()).unwrap();
    assert_eq!(round, ok);
}

proptest! {
    /// Selecting any rows keeps the names, gives exactly those rows, and row-major order
    /// agrees with `row`.
    #[test]
    fn selection_matches_row_lookup(
        cols in 1usize..4,
        data in prop::collection::vec(-1e6f64..1e6, 0..40),
        picks in prop::collection::vec(0usize..100, 0..20),
    ) {
        let n_rows = data.len() / cols;
        let columns: Vec<Vec<f64>> = (0..cols)
            .map(|c| (0..n_rows).map(|r| data[r * cols + c]).collect())
            .collect();
        let t = Table::new(names(cols), columns).unwrap();
        let picks: Vec<usize> = picks.into_iter().filter(|&p| p < n_rows).collect();
        let s = t.select_rows(&picks).unwrap();
        prop_assert_eq!(s.n_rows(), picks.len());
        prop_assert_eq!(s.names(), t.names());
        for (i, &p) in picks.iter().enumerate() {
            prop_assert_eq!(s.row(i), t.row(p));
        }
        let rm = t.to_row_major();
        for r in 0..n_rows {
            prop_assert_eq!(&rm[r * cols..(r + 1) * cols], &t.row(r)[..]);
        }
    }
}
