//! Reading user files with errors that point at the line, column and key.

use std::ops::Range;
use std::path::{Path, PathBuf};

use serde::de::DeserializeOwned;
use toml::Spanned;

use crate::error::ScenarioError;
use crate::numbers::short;

/// A text file the user wrote, kept to locate errors in it.
#[derive(Debug, Clone)]
pub struct SourceFile {
    /// Where it was read from.
    pub path: PathBuf,
    /// Its contents.
    pub text: String,
}

impl SourceFile {
    /// Reads `path` as UTF-8 text. Bytes that are not UTF-8 are an input
    /// error at the first of them, saying what the file looks like (an
    /// HDF5 run file, gzip, UTF-16, Latin-1 text).
    pub fn read(path: &Path) -> Result<Self, ScenarioError> {
        use std::io::Read;
        // Scenario and protocol files are kilobytes; `/dev/zero` never ends.
        const MOST_BYTES: u64 = 64 << 20;
        let mut bytes = Vec::new();
        std::fs::File::open(path)
            .and_then(|f| f.take(MOST_BYTES + 1).read_to_end(&mut bytes))
            .map_err(|e| ScenarioError::io(path, e))?;
        if bytes.len() as u64 > MOST_BYTES {
            return Err(ScenarioError::Input {
                file: path.to_path_buf(),
                line: 1,
                column: 1,
                key: None,
                message: format!(
                    "more than {} MiB: not a scenario or protocol file",
                    MOST_BYTES >> 20
                ),
            });
        }
        match String::from_utf8(bytes) {
            Ok(text) => Ok(Self {
                path: path.to_path_buf(),
                text,
            }),
            Err(e) => {
                let bytes = e.as_bytes();
                let at = e.utf8_error().valid_up_to();
                let prefix = Self {
                    path: path.to_path_buf(),
                    text: String::from_utf8_lossy(&bytes[..at]).into_owned(),
                };
                let (message, whole_file) = not_text(bytes, at);
                let (line, column) = if whole_file {
                    (1, 1)
                } else {
                    prefix.line_column(at)
                };
                Err(ScenarioError::Input {
                    file: path.to_path_buf(),
                    line,
                    column,
                    key: None,
                    message,
                })
            }
        }
    }

    /// The file as an editable TOML document (comments and layout kept),
    /// for tools that rewrite scenarios; a syntax error is located.
    pub fn parse_document(&self) -> Result<toml_edit::DocumentMut, ScenarioError> {
        self.text.parse::<toml_edit::DocumentMut>().map_err(|e| {
            if e.span().is_none() && e.message().contains("recursion limit") {
                return self.too_deep();
            }
            let (line, column) = e.span().map_or((1, 1), |s| self.line_column(s.start));
            ScenarioError::Input {
                file: self.path.clone(),
                line,
                column,
                key: None,
                message: e.message().to_string(),
            }
        })
    }

    /// 1-based line and column of byte offset `offset`.
    pub fn line_column(&self, offset: usize) -> (usize, usize) {
        let before = &self.text[..offset.min(self.text.len())];
        let line = before.matches('\n').count() + 1;
        let column = before
            .rfind('\n')
            .map_or(before.len(), |nl| before.len() - nl - 1)
            + 1;
        (line, column)
    }

    /// The key a span belongs to: the span itself if it is a key (as for an
    /// unknown field), else the key before `=` on the span's line.
    fn key_at(&self, span: &Range<usize>) -> Option<String> {
        let start = span.start.min(self.text.len());
        let line_start = self.text[..start].rfind('\n').map_or(0, |i| i + 1);
        let line_end = self.text[start..]
            .find('\n')
            .map_or(self.text.len(), |i| start + i);
        let line = &self.text[line_start..line_end];
        let eq = line.find('=')?;
        let key = line[..eq].trim();
        (!key.is_empty() && !key.starts_with('[')).then(|| key.to_string())
    }

    /// Where the key of the `key = value` whose value is at `value` starts
    /// (for messages about the key rather than its value): back over
    /// `=` and the key before it, in a table or an inline table alike.
    pub fn key_start(&self, value: Range<usize>) -> Range<usize> {
        let start = value.start.min(self.text.len());
        let before = self.text[..start].trim_end_matches([' ', '\t']);
        let Some(before_eq) = before.strip_suffix('=') else {
            return value;
        };
        let key_end = before_eq.trim_end_matches([' ', '\t']).len();
        let key_start = before_eq[..key_end]
            .rfind(|c: char| !(c.is_alphanumeric() || "_-.\"'".contains(c)))
            .map_or(0, |i| i + 1);
        key_start..value.end
    }

    /// An input error at `span` about `key`.
    pub fn error(
        &self,
        span: Range<usize>,
        key: impl Into<String>,
        message: impl Into<String>,
    ) -> ScenarioError {
        let (line, column) = self.line_column(span.start);
        ScenarioError::Input {
            file: self.path.clone(),
            line,
            column,
            key: Some(clipped(key.into())),
            message: message.into(),
        }
    }

    /// An input error about the file as a whole (reported at line 1).
    pub fn error_in_file(&self, message: impl Into<String>) -> ScenarioError {
        ScenarioError::Input {
            file: self.path.clone(),
            line: 1,
            column: 1,
            key: None,
            message: message.into(),
        }
    }

    /// Parses the file as TOML into `T`, turning syntax and schema errors
    /// (unknown keys, wrong types, missing keys) into located messages.
    pub fn parse_toml<T: DeserializeOwned>(&self) -> Result<T, ScenarioError> {
        toml::from_str(&self.text).map_err(|e| {
            if e.span().is_none() && e.message().contains("recursion limit") {
                return self.too_deep();
            }
            let span = e.span().unwrap_or(0..0);
            let (line, column) = self.line_column(span.start);
            let message = clipped(plain_serde(e.message().trim()));
            // serde names the key in "unknown field" messages already.
            let key = if message.starts_with("unknown field") {
                None
            } else {
                self.key_at(&span).map(clipped)
            };
            ScenarioError::Input {
                file: self.path.clone(),
                line,
                column,
                key,
                message,
            }
        })
    }

    /// The parser's nesting limit was hit (it gives no location): the
    /// error is put at the line with the most dots and brackets.
    fn too_deep(&self) -> ScenarioError {
        let depth = |l: &str| l.chars().filter(|c| ".[{".contains(*c)).count();
        let (index, line) = self
            .text
            .lines()
            .enumerate()
            .max_by_key(|(i, l)| (depth(l), std::cmp::Reverse(*i)))
            .unwrap_or((0, ""));
        let key = line.split('=').next().unwrap_or("").trim();
        ScenarioError::Input {
            file: self.path.clone(),
            line: index + 1,
            column: 1,
            key: (!key.is_empty()).then(|| clipped(key.to_string())),
            message: format!(
                "nested too deep for the parser ({} dots and brackets on this line); \
                 scenario keys nest at most 3 levels, e.g. [tessellation.grid]",
                depth(line)
            ),
        }
    }

    /// The value named by a keyword, or `default` if the key is absent.
    pub fn keyword<T: Copy>(
        &self,
        word: &Option<Spanned<String>>,
        key: &str,
        choices: &[(&str, T)],
        default: T,
    ) -> Result<T, ScenarioError> {
        let Some(w) = word else {
            return Ok(default);
        };
        choices
            .iter()
            .find(|(name, _)| *name == w.get_ref())
            .map(|&(_, value)| value)
            .ok_or_else(|| {
                let names: Vec<String> = choices
                    .iter()
                    .map(|(name, _)| format!("`{name}`"))
                    .collect();
                self.error(
                    w.span(),
                    key,
                    format!(
                        "unknown value `{}`, expected one of {}",
                        w.get_ref(),
                        names.join(", ")
                    ),
                )
            })
    }

    /// A finite number > 0.
    pub fn positive(&self, v: &Spanned<f64>, key: &str) -> Result<f64, ScenarioError> {
        let x = *v.get_ref();
        if x.is_finite() && x > 0.0 {
            Ok(x)
        } else {
            Err(self.error(
                v.span(),
                key,
                format!("must be a finite number > 0, got {}", short(x)),
            ))
        }
    }

    /// A finite number >= 0.
    pub fn non_negative(&self, v: &Spanned<f64>, key: &str) -> Result<f64, ScenarioError> {
        let x = *v.get_ref();
        if x.is_finite() && x >= 0.0 {
            Ok(x)
        } else {
            Err(self.error(
                v.span(),
                key,
                format!("must be a finite number >= 0, got {}", short(x)),
            ))
        }
    }

    /// A finite number in `[min, max]`, `unit` naming what it is in.
    pub fn in_range(
        &self,
        v: &Spanned<f64>,
        key: &str,
        (min, max): (f64, f64),
        unit: &str,
    ) -> Result<f64, ScenarioError> {
        let x = *v.get_ref();
        if x.is_finite() && x >= min && x <= max {
            Ok(x)
        } else {
            Err(self.error(
                v.span(),
                key,
                format!(
                    "must be a finite number in [{}, {}] {unit}, got {}",
                    short(min),
                    short(max),
                    short(x)
                ),
            ))
        }
    }

    /// A finite `[x, y]`.
    pub(crate) fn pair(
        &self,
        v: &Spanned<crate::exact::Exact<f64, 2>>,
        key: &str,
    ) -> Result<floe_dem::Vec2, ScenarioError> {
        let [x, y] = v.get_ref().0;
        if x.is_finite() && y.is_finite() {
            Ok(floe_dem::Vec2::new(x, y))
        } else {
            Err(self.error(
                v.span(),
                key,
                format!(
                    "must be finite, got {}",
                    crate::numbers::short_list(&[x, y])
                ),
            ))
        }
    }

    /// A finite number.
    pub fn finite(&self, v: &Spanned<f64>, key: &str) -> Result<f64, ScenarioError> {
        let x = *v.get_ref();
        if x.is_finite() {
            Ok(x)
        } else {
            Err(self.error(
                v.span(),
                key,
                format!("must be a finite number, got {}", short(x)),
            ))
        }
    }
}

/// serde's wording made plain: the number it quotes in short form
/// (`floating point `1e300``, not 301 digits) and `expected i64` as
/// `expected an integer`.
fn plain_serde(message: &str) -> String {
    let mut out = message
        .replace("expected i64", "expected an integer")
        .replace("expected u64", "expected an integer >= 0");
    let marker = "floating point `";
    if let Some(start) = out.find(marker).map(|i| i + marker.len()) {
        if let Some(len) = out[start..].find('`') {
            if let Ok(x) = out[start..start + len].parse::<f64>() {
                out.replace_range(start..start + len, &short(x));
            }
        }
    }
    out
}

/// A key (or message) as shown: one of thousands of parts is cut.
fn clipped(key: String) -> String {
    const MOST: usize = 200;
    if key.chars().count() <= MOST {
        return key;
    }
    let head: String = key.chars().take(MOST).collect();
    format!("{head}... ({} characters)", key.chars().count())
}

/// What a file that is not UTF-8 looks like, what to do, and whether that
/// is about the whole file (recognised by its first bytes) rather than
/// the first bad byte.
fn not_text(bytes: &[u8], at: usize) -> (String, bool) {
    if bytes.starts_with(b"\x89HDF\r\n\x1a\n") {
        let m = "this is an HDF5 file (a run file?), not a TOML text file; `floe info` describes run files";
        (m.into(), true)
    } else if bytes.starts_with(&[0x1f, 0x8b]) {
        (
            "this is a gzip-compressed file; decompress it first".into(),
            true,
        )
    } else if bytes.starts_with(&[0xff, 0xfe]) || bytes.starts_with(&[0xfe, 0xff]) {
        ("this is UTF-16 text; save the file as UTF-8".into(), true)
    } else {
        let m = format!(
            "byte 0x{:02x} is not UTF-8 (a Latin-1 or Windows-1252 file?); save the file as UTF-8",
            bytes[at]
        );
        (m, false)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn locates_lines_columns_and_keys() {
        let f = SourceFile {
            path: "p.toml".into(),
            text: "[a]\nx = 1\n  yy = -3\n".into(),
        };
        assert_eq!(f.line_column(0), (1, 1));
        assert_eq!(f.line_column(8), (2, 5));
        assert_eq!(f.line_column(17), (3, 8));
        assert_eq!(f.key_at(&(17..19)).as_deref(), Some("yy"));
        assert_eq!(f.key_at(&(0..3)), None);
    }
}
