//! The committed program set for the pyoperon comparison matches the generator.
//! Regenerate with `HXAI_BLESS=1 cargo test -p hxai-symreg --test eval_programs`.
#![allow(clippy::unwrap_used)]
use hxai_symreg::bench_programs::programs;
use hxai_symreg::{Node, Op, Program};

/// Fully parenthesised infix with function-call unary operators, as Operon's parser reads it
/// (inputs are Operon's default names X1, X2, X3).
fn operon_infix(p: &Program, params: &[f64]) -> String {
    let offs = p.param_offsets();
    let mut st: Vec<String> = Vec::new();
    for (k, n) in p.nodes.iter().enumerate() {
        let s = match n {
            Node::Var(j) => format!("X{}", j + 1),
            Node::Const => format!("{:?}", params[offs[k]]),
            Node::Op(op) => {
                let b = st.pop().unwrap();
                if op.arity() == 2 {
                    let a = st.pop().unwrap();
                    let sym = match op {
                        Op::Add => "+",
                        Op::Sub => "-",
                        Op::Mul => "*",
                        _ => "/",
                    };
                    format!("({a} {sym} {b})")
                } else {
                    format!("{}({b})", op.name())
                }
            }
        };
        st.push(s);
    }
    st.pop().unwrap()
}

#[test]
fn committed_eval_programs_are_current() {
    let list: Vec<serde_json::Value> = programs(100, 7)
        .into_iter()
        .map(|(p, params)| {
            serde_json::json!({"nodes": p.nodes.len(), "infix": operon_infix(&p, &params)})
        })
        .collect();
    let text = serde_json::to_string_pretty(&serde_json::json!({"rows_formula": "0.5 + 2*((7919*r + 104729*j) % 10007)/10007", "programs": list})).unwrap();
    let path = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../../testdata/symreg/eval_programs.json"
    );
    if std::env::var("HXAI_BLESS").is_ok() {
        std::fs::create_dir_all(concat!(
            env!("CARGO_MANIFEST_DIR"),
            "/../../testdata/symreg"
        ))
        .unwrap();
        std::fs::write(path, &text).unwrap();
    }
    let stored = std::fs::read_to_string(path).unwrap();
    assert_eq!(
        stored, text,
        "testdata/symreg/eval_programs.json is stale: rerun with HXAI_BLESS=1"
    );
}
