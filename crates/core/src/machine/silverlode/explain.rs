//! The last command in words, with its operand values: built only when a view asks, from the
//! command and the few words the executor recorded, so running costs no formatting.

use super::program::{ClcOp, ExtOp, Instr, MoveKind};
use super::{Outcome, SilverLode, TICK_MICROS};

fn hex(v: i32) -> String {
    format!("0x{:08X}", v as u32)
}

use super::{RawQueue, hi, lo, sx16};
use crate::machine::value::{q16, remainder_note, wrap_note};

pub fn explain(m: &SilverLode) -> Option<String> {
    let last = m.s.last;
    let instr = *m.program.instrs.get(last.pc as usize)?;
    if last.outcome == Outcome::Faulted {
        let fault = m.s.fault.as_ref()?;
        return Some(format!(
            "command error ({}): {}",
            fault.kind.code(),
            fault.message
        ));
    }
    let [v0, v1, v2, v3] = last.vals;
    let target_name = |t: u32| -> String {
        let line = m.program.lines.get(t as usize);
        match (m.program.label_at(t), line) {
            (Some(label), Some(line)) => format!("{label} (line {line})"),
            (None, Some(line)) => format!("line {line}"),
            _ => "the end of the program".to_string(),
        }
    };
    Some(match instr {
        Instr::Clc { op, reg } => clc(op, reg, v0, v1, v2, v3),
        Instr::Cld {
            op,
            res,
            reg1,
            data,
            ..
        } => ext(op, res, reg1, &data.to_string(), last.outcome, last.vals),
        Instr::Clx {
            op,
            res,
            reg1,
            reg2,
            ..
        } => ext(op, res, reg1, &format!("R{reg2}"), last.outcome, last.vals),
        Instr::Wrp { reg, value } => format!("R{reg} = {value} (was {v0})"),
        Instr::Jmp { target, cond: None } => format!("jump to {}", target_name(target)),
        Instr::Jmp {
            target,
            cond: Some(c),
        } => {
            if v0 != 0 {
                format!("{c} holds: jump to {}", target_name(target))
            } else {
                format!("{c} does not hold: no jump, continue on the next line")
            }
        }
        Instr::Call { target } => format!(
            "call {}; return to {}; stack depth {} → {}",
            target_name(target),
            target_name(last.pc + 1),
            v0,
            v0 + 1
        ),
        Instr::Ret => {
            let back = (v0 as usize)
                .checked_sub(1)
                .and_then(|i| m.s.stack.get(i).copied())
                .unwrap_or(0);
            format!(
                "return to {}; stack depth {} → {}",
                target_name(back),
                v0,
                v0 - 1
            )
        }
        Instr::Dly { ticks } => format!(
            "wait {ticks} ticks ({:.3} ms), then set DELAY_DONE",
            f64::from(ticks.max(1)) * f64::from(TICK_MICROS) / 1000.0
        ),
        Instr::Wbs { cond } => {
            if v0 != 0 {
                format!("wait until {cond}: it already holds")
            } else {
                format!("wait until {cond} (checked every tick)")
            }
        }
        Instr::Cer { target: Some(t) } => {
            format!(
                "on a command error, jump to {} instead of stopping",
                target_name(t)
            )
        }
        Instr::Cer { target: None } => "on a command error, stop the program".to_string(),
        Instr::End => "end of program: PSW bit 13 (program done) set".to_string(),
        Instr::Move {
            kind,
            accel,
            vel,
            cond,
            pos,
        } => {
            let how = match kind {
                MoveKind::Mav => format!("to {v1}"),
                MoveKind::Mrv => format!("by {v2} to {v1}"),
                MoveKind::Rav => format!("to R{pos} = {v1}"),
                MoveKind::Rrv => format!("by R{pos} = {v2} to {v1}"),
            };
            let counts_per_s = f64::from(vel as u32) / 67_108_864.0 * 1e6 / f64::from(TICK_MICROS);
            let stop = cond.map(|c| format!(", stop when {c}")).unwrap_or_default();
            format!(
                "{}: move target from {v0} {how} (accel {}, vel {} ≈ {counts_per_s:.0} counts/s){stop}",
                kind.name(),
                accel as u32,
                vel as u32
            )
        }
        Instr::Ztp => {
            format!("R0 = R1 = 0 (target was {v0}, actual {v1}; the motor does not move)")
        }
        Instr::Ttp => format!("R0 = R1 = {v1} (target was {v0})"),
    })
}

fn clc(op: ClcOp, reg: u8, acc: i32, x: i32, res: i32, extra: i32) -> String {
    format!(
        "{}{}",
        clc_formula(op, reg, acc, x, res, extra),
        clc_note(op, acc, x, res)
    )
}

/// What a CLC result lost: a wrap past 32 bits, a bit shifted out, a discarded remainder.
fn clc_note(op: ClcOp, acc: i32, x: i32, res: i32) -> String {
    let (acc, x128) = (i128::from(acc), i128::from(x));
    let divisor = i128::from(sx16(lo(x)));
    let res64 = i64::from(res);
    match op {
        ClcOp::Abs => wrap_note(x128.abs(), res64),
        ClcOp::Neg => wrap_note(-x128, res64),
        ClcOp::Inc => wrap_note(x128 + 1, res64),
        ClcOp::Dec => wrap_note(x128 - 1, res64),
        ClcOp::Add => wrap_note(acc + x128, res64),
        ClcOp::AddHi => wrap_note(acc + i128::from(sx16(hi(x))), res64),
        ClcOp::AddLo => wrap_note(acc + i128::from(sx16(lo(x))), res64),
        ClcOp::Sub => wrap_note(acc - x128, res64),
        ClcOp::SubRev => wrap_note(x128 - acc, res64),
        ClcOp::MultS => wrap_note(acc * x128, res64),
        ClcOp::MultU => wrap_note(
            i128::from(acc as u32) * i128::from(x as u32),
            i64::from(res as u32),
        ),
        ClcOp::Div if divisor != 0 => remainder_note(acc % divisor),
        ClcOp::Shl if x < 0 => " — bit 31 (1) was shifted out".to_string(),
        ClcOp::Shl if (x ^ res) < 0 => " — the sign changed: bit 30 moved into bit 31".to_string(),
        ClcOp::ShrS | ClcOp::ShrU if x & 1 == 1 => " — bit 0 (1) was shifted out".to_string(),
        ClcOp::SubTarget => wrap_note(acc - x128, res64),
        _ => String::new(),
    }
}

fn clc_formula(op: ClcOp, reg: u8, acc: i32, x: i32, res: i32, extra: i32) -> String {
    let r = format!("R{reg}");
    match op {
        ClcOp::Clear => format!("{r} = 0"),
        ClcOp::Copy => format!("R10 = {r} = {x}"),
        ClcOp::Save => format!("{r} = R10 = {acc}"),
        ClcOp::CopyRef => format!("R10 = R[{r}] = R{x} = {res}"),
        ClcOp::SaveRef => format!("R[{r}] = R10: R{x} = {acc}"),
        ClcOp::Abs => format!("{r} = |{r}| = |{x}| = {res}"),
        ClcOp::Neg => format!("{r} = -{r} = -({x}) = {res}"),
        ClcOp::Inc => format!("{r} = {r} + 1 = {x} + 1 = {res}"),
        ClcOp::Dec => format!("{r} = {r} - 1 = {x} - 1 = {res}"),
        ClcOp::Add => format!("R10 = R10 + {r} = {acc} + {x} = {res}"),
        ClcOp::AddHi => format!(
            "R10 = R10 + sx16(HI({r})) = {acc} + sx16({}) = {acc} + {} = {res}",
            hex(x),
            sx16(hi(x))
        ),
        ClcOp::AddLo => format!(
            "R10 = R10 + sx16(LO({r})) = {acc} + sx16({}) = {acc} + {} = {res}",
            hex(x),
            sx16(lo(x))
        ),
        ClcOp::Sub => format!("R10 = R10 - {r} = {acc} - {x} = {res}"),
        ClcOp::SubRev => format!("R10 = {r} - R10 = {x} - {acc} = {res}"),
        ClcOp::MultS => format!("R10 = R10 × {r} = {acc} × {x} = {res} (low 32 bits, signed)"),
        ClcOp::MultU => format!(
            "R10 = R10 × {r} = {} × {} = {} (low 32 bits, unsigned)",
            acc as u32, x as u32, res as u32
        ),
        ClcOp::Div => format!(
            "R10 = R10 / sx16(LO({r})) = {acc} / {} = {res} (truncated toward zero)",
            sx16(lo(x))
        ),
        ClcOp::Mod => format!(
            "R10 = R10 % sx16(LO({r})) = {acc} % {} = {res}",
            sx16(lo(x))
        ),
        ClcOp::Max => format!("R10 = max(R10, {r}) = max({acc}, {x}) = {res}"),
        ClcOp::Min => format!("R10 = min(R10, {r}) = min({acc}, {x}) = {res}"),
        ClcOp::And => format!(
            "R10 = R10 AND {r} = {} AND {} = {}",
            hex(acc),
            hex(x),
            hex(res)
        ),
        ClcOp::Or => format!(
            "R10 = R10 OR {r} = {} OR {} = {}",
            hex(acc),
            hex(x),
            hex(res)
        ),
        ClcOp::Xor => format!(
            "R10 = R10 XOR {r} = {} XOR {} = {}",
            hex(acc),
            hex(x),
            hex(res)
        ),
        ClcOp::Shl => format!("{r} = {r} << 1 = {} << 1 = {}", hex(x), hex(res)),
        ClcOp::ShrS => format!(
            "{r} = {r} >> 1 (sign kept) = {} >> 1 = {}",
            hex(x),
            hex(res)
        ),
        ClcOp::ShrU => format!("{r} = {r} >> 1 (zero in) = {} >> 1 = {}", hex(x), hex(res)),
        ClcOp::CopyWordHiAcc => format!(
            "HI(R10) = LO({r}): LO({r}) = 0x{:04X}, R10 {} → {}",
            lo(x),
            hex(acc),
            hex(res)
        ),
        ClcOp::CopyWordHiReg => format!(
            "HI({r}) = LO(R10): LO(R10) = 0x{:04X}, {r} {} → {}",
            lo(acc),
            hex(x),
            hex(res)
        ),
        ClcOp::CopyWordLoReg => format!(
            "LO({r}) = LO(R10): LO(R10) = 0x{:04X}, {r} {} → {}",
            lo(acc),
            hex(x),
            hex(res)
        ),
        ClcOp::SextHi => format!(
            "R10 = sx16(HI({r})) = sx16(0x{:04X}) = {} = {res}",
            hi(x),
            hex(res)
        ),
        ClcOp::SextLo => format!(
            "R10 = sx16(LO({r})) = sx16(0x{:04X}) = {} = {res}",
            lo(x),
            hex(res)
        ),
        ClcOp::SubTarget => format!(
            "R0 = R0 - {r} = {acc} - {x} = {res}; R1 = R1 - {r} = {extra} - {x} = {} (the motor does not move)",
            extra.wrapping_sub(x)
        ),
    }
}

fn ext(op: ExtOp, res: u8, reg1: u8, d_name: &str, outcome: Outcome, vals: [i32; 4]) -> String {
    let text = ext_formula(op, res, reg1, d_name, outcome, vals);
    if op.is_queue() {
        return text;
    }
    format!("{text}{}", ext_note(op, vals))
}

/// What a CLD/CLX result lost: a wrap past 32 bits, the fraction a Q16.16 shift drops, a
/// discarded remainder.
fn ext_note(op: ExtOp, [a, d, v, _]: [i32; 4]) -> String {
    let (a128, d128, v64) = (i128::from(a), i128::from(d), i64::from(v));
    let exact_div = |n: i128, divisor: i128| {
        if divisor == 0 {
            String::new()
        } else {
            remainder_note(n % divisor)
        }
    };
    match op {
        ExtOp::Abs => wrap_note(a128.abs(), v64),
        ExtOp::Neg => wrap_note(-a128, v64),
        ExtOp::Add => wrap_note(a128 + d128, v64),
        ExtOp::Sub => wrap_note(a128 - d128, v64),
        ExtOp::SubRev => wrap_note(d128 - a128, v64),
        ExtOp::AddHi => wrap_note(i128::from(sx16(hi(a))) + d128, v64),
        ExtOp::AddLo => wrap_note(i128::from(sx16(lo(a))) + d128, v64),
        ExtOp::MultS => wrap_note(a128 * d128, v64),
        ExtOp::MultU => wrap_note(
            i128::from(a as u32) * i128::from(d as u32),
            i64::from(v as u32),
        ),
        ExtOp::MultS64Shr16 => {
            let product = a128 * d128;
            // The shift is arithmetic: it rounds toward minus infinity, dropping product mod 2^16.
            let dropped = product.rem_euclid(65536) as i64;
            let exact = product >> 16;
            let mut note = String::new();
            if dropped != 0 {
                note = format!(" — {} dropped by the shift", q16(dropped));
            }
            if exact != i128::from(v) {
                note.push_str(&format!(
                    " — overflow: (a × d) >> 16 = {exact} does not fit 32 bits; bits 47..16 kept = {v}"
                ));
            }
            note
        }
        ExtOp::Div => exact_div(a128, i128::from(sx16(lo(d)))),
        ExtOp::DivRev => exact_div(d128, i128::from(sx16(lo(a)))),
        // vals: upper, lower, divisor, quotient.
        ExtOp::DivU64 => {
            let n = i128::from(u64::from(a as u32) << 32 | u64::from(d as u32));
            exact_div(n, i128::from(v as u32))
        }
        _ => String::new(),
    }
}

fn ext_formula(
    op: ExtOp,
    res: u8,
    reg1: u8,
    d_name: &str,
    outcome: Outcome,
    vals: [i32; 4],
) -> String {
    let [a, d, v, extra] = vals;
    let r1 = format!("R{reg1}");
    let out = format!("R{res}");
    if op.is_queue() {
        return queue(op, res, reg1, d_name, outcome, vals);
    }
    // (formula with names, formula with values, result text)
    let (sym, val, result) = match op {
        ExtOp::Copy => (r1.clone(), a.to_string(), v.to_string()),
        ExtOp::Abs => (format!("|{r1}|"), format!("|{a}|"), v.to_string()),
        ExtOp::Neg => (format!("-{r1}"), format!("-({a})"), v.to_string()),
        ExtOp::Add => (
            format!("{r1} + {d_name}"),
            format!("{a} + {d}"),
            v.to_string(),
        ),
        ExtOp::Sub => (
            format!("{r1} - {d_name}"),
            format!("{a} - {d}"),
            v.to_string(),
        ),
        ExtOp::SubRev => (
            format!("{d_name} - {r1}"),
            format!("{d} - {a}"),
            v.to_string(),
        ),
        ExtOp::AddHi => (
            format!("sx16(HI({r1})) + {d_name}"),
            format!("{} + {d}", sx16(hi(a))),
            v.to_string(),
        ),
        ExtOp::AddLo => (
            format!("sx16(LO({r1})) + {d_name}"),
            format!("{} + {d}", sx16(lo(a))),
            v.to_string(),
        ),
        ExtOp::And | ExtOp::Or | ExtOp::Xor => {
            let word = match op {
                ExtOp::And => "AND",
                ExtOp::Or => "OR",
                _ => "XOR",
            };
            (
                format!("{r1} {word} {d_name}"),
                format!("{} {word} {}", hex(a), hex(d)),
                hex(v),
            )
        }
        ExtOp::Max => (
            format!("max({r1}, {d_name})"),
            format!("max({a}, {d})"),
            v.to_string(),
        ),
        ExtOp::Min => (
            format!("min({r1}, {d_name})"),
            format!("min({a}, {d})"),
            v.to_string(),
        ),
        ExtOp::SextHi => (
            format!("sx16(HI({r1}))"),
            format!("sx16(0x{:04X})", hi(a)),
            format!("{v} ({})", hex(v)),
        ),
        ExtOp::SextLo => (
            format!("sx16(LO({r1}))"),
            format!("sx16(0x{:04X})", lo(a)),
            format!("{v} ({})", hex(v)),
        ),
        ExtOp::PackLoLo => (
            format!("LO({r1}) << 16 | LO({d_name})"),
            format!("0x{:04X} << 16 | 0x{:04X}", lo(a), lo(d)),
            hex(v),
        ),
        ExtOp::PackHiLo => (
            format!("HI({r1}) << 16 | LO({d_name})"),
            format!("0x{:04X} << 16 | 0x{:04X}", hi(a), lo(d)),
            hex(v),
        ),
        ExtOp::PackHiHi => (
            format!("HI({r1}) << 16 | HI({d_name})"),
            format!("0x{:04X} << 16 | 0x{:04X}", hi(a), hi(d)),
            hex(v),
        ),
        ExtOp::MultS => (
            format!("{r1} × {d_name}"),
            format!("{a} × {d}"),
            format!("{v} (low 32 bits, signed)"),
        ),
        ExtOp::MultU => (
            format!("{r1} × {d_name}"),
            format!("{} × {}", a as u32, d as u32),
            format!("{} (low 32 bits, unsigned)", v as u32),
        ),
        ExtOp::MultS64Shr16 => (
            format!("({r1} × {d_name}) >> 16"),
            format!("({a} × {d}) >> 16"),
            v.to_string(),
        ),
        ExtOp::MultU64 => {
            let p = u64::from(v as u32) << 32 | u64::from(extra as u32);
            return format!(
                "{out}:R{} = {r1} × {d_name} = {} × {} = {p} (R{res} = {}, R{} = {})",
                res as usize + 1,
                a as u32,
                d as u32,
                hex(v),
                res as usize + 1,
                hex(extra)
            );
        }
        ExtOp::DivU64 => {
            // vals: upper, lower, divisor, quotient
            let n = u64::from(a as u32) << 32 | u64::from(d as u32);
            return format!(
                "{out} = {r1}:R{} / {d_name} = {n} / {} = {}",
                reg1 as usize + 1,
                v as u32,
                extra as u32
            );
        }
        ExtOp::Div => (
            format!("{r1} / sx16(LO({d_name}))"),
            format!("{a} / {}", sx16(lo(d))),
            format!("{v} (truncated toward zero)"),
        ),
        ExtOp::Mod => (
            format!("{r1} % sx16(LO({d_name}))"),
            format!("{a} % {}", sx16(lo(d))),
            v.to_string(),
        ),
        ExtOp::DivRev => (
            format!("{d_name} / sx16(LO({r1}))"),
            format!("{d} / {}", sx16(lo(a))),
            format!("{v} (truncated toward zero)"),
        ),
        ExtOp::ModRev => (
            format!("{d_name} % sx16(LO({r1}))"),
            format!("{d} % {}", sx16(lo(a))),
            v.to_string(),
        ),
        _ => return queue(op, res, reg1, d_name, outcome, vals),
    };
    if sym == val {
        format!("{out} = {sym} = {result}")
    } else {
        format!("{out} = {sym} = {val} = {result}")
    }
}

fn queue(op: ExtOp, res: u8, base: u8, d_name: &str, outcome: Outcome, vals: [i32; 4]) -> String {
    let [h0, h1, d, value] = vals;
    let header = RawQueue::from_words(h0, h1);
    let (size, len) = (header.size as usize, header.len as usize);
    let (head, tail) = (header.head as usize, header.tail as usize);
    let q = format!("queue R{base}");
    let slot = |i: usize| format!("slot {i} (R{})", base as usize + 2 + i);
    let data = if d_name.starts_with('R') {
        format!("{d_name} = {d}")
    } else {
        d.to_string()
    };
    let ok = outcome == Outcome::Done;
    match op {
        ExtOp::QInit => format!(
            "init {q} with {d} slots (R{}–R{}): R{base} = size {d} | len 0, R{} = head 0 | tail 0; R{res} = {d}",
            base as usize + 2,
            base as usize + 1 + d as usize,
            base as usize + 1
        ),
        ExtOp::QPushHead | ExtOp::QPushHeadErr if ok => format!(
            "push {data} at head of {q}: {}, head {head}→{}, len {len}→{}; R{res} = {value} free",
            slot(head),
            (head + 1) % size.max(1),
            len + 1
        ),
        ExtOp::QPushTail | ExtOp::QPushTailErr if ok => {
            let new_tail = (tail + size - 1) % size.max(1);
            format!(
                "push {data} at tail of {q}: tail {tail}→{new_tail}, {}, len {len}→{}; R{res} = {value} free",
                slot(new_tail),
                len + 1
            )
        }
        ExtOp::QPopHead | ExtOp::QPopHeadErr if ok => {
            let new_head = (head + size - 1) % size.max(1);
            format!(
                "pop head of {q}: head {head}→{new_head}, {} = {value} → R{res}, len {len}→{}",
                slot(new_head),
                len - 1
            )
        }
        ExtOp::QPopTail | ExtOp::QPopTailErr if ok => format!(
            "pop tail of {q}: {} = {value} → R{res}, tail {tail}→{}, len {len}→{}",
            slot(tail),
            (tail + 1) % size.max(1),
            len - 1
        ),
        ExtOp::QRead if ok => {
            let n = i64::from(d);
            let (from, index) = if n >= 0 {
                (
                    "from the head, 0 = newest",
                    (head as i64 - 1 - n).rem_euclid(size as i64),
                )
            } else {
                (
                    "from the tail, -1 = oldest",
                    (tail as i64 - 1 - n).rem_euclid(size as i64),
                )
            };
            format!(
                "read element {n} of {q} ({from}): {} = {value} → R{res}",
                slot(index as usize)
            )
        }
        ExtOp::QRead => format!(
            "read element {d} of {q}: no such element (len {len}); nothing changed, NEGATIVE set"
        ),
        ExtOp::QPushHead | ExtOp::QPushTail => {
            format!("push {data} on {q}: full ({len} of {size}); nothing changed, NEGATIVE set")
        }
        _ => format!("pop from {q}: empty; nothing changed, NEGATIVE set"),
    }
}
