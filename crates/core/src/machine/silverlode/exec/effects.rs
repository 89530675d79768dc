//! What the register-only commands do to the registers alone (CLC, CLD/CLX, the queues), which
//! the full executor and the fast loop both run, and the divide they share.

use super::{Raise, flag_bits};
use crate::machine::silverlode::program::{ClcOp, ExtOp};
use crate::machine::silverlode::{FaultKind, Outcome, REGISTERS, RawQueue, hi, isw, lo, sx16};

/// `dividend / LO(word)` (`%` when `modulo`), the divisor sign-extended from 16 bits (spec §3);
/// `what` names the divisor in the fault of a 0 (or of −1 under i32::MIN).
#[inline]
fn divide(
    dividend: i32,
    word: i32,
    modulo: bool,
    what: impl FnOnce() -> String,
) -> Result<i32, Raise> {
    let divisor = sx16(lo(word));
    if divisor == 0 {
        return Err(Raise(
            FaultKind::DivideByZero,
            format!("divide by zero: the divisor {} is 0", what()),
        ));
    }
    if dividend == i32::MIN && divisor == -1 {
        return Err(Raise(
            FaultKind::DivideOverflow,
            format!("{dividend} / -1 does not fit in 32 bits"),
        ));
    }
    Ok(if modulo {
        dividend % divisor
    } else {
        dividend / divisor
    })
}

/// What a register-only command did: the values its explanation shows, whether it succeeded
/// (a flag-variant queue operation may not), and the flag bits it leaves.
pub(super) struct Effect {
    pub(super) vals: [i32; 4],
    pub(super) outcome: Outcome,
    pub(super) flags: u16,
}

impl Effect {
    #[inline(always)]
    fn value(vals: [i32; 4], v: i32) -> Effect {
        Effect {
            vals,
            outcome: Outcome::Done,
            flags: flag_bits(v),
        }
    }
}

/// A CLC command but SUB_TARGET, on the registers alone: the full executor and the fast loop
/// both run this. A fault leaves the registers untouched.
#[inline]
pub(super) fn clc_effect(
    regs: &mut [i32; REGISTERS],
    op: ClcOp,
    reg: usize,
) -> Result<Effect, Raise> {
    let acc = regs[10];
    let x = regs[reg];
    // (register written, value)
    let (dst, v) = match op {
        ClcOp::Clear => (reg, 0),
        ClcOp::Copy => (10, x),
        ClcOp::Save => (reg, acc),
        ClcOp::CopyRef | ClcOp::SaveRef => {
            if !(0..REGISTERS as i32).contains(&x) {
                return Err(Raise(
                    FaultKind::BadRegister,
                    format!("R{reg} = {x} does not name a register (0 ..= 199)"),
                ));
            }
            if op == ClcOp::CopyRef {
                (10, regs[x as usize])
            } else {
                (x as usize, acc)
            }
        }
        ClcOp::Abs => (reg, x.wrapping_abs()),
        ClcOp::Neg => (reg, x.wrapping_neg()),
        ClcOp::Inc => (reg, x.wrapping_add(1)),
        ClcOp::Dec => (reg, x.wrapping_sub(1)),
        ClcOp::Add => (10, acc.wrapping_add(x)),
        ClcOp::AddHi => (10, acc.wrapping_add(sx16(hi(x)))),
        ClcOp::AddLo => (10, acc.wrapping_add(sx16(lo(x)))),
        ClcOp::Sub => (10, acc.wrapping_sub(x)),
        ClcOp::SubRev => (10, x.wrapping_sub(acc)),
        ClcOp::MultS | ClcOp::MultU => (10, acc.wrapping_mul(x)),
        ClcOp::Div | ClcOp::Mod => (
            10,
            divide(acc, x, op == ClcOp::Mod, || {
                format!("LO(R{reg}) of 0x{:08X}", x as u32)
            })?,
        ),
        ClcOp::Max => (10, acc.max(x)),
        ClcOp::Min => (10, acc.min(x)),
        ClcOp::And => (10, acc & x),
        ClcOp::Or => (10, acc | x),
        ClcOp::Xor => (10, acc ^ x),
        ClcOp::Shl => (reg, x.wrapping_shl(1)),
        ClcOp::ShrS => (reg, x >> 1),
        ClcOp::ShrU => (reg, (x as u32 >> 1) as i32),
        ClcOp::CopyWordHiAcc => (10, lo(x) << 16 | lo(acc)),
        ClcOp::CopyWordHiReg => (reg, lo(acc) << 16 | lo(x)),
        ClcOp::CopyWordLoReg => (reg, (x as u32 & 0xFFFF_0000) as i32 | lo(acc)),
        ClcOp::SextHi => (10, sx16(hi(x))),
        ClcOp::SextLo => (10, sx16(lo(x))),
        // Moves the zero point: the executor's own (`SilverLode::clc`).
        ClcOp::SubTarget => {
            return Err(Raise(
                FaultKind::BadRegister,
                "SUB_TARGET moves the motion model".to_string(),
            ));
        }
    };
    regs[dst] = v;
    Ok(Effect::value([acc, x, v, 0], v))
}

/// A CLD/CLX command but Q_INIT, on the registers alone: the full executor and the fast loop
/// both run this. A fault leaves the registers untouched.
#[inline]
pub(super) fn ext_effect(
    regs: &mut [i32; REGISTERS],
    op: ExtOp,
    res: usize,
    reg1: usize,
    d: i32,
) -> Result<Effect, Raise> {
    let a = regs[reg1];
    let v = match op {
        ExtOp::Copy => a,
        ExtOp::Abs => a.wrapping_abs(),
        ExtOp::Neg => a.wrapping_neg(),
        ExtOp::Add => a.wrapping_add(d),
        ExtOp::Sub => a.wrapping_sub(d),
        ExtOp::SubRev => d.wrapping_sub(a),
        ExtOp::AddHi => sx16(hi(a)).wrapping_add(d),
        ExtOp::AddLo => sx16(lo(a)).wrapping_add(d),
        ExtOp::And => a & d,
        ExtOp::Or => a | d,
        ExtOp::Xor => a ^ d,
        ExtOp::Max => a.max(d),
        ExtOp::Min => a.min(d),
        ExtOp::SextHi => sx16(hi(a)),
        ExtOp::SextLo => sx16(lo(a)),
        ExtOp::PackLoLo => lo(a) << 16 | lo(d),
        ExtOp::PackHiLo => hi(a) << 16 | lo(d),
        ExtOp::PackHiHi => hi(a) << 16 | hi(d),
        ExtOp::MultS | ExtOp::MultU => a.wrapping_mul(d),
        ExtOp::MultS64Shr16 => ((i64::from(a) * i64::from(d)) >> 16) as i32,
        ExtOp::Div | ExtOp::Mod => divide(a, d, op == ExtOp::Mod, || {
            format!("LO(data) of 0x{:08X}", d as u32)
        })?,
        ExtOp::DivRev | ExtOp::ModRev => divide(d, a, op == ExtOp::ModRev, || {
            format!("LO(R{reg1}) of 0x{:08X}", a as u32)
        })?,
        ExtOp::MultU64 => {
            if res >= REGISTERS - 1 {
                return Err(Raise(
                    FaultKind::BadRegister,
                    "MULT_U64 needs two result registers; R199 has no R200 after it".to_string(),
                ));
            }
            let p = u64::from(a as u32) * u64::from(d as u32);
            regs[res + 1] = p as i32;
            regs[res] = (p >> 32) as i32;
            return Ok(Effect {
                vals: [a, d, (p >> 32) as i32, p as i32],
                outcome: Outcome::Done,
                flags: if p == 0 { isw::ZERO } else { isw::POSITIVE },
            });
        }
        ExtOp::DivU64 => {
            if reg1 >= REGISTERS - 1 {
                return Err(Raise(
                    FaultKind::BadRegister,
                    "DIV_U64 reads a register pair; R199 has no R200 after it".to_string(),
                ));
            }
            let low = regs[reg1 + 1];
            let n = u64::from(a as u32) << 32 | u64::from(low as u32);
            let divisor = u64::from(d as u32);
            if divisor == 0 {
                return Err(Raise(
                    FaultKind::DivideByZero,
                    "divide by zero: the 32-bit divisor is 0".to_string(),
                ));
            }
            let q = n / divisor;
            if q > u64::from(u32::MAX) {
                return Err(Raise(
                    FaultKind::DivideOverflow,
                    format!("{n} / {divisor} = {q} does not fit in 32 bits"),
                ));
            }
            regs[res] = q as i32;
            return Ok(Effect {
                vals: [a, low, d, q as i32],
                outcome: Outcome::Done,
                flags: if q == 0 { isw::ZERO } else { isw::POSITIVE },
            });
        }
        _ => return queue_effect(regs, op, res, reg1, d),
    };
    regs[res] = v;
    Ok(Effect::value([a, d, v, 0], v))
}

/// A queue operation but Q_INIT (spec §4).
fn queue_effect(
    regs: &mut [i32; REGISTERS],
    op: ExtOp,
    res: usize,
    base: usize,
    d: i32,
) -> Result<Effect, Raise> {
    let before = [regs[base], regs.get(base + 1).copied().unwrap_or(0)];
    let Some(mut q) = RawQueue::decode(regs, base) else {
        return Err(Raise(
            FaultKind::BadQueue,
            format!(
                "R{base} does not hold a valid queue header (size|len = 0x{:08X}, head|tail = 0x{:08X})",
                before[0] as u32, before[1] as u32
            ),
        ));
    };
    let slot0 = base + 2;
    let full = q.len == q.size;
    let empty = q.len == 0;
    let fail = |kind: FaultKind, what: &str| {
        Err(Raise(
            kind,
            format!(
                "queue at R{base} is {what} ({} of {} slots used)",
                q.len, q.size
            ),
        ))
    };
    let result = match op {
        ExtOp::QPushHeadErr if full => return fail(FaultKind::QueueFull, "full"),
        ExtOp::QPushTailErr if full => return fail(FaultKind::QueueFull, "full"),
        ExtOp::QPopHeadErr | ExtOp::QPopTailErr if empty => {
            return fail(FaultKind::QueueEmpty, "empty");
        }
        ExtOp::QPushHead | ExtOp::QPushTail if full => None,
        ExtOp::QPopHead | ExtOp::QPopTail if empty => None,
        ExtOp::QPushHead | ExtOp::QPushHeadErr => {
            regs[slot0 + q.head as usize] = d;
            q.head = (q.head + 1) % q.size;
            q.len += 1;
            Some((q.size - q.len) as i32)
        }
        ExtOp::QPushTail | ExtOp::QPushTailErr => {
            q.tail = (q.tail + q.size - 1) % q.size;
            regs[slot0 + q.tail as usize] = d;
            q.len += 1;
            Some((q.size - q.len) as i32)
        }
        ExtOp::QPopHead | ExtOp::QPopHeadErr => {
            q.head = (q.head + q.size - 1) % q.size;
            q.len -= 1;
            Some(regs[slot0 + q.head as usize])
        }
        ExtOp::QPopTail | ExtOp::QPopTailErr => {
            let v = regs[slot0 + q.tail as usize];
            q.tail = (q.tail + 1) % q.size;
            q.len -= 1;
            Some(v)
        }
        _ => {
            // Q_READ: 0 ..< len from the head (0 = newest), -1 ..= -len from the tail.
            let n = i64::from(d);
            let (size, len) = (i64::from(q.size), i64::from(q.len));
            let slot = if n >= 0 && n < len {
                Some((i64::from(q.head) - 1 - n).rem_euclid(size))
            } else if n < 0 && -n <= len {
                Some((i64::from(q.tail) - 1 - n).rem_euclid(size))
            } else {
                None
            };
            slot.map(|s| regs[slot0 + s as usize])
        }
    };
    Ok(match result {
        Some(value) => {
            if op != ExtOp::QRead {
                let (h0, h1) = q.encode();
                regs[base] = h0;
                regs[base + 1] = h1;
            }
            regs[res] = value;
            Effect {
                vals: [before[0], before[1], d, value],
                outcome: Outcome::Done,
                flags: isw::ZERO,
            }
        }
        None => Effect {
            vals: [before[0], before[1], d, 0],
            outcome: Outcome::Failed,
            flags: isw::NEGATIVE,
        },
    })
}
