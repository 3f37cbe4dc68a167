//! The ASCII RIB tokenizer: request names, numbers, strings, `[` and `]`,
//! with `#` comments skipped. Every token carries its 1-based line and
//! column. [`Lexer`] yields one token at a time, so memory does not grow
//! with the length of the file.

use std::iter::Peekable;
use std::path::Path;
use std::str::CharIndices;

use super::RibError;
use crate::input::excerpt;

/// One token of an ASCII RIB stream.
#[derive(Debug, Clone, PartialEq)]
pub enum Token {
    /// A bare word: a request name such as `WorldBegin`.
    Request(String),
    /// A number (integer or real).
    Number(f64),
    /// A quoted string, escapes resolved.
    Str(String),
    /// `[`
    Open,
    /// `]`
    Close,
}

/// A token with its position (1-based line and column, columns in characters).
#[derive(Debug, Clone, PartialEq)]
pub struct Spanned {
    /// The token.
    pub token: Token,
    /// Line of its first character.
    pub line: usize,
    /// Column of its first character.
    pub col: usize,
}

/// Longest string or word accepted, in bytes: a bound on what one token can
/// hold beyond the file itself.
const MAX_TOKEN_BYTES: usize = 1 << 20;

/// The tokens of one RIB text, in order.
#[derive(Debug)]
pub struct Lexer<'a> {
    text: &'a str,
    chars: Peekable<CharIndices<'a>>,
    line: usize,
    col: usize,
    file: &'a Path,
    failed: bool,
}

impl<'a> Lexer<'a> {
    /// A lexer over `text`, the whole of one file named `file` (for errors).
    pub fn new(text: &'a str, file: &'a Path) -> Lexer<'a> {
        Lexer {
            text,
            chars: text.char_indices().peekable(),
            line: 1,
            col: 1,
            file,
            failed: false,
        }
    }

    fn bump(&mut self) -> Option<char> {
        let (_, c) = self.chars.next()?;
        if c == '\n' {
            self.line += 1;
            self.col = 1;
        } else {
            self.col += 1;
        }
        Some(c)
    }

    fn error(&self, line: usize, col: usize, message: String) -> RibError {
        RibError::Syntax {
            file: self.file.to_path_buf(),
            line,
            col,
            message,
        }
    }

    /// The end (byte offset) of the word starting at `start`, consuming it.
    fn word_end(&mut self, start: usize, part: impl Fn(char) -> bool) -> usize {
        let mut end = start;
        while let Some(&(i, c)) = self.chars.peek() {
            if !part(c) {
                break;
            }
            end = i + c.len_utf8();
            self.bump();
        }
        end
    }

    fn string(&mut self, line: usize, col: usize) -> Result<Token, RibError> {
        self.bump();
        let mut s = String::new();
        loop {
            let Some(c) = self.bump() else {
                return Err(self.error(line, col, "unterminated string".into()));
            };
            match c {
                '"' => return Ok(Token::Str(s)),
                '\\' => match self.bump() {
                    None => return Err(self.error(line, col, "unterminated string".into())),
                    Some('n') => s.push('\n'),
                    Some('t') => s.push('\t'),
                    Some('r') => s.push('\r'),
                    Some('\n') => {}
                    Some(other) => s.push(other),
                },
                other => s.push(other),
            }
            if s.len() > MAX_TOKEN_BYTES {
                return Err(self.error(line, col, "string longer than 1 MiB".into()));
            }
        }
    }

    fn token(&mut self) -> Option<Result<Spanned, RibError>> {
        loop {
            let &(start, c) = self.chars.peek()?;
            let (line, col) = (self.line, self.col);
            let token = match c {
                c if c.is_whitespace() => {
                    self.bump();
                    continue;
                }
                '#' => {
                    while self.chars.peek().is_some_and(|&(_, c)| c != '\n') {
                        self.bump();
                    }
                    continue;
                }
                '[' => {
                    self.bump();
                    Ok(Token::Open)
                }
                ']' => {
                    self.bump();
                    Ok(Token::Close)
                }
                '"' => self.string(line, col),
                c if c.is_ascii_digit() || matches!(c, '-' | '+' | '.') => {
                    let end = self.word_end(start, |c| {
                        c.is_ascii_alphanumeric() || matches!(c, '-' | '+' | '.')
                    });
                    let word = &self.text[start..end];
                    let letters_ok = word
                        .chars()
                        .all(|c| !c.is_ascii_alphabetic() || c == 'e' || c == 'E');
                    match word.parse::<f64>() {
                        Ok(v) if v.is_finite() && letters_ok => Ok(Token::Number(v)),
                        _ => Err(self.error(
                            line,
                            col,
                            format!("invalid number {:?}", excerpt(word)),
                        )),
                    }
                }
                c if c.is_ascii_alphabetic() || c == '_' => {
                    let end = self.word_end(start, |c| c.is_ascii_alphanumeric() || c == '_');
                    let word = &self.text[start..end];
                    if word.len() > MAX_TOKEN_BYTES {
                        Err(self.error(line, col, "request name longer than 1 MiB".into()))
                    } else {
                        Ok(Token::Request(word.to_owned()))
                    }
                }
                c if !c.is_ascii() || (c as u32) < 0x20 || c as u32 == 0x7f => Err(self.error(
                    line,
                    col,
                    format!(
                        "unexpected byte {:#04x}: binary RIB is not supported (only ASCII RIB)",
                        self.text.as_bytes()[start]
                    ),
                )),
                other => Err(self.error(line, col, format!("unexpected character {other:?}"))),
            };
            return Some(token.map(|token| Spanned { token, line, col }));
        }
    }
}

impl Iterator for Lexer<'_> {
    type Item = Result<Spanned, RibError>;

    /// The next token; after an error, `None`.
    fn next(&mut self) -> Option<Self::Item> {
        if self.failed {
            return None;
        }
        let next = self.token();
        self.failed = matches!(next, Some(Err(_)));
        next
    }
}

/// All the tokens of `text` (a file named `file`), or the first error.
pub fn tokenize(text: &str, file: &Path) -> Result<Vec<Spanned>, RibError> {
    Lexer::new(text, file).collect()
}
