#![no_main]
#[path = "../check.rs"]
mod check;
#[path = "../check_loop.rs"]
mod check_loop;
libfuzzer_sys::fuzz_target!(|data: &[u8]| {
    check_loop::check_loop(data);
});
