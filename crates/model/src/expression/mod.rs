//! Arithmetic expressions as OpenSim writes them (its Lepton parser), e.g. the force law
//! of an `ExpressionBasedCoordinateForce` in the coordinate value `q` and speed `qdot`.
//!
//! [`Expression::parse`] accepts what Lepton accepts: numbers, named variables, `+ - * / ^`
//! (`^` right-associative, unary minus binding tighter than `*` but looser than `^`),
//! parentheses, the functions `sqrt exp log sin cos sec csc tan cot asin acos atan sinh
//! cosh tanh erf erfc step delta square cube recip abs` (one argument) and `min max` (two),
//! and subexpressions after `;` (`a*q; a=2`). Whitespace is ignored. The expression is
//! compiled once into a postfix instruction list that [`Expression::eval`] runs on any
//! [`Scalar`], so the AD types differentiate it.

mod parse;
mod unary;

use serde::{Deserialize, Deserializer, Serialize, Serializer};
use std::sync::Arc;
use stride_ad::{Scalar, UnaryFn};

/// Why an expression was rejected (one line, naming the expression).
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
#[error("expression `{expression}`: {message}")]
pub struct ExpressionError {
    /// The expression as written.
    pub expression: String,
    /// What is wrong.
    pub message: String,
}

/// One instruction of the postfix program.
#[derive(Clone, Debug)]
enum Op {
    /// Push a constant.
    Const(f64),
    /// Push variable `k`.
    Var(usize),
    /// Negate the top.
    Neg,
    /// Binary arithmetic on the two top values.
    Add,
    Sub,
    Mul,
    Div,
    /// General power `x^y` = exp(y ln x) (for a variable exponent).
    Pow,
    /// `x^p` with a constant exponent.
    PowConst(f64),
    Min,
    Max,
    /// A function of the top value that the scalar type provides.
    Native(Native),
    /// Any other function of the top value, with its derivatives.
    Unary(Arc<dyn UnaryFn>),
}

/// Functions of one variable that [`Scalar`] evaluates itself.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Native {
    Sqrt,
    Exp,
    Log,
    Sin,
    Cos,
    Tan,
    Tanh,
    Recip,
}

/// A compiled arithmetic expression of named variables.
#[derive(Clone, Debug)]
pub struct Expression {
    source: String,
    variables: Vec<String>,
    ops: Vec<Op>,
}

impl Expression {
    /// Compile `source` as an expression of `variables` (evaluated in this order); any
    /// other name, unknown function or syntax error is an [`ExpressionError`].
    pub fn parse(source: &str, variables: &[&str]) -> Result<Self, ExpressionError> {
        let ops = parse::compile(source, variables).map_err(|message| ExpressionError {
            expression: source.to_string(),
            message,
        })?;
        Ok(Self {
            source: source.to_string(),
            variables: variables.iter().map(|v| v.to_string()).collect(),
            ops,
        })
    }

    /// The expression as written.
    pub fn source(&self) -> &str {
        &self.source
    }

    /// The variable names, in the order [`Expression::eval`] takes their values.
    pub fn variables(&self) -> &[String] {
        &self.variables
    }

    /// Value of the expression at the variable values `vars` (same order as the names).
    pub fn eval<T: Scalar>(&self, vars: &[T]) -> T {
        run(&self.ops, vars)
    }
}

/// Run a postfix program at the variable values `vars`.
fn run<T: Scalar>(ops: &[Op], vars: &[T]) -> T {
    let mut stack: Vec<T> = Vec::with_capacity(8);
    for op in ops {
        let v = match op {
            Op::Const(c) => T::cst(*c),
            Op::Var(k) => vars[*k],
            Op::Native(f) => native(*f, pop(&mut stack)),
            Op::Unary(f) => pop(&mut stack).apply(f),
            Op::Neg => -pop(&mut stack),
            Op::PowConst(p) => pop(&mut stack).powf(*p),
            binary => {
                let b = pop(&mut stack);
                let a = pop(&mut stack);
                match binary {
                    Op::Add => a + b,
                    Op::Sub => a - b,
                    Op::Mul => a * b,
                    Op::Div => a / b,
                    Op::Pow => (b * a.ln()).exp(),
                    Op::Min => a.fmin(b),
                    _ => a.fmax(b),
                }
            }
        };
        stack.push(v);
    }
    pop(&mut stack)
}

/// The top of the evaluation stack (the compiler guarantees it is there).
fn pop<T>(stack: &mut Vec<T>) -> T {
    stack.pop().expect("compiled expressions are balanced")
}

fn native<T: Scalar>(f: Native, x: T) -> T {
    match f {
        Native::Sqrt => x.sqrt(),
        Native::Exp => x.exp(),
        Native::Log => x.ln(),
        Native::Sin => x.sin(),
        Native::Cos => x.cos(),
        Native::Tan => x.tan(),
        Native::Tanh => x.tanh(),
        Native::Recip => x.recip(),
    }
}

impl PartialEq for Expression {
    fn eq(&self, other: &Self) -> bool {
        self.source == other.source && self.variables == other.variables
    }
}

/// Serialised as its source and variable names; compiled again when read.
#[derive(Serialize, Deserialize)]
struct ExpressionText {
    expression: String,
    variables: Vec<String>,
}

impl Serialize for Expression {
    fn serialize<S: Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        ExpressionText {
            expression: self.source.clone(),
            variables: self.variables.clone(),
        }
        .serialize(s)
    }
}

impl<'de> Deserialize<'de> for Expression {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        let t = ExpressionText::deserialize(d)?;
        let vars: Vec<&str> = t.variables.iter().map(String::as_str).collect();
        Expression::parse(&t.expression, &vars).map_err(serde::de::Error::custom)
    }
}

#[cfg(test)]
mod tests;
