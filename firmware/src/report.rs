//! Measuring on the target: stack painting (the high-water mark).

const PAINT: u32 = 0xC0FF_EE55;
const PAINT_WORDS: usize = 8 * 1024; // 32 KiB below the current stack pointer

pub fn paint_stack() -> usize {
    let sp = cortex_m::register::msp::read() as usize;
    let bottom = sp - 256 - PAINT_WORDS * 4;
    for k in 0..PAINT_WORDS {
        // SAFETY: the words between `bottom` and `sp - 256` are unused stack in RAM
        unsafe { core::ptr::write_volatile((bottom + 4 * k) as *mut u32, PAINT) };
    }
    bottom
}

pub fn stack_used(bottom: usize, top: usize) -> usize {
    let mut k = 0;
    // SAFETY: reads back the words painted above
    while k < PAINT_WORDS
        && unsafe { core::ptr::read_volatile((bottom + 4 * k) as *const u32) } == PAINT
    {
        k += 1;
    }
    top - (bottom + 4 * k)
}
