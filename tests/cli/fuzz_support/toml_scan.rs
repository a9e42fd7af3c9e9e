//! Finding statements, values, numbers and arrays in a base input by simple
//! scanning (the bases keep every statement on one line, without trailing
//! comments).

pub fn split_lines(text: &str) -> Vec<String> {
    text.split('\n').map(String::from).collect()
}

/// `key = value` lines: (line index, byte offset of the value).
pub fn statements(lines: &[String]) -> Vec<(usize, usize)> {
    let mut found = Vec::new();
    for (i, line) in lines.iter().enumerate() {
        let trimmed = line.trim_start();
        if trimmed.starts_with('#') || trimmed.starts_with('[') {
            continue;
        }
        if let Some(eq) = line.find('=') {
            found.push((i, eq + 1));
        }
    }
    found
}

/// Lines that are neither blank nor comments.
pub fn content_lines(lines: &[String]) -> Vec<usize> {
    (0..lines.len())
        .filter(|&i| {
            let t = lines[i].trim();
            !t.is_empty() && !t.starts_with('#')
        })
        .collect()
}

/// For each byte of `value`: whether it is inside a string literal (the
/// bases use only basic strings without escapes).
pub fn in_string(value: &str) -> Vec<bool> {
    let mut inside = false;
    value
        .bytes()
        .map(|b| {
            if b == b'"' {
                inside = !inside;
                return true;
            }
            inside
        })
        .collect()
}

/// Number literals in values: (line, start, end).
pub fn number_tokens(lines: &[String]) -> Vec<(usize, usize, usize)> {
    let is_token_byte = |b: u8| b.is_ascii_alphanumeric() || b"._+-".contains(&b);
    let mut found = Vec::new();
    for (i, v) in statements(lines) {
        let value = &lines[i][v..];
        let quoted = in_string(value);
        let bytes = value.as_bytes();
        let mut j = 0;
        while j < bytes.len() {
            if quoted[j] || !is_token_byte(bytes[j]) {
                j += 1;
                continue;
            }
            let start = j;
            while j < bytes.len() && !quoted[j] && is_token_byte(bytes[j]) {
                j += 1;
            }
            if is_number(&value[start..j]) {
                found.push((i, v + start, v + j));
            }
        }
    }
    found
}

/// A TOML number literal (not `inf` or `nan`, which the bases do not hold).
fn is_number(token: &str) -> bool {
    let digits = token.trim_start_matches(['+', '-']);
    digits.starts_with(|c: char| c.is_ascii_digit()) && digits.parse::<f64>().is_ok()
}

/// An array in a value: line, byte offsets of `[` and its `]`, and whether a
/// changed length may still be valid (only a floe's list of vertices).
pub struct Array {
    pub line: usize,
    pub open: usize,
    pub close: usize,
    pub any_length: bool,
}

pub fn arrays(lines: &[String]) -> Vec<Array> {
    let mut found = Vec::new();
    for (i, v) in statements(lines) {
        let value = &lines[i][v..];
        let quoted = in_string(value);
        let key = lines[i][..v - 1].trim();
        let mut first = true;
        for (j, b) in value.bytes().enumerate() {
            if b != b'[' || quoted[j] {
                continue;
            }
            let close = matching_bracket(value, &quoted, j);
            found.push(Array {
                line: i,
                open: v + j,
                close: v + close,
                any_length: key == "vertices_m" && first,
            });
            first = false;
        }
    }
    found
}

fn matching_bracket(value: &str, quoted: &[bool], open: usize) -> usize {
    let mut depth = 0;
    for (j, b) in value.bytes().enumerate().skip(open) {
        match b {
            _ if quoted[j] => {}
            b'[' => depth += 1,
            b']' => {
                depth -= 1;
                if depth == 0 {
                    return j;
                }
            }
            _ => {}
        }
    }
    value.len()
}

/// The elements of an array's inside, split at its own commas.
pub fn elements(inner: &str) -> Vec<String> {
    let quoted = in_string(inner);
    let mut parts = Vec::new();
    let (mut depth, mut start) = (0, 0);
    for (j, b) in inner.bytes().enumerate() {
        match b {
            _ if quoted[j] => {}
            b'[' | b'{' => depth += 1,
            b']' | b'}' => depth -= 1,
            b',' if depth == 0 => {
                parts.push(inner[start..j].trim().to_string());
                start = j + 1;
            }
            _ => {}
        }
    }
    parts.push(inner[start..].trim().to_string());
    parts.retain(|p| !p.is_empty());
    parts
}

/// The TOML type of a (simple) value.
pub fn toml_type(value: &str) -> Option<&'static str> {
    let table: toml::Table = format!("x = {value}").parse().ok()?;
    Some(table["x"].type_str())
}
