//! The last instruction in words: each REP cycle with its addresses and values, the signed
//! overflow rule or the carry when they applied.

use super::ladder::bit_name;
use super::program::{Arith, CounterKind, Logic, Op, Ty, Value, Word, point_name};
use super::{Cycle, OpenNet};

fn operand(w: &Word, offset: u32) -> String {
    match *w {
        Word::Const(v) => format!("{v}"),
        Word::Reg { n, .. } => format!("D{}", n + offset),
        Word::Bits { area, index, .. } => point_name(area, index + offset * 16),
        Word::Timer { n, .. } => format!("T{}", n + offset),
        Word::Counter { n, .. } => format!("C{}", n + offset),
    }
}

/// A destination word: a timer or counter takes the value as its preset.
fn destination(w: &Word, offset: u32) -> String {
    match w {
        Word::Timer { .. } | Word::Counter { .. } => format!("{}.preset", operand(w, offset)),
        _ => operand(w, offset),
    }
}

fn value_text(m: &OpenNet, v: Value) -> String {
    match v {
        Value::Const(c) => c.to_string(),
        Value::Reg(n) => format!("D{n} = {}", m.d.get(n as usize).copied().unwrap_or(0)),
    }
}

/// "TIM T0 50: T0 1200 → 1100 ms left (12 → 11 × 100 ms); T0 = 0".
fn timer_text(m: &OpenNet, text: &str, inc: u32, n: u32) -> String {
    let t = m.timers[n as usize];
    let (was, was_on) = m.box_before;
    let out = format!("T{n} = {}", u8::from(t.output));
    if !t.running {
        return format!(
            "{text}: input off{}: T{n}.current = preset {}; {out}",
            if m.mc { "" } else { " (MC = 0)" },
            t.preset
        );
    }
    let ms = |v: u16| u64::from(v) * u64::from(inc);
    if was == t.current && !was_on && t.current == t.preset && t.elapsed_ms == 0 && t.preset > 0 {
        return format!(
            "{text}: input on: timing starts at {} ms ({} × {inc} ms); {out}",
            ms(t.current),
            t.current
        );
    }
    let turned = if t.output && !was_on {
        " — time is up"
    } else {
        ""
    };
    format!(
        "{text}: T{n}: {} → {} ms left ({was} → {} × {inc} ms, {} ms toward the next){turned}; {out}",
        ms(was),
        ms(t.current),
        t.current,
        t.elapsed_ms
    )
}

/// "CNT C0 10: C0 counted 4 → 5 (preset 10); C0 = 0".
fn counter_text(m: &OpenNet, text: &str, kind: CounterKind, n: u32) -> String {
    let c = m.counters[n as usize];
    let [a, b, third] = m.legs.map(u8::from);
    let out = format!("C{n} = {} (preset {})", u8::from(c.output), c.preset);
    let inputs = match kind {
        CounterKind::Cnt => format!("reset {a}, pulse {b}"),
        CounterKind::Cdp => format!("preset input {a}, up {b}, down {third}"),
        CounterKind::Cud => format!("preset input {a}, pulse {b}, up/down {third}"),
    };
    if !m.mc {
        return format!("{text}: MC = 0: C{n} holds {}; {out}", c.current);
    }
    let (was, _) = m.box_before;
    let what = if kind == CounterKind::Cnt && a == 1 {
        format!("reset: C{n}.current = 0")
    } else if kind != CounterKind::Cnt && a == 1 {
        format!("preset: C{n}.current = {}", c.current)
    } else if was != c.current {
        format!("C{n} counted {was} → {}", c.current)
    } else {
        format!("no count: C{n}.current stays {}", c.current)
    };
    format!("{text}: {inputs}: {what}; {out}")
}

fn stored(ty: Ty, c: &Cycle) -> String {
    let hex = if ty.words() == 1 {
        format!("0x{:04X}", c.stored & 0xFFFF)
    } else {
        format!("0x{:08X}", c.stored)
    };
    if !c.out_of_range {
        return format!("{} ({hex})", ty.value(c.stored));
    }
    match ty {
        Ty::I => format!(
            "{hex} (sign {}, low 15 bits {})",
            c.stored >> 15 & 1,
            c.stored & 0x7FFF
        ),
        Ty::L => format!(
            "{hex} (sign {}, low 31 bits {})",
            c.stored >> 31 & 1,
            c.stored & 0x7FFF_FFFF
        ),
        _ => format!("{hex} (mod 2^{})", ty.bits()),
    }
}

pub fn explain(m: &OpenNet) -> Option<String> {
    let instr = m.program.instrs.get(m.last? as usize)?;
    let text = &instr.text;
    let rlo = u8::from(m.rlo);
    Some(match instr.op {
        Op::Lod(..)
        | Op::And(..)
        | Op::Or(..)
        | Op::AndLod
        | Op::OrLod
        | Op::Bps
        | Op::Brd
        | Op::Bpp
        | Op::Sotu(_)
        | Op::Sotd(_) => format!("{text}: RLO = {rlo}"),
        Op::Out(b, _) => format!("{text}: {} = {}", bit_name(b), u8::from(m.bit(b))),
        Op::Set(b) | Op::Rst(b) => format!(
            "{text}: RLO = {rlo}, {} = {}",
            bit_name(b),
            u8::from(m.bit(b))
        ),
        Op::End => format!("END: scan {} done", m.tick.saturating_sub(1)),
        Op::Nop => format!("{text}: nothing"),
        Op::Compare {
            counter, n, value, ..
        } => {
            let x = if counter {
                format!("C{n}.current = {}", m.counters[n as usize].current)
            } else {
                format!("D{n} = {}", m.d[n as usize])
            };
            format!("{text}: {x}, value {}: RLO = {rlo}", value_text(m, value))
        }
        Op::Timer { kind, n, .. } => timer_text(m, text, kind.increment_ms(), n),
        Op::Counter { kind, n, .. } => counter_text(m, text, kind, n),
        Op::ShiftRegister { first, len, .. } => {
            let [reset, pulse, data] = m.legs.map(u8::from);
            let bits: String = (first..first + len)
                .rev()
                .map(|i| if m.r[i as usize] { '1' } else { '0' })
                .collect();
            format!(
                "{text}: reset {reset}, pulse {pulse}, data {data}: R{}…R{first} = {bits}",
                first + len - 1
            )
        }
        Op::Mcs(_) => format!("{text}: MC = {}", u8::from(m.mc)),
        Op::Mcr => format!("{text}: MC = 1"),
        Op::Jmp(to) => {
            let line = m.program.instrs.get(to as usize).map_or(0, |i| i.line);
            if m.last_acted {
                format!("{text}: jumped to JEND on line {line}: the code between did not run")
            } else {
                format!("{text}: RLO = 0 (or MC = 0), no jump")
            }
        }
        Op::Jend => format!("{text}: end of a jump's area"),
        _ if !m.last_acted => format!("{text}: RLO = 0, not executed"),
        Op::WordCompare {
            rel,
            ty,
            a,
            b,
            c,
            dst,
            rep,
            ..
        } => {
            let parts: Vec<String> = m
                .last_cycles
                .iter()
                .map(|k| {
                    let to = point_name(dst.0, dst.1 + k.dst_at);
                    let third = if rel == super::program::Rel::Between {
                        format!(" ≥ {}", k.exact)
                    } else {
                        String::new()
                    };
                    let names = if rep > 1 {
                        format!(
                            "{} {} {}: ",
                            operand(&a, k.a_at),
                            rel.symbol(),
                            operand(&b, k.b_at)
                        )
                    } else {
                        String::new()
                    };
                    let _ = c;
                    format!(
                        "{names}{} {} {}{third} → {to} = {}",
                        k.a,
                        rel.symbol(),
                        k.b,
                        k.stored
                    )
                })
                .collect();
            format!(
                "{text}: {} ({})",
                parts.join("; "),
                if ty.signed() { "signed" } else { "unsigned" }
            )
        }
        Op::WordLogic { op, ty, dst, .. } => {
            let sign = match op {
                Logic::And => "AND",
                Logic::Or => "OR",
                Logic::Xor => "XOR",
            };
            let width = if ty.words() == 1 { 4 } else { 8 };
            let parts: Vec<String> = m
                .last_cycles
                .iter()
                .map(|k| {
                    format!(
                        "{:0width$X}h {sign} {:0width$X}h = {:0width$X}h → {}",
                        k.a,
                        k.b,
                        k.stored,
                        destination(&dst, k.dst_at)
                    )
                })
                .collect();
            format!("{text}: {}", parts.join("; "))
        }
        Op::Shift { left, ty, .. } => {
            let k = m
                .last_cycles
                .first()
                .copied()
                .unwrap_or(super::Cycle::default());
            let width = if ty.words() == 1 { 4 } else { 8 };
            format!(
                "{text}: {:0width$X}h {} {} = {:0width$X}h, M8003 = {} (the last bit shifted out)",
                k.a,
                if left { "<<" } else { ">>" },
                k.b,
                k.stored,
                u8::from(m.special[super::M8003])
            )
        }
        Op::Convert {
            to_bcd, ty, dst, ..
        } => {
            let width = if ty.words() == 1 { 4 } else { 8 };
            let parts: Vec<String> = m
                .last_cycles
                .iter()
                .map(|k| match k.error {
                    Some("bcd_range") => format!(
                        "{} has more than {width} digits: execution error bcd_range, nothing written, M8004 = 1",
                        k.a
                    ),
                    Some(kind) => format!(
                        "{:0width$X}h has a nibble over 9: execution error {kind}, nothing written, M8004 = 1",
                        k.a
                    ),
                    None if to_bcd => format!(
                        "{} → {:0width$X}h (one decimal digit per nibble) → {}",
                        k.a,
                        k.stored,
                        destination(&dst, k.dst_at)
                    ),
                    None => format!(
                        "{:0width$X}h (BCD) → {} → {}",
                        k.a,
                        k.stored,
                        destination(&dst, k.dst_at)
                    ),
                })
                .collect();
            format!("{text}: {}", parts.join("; "))
        }
        Op::Mov { ty, src, dst, .. } => {
            let parts: Vec<String> = m
                .last_cycles
                .iter()
                .map(|c| {
                    format!(
                        "{} → {} = {}",
                        operand(&src, c.a_at),
                        destination(&dst, c.dst_at),
                        ty.value(c.stored)
                    )
                })
                .collect();
            format!("{text}: {}", parts.join("; "))
        }
        Op::Arith {
            op,
            ty,
            a,
            b,
            dst,
            rep,
        } => {
            let sign = match op {
                Arith::Add => "+",
                Arith::Sub => "−",
                Arith::Mul => "×",
                Arith::Div => "÷",
            };
            let parts: Vec<String> = m
                .last_cycles
                .iter()
                .enumerate()
                .map(|(k, c)| {
                    // With REP every cycle names its addresses.
                    let (x, y) = if rep > 1 {
                        (
                            format!("{} {}", operand(&a, c.a_at), c.a),
                            format!("{} {}", operand(&b, c.b_at), c.b),
                        )
                    } else {
                        (c.a.to_string(), c.b.to_string())
                    };
                    let into = if rep > 1 {
                        format!("cycle {k}: ")
                    } else {
                        String::new()
                    };
                    let to = if rep > 1 {
                        format!(" → {}", destination(&dst, c.dst_at))
                    } else {
                        String::new()
                    };
                    if let Some(kind) = c.error {
                        return format!("{into}{x} {sign} {y}: execution error {kind}, nothing written, M8004 = 1");
                    }
                    match op {
                        Arith::Add | Arith::Sub if c.out_of_range => {
                            let bound = if c.exact > ty.max() {
                                format!("> {}", ty.max())
                            } else {
                                format!("< {}", ty.min())
                            };
                            format!(
                                "{into}{x} {sign} {y} = {} {bound}{to} → stored {}",
                                c.exact,
                                stored(ty, c)
                            )
                        }
                        Arith::Add | Arith::Sub => {
                            format!("{into}{x} {sign} {y} = {}{to}", stored(ty, c))
                        }
                        Arith::Mul => format!("{into}{x} × {y} = {}{to}", c.exact),
                        Arith::Div => format!(
                            "{into}{x} ÷ {y} = {} remainder {}{to}",
                            c.exact, c.remainder
                        ),
                    }
                })
                .collect();
            let flag = if matches!(op, Arith::Add | Arith::Sub) {
                let carry = m.special[super::M8003];
                format!(
                    ", M8003 = {}{}",
                    u8::from(carry),
                    if carry {
                        " (carry/borrow: a result did not fit its type)"
                    } else {
                        ""
                    }
                )
            } else {
                String::new()
            };
            format!("{text}: {}{flag}", parts.join("; "))
        }
        Op::Step { up, ty, reg } => {
            let v = if ty.words() == 1 {
                i64::from(m.d[reg as usize])
            } else {
                i64::from((u32::from(m.d[reg as usize]) << 16) | u32::from(m.d[reg as usize + 1]))
            };
            let max = if ty.words() == 1 { 0xFFFF } else { 0xFFFF_FFFF };
            let wrapped = if up { v == 0 } else { v == max };
            format!(
                "{text}: D{reg} {} 1 = {v}{}",
                if up { "+" } else { "−" },
                if wrapped {
                    " — wrapped past the type's range (M8003 unchanged)"
                } else {
                    ""
                }
            )
        }
    })
}
