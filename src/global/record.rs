//! [`Record`]: how a point, a result or an error is written to a sweep's folder and read back.

use super::json::{Json, JsonError};

/// A value that a resumable sweep writes as JSON and reads back when it restarts.
///
/// `from_json(&x.to_json())` must give back `x`; the sweep runner passes every result through
/// its record even when it is not restarted ([`run_points`](super::run_points)), so a lossy
/// encoding cannot make a restarted run differ from an uninterrupted one, but it would lose
/// information. Implemented here for numbers, strings, vectors, arrays and options; write
/// your own for your result types (see [`Attractor`](super::Attractor)'s for an example).
pub trait Record: Sized {
    /// The value as JSON.
    fn to_json(&self) -> Json;
    /// The value back from its JSON.
    ///
    /// # Errors
    /// [`JsonError::Shape`] if `json` is not what [`Record::to_json`] writes.
    fn from_json(json: &Json) -> Result<Self, JsonError>;
}

impl Record for f64 {
    fn to_json(&self) -> Json {
        Json::from(*self)
    }
    fn from_json(json: &Json) -> Result<Self, JsonError> {
        json.as_f64()
            .ok_or_else(|| JsonError::shape("", "a number", json))
    }
}

impl Record for u64 {
    fn to_json(&self) -> Json {
        Json::from(*self)
    }
    fn from_json(json: &Json) -> Result<Self, JsonError> {
        json.as_u64()
            .ok_or_else(|| JsonError::shape("", "a whole number >= 0", json))
    }
}

impl Record for usize {
    fn to_json(&self) -> Json {
        Json::from(*self)
    }
    fn from_json(json: &Json) -> Result<Self, JsonError> {
        json.as_u64()
            .and_then(|v| usize::try_from(v).ok())
            .ok_or_else(|| JsonError::shape("", "a whole number >= 0", json))
    }
}

impl Record for u8 {
    fn to_json(&self) -> Json {
        Json::from(u64::from(*self))
    }
    fn from_json(json: &Json) -> Result<Self, JsonError> {
        json.as_u64()
            .and_then(|v| u8::try_from(v).ok())
            .ok_or_else(|| JsonError::shape("", "a whole number in 0..=255", json))
    }
}

impl Record for bool {
    fn to_json(&self) -> Json {
        Json::Bool(*self)
    }
    fn from_json(json: &Json) -> Result<Self, JsonError> {
        match json {
            Json::Bool(b) => Ok(*b),
            _ => Err(JsonError::shape("", "true or false", json)),
        }
    }
}

impl Record for String {
    fn to_json(&self) -> Json {
        Json::String(self.clone())
    }
    fn from_json(json: &Json) -> Result<Self, JsonError> {
        json.as_str()
            .map(str::to_string)
            .ok_or_else(|| JsonError::shape("", "a string", json))
    }
}

impl<T: Record> Record for Vec<T> {
    fn to_json(&self) -> Json {
        Json::Array(self.iter().map(Record::to_json).collect())
    }
    fn from_json(json: &Json) -> Result<Self, JsonError> {
        let items = json
            .as_array()
            .ok_or_else(|| JsonError::shape("", "an array", json))?;
        items
            .iter()
            .enumerate()
            .map(|(i, v)| T::from_json(v).map_err(|e| nest(e, &format!("[{i}]"))))
            .collect()
    }
}

impl<T: Record, const N: usize> Record for [T; N] {
    fn to_json(&self) -> Json {
        Json::Array(self.iter().map(Record::to_json).collect())
    }
    fn from_json(json: &Json) -> Result<Self, JsonError> {
        let v = Vec::<T>::from_json(json)?;
        v.try_into()
            .map_err(|_| JsonError::shape("", "an array of the right length", json))
    }
}

impl<T: Record> Record for Option<T> {
    fn to_json(&self) -> Json {
        self.as_ref().map_or(Json::Null, Record::to_json)
    }
    fn from_json(json: &Json) -> Result<Self, JsonError> {
        match json {
            Json::Null => Ok(None),
            v => T::from_json(v).map(Some),
        }
    }
}

/// Prefixes the path of a shape error with `prefix` (a key or `[i]`).
pub(crate) fn nest(e: JsonError, prefix: &str) -> JsonError {
    match e {
        JsonError::Shape {
            path,
            expected,
            found,
        } => {
            let path = match (prefix.is_empty(), path.is_empty()) {
                (true, _) => path,
                (false, true) => prefix.to_string(),
                (false, false) if path.starts_with('[') => format!("{prefix}{path}"),
                (false, false) => format!("{prefix}.{path}"),
            };
            JsonError::Shape {
                path,
                expected,
                found,
            }
        }
        other => other,
    }
}

/// Reads field `key` of an object as a `T`, with the key in the error's path.
pub(crate) fn field<T: Record>(json: &Json, key: &'static str) -> Result<T, JsonError> {
    T::from_json(json.field(key)?).map_err(|e| nest(e, key))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn round_trip<T: Record + PartialEq + std::fmt::Debug>(v: T) {
        let text = v.to_json().to_string();
        let back = T::from_json(&Json::parse(&text).unwrap()).unwrap();
        assert_eq!(back, v, "{text}");
    }

    #[test]
    fn standard_types_round_trip() {
        round_trip(0.1_f64);
        round_trip(u64::from(u32::MAX) * 1000);
        round_trip(17usize);
        round_trip(200u8);
        round_trip(true);
        round_trip("a \"b\"".to_string());
        round_trip(vec![[1.0, 2.0], [3.0, -0.0]]);
        round_trip(Some(vec![1u8, 2]));
        round_trip(None::<f64>);
    }

    #[test]
    fn shape_errors_name_the_path() {
        let json = Json::parse(r#"[[1, 2], [3, "x"]]"#).unwrap();
        match Vec::<[f64; 2]>::from_json(&json) {
            Err(JsonError::Shape { path, .. }) => assert_eq!(path, "[1][1]"),
            other => panic!("{other:?}"),
        }
        let json = Json::parse(r#"[1, 2, 3]"#).unwrap();
        assert!(<[f64; 2]>::from_json(&json).is_err());
        assert!(u8::from_json(&Json::Number(256.0)).is_err());
        assert!(u64::from_json(&Json::Number(1.5)).is_err());
    }
}
