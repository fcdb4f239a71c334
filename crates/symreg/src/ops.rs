//! Operators: names, arities, values and partial derivatives.
use crate::SrError;
use crate::vmath;
use serde::{Deserialize, Serialize};

/// One operator of an expression. Unary operators take one argument, binary two.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Op {
    /// a + b
    Add,
    /// a - b
    Sub,
    /// a * b
    Mul,
    /// a / b
    Div,
    /// exp(a)
    Exp,
    /// ln(a), rejected for a <= 0
    Log,
    /// sqrt(a), rejected for a < 0
    Sqrt,
    /// a^2
    Square,
    /// 1 / a
    Inverse,
    /// sin(a)
    Sin,
    /// cos(a)
    Cos,
    /// tanh(a)
    Tanh,
    /// |a|
    Abs,
    /// exp(-a^2)
    Gaussian,
    /// exp(-(a^2 + b^2)), QLattice's two-input gaussian
    Gaussian2,
    /// a^b (`a.powf(b)`): for user equations (`hxai hybrid`), not a search operator
    Pow,
    /// tan(a): for user equations (`hxai hybrid`), not a search operator
    Tan,
}

impl Op {
    /// Every operator the search can use, in a fixed order. [`Op::Pow`] and [`Op::Tan`]
    /// are left out: they exist for equations users write (see [`crate::infix`]), and the
    /// search's operator set stays as it was.
    pub const ALL: [Op; 15] = [
        Op::Add,
        Op::Sub,
        Op::Mul,
        Op::Div,
        Op::Exp,
        Op::Log,
        Op::Sqrt,
        Op::Square,
        Op::Inverse,
        Op::Sin,
        Op::Cos,
        Op::Tanh,
        Op::Abs,
        Op::Gaussian,
        Op::Gaussian2,
    ];

    /// The operator's name as used in configurations (`add`, `gaussian2`, ...).
    pub fn name(self) -> &'static str {
        match self {
            Op::Add => "add",
            Op::Sub => "sub",
            Op::Mul => "mul",
            Op::Div => "div",
            Op::Exp => "exp",
            Op::Log => "log",
            Op::Sqrt => "sqrt",
            Op::Square => "square",
            Op::Inverse => "inverse",
            Op::Sin => "sin",
            Op::Cos => "cos",
            Op::Tanh => "tanh",
            Op::Abs => "abs",
            Op::Gaussian => "gaussian",
            Op::Gaussian2 => "gaussian2",
            Op::Pow => "pow",
            Op::Tan => "tan",
        }
    }

    /// Parses an operator name (case-insensitive; `+ - * /` and a few aliases accepted).
    ///
    /// # Errors
    /// [`SrError::UnknownOperator`] for any other name.
    pub fn parse(name: &str) -> Result<Op, SrError> {
        let n = name.trim().to_ascii_lowercase();
        let op = match n.as_str() {
            "add" | "+" => Op::Add,
            "sub" | "-" => Op::Sub,
            "mul" | "multiply" | "*" => Op::Mul,
            "div" | "divide" | "/" => Op::Div,
            "exp" => Op::Exp,
            "log" | "ln" => Op::Log,
            "sqrt" => Op::Sqrt,
            "square" | "squared" => Op::Square,
            "inverse" | "inv" => Op::Inverse,
            "sin" => Op::Sin,
            "cos" => Op::Cos,
            "tanh" => Op::Tanh,
            "abs" => Op::Abs,
            "gaussian" => Op::Gaussian,
            "gaussian2" => Op::Gaussian2,
            _ => return Err(SrError::UnknownOperator(name.to_string())),
        };
        Ok(op)
    }

    /// 1 or 2.
    pub fn arity(self) -> usize {
        match self {
            Op::Add | Op::Sub | Op::Mul | Op::Div | Op::Gaussian2 | Op::Pow => 2,
            _ => 1,
        }
    }

    /// Value of a unary operator.
    #[inline]
    pub fn apply1(self, a: f64) -> f64 {
        match self {
            Op::Exp => vmath::exp(a),
            Op::Log => {
                if a > 0.0 {
                    vmath::ln(a)
                } else {
                    f64::NAN
                }
            }
            Op::Sqrt => a.sqrt(),
            Op::Square => a * a,
            Op::Inverse => 1.0 / a,
            Op::Sin => vmath::sin(a),
            Op::Cos => vmath::cos(a),
            Op::Tanh => vmath::tanh(a),
            Op::Abs => a.abs(),
            Op::Gaussian => vmath::exp(-a * a),
            Op::Tan => a.tan(),
            _ => f64::NAN,
        }
    }

    /// Value of a binary operator.
    #[inline]
    pub fn apply2(self, a: f64, b: f64) -> f64 {
        match self {
            Op::Add => a + b,
            Op::Sub => a - b,
            Op::Mul => a * b,
            Op::Div => a / b,
            Op::Gaussian2 => vmath::exp(-(a * a + b * b)),
            Op::Pow => a.powf(b),
            _ => f64::NAN,
        }
    }

    /// d out / d a of a unary operator, given the argument `a` and the value `out`.
    #[inline]
    pub fn d1(self, a: f64, out: f64) -> f64 {
        match self {
            Op::Exp => out,
            Op::Log => 1.0 / a,
            Op::Sqrt => 0.5 / out,
            Op::Square => 2.0 * a,
            Op::Inverse => -out * out,
            Op::Sin => vmath::cos(a),
            Op::Cos => -vmath::sin(a),
            Op::Tanh => 1.0 - out * out,
            Op::Abs => {
                if a > 0.0 {
                    1.0
                } else if a < 0.0 {
                    -1.0
                } else {
                    0.0
                }
            }
            Op::Gaussian => -2.0 * a * out,
            Op::Tan => 1.0 + out * out,
            _ => f64::NAN,
        }
    }

    /// (d out / d a, d out / d b) of a binary operator.
    #[inline]
    pub fn d2(self, a: f64, b: f64, out: f64) -> (f64, f64) {
        match self {
            Op::Add => (1.0, 1.0),
            Op::Sub => (1.0, -1.0),
            Op::Mul => (b, a),
            Op::Div => (1.0 / b, -out / b),
            Op::Gaussian2 => (-2.0 * a * out, -2.0 * b * out),
            // d/db = a^b ln a exists for a > 0 only (and is 0 where a^b is 0 for b > 0)
            Op::Pow => (
                if b == 0.0 { 0.0 } else { b * a.powf(b - 1.0) },
                if a > 0.0 {
                    out * a.ln()
                } else if out == 0.0 && b > 0.0 {
                    0.0
                } else {
                    f64::NAN
                },
            ),
            _ => (f64::NAN, f64::NAN),
        }
    }

    /// How plainly the operator reads in an engineering law (lower is plainer): arithmetic 0;
    /// powers, roots, `exp` and `log` (power laws and exponentials) 1; `abs` and the
    /// periodic and sigmoid functions 2; the gaussian 3, the two-input gaussian 4.
    pub fn plainness(self) -> usize {
        match self {
            Op::Add | Op::Sub | Op::Mul | Op::Div => 0,
            Op::Exp | Op::Log | Op::Sqrt | Op::Square | Op::Inverse | Op::Pow => 1,
            Op::Abs | Op::Sin | Op::Cos | Op::Tanh | Op::Tan => 2,
            Op::Gaussian => 3,
            Op::Gaussian2 => 4,
        }
    }

    /// Whether evaluating the operator costs a transcendental function call.
    pub fn is_transcendental(self) -> bool {
        matches!(
            self,
            Op::Exp
                | Op::Log
                | Op::Sin
                | Op::Cos
                | Op::Tanh
                | Op::Gaussian
                | Op::Gaussian2
                | Op::Pow
                | Op::Tan
        )
    }
}

/// Largest complexity one operator may be given: a single operator worth more than this
/// would not fit in a model under [`crate::SearchConfig::max_complexity`]'s own limit.
pub const MAX_OPERATOR_COMPLEXITY: usize = 20;

/// The complexity each operator adds to a model (1 each by default, the paper's count).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct OpCosts([usize; 17]);

impl Default for OpCosts {
    fn default() -> Self {
        OpCosts([1; 17])
    }
}

impl OpCosts {
    /// The costs of `overrides` (operator name, complexity); operators not named cost 1.
    ///
    /// # Errors
    /// [`SrError::UnknownOperator`] for a name [`Op::parse`] does not know,
    /// [`SrError::InvalidConfig`] for a complexity of 0 or above
    /// [`MAX_OPERATOR_COMPLEXITY`].
    pub fn parse<'a>(
        overrides: impl IntoIterator<Item = (&'a String, &'a usize)>,
    ) -> Result<OpCosts, SrError> {
        let mut costs = OpCosts::default();
        for (name, &c) in overrides {
            let op = Op::parse(name)?;
            if c == 0 || c > MAX_OPERATOR_COMPLEXITY {
                return Err(SrError::InvalidConfig(format!(
                    "operator_complexity of `{name}` is {c}: choose 1 to {MAX_OPERATOR_COMPLEXITY}"
                )));
            }
            costs.0[op as usize] = c;
        }
        Ok(costs)
    }

    /// The complexity `op` adds.
    #[inline]
    pub fn of(&self, op: Op) -> usize {
        self.0[op as usize]
    }
}

/// Parses a list of operator names.
///
/// # Errors
/// [`SrError::UnknownOperator`] for the first unknown name, [`SrError::InvalidConfig`] if the
/// list is empty.
pub fn parse_operators(names: &[String]) -> Result<Vec<Op>, SrError> {
    let mut ops = Vec::new();
    for n in names {
        let op = Op::parse(n)?;
        if !ops.contains(&op) {
            ops.push(op);
        }
    }
    if ops.is_empty() {
        return Err(SrError::InvalidConfig(
            "the operator list is empty: allow at least one operator".into(),
        ));
    }
    Ok(ops)
}
