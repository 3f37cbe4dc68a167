//! Gives a user shader's module-scope names a prefix of their own, so that
//! several shaders (each with its own `surface`, `Parameters` and helpers)
//! live side by side in one megakernel without clashing with each other or
//! with the renderer's names.
//!
//! The renaming works on tokens: it runs only on source that naga has
//! already accepted, and it renames every identifier that names one of the
//! shader's own module-scope declarations, except a member after `.` and a
//! member declared in a struct body. A local that shadows a module-scope
//! name is renamed with it, consistently, which keeps the program's meaning.
//! Comments and layout stay as the user wrote them.

use std::collections::BTreeSet;

/// One lexical token of WGSL, as far as renaming needs.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Token<'a> {
    /// An identifier (or keyword).
    Ident(&'a str),
    /// A single punctuation character.
    Punct(char),
    /// Anything renaming leaves alone: comments, whitespace, numbers.
    Other(&'a str),
}

/// Splits `source` into tokens that concatenate back to it.
fn tokens(source: &str) -> Vec<Token<'_>> {
    let bytes = source.as_bytes();
    let mut out = Vec::new();
    let mut i = 0;
    while i < bytes.len() {
        let start = i;
        let c = bytes[i];
        if c == b'/' && bytes.get(i + 1) == Some(&b'/') {
            while i < bytes.len() && bytes[i] != b'\n' {
                i += 1;
            }
            out.push(Token::Other(&source[start..i]));
        } else if c == b'/' && bytes.get(i + 1) == Some(&b'*') {
            // WGSL block comments nest.
            let mut depth = 0usize;
            while i < bytes.len() {
                if bytes[i] == b'/' && bytes.get(i + 1) == Some(&b'*') {
                    depth += 1;
                    i += 2;
                } else if bytes[i] == b'*' && bytes.get(i + 1) == Some(&b'/') {
                    depth -= 1;
                    i += 2;
                    if depth == 0 {
                        break;
                    }
                } else {
                    i += 1;
                }
            }
            out.push(Token::Other(&source[start..i.min(bytes.len())]));
        } else if c.is_ascii_alphabetic() || c == b'_' {
            while i < bytes.len() && (bytes[i].is_ascii_alphanumeric() || bytes[i] == b'_') {
                i += 1;
            }
            out.push(Token::Ident(&source[start..i]));
        } else if c.is_ascii_digit() {
            // Numbers, with exponents' signs (1e-5) and suffixes (2u, 0x1p3f).
            while i < bytes.len() {
                let b = bytes[i];
                let signed_exponent = (b == b'+' || b == b'-')
                    && matches!(bytes[i - 1], b'e' | b'E' | b'p' | b'P')
                    && !source[start..i].starts_with("0x");
                if b.is_ascii_alphanumeric() || b == b'.' || b == b'_' || signed_exponent {
                    i += 1;
                } else {
                    break;
                }
            }
            out.push(Token::Other(&source[start..i]));
        } else if c.is_ascii_whitespace() {
            while i < bytes.len() && bytes[i].is_ascii_whitespace() {
                i += 1;
            }
            out.push(Token::Other(&source[start..i]));
        } else {
            // One character, as a whole UTF-8 sequence.
            let ch = source[i..].chars().next().unwrap_or('\u{fffd}');
            i += ch.len_utf8();
            out.push(if ch.is_ascii() {
                Token::Punct(ch)
            } else {
                Token::Other(&source[start..i])
            });
        }
    }
    out
}

/// Whether `token` carries meaning (not a comment or whitespace).
fn significant(token: &Token<'_>) -> bool {
    match token {
        Token::Other(text) => {
            !(text.starts_with("//") || text.starts_with("/*") || text.trim().is_empty())
        }
        _ => true,
    }
}

/// The names `source` declares at module scope: after `fn`, `struct`,
/// `const`, `alias` and `override` outside any braces.
pub(super) fn module_scope_names(source: &str) -> BTreeSet<String> {
    let tokens: Vec<Token<'_>> = tokens(source).into_iter().filter(significant).collect();
    let mut names = BTreeSet::new();
    let mut depth = 0i32;
    for pair in tokens.windows(2) {
        match pair[0] {
            Token::Punct('{') => depth += 1,
            Token::Punct('}') => depth -= 1,
            Token::Ident("fn" | "struct" | "const" | "alias" | "override") if depth == 0 => {
                if let Token::Ident(name) = pair[1] {
                    names.insert(name.to_owned());
                }
            }
            _ => {}
        }
    }
    names
}

/// `source` with every use of a name in `names` written `{prefix}{name}`
/// (see the module's documentation for what counts as a use).
pub(super) fn prefix_names(source: &str, names: &BTreeSet<String>, prefix: &str) -> String {
    let all = tokens(source);
    let mut out = String::with_capacity(source.len() + 16 * names.len());
    // The last significant token, the brace depth at which a struct body
    // was opened (if inside one), and whether the next `{` opens one.
    let mut previous: Option<Token<'_>> = None;
    let mut depth = 0i32;
    let mut struct_body: Option<i32> = None;
    let mut struct_pending = false;
    for (index, token) in all.iter().enumerate() {
        match *token {
            Token::Punct('{') => {
                depth += 1;
                if struct_pending {
                    struct_body = Some(depth);
                    struct_pending = false;
                }
            }
            Token::Punct('}') => {
                if struct_body == Some(depth) {
                    struct_body = None;
                }
                depth -= 1;
            }
            Token::Ident("struct") => struct_pending = true,
            _ => {}
        }
        let rename = match *token {
            Token::Ident(name) if names.contains(name) => {
                let after_dot = previous == Some(Token::Punct('.'));
                let after_attribute = previous == Some(Token::Punct('@'));
                let next = all[index + 1..].iter().find(|t| significant(t));
                let member_declaration =
                    struct_body == Some(depth) && next == Some(&Token::Punct(':'));
                !(after_dot || after_attribute || member_declaration)
            }
            _ => false,
        };
        match *token {
            Token::Ident(name) if rename => {
                out.push_str(prefix);
                out.push_str(name);
            }
            Token::Ident(text) | Token::Other(text) => out.push_str(text),
            Token::Punct(c) => out.push(c),
        }
        if significant(token) {
            previous = Some(*token);
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    const SHADER: &str = "// fbm: sums octaves of noise
struct Parameters {
    fbm: f32,   /* a member named like a function */
    octaves: u32,
}
const DEFAULTS = Parameters(1e-5, 4u);
fn fbm(x: f32) -> f32 { return x * 2.0; }
fn surface(ctx: ShadingContext, params: Parameters) -> SurfaceOutput {
    let fbm_value = fbm(params.fbm) + DEFAULTS.fbm;
    return SurfaceOutput(ctx.Cs * fbm_value, ctx.Os);
}
";

    #[test]
    fn finds_the_module_scope_declarations_only() {
        let names: Vec<String> = module_scope_names(SHADER).into_iter().collect();
        assert_eq!(names, ["DEFAULTS", "Parameters", "fbm", "surface"]);
    }

    #[test]
    fn renames_uses_but_not_members_comments_or_the_interface() {
        let renamed = prefix_names(SHADER, &module_scope_names(SHADER), "s0_");
        let expected = "// fbm: sums octaves of noise
struct s0_Parameters {
    fbm: f32,   /* a member named like a function */
    octaves: u32,
}
const s0_DEFAULTS = s0_Parameters(1e-5, 4u);
fn s0_fbm(x: f32) -> f32 { return x * 2.0; }
fn s0_surface(ctx: ShadingContext, params: s0_Parameters) -> SurfaceOutput {
    let fbm_value = s0_fbm(params.fbm) + s0_DEFAULTS.fbm;
    return SurfaceOutput(ctx.Cs * fbm_value, ctx.Os);
}
";
        assert_eq!(renamed, expected);
    }

    #[test]
    fn tokens_concatenate_back_to_the_source() {
        let odd = "fn f() { let x = 0x1p-3f + 1e+5 - 2u; /* a /* nested */ comment */ } // é\n";
        let joined: String = tokens(odd)
            .iter()
            .map(|t| match t {
                Token::Ident(s) | Token::Other(s) => (*s).to_owned(),
                Token::Punct(c) => c.to_string(),
            })
            .collect();
        assert_eq!(joined, odd);
    }
}
