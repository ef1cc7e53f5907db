//! A hyperelastic law written as an expression of the invariants, as a scene file gives it.
//!
//! # Physics
//! An isotropic hyperelastic solid is a stored energy of the invariants of the right
//! Cauchy–Green tensor $C = F^T F$:
//! ```math
//! W = W(I_1, I_2, J), \qquad I_1 = \operatorname{tr} C,\quad
//! I_2 = \tfrac12\big((\operatorname{tr} C)^2 - \operatorname{tr} C^2\big),\quad J = \det F .
//! ```
//! [`ExpressionLaw`] parses W once into a postfix program and evaluates it for any num-dual
//! scalar, so P = ∂W/∂F and the tangent come by automatic differentiation exactly as for the
//! built-in laws. Its small-strain moduli are read off the tangent at F = 1: for an isotropic
//! law $\partial P_{12}/\partial F_{12} = \mu_s$ and $\partial P_{11}/\partial F_{11} =
//! \lambda_s + 2\mu_s$. The reference state must be stress-free and stable: P(1) = 0 (to
//! round-off of the moduli), μ_s > 0 and λ_s finite.
//!
//! # Syntax
//! Numbers (`1`, `0.5`, `2e-3`), the variables `I1`, `I2`, `J`, the scene's named parameters,
//! `+ - * / ^` (`^` binds tightest and is right-associative; unary minus binds looser than
//! `^`, so `-x^2` is −(x²)), parentheses, and the functions `ln`, `exp`, `sqrt`. A constant
//! exponent (`x^2`, `x^-0.5`, a parameter) applies to any base; a variable one (`x^J`) is
//! exp(J ln x) and needs x > 0. For example
//! the paper's Neo-Hooke law (eq. 9) is
//! `mu/2*(I1 - 3) - mu*ln(J) + lambda/2*ln(J)^2`.

use super::Hyperelastic;
use crate::error::ParamError;
use crate::tensor::{Mat3, Scalar, det3};
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;

/// Longest energy expression accepted (characters).
pub const MAX_EXPRESSION: usize = 4096;
/// Deepest nesting of parentheses, powers and signs accepted.
pub const MAX_DEPTH: usize = 64;

/// One instruction of the postfix program.
#[derive(Debug, Clone, Copy, PartialEq)]
enum Op {
    Const(f64),
    I1,
    I2,
    J,
    Add,
    Sub,
    Mul,
    Div,
    /// A variable exponent: a^b = exp(b ln a), for a > 0.
    Pow,
    /// A constant integer exponent (any sign of the base).
    Powi(i32),
    /// A constant real exponent.
    Powf(f64),
    Neg,
    Ln,
    Exp,
    Sqrt,
}

/// A stored energy W(I₁, I₂, J) given as text, with named parameters.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(try_from = "ExpressionRaw", into = "ExpressionRaw")]
pub struct ExpressionLaw {
    energy: String,
    parameters: BTreeMap<String, f64>,
    program: Vec<Op>,
    mu: f64,
    lambda: f64,
}

/// The serialised form of an [`ExpressionLaw`] (parsed and checked again when read).
#[derive(Serialize, Deserialize)]
struct ExpressionRaw {
    energy: String,
    parameters: BTreeMap<String, f64>,
}

impl TryFrom<ExpressionRaw> for ExpressionLaw {
    type Error = ParamError;
    fn try_from(raw: ExpressionRaw) -> Result<Self, ParamError> {
        Self::new(&raw.energy, raw.parameters)
    }
}

impl From<ExpressionLaw> for ExpressionRaw {
    fn from(law: ExpressionLaw) -> Self {
        Self {
            energy: law.energy,
            parameters: law.parameters,
        }
    }
}

impl ExpressionLaw {
    /// The law with energy `energy` (see the module docs for the syntax) and parameter values
    /// `parameters` (finite; names are identifiers other than `I1`, `I2`, `J` and the
    /// functions). Refused: a syntax error, an unknown name, a non-finite parameter, and an
    /// energy whose reference state is not stress-free or has μ_s ≤ 0 or a non-finite λ_s.
    pub fn new(energy: &str, parameters: BTreeMap<String, f64>) -> Result<Self, ParamError> {
        let fail = |position: usize, message: String| ParamError::Expression {
            position,
            message,
            energy: energy.to_string(),
        };
        if energy.len() > MAX_EXPRESSION {
            return Err(fail(MAX_EXPRESSION, format!("longer than {MAX_EXPRESSION} characters")));
        }
        for (name, value) in &parameters {
            if !value.is_finite() {
                return Err(fail(0, format!("parameter `{name}` must be finite, got {value}")));
            }
            if reserved(name) || !is_identifier(name) {
                return Err(fail(0, format!("`{name}` cannot name a parameter")));
            }
        }
        let tokens = tokenize(energy).map_err(|(p, m)| fail(p, m))?;
        let mut parser = Parser {
            tokens: &tokens,
            next: 0,
            parameters: &parameters,
            program: Vec::new(),
        };
        parser.sum(0).map_err(|(p, m)| fail(p, m))?;
        if let Some(&(p, ref t)) = tokens.get(parser.next) {
            return Err(fail(
                p,
                format!("unexpected `{}` after a complete expression", t.text()),
            ));
        }
        let mut law = Self {
            energy: energy.to_string(),
            program: parser.program,
            parameters,
            mu: 0.0,
            lambda: 0.0,
        };
        law.reference_moduli()?;
        Ok(law)
    }

    /// The energy's text.
    pub fn energy_text(&self) -> &str {
        &self.energy
    }

    /// μ_s and λ_s from the tangent at F = 1, after checking that P(1) = 0.
    fn reference_moduli(&mut self) -> Result<(), ParamError> {
        let one = Mat3::identity();
        let tangent = super::tangent_ad(self, &one);
        // Column-major flattening: component (i, j) is entry i + 3j.
        let (mu, lambda) = (tangent[(3, 3)], tangent[(0, 0)] - 2.0 * tangent[(3, 3)]);
        let p = super::piola_ad(self, &one);
        let scale = mu.abs() + lambda.abs();
        let residual = p.amax();
        let fail = |message: String| ParamError::Expression {
            position: 0,
            message,
            energy: self.energy.clone(),
        };
        if !(mu.is_finite() && mu > 0.0 && lambda.is_finite()) {
            return Err(fail(format!(
                "the reference state needs a shear modulus > 0 and a finite lambda, got mu_s = {mu}, lambda_s = {lambda}"
            )));
        }
        // P(1) is a sum of terms of the size of the moduli; 1e-12 of them is round-off.
        if !(residual <= 1e-12 * scale) {
            return Err(fail(format!(
                "the reference state F = 1 is not stress-free: |P(1)| = {residual:e} (moduli {scale:e})"
            )));
        }
        self.mu = mu;
        self.lambda = lambda;
        Ok(())
    }
}

impl Hyperelastic for ExpressionLaw {
    fn energy<S: Scalar>(&self, f: &Mat3<S>) -> S {
        let c = f.transpose() * f;
        let i1 = c.trace();
        let tr_c2 = c.iter().fold(S::from(0.0), |acc, &x| acc + x * x);
        let i2 = (i1 * i1 - tr_c2) * 0.5;
        let j = det3(f);
        let mut stack: Vec<S> = Vec::with_capacity(self.program.len());
        for op in &self.program {
            let value = match *op {
                Op::Const(v) => S::from(v),
                Op::I1 => i1,
                Op::I2 => i2,
                Op::J => j,
                Op::Neg => -pop(&mut stack),
                Op::Ln => pop(&mut stack).ln(),
                Op::Exp => pop(&mut stack).exp(),
                Op::Sqrt => pop(&mut stack).sqrt(),
                Op::Powi(n) => pop(&mut stack).powi(n),
                Op::Powf(x) => pop(&mut stack).powf(x),
                binary => {
                    let (b, a) = (pop(&mut stack), pop(&mut stack));
                    match binary {
                        Op::Add => a + b,
                        Op::Sub => a - b,
                        Op::Mul => a * b,
                        Op::Div => a / b,
                        _ => a.powd(b),
                    }
                }
            };
            stack.push(value);
        }
        pop(&mut stack)
    }

    fn shear_modulus(&self) -> f64 {
        self.mu
    }

    fn lame_lambda(&self) -> f64 {
        self.lambda
    }

    /// The expression's only variables are I₁, I₂ and J.
    fn is_isotropic(&self) -> bool {
        true
    }
}

/// The top of a stack the parser made: it emits every operand before its operator, so an
/// empty stack cannot occur; NaN rather than a panic if it ever did.
fn pop<S: Scalar>(stack: &mut Vec<S>) -> S {
    stack.pop().unwrap_or_else(|| S::from(f64::NAN))
}

fn reserved(name: &str) -> bool {
    matches!(name, "I1" | "I2" | "J" | "ln" | "exp" | "sqrt")
}

fn is_identifier(name: &str) -> bool {
    let mut chars = name.chars();
    chars.next().is_some_and(|c| c.is_ascii_alphabetic() || c == '_')
        && chars.all(|c| c.is_ascii_alphanumeric() || c == '_')
}

#[derive(Debug, Clone, PartialEq)]
enum Token {
    Number(f64),
    Name(String),
    Symbol(char),
}

impl Token {
    fn text(&self) -> String {
        match self {
            Token::Number(v) => v.to_string(),
            Token::Name(n) => n.clone(),
            Token::Symbol(c) => c.to_string(),
        }
    }
}

type Failure = (usize, String);

fn tokenize(text: &str) -> Result<Vec<(usize, Token)>, Failure> {
    let chars: Vec<(usize, char)> = text.char_indices().collect();
    let mut tokens = Vec::new();
    let mut k = 0;
    while let Some(&(at, c)) = chars.get(k) {
        if c.is_whitespace() {
            k += 1;
        } else if c.is_ascii_digit() || c == '.' {
            let start = k;
            while chars.get(k).is_some_and(|&(_, d)| d.is_ascii_digit() || d == '.') {
                k += 1;
            }
            // An exponent: e or E, an optional sign, digits.
            if chars.get(k).is_some_and(|&(_, d)| d == 'e' || d == 'E') {
                let mut m = k + 1;
                if chars.get(m).is_some_and(|&(_, d)| d == '+' || d == '-') {
                    m += 1;
                }
                if chars.get(m).is_some_and(|&(_, d)| d.is_ascii_digit()) {
                    k = m;
                    while chars.get(k).is_some_and(|&(_, d)| d.is_ascii_digit()) {
                        k += 1;
                    }
                }
            }
            let end = chars.get(k).map_or(text.len(), |&(i, _)| i);
            let literal = &text[at..end];
            let value: f64 = literal
                .parse()
                .map_err(|_| (chars[start].0, format!("`{literal}` is not a number")))?;
            tokens.push((at, Token::Number(value)));
        } else if c.is_ascii_alphabetic() || c == '_' {
            let start = at;
            while chars
                .get(k)
                .is_some_and(|&(_, d)| d.is_ascii_alphanumeric() || d == '_')
            {
                k += 1;
            }
            let end = chars.get(k).map_or(text.len(), |&(i, _)| i);
            tokens.push((start, Token::Name(text[start..end].to_string())));
        } else if "+-*/^()".contains(c) {
            tokens.push((at, Token::Symbol(c)));
            k += 1;
        } else {
            return Err((at, format!("unexpected character `{c}`")));
        }
    }
    Ok(tokens)
}

/// Recursive descent to postfix: sum → product → signed → power → atom.
struct Parser<'a> {
    tokens: &'a [(usize, Token)],
    next: usize,
    parameters: &'a BTreeMap<String, f64>,
    program: Vec<Op>,
}

impl Parser<'_> {
    fn peek(&self) -> Option<&Token> {
        self.tokens.get(self.next).map(|(_, t)| t)
    }

    fn position(&self) -> usize {
        self.tokens.get(self.next).or(self.tokens.last()).map_or(0, |&(p, _)| p)
    }

    fn symbol(&mut self, c: char) -> bool {
        let hit = self.peek() == Some(&Token::Symbol(c));
        if hit {
            self.next += 1;
        }
        hit
    }

    fn deeper(&self, depth: usize) -> Result<usize, Failure> {
        if depth >= MAX_DEPTH {
            Err((self.position(), format!("nested deeper than {MAX_DEPTH}")))
        } else {
            Ok(depth + 1)
        }
    }

    fn sum(&mut self, depth: usize) -> Result<(), Failure> {
        let depth = self.deeper(depth)?;
        self.product(depth)?;
        loop {
            let op = if self.symbol('+') {
                Op::Add
            } else if self.symbol('-') {
                Op::Sub
            } else {
                return Ok(());
            };
            self.product(depth)?;
            self.program.push(op);
        }
    }

    fn product(&mut self, depth: usize) -> Result<(), Failure> {
        let depth = self.deeper(depth)?;
        self.signed(depth)?;
        loop {
            let op = if self.symbol('*') {
                Op::Mul
            } else if self.symbol('/') {
                Op::Div
            } else {
                return Ok(());
            };
            self.signed(depth)?;
            self.program.push(op);
        }
    }

    fn signed(&mut self, depth: usize) -> Result<(), Failure> {
        let depth = self.deeper(depth)?;
        if self.symbol('-') {
            self.signed(depth)?;
            self.program.push(Op::Neg);
            Ok(())
        } else if self.symbol('+') {
            self.signed(depth)
        } else {
            self.power(depth)
        }
    }

    fn power(&mut self, depth: usize) -> Result<(), Failure> {
        let depth = self.deeper(depth)?;
        self.atom(depth)?;
        if self.symbol('^') {
            // Right-associative, and the exponent may carry a sign: 2^-1.
            let start = self.program.len();
            self.signed(depth)?;
            // A constant exponent is applied as such: ln(J)^2 has a negative base when J < 1,
            // where exp(2 ln(ln J)) would be NaN.
            let constant = match self.program[start..] {
                [Op::Const(v)] => Some(v),
                [Op::Const(v), Op::Neg] => Some(-v),
                _ => None,
            };
            match constant {
                Some(v) => {
                    self.program.truncate(start);
                    self.program.push(if v.fract() == 0.0 && v.abs() <= 1e6 {
                        Op::Powi(v as i32)
                    } else {
                        Op::Powf(v)
                    });
                }
                None => self.program.push(Op::Pow),
            }
        }
        Ok(())
    }

    fn atom(&mut self, depth: usize) -> Result<(), Failure> {
        let at = self.position();
        let Some(token) = self.peek().cloned() else {
            return Err((at, "the expression ends where a value is expected".into()));
        };
        self.next += 1;
        match token {
            Token::Number(v) => self.program.push(Op::Const(v)),
            Token::Symbol('(') => {
                self.sum(depth)?;
                if !self.symbol(')') {
                    return Err((self.position(), "a `(` is not closed".into()));
                }
            }
            Token::Symbol(c) => return Err((at, format!("`{c}` where a value is expected"))),
            Token::Name(name) => match name.as_str() {
                "I1" => self.program.push(Op::I1),
                "I2" => self.program.push(Op::I2),
                "J" => self.program.push(Op::J),
                "ln" | "exp" | "sqrt" => {
                    if !self.symbol('(') {
                        return Err((self.position(), format!("`{name}` needs `(`")));
                    }
                    self.sum(depth)?;
                    if !self.symbol(')') {
                        return Err((self.position(), format!("`{name}(` is not closed")));
                    }
                    self.program.push(match name.as_str() {
                        "ln" => Op::Ln,
                        "exp" => Op::Exp,
                        _ => Op::Sqrt,
                    });
                }
                other => match self.parameters.get(other) {
                    Some(&v) => self.program.push(Op::Const(v)),
                    None => {
                        let known: Vec<&str> = ["I1", "I2", "J"]
                            .into_iter()
                            .chain(self.parameters.keys().map(String::as_str))
                            .collect();
                        return Err((at, format!("unknown name `{other}` (known: {})", known.join(", "))));
                    }
                },
            },
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::tensor::mat3;

    fn law(energy: &str, params: &[(&str, f64)]) -> Result<ExpressionLaw, ParamError> {
        ExpressionLaw::new(energy, params.iter().map(|&(k, v)| (k.to_string(), v)).collect())
    }

    #[test]
    fn flattening_is_column_major() {
        let m = mat3(&crate::tensor::vec9(&Mat3::new(1., 2., 3., 4., 5., 6., 7., 8., 9.)));
        assert_eq!(m[(1, 0)], 4.0);
        assert_eq!(crate::tensor::vec9(&m)[1], 4.0);
    }

    #[test]
    fn precedence_and_errors() {
        // W = a (I1 − 3)² with a = −2^2 = −4 would be unstable; check the parse through the
        // energy at F = 2·1: I1 = 12, so (I1 − 3)^2 = 81 and −x^2 is −(x²).
        let l = law(
            "mu/2*(I1-3) - mu*ln(J) + lambda/2*ln(J)^2 + 0*(-(I1-3)^2)",
            &[("mu", 1.0), ("lambda", 2.0)],
        )
        .unwrap();
        assert_eq!(
            l.energy(&(Mat3::identity() * 2.0)),
            0.5 * 9.0 - 8f64.ln() + 8f64.ln().powi(2)
        );
        for (bad, fragment) in [
            ("mu*(I1 - 3", "not closed"),
            ("mu*(I1 - 3) + k", "unknown name `k`"),
            ("mu*(I1 - 3) $", "unexpected character"),
            ("mu*", "ends where a value"),
            ("ln I1", "needs `(`"),
            ("mu*(I1 - 3) 2", "after a complete"),
            ("mu*(I1 - 2)", "not stress-free"),
            ("-mu*(I1 - 3) + 2*mu*ln(J)", "shear modulus > 0"),
        ] {
            let e = law(bad, &[("mu", 1.0)]).unwrap_err().to_string();
            assert!(e.contains(fragment), "{bad}: {e}");
        }
        let deep = format!("{}1{}", "(".repeat(100), ")".repeat(100));
        assert!(law(&deep, &[]).unwrap_err().to_string().contains("nested deeper"));
        assert!(law("mu*(I1-3)", &[("mu", f64::NAN)]).is_err());
        assert!(law("J*(I1-3)", &[("J", 1.0)]).is_err());
    }
}

// Selectable by name: `material = { law = "expression", energy = "…", parameters = { … } }`.
inventory::submit! {
    super::LawRegistration {
        name: "expression",
        build: |p| {
            p.only(&["energy", "parameters"])?;
            Ok(std::sync::Arc::new(ExpressionLaw::new(p.text("energy")?, p.table("parameters")?)?))
        },
    }
}
