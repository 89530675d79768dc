//! The last instruction in words: each REP cycle with its addresses and values, the signed
//! overflow rule or the carry when they applied.

use super::program::{Arith, Bit, Op, Ty, Word, point_name};
use super::{Cycle, OpenNet};

fn operand(w: &Word, offset: u32) -> String {
    match *w {
        Word::Const(v) => format!("{v}"),
        Word::Reg { n, .. } => format!("D{}", n + offset),
        Word::Bits { area, index, .. } => point_name(area, index + offset * 16),
    }
}

fn bit_name(b: Bit) -> String {
    match b {
        Bit::Point(area, i) => point_name(area, i),
        Bit::Special(s) => format!("M{}", super::program::SPECIAL[s as usize]),
    }
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
        Op::Lod(..) | Op::And(..) | Op::Or(..) | Op::AndLod | Op::OrLod | Op::Bps | Op::Brd
        | Op::Bpp | Op::Sotu(_) | Op::Sotd(_) => format!("{text}: RLO = {rlo}"),
        Op::Out(b, _) => format!("{text}: {} = {}", bit_name(b), u8::from(m.bit(b))),
        Op::Set(b) | Op::Rst(b) => format!(
            "{text}: RLO = {rlo}, {} = {}",
            bit_name(b),
            u8::from(m.bit(b))
        ),
        Op::End => format!("END: scan {} done", m.tick.saturating_sub(1)),
        _ if !m.last_acted => format!("{text}: RLO = 0, not executed"),
        Op::Mov { ty, src, dst, .. } => {
            let parts: Vec<String> = m
                .last_cycles
                .iter()
                .map(|c| {
                    format!(
                        "{} → {} = {}",
                        operand(&src, c.a_at),
                        operand(&dst, c.dst_at),
                        ty.value(c.stored)
                    )
                })
                .collect();
            format!("{text}: {}", parts.join("; "))
        }
        Op::Arith { op, ty, a, b, dst, rep } => {
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
                        format!(" → {}", operand(&dst, c.dst_at))
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
