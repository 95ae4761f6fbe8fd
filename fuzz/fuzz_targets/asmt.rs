//! Arbitrary bytes → the ASMT reader (tree, document, TimeSeries, expressions), the import to
//! cardan elements and the mechanism builder. Must never panic.
#![no_main]

use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    let Ok(text) = std::str::from_utf8(data) else {
        return;
    };
    let Ok((_doc, import)) = cardan_asmt::load(text) else {
        return;
    };
    let _ = import.builder().build();
});
