//! The `octs_index` target (octsolid_fuzz::targets) under libFuzzer: a panic is a finding, an
//! error is not.
#![no_main]

libfuzzer_sys::fuzz_target!(|data: &[u8]| {
    let target = octsolid_fuzz::targets::by_name("octs_index").expect("a target of that name");
    let _ = (target.run)(data);
});
