//! Test support: std430 offsets of a struct in a GLSL include, so that tests can check the
//! `#[repr(C)]` mirrors against the shader source itself.

/// `(field, offset)` of every member of `struct name` in `src`, and the struct's size.
/// Knows the member types our layouts use; any other type fails the test that asks.
pub fn std430_offsets(src: &str, name: &str) -> (Vec<(String, usize)>, usize) {
    let start = src
        .find(&format!("struct {name} {{"))
        .unwrap_or_else(|| panic!("struct {name} not found"));
    let body = &src[start..start + src[start..].find("};").expect("struct end")];
    let mut offset = 0usize;
    let mut largest_align = 4;
    let mut out = Vec::new();
    for line in body.lines().skip(1) {
        let code = line.split("//").next().unwrap_or("").trim();
        let Some(decl) = code.strip_suffix(';') else {
            continue;
        };
        let mut parts = decl.split_whitespace();
        let (ty, field) = (parts.next().expect("type"), parts.next().expect("name"));
        let (size, align): (usize, usize) = match ty {
            "float" | "int" | "uint" => (4, 4),
            "vec2" | "ivec2" | "uvec2" | "int64_t" => (8, 8),
            "vec3" => (12, 16),
            "vec4" | "ivec4" | "uvec4" => (16, 16),
            "mat4" => (64, 16),
            "i64vec2" => (16, 16),
            "i64vec4" | "dvec4" => (32, 32),
            other => panic!("{name}.{field} has type {other}; teach glsl_layout its std430 layout"),
        };
        // An array `field[N]`: N elements, each padded to its alignment (std430). A lone
        // vec3 is not padded: a scalar may follow in its fourth component.
        let (field, size) = match field.split_once('[') {
            Some((field, rest)) => (
                field,
                size.next_multiple_of(align) * array_length(src, rest.trim_end_matches(']')),
            ),
            None => (field, size),
        };
        offset = offset.next_multiple_of(align);
        largest_align = largest_align.max(align);
        out.push((field.to_string(), offset));
        offset += size;
    }
    (out, offset.next_multiple_of(largest_align))
}

/// An array length: a number, or the name of a `#define` in `src`.
fn array_length(src: &str, length: &str) -> usize {
    let value = src
        .lines()
        .find_map(|l| l.strip_prefix(&format!("#define {length} ")))
        .unwrap_or(length);
    value
        .trim()
        .trim_end_matches('u')
        .parse()
        .unwrap_or_else(|_| panic!("array length {length} is neither a number nor a #define"))
}

#[cfg(test)]
mod tests {
    use super::std430_offsets;

    #[test]
    fn arrays_take_their_length_from_a_number_or_a_define() {
        let src = "#define COUNT 3u\nstruct S {\n    uint a;\n    uint b[COUNT]; // note\n    vec2 c[2];\n    vec3 d;\n    uint e;\n    vec3 f[2];\n};\n";
        let (fields, size) = std430_offsets(src, "S");
        let offsets: Vec<usize> = fields.iter().map(|(_, o)| *o).collect();
        assert_eq!(offsets, [0, 4, 16, 32, 44, 48]);
        assert_eq!(fields[1].0, "b");
        assert_eq!(size, 80);
    }
}
