//! The simulated sensor board behind `embedded_hal::i2c::I2c`, and its driver: a board's HAL
//! drops in for `SimBoard`.

use core::convert::Infallible;
use embedded_hal::i2c::{I2c, Operation};

/// The simulated sensor board: an I2C target with a register map.
/// `0x00..0x0c`: gyro rate (x, y, z) as little-endian f32, body frame, rad/s;
/// `0x10..0x20`: star tracker quaternion (w, x, y, z) body to space, f32;
/// `0x20`: status, bit 0 = a new star tracker fix since the last read of `0x10`.
pub struct SimBoard {
    regs: [u8; 0x24],
    pointer: usize,
}

pub const BOARD_ADDR: u8 = 0x68;

impl SimBoard {
    pub fn new() -> Self {
        Self {
            regs: [0; 0x24],
            pointer: 0,
        }
    }
    fn put(&mut self, at: usize, v: f32) {
        self.regs[at..at + 4].copy_from_slice(&v.to_le_bytes());
    }
    pub fn set_gyro(&mut self, w: [f32; 3]) {
        self.put(0x00, w[0]);
        self.put(0x04, w[1]);
        self.put(0x08, w[2]);
    }
    pub fn set_star(&mut self, q: [f32; 4]) {
        self.put(0x10, q[0]);
        self.put(0x14, q[1]);
        self.put(0x18, q[2]);
        self.put(0x1c, q[3]);
        self.regs[0x20] |= 1;
    }
}

impl embedded_hal::i2c::ErrorType for SimBoard {
    type Error = Infallible;
}

impl I2c for SimBoard {
    fn transaction(
        &mut self,
        _address: u8,
        operations: &mut [Operation<'_>],
    ) -> Result<(), Infallible> {
        for op in operations {
            match op {
                Operation::Write(bytes) => {
                    if let Some(&r) = bytes.first() {
                        self.pointer = r as usize;
                    }
                }
                Operation::Read(buf) => {
                    let start = self.pointer.min(self.regs.len());
                    let end = (start + buf.len()).min(self.regs.len());
                    buf[..end - start].copy_from_slice(&self.regs[start..end]);
                    if start <= 0x10 && end > 0x10 {
                        self.regs[0x20] &= !1;
                    }
                    self.pointer = end;
                }
            }
        }
        Ok(())
    }
}

/// The sensor driver, generic over any `embedded-hal` I2C bus.
pub struct Sensors<B> {
    pub bus: B,
}

impl<B: I2c> Sensors<B> {
    fn f32s<const N: usize>(&mut self, reg: u8) -> Result<[f32; N], B::Error> {
        let mut raw = [0u8; 16];
        self.bus.write_read(BOARD_ADDR, &[reg], &mut raw[..4 * N])?;
        let mut out = [0.0f32; N];
        for (k, o) in out.iter_mut().enumerate() {
            *o = f32::from_le_bytes([raw[4 * k], raw[4 * k + 1], raw[4 * k + 2], raw[4 * k + 3]]);
        }
        Ok(out)
    }
    pub fn gyro(&mut self) -> Result<[f32; 3], B::Error> {
        self.f32s(0x00)
    }
    /// A new star tracker fix, if there is one.
    #[inline(never)]
    pub fn star(&mut self) -> Result<Option<[f32; 4]>, B::Error> {
        let mut status = [0u8];
        self.bus.write_read(BOARD_ADDR, &[0x20], &mut status)?;
        if status[0] & 1 == 0 {
            return Ok(None);
        }
        self.f32s(0x10).map(Some)
    }
}
