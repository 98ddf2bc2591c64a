//! Tokens, parser and code generation of [`super::Expression`], following the grammar of
//! OpenSim's Lepton parser (precedence climbing; subexpressions after `;`).

use super::unary::{lepton_unary, Lepton};
use super::Op;
use std::collections::HashMap;

/// A token of the whitespace-free source.
#[derive(Clone, Debug, PartialEq)]
enum Token {
    Number(f64),
    /// `+ - * / ^`.
    Operator(char),
    LeftParen,
    RightParen,
    Comma,
    /// A function name (its `(` is part of the token).
    Function(String),
    Variable(String),
}

impl Token {
    fn text(&self) -> String {
        match self {
            Token::Number(x) => x.to_string(),
            Token::Operator(c) => c.to_string(),
            Token::LeftParen => "(".into(),
            Token::RightParen => ")".into(),
            Token::Comma => ",".into(),
            Token::Function(f) => format!("{f}("),
            Token::Variable(v) => v.clone(),
        }
    }
}

const OPERATORS: &str = "+-*/^";

/// Split a whitespace-free expression into tokens.
fn tokenize(s: &str) -> Result<Vec<Token>, String> {
    let b: Vec<char> = s.chars().collect();
    let mut tokens = Vec::new();
    let mut i = 0;
    while i < b.len() {
        let c = b[i];
        let (token, next) = match c {
            '(' => (Token::LeftParen, i + 1),
            ')' => (Token::RightParen, i + 1),
            ',' => (Token::Comma, i + 1),
            c if OPERATORS.contains(c) => (Token::Operator(c), i + 1),
            c if c.is_ascii_digit() || c == '.' => number(&b, i)?,
            _ => name(&b, i),
        };
        tokens.push(token);
        i = next;
    }
    Ok(tokens)
}

/// A number starting at `start`: digits with at most one `.` and an optional exponent.
fn number(b: &[char], start: usize) -> Result<(Token, usize), String> {
    let (mut decimal, mut exponent) = (b[start] == '.', false);
    let mut i = start + 1;
    while i < b.len() {
        let c = b[i];
        if c == '.' && !decimal && !exponent {
            decimal = true;
        } else if (c == 'e' || c == 'E') && !exponent {
            exponent = true;
            if i + 1 < b.len() && (b[i + 1] == '-' || b[i + 1] == '+') {
                i += 1;
            }
        } else if !c.is_ascii_digit() {
            break;
        }
        i += 1;
    }
    let text: String = b[start..i].iter().collect();
    let x = text
        .parse::<f64>()
        .map_err(|_| format!("`{text}` is not a number"))?;
    Ok((Token::Number(x), i))
}

/// A variable name, or a function name when a `(` follows it.
fn name(b: &[char], start: usize) -> (Token, usize) {
    let mut i = start;
    while i < b.len() {
        let c = b[i];
        if c == '(' {
            return (Token::Function(b[start..i].iter().collect()), i + 1);
        }
        if OPERATORS.contains(c) || c == ',' || c == ')' {
            break;
        }
        i += 1;
    }
    (Token::Variable(b[start..i].iter().collect()), i)
}

/// Binary operators of the syntax tree.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Bin {
    Add,
    Sub,
    Mul,
    Div,
    Pow,
    Min,
    Max,
}

/// Syntax tree.
#[derive(Clone, Debug)]
enum Node {
    Num(f64),
    Var(usize),
    Neg(Box<Node>),
    Bin(Bin, Box<Node>, Box<Node>),
    Call(Lepton, Box<Node>),
}

/// Precedence and left-associativity of `+ - * / ^` (Lepton's table; unary minus is 2).
fn precedence(op: char) -> (u8, bool) {
    match op {
        '+' | '-' => (0, true),
        '*' | '/' => (1, true),
        _ => (3, false),
    }
}

struct Parser<'a> {
    tokens: Vec<Token>,
    pos: usize,
    variables: &'a [&'a str],
    definitions: &'a HashMap<String, Node>,
}

impl Parser<'_> {
    fn peek(&self) -> Option<&Token> {
        self.tokens.get(self.pos)
    }

    /// An expression whose binary operators bind at least as tightly as `min`.
    fn expression(&mut self, min: u8) -> Result<Node, String> {
        let mut left = self.operand()?;
        while let Some(Token::Operator(op)) = self.peek() {
            let op = *op;
            let (p, left_assoc) = precedence(op);
            if p < min {
                break;
            }
            self.pos += 1;
            let right = self.expression(if left_assoc { p + 1 } else { p })?;
            let bin = match op {
                '+' => Bin::Add,
                '-' => Bin::Sub,
                '*' => Bin::Mul,
                '/' => Bin::Div,
                _ => Bin::Pow,
            };
            left = Node::Bin(bin, Box::new(left), Box::new(right));
        }
        Ok(left)
    }

    /// A number, variable, parenthesised expression, function call or negation.
    fn operand(&mut self) -> Result<Node, String> {
        let token = self
            .peek()
            .cloned()
            .ok_or_else(|| "unexpected end of expression".to_string())?;
        self.pos += 1;
        match token {
            Token::Number(x) => Ok(Node::Num(x)),
            Token::Variable(v) => self.variable(&v),
            Token::LeftParen => {
                let inner = self.expression(0)?;
                self.close()?;
                Ok(inner)
            }
            Token::Function(f) => {
                let mut args = vec![self.expression(0)?];
                while self.peek() == Some(&Token::Comma) {
                    self.pos += 1;
                    args.push(self.expression(0)?);
                }
                self.close()?;
                call(&f, args)
            }
            Token::Operator('-') => Ok(Node::Neg(Box::new(self.expression(2)?))),
            other => Err(format!("unexpected token `{}`", other.text())),
        }
    }

    fn close(&mut self) -> Result<(), String> {
        if self.peek() != Some(&Token::RightParen) {
            return Err("unbalanced parentheses".into());
        }
        self.pos += 1;
        Ok(())
    }

    fn variable(&self, v: &str) -> Result<Node, String> {
        if let Some(node) = self.definitions.get(v) {
            return Ok(node.clone());
        }
        match self.variables.iter().position(|n| *n == v) {
            Some(k) => Ok(Node::Var(k)),
            None => Err(format!(
                "unknown variable `{v}` (known: {})",
                self.variables.join(", ")
            )),
        }
    }
}

/// A call of Lepton function `f`.
fn call(f: &str, mut args: Vec<Node>) -> Result<Node, String> {
    let two = match f {
        "min" => Some(Bin::Min),
        "max" => Some(Bin::Max),
        _ => None,
    };
    let want = if two.is_some() { 2 } else { 1 };
    let unary = lepton_unary(f);
    if two.is_none() && unary.is_none() {
        return Err(format!("unknown function `{f}`"));
    }
    if args.len() != want {
        return Err(format!(
            "function `{f}` takes {want} argument(s), found {}",
            args.len()
        ));
    }
    let last = Box::new(args.pop().expect("checked count"));
    Ok(match (two, unary) {
        (Some(bin), _) => Node::Bin(bin, Box::new(args.pop().expect("checked count")), last),
        (None, Some(u)) => Node::Call(u, last),
        (None, None) => unreachable!("checked above"),
    })
}

/// Parse one (sub)expression with the definitions made so far.
fn parse_one(
    text: &str,
    variables: &[&str],
    definitions: &HashMap<String, Node>,
) -> Result<Node, String> {
    let mut p = Parser {
        tokens: tokenize(text)?,
        pos: 0,
        variables,
        definitions,
    };
    let node = p.expression(0)?;
    match p.peek() {
        None => Ok(node),
        Some(t) => Err(format!("unexpected text at the end: `{}`", t.text())),
    }
}

/// Compile `source` (whitespace ignored, subexpressions after `;` defined from the last
/// one backwards, as Lepton does) into a postfix program over `variables`.
pub(super) fn compile(source: &str, variables: &[&str]) -> Result<Vec<Op>, String> {
    let text: String = source.chars().filter(|c| !c.is_whitespace()).collect();
    let mut parts: Vec<&str> = text.split(';').collect();
    let primary = parts.remove(0);
    let mut definitions = HashMap::new();
    for sub in parts.iter().rev().filter(|s| !s.is_empty()) {
        let (name, body) = sub
            .split_once('=')
            .filter(|(n, _)| !n.is_empty())
            .ok_or_else(|| format!("subexpression `{sub}` does not specify a name"))?;
        let node = parse_one(body, variables, &definitions)?;
        definitions.insert(name.to_string(), node);
    }
    let tree = parse_one(primary, variables, &definitions)?;
    let mut ops = Vec::new();
    emit(&fold(tree), &mut ops);
    Ok(ops)
}

/// The tree with every subtree of constants replaced by its value.
fn fold(node: Node) -> Node {
    let folded = match node {
        Node::Neg(a) => Node::Neg(Box::new(fold(*a))),
        Node::Bin(op, a, b) => Node::Bin(op, Box::new(fold(*a)), Box::new(fold(*b))),
        Node::Call(f, a) => Node::Call(f, Box::new(fold(*a))),
        leaf => return leaf,
    };
    let constant = match &folded {
        Node::Neg(a) | Node::Call(_, a) => matches!(**a, Node::Num(_)),
        Node::Bin(_, a, b) => matches!(**a, Node::Num(_)) && matches!(**b, Node::Num(_)),
        _ => false,
    };
    if !constant {
        return folded;
    }
    let mut ops = Vec::new();
    emit(&folded, &mut ops);
    Node::Num(super::run::<f64>(&ops, &[]))
}

/// Append the postfix code of `node` to `ops`.
fn emit(node: &Node, ops: &mut Vec<Op>) {
    match node {
        Node::Num(x) => ops.push(Op::Const(*x)),
        Node::Var(k) => ops.push(Op::Var(*k)),
        Node::Neg(a) => {
            emit(a, ops);
            ops.push(Op::Neg);
        }
        Node::Bin(Bin::Pow, a, b) if matches!(**b, Node::Num(_)) => {
            emit(a, ops);
            let Node::Num(p) = **b else { unreachable!() };
            ops.push(Op::PowConst(p));
        }
        Node::Bin(op, a, b) => {
            emit(a, ops);
            emit(b, ops);
            ops.push(match op {
                Bin::Add => Op::Add,
                Bin::Sub => Op::Sub,
                Bin::Mul => Op::Mul,
                Bin::Div => Op::Div,
                Bin::Pow => Op::Pow,
                Bin::Min => Op::Min,
                Bin::Max => Op::Max,
            });
        }
        Node::Call(f, a) => {
            emit(a, ops);
            ops.extend(f.ops());
        }
    }
}
