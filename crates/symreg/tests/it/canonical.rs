//! The canonical form (`hxai_symreg::canonical`): each rewrite of its rule set, structures
//! that must meet and structures that must stay apart (the property tests of value and
//! invariance are in `canonical_properties`).
#![allow(clippy::unwrap_used)]
use hxai_symreg::canonical::{
    Effort, canonical_expr, degrees_of_freedom, structure_expr_with, structure_key,
    structure_key_expr, structure_with,
};
use hxai_symreg::expr::Expr;
use hxai_symreg::{Node, Op, Program, infix};

pub(crate) fn p(s: &str) -> Expr {
    infix::parse(s).unwrap().expr
}

fn var(n: &str) -> Box<Expr> {
    Box::new(Expr::Var(n.into()))
}

fn key(e: &Expr) -> String {
    let c = structure_expr_with(e, Effort::Full);
    assert!(c.saturated, "{e:?} did not saturate");
    let k = c.expr.to_text(None, true);
    assert_eq!(k, structure_key_expr(e));
    k
}

/// Pairs written with `c` for constants (each `c` a different non-literal number) that must
/// be one structure, and the key they share.
fn same(a: &str, b: &str, want: &str) {
    let (ea, eb) = (with_constants(a), with_constants(b));
    assert_eq!(key(&ea), want, "{a}");
    assert_eq!(key(&eb), want, "{b}");
    // and the numeric canonical form keeps the value
    for e in [&ea, &eb] {
        close_at_points(e, &canonical_expr(e));
    }
}

/// `s` with each `c` replaced by a distinct number that is not a small literal.
fn with_constants(s: &str) -> Expr {
    let mut out = String::new();
    let mut k = 0;
    let chars: Vec<char> = s.chars().collect();
    for (i, ch) in chars.iter().enumerate() {
        let alone = |j: Option<&char>| j.is_none_or(|c| !c.is_alphanumeric() && *c != '_');
        if *ch == 'c' && alone(i.checked_sub(1).map(|j| &chars[j])) && alone(chars.get(i + 1)) {
            k += 1;
            out.push_str(&format!(
                "{}",
                1.0 + 0.37 * k as f64 + 0.0013 * (k * k) as f64
            ));
        } else {
            out.push(*ch);
        }
    }
    p(&out)
}

pub(crate) fn close_at_points(a: &Expr, b: &Expr) {
    for (x, y, z) in [(0.7, 1.3, 2.1), (1.9, 0.4, 0.8), (2.6, 2.2, 1.1)] {
        let look = |n: &str| match n {
            "x" | "x1" => x,
            "y" | "x2" => y,
            _ => z,
        };
        let (u, v) = (a.eval(&look), b.eval(&look));
        if u.is_finite() && v.is_finite() {
            assert!(
                (u - v).abs() <= 1e-9 * (1.0 + u.abs()),
                "{} = {u} but {} = {v}",
                a.to_text(None, false),
                b.to_text(None, false)
            );
        }
    }
}

#[test]
fn reordered_sums_and_products_are_one_structure() {
    same("c*x1*x2 + c", "c + c*x2*x1", "c*x1*x2 + c");
    same("x*(c*(c*y))", "c*x*y", "c*x*y");
    same("(x + y) + z", "x + (z + y)", "x + y + z");
}

#[test]
fn constants_are_absorbed() {
    same("c + (c + x)", "c + x", "x + c");
    same("c*(c*x)", "c*x", "c*x");
    same("exp(c + x)", "c*exp(x)", "c*exp(x)");
    same("(c*x)/(c*y)", "c*x/y", "c*x/y");
    same("x - (c + y)", "c + (x - y)", "x - y + c");
    same("log(c*x)", "c + log(x)", "log(x) + c");
    same("sqrt(c*x)", "c*sqrt(x)", "c*sqrt(x)");
    same("(c*x)^2", "c*x^2", "c*x**2");
    same("1/(c*x)", "c/x", "c/x");
    same("c*log(c*x + c) + c", "c*log(x + c) + c", "c*log(x + c) + c");
    same("c*x + c*x", "c*x", "c*x");
    same("x + c*x", "c*x", "c*x");
    same("abs(c*x)", "c*abs(x)", "c*Abs(x)");
    // of two forms of one length, the one with fewer constants (a constant split in two
    // under a square root whose argument is negative: a draw of the property test
    // `rewrites_keep_the_key`)
    same("-sqrt(-(c*x))", "c*sqrt(-(c*(c*x)))", "c*sqrt(-x)");
    // a power of an exponential is an exponential
    same("c/exp(c*x) + c", "c*exp(c*x) + c", "c*exp(c*x) + c");
    same("c*exp(c*x)^2", "c*exp(c*x)", "c*exp(c*x)");
    same("c*sqrt(exp(c*x + c))", "c*exp(c*x)", "c*exp(c*x)");
    same(
        "c*(x + c)/exp(c*y) + c",
        "c*(x + c)*exp(c*y) + c",
        "c*(x + c)*exp(c*y) + c",
    );
}

#[test]
fn operator_identities() {
    let x = || var("x");
    let y = || var("y");
    let neg_sq = |a: Box<Expr>| Box::new(Expr::Neg(Box::new(Expr::Un(Op::Square, a))));
    let cases: Vec<(Expr, Expr)> = vec![
        // gaussian(a) = exp(-a^2)
        (Expr::Un(Op::Gaussian, x()), Expr::Un(Op::Exp, neg_sq(x()))),
        // gaussian2(a, b) = exp(-(a^2 + b^2)) = exp(-a^2) exp(-b^2)
        (Expr::Bin(Op::Gaussian2, x(), y()), p("exp(-(x^2 + y^2))")),
        (Expr::Bin(Op::Gaussian2, x(), y()), p("exp(-x^2)*exp(-y^2)")),
        // inverse(a) = 1/a, square(a) = a^2 = a*a
        (Expr::Un(Op::Inverse, x()), p("1/x")),
        (Expr::Un(Op::Square, x()), p("x*x")),
        (Expr::Un(Op::Square, x()), p("x^2")),
        // sub is add of -1*, neg is -1*, div is mul by the inverse
        (p("x - y"), p("x + (-1)*y")),
        (p("x - y"), p("-y + x")),
        (Expr::Neg(x()), p("(-1)*x")),
        (
            p("x/y"),
            Expr::Bin(Op::Mul, x(), Box::new(Expr::Un(Op::Inverse, y()))),
        ),
        // log of exp, signs through odd and even functions
        (p("log(exp(x + y))"), p("y + x")),
        (p("sin(-x)"), p("-sin(x)")),
        (p("cos(-x)"), p("cos(x)")),
        (p("tanh(-2*x)"), p("-tanh(2*x)")),
        (p("sqrt(x^2)"), p("abs(x)")),
        (p("x - (y + z)"), p("x - y - z")),
    ];
    for (a, b) in &cases {
        assert_eq!(
            key(a),
            key(b),
            "{} vs {}",
            a.to_text(None, false),
            b.to_text(None, false)
        );
        close_at_points(a, &canonical_expr(a));
        close_at_points(b, &canonical_expr(b));
    }
    assert_eq!(key(&Expr::Un(Op::Gaussian, x())), "exp(-x**2)");
    assert_eq!(key(&p("x + (-1)*y")), "x - y");
}

#[test]
fn different_structures_stay_apart() {
    let pairs = [
        ("exp(x)", "exp(x^2)"),
        ("x*y", "x + y"),
        ("x - y", "x + y"),
        ("c*x + c*y", "c*(x + y)"),
        ("x*(y + z)", "x*y + x*z"),
        ("sin(x)", "cos(x)"),
        ("log(x)", "log(x + c)"),
        ("c*x", "x"),
        ("x/y", "y/x"),
        ("exp(c*x)", "c*exp(x)"),
        ("1/exp(x)", "exp(x)"),
        ("exp(x)^2", "exp(x)"),
    ];
    for (a, b) in pairs {
        let (ka, kb) = (key(&with_constants(a)), key(&with_constants(b)));
        assert_ne!(ka, kb, "{a} and {b}");
    }
}

#[test]
fn the_numeric_form_folds_and_keeps_values() {
    let e = p("2*(3*x) + (1 + (2 + y))");
    let c = canonical_expr(&e);
    assert_eq!(c.to_text(None, false), "y + 6*x + 3");
    let e = p("exp(2 + x)");
    let c = canonical_expr(&e);
    assert_eq!(c.to_text(Some(6), false), "7.38906*exp(x)");
    // an expression whose operands were written in another order prints the same
    let a = canonical_expr(&p("1.5*x*y + 0.25*exp(-y) - x"));
    let b = canonical_expr(&p("-x + exp(-y)*0.25 + y*(x*1.5)"));
    assert_eq!(a, b);
}

pub(crate) fn prog(nodes: Vec<Node>, affine: bool) -> Program {
    Program { nodes, affine }
}

pub(crate) fn names() -> Vec<String> {
    vec!["x".into(), "y".into(), "z".into()]
}

#[test]
fn programs_equal_up_to_constants_share_a_key() {
    use Node::{Const, Var};
    let op = Node::Op;
    // mul(x, y) and mul(y, x), with affine inputs
    let a = prog(vec![Var(0), Var(1), op(Op::Mul)], true);
    let b = prog(vec![Var(1), Var(0), op(Op::Mul)], true);
    assert_eq!(structure_key(&a, &names()), structure_key(&b, &names()));
    assert_eq!(structure_key(&a, &names()), "c*(x + c)*(y + c) + c");
    // inputs with their own scale: sub(x, y) is add(x, y)
    let a = prog(vec![Var(0), Var(1), op(Op::Sub)], true);
    let b = prog(vec![Var(0), Var(1), op(Op::Add)], true);
    assert_eq!(structure_key(&a, &names()), structure_key(&b, &names()));
    // without: they differ
    let a = prog(vec![Var(0), Var(1), op(Op::Sub)], false);
    let b = prog(vec![Var(0), Var(1), op(Op::Add)], false);
    assert_ne!(structure_key(&a, &names()), structure_key(&b, &names()));
    // a constant factor inside is absorbed by the output scale
    let a = prog(vec![Var(0), Const, Var(1), op(Op::Mul), op(Op::Mul)], false);
    let b = prog(vec![Var(0), Var(1), op(Op::Mul)], false);
    assert_eq!(structure_key(&a, &names()), structure_key(&b, &names()));
    assert_eq!(structure_key(&a, &names()), "c*x*y + c");
    // exp(x + c) is exp(x) under the output scale
    let a = prog(vec![Var(0), Const, op(Op::Add), op(Op::Exp)], false);
    let b = prog(vec![Var(0), op(Op::Exp)], false);
    assert_eq!(structure_key(&a, &names()), structure_key(&b, &names()));
    // gaussian2 of (x, y) is gaussian2 of (y, x), and of a product the product either way
    let a = prog(
        vec![Var(0), Var(1), op(Op::Mul), Var(2), op(Op::Gaussian2)],
        true,
    );
    let b = prog(
        vec![Var(2), Var(1), Var(0), op(Op::Mul), op(Op::Gaussian2)],
        true,
    );
    assert_eq!(structure_key(&a, &names()), structure_key(&b, &names()));
    // and different programs differ
    let c = prog(vec![Var(0), Var(1), op(Op::Gaussian2)], true);
    assert_ne!(structure_key(&a, &names()), structure_key(&c, &names()));
}

// A parameter that is exactly 0 (a snapped shift) leaves the structure; every other one
// counts, whatever its value: `s*log(w*x + b) + o` is `c*log(x) + c` at `b = 0` (the scale
// `w` gives up its constant to the offset), `c*log(x + c) + c` otherwise.
#[test]
fn degrees_of_freedom_count_the_constants_the_algebra_leaves() {
    use Node::Var;
    let op = Node::Op;
    let log = prog(vec![Var(0), op(Op::Log)], true);
    let inv = prog(vec![Var(0), op(Op::Inverse)], true);
    let n = names();
    assert_eq!(degrees_of_freedom(&log, &[-2.46, -4.0, 1.3, 0.0], &n), 2);
    assert_eq!(degrees_of_freedom(&log, &[-2.46, -4.0, 1.3, 0.01], &n), 3);
    // a whole number is a constant still fitted: it counts
    assert_eq!(degrees_of_freedom(&log, &[-2.0, -4.0, 1.0, 2.0], &n), 3);
    // s/(w*x + b) + o is c/(x + c) + c
    assert_eq!(degrees_of_freedom(&inv, &[4.8, -6.0, 1.5, 0.5], &n), 3);
    assert_eq!(degrees_of_freedom(&inv, &[4.8, -6.0, 1.5, 0.0], &n), 2);
    // a product of two affine inputs: c*(x + c)*(y + c) + c, and c*x*(y + c) + c
    let mul = prog(vec![Var(0), Var(1), op(Op::Mul)], true);
    assert_eq!(
        degrees_of_freedom(&mul, &[1.2, 0.3, 0.7, 0.1, 1.1, 0.4], &n),
        4
    );
    assert_eq!(
        degrees_of_freedom(&mul, &[1.2, 0.3, 0.7, 0.0, 1.1, 0.4], &n),
        3
    );
}

// With no parameter at 0, the degrees of freedom are the parameters of the structure key:
// its `c`s, on random programs of 5 and 6 nodes with and without affine inputs.
#[test]
fn degrees_of_freedom_without_zeros_are_the_keys_constants() {
    let names = vec!["x0".to_string(), "x1".into(), "x2".into()];
    let mut programs = hxai_symreg::bench_programs::affine_programs(40, 5);
    programs.extend(hxai_symreg::bench_programs::programs(40, 6));
    for (program, params) in &programs {
        let values: Vec<f64> = (0..params.len()).map(|i| 0.3 + i as f64 * 0.37).collect();
        let key = structure_key(program, &names);
        let cs = key
            .split(|ch: char| !ch.is_alphanumeric() && ch != '_')
            .filter(|t| *t == "c")
            .count();
        assert_eq!(degrees_of_freedom(program, &values, &names), cs, "{key}");
    }
}

#[test]
fn keys_are_deterministic_and_fast_is_a_coarser_path() {
    let progs = hxai_symreg::bench_programs::affine_programs(30, 5);
    let names = vec!["x0".to_string(), "x1".into(), "x2".into()];
    for (prog, _) in &progs {
        let full = structure_with(prog, &names, Effort::Full);
        assert_eq!(full, structure_with(prog, &names, Effort::Full));
        let fast = structure_with(prog, &names, Effort::Fast);
        assert_eq!(fast, structure_with(prog, &names, Effort::Fast));
        assert_eq!(
            full.expr.to_text(None, true),
            structure_key(prog, &names),
            "the default is Full"
        );
    }
    // in parallel, the same keys
    let keys: Vec<String> = progs
        .iter()
        .map(|(p, _)| structure_key(p, &names))
        .collect();
    let par: Vec<String> = std::thread::scope(|s| {
        let hs: Vec<_> = progs
            .iter()
            .map(|(p, _)| s.spawn(|| structure_key(p, &names)))
            .collect();
        hs.into_iter().map(|h| h.join().unwrap()).collect()
    });
    assert_eq!(keys, par);
}

/// The keys are sympy-readable: the infix parser (Python's syntax) reads them back.
#[test]
fn keys_parse_back() {
    for (prog, _) in hxai_symreg::bench_programs::affine_programs(20, 9) {
        let k = structure_key(&prog, &["x0".into(), "x1".into(), "x2".into()]);
        assert!(infix::parse(&k).is_ok(), "{k}");
    }
}
