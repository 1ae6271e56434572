//! The settings file: any bytes are read as settings or refused with a reason, never a panic;
//! what is accepted validates, and saves and reads back the same.
#![no_main]

use libfuzzer_sys::fuzz_target;
use vr_ocean::ui::Settings;

fuzz_target!(|data: &[u8]| {
    let Ok(text) = std::str::from_utf8(data) else {
        return;
    };
    if let Ok(s) = Settings::from_json(text) {
        assert!(s.validate().is_ok());
        let again = Settings::from_json(&s.to_json()).expect("a saved file reads back");
        assert_eq!(again, s);
    }
});
