//! The 100 equations of the AI Feynman database (Udrescu and Tegmark, "AI Feynman: a
//! physics-inspired method for symbolic regression", Science Advances 6(16), 2020), as
//! `/work/shared/data/feynman100.csv` gives them (its `Formula` column, sympy syntax), and
//! a structure key to compare laws by shape: the corpus must hold none of them
//! (issue 65: the AI Feynman 100 is a held-out set for the prior).

use crate::expr::Expr;
use crate::ops::Op;

/// (file name, formula) of each AI Feynman equation.
pub(super) const FEYNMAN: [(&str, &str); 100] = [
    ("I.6.2a", "exp(-theta**2/2)/sqrt(2*pi)"),
    ("I.6.2", "exp(-(theta/sigma)**2/2)/(sqrt(2*pi)*sigma)"),
    (
        "I.6.2b",
        "exp(-((theta-theta1)/sigma)**2/2)/(sqrt(2*pi)*sigma)",
    ),
    ("I.8.14", "sqrt((x2-x1)**2+(y2-y1)**2)"),
    ("I.9.18", "G*m1*m2/((x2-x1)**2+(y2-y1)**2+(z2-z1)**2)"),
    ("I.10.7", "m_0/sqrt(1-v**2/c**2)"),
    ("I.11.19", "x1*y1+x2*y2+x3*y3"),
    ("I.12.1", "mu*Nn"),
    ("I.12.2", "q1*q2*r/(4*pi*epsilon*r**3)"),
    ("I.12.4", "q1*r/(4*pi*epsilon*r**3)"),
    ("I.12.5", "q2*Ef"),
    ("I.12.11", "q*(Ef+B*v*sin(theta))"),
    ("I.13.4", "1/2*m*(v**2+u**2+w**2)"),
    ("I.13.12", "G*m1*m2*(1/r2-1/r1)"),
    ("I.14.3", "m*g*z"),
    ("I.14.4", "1/2*k_spring*x**2"),
    ("I.15.3x", "(x-u*t)/sqrt(1-u**2/c**2)"),
    ("I.15.3t", "(t-u*x/c**2)/sqrt(1-u**2/c**2)"),
    ("I.15.1", "m_0*v/sqrt(1-v**2/c**2)"),
    ("I.16.6", "(u+v)/(1+u*v/c**2)"),
    ("I.18.4", "(m1*r1+m2*r2)/(m1+m2)"),
    ("I.18.12", "r*F*sin(theta)"),
    ("I.18.14", "m*r*v*sin(theta)"),
    ("I.24.6", "1/2*m*(omega**2+omega_0**2)*1/2*x**2"),
    ("I.25.13", "q/C"),
    ("I.26.2", "arcsin(n*sin(theta2))"),
    ("I.27.6", "1/(1/d1+n/d2)"),
    ("I.29.4", "omega/c"),
    ("I.29.16", "sqrt(x1**2+x2**2-2*x1*x2*cos(theta1-theta2))"),
    ("I.30.3", "Int_0*sin(n*theta/2)**2/sin(theta/2)**2"),
    ("I.30.5", "arcsin(lambd/(n*d))"),
    ("I.32.5", "q**2*a**2/(6*pi*epsilon*c**3)"),
    (
        "I.32.17",
        "(1/2*epsilon*c*Ef**2)*(8*pi*r**2/3)*(omega**4/(omega**2-omega_0**2)**2)",
    ),
    ("I.34.8", "q*v*B/p"),
    ("I.34.1", "omega_0/(1-v/c)"),
    ("I.34.14", "(1+v/c)/sqrt(1-v**2/c**2)*omega_0"),
    ("I.34.27", "(h/(2*pi))*omega"),
    ("I.37.4", "I1+I2+2*sqrt(I1*I2)*cos(delta)"),
    ("I.38.12", "4*pi*epsilon*(h/(2*pi))**2/(m*q**2)"),
    ("I.39.1", "3/2*pr*V"),
    ("I.39.11", "1/(gamma-1)*pr*V"),
    ("I.39.22", "n*kb*T/V"),
    ("I.40.1", "n_0*exp(-m*g*x/(kb*T))"),
    (
        "I.41.16",
        "h/(2*pi)*omega**3/(pi**2*c**2*(exp((h/(2*pi))*omega/(kb*T))-1))",
    ),
    ("I.43.16", "mu_drift*q*Volt/d"),
    ("I.43.31", "mob*kb*T"),
    ("I.43.43", "1/(gamma-1)*kb*v/A"),
    ("I.44.4", "n*kb*T*ln(V2/V1)"),
    ("I.47.23", "sqrt(gamma*pr/rho)"),
    ("I.48.2", "m*c**2/sqrt(1-v**2/c**2)"),
    ("I.50.26", "x1*(cos(omega*t)+alpha*cos(omega*t)**2)"),
    ("II.2.42", "kappa*(T2-T1)*A/d"),
    ("II.3.24", "Pwr/(4*pi*r**2)"),
    ("II.4.23", "q/(4*pi*epsilon*r)"),
    ("II.6.11", "1/(4*pi*epsilon)*p_d*cos(theta)/r**2"),
    ("II.6.15a", "p_d/(4*pi*epsilon)*3*z/r**5*sqrt(x**2+y**2)"),
    (
        "II.6.15b",
        "p_d/(4*pi*epsilon)*3*cos(theta)*sin(theta)/r**3",
    ),
    ("II.8.7", "3/5*q**2/(4*pi*epsilon*d)"),
    ("II.8.31", "epsilon*Ef**2/2"),
    ("II.10.9", "sigma_den/epsilon*1/(1+chi)"),
    ("II.11.3", "q*Ef/(m*(omega_0**2-omega**2))"),
    ("II.11.17", "n_0*(1+p_d*Ef*cos(theta)/(kb*T))"),
    ("II.11.20", "n_rho*p_d**2*Ef/(3*kb*T)"),
    ("II.11.27", "n*alpha/(1-(n*alpha/3))*epsilon*Ef"),
    ("II.11.28", "1+n*alpha/(1-(n*alpha/3))"),
    ("II.13.17", "1/(4*pi*epsilon*c**2)*2*I/r"),
    ("II.13.23", "rho_c_0/sqrt(1-v**2/c**2)"),
    ("II.13.34", "rho_c_0*v/sqrt(1-v**2/c**2)"),
    ("II.15.4", "-mom*B*cos(theta)"),
    ("II.15.5", "-p_d*Ef*cos(theta)"),
    ("II.21.32", "q/(4*pi*epsilon*r*(1-v/c))"),
    ("II.24.17", "sqrt(omega**2/c**2-pi**2/d**2)"),
    ("II.27.16", "epsilon*c*Ef**2"),
    ("II.27.18", "epsilon*Ef**2"),
    ("II.34.2a", "q*v/(2*pi*r)"),
    ("II.34.2", "q*v*r/2"),
    ("II.34.11", "g_*q*B/(2*m)"),
    ("II.34.29a", "q*h/(4*pi*m)"),
    ("II.34.29b", "g_*mom*B*Jz/(h/(2*pi))"),
    ("II.35.18", "n_0/(exp(mom*B/(kb*T))+exp(-mom*B/(kb*T)))"),
    ("II.35.21", "n_rho*mom*tanh(mom*B/(kb*T))"),
    ("II.36.38", "mom*H/(kb*T)+(mom*alpha)/(epsilon*c**2*kb*T)*M"),
    ("II.37.1", "mom*(1+chi)*B"),
    ("II.38.3", "Y*A*x/d"),
    ("II.38.14", "Y/(2*(1+sigma))"),
    ("III.4.32", "1/(exp((h/(2*pi))*omega/(kb*T))-1)"),
    (
        "III.4.33",
        "(h/(2*pi))*omega/(exp((h/(2*pi))*omega/(kb*T))-1)",
    ),
    ("III.7.38", "2*mom*B/(h/(2*pi))"),
    ("III.8.54", "sin(E_n*t/(h/(2*pi)))**2"),
    (
        "III.9.52",
        "(p_d*Ef*t/(h/(2*pi)))*sin((omega-omega_0)*t/2)**2/((omega-omega_0)*t/2)**2",
    ),
    ("III.10.19", "mom*sqrt(Bx**2+By**2+Bz**2)"),
    ("III.12.43", "n*(h/(2*pi))"),
    ("III.13.18", "2*E_n*d**2*k/(h/(2*pi))"),
    ("III.14.14", "I_0*(exp(q*Volt/(kb*T))-1)"),
    ("III.15.12", "2*U*(1-cos(k*d))"),
    ("III.15.14", "(h/(2*pi))**2/(2*E_n*d**2)"),
    ("III.15.27", "2*pi*alpha/(n*d)"),
    ("III.17.37", "beta*(1+alpha*cos(theta))"),
    (
        "III.19.51",
        "-m*q**4/(2*(4*pi*epsilon)**2*(h/(2*pi))**2)*(1/n**2)",
    ),
    ("III.21.20", "-rho_c_0*q*A_vec/m"),
];

/// A canonical tree: sums and products flattened, their numbers folded, their terms
/// sorted; `a - b` is `a + (-1) b`, `a / b` is `a b^-1`, `square`, `sqrt`, `inverse` are
/// powers; every name is the same symbol.
#[derive(Clone, Debug)]
enum K {
    Num(f64),
    Sym,
    Add(Vec<K>),
    Mul(Vec<K>),
    Pow(Box<K>, Box<K>),
    Fn(Op, Box<K>),
}

fn add(items: Vec<K>) -> K {
    let mut terms = Vec::new();
    let mut sum = 0.0;
    for k in items {
        match k {
            K::Add(inner) => terms.extend(inner),
            K::Num(v) => sum += v,
            k => terms.push(k),
        }
    }
    if sum != 0.0 || terms.is_empty() {
        terms.push(K::Num(sum));
    }
    if terms.len() == 1 {
        terms.remove(0)
    } else {
        K::Add(terms)
    }
}

fn mul(items: Vec<K>) -> K {
    let mut factors = Vec::new();
    let mut coefficient = 1.0;
    for k in items {
        match k {
            K::Mul(inner) => {
                for f in inner {
                    match f {
                        K::Num(v) => coefficient *= v,
                        f => factors.push(f),
                    }
                }
            }
            K::Num(v) => coefficient *= v,
            k => factors.push(k),
        }
    }
    if coefficient != 1.0 || factors.is_empty() {
        factors.push(K::Num(coefficient));
    }
    if factors.len() == 1 {
        factors.remove(0)
    } else {
        K::Mul(factors)
    }
}

fn pow(base: K, exponent: K) -> K {
    match (base, exponent) {
        (b, K::Num(1.0)) => b,
        (K::Num(b), K::Num(p)) => K::Num(b.powf(p)),
        (K::Mul(fs), K::Num(p)) => mul(fs.into_iter().map(|f| pow(f, K::Num(p))).collect()),
        (K::Pow(b, q), K::Num(p)) => match *q {
            K::Num(q) => pow(*b, K::Num(p * q)),
            q => K::Pow(Box::new(K::Pow(b, Box::new(q))), Box::new(K::Num(p))),
        },
        (b, e) => K::Pow(Box::new(b), Box::new(e)),
    }
}

fn canon(e: &Expr) -> K {
    match e {
        Expr::Num(v) => K::Num(*v),
        Expr::Var(_) => K::Sym,
        Expr::Neg(a) => mul(vec![K::Num(-1.0), canon(a)]),
        Expr::Un(Op::Square, a) => pow(canon(a), K::Num(2.0)),
        Expr::Un(Op::Sqrt, a) => pow(canon(a), K::Num(0.5)),
        Expr::Un(Op::Inverse, a) => pow(canon(a), K::Num(-1.0)),
        Expr::Un(op, a) => match canon(a) {
            K::Num(v) => K::Num(op.apply1(v)),
            k => K::Fn(*op, Box::new(k)),
        },
        Expr::Bin(Op::Add, a, b) => add(vec![canon(a), canon(b)]),
        Expr::Bin(Op::Sub, a, b) => add(vec![canon(a), mul(vec![K::Num(-1.0), canon(b)])]),
        Expr::Bin(Op::Mul, a, b) => mul(vec![canon(a), canon(b)]),
        Expr::Bin(Op::Div, a, b) => mul(vec![canon(a), pow(canon(b), K::Num(-1.0))]),
        Expr::Bin(Op::Pow, a, b) => pow(canon(a), canon(b)),
        Expr::Bin(op, a, b) => K::Fn(*op, Box::new(K::Add(vec![canon(a), canon(b)]))),
    }
}

fn text(k: &K) -> String {
    let sorted = |items: &[K]| {
        let mut t: Vec<String> = items.iter().map(text).collect();
        t.sort();
        t.join(",")
    };
    match k {
        K::Num(v) => {
            let v = if *v == 0.0 { 0.0 } else { *v };
            format!("{v:.4}")
        }
        K::Sym => "s".into(),
        K::Add(items) => format!("add({})", sorted(items)),
        K::Mul(items) => format!("mul({})", sorted(items)),
        K::Pow(b, e) => format!("pow({},{})", text(b), text(e)),
        K::Fn(op, a) => format!("{}({})", op.name(), text(a)),
    }
}

/// The structure key of an expression: equal for expressions that differ only in their
/// names, the order of sums and products, and the way a quotient, a square or a root is
/// written.
pub(super) fn structure_key(e: &Expr) -> String {
    text(&canon(e))
}
