//! The typed arithmetic's rules: what ADD/SUB store under the vendor's signed-overflow rule,
//! MUL's and DIV's results, and the execution errors that turn M8004 on.

use super::program::Ty;
use super::{ExecError, M8004, OpenNet};

impl OpenNet {
    /// Spec §5.4: what ADD/SUB store, and whether the result was out of range. Inlined: the
    /// fast loop calls it from another module.
    #[inline]
    pub fn store_add(ty: Ty, r: i64) -> (u32, bool) {
        let in_range = r >= ty.min() && r <= ty.max();
        let pattern = match ty {
            Ty::W => r.rem_euclid(1 << 16) as u32,
            Ty::D => r.rem_euclid(1 << 32) as u32,
            Ty::I if in_range => r as u16 as u32,
            Ty::L if in_range => r as u32,
            // Out of range: the sign of r, then r mod 2^15 / 2^31 (not two's complement).
            Ty::I => (u32::from(r < 0) << 15) | r.rem_euclid(1 << 15) as u32,
            Ty::L => (u32::from(r < 0) << 31) | r.rem_euclid(1 << 31) as u32,
        };
        (pattern, !in_range)
    }

    /// MUL's 32-bit result pattern, or None when D or L cannot hold the product.
    #[inline]
    pub(super) fn product(ty: Ty, x: i64, y: i64) -> Option<u32> {
        let p = i128::from(x) * i128::from(y);
        let fits = match ty {
            Ty::D => p <= i128::from(u32::MAX),
            Ty::L => (i128::from(i32::MIN)..=i128::from(i32::MAX)).contains(&p),
            _ => true,
        };
        fits.then_some(p as u32)
    }

    /// DIV's quotient and remainder (truncated toward zero; the remainder has the dividend's
    /// sign), or the error it raises.
    #[inline]
    pub(super) fn quotient(ty: Ty, x: i64, y: i64) -> Result<(i64, i64), &'static str> {
        if y == 0 {
            Err("divide_by_zero")
        } else if ty.signed() && x == ty.min() && y == -1 {
            Err("divide_overflow")
        } else {
            Ok((x / y, x % y))
        }
    }

    pub(super) fn record_error(&mut self, kind: &'static str) {
        self.record_error_at(self.pc as usize, kind);
    }

    #[inline]
    pub(super) fn record_error_at(&mut self, index: usize, kind: &'static str) {
        let line = self.program.instrs.get(index).map_or(0, |i| i.line);
        self.special[M8004] = true;
        self.error_count += 1;
        self.last_error = Some(ExecError {
            kind,
            line,
            tick: self.tick,
        });
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Every row of the vendor's storage table (spec §5.4).
    #[test]
    fn the_vendors_storage_table() {
        let rows: &[(Ty, i64, u32, bool)] = &[
            (Ty::W, 0, 0x0000, false),
            (Ty::W, 65535, 0xFFFF, false),
            (Ty::W, 131071, 0xFFFF, true),
            (Ty::W, -1, 0xFFFF, true),
            (Ty::W, -65535, 0x0001, true),
            (Ty::W, -65536, 0x0000, true),
            (Ty::I, 65534, 0x7FFE, true),
            (Ty::I, 32768, 0x0000, true),
            (Ty::I, 32767, 0x7FFF, false),
            (Ty::I, 0, 0x0000, false),
            (Ty::I, -1, 0xFFFF, false),
            (Ty::I, -32767, 0x8001, false),
            (Ty::I, -32768, 0x8000, false),
            (Ty::I, -32769, 0xFFFF, true),
            (Ty::I, -65535, 0x8001, true),
            (Ty::D, 0, 0, false),
            (Ty::D, 4294967295, 0xFFFF_FFFF, false),
            (Ty::D, 8589934591, 0xFFFF_FFFF, true),
            (Ty::D, -1, 0xFFFF_FFFF, true),
            (Ty::D, -4294967295, 0x0000_0001, true),
            (Ty::D, -4294967296, 0x0000_0000, true),
            (Ty::L, 4294967294, 0x7FFF_FFFE, true),
            (Ty::L, 2147483648, 0x0000_0000, true),
            (Ty::L, 2147483647, 0x7FFF_FFFF, false),
            (Ty::L, 0, 0, false),
            (Ty::L, -1, 0xFFFF_FFFF, false),
            (Ty::L, -2147483647, 0x8000_0001, false),
            (Ty::L, -2147483648, 0x8000_0000, false),
            (Ty::L, -2147483649, 0xFFFF_FFFF, true),
            (Ty::L, -4294967295, 0x8000_0001, true),
        ];
        for &(ty, r, stored, carry) in rows {
            assert_eq!(OpenNet::store_add(ty, r), (stored, carry), "{ty:?} {r}");
        }
    }
}
