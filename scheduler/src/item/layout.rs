//! WGSL's struct layout rules as const functions, so that
//! [`#[derive(Item)]`](crate::Item) can compare them with Rust's layout at
//! compile time. Each field is given as `(alignment, size)` in bytes, taken
//! from its [`WgslType`](crate::WgslType).
//!
//! WGSL places a member at the first offset past the previous member that is
//! a multiple of its alignment; a struct's alignment is its largest member
//! alignment and its size is rounded up to a multiple of that (WGSL spec,
//! "Alignment and Size"). Explicit `@align` and `@size` attributes are not
//! used: derived structs state padding as ordinary fields, as Rust does.

/// `offset` rounded up to a multiple of `align` (a power of two).
pub const fn round_up(offset: usize, align: usize) -> usize {
    offset.div_ceil(align) * align
}

/// The alignment of a struct whose members have the given alignments.
pub const fn struct_align(aligns: &[usize]) -> usize {
    let mut align = 1;
    let mut i = 0;
    while i < aligns.len() {
        if aligns[i] > align {
            align = aligns[i];
        }
        i += 1;
    }
    align
}

/// The byte offset WGSL gives member `index` of a struct whose members have
/// the given `(alignment, size)`.
pub const fn field_offset(fields: &[(usize, usize)], index: usize) -> usize {
    let mut end = 0;
    let mut i = 0;
    while i < index {
        end = round_up(end, fields[i].0) + fields[i].1;
        i += 1;
    }
    round_up(end, fields[index].0)
}

/// The size WGSL gives a struct whose members have the given
/// `(alignment, size)`.
pub const fn struct_size(fields: &[(usize, usize)]) -> usize {
    let mut end = 0;
    let mut align = 1;
    let mut i = 0;
    while i < fields.len() {
        end = round_up(end, fields[i].0) + fields[i].1;
        if fields[i].0 > align {
            align = fields[i].0;
        }
        i += 1;
    }
    round_up(end, align)
}

/// Longest declaration written on one line; longer ones get a line per field.
const ONE_LINE: usize = 96;

/// The WGSL declaration of struct `name` with `(field, type)` members:
/// `struct Node { depth: u32, id: u32 }`, or one field per line when long.
pub fn struct_declaration(name: &str, fields: &[(&str, String)]) -> String {
    let documented: Vec<(&str, String, &str)> =
        fields.iter().map(|(f, ty)| (*f, ty.clone(), "")).collect();
    documented_struct_declaration(name, &documented)
}

/// [`struct_declaration`] with a comment per field: `(field, type, doc)`.
/// A declaration that fits on one line stays on one line without its
/// comments; a longer one puts each field on its own line, under its doc
/// (each line of it a `//` comment), so that the generated module explains a
/// large shared struct the way its Rust twin's documentation does.
pub fn documented_struct_declaration(name: &str, fields: &[(&str, String, &str)]) -> String {
    let members: Vec<String> = fields
        .iter()
        .map(|(f, ty, _)| format!("{f}: {ty}"))
        .collect();
    let line = format!("struct {name} {{ {} }}", members.join(", "));
    if line.len() <= ONE_LINE {
        return line;
    }
    let mut text = format!("struct {name} {{\n");
    for (member, (_, _, doc)) in members.iter().zip(fields) {
        for doc_line in doc.lines().map(str::trim_end) {
            if doc_line.trim().is_empty() {
                text.push_str("    //\n");
            } else {
                text.push_str(&format!("    // {}\n", doc_line.trim()));
            }
        }
        text.push_str(&format!("    {member},\n"));
    }
    text.push('}');
    text
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn members_are_placed_by_wgsl_rules() {
        // u32, vec4<f32>, vec2<f32>, f32: the vec4 skips to 16, the struct
        // rounds 44 up to 48.
        let fields = [(4, 4), (16, 16), (8, 8), (4, 4)];
        let offsets: Vec<usize> = (0..4).map(|i| field_offset(&fields, i)).collect();
        assert_eq!(offsets, [0, 16, 32, 40]);
        assert_eq!(struct_size(&fields), 48);
        assert_eq!(struct_align(&[4, 16, 8, 4]), 16);
    }

    #[test]
    fn long_declarations_get_a_line_per_field() {
        let short = struct_declaration("A", &[("x", "u32".into())]);
        assert_eq!(short, "struct A { x: u32 }");
        let many: Vec<(&str, String)> = ["alpha", "beta", "gamma", "delta", "epsilon", "zeta"]
            .iter()
            .map(|f| (*f, "array<vec4<f32>, 4>".to_owned()))
            .collect();
        let long = struct_declaration("B", &many);
        assert!(long.starts_with("struct B {\n    alpha: array<vec4<f32>, 4>,\n"));
        assert!(long.ends_with("zeta: array<vec4<f32>, 4>,\n}"));
    }

    #[test]
    fn long_declarations_carry_their_field_docs() {
        let fields: Vec<(&str, String, &str)> = vec![
            (
                "view_proj",
                "mat4x4<f32>".into(),
                "World to clip.\n\nColumn-major.",
            ),
            ("eye", "vec3<f32>".into(), ""),
            (
                "a_long_field_name_to_force_lines",
                "array<vec4<f32>, 4>".into(),
                "Why.",
            ),
        ];
        let text = documented_struct_declaration("Frame", &fields);
        assert_eq!(
            text,
            "struct Frame {\n    // World to clip.\n    //\n    // Column-major.\n    view_proj: mat4x4<f32>,\n    eye: vec3<f32>,\n    // Why.\n    a_long_field_name_to_force_lines: array<vec4<f32>, 4>,\n}"
        );
        let short = documented_struct_declaration("A", &[("x", "u32".into(), "Dropped.")]);
        assert_eq!(short, "struct A { x: u32 }");
    }
}
