//! Parameter sets serialize and read back unchanged (feature `serde`).
#![cfg(feature = "serde")]

use jeffcott::params::{Params, Preset, Scales};

#[test]
fn params_round_trip_through_json() {
    for preset in Preset::ALL {
        let p = preset.params();
        let text = serde_json::to_string(&p).unwrap();
        let back: Params = serde_json::from_str(&text).unwrap();
        assert_eq!(p, back, "{preset}: {text}");
    }
    let scales = Scales {
        rotor_mass: 12.0,
        rotor_stiffness: 3.0e5,
        gap: 2.0e-4,
        unbalance_radius: 0.05,
    };
    let d = Preset::Fig8b.params().to_dimensional(&scales).unwrap();
    let text = serde_json::to_string(&d).unwrap();
    assert_eq!(
        serde_json::from_str::<jeffcott::params::DimensionalParams>(&text).unwrap(),
        d
    );
}
