//! A small JSON value with an exact writer and a parser: the format of a sweep's records.
//!
//! Numbers are written in Rust's shortest round-trip form (`{:?}` of an `f64`: `0.1`,
//! `1e-7`, `-0.0`) and read back with the correctly rounded `str::parse`, so an `f64` survives
//! a write and a read **bit for bit**. JSON has no NaN or infinity: they are written as the
//! strings `"NaN"`, `"inf"` and `"-inf"`, which [`Json::as_f64`] reads back as numbers.
//! Objects keep their keys in the order written (a record is written the same way every
//! time, so equal records are equal text).

use std::fmt::{self, Write as _};

use thiserror::Error;

/// A JSON value.
#[derive(Debug, Clone, PartialEq)]
pub enum Json {
    /// `null`.
    Null,
    /// `true` or `false`.
    Bool(bool),
    /// A finite number (non-finite `f64`s are written as strings, see the [module docs](self)).
    Number(f64),
    /// A string.
    String(String),
    /// An array.
    Array(Vec<Json>),
    /// An object: `(key, value)` pairs in the order written.
    Object(Vec<(String, Json)>),
}

/// A text that is not the JSON the reader expected.
#[derive(Debug, Clone, PartialEq, Eq, Error)]
#[non_exhaustive]
pub enum JsonError {
    /// The text is not valid JSON (of the subset written here).
    #[error("invalid JSON at byte {at}: {what}")]
    Syntax {
        /// Byte offset of the problem.
        at: usize,
        /// What was expected.
        what: &'static str,
    },
    /// Valid JSON, but not the shape a record needs.
    #[error("unexpected JSON at `{path}`: expected {expected}, found {found}")]
    Shape {
        /// Where in the record (a key, or `[i]` for an array element).
        path: String,
        /// What the record needs there.
        expected: &'static str,
        /// What was found (a short excerpt).
        found: String,
    },
}

impl JsonError {
    /// A shape error at `path`.
    pub fn shape(path: impl Into<String>, expected: &'static str, found: &Json) -> Self {
        let mut text = found.to_string();
        if text.len() > 40 {
            let mut cut = 40;
            while !text.is_char_boundary(cut) {
                cut -= 1;
            }
            text.truncate(cut);
            text.push('…');
        }
        JsonError::Shape {
            path: path.into(),
            expected,
            found: text,
        }
    }
}

impl From<f64> for Json {
    /// A number; NaN and infinities become the strings `"NaN"`, `"inf"`, `"-inf"`.
    fn from(v: f64) -> Self {
        if v.is_finite() {
            Json::Number(v)
        } else if v.is_nan() {
            Json::String("NaN".into())
        } else if v > 0.0 {
            Json::String("inf".into())
        } else {
            Json::String("-inf".into())
        }
    }
}

impl From<usize> for Json {
    fn from(v: usize) -> Self {
        Json::Number(v as f64)
    }
}

impl From<u64> for Json {
    fn from(v: u64) -> Self {
        Json::Number(v as f64)
    }
}

impl From<bool> for Json {
    fn from(v: bool) -> Self {
        Json::Bool(v)
    }
}

impl From<&str> for Json {
    fn from(v: &str) -> Self {
        Json::String(v.to_string())
    }
}

impl From<String> for Json {
    fn from(v: String) -> Self {
        Json::String(v)
    }
}

impl<T: Into<Json>> From<Vec<T>> for Json {
    fn from(v: Vec<T>) -> Self {
        Json::Array(v.into_iter().map(Into::into).collect())
    }
}

impl Json {
    /// An object from `(key, value)` pairs, in that order.
    pub fn object<K: Into<String>, I: IntoIterator<Item = (K, Json)>>(pairs: I) -> Json {
        Json::Object(pairs.into_iter().map(|(k, v)| (k.into(), v)).collect())
    }

    /// The value under `key` of an object (`None` for a missing key or a non-object).
    pub fn get(&self, key: &str) -> Option<&Json> {
        match self {
            Json::Object(pairs) => pairs.iter().find(|(k, _)| k == key).map(|(_, v)| v),
            _ => None,
        }
    }

    /// The value under `key`, or a [`JsonError::Shape`] naming the missing key.
    ///
    /// # Errors
    /// If `self` is not an object or has no such key.
    pub fn field(&self, key: &'static str) -> Result<&Json, JsonError> {
        self.get(key)
            .ok_or_else(|| JsonError::shape(key, "a field with this key", self))
    }

    /// A number, or one of the strings `"NaN"`, `"inf"`, `"-inf"`.
    pub fn as_f64(&self) -> Option<f64> {
        match self {
            Json::Number(v) => Some(*v),
            Json::String(s) if s == "NaN" => Some(f64::NAN),
            Json::String(s) if s == "inf" => Some(f64::INFINITY),
            Json::String(s) if s == "-inf" => Some(f64::NEG_INFINITY),
            _ => None,
        }
    }

    /// A whole number in `0..=2^53` (exact in an `f64`).
    pub fn as_u64(&self) -> Option<u64> {
        match self {
            Json::Number(v) if *v >= 0.0 && *v <= 9_007_199_254_740_992.0 && v.fract() == 0.0 => {
                Some(*v as u64)
            }
            _ => None,
        }
    }

    /// A string.
    pub fn as_str(&self) -> Option<&str> {
        match self {
            Json::String(s) => Some(s),
            _ => None,
        }
    }

    /// An array's elements.
    pub fn as_array(&self) -> Option<&[Json]> {
        match self {
            Json::Array(a) => Some(a),
            _ => None,
        }
    }

    /// Appends the compact text of the value to `out` (no spaces, no line break).
    pub fn write_to(&self, out: &mut String) {
        match self {
            Json::Null => out.push_str("null"),
            Json::Bool(b) => out.push_str(if *b { "true" } else { "false" }),
            Json::Number(v) => write_number(*v, out),
            Json::String(s) => write_string(s, out),
            Json::Array(items) => {
                out.push('[');
                for (i, item) in items.iter().enumerate() {
                    if i > 0 {
                        out.push(',');
                    }
                    item.write_to(out);
                }
                out.push(']');
            }
            Json::Object(pairs) => {
                out.push('{');
                for (i, (k, v)) in pairs.iter().enumerate() {
                    if i > 0 {
                        out.push(',');
                    }
                    write_string(k, out);
                    out.push(':');
                    v.write_to(out);
                }
                out.push('}');
            }
        }
    }

    /// Parses one JSON value (surrounding white space allowed, nothing else after it).
    ///
    /// # Errors
    /// [`JsonError::Syntax`] with the byte offset of the first problem.
    pub fn parse(text: &str) -> Result<Json, JsonError> {
        let mut p = Parser {
            s: text.as_bytes(),
            i: 0,
            depth: 0,
        };
        let v = p.value()?;
        p.ws();
        if p.i != p.s.len() {
            return Err(p.err("end of input after the value"));
        }
        Ok(v)
    }
}

impl fmt::Display for Json {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let mut s = String::new();
        self.write_to(&mut s);
        f.write_str(&s)
    }
}

fn write_number(v: f64, out: &mut String) {
    if v.is_finite() {
        // `{:?}` is the shortest text that reads back to the same bits, and valid JSON for
        // finite values (`1.0`, `1e-7`, `-0.0`, `1e21`).
        let _ = write!(out, "{v:?}");
    } else {
        // Only reachable through `Json::Number(non-finite)` built by hand.
        Json::from(v).write_to(out);
    }
}

fn write_string(s: &str, out: &mut String) {
    out.push('"');
    for c in s.chars() {
        match c {
            '"' => out.push_str("\\\""),
            '\\' => out.push_str("\\\\"),
            '\n' => out.push_str("\\n"),
            '\r' => out.push_str("\\r"),
            '\t' => out.push_str("\\t"),
            c if (c as u32) < 0x20 => {
                let _ = write!(out, "\\u{:04x}", c as u32);
            }
            c => out.push(c),
        }
    }
    out.push('"');
}

/// Nesting deeper than this is refused (records are shallow; this bounds the recursion).
const MAX_DEPTH: usize = 64;

struct Parser<'a> {
    s: &'a [u8],
    i: usize,
    depth: usize,
}

impl Parser<'_> {
    fn err(&self, what: &'static str) -> JsonError {
        JsonError::Syntax { at: self.i, what }
    }

    fn ws(&mut self) {
        while let Some(b' ' | b'\t' | b'\n' | b'\r') = self.s.get(self.i) {
            self.i += 1;
        }
    }

    fn eat(&mut self, lit: &[u8], what: &'static str) -> Result<(), JsonError> {
        if self.s[self.i..].starts_with(lit) {
            self.i += lit.len();
            Ok(())
        } else {
            Err(self.err(what))
        }
    }

    fn value(&mut self) -> Result<Json, JsonError> {
        self.ws();
        match self.s.get(self.i) {
            None => Err(self.err("a value")),
            Some(b'n') => self.eat(b"null", "null").map(|_| Json::Null),
            Some(b't') => self.eat(b"true", "true").map(|_| Json::Bool(true)),
            Some(b'f') => self.eat(b"false", "false").map(|_| Json::Bool(false)),
            Some(b'"') => self.string().map(Json::String),
            Some(b'[') => self.nested(|p| p.array()),
            Some(b'{') => self.nested(|p| p.object()),
            Some(b'-' | b'0'..=b'9') => self.number(),
            Some(_) => Err(self.err("a value")),
        }
    }

    fn nested(
        &mut self,
        f: impl FnOnce(&mut Self) -> Result<Json, JsonError>,
    ) -> Result<Json, JsonError> {
        if self.depth >= MAX_DEPTH {
            return Err(self.err("nesting of at most 64 levels"));
        }
        self.depth += 1;
        let v = f(self);
        self.depth -= 1;
        v
    }

    fn number(&mut self) -> Result<Json, JsonError> {
        let start = self.i;
        while let Some(b'-' | b'+' | b'.' | b'e' | b'E' | b'0'..=b'9') = self.s.get(self.i) {
            self.i += 1;
        }
        let text = std::str::from_utf8(&self.s[start..self.i]).map_err(|_| self.err("a number"))?;
        match text.parse::<f64>() {
            Ok(v) if v.is_finite() => Ok(Json::Number(v)),
            _ => Err(JsonError::Syntax {
                at: start,
                what: "a finite number",
            }),
        }
    }

    fn hex4(&mut self) -> Result<u32, JsonError> {
        let digits = self
            .s
            .get(self.i..self.i + 4)
            .ok_or_else(|| self.err("four hex digits"))?;
        let text = std::str::from_utf8(digits).map_err(|_| self.err("four hex digits"))?;
        let v = u32::from_str_radix(text, 16).map_err(|_| self.err("four hex digits"))?;
        self.i += 4;
        Ok(v)
    }

    fn string(&mut self) -> Result<String, JsonError> {
        self.i += 1; // opening quote
        let mut out = String::new();
        loop {
            let start = self.i;
            while let Some(&b) = self.s.get(self.i) {
                if b == b'"' || b == b'\\' || b < 0x20 {
                    break;
                }
                self.i += 1;
            }
            let chunk =
                std::str::from_utf8(&self.s[start..self.i]).map_err(|_| self.err("UTF-8 text"))?;
            out.push_str(chunk);
            match self.s.get(self.i) {
                None => return Err(self.err("a closing quote")),
                Some(b'"') => {
                    self.i += 1;
                    return Ok(out);
                }
                Some(b'\\') => {
                    self.i += 1;
                    let Some(&e) = self.s.get(self.i) else {
                        return Err(self.err("an escape"));
                    };
                    self.i += 1;
                    match e {
                        b'"' => out.push('"'),
                        b'\\' => out.push('\\'),
                        b'/' => out.push('/'),
                        b'b' => out.push('\u{8}'),
                        b'f' => out.push('\u{c}'),
                        b'n' => out.push('\n'),
                        b'r' => out.push('\r'),
                        b't' => out.push('\t'),
                        b'u' => {
                            let hi = self.hex4()?;
                            let code = if (0xD800..0xDC00).contains(&hi) {
                                self.eat(b"\\u", "a low surrogate")?;
                                let lo = self.hex4()?;
                                if !(0xDC00..0xE000).contains(&lo) {
                                    return Err(self.err("a low surrogate"));
                                }
                                0x10000 + ((hi - 0xD800) << 10) + (lo - 0xDC00)
                            } else {
                                hi
                            };
                            out.push(char::from_u32(code).ok_or_else(|| self.err("a character"))?);
                        }
                        _ => return Err(self.err("a valid escape")),
                    }
                }
                Some(_) => return Err(self.err("no control character in a string")),
            }
        }
    }

    fn array(&mut self) -> Result<Json, JsonError> {
        self.i += 1;
        let mut items = Vec::new();
        self.ws();
        if self.s.get(self.i) == Some(&b']') {
            self.i += 1;
            return Ok(Json::Array(items));
        }
        loop {
            items.push(self.value()?);
            self.ws();
            match self.s.get(self.i) {
                Some(b',') => self.i += 1,
                Some(b']') => {
                    self.i += 1;
                    return Ok(Json::Array(items));
                }
                _ => return Err(self.err("`,` or `]`")),
            }
        }
    }

    fn object(&mut self) -> Result<Json, JsonError> {
        self.i += 1;
        let mut pairs = Vec::new();
        self.ws();
        if self.s.get(self.i) == Some(&b'}') {
            self.i += 1;
            return Ok(Json::Object(pairs));
        }
        loop {
            self.ws();
            if self.s.get(self.i) != Some(&b'"') {
                return Err(self.err("a key"));
            }
            let key = self.string()?;
            self.ws();
            self.eat(b":", "`:`")?;
            let v = self.value()?;
            pairs.push((key, v));
            self.ws();
            match self.s.get(self.i) {
                Some(b',') => self.i += 1,
                Some(b'}') => {
                    self.i += 1;
                    return Ok(Json::Object(pairs));
                }
                _ => return Err(self.err("`,` or `}`")),
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn numbers_round_trip_bit_for_bit() {
        let values = [
            0.0,
            -0.0,
            0.1,
            1.0 / 3.0,
            1e-300,
            5e-324,
            f64::MAX,
            -2.2348432771234567,
            1e21,
            123456789.0,
        ];
        for v in values {
            let text = Json::from(v).to_string();
            let back = Json::parse(&text).unwrap().as_f64().unwrap();
            assert_eq!(back.to_bits(), v.to_bits(), "{v:e} -> {text}");
        }
        for v in [f64::NAN, f64::INFINITY, f64::NEG_INFINITY] {
            let back = Json::parse(&Json::from(v).to_string())
                .unwrap()
                .as_f64()
                .unwrap();
            assert!(back.is_nan() == v.is_nan() && (back.is_nan() || back == v));
        }
    }

    #[test]
    fn nested_values_and_escapes_round_trip() {
        let v = Json::object([
            ("a", Json::from(vec![1.5, -2.0])),
            (
                "s",
                Json::from("quote \" back \\ nl \n tab \t bell \u{7} é ✓"),
            ),
            ("n", Json::Null),
            ("b", Json::Bool(false)),
            ("o", Json::object([("k", Json::Array(vec![]))])),
        ]);
        let text = v.to_string();
        assert!(!text.contains('\n'));
        assert_eq!(Json::parse(&text).unwrap(), v);
        assert_eq!(
            Json::parse(r#" { "x" : [ 1 , 2e3 , "\ud83d\ude00" ] } "#).unwrap(),
            Json::object([(
                "x",
                Json::Array(vec![
                    Json::Number(1.0),
                    Json::Number(2000.0),
                    Json::from("😀")
                ])
            )])
        );
    }

    #[test]
    fn bad_text_is_a_syntax_error_with_its_offset() {
        for (text, at) in [
            ("{\"index\":3,\"ok\":{\"p", 19),
            ("[1,2", 4),
            ("nul", 0),
            ("{\"a\" 1}", 5),
            ("1 2", 2),
            ("\"a\u{1}\"", 2),
            ("1e999", 0),
        ] {
            match Json::parse(text) {
                Err(JsonError::Syntax { at: a, .. }) => assert_eq!(a, at, "{text}"),
                other => panic!("{text}: {other:?}"),
            }
        }
        let deep = "[".repeat(100) + &"]".repeat(100);
        assert!(Json::parse(&deep).is_err());
    }
}
