//! The small expression language of scene files: numbers, parameter names, `+ - * / ^`,
//! parentheses, unary minus, `pi`, and the functions `sqrt`, `sin`, `cos`, `tan`, `abs`,
//! `exp`, `ln`, `round` (to the nearest whole number) and `rad` (degrees to radians). Angles in `sin`, `cos` and `tan` are
//! radians: `sin(rad(angle))` for a parameter in degrees.
//!
//! An expression is parsed once, when the file is loaded, so that an unknown name is
//! reported with its column before anything is built; it is evaluated every time the
//! scene is built, with the parameters' current values.

use crate::messages::quote;
use crate::messages::{clip, name_list as list};

/// A parsed expression.
#[derive(Clone, Debug, PartialEq)]
pub enum Expr {
    /// A literal number.
    Number(f64),
    /// A variable: index into the evaluation's variable list.
    Variable(usize),
    /// `-x`.
    Negate(Box<Expr>),
    /// `a op b`.
    Binary(Op, Box<Expr>, Box<Expr>),
    /// `f(x)`.
    Call(Function, Box<Expr>),
}

/// A binary operator.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Op {
    /// `+`
    Add,
    /// `-`
    Subtract,
    /// `*`
    Multiply,
    /// `/`
    Divide,
    /// `^`, right-associative.
    Power,
}

/// A function of one argument.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Function {
    /// Square root.
    Sqrt,
    /// Sine of radians.
    Sin,
    /// Cosine of radians.
    Cos,
    /// Tangent of radians.
    Tan,
    /// Absolute value.
    Abs,
    /// `e^x`.
    Exp,
    /// Natural logarithm.
    Ln,
    /// Degrees to radians.
    Rad,
    /// The nearest whole number (half away from zero).
    Round,
}

const FUNCTIONS: &[(&str, Function)] = &[
    ("sqrt", Function::Sqrt),
    ("sin", Function::Sin),
    ("cos", Function::Cos),
    ("tan", Function::Tan),
    ("abs", Function::Abs),
    ("exp", Function::Exp),
    ("ln", Function::Ln),
    ("rad", Function::Rad),
    ("round", Function::Round),
];

/// Deepest nesting accepted, so that a pathological file cannot overflow the stack.
const MAX_DEPTH: usize = 64;

/// Most numbers, names and operations one expression may hold. Evaluating and dropping
/// a tree recurse through it, and a flat chain `1+1+…+1` is as deep as it is long, so
/// nesting alone does not bound the stack: this does (a thousand frames are a few tens
/// of kilobytes), and it bounds the work of every evaluation. Hand-written
/// expressions hold a few dozen.
pub const MAX_NODES: usize = 1000;

/// Why an expression was refused: a byte offset into its text and what was expected.
#[derive(Clone, Debug, PartialEq)]
pub struct ExprError {
    /// Byte offset in the expression's text.
    pub offset: usize,
    /// What went wrong, e.g. "unknown name 'mas'; valid names: mass, g".
    pub message: String,
}

impl Expr {
    /// Parses `text`; `names` are the variables it may use, in the order their values
    /// are given to [`Expr::eval`].
    pub fn parse(text: &str, names: &[&str]) -> Result<Self, ExprError> {
        let mut parser = Parser { text, position: 0, names, depth: 0, nodes: 0 };
        let expr = parser.sum()?;
        parser.skip_space();
        if parser.position < text.len() {
            let found = parser.rest().chars().next().unwrap_or(' ');
            return Err(parser.error(format!(
                "expected an operator (+ - * / ^) or the end, found '{}'",
                quote(&found.to_string())
            )));
        }
        Ok(expr)
    }

    /// The value with `values[k]` for variable `k`.
    #[must_use]
    pub fn eval(&self, values: &[f64]) -> f64 {
        match self {
            Self::Number(x) => *x,
            Self::Variable(k) => values.get(*k).copied().unwrap_or(f64::NAN),
            Self::Negate(x) => -x.eval(values),
            Self::Binary(op, a, b) => {
                let (a, b) = (a.eval(values), b.eval(values));
                match op {
                    Op::Add => a + b,
                    Op::Subtract => a - b,
                    Op::Multiply => a * b,
                    Op::Divide => a / b,
                    Op::Power => a.powf(b),
                }
            }
            Self::Call(function, x) => {
                let x = x.eval(values);
                match function {
                    Function::Sqrt => x.sqrt(),
                    Function::Sin => x.sin(),
                    Function::Cos => x.cos(),
                    Function::Tan => x.tan(),
                    Function::Abs => x.abs(),
                    Function::Exp => x.exp(),
                    Function::Ln => x.ln(),
                    Function::Rad => x.to_radians(),
                    Function::Round => x.round(),
                }
            }
        }
    }

    /// How many numbers, names and operations it holds: the work of one evaluation.
    #[must_use]
    pub fn size(&self) -> usize {
        match self {
            Self::Number(_) | Self::Variable(_) => 1,
            Self::Negate(x) | Self::Call(_, x) => 1 + x.size(),
            Self::Binary(_, a, b) => 1 + a.size() + b.size(),
        }
    }

    /// Whether the expression reads variable `k`.
    #[must_use]
    pub fn uses(&self, k: usize) -> bool {
        match self {
            Self::Number(_) => false,
            Self::Variable(v) => *v == k,
            Self::Negate(x) | Self::Call(_, x) => x.uses(k),
            Self::Binary(_, a, b) => a.uses(k) || b.uses(k),
        }
    }
}

struct Parser<'a> {
    text: &'a str,
    position: usize,
    names: &'a [&'a str],
    depth: usize,
    /// Nodes made so far, against [`MAX_NODES`].
    nodes: usize,
}

impl<'a> Parser<'a> {
    fn rest(&self) -> &'a str {
        &self.text[self.position..]
    }

    fn error(&self, message: String) -> ExprError {
        ExprError { offset: self.position, message }
    }

    fn skip_space(&mut self) {
        let trimmed = self.rest().trim_start();
        self.position = self.text.len() - trimmed.len();
    }

    /// Consumes `c` after any space, if it comes next.
    fn eat(&mut self, c: char) -> bool {
        self.skip_space();
        if self.rest().starts_with(c) {
            self.position += c.len_utf8();
            true
        } else {
            false
        }
    }

    /// `expr`, counted against the expression's budget of nodes.
    fn node(&mut self, expr: Expr) -> Result<Expr, ExprError> {
        self.nodes += 1;
        if self.nodes > MAX_NODES {
            return Err(self.error(format!(
                "the expression is too long: more than {MAX_NODES} numbers, names and operations \
                 (split it with a parameter)"
            )));
        }
        Ok(expr)
    }

    fn nested<T>(&mut self, inner: impl FnOnce(&mut Self) -> Result<T, ExprError>) -> Result<T, ExprError> {
        if self.depth >= MAX_DEPTH {
            return Err(self.error(format!("expression nested more than {MAX_DEPTH} deep")));
        }
        self.depth += 1;
        let result = inner(self);
        self.depth -= 1;
        result
    }

    /// sum := product (('+' | '-') product)*
    fn sum(&mut self) -> Result<Expr, ExprError> {
        let mut left = self.product()?;
        loop {
            let op = if self.eat('+') {
                Op::Add
            } else if self.eat('-') {
                Op::Subtract
            } else {
                return Ok(left);
            };
            let right = self.product()?;
            left = self.node(Expr::Binary(op, Box::new(left), Box::new(right)))?;
        }
    }

    /// product := unary (('*' | '/') unary)*
    fn product(&mut self) -> Result<Expr, ExprError> {
        let mut left = self.unary()?;
        loop {
            let op = if self.eat('*') {
                Op::Multiply
            } else if self.eat('/') {
                Op::Divide
            } else {
                return Ok(left);
            };
            let right = self.unary()?;
            left = self.node(Expr::Binary(op, Box::new(left), Box::new(right)))?;
        }
    }

    /// unary := '-' unary | '+' unary | power
    fn unary(&mut self) -> Result<Expr, ExprError> {
        self.nested(|p| {
            if p.eat('-') {
                let inner = p.unary()?;
                p.node(Expr::Negate(Box::new(inner)))
            } else if p.eat('+') {
                p.unary()
            } else {
                p.power()
            }
        })
    }

    /// power := atom ('^' unary)?   (so `-2^2` is -4 and `2^-1` is 0.5)
    fn power(&mut self) -> Result<Expr, ExprError> {
        let base = self.atom()?;
        if self.eat('^') {
            let exponent = self.unary()?;
            return self.node(Expr::Binary(Op::Power, Box::new(base), Box::new(exponent)));
        }
        Ok(base)
    }

    /// atom := number | name | function '(' sum ')' | '(' sum ')'
    fn atom(&mut self) -> Result<Expr, ExprError> {
        self.skip_space();
        let rest = self.rest();
        let Some(first) = rest.chars().next() else {
            return Err(self.error("expected a number, a parameter name or '(', found the end".into()));
        };
        if first == '(' {
            self.position += 1;
            let inner = self.nested(Self::sum)?;
            if !self.eat(')') {
                return Err(self.error("expected ')'".into()));
            }
            return Ok(inner);
        }
        if first.is_ascii_digit() || first == '.' {
            return self.number();
        }
        if first.is_alphabetic() || first == '_' {
            return self.name();
        }
        Err(self.error(format!(
            "expected a number, a parameter name or '(', found '{}'",
            quote(&first.to_string())
        )))
    }

    fn number(&mut self) -> Result<Expr, ExprError> {
        let rest = self.rest();
        let bytes = rest.as_bytes();
        let mut end = 0;
        while end < bytes.len() && (bytes[end].is_ascii_digit() || bytes[end] == b'.') {
            end += 1;
        }
        // An exponent: 1e-3, 2.5E4.
        if end < bytes.len() && (bytes[end] == b'e' || bytes[end] == b'E') {
            let mut exponent = end + 1;
            if exponent < bytes.len() && (bytes[exponent] == b'+' || bytes[exponent] == b'-') {
                exponent += 1;
            }
            if exponent < bytes.len() && bytes[exponent].is_ascii_digit() {
                end = exponent;
                while end < bytes.len() && bytes[end].is_ascii_digit() {
                    end += 1;
                }
            }
        }
        let text = &rest[..end];
        let value: f64 =
            text.parse().map_err(|_| self.error(format!("'{}' is not a number", clip(text, 40))))?;
        self.position += end;
        self.node(Expr::Number(value))
    }

    fn name(&mut self) -> Result<Expr, ExprError> {
        let start = self.position;
        let rest = self.rest();
        let end = rest.find(|c: char| !(c.is_alphanumeric() || c == '_')).unwrap_or(rest.len());
        let name = &rest[..end];
        if let Some(&(_, function)) = FUNCTIONS.iter().find(|(n, _)| *n == name) {
            self.position += end;
            if !self.eat('(') {
                return Err(self.error(format!("expected '(' after the function '{name}'")));
            }
            let argument = self.nested(Self::sum)?;
            if !self.eat(')') {
                return Err(self.error(format!("expected ')' to close '{name}('")));
            }
            return self.node(Expr::Call(function, Box::new(argument)));
        }
        if name == "pi" {
            self.position += end;
            return self.node(Expr::Number(std::f64::consts::PI));
        }
        match self.names.iter().position(|n| *n == name) {
            Some(k) => {
                self.position += end;
                self.node(Expr::Variable(k))
            }
            None => {
                let valid = self.names.iter().copied().chain(["pi"]);
                Err(ExprError {
                    offset: start,
                    message: format!("unknown name '{}'; valid names here: {}", clip(name, 32), list(valid)),
                })
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn value(text: &str) -> f64 {
        Expr::parse(text, &["a", "b"]).unwrap().eval(&[2.0, 10.0])
    }

    #[test]
    fn precedence_and_associativity() {
        assert_eq!(value("1 + 2 * 3"), 7.0);
        assert_eq!(value("(1 + 2) * 3"), 9.0);
        assert_eq!(value("10 - 4 - 3"), 3.0);
        assert_eq!(value("24 / 4 / 3"), 2.0);
        assert_eq!(value("2 ^ 3 ^ 2"), 512.0);
        assert_eq!(value("-2 ^ 2"), -4.0);
        assert_eq!(value("2 ^ -1"), 0.5);
        assert_eq!(value("a * b + 1"), 21.0);
        assert_eq!(value("1.5e2 + .5"), 150.5);
        assert_eq!(value("sqrt(b * 10)"), 10.0);
        assert!((value("sin(rad(30))") - 0.5).abs() < 1e-12);
        assert!((value("cos(pi)") + 1.0).abs() < 1e-12);
        assert_eq!(value("round(2.5) + round(a / 3)"), 4.0);
    }

    #[test]
    fn errors_name_the_offset_and_what_was_expected() {
        let error = Expr::parse("a + mas", &["a", "mass"]).unwrap_err();
        assert_eq!(error.offset, 4);
        assert_eq!(error.message, "unknown name 'mas'; valid names here: a, mass, pi");
        let error = Expr::parse("(a + 1", &["a"]).unwrap_err();
        assert_eq!((error.offset, error.message.as_str()), (6, "expected ')'"));
        let error = Expr::parse("a 2", &["a"]).unwrap_err();
        assert_eq!(error.offset, 2);
        let error = Expr::parse("", &["a"]).unwrap_err();
        assert!(error.message.contains("found the end"), "{}", error.message);
        let deep = "(".repeat(500) + "1" + &")".repeat(500);
        assert!(Expr::parse(&deep, &[]).unwrap_err().message.contains("nested"));
    }

    #[test]
    fn flat_chains_are_bounded_by_the_node_budget() {
        for op in ["+", "-", "*", "/"] {
            let long = "1".to_string() + &format!("{op}1").repeat(150_000);
            let error = Expr::parse(&long, &[]).unwrap_err();
            assert!(error.message.contains("too long"), "{op}: {}", error.message);
            // Refused as soon as the budget is spent, not at the end of the text.
            assert!(error.offset < 4 * MAX_NODES, "{op}: at {}", error.offset);
        }
        // Just within the budget: 500 numbers and 499 additions.
        let within = "1".to_string() + &"+1".repeat(499);
        assert_eq!(Expr::parse(&within, &[]).unwrap().eval(&[]), 500.0);
        let over = "1".to_string() + &"+1".repeat(500);
        assert!(Expr::parse(&over, &[]).is_err());
    }
}
