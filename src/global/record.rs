use serde::de::DeserializeOwned;
use serde::Serialize;

/// A value that a resumable sweep writes as JSON and reads back when it restarts: every type
/// that implements `Serialize` and `Deserialize` (see the [module docs](super)).
///
/// Reading back the record of `x` must give back `x`; the sweep runner passes every result
/// through its record even when it is not restarted ([`run_points`](super::run_points)), so a
/// lossy encoding cannot make a restarted run differ from an uninterrupted one.
pub trait Record: Serialize + DeserializeOwned {}

impl<T: Serialize + DeserializeOwned> Record for T {}

#[cfg(test)]
mod tests {
    use super::*;

    fn round_trip<T: Record + PartialEq + std::fmt::Debug>(v: T) {
        let text = serde_json::to_string(&v).unwrap();
        let back: T = serde_json::from_str(&text).unwrap();
        assert_eq!(back, v, "{text}");
    }

    #[test]
    fn standard_types_round_trip() {
        round_trip(0.1_f64);
        round_trip(u64::from(u32::MAX) * 1000);
        round_trip(17usize);
        round_trip(200u8);
        round_trip(true);
        round_trip("a \"b\" \n é ✓".to_string());
        round_trip(vec![[1.0, 2.0], [3.0, -0.0]]);
        round_trip(Some(vec![1u8, 2]));
        round_trip(None::<f64>);
    }

    #[test]
    fn shape_errors_name_the_place() {
        let e = serde_json::from_str::<Vec<[f64; 2]>>(r#"[[1, 2], [3, "x"]]"#).unwrap_err();
        assert!(e.to_string().contains("column 16"), "{e}");
        assert!(serde_json::from_str::<[f64; 2]>("[1, 2, 3]").is_err());
        assert!(serde_json::from_str::<u8>("256").is_err());
        assert!(serde_json::from_str::<u64>("1.5").is_err());
        // A non-finite number is written as `null`, which is not an f64.
        let nan = serde_json::to_string(&f64::NAN).unwrap();
        assert_eq!(nan, "null");
        assert!(serde_json::from_str::<f64>(&nan).is_err());
    }
}
