//! What TML's multiplications and divisions do to the bits, for the Product register panel: the
//! last product (spec §5.3) with its binary point when A is fixed, the bits PREG keeps after the
//! shift and the real-number line; and the `W32 /= V16;` at the program counter (§5.4) with the
//! remainder it discards. Decimals and percentages are text for people, not machine values.

use super::program::Op;
use super::{LastMultiply, Tml};
use crate::machine::bits::{BitRow, Breakdown, Keep, decimal, relative_error};

/// Whether A of the multiply on `line` is a fixed datum (its product is then 32.16).
fn a_is_fixed(m: &Tml, line: usize) -> bool {
    m.program
        .stmts
        .iter()
        .filter(|s| s.line == line)
        .any(|s| matches!(s.op, Op::Multiply { a, .. } if a.is_fixed()))
}

/// What the last multiply's shift dropped: the value of the low bits a `>> n` shifted out (0
/// when none of them was set), and whether set bits were lost above PREG's 48 (the shifted
/// product is not what PREG holds).
pub fn multiply_losses(m: &Tml, mult: &LastMultiply) -> (i128, bool) {
    let n = u32::from(mult.shift).min(126);
    let (shifted, low) = if mult.left {
        (mult.product << n, 0)
    } else {
        (mult.product >> n, mult.product & ((1i128 << n) - 1))
    };
    (low, i128::from(m.preg_signed()) != shifted)
}

/// The last multiplication: p = A × B exactly, then PREG = p shifted, kept to 48 bits.
pub fn last_multiply(m: &Tml) -> Option<Breakdown> {
    let mult = m.last_multiply?;
    let fixed = a_is_fixed(m, mult.line);
    let n = u32::from(mult.shift);
    let point = fixed.then_some(16);
    // The bits of p that land in PREG's 48: `<< n` keeps p's bits 47−n..0, `>> n` keeps
    // p's bits 47+n..n (those above 63 are the sign, not drawn).
    let keep = if mult.left {
        Keep::Bits(47u32.saturating_sub(n) as u8, 0)
    } else {
        Keep::Bits((47 + n).min(63) as u8, n.min(63) as u8)
    };
    let dir = if mult.left { "<<" } else { ">>" };
    let shifted = if mult.left {
        mult.product << n
    } else {
        mult.product >> n
    };
    // What the multiply left in PREG (a later `PROD << n` changes PREG, not this multiply).
    let preg_bits = (shifted as u64) & super::PREG_MASK;
    let preg = ((preg_bits << 16) as i64) >> 16;
    let mut notes = Vec::new();
    if m.preg != preg_bits {
        notes.push(format!(
            "PREG was changed since (now {}): shown as this multiply left it",
            m.preg_signed()
        ));
    }
    if mult.left && n > 0 {
        // Bits 47−n..0 land in 47..n; bits 47..48−n leave PREG.
        let top = 47u32.saturating_sub(n);
        notes.push(format!(
            "<< {n}: bits {top}..0 of the product move to 47..{}; low bits are 0",
            n.min(47)
        ));
    }
    if !mult.left && n > 0 {
        let (lost, _) = multiply_losses(m, &mult);
        notes.push(if lost == 0 {
            format!(">> {n}: the {n} low bits dropped are 0: nothing lost")
        } else {
            format!(">> {n}: the low bits {lost} (of 2^{n}) are dropped, toward minus infinity")
        });
    }
    if i128::from(preg) != shifted {
        notes.push(
            "bits beyond PREG's 48 are not a sign extension: the product overflowed".to_string(),
        );
    } else {
        notes.push("PREG's 48 bits hold the whole shifted product".to_string());
    }
    if fixed {
        notes.push("A is fixed: PREG is 32.16, PRODH its integer part".to_string());
    }
    let real = if fixed {
        let a = mult.a as f64 / 65536.0;
        let exact = a * mult.b as f64 * 2f64.powi(if mult.left { n as i32 } else { -(n as i32) });
        let stored = preg as f64 / 65536.0;
        format!(
            "{} × {} {dir} {n} = {} exact; PREG holds {}; error {}",
            decimal(a, 16),
            mult.b,
            decimal(exact, 16),
            decimal(stored, 16),
            relative_error(stored, exact)
        )
    } else {
        format!(
            "{} × {} = {} exact; {dir} {n} → PREG = {preg}",
            mult.a, mult.b, mult.product
        )
    };
    Some(Breakdown {
        line: mult.line,
        command: format!("A * B {dir} {n}"),
        rows: vec![
            BitRow {
                label: format!("A × B = {}", mult.product),
                value: mult.product as u64,
                width: 64,
                point,
                keep,
            },
            BitRow {
                label: format!("PREG = {preg}"),
                value: preg_bits,
                width: 48,
                point,
                keep: Keep::Operand,
            },
        ],
        notes,
        real: Some(real),
    })
}

/// The `W32 /= V16;` at the program counter, if that is what runs next.
pub fn division_at_pc(m: &Tml) -> Option<Breakdown> {
    let stmt = m.program.stmts.get(m.pc as usize)?;
    let Op::Divide(dst, divisor) = stmt.op else {
        return None;
    };
    let old = m.read_operand(&dst);
    let d = m.read_operand(&divisor);
    let fixed = dst.is_fixed();
    // §5.4: N is the dividend as 16.16; the quotient is 16.16, truncated toward zero.
    let n = if fixed {
        i128::from(old)
    } else {
        i128::from(old) * 65536
    };
    let mut notes = vec![if fixed {
        "the destination is fixed: N is its raw 16.16 value".to_string()
    } else {
        "the destination is long: N = value × 65536, and the result is fixed 16.16".to_string()
    }];
    let mut rows = vec![BitRow {
        label: format!("N = {n}"),
        value: n as u64,
        width: 64,
        point: Some(16),
        keep: Keep::Operand,
    }];
    if d == 0 {
        notes.push("a divisor of 0 saturates: 2^31−1 for N ≥ 0, −2^31 below".to_string());
        return Some(Breakdown {
            line: stmt.line,
            command: stmt.text.clone(),
            rows,
            notes,
            real: None,
        });
    }
    let q = n / i128::from(d);
    let r = n % i128::from(d);
    let stored = q.clamp(i128::from(i32::MIN), i128::from(i32::MAX));
    rows.push(BitRow {
        label: format!("quotient = {q}"),
        value: q as u64,
        width: 32,
        point: Some(16),
        keep: Keep::Bits(31, 0),
    });
    rows.push(BitRow {
        label: format!("remainder = {r}"),
        value: r as u64,
        width: 32,
        point: Some(16),
        keep: Keep::Nothing,
    });
    if stored != q {
        notes.push(format!(
            "the quotient does not fit 32 bits: saturated to {stored}"
        ));
    }
    notes.push(if r == 0 {
        "the remainder is 0: the quotient is exact".to_string()
    } else {
        format!(
            "the remainder {r} is discarded: {} of the last fraction bit, truncated toward zero",
            decimal(r as f64 / d as f64, 4)
        )
    });
    let exact = n as f64 / 65536.0 / d as f64;
    let kept = stored as f64 / 65536.0;
    Some(Breakdown {
        line: stmt.line,
        command: stmt.text.clone(),
        rows,
        notes,
        real: Some(format!(
            "{} ÷ {d} = {} exact; stored {}; error {}",
            decimal(n as f64 / 65536.0, 16),
            decimal(exact, 16),
            decimal(kept, 16),
            relative_error(kept, exact)
        )),
    })
}
