//! Groups tokens into requests: a request name followed by its values
//! (numbers, strings and arrays of either). [`Parser`] yields one request at
//! a time.

use std::iter::Peekable;
use std::path::Path;

use super::RibError;
use super::lexer::{Lexer, Spanned, Token};

/// One value after a request name.
#[derive(Debug, Clone, PartialEq)]
pub enum Value {
    /// A bare number.
    Num(f64),
    /// A bare string.
    Str(String),
    /// `[ numbers ]` (an empty array is a number array).
    Nums(Vec<f64>),
    /// `[ strings ]`.
    Strs(Vec<String>),
}

impl Value {
    /// The numbers of a number or number array.
    pub fn nums(&self) -> Option<Vec<f64>> {
        match self {
            Value::Num(n) => Some(vec![*n]),
            Value::Nums(v) => Some(v.clone()),
            _ => None,
        }
    }

    /// The string of a string or one-string array.
    pub fn str(&self) -> Option<&str> {
        match self {
            Value::Str(s) => Some(s),
            Value::Strs(v) if v.len() == 1 => Some(&v[0]),
            _ => None,
        }
    }
}

/// One request and its values, with the position of its name.
#[derive(Debug, Clone, PartialEq)]
pub struct Call {
    /// The request name.
    pub name: String,
    /// Its values in order.
    pub values: Vec<Value>,
    /// Line of the name.
    pub line: usize,
    /// Column of the name.
    pub col: usize,
}

/// The requests of one RIB text, in order.
#[derive(Debug)]
pub struct Parser<'a> {
    tokens: Peekable<Lexer<'a>>,
    file: &'a Path,
}

impl<'a> Parser<'a> {
    /// A parser over `text`, the whole of one file named `file`.
    pub fn new(text: &'a str, file: &'a Path) -> Parser<'a> {
        Parser {
            tokens: Lexer::new(text, file).peekable(),
            file,
        }
    }

    fn error(&self, line: usize, col: usize, message: String) -> RibError {
        RibError::Syntax {
            file: self.file.to_path_buf(),
            line,
            col,
            message,
        }
    }

    /// The next request, `None` at the end of the text.
    pub fn next_call(&mut self) -> Result<Option<Call>, RibError> {
        let Some(first) = self.tokens.next().transpose()? else {
            return Ok(None);
        };
        let Token::Request(name) = first.token else {
            return Err(self.error(
                first.line,
                first.col,
                "a value before the first request".into(),
            ));
        };
        let mut call = Call {
            name,
            values: Vec::new(),
            line: first.line,
            col: first.col,
        };
        loop {
            match self.tokens.peek() {
                None
                | Some(Ok(Spanned {
                    token: Token::Request(_),
                    ..
                })) => return Ok(Some(call)),
                Some(_) => {}
            }
            let Spanned { token, line, col } = self.tokens.next().expect("peeked")?;
            let value = match token {
                Token::Request(_) => unreachable!("peeked"),
                Token::Number(n) => Value::Num(n),
                Token::Str(s) => Value::Str(s),
                Token::Close => {
                    return Err(self.error(line, col, "']' without a matching '['".into()));
                }
                Token::Open => self.array(line, col)?,
            };
            call.values.push(value);
        }
    }

    fn array(&mut self, line: usize, col: usize) -> Result<Value, RibError> {
        let mut nums = Vec::new();
        let mut strs = Vec::new();
        loop {
            let Some(t) = self.tokens.next().transpose()? else {
                return Err(self.error(line, col, "array '[' is never closed".into()));
            };
            match t.token {
                Token::Close => break,
                Token::Number(n) if strs.is_empty() => nums.push(n),
                Token::Str(s) if nums.is_empty() => strs.push(s),
                Token::Number(_) | Token::Str(_) => {
                    return Err(self.error(
                        t.line,
                        t.col,
                        "an array mixes numbers and strings".into(),
                    ));
                }
                Token::Open => {
                    return Err(self.error(t.line, t.col, "nested '[' inside an array".into()));
                }
                Token::Request(name) => {
                    return Err(self.error(
                        t.line,
                        t.col,
                        format!(
                            "request {:?} inside an array (missing ']'?)",
                            crate::input::excerpt(&name)
                        ),
                    ));
                }
            }
        }
        Ok(if strs.is_empty() {
            Value::Nums(nums)
        } else {
            Value::Strs(strs)
        })
    }
}

/// All the requests of `text` (a file named `file`), or the first error.
pub fn parse(text: &str, file: &Path) -> Result<Vec<Call>, RibError> {
    let mut parser = Parser::new(text, file);
    let mut calls = Vec::new();
    while let Some(call) = parser.next_call()? {
        calls.push(call);
    }
    Ok(calls)
}
