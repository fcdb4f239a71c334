//! Units as text (`kg*m/s^2`, `N/mm^2`, `1/min`) and the dimensions they stand for.
//!
//! Only the dimension matters for dimensional analysis: `mm` and `km` are both a length,
//! `min` and `h` both a time. A scale between units of one dimension is a constant the
//! search fits, so it is dropped here.
use crate::SrError;
use std::fmt;

/// The SI base dimensions, in the order of [`Dimension`]'s exponents.
pub const BASE: [&str; 7] = ["m", "kg", "s", "A", "K", "mol", "cd"];

/// Exponents of the seven SI base dimensions (length, mass, time, current, temperature,
/// amount, luminous intensity), in the order of [`BASE`].
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Default)]
pub struct Dimension(pub [i32; 7]);

impl Dimension {
    /// A dimensionless quantity.
    pub const NONE: Dimension = Dimension([0; 7]);

    /// The product of two quantities' dimensions.
    pub fn times(self, o: Dimension) -> Dimension {
        let mut e = self.0;
        for (a, b) in e.iter_mut().zip(o.0) {
            *a += b;
        }
        Dimension(e)
    }

    /// The dimension raised to an integer power.
    pub fn pow(self, k: i32) -> Dimension {
        Dimension(self.0.map(|a| a * k))
    }

    /// Whether every exponent is zero.
    pub fn is_none(self) -> bool {
        self == Dimension::NONE
    }

    /// Reads a unit such as `kg*m/s^2`, `N/mm^2`, `J/(kg*K)`, `1/min` or `1`.
    ///
    /// Factors are joined by `*`, `.` or `/` (each `/` divides by the factor after it);
    /// powers are written `^2`, `^-1` or `**2`; parentheses group. The known names are the
    /// SI base and derived units with the prefixes p n u µ m c d k M G, and `min`, `h`,
    /// `rpm`, `l`, `bar`, `rad`, `deg`, `%`. `degC` is refused: a temperature
    /// measured from an offset zero cannot enter a power law.
    ///
    /// # Errors
    /// [`SrError::InvalidConfig`] naming the unit and what is wrong with it.
    pub fn parse(text: &str) -> Result<Dimension, SrError> {
        let chars: Vec<char> = text.trim().chars().collect();
        if chars.is_empty() {
            return Err(bad(
                text,
                "it is empty (write `1` for a dimensionless column)",
            ));
        }
        let mut p = Parser {
            text,
            chars,
            pos: 0,
        };
        let d = p.product()?;
        if p.pos < p.chars.len() {
            return Err(bad(
                text,
                &format!("unexpected `{}` at character {}", p.chars[p.pos], p.pos + 1),
            ));
        }
        Ok(d)
    }
}

impl fmt::Display for Dimension {
    /// `m*kg/s^2`-style text in base units (`1` when dimensionless).
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let part = |sign: i32| -> Vec<String> {
            BASE.iter()
                .zip(self.0)
                .filter(|(_, e)| e * sign > 0)
                .map(|(n, e)| match e.abs() {
                    1 => (*n).to_string(),
                    k => format!("{n}^{k}"),
                })
                .collect()
        };
        write!(f, "{}", fraction_text(&part(1), &part(-1)))
    }
}

/// `a*b/c` or `a/(b*c)` from the factors above and below the line (`1` above when none).
pub(super) fn fraction_text(num: &[String], den: &[String]) -> String {
    let top = if num.is_empty() {
        "1".to_string()
    } else {
        num.join("*")
    };
    match den {
        [] => top,
        [one] => format!("{top}/{one}"),
        _ => format!("{top}/({})", den.join("*")),
    }
}

fn bad(text: &str, why: &str) -> SrError {
    SrError::InvalidConfig(format!("unit `{text}`: {why}"))
}

/// Exponents of a named unit without prefix, or `None`.
fn named(name: &str) -> Option<Dimension> {
    // [m, kg, s, A, K, mol, cd]
    let d = |e: [i32; 7]| Some(Dimension(e));
    match name {
        "1" | "-" | "rad" | "deg" | "%" | "sr" => d([0; 7]),
        "m" => d([1, 0, 0, 0, 0, 0, 0]),
        "g" => d([0, 1, 0, 0, 0, 0, 0]),
        "t" => d([0, 1, 0, 0, 0, 0, 0]),
        "s" | "min" | "h" => d([0, 0, 1, 0, 0, 0, 0]),
        "A" => d([0, 0, 0, 1, 0, 0, 0]),
        "K" => d([0, 0, 0, 0, 1, 0, 0]),
        "mol" => d([0, 0, 0, 0, 0, 1, 0]),
        "cd" => d([0, 0, 0, 0, 0, 0, 1]),
        "Hz" | "rpm" => d([0, 0, -1, 0, 0, 0, 0]),
        "N" => d([1, 1, -2, 0, 0, 0, 0]),
        "Pa" | "bar" => d([-1, 1, -2, 0, 0, 0, 0]),
        "J" => d([2, 1, -2, 0, 0, 0, 0]),
        "W" => d([2, 1, -3, 0, 0, 0, 0]),
        "C" => d([0, 0, 1, 1, 0, 0, 0]),
        "V" => d([2, 1, -3, -1, 0, 0, 0]),
        "ohm" | "Ω" => d([2, 1, -3, -2, 0, 0, 0]),
        "S" => d([-2, -1, 3, 2, 0, 0, 0]),
        "F" => d([-2, -1, 4, 2, 0, 0, 0]),
        "T" => d([0, 1, -2, -1, 0, 0, 0]),
        "Wb" => d([2, 1, -2, -1, 0, 0, 0]),
        "H" => d([2, 1, -2, -2, 0, 0, 0]),
        "l" | "L" => d([3, 0, 0, 0, 0, 0, 0]),
        _ => None,
    }
}

/// A unit name, with or without an SI prefix.
fn lookup(name: &str) -> Option<Dimension> {
    if let Some(d) = named(name) {
        return Some(d);
    }
    for prefix in ["p", "n", "u", "µ", "m", "c", "d", "k", "M", "G"] {
        if let Some(rest) = name.strip_prefix(prefix)
            && !rest.is_empty()
            && !matches!(rest, "1" | "-" | "%" | "min" | "h" | "rpm" | "deg")
            && let Some(d) = named(rest)
        {
            return Some(d);
        }
    }
    None
}

struct Parser<'a> {
    text: &'a str,
    chars: Vec<char>,
    pos: usize,
}

impl Parser<'_> {
    fn peek(&self) -> Option<char> {
        self.chars.get(self.pos).copied()
    }

    fn skip_space(&mut self) {
        while self.peek().is_some_and(char::is_whitespace) {
            self.pos += 1;
        }
    }

    /// factor (('*' | '.' | '/') factor)*
    fn product(&mut self) -> Result<Dimension, SrError> {
        let mut d = self.factor()?;
        loop {
            self.skip_space();
            match self.peek() {
                Some('*') if self.chars.get(self.pos + 1) != Some(&'*') => {
                    self.pos += 1;
                    d = d.times(self.factor()?);
                }
                Some('.') => {
                    self.pos += 1;
                    d = d.times(self.factor()?);
                }
                Some('/') => {
                    self.pos += 1;
                    d = d.times(self.factor()?.pow(-1));
                }
                _ => return Ok(d),
            }
        }
    }

    /// atom ('^' int | '**' int)?
    fn factor(&mut self) -> Result<Dimension, SrError> {
        self.skip_space();
        let d = self.atom()?;
        self.skip_space();
        let power = if self.peek() == Some('^') {
            self.pos += 1;
            true
        } else if self.peek() == Some('*') && self.chars.get(self.pos + 1) == Some(&'*') {
            self.pos += 2;
            true
        } else {
            false
        };
        if !power {
            return Ok(d);
        }
        self.skip_space();
        let start = self.pos;
        if matches!(self.peek(), Some('-' | '+')) {
            self.pos += 1;
        }
        while self.peek().is_some_and(|c| c.is_ascii_digit()) {
            self.pos += 1;
        }
        let digits: String = self.chars[start..self.pos].iter().collect();
        let k: i32 = digits.parse().map_err(|_| {
            bad(
                self.text,
                &format!("a power must be a whole number (character {})", start + 1),
            )
        })?;
        if k.abs() > 12 {
            return Err(bad(self.text, &format!("the power {k} is out of range")));
        }
        Ok(d.pow(k))
    }

    /// name | '1' | '(' product ')'
    fn atom(&mut self) -> Result<Dimension, SrError> {
        match self.peek() {
            Some('(') => {
                self.pos += 1;
                let d = self.product()?;
                self.skip_space();
                if self.peek() != Some(')') {
                    return Err(bad(self.text, "a `(` is not closed"));
                }
                self.pos += 1;
                Ok(d)
            }
            Some(c) if c.is_alphabetic() || c == '%' || c == '1' || c == '-' => {
                let start = self.pos;
                if matches!(c, '%' | '1' | '-') {
                    self.pos += 1;
                } else {
                    while self.peek().is_some_and(|c| c.is_alphabetic()) {
                        self.pos += 1;
                    }
                }
                let name: String = self.chars[start..self.pos].iter().collect();
                if name == "degC" || name == "°C" {
                    return Err(bad(
                        self.text,
                        "degrees Celsius start from an offset zero, which a power law cannot \
                         use: convert the column to kelvin (K)",
                    ));
                }
                lookup(&name).ok_or_else(|| {
                    bad(
                        self.text,
                        &format!(
                            "`{name}` is not a unit this knows: use SI units (m kg s A K mol cd \
                             and N Pa J W C V ohm S F T Wb H Hz, with prefixes p n u m c d k M G), \
                             min, h, rpm, l, bar, rad, deg, % or 1"
                        ),
                    )
                })
            }
            Some(c) => Err(bad(
                self.text,
                &format!("unexpected `{c}` at character {}", self.pos + 1),
            )),
            None => Err(bad(self.text, "it ends where a unit was expected")),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn reads_derived_units_and_prefixes() {
        let n = Dimension::parse("kg*m/s^2").expect("kg*m/s^2");
        assert_eq!(n, Dimension::parse("N").expect("N"));
        assert_eq!(n, Dimension::parse("kN").expect("kN"));
        assert_eq!(
            Dimension::parse("N/mm^2").expect("N/mm^2"),
            Dimension::parse("MPa").expect("MPa")
        );
        assert_eq!(
            Dimension::parse("J/(kg*K)").expect("J/(kg*K)"),
            Dimension::parse("m^2/(s^2*K)").expect("m^2/(s^2*K)")
        );
        assert_eq!(
            Dimension::parse("1/min").expect("1/min"),
            Dimension::parse("rpm").expect("rpm")
        );
        assert_eq!(
            Dimension::parse("m**2").expect("m**2"),
            Dimension::parse("m.m").expect("m.m")
        );
        assert!(Dimension::parse("1").expect("1").is_none());
        assert!(Dimension::parse("deg").expect("deg").is_none());
        assert_eq!(Dimension::parse("mm").expect("mm").to_string(), "m");
        assert_eq!(
            Dimension::parse("V").expect("V").to_string(),
            "m^2*kg/(s^3*A)"
        );
        assert_eq!(Dimension::parse("1/s").expect("1/s").to_string(), "1/s");
    }

    #[test]
    fn refuses_what_it_cannot_read_by_name() {
        for (text, says) in [
            ("", "empty"),
            ("furlong", "`furlong` is not a unit"),
            ("m^x", "whole number"),
            ("m^1.5", "unexpected"),
            ("(m", "not closed"),
            ("degC", "kelvin"),
            ("m/", "ends where"),
            ("m^40", "out of range"),
        ] {
            let e = Dimension::parse(text).expect_err(text).to_string();
            assert!(e.contains(says), "{text}: {e}");
        }
    }
}
