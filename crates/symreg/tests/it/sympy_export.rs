//! The sympy export must read back with plain `sympy.sympify` for any column name.
//!
//! The escaping is tested in pure Rust here; with `HXAI_PYTHON` naming a python that has
//! sympy (CI sets it), `scripts/check_sympy_export.py` also confirms it with sympy itself.
#![allow(clippy::unwrap_used, clippy::print_stderr)]

use hxai_symreg::Op;
use hxai_symreg::expr::{Expr, SYMPY_RESERVED, sympy_symbol};
use std::io::Write;
use std::process::{Command, Stdio};

/// Names a user's table can have that sympy reads as something else, or not at all.
const AWKWARD: &[&str] = &[
    "E",
    "I",
    "N",
    "S",
    "Q",
    "O",
    "pi",
    "oo",
    "beta",
    "gamma",
    "zeta",
    "lambda",
    "re",
    "im",
    "sin",
    "exp",
    "Symbol",
    "x",
    "f3",
    "A_phys",
    "a b",
    "a_b",
    "a-b",
    "1st",
    "_x",
    "it's",
    "back\\slash",
    "µm",
    "μm",
    "Δt",
    "温度",
    "x.y",
    "None",
    "True",
    "if",
    "print",
    "max",
    "a'b\"c",
    "tab\tname",
    "😀",
];

fn sum_expr(names: &[&str]) -> Expr {
    let mut e: Option<Expr> = None;
    for (k, n) in names.iter().enumerate() {
        let term = Expr::Bin(
            Op::Mul,
            Box::new(Expr::Num(k as f64 + 2.0)),
            Box::new(Expr::Var((*n).to_owned())),
        );
        e = Some(match e {
            None => term,
            Some(acc) => Expr::Bin(Op::Add, Box::new(acc), Box::new(term)),
        });
    }
    e.unwrap()
}

#[test]
fn reserved_list_is_sorted_for_binary_search() {
    assert!(SYMPY_RESERVED.windows(2).all(|w| w[0] < w[1]));
    for n in [
        "E", "I", "N", "S", "Q", "O", "pi", "oo", "beta", "gamma", "lambda", "re", "im",
    ] {
        assert!(
            SYMPY_RESERVED.contains(&n),
            "{n} missing from the reserved list"
        );
    }
}

#[test]
fn escaping_is_injective_and_ascii() {
    let texts: Vec<String> = AWKWARD.iter().map(|n| sympy_symbol(n)).collect();
    for (i, t) in texts.iter().enumerate() {
        assert!(t.is_ascii(), "{t}");
        assert!(!t.contains('\n') && !t.contains('\t'), "{t}");
        for (j, u) in texts.iter().enumerate() {
            assert!(
                i == j || t != u,
                "{} and {} both give {t}",
                AWKWARD[i],
                AWKWARD[j]
            );
        }
    }
    assert_eq!(sympy_symbol("x"), "x");
    assert_eq!(sympy_symbol("A_phys"), "A_phys");
    assert_eq!(sympy_symbol("pi"), "Symbol('pi')");
    assert_eq!(sympy_symbol("a b"), "Symbol('a b')");
    assert_eq!(sympy_symbol("a_b"), "a_b");
    assert_eq!(sympy_symbol("back\\slash"), "Symbol('back\\\\slash')");
    assert_eq!(sympy_symbol("tab\tname"), "Symbol('tab\\u0009name')");
    assert_eq!(sympy_symbol("😀"), "Symbol('\\U0001f600')");
    // The names appear as written in a whole expression.
    let text = sum_expr(&["E", "a b"]).to_text(None, true);
    assert_eq!(text, "2*Symbol('E') + 3*Symbol('a b')");
}

#[test]
fn sympy_reads_every_awkward_name_back() {
    let Some(python) = std::env::var_os("HXAI_PYTHON") else {
        eprintln!("HXAI_PYTHON not set: sympy round trip skipped (the Rust checks above ran)");
        return;
    };
    let script = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../../scripts/check_sympy_export.py"
    );
    let cases: Vec<serde_json::Value> = AWKWARD
        .iter()
        .map(|n| serde_json::json!({"name": n, "text": sympy_symbol(n)}))
        .collect();
    let doc = serde_json::json!({
        "cases": cases,
        "sum": sum_expr(AWKWARD).to_text(None, true),
    });
    let mut child = Command::new(&python)
        .arg(script)
        .stdin(Stdio::piped())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap_or_else(|e| {
            panic!(
                "HXAI_PYTHON={} cannot be run ({e}); point it at a python with sympy or unset it",
                python.to_string_lossy()
            )
        });
    child
        .stdin
        .take()
        .unwrap()
        .write_all(doc.to_string().as_bytes())
        .unwrap();
    let out = child.wait_with_output().unwrap();
    let stdout = String::from_utf8_lossy(&out.stdout);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(
        !stderr.contains("ModuleNotFoundError"),
        "HXAI_PYTHON={} has no sympy: {stderr}",
        python.to_string_lossy()
    );
    assert!(
        out.status.success(),
        "sympy does not read the export back as the same symbols:\n{stdout}{stderr}"
    );
    eprintln!("{stdout}");
}
