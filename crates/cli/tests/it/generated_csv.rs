//! Property test: generated CSV files (random headers with repeats and blanks, empty cells,
//! text, huge and tiny numbers, ragged rows) fed to `hxai sr`, `hxai compare` and
//! `hxai features` end with exit code 0 or 1, never a panic (101), and a refusal is one
//! line on stderr. The case count is small so CI stays fast; each case runs the binary.
#![allow(clippy::unwrap_used)]

use proptest::prelude::*;

use crate::common;

fn cell() -> impl Strategy<Value = String> {
    prop_oneof![
        4 => (-1e3f64..1e3).prop_map(|v| v.to_string()),
        1 => Just(String::new()),
        1 => Just("n/a".to_string()),
        1 => Just("1e400".to_string()),
        1 => Just("-1e-320".to_string()),
        1 => Just("NaN".to_string()),
        1 => Just("\"1,5\"".to_string()),
        1 => (0u64..5).prop_map(|v| v.to_string()),
    ]
}

fn header() -> impl Strategy<Value = Vec<String>> {
    let name = prop_oneof![
        Just("time_s".to_string()),
        Just("accel_ms2".to_string()),
        Just("x".to_string()),
        Just("y".to_string()),
        Just(String::new()),
        Just("a b".to_string()),
        Just("µ".to_string()),
    ];
    prop::collection::vec(name, 1..5)
}

fn csv_text() -> impl Strategy<Value = String> {
    (header(), 0usize..25).prop_flat_map(|(h, rows)| {
        let width = h.len();
        prop::collection::vec(
            prop::collection::vec(cell(), width.saturating_sub(1)..=width + 1),
            rows,
        )
        .prop_map(move |body| {
            let mut s = h.join(",");
            s.push('\n');
            for r in body {
                s.push_str(&r.join(","));
                s.push('\n');
            }
            s
        })
    })
}

fn run(args: &[&str]) -> (Option<i32>, String) {
    let out = common::hxai(args).unwrap();
    (
        out.status.code(),
        String::from_utf8_lossy(&out.stderr).into_owned(),
    )
}

fn check(args: &[&str]) -> Result<(), TestCaseError> {
    let (code, stderr) = run(args);
    prop_assert!(
        code == Some(0) || code == Some(1),
        "{args:?}: exit {code:?}\n{stderr}"
    );
    if code == Some(1) {
        let errors: Vec<&str> = stderr
            .lines()
            .filter(|l| l.starts_with("error: "))
            .collect();
        prop_assert_eq!(errors.len(), 1, "{:?}: {}", args, stderr);
        prop_assert!(!stderr.contains("panicked"), "{:?}: {}", args, stderr);
    }
    Ok(())
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 12, failure_persistence: None, ..ProptestConfig::default() })]

    #[test]
    fn generated_csv_never_panics(text in csv_text(), k in 0u32..1000) {
        let dir = std::env::temp_dir().join(format!("hxai-gen-{}-{k}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let path = dir.join("t.csv");
        std::fs::write(&path, &text).unwrap();
        let p = path.to_str().unwrap();
        check(&["sr", "--csv", p, "--target", "y", "--epochs", "1", "--max-evaluations", "200"])?;
        check(&["compare", "--train", p, "--test", p, "--target", "y"])?;
        check(&["features", "--record", p, "--frequency-hz", "20"])?;
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
