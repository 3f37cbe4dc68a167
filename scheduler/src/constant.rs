//! Graph constants: values from the host, declared as WGSL `const`s in the
//! generated module, so that bodies and the library use them by name
//! instead of having them spliced into their text.

use crate::CompileError;
use crate::naming::RESERVED_PREFIXES;

/// The value of a [`Graph::constant`](crate::Graph::constant): a `u32`,
/// `i32`, `f32` or `bool`, each declared with its WGSL type.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum ConstantValue {
    /// `const NAME: u32 = 7u;`
    U32(u32),
    /// `const NAME: i32 = -7i;`
    I32(i32),
    /// `const NAME: f32 = 0.1f;`, bit-exact (non-finite values are rejected
    /// when the graph compiles: WGSL has no literal for them).
    F32(f32),
    /// `const NAME: bool = true;`
    Bool(bool),
}

impl From<u32> for ConstantValue {
    fn from(value: u32) -> Self {
        Self::U32(value)
    }
}

impl From<i32> for ConstantValue {
    fn from(value: i32) -> Self {
        Self::I32(value)
    }
}

impl From<f32> for ConstantValue {
    fn from(value: f32) -> Self {
        Self::F32(value)
    }
}

impl From<bool> for ConstantValue {
    fn from(value: bool) -> Self {
        Self::Bool(value)
    }
}

impl ConstantValue {
    /// The WGSL type.
    pub fn wgsl_type(self) -> &'static str {
        match self {
            Self::U32(_) => "u32",
            Self::I32(_) => "i32",
            Self::F32(_) => "f32",
            Self::Bool(_) => "bool",
        }
    }

    /// The WGSL expression, or `None` for a non-finite `f32`.
    pub fn wgsl_literal(self) -> Option<String> {
        Some(match self {
            Self::U32(v) => format!("{v}u"),
            // `-2147483648i` would negate `2147483648i`, which does not fit.
            Self::I32(i32::MIN) => "i32(-2147483648)".to_owned(),
            Self::I32(v) => format!("{v}i"),
            // `{:?}` is the shortest text that parses back to the same bits
            // (`0.1`, `1e-7`, `3.4028235e38`), always a valid WGSL float
            // literal; the `f` suffix makes WGSL parse it as an f32 directly.
            Self::F32(v) if v.is_finite() => format!("{v:?}f"),
            Self::F32(_) => return None,
            Self::Bool(v) => v.to_string(),
        })
    }
}

/// Why a constant cannot be declared, or `None` when it can.
fn problem(name: &str, value: ConstantValue) -> Option<CompileError> {
    if RESERVED_PREFIXES
        .iter()
        .any(|prefix| name.starts_with(prefix))
    {
        return Some(CompileError::ReservedName {
            name: name.to_owned(),
        });
    }
    let mut chars = name.chars();
    let identifier = matches!(chars.next(), Some(c) if c.is_ascii_alphabetic() || c == '_')
        && chars.all(|c| c.is_ascii_alphanumeric() || c == '_')
        && !name.starts_with("__")
        && name != "_";
    if !identifier || naga::keywords::wgsl::RESERVED.contains(&name) {
        return Some(CompileError::InvalidConstantName(name.to_owned()));
    }
    if value.wgsl_literal().is_none() {
        return Some(CompileError::NonFiniteConstant {
            name: name.to_owned(),
            value: format!("{value:?}"),
        });
    }
    None
}

/// Checks every constant: names, duplicates and values.
pub(crate) fn check(constants: &[(String, ConstantValue)]) -> Result<(), CompileError> {
    for (i, (name, value)) in constants.iter().enumerate() {
        if let Some(error) = problem(name, *value) {
            return Err(error);
        }
        if constants[..i].iter().any(|(earlier, _)| earlier == name) {
            return Err(CompileError::DuplicateConstant(name.clone()));
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::{Rng, SeedableRng, rngs::StdRng};

    /// Parses `const X: TYPE = LITERAL;` with naga and returns the value.
    fn parse(value: ConstantValue) -> naga::Literal {
        let literal = value.wgsl_literal().unwrap();
        let source = format!("const X: {} = {literal};", value.wgsl_type());
        let module = naga::front::wgsl::parse_str(&source).unwrap();
        let (_, constant) = module.constants.iter().next().unwrap();
        match module.global_expressions[constant.init] {
            naga::Expression::Literal(literal) => literal,
            ref other => panic!("`{source}` is not a literal: {other:?}"),
        }
    }

    #[test]
    fn f32_literals_round_trip_through_naga_bit_for_bit() {
        let mut rng = StdRng::seed_from_u64(17);
        let special = [
            0.0,
            -0.0,
            0.1,
            1.0,
            -1.5,
            1e-7,
            f32::MAX,
            f32::MIN,
            f32::EPSILON,
            // Subnormals: the smallest, and the largest below f32::MIN_POSITIVE.
            1e-45,
            -1.1754942e-38,
        ];
        let drawn = (0..2000).map(|_| f32::from_bits(rng.random::<u32>()));
        for v in special.into_iter().chain(drawn).filter(|v| v.is_finite()) {
            match parse(ConstantValue::F32(v)) {
                naga::Literal::F32(back) => assert_eq!(back.to_bits(), v.to_bits(), "{v:?}"),
                other => panic!("{v:?} parsed as {other:?}"),
            }
        }
    }

    #[test]
    fn integer_extremes_are_valid_literals() {
        for v in [0, 1, -1, i32::MAX, i32::MIN] {
            assert_eq!(parse(ConstantValue::I32(v)), naga::Literal::I32(v));
        }
        for v in [0, u32::MAX] {
            assert_eq!(parse(ConstantValue::U32(v)), naga::Literal::U32(v));
        }
        assert_eq!(parse(ConstantValue::Bool(true)), naga::Literal::Bool(true));
    }

    #[test]
    fn bad_names_and_values_are_typed_errors() {
        let check_one = |name: &str, value: ConstantValue| check(&[(name.to_owned(), value)]);
        assert!(check_one("ROOT_WIDTH", 7u32.into()).is_ok());
        assert!(matches!(
            check_one("SCHED_X", 1u32.into()),
            Err(CompileError::ReservedName { .. })
        ));
        for name in ["", "1a", "a-b", "__x", "loop", "const"] {
            assert_eq!(
                check_one(name, 1u32.into()),
                Err(CompileError::InvalidConstantName(name.to_owned()))
            );
        }
        for v in [f32::NAN, f32::INFINITY, f32::NEG_INFINITY] {
            assert!(matches!(
                check_one("X", v.into()),
                Err(CompileError::NonFiniteConstant { .. })
            ));
        }
        let twice = [("N".to_owned(), 1u32.into()), ("N".to_owned(), 2u32.into())];
        assert_eq!(
            check(&twice),
            Err(CompileError::DuplicateConstant("N".into()))
        );
    }
}
