//! What a multiply or divide does to the bits, for the Product panel: the operands as the
//! command reads them, the full 64-bit product (or the dividend, quotient and remainder) as bit
//! rows with the binary point and the bits the result keeps, what is lost in words, and the
//! real-number arithmetic beside it (`40000 × 0.0254058837890625 = 1016.2353515625 exact;
//! stored 1016; error −0.023 %`).
//!
//! It reads the command at the program counter with the registers as they are now, so it says
//! exactly what that command will do (spec §5.1, §5.2). The machine stays integer-only: the
//! decimals and percentages here are text for people, computed once per frame.

use super::program::{ClcOp, ExtOp, Instr};
use super::{SilverLode, sx16};
use crate::machine::bits::{BitRow, Breakdown, Keep, decimal, relative_error};

/// The operations the panel explains.
fn explained_clc(op: ClcOp) -> bool {
    matches!(op, ClcOp::MultS | ClcOp::MultU | ClcOp::Div | ClcOp::Mod)
}

fn explained_ext(op: ExtOp) -> bool {
    matches!(
        op,
        ExtOp::MultS
            | ExtOp::MultU
            | ExtOp::MultS64Shr16
            | ExtOp::MultU64
            | ExtOp::Div
            | ExtOp::DivRev
            | ExtOp::DivU64
            | ExtOp::Mod
            | ExtOp::ModRev
    )
}

/// Whether the command at index `pc` is one the panel explains.
pub fn is_explained(instr: &Instr) -> bool {
    match *instr {
        Instr::Clc { op, .. } => explained_clc(op),
        Instr::Cld { op, .. } | Instr::Clx { op, .. } => explained_ext(op),
        _ => false,
    }
}

/// The values a multiply or divide reads: the first operand (Acc, or R[reg1]), the second
/// (the register, the literal or R[reg2]), and for DIV_U64 the low word of the dividend.
#[derive(Clone, Copy)]
struct Operands {
    a: i32,
    d: i32,
    low: i32,
}

/// The breakdown of the command at the program counter, if it multiplies or divides.
pub fn at_pc(m: &SilverLode) -> Option<Breakdown> {
    let pc = m.pc();
    let instr = *m.program().instrs.get(pc as usize)?;
    let reg = |r: u8| m.reg(usize::from(r));
    let pair = |r: u8| m.reg((usize::from(r) + 1).min(super::REGISTERS - 1));
    let operands = match instr {
        Instr::Clc { reg: r, .. } => Operands {
            a: reg(10),
            d: reg(r),
            low: 0,
        },
        Instr::Cld { reg1, data, .. } => Operands {
            a: reg(reg1),
            d: data,
            low: pair(reg1),
        },
        Instr::Clx { reg1, reg2, .. } => Operands {
            a: reg(reg1),
            d: reg(reg2),
            low: pair(reg1),
        },
        _ => return None,
    };
    breakdown(instr, m.line_of(pc)?, operands)
}

/// The breakdown of the last command run, if it multiplied or divided, from the values it read
/// (recorded as it ran): the Product panel's "last run" after a run that never stopped on it.
pub fn last_run(m: &SilverLode) -> Option<Breakdown> {
    let last = m.state().last;
    if last.outcome != super::Outcome::Done {
        return None;
    }
    let instr = *m.program().instrs.get(last.pc as usize)?;
    let [v0, v1, v2, _] = last.vals;
    let operands = match instr {
        Instr::Cld {
            op: ExtOp::DivU64, ..
        }
        | Instr::Clx {
            op: ExtOp::DivU64, ..
        } => Operands {
            a: v0,
            low: v1,
            d: v2,
        },
        _ => Operands {
            a: v0,
            d: v1,
            low: 0,
        },
    };
    breakdown(instr, m.line_of(last.pc)?, operands)
}

fn breakdown(instr: Instr, line: usize, o: Operands) -> Option<Breakdown> {
    match instr {
        Instr::Clc { op, reg: r } if explained_clc(op) => {
            let command = format!("CLC {}, R{r}", op.name());
            let (acc, x) = (o.a, o.d);
            Some(match op {
                ClcOp::MultS => multiply(line, command, acc, x, false, "Acc (R10)"),
                ClcOp::MultU => multiply(line, command, acc, x, true, "Acc (R10)"),
                ClcOp::Div => divide(line, command, acc, x, false, "Acc (R10)"),
                _ => divide(line, command, acc, x, true, "Acc (R10)"),
            })
        }
        Instr::Cld {
            op,
            res,
            reg1,
            data,
        } if explained_ext(op) => Some(ext(
            line,
            format!("CLD {}, R{res}, R{reg1}, {data}", op.name()),
            op,
            res,
            reg1,
            o,
        )),
        Instr::Clx {
            op,
            res,
            reg1,
            reg2,
        } if explained_ext(op) => Some(ext(
            line,
            format!("CLX {}, R{res}, R{reg1}, R{reg2}", op.name()),
            op,
            res,
            reg1,
            o,
        )),
        _ => None,
    }
}

fn ext(line: usize, command: String, op: ExtOp, res: u8, a: u8, o: Operands) -> Breakdown {
    let (value, d) = (o.a, o.d);
    let dest = format!("R{res}");
    match op {
        ExtOp::MultS => multiply(line, command, value, d, false, &dest),
        ExtOp::MultU => multiply(line, command, value, d, true, &dest),
        ExtOp::MultS64Shr16 => q16_multiply(line, command, value, d),
        ExtOp::MultU64 => wide_multiply(line, command, value, d, res),
        ExtOp::Div => divide(line, command, value, d, false, &dest),
        ExtOp::Mod => divide(line, command, value, d, true, &dest),
        // The reversed forms divide the literal (or R[reg2]) by sx16(LO(R[reg1])).
        ExtOp::DivRev => divide(line, command, d, value, false, &dest),
        ExtOp::ModRev => divide(line, command, d, value, true, &dest),
        _ => wide_divide(line, command, o.a, o.low, d, a),
    }
}

fn operand(label: &str, value: i32, unsigned: bool) -> BitRow {
    let shown = if unsigned {
        (value as u32).to_string()
    } else {
        value.to_string()
    };
    BitRow {
        label: format!("{label} = {shown}"),
        value: u64::from(value as u32),
        width: 32,
        point: None,
        keep: Keep::Operand,
    }
}

/// MULT_S / MULT_U: the low 32 bits of the 64-bit product.
fn multiply(line: usize, command: String, a: i32, b: i32, unsigned: bool, dest: &str) -> Breakdown {
    let full: i128 = if unsigned {
        i128::from(a as u32) * i128::from(b as u32)
    } else {
        i128::from(a) * i128::from(b)
    };
    let stored = full as i32;
    let stored_text = if unsigned {
        (stored as u32).to_string()
    } else {
        stored.to_string()
    };
    let fits = if unsigned {
        full <= i128::from(u32::MAX)
    } else {
        i128::from(stored) == full
    };
    let mut notes = vec![format!("{dest} keeps bits 31..0 of the 64-bit product")];
    notes.push(if fits {
        if unsigned {
            "bits 63..32 are 0: nothing lost".to_string()
        } else {
            "bits 63..32 copy bit 31 (a sign extension): nothing lost".to_string()
        }
    } else if unsigned {
        format!("bits 63..32 are not 0: overflow, {full} does not fit 32 bits")
    } else {
        format!("bits 63..32 are not a sign extension of bit 31: overflow, {full} does not fit")
    });
    let (x, y) = if unsigned {
        ((a as u32).to_string(), (b as u32).to_string())
    } else {
        (a.to_string(), b.to_string())
    };
    Breakdown {
        line,
        command,
        rows: vec![
            operand("a", a, unsigned),
            operand("b", b, unsigned),
            BitRow {
                label: format!("a × b = {full}"),
                value: full as u64,
                width: 64,
                point: None,
                keep: Keep::Bits(31, 0),
            },
        ],
        notes,
        real: Some(format!(
            "{x} × {y} = {full} exact; stored {stored_text}{}",
            if fits { "" } else { " (wrapped)" }
        )),
    }
}

/// MULT_S64_SHR16: bits 47..16 of the signed 64-bit product, an integer (or Q16.16) times a
/// Q16.16 factor.
fn q16_multiply(line: usize, command: String, a: i32, d: i32) -> Breakdown {
    let full = i64::from(a) * i64::from(d);
    let stored = (full >> 16) as i32;
    let dropped = full & 0xFFFF;
    let high = full >> 47;
    let overflow = high != 0 && high != -1;
    let mut notes =
        vec!["the result keeps bits 47..16: the product shifted right by 16".to_string()];
    notes.push(if dropped == 0 {
        "bits 15..0 are 0: nothing dropped by the shift".to_string()
    } else {
        format!(
            "bits 15..0 = {dropped} = {} dropped by the shift (toward minus infinity)",
            decimal(dropped as f64 / 65536.0, 4)
        )
    });
    notes.push(if overflow {
        "bits 63..48 are not a sign extension of bit 47: overflow".to_string()
    } else {
        "bits 63..48 copy bit 47 (a sign extension): no overflow".to_string()
    });
    let exact = full as f64 / 65536.0;
    let factor = f64::from(d) / 65536.0;
    let real = format!(
        "{a} × {} = {} exact; stored {stored}; error {}",
        decimal(factor, 16),
        decimal(exact, 16),
        relative_error(f64::from(stored), exact)
    );
    Breakdown {
        line,
        command,
        rows: vec![
            operand("a", a, false),
            BitRow {
                label: format!("d = {d} = q16 {}", decimal(factor, 16)),
                value: u64::from(d as u32),
                width: 32,
                point: Some(16),
                keep: Keep::Operand,
            },
            BitRow {
                label: format!("a × d = {full}"),
                value: full as u64,
                width: 64,
                point: Some(16),
                keep: Keep::Bits(47, 16),
            },
        ],
        notes,
        real: Some(real),
    }
}

/// MULT_U64: the whole unsigned 64-bit product in two registers.
fn wide_multiply(line: usize, command: String, a: i32, d: i32, res: u8) -> Breakdown {
    let full = u64::from(a as u32) * u64::from(d as u32);
    Breakdown {
        line,
        command,
        rows: vec![
            operand("a", a, true),
            operand("d", d, true),
            BitRow {
                label: format!("a × d = {full}"),
                value: full,
                width: 64,
                point: None,
                keep: Keep::Bits(63, 0),
            },
        ],
        notes: vec![format!(
            "R{res} gets bits 63..32 ({}), R{} bits 31..0 ({}): nothing lost",
            full >> 32,
            u16::from(res) + 1,
            full & 0xFFFF_FFFF
        )],
        real: Some(format!(
            "{} × {} = {full} exact; stored whole",
            a as u32, d as u32
        )),
    }
}

/// DIV / MOD (and the reversed forms): the divisor is sx16 of its low 16 bits.
fn divide(
    line: usize,
    command: String,
    dividend: i32,
    raw_divisor: i32,
    modulo: bool,
    dest: &str,
) -> Breakdown {
    let divisor = sx16(raw_divisor & 0xFFFF);
    let mut notes = Vec::new();
    if divisor != raw_divisor {
        notes.push(format!(
            "only the low 16 bits of {raw_divisor} divide: sx16(LO) = {divisor}"
        ));
    }
    let mut rows = vec![
        operand("dividend", dividend, false),
        operand("divisor sx16(LO)", divisor, false),
    ];
    if divisor == 0 {
        notes.push("a divisor of 0: this command faults (divide_by_zero)".to_string());
        return Breakdown {
            line,
            command,
            rows,
            notes,
            real: None,
        };
    }
    if dividend == i32::MIN && divisor == -1 {
        notes.push(
            "−2147483648 ÷ −1 = 2147483648 does not fit 32 bits: this command faults \
             (divide_overflow)"
                .to_string(),
        );
        return Breakdown {
            line,
            command,
            rows,
            notes,
            real: None,
        };
    }
    let quotient = dividend / divisor;
    let remainder = dividend % divisor;
    let (keep_q, keep_r) = if modulo {
        (Keep::Nothing, Keep::Bits(31, 0))
    } else {
        (Keep::Bits(31, 0), Keep::Nothing)
    };
    rows.push(BitRow {
        label: format!("quotient = {quotient}"),
        value: u64::from(quotient as u32),
        width: 32,
        point: None,
        keep: keep_q,
    });
    rows.push(BitRow {
        label: format!("remainder = {remainder}"),
        value: u64::from(remainder as u32),
        width: 32,
        point: None,
        keep: keep_r,
    });
    let exact = f64::from(dividend) / f64::from(divisor);
    let real = if modulo {
        notes.push(format!(
            "{dest} keeps the remainder {remainder} (its sign follows the dividend); the \
             quotient {quotient} is discarded"
        ));
        format!("{dividend} ÷ {divisor} = {quotient} remainder {remainder}; stored {remainder}")
    } else {
        notes.push(if remainder == 0 {
            "the remainder is 0: the quotient is exact".to_string()
        } else {
            format!(
                "the remainder {remainder} is discarded: {} of a unit, truncated toward zero",
                decimal(f64::from(remainder) / f64::from(divisor), 4)
            )
        });
        format!(
            "{dividend} ÷ {divisor} = {} exact; stored {quotient}; error {}",
            decimal(exact, 6),
            relative_error(f64::from(quotient), exact)
        )
    };
    Breakdown {
        line,
        command,
        rows,
        notes,
        real: Some(real),
    }
}

/// DIV_U64: R[a]:R[a+1] (unsigned 64-bit, R[a] upper) ÷ d (unsigned 32-bit).
fn wide_divide(line: usize, command: String, upper: i32, lower: i32, d: i32, a: u8) -> Breakdown {
    let dividend = u64::from(upper as u32) << 32 | u64::from(lower as u32);
    let divisor = u64::from(d as u32);
    let mut rows = vec![
        BitRow {
            label: format!("dividend R{a}:R{} = {dividend}", u16::from(a) + 1),
            value: dividend,
            width: 64,
            point: None,
            keep: Keep::Operand,
        },
        operand("divisor", d, true),
    ];
    let mut notes = Vec::new();
    if divisor == 0 {
        notes.push("a divisor of 0: this command faults (divide_by_zero)".to_string());
        return Breakdown {
            line,
            command,
            rows,
            notes,
            real: None,
        };
    }
    let quotient = dividend / divisor;
    let remainder = dividend % divisor;
    if quotient > u64::from(u32::MAX) {
        notes.push(format!(
            "the quotient {quotient} needs more than 32 bits: this command faults (divide_overflow)"
        ));
        return Breakdown {
            line,
            command,
            rows,
            notes,
            real: None,
        };
    }
    rows.push(BitRow {
        label: format!("quotient = {quotient}"),
        value: quotient,
        width: 32,
        point: None,
        keep: Keep::Bits(31, 0),
    });
    notes.push(if remainder == 0 {
        "the remainder is 0: the quotient is exact".to_string()
    } else {
        format!("the remainder {remainder} is discarded")
    });
    let exact = dividend as f64 / divisor as f64;
    Breakdown {
        line,
        command,
        rows,
        notes,
        real: Some(format!(
            "{dividend} ÷ {divisor} = {} exact; stored {quotient}; error {}",
            decimal(exact, 6),
            relative_error(quotient as f64, exact)
        )),
    }
}
